//! Invariant: threshold sweeps find the closed-form static thresholds and report the drop
//! test's beside them; a range that does not bracket a threshold is an error.

use voussoir::dynamics::DropSettings;
use voussoir::sweep::{Family, SweepError, sweep};

fn run(family: Family, range: (f64, f64)) -> voussoir::sweep::SweepResult {
    sweep(&family, range, 10, &DropSettings::default(), &mut || {}).unwrap()
}

#[test]
fn slope_thresholds_at_the_friction_angle() {
    let mu = 0.6f64;
    let r = run(Family::Slope { mu }, (0.0, 80.0));
    let exact = mu.atan().to_degrees(); // 30.96°
    assert!(r.statics.stands_at <= exact + 1e-9 && exact <= r.statics.fails_at + 1e-9, "{r:?}");
    assert!((r.dynamic.mid() - exact).abs() < 1.0, "rapier's sliding angle {:?} vs {exact}", r.dynamic);
    assert_eq!(r.evaluations, 24);
}

#[test]
fn harmonic_and_arch_thresholds() {
    let r = run(Family::Harmonic { n: 6 }, (0.5, 1.5));
    assert!((r.statics.mid() - 1.0).abs() < 1e-3, "{r:?}");
    assert!((r.dynamic.mid() - 1.0).abs() < 0.05, "drop test within 5 %: {r:?}");
    let r = run(Family::Arch { n: 15 }, (0.02, 0.4));
    assert!(r.statics.mid() > 0.10 && r.statics.mid() < 0.11, "{r:?}");
    // rapier's soft contacts need a thicker arch than the statics (measured 0.130 vs 0.106).
    assert!(r.dynamic.mid() > r.statics.mid(), "{r:?}");
}

#[test]
fn unbracketed_range_is_an_error() {
    let err = sweep(&Family::Slope { mu: 0.6 }, (0.0, 10.0), 5, &DropSettings::default(), &mut || {}).unwrap_err();
    assert!(matches!(err, SweepError::NotBracketed { test: "statics", .. }), "{err}");
}
