//! `voussoir shake` end to end, the shipped and generated records, and the scene's
//! `ground_motion`: a design that survives exits 0, one that collapses 1, every bad motion,
//! record or key 2 with one message naming it.

use std::path::PathBuf;
use std::process::{Command, Output};
use voussoir::dynamics::ground_motion::STANDARD_GRAVITY;
use voussoir::io::accelerogram::load_record;

fn voussoir(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_voussoir")).args(args).output().expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    crate::common::scratch("shake").join(name)
}

const STANDING: &str = "builtin:arch?n=15&t=0.25";
const THIN: &str = "builtin:arch?n=15&t=0.15";

/// Invariant: an arch whose λ* (0.41 g) exceeds El Centro's peak (0.28 g) does not move in the
/// exact engine (exit 0, rotation 0), and the report's λ* is the robustness command's; a
/// 0.5 g pulse of 0.2 s brings the thinner arch (λ* 0.15) down in both engines (exit 1).
#[test]
fn shake_reports_survival_and_collapse() {
    let json = tmp("standing.json");
    let out = voussoir(&[
        "shake",
        STANDING,
        "--record",
        "builtin:elcentro",
        "--duration",
        "3",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let lambda = report["static_load_factor"].as_f64().unwrap();
    assert!((lambda - 0.4107).abs() < 5e-4, "λ* {lambda}");
    let run = &report["runs"][0];
    assert_eq!(run["collapsed"], false);
    assert!(run["result"]["max_rotation"].as_f64().unwrap() < 1e-9, "{run}");
    assert!((report["peak_g"].as_f64().unwrap() - 0.2808).abs() < 2e-3);

    let robustness = voussoir(&["robustness", STANDING, "--direction", "180"]);
    let text = String::from_utf8_lossy(&robustness.stdout);
    assert!(text.contains(&format!("{lambda:.4}")), "robustness says {text}");

    let out = voussoir(&["shake", THIN, "--pulse", "rect:0.5,0.2", "--engine", "both"]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.matches("COLLAPSES").count(), 2, "{text}");
}

/// Invariant: every bad motion, record, option or scene key is exit 2 with one message that
/// names it.
#[test]
fn bad_motions_are_one_clear_error() {
    let unsorted = tmp("unsorted.csv");
    std::fs::write(&unsorted, "time (s),acceleration (g)\n0,0\n0.02,0.1\n0.01,0.2\n").unwrap();
    let unsorted = unsorted.to_str().unwrap().to_string();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--pulse", "heat:0.5,0.2"], "unknown shape 'heat'"),
        (vec!["--pulse", "rect:0.5"], "expected 2 numbers"),
        (vec!["--pulse", "rect:nan,0.2"], "amplitude NaN g"),
        (vec!["--pulse", "rect:30,0.2"], "at most 20 g"),
        (vec!["--pulse", "rect:0.3,0"], "duration = 0"),
        (vec!["--sine", "0.1,0.5,1e9"], "duration × cycles"),
        (vec!["--sine", "0.1,0.5,-2"], "cycles = -2"),
        (vec!["--record", "missing.AT2"], "missing.AT2: cannot read"),
        (vec!["--record", &unsorted], "unsorted.csv:4"),
        (vec!["--record", "builtin:quake"], "unknown built-in record"),
        (vec!["--record", "builtin:synthetic?pga=50"], "pga '50'"),
        (vec!["--pulse", "rect:0.3,0.2", "--scale", "inf"], "scale"),
        (vec!["--pulse", "rect:0.3,0.2", "--duration", "1e9"], "steps"),
        (vec![], "name a motion"),
        (vec!["--pulse", "rect:0.3,0.2", "--shake-support", "nothere"], "support 'nothere': no block has this name"),
        (vec!["--spectrum", "heat"], "--spectrum 'heat'"),
        (vec!["--spectrum", "rect", "--durations=0.5,-1"], "duration -1"),
    ];
    for (extra, expected) in cases {
        let mut args = vec!["shake", STANDING];
        args.extend(extra.iter().copied());
        let out = voussoir(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(expected), "{args:?}: `{err}` should say `{expected}`");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: one message: {err}");
    }
}

/// Invariant: the shipped record reads as PEER's header says (5 372 samples at 0.01 s), its peak
/// the largest |sample| of the file × standard gravity (parsed here independently), and the
/// synthetic record is seeded: the same text gives the same samples.
#[test]
fn the_shipped_and_generated_records() {
    let r = load_record("builtin:elcentro").expect("El Centro");
    assert_eq!(r.times.len(), 5372);
    assert!((r.times[1] - 0.01).abs() < 1e-12 && (r.duration() - 53.71).abs() < 1e-9);
    let text =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/records/elcentro_1940_ns.AT2"))
            .unwrap();
    let peak = text
        .lines()
        .skip(4)
        .flat_map(str::split_whitespace)
        .map(|w| w.parse::<f64>().unwrap().abs())
        .fold(0.0, f64::max);
    assert!((r.peak() - peak * STANDARD_GRAVITY).abs() < 1e-12, "{} vs {peak}", r.peak());
    let a = load_record("builtin:synthetic?seed=7&pga=0.2&duration=5").unwrap();
    assert_eq!(a, load_record("builtin:synthetic?seed=7&pga=0.2&duration=5").unwrap());
    assert!((a.peak() - 0.2 * STANDARD_GRAVITY).abs() < 1e-12);
}

/// Invariant: a scene's `ground_motion` runs when no motion is named (and its records are read
/// relative to the scene file); a component with two shapes, an unknown key or a bad record
/// fails on reading, naming the file and the component.
#[test]
fn a_scene_carries_its_ground_motion() {
    let dir = tmp("scene");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("pulse.csv"), "time (s),acceleration (g)\n0,0.5\n0.2,0.5\n0.2001,0\n").unwrap();
    let arch = voussoir::model::builtin("arch?n=15&t=0.15").unwrap();
    let scene: serde_json::Value = serde_json::from_str(&voussoir::io::scene_json::scene_to_string(&arch)).unwrap();
    let write = |motion: serde_json::Value, name: &str| {
        let mut s = scene.clone();
        s["ground_motion"] = motion;
        let path = dir.join(name);
        std::fs::write(&path, s.to_string()).unwrap();
        path.to_str().unwrap().to_string()
    };
    let good = write(serde_json::json!({"components": [{"record": "pulse.csv", "azimuth": 0}]}), "good.json");
    let out = voussoir(&["shake", &good]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("the scene's ground motion"));
    let bad = [
        (
            serde_json::json!({"components": [{"record": "pulse.csv", "pulse": {"shape": "rect", "amplitude": 0.1, "duration": 1}}]}),
            "component 1: give exactly one",
        ),
        (serde_json::json!({"components": [{"pulse": {"shape": "rect", "amplitud": 0.1, "duration": 1}}]}), "amplitud"),
        (serde_json::json!({"components": [{"record": "nothere.csv"}]}), "nothere.csv: cannot read"),
        (
            serde_json::json!({"components": [{"harmonic": {"amplitude": 0.1, "period": -1, "cycles": 2}}]}),
            "period = -1",
        ),
    ];
    for (k, (motion, expected)) in bad.into_iter().enumerate() {
        let path = write(motion, &format!("bad{k}.json"));
        let out = voussoir(&["shake", &path, "--pulse", "rect:0.1,0.1"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{expected}: {err}");
        assert!(err.contains(expected) && err.contains(&format!("bad{k}.json")), "`{err}` should say `{expected}`");
    }
}
