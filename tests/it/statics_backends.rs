//! Invariant: the structured interior-point backend (default) and clarabel give the same
//! answer — verdict, exact minimum tension and friction excess, and the force distribution —
//! on standing and failing designs, for every friction model (the cone too) and with μ = 0.

use crate::common::*;
use voussoir::model::builtin;
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::{Backend, FrictionModel, SolverStatus, StaticsResult, StaticsSettings};

fn solve(spec: &str, model: FrictionModel, mu: Option<f64>, backend: Backend) -> StaticsResult {
    let scene = match spec.strip_prefix("data:") {
        Some(rel) => voussoir::io::load_scene(&compas_data(rel)).unwrap(),
        None => builtin(spec).unwrap(),
    };
    let statics = StaticsSettings { friction_model: model, friction: mu, backend, ..Default::default() };
    run(&scene, &AnalysisSettings { statics, ..Default::default() }).statics
}

fn compare(spec: &str, model: FrictionModel, mu: Option<f64>) -> (StaticsResult, StaticsResult) {
    let s = solve(spec, model, mu, Backend::Structured);
    let c = solve(spec, model, mu, Backend::Clarabel);
    let what = format!("{spec} {model:?} μ {mu:?}");
    assert_eq!(s.solver.backend, Backend::Structured, "{what}: the structured solver took every stage");
    assert_eq!(c.solver.backend, Backend::Clarabel, "{what}");
    let w = c.free_weight;
    for r in [&s, &c] {
        assert!(matches!(r.solver.status, SolverStatus::Solved), "{what}: {:?}", r.solver);
        assert!(r.solver.residual <= 1e-9 * w, "{what}: residual {:e} W", r.solver.residual / w);
    }
    assert_eq!(s.verdict, c.verdict, "{what}");
    assert_close(s.tension_ratio, c.tension_ratio, 1e-7, &format!("{what}: tension ratio"));
    assert_close(s.friction_excess_ratio, c.friction_excess_ratio, 1e-7, &format!("{what}: friction excess"));
    // The distribution QP is strictly convex: one optimum, met by both to the tolerance.
    assert_eq!(s.interfaces.len(), c.interfaces.len(), "{what}");
    for (a, b) in s.interfaces.iter().zip(&c.interfaces) {
        assert_close(a.normal_force / w, b.normal_force / w, 2e-5, &format!("{what}: {}–{} normal", a.a, a.b));
        assert_close(a.friction / w, b.friction / w, 2e-5, &format!("{what}: {}–{} friction", a.a, a.b));
    }
    (s, c)
}

#[test]
fn standing_designs_agree() {
    for model in [FrictionModel::Pyramid8, FrictionModel::Box4, FrictionModel::Cone] {
        let (s, _) = compare("wall?courses=6&bricks=6", model, None);
        assert!(s.stands);
        let (s, _) = compare("arch?n=40&t=0.115", model, None);
        assert!(s.stands);
        compare("data:compas_assembly/crossvault_assembly.json", model, None);
    }
}

#[test]
fn failing_designs_agree_on_the_graded_numbers() {
    for model in [FrictionModel::Pyramid8, FrictionModel::Box4, FrictionModel::Cone] {
        // Needs tension (the 40-voussoir arch at t/R 0.100), slides (35° slope at μ 0.5),
        // overhangs (harmonic stack beyond H_n/2).
        let (s, _) = compare("arch?n=40&t=0.10", model, None);
        assert!(!s.stands && s.tension_ratio > 1e-3, "{}", s.tension_ratio);
        let (s, _) = compare("slope?angle=35", model, Some(0.5));
        assert!(!s.stands && s.friction_excess_ratio > 1e-3, "{}", s.friction_excess_ratio);
        let (s, _) = compare("harmonic?n=10&s=1.01", model, None);
        assert!(!s.stands);
    }
}

#[test]
fn frictionless_problems_agree() {
    // μ = 0: the strict problem has no friction columns; a box stack stands, a slope slides.
    let (s, _) = compare("stack?n=4", FrictionModel::Pyramid8, Some(0.0));
    assert!(s.stands);
    let (s, _) = compare("slope?angle=10", FrictionModel::Pyramid8, Some(0.0));
    assert!(!s.stands);
}

#[test]
fn the_cone_model_meets_its_closed_form_on_both_backends() {
    // A 30° slope at μ = 0.5: the cone's exact friction excess per unit weight is
    // sin θ − μ cos θ (the block slides; no tension is needed), on either backend.
    let theta = 30f64.to_radians();
    let exact = theta.sin() - 0.5 * theta.cos();
    for backend in [Backend::Structured, Backend::Clarabel] {
        let r = solve("slope?angle=30", FrictionModel::Cone, Some(0.5), backend);
        assert_eq!(r.solver.backend, backend);
        assert!(r.tension_ratio < 1e-8, "{backend:?}: {}", r.tension_ratio);
        assert_close(r.friction_excess_ratio, exact, 1e-6, &format!("{backend:?}: friction excess"));
    }
}
