//! Invariant: the CLI's exit code is 0 when the assembly stands, 1 when it does not, 2 for bad
//! input (with one message naming the file); the JSON report has the documented keys and is
//! written atomically, never over the input.

use std::path::PathBuf;
use std::process::{Command, Output};

fn voussoir(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_voussoir")).args(args).output().expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    crate::common::scratch("cli").join(name)
}

fn compas_data(rel: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/compas").join(rel).display().to_string()
}

#[test]
fn default_scene_stands_with_exit_code_0() {
    let out = voussoir(&[]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("STANDS"), "verdict first: {text}");
}

#[test]
fn failing_scene_exits_1_and_reports_json() {
    let json = tmp("arch.json");
    let out = voussoir(&[
        "analyze",
        "builtin:arch?n=40&t=0.10",
        "--friction-model",
        "cone",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("DOES NOT STAND: needs tension"));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in [
        "stands",
        "tension_ratio",
        "friction_excess_ratio",
        "max_friction_utilization",
        "blocks",
        "supports",
        "interfaces",
        "solver",
        "timings",
    ] {
        assert!(v.get(key).is_some(), "report has '{key}'");
    }
    assert_eq!(v["stands"], false);
    assert_eq!(v["friction_model"], "cone");
    assert!(v["tension_ratio"].as_f64().unwrap() > 1e-4);
    let i = &v["interfaces"][0];
    for key in
        ["a", "b", "area", "normal_force", "tension", "friction", "friction_utilization", "resultant_point", "vertices"]
    {
        assert!(i.get(key).is_some(), "interface has '{key}'");
    }
    for key in ["status", "iterations", "residual"] {
        assert!(v["solver"].get(key).is_some(), "solver has '{key}'");
    }
    // No temporary file of this report left behind (the other tests write into the same
    // folder at the same time: only this file's own temporary name counts).
    let own = format!(".{}.tmp-", json.file_name().unwrap().to_string_lossy());
    let leftovers: Vec<_> = std::fs::read_dir(json.parent().unwrap())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with(&own))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn options_mu_density_supports() {
    // μ below tan 30°: the block slides (exit 1); above: stands (exit 0).
    assert_eq!(voussoir(&["analyze", "builtin:slope?angle=30", "--mu", "0.5"]).status.code(), Some(1));
    assert_eq!(voussoir(&["analyze", "builtin:slope?angle=30", "--mu", "0.7"]).status.code(), Some(0));
    // Density changes W, not the verdict.
    let json = tmp("dense.json");
    let out = voussoir(&["analyze", "builtin:stack?n=2", "--density", "2400", "--json", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!((v["free_weight"].as_f64().unwrap() - 2.0 * 2400.0 * 9.81).abs() < 1e-6);
    // compas_cra file without stored supports: lowest blocks.
    let out = voussoir(&["analyze", &compas_data("compas_cra/cubes.json"), "--supports", "lowest"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stdout));
}

#[test]
fn bad_input_exits_2_naming_the_file() {
    let bad = tmp("bad.json");
    std::fs::write(&bad, "{\"blocks\": [{\"name\": \"a\"}]}").unwrap();
    let out = voussoir(&["analyze", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.json") && err.lines().count() == 1, "{err}");
    for args in [
        vec!["analyze", "/nonexistent.json"],
        vec!["analyze", "builtin:nothing"],
        vec!["analyze", "builtin:stack", "--supports", "nosuchblock"],
        vec!["analyze", "builtin:stack", "--mu", "-1"],
    ] {
        let out = voussoir(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: "));
    }
    // An open mesh: the message names file, block and face.
    let open = tmp("open.json");
    std::fs::write(
        &open,
        r#"{"blocks": [{"name": "lidless", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],
            "faces": [[0,3,2,1],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]}]}"#,
    )
    .unwrap();
    let out = voussoir(&["analyze", open.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("open.json") && err.contains("block 'lidless'") && err.contains("face"), "{err}");
}

#[test]
fn the_report_never_overwrites_the_input() {
    let scene = tmp("scene.json");
    std::fs::copy(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/default.json"), &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    let out = voussoir(&["analyze", scene.to_str().unwrap(), "--json", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read(&scene).unwrap(), before);
}

#[test]
fn cut_appends_to_the_history_and_never_overwrites_the_input() {
    let first = tmp("cut1.json");
    let out = voussoir(&["cut", "builtin:stack?n=1", "--plane", "0,0,0.5,0,0,1", "-o", first.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("box0.0-, box0.0+"));
    let second = tmp("cut2.json");
    let out = voussoir(&[
        "cut",
        first.to_str().unwrap(),
        "--plane",
        "0,0,0,1,0,0",
        "--target",
        "box0.0+",
        "-o",
        second.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&second).unwrap()).unwrap();
    assert_eq!(v["cuts"].as_array().unwrap().len(), 2);
    // The result analyses: 4 blocks after replaying the history.
    let json = tmp("cut2-report.json");
    let out = voussoir(&["analyze", second.to_str().unwrap(), "--json", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["blocks"].as_array().unwrap().len(), 4);
    // Writing over the input is refused, and the input is unchanged.
    let before = std::fs::read(&first).unwrap();
    let out = voussoir(&["cut", first.to_str().unwrap(), "--plane", "0,0,0.2,0,0,1", "-o", first.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read(&first).unwrap(), before);
    // Bad planes and targets are input errors.
    for plane in ["1,2,3", "0,0,0,0,0,0", "a,b,c,d,e,f"] {
        let out = voussoir(&["cut", "builtin:stack", "--plane", plane, "-o", tmp("x.json").to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{plane}");
    }
    let out = voussoir(&[
        "cut",
        "builtin:stack",
        "--plane",
        "0,0,0.5,0,0,1",
        "--target",
        "nope",
        "-o",
        tmp("y.json").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("'nope'"));
}

#[test]
fn pattern_cut_from_the_command_line() {
    // A 2 × 2 × 0.5 slab on the ground cut by a line across and a half line, both to an apex
    // below: three pieces with interfaces converging on the apex.
    let slab = tmp("slab.json");
    std::fs::write(
        &slab,
        r#"{"ground": true, "blocks": [{"name": "slab", "vertices": [[-1,-1,0],[1,-1,0],[1,1,0],[-1,1,0],
            [-1,-1,0.5],[1,-1,0.5],[1,1,0.5],[-1,1,0.5]],
            "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]}]}"#,
    )
    .unwrap();
    let out_path = tmp("slab-cut.json");
    let out = voussoir(&[
        "cut",
        slab.to_str().unwrap(),
        "--apex",
        "0,0,-3",
        "--segment",
        "0,-1,0.5,0,1,0.5",
        "--segment",
        "-1,0,0.5,0,0,0.5",
        "-o",
        out_path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("3 new pieces"), "{}", String::from_utf8_lossy(&out.stdout));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out_path).unwrap()).unwrap();
    assert_eq!(v["cuts"][0]["apex"], serde_json::json!([0.0, 0.0, -3.0]));
    assert_eq!(v["cuts"][0]["segments"].as_array().unwrap().len(), 2);
    // Malformed patterns are input errors: a segment through the apex, a segment without apex.
    let bad = voussoir(&[
        "cut",
        slab.to_str().unwrap(),
        "--apex",
        "0,0,-3",
        "--segment",
        "0,0,0,0,0,1",
        "-o",
        tmp("z.json").to_str().unwrap(),
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("segment 0"), "{}", String::from_utf8_lossy(&bad.stderr));
    let bad = voussoir(&[
        "cut",
        slab.to_str().unwrap(),
        "--segment",
        "0,-1,0.5,0,1,0.5",
        "-o",
        tmp("z.json").to_str().unwrap(),
    ]);
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn drop_prints_both_verdicts_and_writes_static_dynamic_agree() {
    let json = tmp("drop.json");
    let out = voussoir(&["drop", "builtin:stack?n=3", "--duration", "0.5", "--json", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("AGREE"));
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["static"]["stands"], true);
    for key in ["stands", "max_drift", "max_rotation", "simulated_s", "wall_s"] {
        assert!(!r["dynamic"][key].is_null(), "dynamic.{key}");
    }
    assert_eq!(r["agree"], true);
    // A falling design exits 1 with both verdicts.
    let out = voussoir(&["analyze", "builtin:harmonic?n=5&s=1.4", "--dynamic", "--duration", "1"]);
    assert_eq!(out.status.code(), Some(1));
    let bad = voussoir(&["drop", "builtin:stack", "--dt", "0"]);
    assert_eq!(bad.status.code(), Some(2));
}

/// `analyze --kinematic` prints both verdicts and flags a disagreement; exits 1 when the
/// kinematic check fails even though the statics stands; the JSON report carries the key
/// `kinematic` with the documented fields. compas_cra's H (supports 0 and 1): RBE holds the
/// bar on a squeeze, the kinematic check lets it fall.
#[test]
fn kinematic_prints_both_verdicts_and_flags_disagreement() {
    let json = tmp("kinematic.json");
    let h = compas_data("compas_cra/H.json");
    let out = voussoir(&["analyze", &h, "--supports", "lowest", "--kinematic", "--json", json.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("STANDS") && text.contains("statics (RBE) stands | kinematic falls: DISAGREE"), "{text}");
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["stands"], true);
    assert_eq!(r["kinematic"]["verdict"], "fails");
    assert_eq!(r["kinematic"]["agrees"], false);
    assert_eq!(r["kinematic"]["mechanism"]["blocks"].as_array().map(|b| b.len()), Some(1));
    for key in ["peak_acceleration", "rounds", "iterations", "residual", "status", "solver_seconds"] {
        assert!(!r["kinematic"][key].is_null(), "kinematic.{key}");
    }
    let out = voussoir(&["analyze", "builtin:stack?n=3", "--kinematic"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).contains("kinematic stands: AGREE"));

    // `sequence --kinematic`: H with its posts as supports, then its bar: the bar's step stands
    // by the statics and falls kinematically (exit 1), with a kinematic check per step in the
    // JSON report.
    let mut scene = voussoir::io::load_scene(std::path::Path::new(&h)).unwrap();
    scene.mark_lowest_as_supports(1e-3);
    let file = tmp("h_supported.json");
    std::fs::write(&file, voussoir::io::scene_json::scene_to_string(&scene)).unwrap();
    let json = tmp("h_sequence.json");
    let out = voussoir(&["sequence", file.to_str().unwrap(), "--kinematic", "--json", json.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("FALLS (!)") && text.contains("first kinematic failure at step 0"), "{text}");
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["steps"][0]["stands"], true);
    assert_eq!(r["steps"][0]["kinematic"]["verdict"], "fails");
}

#[test]
fn sequence_search_props_and_exit_codes() {
    let case = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/cases/fig6_dmsc_sequence.json");
    // The scene's own order (D, M, S, C) fails while D and M are placed: exit 1.
    let json = tmp("seq_given.json");
    let out = voussoir(&["sequence", case, "--json", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in ["order", "steps", "first_failure", "temporary_supports"] {
        assert!(r.get(key).is_some(), "missing {key}");
    }
    assert_eq!(r["first_failure"], 4);
    let step = &r["steps"][4];
    assert_eq!(step["stands"], false);
    assert!(step["tension_ratio"].as_f64().unwrap() > 0.1 && step.get("friction_excess_ratio").is_some());
    // The search finds a standing order: exit 0, no props.
    let json = tmp("seq_search.json");
    let out = voussoir(&["sequence", case, "--search", "--json", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stdout));
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["first_failure"], serde_json::Value::Null);
    assert_eq!(r["temporary_supports"].as_array().unwrap().len(), 0);
    assert_eq!(r["search"]["found"], true);
    // An arch has no standing order: props are proposed, every step then stands, exit 1.
    let json = tmp("seq_arch.json");
    let out = voussoir(&["sequence", "builtin:arch?n=7&t=0.15", "--search", "--json", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let props = r["temporary_supports"].as_array().unwrap();
    assert!(!props.is_empty() && props.iter().all(|p| p["block"].is_string() && p["until"].is_u64()));
    assert_eq!(r["first_failure"], serde_json::Value::Null);
    // The report never goes over the input.
    let input = tmp("seq_input.json");
    std::fs::copy(case, &input).unwrap();
    let out = voussoir(&["sequence", input.to_str().unwrap(), "--json", input.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read(&input).unwrap(), std::fs::read(case).unwrap());
    // Bad orders are bad input.
    let out = voussoir(&["sequence", case, "--order", "D,M,S"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is missing"));
}

#[test]
fn export_writes_a_glb_and_refuses_bad_modes() {
    let out_path = tmp("stack.glb");
    let out = voussoir(&["export", "builtin:stack?n=3", "--gltf", out_path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&out_path).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize, bytes.len());
    let out = voussoir(&["export", "builtin:stack?n=3", "--gltf", out_path.to_str().unwrap(), "--mode", "heat"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--mode heat"));
    let png = tmp("stack.png");
    let out = voussoir(&["export", "builtin:stack?n=3", "--png", png.to_str().unwrap(), "--mode", "vectors"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(&std::fs::read(&png).unwrap()[..4], b"\x89PNG");
    let scene = tmp("stack_scene.json");
    std::fs::write(&scene, std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/cases/fig3c_sc.json")).unwrap())
        .unwrap();
    let before = std::fs::read(&scene).unwrap();
    let out = voussoir(&["export", scene.to_str().unwrap(), "--gltf", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read(&scene).unwrap(), before, "the input is never overwritten");
}

/// The headless build says how to get the viewer instead of failing obscurely.
#[cfg(not(feature = "viewer"))]
#[test]
fn view_without_the_viewer_feature_says_how_to_build_it() {
    let out = voussoir(&["view", "builtin:stack?n=2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--features viewer"));
}

#[test]
fn friction_use_says_what_a_polyhedral_model_allows() {
    // A 40° slope at μ = 0.9: the block needs |f_t| = tan 40° f_n ≈ 0.93 μ f_n.
    let line = |model: &str| {
        let out = voussoir(&["analyze", "builtin:slope?angle=40", "--mu", "0.9", "--friction-model", model]);
        assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        text.lines().find(|l| l.contains("max friction use")).expect("the line is printed").to_string()
    };
    let (pyramid, cone, boxed) = (line("pyramid8"), line("cone"), line("box4"));
    assert!(pyramid.contains("93.2 %") && pyramid.contains("pyramid8 allows up to 108.2 %"), "{pyramid}");
    assert!(cone.contains("93.2 %") && !cone.contains("allows"), "{cone}");
    assert!(boxed.contains("box4 allows up to 141.4 %"), "{boxed}");
}

#[test]
fn a_closed_stdout_is_no_panic_and_the_report_is_still_written() {
    // `voussoir analyze … | head -1`: the reader goes away before the summary is printed.
    let json = tmp("closed_pipe.json");
    let _ = std::fs::remove_file(&json);
    let mut child = Command::new(env!("CARGO_BIN_EXE_voussoir"))
        .args(["analyze", "builtin:stack?n=3", "--json", json.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("it ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(json.exists(), "the JSON report is written");
}

#[test]
fn a_disagreement_says_whether_the_drop_test_came_to_rest() {
    let verdict_line = |args: &[&str]| {
        let out = voussoir(args);
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        text.lines().find(|l| l.starts_with("statics ")).expect("the side-by-side line").to_string()
    };
    // The compas arch: its crown sags 4 % of a block in rapier within 0.1 s, then holds.
    let settled = verdict_line(&["drop", &compas_data("compas_assembly/arch_assembly.json")]);
    assert!(settled.contains("DISAGREE (the blocks moved past the tolerance, then came to rest"), "{settled}");
    // A 15-voussoir arch just above its static limit: rapier lets it hinge and fall.
    let moving = verdict_line(&["drop", "builtin:arch?n=15&t=0.115"]);
    assert!(moving.contains("DISAGREE (still moving at the end"), "{moving}");
    // Both agree on a stack that needs tension.
    let agree = verdict_line(&["drop", &compas_data("compas_assembly/stack_assembly.json")]);
    assert!(agree.ends_with("AGREE") && !agree.contains("DISAGREE"), "{agree}");
}

#[test]
fn the_command_line_is_well_formed() {
    use clap::CommandFactory;
    voussoir::cli::Cli::command().debug_assert();
}

/// One source per default: what the command line gives without options is the library's.
#[test]
fn the_options_default_to_the_librarys_settings() {
    use clap::Parser;
    use voussoir::cli::{AnalyzeArgs, Cli, Command as Cmd};
    let args = AnalyzeArgs::defaults();
    assert_eq!(args.solver.settings(), voussoir::pipeline::AnalysisSettings::default());
    assert_eq!(
        args.drop.settings(None, Default::default(), Default::default()),
        voussoir::dynamics::DropSettings::default()
    );
    let Ok(Cli { command: Some(Cmd::Analyze(parsed)) }) = Cli::try_parse_from(["voussoir", "analyze"]) else {
        panic!("analyze parses")
    };
    assert_eq!(parsed, args, "`voussoir` alone runs `analyze` with its defaults");
    let Ok(Cli { command: Some(Cmd::Export(export)) }) =
        Cli::try_parse_from(["voussoir", "export", "builtin:stack", "--gltf", "x.glb"])
    else {
        panic!("export parses")
    };
    assert_eq!(export.diagram.mode().unwrap(), voussoir::viz::DiagramMode::default());
    assert_eq!(export.diagram.threshold, voussoir::viz::DiagramMode::DEFAULT_THRESHOLD);
    // The exact engine's switches turn the library's defaults over, and only those.
    let flags = ["voussoir", "analyze", "--no-split-impacts", "--rest-when-admissible", "--no-floor", "--rounds-only"];
    let Ok(Cli { command: Some(Cmd::Analyze(flagged)) }) = Cli::try_parse_from(flags) else { panic!("flags parse") };
    let s = flagged.drop.settings(None, Default::default(), Default::default());
    let d = voussoir::dynamics::DropSettings::default();
    assert!(!s.exact.split_impacts && d.exact.split_impacts);
    assert!(s.exact.rest_when_admissible && !d.exact.rest_when_admissible);
    assert!(!s.floor && d.floor);
    assert!(!s.exact.by_states && d.exact.by_states);
    let back = voussoir::dynamics::ExactSettings {
        split_impacts: d.exact.split_impacts,
        rest_when_admissible: d.exact.rest_when_admissible,
        by_states: d.exact.by_states,
        ..s.exact.clone()
    };
    assert_eq!(back, d.exact);
}

#[test]
fn a_wrong_name_is_an_input_error_naming_option_and_value() {
    let out = voussoir(&["analyze", "builtin:stack", "--friction-model", "pyramid9"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: --friction-model pyramid9: expected pyramid8, cone or box4"), "{err}");
    let out = voussoir(&["sweep", "dome"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("arch, slope, harmonic or tilt"));
    // The short spellings stay accepted.
    for model in ["pyramid", "box"] {
        let out = voussoir(&["analyze", "builtin:stack?n=2", "--friction-model", model]);
        assert_eq!(out.status.code(), Some(0), "{model}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

/// A box block as scene JSON: corners `lo`, `hi`, faces counter-clockwise seen from outside.
fn box_json(name: &str, lo: [f64; 3], hi: [f64; 3], support: bool) -> String {
    let v: Vec<String> = (0..8)
        .map(|i| {
            let x = if matches!(i % 4, 1 | 2) { hi[0] } else { lo[0] };
            let y = if matches!(i % 4, 2 | 3) { hi[1] } else { lo[1] };
            let z = if i >= 4 { hi[2] } else { lo[2] };
            format!("[{x},{y},{z}]")
        })
        .collect();
    format!(
        r#"{{"name":"{name}","support":{support},"vertices":[{}],"faces":[[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]}}"#,
        v.join(",")
    )
}

/// Invariant: interpenetrating blocks are a warning in the text report (naming the pair) and,
/// with `--strict`, an input error (exit 2) naming the same pair.
#[test]
fn overlaps_warn_and_strict_refuses_them() {
    let scene = tmp("overlap.json");
    let blocks = [
        box_json("base", [-1.0, -1.0, -1.0], [3.0, 2.0, 0.0], true),
        box_json("a", [0.0, 0.0, 0.0], [1.0, 1.0, 1.0], false),
        box_json("b", [0.8, 0.0, 0.0], [1.8, 1.0, 1.0], false),
    ];
    std::fs::write(&scene, format!(r#"{{"blocks":[{}]}}"#, blocks.join(","))).unwrap();
    let out = voussoir(&["analyze", scene.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("warning: blocks 'a' and 'b' interpenetrate"), "{text}");
    let out = voussoir(&["analyze", scene.to_str().unwrap(), "--strict"]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stdout));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("overlap.json") && err.contains("blocks 'a' and 'b' interpenetrate"), "{err}");
}

/// Invariant: `robustness` prints λ* first and writes it (with the mechanism) to the JSON
/// report: a column of two unit blocks under a horizontal 1 g tips at b/(n h) = 0.5; a
/// vertical load on top is carried at any size (λ* = ∞, `null`); the worst direction writes
/// the polar plot and the mechanism picture; bad loads exit 2 naming the problem.
#[test]
fn robustness_reports_the_load_factor_and_mechanism() {
    let json = tmp("robust.json");
    let out = voussoir(&["robustness", "builtin:stack?n=2", "--direction", "0", "--json", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("LOAD FACTOR λ* = 0.5000"), "{text}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let r = &v["robustness"];
    assert_eq!(r["safety"]["kind"], "collapses");
    assert!((r["load_factor"].as_f64().unwrap() - 0.5).abs() < 1e-6);
    assert_eq!(r["mechanism"]["blocks"].as_array().unwrap().len(), 2);
    let states: Vec<&str> =
        r["mechanism"]["interfaces"].as_array().unwrap().iter().map(|i| i["state"].as_str().unwrap()).collect();
    assert!(states.contains(&"hinging"), "{states:?}");
    for key in ["load", "residual", "iterations", "solver_seconds"] {
        assert!(r.get(key).is_some(), "robustness has '{key}'");
    }

    let out = voussoir(&[
        "robustness",
        "builtin:stack?n=2",
        "--load",
        "box1:0,0,2:0,0,-1000",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["robustness"]["safety"]["kind"], "unlimited");
    assert!(v["robustness"]["load_factor"].is_null());

    let (plot, picture) = (tmp("polar.png"), tmp("mechanism.svg"));
    let out = voussoir(&[
        "robustness",
        "builtin:stack?n=2",
        "--directions",
        "8",
        "--plot",
        plot.to_str().unwrap(),
        "--mechanism",
        picture.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("worst direction"));
    assert!(std::fs::read(&plot).unwrap().starts_with(b"\x89PNG"));
    assert!(std::fs::read_to_string(&picture).unwrap().contains("<svg"));

    for (args, message) in [
        (vec!["--load", "nope:0,0,0:1,0,0"], "no block named 'nope'"),
        (vec!["--load", "box1:1,2"], "expected BLOCK:X,Y,Z:FX,FY,FZ[:dead]"),
        (vec!["--accel", "0.2,0"], "--accel '0.2,0': expected 3 numbers"),
        (vec!["--load", "box1:0,0,9:1,0,0"], "outside block 'box1'"),
    ] {
        let mut all = vec!["robustness", "builtin:stack?n=2"];
        all.extend(args);
        let out = voussoir(&all);
        assert_eq!(out.status.code(), Some(2), "{all:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(message), "{all:?}: {err}");
    }
    // A dead acceleration of 0.6 g tips the column in `analyze` (b/(n h) = 0.5).
    let out = voussoir(&["analyze", "builtin:stack?n=2", "--accel", "0.6,0,0:dead"]);
    assert_eq!(out.status.code(), Some(1));
    let out = voussoir(&["analyze", "builtin:stack?n=2", "--accel", "0.4,0,0:dead"]);
    assert_eq!(out.status.code(), Some(0));
}

/// `--supports-file`: compas_dem's pavillion vault stands with its 10 support meshes added;
/// a missing supports file is bad input naming it (exit 2).
#[test]
fn analyze_takes_a_supports_file() {
    let blocks = compas_data("compas_dem/pavillionvault/blocks.json");
    let supports = compas_data("compas_dem/pavillionvault/supports.json");
    let out = voussoir(&["analyze", &blocks, "--supports-file", &supports]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.contains("387 blocks (10 supports)"), "{text}");
    let out = voussoir(&["analyze", &blocks, "--supports-file", "no-such-supports.json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no-such-supports.json"));
}

/// Invariant: `repair` writes the repaired design (its moved cut reloads and stands by an
/// independent analyze run, exit 0), prints before/after, refuses to write over its input,
/// exits 1 with the support it proposes when no cut can help, and 2 naming a cut the history
/// does not have.
#[test]
fn repair_writes_a_standing_design_or_says_why_not() {
    let out = tmp("repair_fig4a.json");
    let o = voussoir(&["repair", "assets/cases/fig4a_m_cut.json", "--max-turn", "0", "-o", out.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}");
    assert!(text.starts_with("REPAIRED: it stands now"), "{text}");
    assert!(text.contains("needs tension") && text.contains("cut 0: plane through"), "{text}");
    let check = voussoir(&["analyze", out.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", String::from_utf8_lossy(&check.stdout));

    let o = voussoir(&["repair", "assets/cases/fig3a_sc.json", "-o", tmp("repair_fig3a.json").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{text}");
    assert!(
        text.starts_with("NOTHING TO MOVE") && text.contains("a support makes it stand") && text.contains("under 'SC'"),
        "{text}"
    );

    let o = voussoir(&[
        "repair",
        "assets/cases/fig4a_m_cut.json",
        "--cuts",
        "4",
        "-o",
        tmp("repair_bad.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim(),
        "error: assets/cases/fig4a_m_cut.json: cut 4: there are only 1 cuts in the design's history"
    );
    let o = voussoir(&["repair", "assets/cases/fig4a_m_cut.json", "-o", "assets/cases/fig4a_m_cut.json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("would overwrite the input"));
}

/// Invariant: `decompose` cuts a source shape into courses and writes a design whose pieces
/// `analyze` finds (the count it printed), exits with the verdict's code, and refuses a shape
/// that already has a cut history (exit 2, naming the file).
#[test]
fn decompose_writes_courses() {
    let out = tmp("decompose_sc.json");
    let o = voussoir(&["decompose", "assets/cases/fig3a_sc.json", "--max-size", "0.15", "-o", out.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.starts_with("4 courses, 22 pieces (block size 0.1500 m)"), "{text}");
    assert_eq!(o.status.code(), Some(1), "the lettering in running bond needs tension: {text}");
    let check = voussoir(&["analyze", out.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&check.stdout).contains("22 blocks"), "{}", String::from_utf8_lossy(&check.stdout));
    let o = voussoir(&[
        "decompose",
        "assets/cases/fig4a_m_cut.json",
        "--blocks",
        "5",
        "-o",
        tmp("decompose_bad.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr)
            .starts_with("error: assets/cases/fig4a_m_cut.json: the shape already has a cut history")
    );
}

/// Invariant: `decompose --strategy thrust` on a wall of the builtin pier (a straight load
/// path) settles at once with horizontal beds (the thrust is vertical: no bed turns), and an
/// unknown strategy is a bad input naming the option.
#[test]
fn decompose_by_thrust_settles() {
    let shape = tmp("thrust_pier_src.json");
    std::fs::write(
        &shape,
        r#"{"name": "pier", "ground": true, "blocks": [{"name": "pier",
            "vertices": [[0, 0, 0], [0.4, 0, 0], [0.4, 0.3, 0], [0, 0.3, 0], [0, 0, 1.2], [0.4, 0, 1.2], [0.4, 0.3, 1.2], [0, 0.3, 1.2]],
            "faces": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]}]}"#,
    )
    .unwrap();
    let out = tmp("thrust_pier.json");
    let o = voussoir(&[
        "decompose",
        shape.to_str().unwrap(),
        "--max-size",
        "0.4",
        "--strategy",
        "thrust",
        "-o",
        out.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("3 courses, 3 pieces"), "{text}");
    assert!(
        text.contains(
            "beds normal to the thrust after 1 analyses (settled; last turn 0.000°), at most 0.00° from the field's"
        ),
        "{text}"
    );
    assert_eq!(o.status.code(), Some(0), "{text}");
    let o = voussoir(&[
        "decompose",
        shape.to_str().unwrap(),
        "--max-size",
        "0.4",
        "--strategy",
        "funicular",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("--strategy funicular: expected courses, thrust"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Invariant: `settle` on a path that only turns the support says how far it turned — over the
/// path and at the collapse — instead of a movement of 0 m: a cube on a base tilting 60° with
/// μ = 0.8 slides at atan 0.8 = 38.66° (within 0.1°, as tests/it/settlement.rs measures).
#[test]
fn settle_reports_the_turn_of_a_tilting_support() {
    let o = voussoir(&[
        "settle",
        "builtin:stack?n=1&a=0.5",
        "--move",
        "base:0,0,0:0,60,0",
        "--quasi-static",
        "--mu",
        "0.8",
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("turned 60.000° at the end of the path"), "{text}");
    let at = text.split("turned ").nth(2).and_then(|t| t.split('°').next()).and_then(|t| t.parse::<f64>().ok());
    let at = at.unwrap_or_else(|| panic!("a turn at the collapse: {text}"));
    assert!((at - 0.8f64.atan().to_degrees()).abs() < 0.1, "{at}° against 38.66°: {text}");
    assert_eq!(o.status.code(), Some(1), "{text}");
}

/// Invariant: `infill --density-range LO,HI` (the README's form) writes the lightest standing
/// design and its report: the overhang of tests/it/infill.rs (a plank held down by a tail,
/// the lever rule's ratio 2) gets the plank at 150 and the tail at 300 kg/m³ (1e-6), exit 0,
/// and `analyze` of the written design stands; a range that is not two numbers exits 2
/// naming the option and the form.
#[test]
fn infill_writes_the_lightest_standing_design() {
    let scene = tmp("overhang.json");
    let blocks = [
        box_json("support", [-1.0, 0.0, -1.0], [0.0, 1.0, 0.0], true),
        box_json("plank", [-0.8, 0.0, 0.0], [1.2, 1.0, 0.2], false),
        box_json("tail", [-0.8, 0.0, 0.2], [0.0, 1.0, 0.325], false),
    ];
    std::fs::write(&scene, format!(r#"{{"blocks":[{}]}}"#, blocks.join(","))).unwrap();
    let (design, report) = (tmp("overhang_infilled.json"), tmp("overhang_infill_report.json"));
    let (s, d, r) = (scene.to_str().unwrap(), design.to_str().unwrap(), report.to_str().unwrap());
    let out = voussoir(&["infill", s, "--density-range", "150,600", "-o", d, "--json", r]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let after = |name: &str| {
        let blocks = v["blocks"].as_array().expect("blocks");
        blocks.iter().find(|b| b["block"] == name).expect("a block")["after"].as_f64().unwrap()
    };
    assert!((after("plank") - 150.0).abs() < 150.0 * 1e-6, "plank {}", after("plank"));
    assert!((after("tail") - 300.0).abs() < 300.0 * 1e-6, "tail {}", after("tail"));
    let out = voussoir(&["analyze", d]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stdout));
    let out = voussoir(&["infill", s, "--density-range", "150", "-o", d]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--density-range") && err.contains("LO,HI"), "{err}");
}

/// The `Example:` line of a command's help, split into arguments as a shell does.
fn help_example(command: &mut clap::Command) -> Vec<String> {
    let help = command.render_help().to_string();
    let mut lines = help.lines().skip_while(|l| *l != "Example:");
    let line =
        lines.nth(1).unwrap_or_else(|| panic!("`{}` --help has an Example section:\n{help}", command.get_name()));
    shlex::split(line.trim()).expect("the example is quoted as a shell reads it")
}

/// Every command's `--help` ends with one example that parses as that command, and
/// `voussoir --help` lists them all.
#[test]
fn every_command_shows_an_example_that_parses() {
    use clap::CommandFactory;
    let mut cli = voussoir::cli::Cli::command();
    let long_help = cli.render_long_help().to_string();
    // clap's own `help` subcommand aside.
    let names: Vec<String> = cli.get_subcommands().map(|c| c.get_name().to_string()).filter(|n| n != "help").collect();
    assert_eq!(names.len(), voussoir::cli::EXAMPLES.len(), "one example per command");
    for name in &names {
        let args = help_example(cli.find_subcommand_mut(name).expect("the command"));
        assert_eq!(args[0], "voussoir");
        let matches = voussoir::cli::Cli::command()
            .try_get_matches_from(&args)
            .unwrap_or_else(|e| panic!("`{}` does not parse: {e}", args.join(" ")));
        assert_eq!(matches.subcommand_name(), Some(name.as_str()), "{args:?}");
        let line = voussoir::cli::EXAMPLES.iter().find(|(c, _)| c == name).unwrap().1;
        assert!(long_help.lines().any(|l| l.trim() == line), "voussoir --help lists `{line}`");
    }
}

/// Each command's example does what it shows: run from a scratch folder that sees the
/// repository's assets/, it ends with a verdict (exit 0 or 1), never an input error. `view`
/// opens a window: its example only parses (above).
#[cfg(unix)]
#[test]
fn every_commands_example_runs() {
    let dir = tmp("help-examples");
    std::fs::create_dir_all(&dir).unwrap();
    let assets = dir.join("assets");
    if !assets.exists() {
        std::os::unix::fs::symlink(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets"), &assets).unwrap();
    }
    for (name, line) in voussoir::cli::EXAMPLES.iter().filter(|(c, _)| *c != "view") {
        let args = shlex::split(line).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_voussoir")).args(&args[1..]).current_dir(&dir).output().unwrap();
        let code = out.status.code();
        assert!(
            matches!(code, Some(0 | 1)),
            "{name}: `{line}` exits {code:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(!out.stdout.is_empty(), "{name}: `{line}` prints its answer");
    }
}
