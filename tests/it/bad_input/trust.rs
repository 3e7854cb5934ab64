//! Invariant: input the analysis cannot trust is caught at load with one message naming the
//! file, block, vertex or pair — unknown scene keys (a typo is an error with the key meant,
//! metadata a warning), coordinates far outside the model (blamed on their own block, not the
//! one the tolerances would break) and interpenetrating blocks (a warning with the depth, an
//! error when strict) — while sound input (touching blocks, interlocking non-convex blocks,
//! every shipped scene) passes untouched.

use crate::common::*;
use std::path::{Path, PathBuf};
use voussoir::geometry::{Mesh, Point3};
use voussoir::io::{load_scene, scene_json::scene_to_string};
use voussoir::model::{Assembly, Block, ModelError, Overlap, Scene, Warning, builtin};
use voussoir::pipeline::{AnalysisError, AnalysisSettings, Pipeline, analyze};

fn write(name: &str, content: &str) -> PathBuf {
    let p = crate::common::scratch("input-checks").join(name);
    std::fs::write(&p, content).unwrap();
    p
}

/// A support slab under a unit cube, as scene JSON to edit.
fn two_blocks() -> serde_json::Value {
    let scene = Scene::new(
        "pair",
        vec![cuboid("support_ground", [-1.0, -1.0, -1.0], [2.0, 2.0, 0.0]).support(true), cube("top", [0.0; 3], 1.0)],
    );
    serde_json::from_str(&scene_to_string(&scene)).unwrap()
}

fn load_error(name: &str, value: &serde_json::Value) -> String {
    let p = write(name, &value.to_string());
    load_scene(&p).expect_err("must be rejected").to_string()
}

fn unknown_keys(warnings: &[Warning]) -> Vec<(Option<String>, String)> {
    warnings
        .iter()
        .filter_map(|w| match w {
            Warning::UnknownKey { place, key, .. } => Some((place.clone(), key.clone())),
            _ => None,
        })
        .collect()
}

/// Metadata keys at the top level, in a block and in a cut are ignored with one warning each,
/// naming file, place and key; the scene's own values still load, and the warnings reach the
/// analysis (the channel the CLI prints and the JSON report lists).
#[test]
fn metadata_keys_load_with_a_warning_naming_each() {
    let mut v = two_blocks();
    v["params"] = serde_json::json!({"span": 3.0, "rise": 1.2});
    v["generator"] = "rhino-export 7.2".into();
    v["friction"] = 0.5.into();
    v["blocks"][1]["colour"] = serde_json::json!([200, 80, 40]);
    v["cuts"] = serde_json::json!([{"point": [0, 0, 0.5], "normal": [0, 0, 1], "note": "level joint"}]);
    let p = write("metadata.json", &v.to_string());
    let scene = load_scene(&p).expect("metadata must not stop a file from loading");
    assert_eq!(scene.material.friction, 0.5, "known keys still read");
    assert_eq!(scene.cuts.len(), 1);
    let keys = unknown_keys(&scene.warnings);
    assert_eq!(
        keys,
        vec![
            (None, "generator".to_string()),
            (None, "params".to_string()),
            (Some("block 'top'".to_string()), "colour".to_string()),
            (Some("cut 0".to_string()), "note".to_string()),
        ]
    );
    let shown: Vec<String> = scene.warnings.iter().map(|w| w.to_string()).collect();
    assert!(shown[1].contains("metadata.json") && shown[1].ends_with("unknown key `params` ignored"), "{shown:?}");
    assert!(shown[2].contains("block 'top': unknown key `colour` ignored"), "{shown:?}");

    let a = analyze(&scene, &AnalysisSettings::default()).unwrap();
    assert_eq!(unknown_keys(&a.assembly.warnings), keys, "the analysis carries the load warnings");
    assert_eq!(a.assembly.blocks.len(), 3, "the cut was replayed");
    let report: serde_json::Value = serde_json::from_str(&voussoir::report::json::to_json(&a)).unwrap();
    let listed: Vec<&str> = report["warnings"].as_array().unwrap().iter().filter_map(|w| w.as_str()).collect();
    assert!(listed.iter().any(|w| w.contains("unknown key `params`")), "{listed:?}");
}

/// A key within a typo of a known one (at any level) is an error that names the file, the
/// place and the key meant; short keys must be closer (`note` is metadata, not `name`).
#[test]
fn a_typo_of_a_known_key_is_an_error_suggesting_it() {
    let mut v = two_blocks();
    v["frction"] = 0.5.into();
    let e = load_error("typo.json", &v);
    assert!(e.contains("typo.json") && e.ends_with("unknown key `frction`: did you mean `friction`?"), "{e}");

    let mut v = two_blocks();
    v["blocks"][1]["densty"] = 2400.into();
    let e = load_error("typo_block.json", &v);
    assert!(e.ends_with("block 'top': unknown key `densty`: did you mean `density`?"), "{e}");

    let mut v = two_blocks();
    v["blocks"][1]["supports"] = true.into();
    assert!(load_error("typo_support.json", &v).ends_with("did you mean `support`?"));

    let mut v = two_blocks();
    v["cuts"] = serde_json::json!([{"point": [0, 0, 0.5], "normall": [0, 0, 1]}]);
    assert!(load_error("typo_cut.json", &v).ends_with("cut 0: unknown key `normall`: did you mean `normal`?"));

    let mut v = two_blocks();
    v["Gravity"] = serde_json::json!([0, 0, -9.81]);
    assert!(load_error("typo_case.json", &v).ends_with("did you mean `gravity`?"));

    let mut v = two_blocks();
    v["note"] = "two edits from `name`, but four letters".into();
    v["blocks"][1]["nme"] = "x".into();
    assert!(load_error("typo_short.json", &v).ends_with("block 'top': unknown key `nme`: did you mean `name`?"));
}

/// A scene with a unit cube whose vertex `v` is moved to `p`, on a support slab.
fn with_vertex(v: usize, p: [f64; 3]) -> Scene {
    let mut top = cube("top", [0.0; 3], 1.0);
    top.mesh.vertices[v] = Point3::from(p);
    Scene::new("pair", vec![cuboid("support_ground", [-1.0, -1.0, -1.0], [2.0, 2.0, 0.0]).support(true), top])
}

/// A vertex at 1e308 (or any coordinate past the range) is blamed on its own block, vertex and
/// coordinates — before, the slab validated first collapsed under the tolerances it set.
#[test]
fn a_coordinate_out_of_range_names_its_block_and_vertex() {
    for p in [[1e308, 1.0, 1.0], [1.0, -2e15, 1.0]] {
        let e = Assembly::new(&with_vertex(6, p), &Default::default()).unwrap_err().to_string();
        assert!(e.starts_with("block 'top': vertex 6 at ") && e.contains("out of range"), "{e}");
        assert!(!e.contains("support_ground"), "{e}");
        let e = analyze(&with_vertex(6, p), &AnalysisSettings::default()).unwrap_err().to_string();
        assert!(e.starts_with("block 'top': vertex 6"), "{e}");
    }
    assert!(
        Assembly::new(&with_vertex(6, [1e308, 1.0, 1.0]), &Default::default())
            .unwrap_err()
            .to_string()
            .contains("1e308")
    );
    // Through a file and a cut history (the sources are repaired before the replay).
    let mut v = two_blocks();
    v["blocks"][1]["vertices"][6] = serde_json::json!([1.0, 1.0, 1e308]);
    v["cuts"] = serde_json::json!([{"point": [0, 0, 0.5], "normal": [0, 0, 1]}]);
    let p = write("far.json", &v.to_string());
    let e = analyze(&load_scene(&p).unwrap(), &AnalysisSettings::default()).unwrap_err().to_string();
    assert!(e.contains("'top'") && e.contains("vertex 6") && e.contains("out of range"), "{e}");
}

/// A vertex cut off from the rest of the model by a gap of more than 1/coplanar (333) times the
/// rest's size is blamed on its own block with the gap; a design beside a support slab ten
/// times its size, stacks side by side and every built-in scene pass.
#[test]
fn a_vertex_far_outside_the_model_names_its_block_and_vertex() {
    let e = Assembly::new(&with_vertex(5, [1.0, 0.0, 1e4]), &Default::default()).unwrap_err();
    let ModelError::Mesh { block, source } = &e else { panic!("{e}") };
    assert_eq!(block, "top");
    let msg = e.to_string();
    assert!(
        msg.starts_with(
            "block 'top': vertex 5 at [1.0, 0.0, 10000.0] lies 9999 m beyond the rest of the model along z"
        ),
        "{msg}"
    );
    let voussoir::geometry::MeshError::FarOutside { size, limit, .. } = source else { panic!("{e}") };
    assert_close(*size, (9.0f64 + 9.0 + 4.0).sqrt(), 1e-12, "the slab and cube without the vertex");
    assert_close(*limit, 1.0 / 3e-3, 1e-9, "1 / coplanar");
    // Just inside the limit: loads (whatever the mesh makes of it).
    let inside = 300.0 * (22f64).sqrt();
    assert!(!matches!(
        Assembly::new(&with_vertex(5, [1.0, 0.0, 1.0 + inside]), &Default::default()),
        Err(ModelError::Mesh { source: voussoir::geometry::MeshError::FarOutside { .. }, .. })
    ));

    let mut big_slab = builtin("stack?n=3").unwrap();
    big_slab.blocks[0] = cuboid("base", [-15.0, -15.0, -1.0], [15.0, 15.0, 0.0]).support(true);
    Assembly::new(&big_slab, &Default::default()).expect("a big support slab is sane");
    for spec in
        ["stacks?k=6&n=2", "arch?n=40&t=0.1", "wall?courses=5&bricks=5", "slope?angle=30", "dome", "harmonic?n=8"]
    {
        analyze(&builtin(spec).unwrap(), &AnalysisSettings::default()).unwrap_or_else(|e| panic!("{spec}: {e}"));
    }
}

fn overlaps(warnings: &[Warning]) -> Vec<&Overlap> {
    warnings
        .iter()
        .filter_map(|w| match w {
            Warning::Overlap(o) => Some(o),
            _ => None,
        })
        .collect()
}

/// Unit cubes `a` at the origin and `b` shifted by `dx` along x, on a support slab.
fn cubes(dx: f64) -> Scene {
    Scene::new(
        "cubes",
        vec![
            cuboid("base", [-1.0, -1.0, -1.0], [3.0, 2.0, 0.0]).support(true),
            cube("a", [0.0; 3], 1.0),
            cube("b", [dx, 0.0, 0.0], 1.0),
        ],
    )
}

/// Two unit cubes pushed 0.2 into each other: one warning naming the pair with depth 0.2 =
/// 0.2 of the size 1, first among the warnings; an error naming the same when strict.
#[test]
fn overlapping_cubes_warn_with_the_pair_and_depth_and_fail_when_strict() {
    let a = analyze(&cubes(0.8), &AnalysisSettings::default()).unwrap();
    let found = overlaps(&a.assembly.warnings);
    assert_eq!(found.len(), 1, "{:?}", a.assembly.warnings);
    let o = found[0];
    assert_eq!((o.a.as_str(), o.b.as_str()), ("a", "b"));
    assert_close(o.depth, 0.2, 1e-6, "depth");
    assert_close(o.size, 1.0, 1e-12, "the thinner block's thickness: the cube's edge");
    assert_close(o.relative(), 0.2, 1e-6, "relative depth");
    assert_close(o.tolerance, 3e-3 * a.assembly.scale, 1e-12, "the coplanarity tolerance");
    assert!(matches!(a.assembly.warnings[0], Warning::Overlap(_)), "first: it can make the statics wrong");
    let shown = a.assembly.warnings[0].to_string();
    assert!(
        shown
            .starts_with("blocks 'a' and 'b' interpenetrate 0.200 m deep (0.200 of the thinner one's thickness 1.00 m"),
        "{shown}"
    );

    let strict = AnalysisSettings { strict: true, ..Default::default() };
    let e = analyze(&cubes(0.8), &strict).unwrap_err();
    let AnalysisError::Model(ModelError::Overlap { overlap, others }) = &e else { panic!("{e}") };
    assert_eq!((overlap.a.as_str(), overlap.b.as_str(), *others), ("a", "b", 0));
    assert_close(overlap.depth, 0.2, 1e-6, "depth");
    assert!(e.to_string().starts_with("blocks 'a' and 'b' interpenetrate 0.200 m deep"), "{e}");

    // Three cubes in a row, each 0.3 into the next: the error names the deepest and counts the rest.
    let mut three = cubes(0.8);
    three.blocks.push(cube("c", [1.5, 0.0, 0.0], 1.0));
    let e = analyze(&three, &strict).unwrap_err();
    let AnalysisError::Model(ModelError::Overlap { overlap, others }) = &e else { panic!("{e}") };
    assert_eq!((overlap.a.as_str(), overlap.b.as_str(), *others), ("b", "c", 1), "{e}");
    assert_close(overlap.depth, 0.3, 1e-6, "the deepest");
    assert!(e.to_string().ends_with("; 1 other pair(s) interpenetrate too"), "{e}");
}

/// Cubes sharing a face (and a stack on its slab), cubes closed 0.1 mm into each other (within
/// the coplanarity tolerance: an interface) and cubes apart give no warning, strict or not.
#[test]
fn touching_blocks_give_no_warning() {
    let strict = AnalysisSettings { strict: true, ..Default::default() };
    for dx in [1.0, 1.0 - 1e-4, 1.5] {
        let a = analyze(&cubes(dx), &strict).unwrap_or_else(|e| panic!("dx {dx}: {e}"));
        assert!(overlaps(&a.assembly.warnings).is_empty(), "dx {dx}: {:?}", a.assembly.warnings);
    }
    let a = analyze(&builtin("stacks?k=3&n=3").unwrap(), &strict).unwrap();
    assert!(a.assembly.warnings.is_empty(), "{:?}", a.assembly.warnings);
}

/// An L-shaped block with a cube in its notch: the L's hull contains half the cube, the
/// blocks only touch — no warning. The cube pushed 0.2 into the L's arm: 0.2 deep.
#[test]
fn interlocking_non_convex_blocks_are_measured_by_their_convex_parts() {
    let l = Block::new("L", Mesh::extrude_z(&[[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]], 0.0, 1.0));
    let scene = |x: f64| {
        Scene::new(
            "notch",
            vec![
                cuboid("base", [-1.0, -1.0, -1.0], [3.0, 3.0, 0.0]).support(true),
                l.clone(),
                cube("key", [x, 1.0, 0.0], 1.0),
            ],
        )
    };
    let strict = AnalysisSettings { strict: true, ..Default::default() };
    let a = analyze(&scene(1.0), &strict).expect("a key in a notch touches, it does not overlap");
    assert!(overlaps(&a.assembly.warnings).is_empty());
    let a = analyze(&scene(0.8), &AnalysisSettings::default()).unwrap();
    let found = overlaps(&a.assembly.warnings);
    assert_eq!(found.len(), 1, "{:?}", a.assembly.warnings);
    assert_eq!((found[0].a.as_str(), found[0].b.as_str()), ("L", "key"));
    assert_close(found[0].depth, 0.2, 1e-6, "depth into the arm");
}

/// The pipeline remembers the pairs it checked: a re-run finds the same overlaps, an edit
/// that separates the blocks clears the warning, one that pushes them back brings it back.
#[test]
fn a_pipeline_rerun_gives_the_fresh_overlaps() {
    let settings = AnalysisSettings::default();
    let mut p = Pipeline::new();
    let first = p.run(&cubes(0.8), &settings).unwrap();
    let again = p.run(&cubes(0.8), &settings).unwrap();
    assert_eq!(again.assembly.warnings, first.assembly.warnings);
    assert!(overlaps(&p.run(&cubes(1.0), &settings).unwrap().assembly.warnings).is_empty());
    let back = p.run(&cubes(0.7), &settings).unwrap();
    assert_eq!(overlaps(&back.assembly.warnings).len(), 1);
    assert_close(overlaps(&back.assembly.warnings)[0].depth, 0.3, 1e-6, "depth");
}

/// The reference data loads with no coordinate error and no unknown-key warning; the scenes
/// shipped in assets/ as well.
#[test]
fn shipped_scenes_pass_the_checks() {
    for rel in assembly_files() {
        let scene = load_scene(&compas_data(&rel)).unwrap();
        assert!(scene.warnings.is_empty(), "{rel}: {:?}", scene.warnings);
        Assembly::new(&scene, &Default::default()).unwrap_or_else(|e| panic!("{rel}: {e}"));
    }
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let mut files = vec![assets.join("default.json")];
    files.extend(std::fs::read_dir(assets.join("cases")).unwrap().map(|e| e.unwrap().path()));
    for f in files.iter().filter(|f| f.extension().is_some_and(|e| e == "json")) {
        let scene = load_scene(f).unwrap();
        assert!(scene.warnings.is_empty(), "{}: {:?}", f.display(), scene.warnings);
        analyze(&scene, &AnalysisSettings::default()).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
    }
}

/// Through the binary: a typo exits 2 with one line naming the file and the key meant; a file
/// with metadata runs, and the JSON report lists the warning naming the key.
#[test]
fn the_cli_rejects_typos_and_reports_ignored_keys() {
    let run = |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_voussoir")).args(args).output().unwrap();
    let mut v = two_blocks();
    v["frction"] = 0.5.into();
    let typo = write("cli_typo.json", &v.to_string());
    let out = run(&["analyze", typo.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: ") && err.contains("cli_typo.json"), "{err}");
    assert!(
        err.trim_end().ends_with("unknown key `frction`: did you mean `friction`?") && err.lines().count() == 1,
        "{err}"
    );

    let mut v = two_blocks();
    v["params"] = serde_json::json!({"n": 1});
    let meta = write("cli_meta.json", &v.to_string());
    let report = meta.with_file_name("cli_meta_report.json");
    let out = run(&["analyze", meta.to_str().unwrap(), "--json", report.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("unknown key `params` ignored"));
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["warnings"][0].as_str().unwrap(), format!("{}: unknown key `params` ignored", meta.display()));
}

fn scaled(mut scene: Scene, s: f64) -> Scene {
    for b in &mut scene.blocks {
        b.mesh = b.mesh.scaled_translated(s, nalgebra::Vector3::zeros());
    }
    scene
}

/// The overlap check does not depend on the unit (parry's f32 queries run on shapes of about
/// unit size): the overlapping cubes give depth 0.2 × the unit from picometres to 1e10, a sound
/// arch no warning; a model under 1e-15 across (whose areas underflow) is an error, not a
/// design that silently loses its interfaces.
#[test]
fn the_checks_hold_in_any_unit() {
    for s in [1e-12, 1e-3, 1.0, 1e3, 1e10] {
        let a = analyze(&scaled(cubes(0.8), s), &AnalysisSettings::default()).unwrap();
        let found = overlaps(&a.assembly.warnings);
        assert_eq!(found.len(), 1, "unit {s}: {:?}", a.assembly.warnings);
        assert_close(found[0].depth / s, 0.2, 1e-6, "depth");
        assert_close(found[0].relative(), 0.2, 1e-6, "relative depth");
        let arch = analyze(&scaled(builtin("arch?n=15&t=0.15").unwrap(), s), &AnalysisSettings::default()).unwrap();
        assert!(arch.assembly.warnings.is_empty(), "unit {s}: {:?}", arch.assembly.warnings);
        assert_eq!(arch.interfaces.len(), 16, "unit {s}");
    }
    let e = analyze(&scaled(builtin("arch?n=15&t=0.15").unwrap(), 1e-100), &AnalysisSettings::default()).unwrap_err();
    assert!(matches!(e, AnalysisError::Model(ModelError::TooSmall(_))), "{e}");
    assert!(e.to_string().starts_with("the model is only 2.") && e.to_string().contains("smaller unit"), "{e}");
}
