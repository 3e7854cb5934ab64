//! Invariant: threshold sweeps find the closed-form static thresholds and report the drop
//! test's beside them; a range that does not bracket a threshold is an error.

use voussoir::dynamics::DropSettings;
use voussoir::studies::threshold::{Family, ThresholdError, bisect_thresholds};

fn run(family: Family, range: (f64, f64)) -> voussoir::studies::threshold::ThresholdStudy {
    bisect_thresholds(&family, range, 10, &DropSettings::default(), &mut || {}).unwrap()
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
    let err = bisect_thresholds(&Family::Slope { mu: 0.6 }, (0.0, 10.0), 5, &DropSettings::default(), &mut || {})
        .unwrap_err();
    assert!(matches!(err, ThresholdError::NotBracketed { test: "statics", .. }), "{err}");
}

#[test]
fn scan_and_plot_show_both_verdicts() {
    use voussoir::viz::plot::{ThresholdPlot, write_thresholds};
    let mu = 0.6f64;
    let family = Family::Slope { mu };
    let scan =
        voussoir::studies::threshold::scan(&family, (0.0, 60.0), 13, &DropSettings::default(), &mut || {}).unwrap();
    assert_eq!(scan.len(), 13);
    let exact = mu.atan().to_degrees();
    for p in &scan {
        // Statics: stands below the friction angle with a zero margin; above it (and below
        // tipping at 45°, b = h) the margin is the friction excess sin θ − μ cos θ per unit weight.
        assert_eq!(p.statics_stands, p.parameter < exact, "{p:?}");
        let a = p.parameter.to_radians();
        let expected = (a.sin() - mu * a.cos()).max(0.0);
        if p.parameter <= 45.0 {
            assert!((p.static_margin - expected).abs() < 1e-6, "{p:?} vs {expected}");
        } else {
            assert!(p.static_margin > expected, "tipping adds tension: {p:?}");
        }
        // The drop test agrees away from the threshold.
        if (p.parameter - exact).abs() > 3.0 {
            assert_eq!(p.drop_stands, p.statics_stands, "{p:?}");
            assert_eq!(p.drop_motion <= 1.0, p.drop_stands, "{p:?}");
        }
    }
    let r = run(family, (0.0, 60.0));
    let dir = crate::common::scratch("plot");
    let plot = ThresholdPlot { title: "slope".into(), parameter: "angle".into(), scan: &scan, result: Some(&r) };
    let png = dir.join("slope.png");
    write_thresholds(&plot, &png).unwrap();
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert!(bytes.len() > 10_000, "a drawn plot, not an empty image");
    let svg = dir.join("slope.svg");
    write_thresholds(&plot, &svg).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg") && text.contains("drop-test threshold"));
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "no temporary files left: {left:?}");
    let err = write_thresholds(&plot, &dir.join("slope.jpg")).unwrap_err();
    assert!(err.to_string().contains("slope.jpg"));
}

/// Invariant: `compare_engines` finds the statics' threshold once and each engine's drop-test
/// threshold beside it — on the slope, the statics and the exact engine bracket atan μ within
/// 0.1° and rapier within 1° — and each study counts the statics' evaluations plus its own
/// (2 + iterations each). The CLI's `--both-engines` writes both studies, one per engine.
#[test]
fn both_engines_side_by_side() {
    use voussoir::dynamics::Engine;
    use voussoir::studies::threshold::compare_engines;
    let mu = 0.6f64;
    let exact = mu.atan().to_degrees();
    let engines = [Engine::Rapier, Engine::Exact];
    let studies =
        compare_engines(&Family::Slope { mu }, (20.0, 40.0), 10, &DropSettings::default(), &engines, &mut || {})
            .unwrap();
    assert_eq!(studies.iter().map(|s| s.engine).collect::<Vec<_>>(), engines);
    assert_eq!(studies[0].statics, studies[1].statics);
    assert!((studies[0].statics.mid() - exact).abs() < 0.1, "{studies:?}");
    assert!((studies[0].dynamic.mid() - exact).abs() < 1.0, "rapier: {studies:?}");
    assert!((studies[1].dynamic.mid() - exact).abs() < 0.1, "exact: {studies:?}");
    assert!(studies.iter().all(|s| s.evaluations == 24 && s.gap == s.dynamic.mid() - s.statics.mid()));

    let dir = crate::common::scratch("both");
    let json = dir.join("sweep.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_voussoir"))
        .args(["sweep", "slope", "--mu", "0.6", "--lo", "20", "--hi", "40", "--iterations", "4", "--both-engines"])
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("(rapier)") && text.contains("(exact)"), "{text}");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let names: Vec<_> = v.as_array().unwrap().iter().map(|s| s["engine"].as_str().unwrap().to_string()).collect();
    assert_eq!(names, ["rapier", "exact"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
