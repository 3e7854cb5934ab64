//! Invariant: the statics reproduce the closed forms of docs/design.md#closed-forms — cube on
//! cube 0.25 W per corner, offset cube needs tension W, lever-rule reactions — with equilibrium
//! residual ≤ 1e-9 W.

use crate::common::*;
use voussoir::geometry::Vector3;
use voussoir::model::Scene;
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::{FrictionModel, SolverStatus, Verdict};

/// Density 1 and g = 1: W equals the free volume.
fn unit_scene(name: &str, blocks: Vec<voussoir::model::Block>) -> Scene {
    let mut s = Scene::new(name, blocks);
    s.material.density = 1.0;
    s.gravity = Vector3::new(0.0, 0.0, -1.0);
    s
}

fn check_residual(r: &voussoir::statics::StaticsResult) {
    assert!(matches!(r.solver.status, SolverStatus::Solved | SolverStatus::AlmostSolved), "{:?}", r.solver);
    assert!(r.solver.residual <= 1e-9 * r.free_weight, "residual {} > 1e-9 W", r.solver.residual);
}

#[test]
fn cube_on_cube_carries_a_quarter_at_each_corner() {
    for model in [FrictionModel::Pyramid8, FrictionModel::Cone, FrictionModel::Box4] {
        let s = unit_scene(
            "cubes",
            vec![cube("base", [0.0, 0.0, -1.0], 1.0).support(true), cube("top", [0.0, 0.0, 0.0], 1.0)],
        );
        let mut set = AnalysisSettings::default();
        set.statics.friction_model = model;
        let r = run(&s, &set).statics;
        check_residual(&r);
        assert_eq!(r.verdict, Verdict::Stands);
        assert_close(r.free_weight, 1.0, 1e-12, "W");
        let i = &r.interfaces[0];
        assert_eq!(i.vertices.len(), 4);
        for v in &i.vertices {
            assert_close(v.compression, 0.25, 1e-9, "corner force / W");
            assert_close(v.tension, 0.0, 1e-9, "no tension");
            assert!(v.friction_u.abs() < 1e-9 && v.friction_v.abs() < 1e-9);
        }
        assert_close(i.normal_force, 1.0, 1e-9, "total normal");
        let p = i.resultant_point.unwrap();
        assert_close(p[0], 0.5, 1e-9, "resultant x");
        assert_close(p[1], 0.5, 1e-9, "resultant y");
    }
}

#[test]
fn cube_shifted_by_three_quarters_needs_tension_w() {
    // Overlap x ∈ [0.75, 1], centroid at 1.25: C − T = W and C·0.25 = T·0.5 ⇒ T = W, C = 2W.
    let s = unit_scene(
        "offset",
        vec![cube("base", [0.0, 0.0, -1.0], 1.0).support(true), cube("top", [0.75, 0.0, 0.0], 1.0)],
    );
    let r = run(&s, &AnalysisSettings::default()).statics;
    check_residual(&r);
    assert_eq!(r.verdict, Verdict::NeedsTension);
    assert!(!r.stands);
    assert_close(r.tension_ratio, 1.0, 1e-7, "minimum tension / W");
    let i = &r.interfaces[0];
    assert_close(i.normal_force, 1.0, 1e-9, "net normal = W");
    assert_close(i.compression, 2.0, 1e-6, "compression 2W");
    for v in &i.vertices {
        if v.position[0] < 0.8 {
            assert_close(v.tension, 0.5, 1e-6, "tension at the inner corners");
        } else {
            assert_close(v.tension, 0.0, 1e-6, "no tension at the edge");
        }
    }
}

#[test]
fn beam_on_two_supports_follows_the_lever_rule() {
    // Beam [0, 4] × [0, 0.2] × [0, 0.2] on two narrow supports centred at x_a = 0.5 and
    // x_b = 3.0 (width w = 1e-3), plus a heavy block making the centroid asymmetric.
    let (xa, xb, w) = (0.5, 3.0, 1e-3);
    let blocks = vec![
        cuboid("sa", [xa - w / 2.0, 0.0, -0.2], [xa + w / 2.0, 0.2, 0.0]).support(true),
        cuboid("sb", [xb - w / 2.0, 0.0, -0.2], [xb + w / 2.0, 0.2, 0.0]).support(true),
        cuboid("beam", [0.0, 0.0, 0.0], [4.0, 0.2, 0.2]),
    ];
    let s = unit_scene("beam", blocks);
    let an = run(&s, &AnalysisSettings::default());
    let r = &an.statics;
    check_residual(r);
    assert_eq!(r.verdict, Verdict::Stands);
    let xc = 2.0;
    let ra = r.interfaces.iter().find(|i| i.a == "sa").unwrap();
    let rb = r.interfaces.iter().find(|i| i.a == "sb").unwrap();
    let (pa, pb) = (ra.resultant_point.unwrap()[0], rb.resultant_point.unwrap()[0]);
    // Exact with the reported points of application.
    let wt = r.free_weight;
    assert_close(ra.normal_force, wt * (pb - xc) / (pb - pa), 1e-9 * wt, "R_a by the lever rule");
    assert_close(rb.normal_force, wt * (xc - pa) / (pb - pa), 1e-9 * wt, "R_b by the lever rule");
    // And with the support centres, to O(w²/L²).
    assert_close(ra.normal_force, wt * (xb - xc) / (xb - xa), 1e-5 * wt, "R_a at the support centre");
}

#[test]
fn unsupported_block_is_named_and_never_stands() {
    let s = unit_scene(
        "floating",
        vec![
            cube("base", [0.0, 0.0, -1.0], 1.0).support(true),
            cube("ok", [0.0, 0.0, 0.0], 1.0),
            cube("ghost", [5.0, 5.0, 5.0], 1.0),
        ],
    );
    let r = run(&s, &AnalysisSettings::default()).statics;
    assert_eq!(r.verdict, Verdict::Unsupported);
    assert!(!r.stands);
    assert_eq!(r.solver.status, SolverStatus::Unsupported);
    assert!(
        r.solver.messages.iter().any(|m| m.contains("'ghost'") && m.contains("touches nothing")),
        "{:?}",
        r.solver.messages
    );
    // Nothing balances the ghost: the residual is its weight (W = 2: density 1, g = 1, two cubes).
    assert_close(r.solver.residual, 1.0, 1e-12, "unbalanced weight");
    // The supported part is still solved.
    assert_eq!(r.interfaces.len(), 1);
    assert_close(r.interfaces[0].normal_force, 1.0, 1e-9, "the supported cube");
    // A group resting on nothing.
    let s = unit_scene(
        "group",
        vec![
            cube("base", [0.0, 0.0, -1.0], 1.0).support(true),
            cube("x", [5.0, 0.0, 0.0], 1.0),
            cube("y", [5.0, 0.0, 1.0], 1.0),
        ],
    );
    let r = run(&s, &AnalysisSettings::default()).statics;
    assert_eq!(r.verdict, Verdict::Unsupported);
    assert!(
        r.solver.messages.iter().any(|m| m.contains("'x', 'y'") && m.contains("no support")),
        "{:?}",
        r.solver.messages
    );
}

#[test]
fn zero_friction_drops_friction_and_a_slope_then_needs_friction() {
    let mut set = AnalysisSettings::default();
    set.statics.friction = Some(0.0);
    let r = run(&voussoir::model::builtin("slope?angle=5").unwrap(), &set).statics;
    check_residual(&r);
    assert_eq!(r.verdict, Verdict::NeedsFriction, "μ = 0 on a slope: it slides");
    // The friction needed is the whole tangential weight W sin 5°.
    assert_close(r.friction_excess_ratio, 5f64.to_radians().sin(), 1e-7, "friction excess / W");
    // Flat: stands, and the strict problem carried no friction at all.
    let r = run(&voussoir::model::builtin("stack?n=3").unwrap(), &set).statics;
    assert_eq!(r.verdict, Verdict::Stands);
    assert!(r.interfaces.iter().all(|i| i.friction == 0.0 && i.vertices.iter().all(|v| v.friction_u == 0.0)));
}

#[test]
fn support_reactions_equal_the_free_weight() {
    let an = run(&voussoir::model::builtin("wall?courses=6&bricks=5").unwrap(), &AnalysisSettings::default());
    let r = &an.statics;
    check_residual(r);
    let mut total = Vector3::zeros();
    for i in &r.interfaces {
        let f = Vector3::from(i.resultant);
        if i.a == "base" {
            total += f;
        } else if i.b == "base" {
            total -= f;
        }
    }
    assert!((total - Vector3::new(0.0, 0.0, r.free_weight)).norm() <= 1e-9 * r.free_weight, "{total}");
}

#[test]
fn split_and_merged_components_give_the_same_answer() {
    // 6 stacks; in one the top cube overhangs sideways (y) by 0.6 and needs tension.
    let mut s = voussoir::model::builtin("stacks?k=6&n=3").unwrap();
    let top = s.blocks.iter_mut().find(|b| b.name == "s2b2").unwrap();
    top.mesh = top.mesh.scaled_translated(1.0, Vector3::new(0.0, 0.6, 0.0));
    let mut merged = AnalysisSettings::default();
    merged.statics.split_components = false;
    let a = run(&s, &AnalysisSettings::default()).statics;
    let b = run(&s, &merged).statics;
    assert_eq!(a.components, 6);
    assert_eq!(b.components, 1);
    assert_eq!(a.verdict, Verdict::NeedsTension);
    assert_eq!(a.verdict, b.verdict);
    assert_close(a.tension_ratio, b.tension_ratio, 1e-7, "the same minimum tension");
    for (x, y) in a.interfaces.iter().zip(&b.interfaces) {
        assert_close(x.normal_force, y.normal_force, 1e-6 * a.free_weight, "normal force");
    }
}
