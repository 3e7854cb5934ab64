//! Invariant: the answer does not depend on units or density — metres vs millimetres and
//! density × 1e6 give the same verdict and ratios, and forces scale exactly.

use crate::common::*;
use voussoir::model::builtin;
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::StaticsResult;

fn solve(spec: &str, density_factor: f64) -> StaticsResult {
    let mut s = builtin(spec).unwrap();
    s.material.density *= density_factor;
    run(&s, &AnalysisSettings::default()).statics
}

fn same(a: &StaticsResult, b: &StaticsResult, force_factor: f64, what: &str) {
    assert_eq!(a.verdict, b.verdict, "{what}");
    assert_close(b.tension_ratio, a.tension_ratio, 1e-6 * a.tension_ratio.max(1e-6), &format!("{what}: tension ratio"));
    assert_close(b.friction_excess_ratio, a.friction_excess_ratio, 1e-6, &format!("{what}: excess ratio"));
    assert_close(b.max_friction_utilization, a.max_friction_utilization, 1e-6, &format!("{what}: utilisation"));
    assert_eq!(a.interfaces.len(), b.interfaces.len());
    for (x, y) in a.interfaces.iter().zip(&b.interfaces) {
        let tol = 1e-6 * a.free_weight * force_factor;
        assert_close(
            y.normal_force,
            x.normal_force * force_factor,
            tol,
            &format!("{what}: normal force {}-{}", x.a, x.b),
        );
    }
    assert!(b.solver.residual <= 1e-9 * b.free_weight);
}

#[test]
fn millimetres_and_metres_agree() {
    for (m, mm) in [
        ("arch?n=20&t=0.13&r=1&d=0.5", "arch?n=20&t=130&r=1000&d=500"),
        ("arch?n=20&t=0.09&r=1&d=0.5", "arch?n=20&t=90&r=1000&d=500"),
        ("slope?angle=45&b=0.5&h=0.3", "slope?angle=45&b=500&h=300"),
    ] {
        // Same density per m³ in both: forces scale with the volume, 1e9.
        let a = solve(m, 1.0);
        let b = solve(mm, 1.0);
        same(&a, &b, 1e9, m);
    }
}

#[test]
fn density_times_a_million_scales_forces_only() {
    for spec in ["arch?n=20&t=0.13", "arch?n=20&t=0.09", "wall?courses=4&bricks=4", "harmonic?n=6&s=1.01"] {
        let a = solve(spec, 1.0);
        let b = solve(spec, 1e6);
        same(&a, &b, 1e6, spec);
    }
}
