//! Invariant: the graded verdict switches exactly at the analytic limits — slope sliding at
//! tan θ = μ and tipping at tan θ = b/h (1e-4 rad), the harmonic stack at overhang H_n/2, the
//! 40-voussoir semicircular arch between t/R 0.100 and 0.115 — with residual ≤ 1e-9 W.

use crate::common::*;
use voussoir::model::builtin;
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::{FrictionModel, StaticsResult, Verdict};

fn solve(spec: &str, model: FrictionModel) -> StaticsResult {
    let mut set = AnalysisSettings::default();
    set.statics.friction_model = model;
    let r = run(&builtin(spec).unwrap(), &set).statics;
    assert!(r.solver.residual <= 1e-9 * r.free_weight, "{spec}: residual {:e}", r.solver.residual / r.free_weight);
    r
}

/// Bisection on the slope angle (degrees) between a standing and a failing angle.
fn threshold(spec: impl Fn(f64) -> String, mut lo: f64, mut hi: f64, model: FrictionModel) -> f64 {
    assert!(solve(&spec(lo), model).stands && !solve(&spec(hi), model).stands, "bracket");
    while (hi - lo).to_radians() > 2e-5 {
        let mid = 0.5 * (lo + hi);
        if solve(&spec(mid), model).stands { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

#[test]
fn slope_slides_at_tan_theta_equal_mu_with_the_cone() {
    let mu: f64 = 0.5;
    let th = threshold(|a| format!("slope?angle={a}&mu={mu}&b=0.5&h=0.2"), 20.0, 35.0, FrictionModel::Cone);
    assert_close(th.to_radians(), mu.atan(), 1e-4, "sliding angle");
    let over = solve(&format!("slope?angle={}&mu={mu}&b=0.5&h=0.2", th + 0.5), FrictionModel::Cone);
    assert_eq!(over.verdict, Verdict::NeedsFriction, "sliding, not tipping");
}

#[test]
fn slope_tips_at_tan_theta_equal_b_over_h() {
    // μ = 10: no sliding; b/h = 0.5.
    let th = threshold(|a| format!("slope?angle={a}&mu=10&b=0.5&h=1.0"), 20.0, 35.0, FrictionModel::Cone);
    assert_close(th.to_radians(), 0.5f64.atan(), 1e-4, "tipping angle");
    let over = solve(&format!("slope?angle={}&mu=10&b=0.5&h=1.0", th + 0.5), FrictionModel::Cone);
    assert_eq!(over.verdict, Verdict::NeedsTension, "tipping needs tension");
}

#[test]
fn friction_models_order_the_sliding_limit() {
    // The block slides along v; the pyramids' faces are along u and v, so there every model
    // gives exactly μ. Friction utilisation = tan θ / μ for the determinate slope.
    for model in [FrictionModel::Cone, FrictionModel::Pyramid8, FrictionModel::Box4] {
        let r = solve("slope?angle=20&mu=0.6", model);
        assert_eq!(r.verdict, Verdict::Stands);
        assert_close(r.max_friction_utilization, 20f64.to_radians().tan() / 0.6, 1e-6, "utilisation");
    }
}

#[test]
fn harmonic_stack_limit_is_h_n_over_2() {
    for n in [4, 10, 20] {
        let below = solve(&format!("harmonic?n={n}&s=0.999"), FrictionModel::Pyramid8);
        assert_eq!(below.verdict, Verdict::Stands, "n = {n} at 0.999 H_n/2");
        let above = solve(&format!("harmonic?n={n}&s=1.001"), FrictionModel::Pyramid8);
        assert_eq!(above.verdict, Verdict::NeedsTension, "n = {n} at 1.001 H_n/2");
        assert!(above.tension_ratio > 1e-5, "n = {n}: tension {} well above the tolerance", above.tension_ratio);
    }
    // The overhang itself: H_4/2 = 25/24.
    let s = builtin("harmonic?n=4&s=1").unwrap();
    let top = s.blocks.iter().find(|b| b.name == "h1").unwrap();
    let right = top.mesh.vertices.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    assert_close(right, 25.0 / 24.0, 1e-12, "overhang H_4/2");
}

#[test]
fn forty_voussoir_arch_stands_at_0_115_and_needs_tension_at_0_100() {
    for model in [FrictionModel::Pyramid8, FrictionModel::Cone] {
        let thick = solve("arch?n=40&t=0.115", model);
        assert_eq!(thick.verdict, Verdict::Stands, "{model}");
        let thin = solve("arch?n=40&t=0.100", model);
        assert_eq!(thin.verdict, Verdict::NeedsTension, "{model}");
    }
}
