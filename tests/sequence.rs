//! Invariant: a sequence check analyses every prefix of an order (supports always in place),
//! reports the first failing step, and rejects unknown, repeated, support or missing names.

use voussoir::analysis::AnalysisSettings;
use voussoir::model::builtin;
use voussoir::sequence::{OrderSpec, SequenceError, check};

fn given(names: &[&str]) -> OrderSpec {
    OrderSpec::Given(names.iter().map(|s| s.to_string()).collect())
}

#[test]
fn stack_bottom_up_stands_top_down_fails_at_once() {
    let scene = builtin("stack?n=4").unwrap();
    let r = check(&scene, &OrderSpec::BottomUp, &AnalysisSettings::default(), None, &mut || {}).unwrap();
    assert_eq!(r.first_failure, None);
    assert!(r.steps.iter().all(|s| s.stands));
    let free: Vec<String> = r.order.clone();
    let reversed: Vec<&str> = free.iter().rev().map(String::as_str).collect();
    let r = check(&scene, &given(&reversed), &AnalysisSettings::default(), None, &mut || {}).unwrap();
    assert_eq!(r.first_failure, Some(0), "the top block alone floats");
    assert!(r.steps.last().unwrap().stands, "complete, it stands again");
}

#[test]
fn arch_without_centering_fails_before_the_keystone() {
    let scene = builtin("arch?n=7&t=0.15").unwrap();
    let r = check(&scene, &OrderSpec::BottomUp, &AnalysisSettings::default(), None, &mut || {}).unwrap();
    let k = r.first_failure.expect("a half arch does not stand");
    assert!(k < r.steps.len() - 1);
    assert!(!r.steps[k].offending.is_empty() && r.steps[k].tension_ratio > 0.0);
    assert!(r.steps.last().unwrap().stands, "the closed arch stands");
}

#[test]
fn bad_orders_are_named_errors() {
    let scene = builtin("stack?n=3").unwrap();
    let s = AnalysisSettings::default();
    let free = check(&scene, &OrderSpec::BottomUp, &s, None, &mut || {}).unwrap().order;
    let f: Vec<&str> = free.iter().map(String::as_str).collect();
    let err = |o: OrderSpec| check(&scene, &o, &s, None, &mut || {}).unwrap_err();
    assert_eq!(err(given(&[f[0], "nope", f[1]])), SequenceError::Unknown("nope".into()));
    assert_eq!(err(given(&[f[0], f[0], f[1]])), SequenceError::Repeated(f[0].into()));
    assert_eq!(err(given(&[f[0]])), SequenceError::Missing(f[1].into()));
}

#[test]
fn from_supports_orders_by_graph_distance() {
    // An arch: the voussoirs next to the springers first, the keystone last.
    let scene = builtin("arch?n=7&t=0.15").unwrap();
    let r = check(&scene, &OrderSpec::FromSupports, &AnalysisSettings::default(), None, &mut || {}).unwrap();
    assert_eq!(r.order.len(), 7);
    let ends: Vec<&str> = r.order[..2].iter().map(String::as_str).collect();
    assert!(ends.contains(&"v0") && ends.contains(&"v6"), "{:?}", r.order);
    assert_eq!(r.order[6], "v3", "the keystone is farthest from the supports");
    assert!(r.steps.last().unwrap().stands);
}
