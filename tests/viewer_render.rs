//! The viewer rendered for real: one window (Xvfb and Mesa's software Vulkan in CI), one app,
//! one script. The default scene and failing scenes are shot in each diagram mode and the
//! pixels of the 3D view are classified by hue; editing, undo/redo, save, the drop test and the
//! sequence stepper are driven through the same actions the keys and buttons send.
//!
//! Runs on the main thread (winit's event loop must), hence `harness = false`:
//! `cargo test --features viewer --test viewer_render` (under `xvfb-run` without a display).

use image::RgbImage;
use serde_json::Value;
use std::path::Path;
use voussoir::dynamics::Engine;
use voussoir::model::builtin;
use voussoir::viewer::{Script, ScriptStep, ViewerAction, ViewerOptions};
use voussoir::viz::DiagramMode;

/// Pixel counts of the 3D view by colour class.
#[derive(Default)]
struct Census {
    total: usize,
    blue: usize,
    red: usize,
    yellow: usize,
    orange: usize,
    green: usize,
    sandstone: usize,
    /// The motion pane's moved blocks.
    violet: usize,
    /// Hues of the orange pixels (degrees).
    orange_hues: Vec<f32>,
}

/// Hue (degrees), saturation and value of an sRGB pixel.
impl std::fmt::Debug for Census {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let Census { total, blue, red, yellow, orange, green, sandstone, violet, .. } = self;
        write!(
            f,
            "total {total}, blue {blue}, red {red}, yellow {yellow}, orange {orange}, green {green}, \
             sandstone {sandstone}, violet {violet}"
        )
    }
}

/// The 5th and 95th percentiles of `hues`.
fn spread(hues: &[f32]) -> (f32, f32) {
    let mut h = hues.to_vec();
    h.sort_by(f32::total_cmp);
    (h[h.len() / 20], h[h.len() * 19 / 20])
}

fn hsv(p: [u8; 3]) -> (f32, f32, f32) {
    let [r, g, b] = p.map(|c| c as f32 / 255.0);
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let d = max - min;
    let h = if d == 0.0 {
        0.0
    } else if max == r {
        60.0 * (((g - b) / d).rem_euclid(6.0))
    } else if max == g {
        60.0 * ((b - r) / d + 2.0)
    } else {
        60.0 * ((r - g) / d + 4.0)
    };
    (h, if max > 0.0 { d / max } else { 0.0 }, max)
}

fn census(img: &RgbImage, rect: [u32; 4]) -> Census {
    let mut c = Census::default();
    for y in rect[1]..rect[3].min(img.height()) {
        for x in rect[0]..rect[2].min(img.width()) {
            let (h, s, v) = hsv(img.get_pixel(x, y).0);
            c.total += 1;
            // Tension's light end is pink (the gradient is per face): red and pink count.
            if !(12.0..=348.0).contains(&h) && s > 0.08 && v > 0.4 {
                c.red += 1;
                continue;
            }
            if s < 0.25 || v < 0.2 {
                continue;
            }
            match h {
                h if (200.0..=250.0).contains(&h) && s > 0.4 => c.blue += 1,
                h if (45.0..=65.0).contains(&h) && s > 0.4 => c.yellow += 1,
                h if (18.0..=40.0).contains(&h) && s > 0.45 => {
                    c.orange += 1;
                    c.orange_hues.push(h);
                }
                h if (100.0..=150.0).contains(&h) && s > 0.5 => c.green += 1,
                h if (20.0..=45.0).contains(&h) && s <= 0.45 => c.sandstone += 1,
                h if (250.0..=290.0).contains(&h) && s > 0.25 => c.violet += 1,
                _ => {}
            }
        }
    }
    c
}

fn shot(report: &Value, name: &str) -> Value {
    report["shots"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["path"].as_str().unwrap().ends_with(&format!("{name}.png")))
        .unwrap_or_else(|| panic!("no shot {name}"))
        .clone()
}

fn rect(v: &Value) -> [u32; 4] {
    let a: Vec<u32> = v.as_array().expect("a viewport").iter().map(|x| x.as_u64().unwrap() as u32).collect();
    [a[0], a[1], a[2], a[3]]
}

fn picture(s: &Value, viewport: &str) -> Census {
    let img = image::open(s["path"].as_str().unwrap()).expect("a PNG").to_rgb8();
    census(&img, rect(&s[viewport]))
}

fn main() {
    no_display_is_one_clear_error();
    // Cargo's scratch space for integration tests, emptied first: nothing left in the system's
    // temporary folder, no screenshot of an earlier run read as this one's.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = |name: &str| dir.join(format!("{name}.png"));
    let friction = DiagramMode::Friction { threshold: 0.5 };
    let default_scene = voussoir::cli::load(None).unwrap();
    let saved = dir.join("saved.json");
    use ScriptStep::*;
    use ViewerAction as A;
    let steps = vec![
        Settle(5),
        Shot(path("default_compression")),
        Act(A::SetMode(friction)),
        Settle(3),
        Shot(path("default_friction")),
        Act(A::SetMode(DiagramMode::Vectors)),
        Settle(3),
        Shot(path("default_vectors")),
        // Thinner than Milankovitch's minimum (t/R ≈ 0.1075): needs tension.
        Act(A::SetMode(DiagramMode::Compression)),
        Load(Box::new(builtin("arch?n=15&t=0.08").unwrap())),
        Settle(5),
        Shot(path("tension_compression")),
        // tan 35° = 0.70 > μ = 0.5: slides, friction exceeded.
        Act(A::SetMode(friction)),
        Load(Box::new(builtin("slope?angle=35&mu=0.5").unwrap())),
        Settle(5),
        Shot(path("sliding_friction")),
        // tan 25° / 0.7 = 0.666: above the threshold, within μ: one orange interface.
        Load(Box::new(builtin("slope?angle=25&mu=0.7").unwrap())),
        Settle(5),
        Shot(path("orange_friction")),
        // The seed paper's Fig 6 in both modes.
        Load(Box::new(fig6())),
        Settle(5),
        Shot(path("fig6_friction")),
        Act(A::SetMode(DiagramMode::Compression)),
        Settle(3),
        Shot(path("fig6_compression")),
        // Editing: cut the top cube of a stack, move the cut, undo, redo, undo, save.
        Load(Box::new(builtin("stack?n=2").unwrap())),
        Settle(3),
        // Picked as a click would: the ray towards box1's centre meets box1 first.
        Act(A::ClickToward([0.0, 0.0, 1.5])),
        Settle(2),
        Act(A::AddCut),
        Settle(3),
        Act(A::ShiftCut(0.1)),
        Settle(3),
        Act(A::Undo),
        Act(A::Redo),
        Act(A::Undo),
        Act(A::Save),
        Settle(3),
        Shot(path("edited")),
        Act(A::ClickToward([0.0, 0.0, 0.5])),
        Settle(2),
        Act(A::RemoveBlock),
        Settle(3),
        Shot(path("removed")),
        Act(A::RestoreBlock),
        Settle(3),
        Shot(path("restored")),
        // The drop test beside the statics, then the sequence stepper, on the default arch.
        Load(Box::new(default_scene.clone())),
        Act(A::DropTest(Engine::Rapier)),
        Settle(3),
        Shot(path("drop")),
        Act(A::DropTest(Engine::Exact)),
        Settle(3),
        Shot(path("drop_exact")),
        Act(A::CompareEngines),
        Settle(3),
        Shot(path("drop_both")),
        Act(A::ResetDrop),
        Act(A::StartSequence),
        Settle(3),
        Act(A::Step(8)),
        Settle(3),
        Shot(path("sequence")),
        // The collapse mechanism of the default arch's worst horizontal direction, beside it.
        Act(A::ExitSequence),
        Act(A::ToggleMechanism),
        Settle(5),
        Shot(path("mechanism")),
        // compas_cra's H as its file has it, with no support: the panel says so, no solver numbers.
        Load(Box::new(letter_h_unsupported())),
        Settle(3),
        Shot(path("unsupported")),
        // The kinematic check of compas_cra's letter H on its lowest blocks (`--supports
        // lowest`): RBE holds the bar, released from rest it falls; its mechanism is drawn
        // beside the design (the load factor's pane closes).
        Load(Box::new(letter_h())),
        Act(A::ToggleKinematic),
        Settle(5),
        Shot(path("kinematic")),
        // The paper's M (Fig 4a: its cut through the V needs tension), repaired with O: the
        // cut glides into place and the design stands; the keys listed too.
        Act(A::ToggleKinematic),
        Load(Box::new(fig4a())),
        Settle(3),
        Act(A::Repair),
        Act(A::ToggleKeys),
        Settle(3),
        Shot(path("repaired")),
        // A lintel on a settling pier (P): the quasi-static motion played in the pane, the
        // thrust curve under it.
        Act(A::ToggleKeys),
        Load(Box::new(settling_lintel())),
        Settle(3),
        Act(A::Settle),
        Settle(3),
        Shot(path("settle")),
        // A slender block on the ground under its scene's 1.5 s pulse of 0.3 g (W): λ* = 0.2,
        // it overturns; its fall played in the pane, the ground's trace and λ* under it.
        Act(A::ResetDrop),
        Load(Box::new(shaken_block())),
        Settle(3),
        Act(A::Shake),
        Settle(3),
        Shot(path("shake")),
    ];
    let report_path = dir.join("report.json");
    let mut options = ViewerOptions::new(default_scene);
    // The smallest window the panel must fit (VOUSSOIR_SHOT_SIZE=1280x800 shoots another).
    options.size = std::env::var("VOUSSOIR_SHOT_SIZE")
        .ok()
        .and_then(|s| s.split_once('x').and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?))))
        .unwrap_or((1024, 640));
    options.save_to = Some(saved.clone());
    options.script = Some(Script { steps, report: Some(report_path.clone()) });
    let width = options.size.0;
    let exit = voussoir::viewer::run(options);
    assert!(exit.is_success(), "the scripted session failed: {exit:?}");
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    check(&report, &saved, width);
    // The line .ci/run sums, as the test harness prints it.
    println!("test result: ok. 1 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out (viewer_render)");
    if std::env::var_os("VOUSSOIR_KEEP_SHOTS").is_none() {
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// Without a display `view` says so and exits 2, and writes no screenshot.
fn no_display_is_one_clear_error() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-display.png");
    let _ = std::fs::remove_file(&out);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_voussoir"))
        .args(["view", "--screenshot"])
        .arg(&out)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the CLI runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(stderr.starts_with("error: no display") && stderr.contains("xvfb-run"), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
    assert!(!String::from_utf8_lossy(&run.stdout).contains("screenshot written"));
    assert!(!out.exists());
}

/// The seed paper's Fig 6: DMSC in many pieces.
fn fig6() -> voussoir::model::Scene {
    voussoir::io::load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases/fig6_dmsc.json")).unwrap()
}

/// The seed paper's Fig 4a: the M cut at z = 0.2 through its V.
fn fig4a() -> voussoir::model::Scene {
    voussoir::io::load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases/fig4a_m_cut.json")).unwrap()
}

/// compas_cra's letter H as its file has it: nothing marked as a support.
fn letter_h_unsupported() -> voussoir::model::Scene {
    voussoir::io::load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/H.json")).unwrap()
}

/// compas_cra's letter H on its two posts, as `view H.json --supports lowest --mu 0.84` opens it.
fn letter_h() -> voussoir::model::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/H.json");
    let mut scene = voussoir::io::load_scene(&path).unwrap();
    let options = voussoir::cli::options::SceneOptions { supports: Some("lowest".into()), ..Default::default() };
    options.apply(&mut scene, &Default::default()).unwrap();
    scene.material.friction = 0.84;
    scene
}

/// A 3 × 1 × 0.3 lintel on two 1 m piers, the right one settling 0.1 m (its `movements`).
fn settling_lintel() -> voussoir::model::Scene {
    use voussoir::geometry::{Mesh, Point3};
    use voussoir::model::{Block, Movement, Scene};
    let cuboid =
        |name: &str, min: [f64; 3], max: [f64; 3]| Block::new(name, Mesh::cuboid(Point3::from(min), Point3::from(max)));
    let mut scene = Scene::new(
        "settling lintel",
        vec![
            cuboid("left", [0.0, 0.0, -1.0], [0.5, 1.0, 0.0]).support(true),
            cuboid("right", [2.5, 0.0, -1.0], [3.5, 1.0, 0.0]).support(true),
            cuboid("lintel", [0.0, 0.0, 0.0], [3.0, 1.0, 0.3]),
        ],
    );
    scene.movements = vec![Movement { block: "right".into(), translation: [0.0, 0.0, -0.1], rotation: [0.0; 3] }];
    scene
}

/// Every section of the panel lies within the panel and the window; a section written as
/// lines (not free text) has no line wrapped.
fn panel_fits(report: &Value, logical_width: u32) {
    for s in report["shots"].as_array().unwrap() {
        let [w, h] = [0, 1].map(|k| s["size"][k].as_f64().unwrap());
        let panel = voussoir::viewer::PANEL_WIDTH as f64 * w / logical_width as f64;
        for section in s["panel"].as_array().expect("the panel's layout") {
            let r: Vec<f64> = section["rect"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
            let name = &s["path"];
            assert!(
                r[0] >= -0.5 && r[1] >= -0.5 && r[2] <= panel + 0.5 && r[3] <= h + 0.5,
                "{name}: {section} outside {panel}×{h}"
            );
            if !section["may_wrap"].as_bool().unwrap() {
                assert!(
                    section["visual_lines"].as_u64() <= section["lines"].as_u64(),
                    "{name}: a line wraps: {section}"
                );
            }
        }
    }
}

/// The friction diagram's bands of a shot's interfaces.
fn bands(s: &Value) -> Vec<String> {
    s["friction_bands"].as_array().unwrap().iter().map(|b| b["band"].as_str().unwrap().to_string()).collect()
}

fn check(report: &Value, saved: &Path, logical_width: u32) {
    panel_fits(report, logical_width);
    // The default arch stands: blue compression, no red tension; 17 blocks, 16 interfaces.
    let s = shot(report, "default_compression");
    assert_eq!((s["blocks"].as_u64(), s["interfaces"].as_u64()), (Some(17), Some(16)), "{s}");
    assert_eq!(s["verdict"], "Stands");
    let c = picture(&s, "main_viewport");
    println!("default, compression: {c:?}");
    assert!(c.blue > c.total / 200, "blue compression is shown: {c:?}");
    assert!(c.red < c.blue / 50, "no tension on a standing arch: {c:?}");
    assert_eq!(s["view_caption"], "the design · compression (blue) and tension (red)", "{s}");
    // Friction: at most 45 % of μ everywhere, below the 50 % threshold: yellow, nothing red.
    let s = shot(report, "default_friction");
    assert!(bands(&s).iter().all(|b| b == "yellow" || b == "no friction"), "{s}");
    let c = picture(&s, "main_viewport");
    println!("default, friction: {c:?}");
    assert!(c.yellow > c.total / 400, "low friction is yellow: {c:?}");
    assert!(c.red < c.yellow / 50 && c.blue < c.yellow / 50 && c.orange < c.yellow / 50, "{c:?}");
    // Vectors: green resultant arrows over the blue compression.
    let c = picture(&shot(report, "default_vectors"), "main_viewport");
    println!("default, vectors: {c:?}");
    assert!(c.green > 100 && c.blue > c.total / 200, "{c:?}");
    // Too thin an arch needs tension: red appears.
    let s = shot(report, "tension_compression");
    assert_eq!(s["verdict"], "NeedsTension");
    let c = picture(&s, "main_viewport");
    println!("thin arch, compression: {c:?}");
    assert!(c.red > 50, "tension is red: {c:?}");
    // A block sliding down a slope: friction exceeded, red.
    let s = shot(report, "sliding_friction");
    assert_eq!(s["verdict"], "NeedsFriction");
    let c = picture(&s, "main_viewport");
    println!("slope, friction: {c:?}");
    assert!(c.red > c.total / 200 && c.yellow < c.red / 10, "exceeded friction is red: {c:?}");

    // One orange interface at u = 0.67: orange pixels of one hue, the band's; the panel's
    // largest use is the band's.
    let s = shot(report, "orange_friction");
    assert_eq!(bands(&s), ["orange"], "{s}");
    let u = s["max_friction_use"].as_f64().unwrap();
    assert!((u - 25f64.to_radians().tan() / 0.7).abs() < 1e-6, "{s}");
    let c = picture(&s, "main_viewport");
    println!("slope within μ, friction: {c:?}");
    assert!(c.orange > c.total / 400 && c.yellow < c.orange / 50 && c.red < c.orange / 50, "{c:?}");
    let (lo, hi) = spread(&c.orange_hues);
    let band = &s["friction_bands"][0]["colour"];
    let srgb = |k: usize| {
        let l = band[k].as_f64().unwrap() as f32;
        let v = if l <= 0.0031308 { 12.92 * l } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 };
        (v * 255.0).round() as u8
    };
    let (expected, _, _) = hsv([srgb(0), srgb(1), srgb(2)]);
    assert!(
        hi - lo < 6.0 && lo - 3.0 <= expected && expected <= hi + 3.0,
        "one orange, the band's: {lo}–{hi} vs {expected}"
    );
    // Fig 6 (largest use 0.40 μ, by the panel): every interface yellow or grey, no orange.
    let s = shot(report, "fig6_friction");
    assert!(bands(&s).iter().all(|b| b == "yellow" || b == "no friction"), "{s}");
    let numbers = s["panel"].as_array().unwrap().iter().find(|p| p["section"] == "Numbers").unwrap();
    let u = s["max_friction_use"].as_f64().unwrap();
    assert!(numbers["text"].as_str().unwrap().contains(&format!("{u:.2} μN")), "{numbers}");
    let c = picture(&s, "main_viewport");
    println!("fig6, friction: {c:?}");
    assert!(c.yellow > c.total / 1000 && c.orange < c.yellow / 50 && c.red < c.yellow / 50, "{c:?}");
    let c = picture(&shot(report, "fig6_compression"), "main_viewport");
    println!("fig6, compression: {c:?}");
    assert!(c.blue > c.total / 1000 && c.red < c.blue / 50, "{c:?}");

    // Editing: cut box1 (4 blocks with the slab), the move undone, so the cut halves box1: the
    // saved design has that one cut, through box1's centroid (0, 0, 1.5).
    let s = shot(report, "edited");
    assert_eq!((s["cuts"].as_u64(), s["blocks"].as_u64()), (Some(1), Some(4)), "{s}");
    assert_eq!((s["undo"].as_u64(), s["redo"].as_u64()), (Some(1), Some(1)), "{s}");
    let design: Value = serde_json::from_str(&std::fs::read_to_string(saved).expect("the design was saved")).unwrap();
    let cut = &design["cuts"][0];
    let point: Vec<f64> = cut["point"].as_array().expect("a plane cut").iter().map(|x| x.as_f64().unwrap()).collect();
    let centroid = voussoir::pipeline::analyze(&builtin("stack?n=2").unwrap(), &Default::default())
        .unwrap()
        .assembly
        .blocks
        .iter()
        .find(|b| b.name == "box1")
        .unwrap()
        .mass
        .centroid;
    for k in 0..3 {
        assert!((point[k] - centroid[k]).abs() < 1e-9, "cut through box1's centroid: {point:?} vs {centroid:?}");
    }
    let s = shot(report, "removed");
    assert_eq!(s["removed"], serde_json::json!(["box0"]), "the clicked block is removed: {s}");
    assert_eq!(s["blocks"].as_u64(), Some(3));
    let s = shot(report, "restored");
    assert!(s["removed"].as_array().unwrap().is_empty());
    assert_eq!(s["blocks"].as_u64(), Some(4));

    // Drop test: a second view of the moving blocks, the verdicts side by side.
    let s = shot(report, "drop");
    assert_eq!(s["drop_stands"], Value::Bool(true), "{s}");
    assert_eq!(s["drop_agrees"], Value::Bool(true));
    let main = rect(&s["main_viewport"]);
    let physics = rect(&s["physics_viewport"]);
    assert!(physics[0] >= main[2], "the drop view is beside the static one: {main:?} {physics:?}");
    assert!(s["caption"].as_str().unwrap().starts_with("drop test (rapier)"), "{s}");
    let c = picture(&s, "physics_viewport");
    println!("drop view: {c:?}");
    assert!(c.violet > c.total / 100, "the blocks are drawn in the drop view: {c:?}");
    assert!(c.blue == 0, "the drop view shows no diagram: {c:?}");
    // Both engines (B): three views side by side — the design, rapier's, the exact engine's —
    // each pane with its own caption and blocks, both verdicts (stands) agreeing with the statics.
    let s = shot(report, "drop_both");
    let lanes: Vec<(&str, bool, bool)> = s["drop_lanes"]
        .as_array()
        .expect("the lanes")
        .iter()
        .map(|l| (l["engine"].as_str().unwrap(), l["stands"] == true, l["agrees"] == true))
        .collect();
    assert_eq!(lanes, [("rapier", true, true), ("exact", true, true)], "{s}");
    let (main, physics, compared) =
        (rect(&s["main_viewport"]), rect(&s["physics_viewport"]), rect(&s["compared_viewport"]));
    assert!(physics[0] >= main[2] && compared[0] >= physics[2], "{main:?} {physics:?} {compared:?}");
    assert!(s["caption"].as_str().unwrap().starts_with("drop test (rapier)"), "{s}");
    assert!(s["compared_caption"].as_str().unwrap().starts_with("drop test (exact)"), "{s}");
    assert_eq!(s["pane"]["copies"], s["pane"]["compared_copies"], "{s}");
    for view in ["physics_viewport", "compared_viewport"] {
        let c = picture(&s, view);
        println!("{view} (both engines): {c:?}");
        assert!(c.violet > c.total / 100 && c.blue == 0, "{view}: {c:?}");
    }
    // Sequence: bottom-up, step 9 of 15 of the arch (v0–v4 on the right, v10–v14 on the
    // left): the half arches lean in, needing tension (1.44 W by `voussoir sequence`).
    let s = shot(report, "sequence");
    let step = &s["sequence_step"];
    assert_eq!(step["index"].as_u64(), Some(8), "{s}");
    assert_eq!(step["placed"], "v4", "{s}");
    assert_eq!(step["stands"], Value::Bool(false), "{s}");
    assert!(step["drop_stands"].is_boolean());
    let c = picture(&s, "main_viewport");
    println!("sequence step 9: {c:?}");
    assert!(c.red > 20, "the step's own diagram shows its tension: {c:?}");
    // The mechanism view: the arch's worst direction and λ* (the core's), the blocks moved
    // along the mechanism in the second view.
    let s = shot(report, "mechanism");
    let arch = voussoir::pipeline::analyze(&voussoir::cli::load(None).unwrap(), &Default::default()).unwrap();
    let sweep = voussoir::stability::worst_direction(
        &arch.assembly,
        &arch.interfaces,
        &Default::default(),
        &Default::default(),
        &|_, _| {},
    )
    .unwrap();
    let shown = s["load_factor"].as_f64().expect("a load factor");
    assert!((shown - sweep.worst_load_factor).abs() < 1e-9, "{s}");
    assert!(s["worst_azimuth"].is_number(), "{s}");
    let physics = rect(&s["physics_viewport"]);
    assert!(physics[0] >= rect(&s["main_viewport"])[2], "the mechanism is beside the design: {s}");
    // The pane: every block copied, the moved ones violet over their rest-state ghosts, the
    // hinges marked, a caption with λ*, the exaggeration and the load.
    let pane = &s["pane"];
    assert_eq!(pane["copies"].as_u64(), Some(17), "{s}");
    assert!(pane["moved"].as_u64().unwrap() >= 3 && pane["ghosts"] == pane["moved"], "{s}");
    assert!(pane["joints"].as_u64().unwrap() >= 3, "an arch hinges at four joints: {s}");
    let caption = s["caption"].as_str().unwrap();
    assert!(caption.contains(&format!("λ* = {shown:.4}")) && caption.contains("8 % of the size"), "{caption}");
    assert!(caption.contains("worst at") && caption.contains("hinging"), "{caption}");
    let c = picture(&s, "physics_viewport");
    println!("mechanism view: {c:?}");
    assert!(c.violet > c.total / 100, "the moved blocks are drawn: {c:?}");
    assert!(c.orange > 20, "the hinges are marked: {c:?}");
    // H without supports: UNSUPPORTED, what touches nothing named, no solver numbers.
    let s = shot(report, "unsupported");
    assert_eq!((s["verdict"].as_str(), s["headline"].as_str()), (Some("Unsupported"), Some("UNSUPPORTED")), "{s}");
    let numbers = s["panel"].as_array().unwrap().iter().find(|p| p["section"] == "Numbers").unwrap();
    let text = numbers["text"].as_str().unwrap();
    assert!(text.contains("touch no support") && text.contains("--supports lowest"), "{text}");
    assert!(!text.contains("solved in") && !text.contains("tension needed"), "no solver numbers: {text}");
    // The mechanism pane (K is still on) says why it is empty.
    assert_eq!(s["caption"], "no collapse mechanism:\nit does not stand under its own weight", "{s}");
    // The kinematic view: the core's verdicts on H (statics stands, the bar falls), one block
    // moving, drawn in the second view.
    let s = shot(report, "kinematic");
    let core = voussoir::stability::kinematic::check(
        &voussoir::pipeline::analyze(&letter_h(), &Default::default()).unwrap(),
        &Default::default(),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(s["kinematic"], serde_json::to_value(core.verdict).unwrap(), "{s}");
    assert_eq!(s["kinematic"], "fails", "{s}");
    assert_eq!((s["kinematic_agrees"].as_bool(), s["stands"].as_bool()), (Some(false), Some(true)), "{s}");
    assert_eq!(s["kinematic_moving"].as_u64(), Some(1), "only the bar: {s}");
    assert_eq!(s["load_factor"], Value::Null, "one mechanism at a time: {s}");
    assert_eq!(s["headline"], "STANDS (statics)\nFALLS (kinematic)", "the headline says they disagree: {s}");
    assert!(s["caption"].as_str().unwrap().starts_with("kinematic check"), "{s}");
    let c = picture(&s, "physics_viewport");
    println!("kinematic view: {c:?}");
    assert!(c.violet > c.total / 200, "the falling bar is drawn beside the design: {c:?}");
    // Repair (O): the M stands with its one cut moved, one undo step back to Fig 4a, the
    // message the repair's, no red tension on screen; the design is the core's repair.
    let s = shot(report, "repaired");
    assert_eq!(
        (s["verdict"].as_str(), s["cuts"].as_u64(), s["undo"].as_u64()),
        (Some("Stands"), Some(1), Some(1)),
        "{s}"
    );
    assert!(s["message"].as_str().is_some_and(|m| m.starts_with("repaired: it stands now")), "{s}");
    let message = s["message"].as_str().unwrap();
    assert!(message.contains("needs tension → stands") && !message.contains("NeedsTension"), "words: {message}");
    let title = s["panel"].as_array().unwrap().iter().find(|p| p["section"] == "Title").unwrap();
    assert!(title["text"].as_str().unwrap().contains("(edited)"), "the title says it was edited: {title}");
    assert!(s["panel"].as_array().unwrap().iter().any(|p| p["section"] == "Keys"), "the keys are listed: {s}");
    let core = voussoir::synthesis::repair(&fig4a(), &Default::default(), &Default::default(), &|_, _, _| {}).unwrap();
    assert_eq!(s["blocks"].as_u64(), Some(core.after.pieces as u64), "{s}");
    let c = picture(&s, "main_viewport");
    println!("repaired M: {c:?}");
    assert!(c.blue > c.total / 400 && c.red < c.blue / 50, "compression only: {c:?}");
    // Settlement (P): the lintel follows the settling pier to the end of the path and stands,
    // the playback at its last frame; the pane beside the design shows the moved blocks and
    // the thrust curve (the quasi-static line is blue; the pane draws no diagram otherwise).
    let s = shot(report, "settle");
    assert_eq!(s["settle"]["outcome"]["kind"], "stands", "{s}");
    assert_eq!((s["settle"]["played"].as_bool(), s["settle"]["fraction"].as_f64()), (Some(true), Some(1.0)), "{s}");
    assert_eq!(s["thrust_plot_shown"], true, "{s}");
    assert!(s["caption"].as_str().unwrap().starts_with("supports move (quasi-static)"), "{s}");
    assert!(physics_beside_main(&s), "{s}");
    let c = picture(&s, "physics_viewport");
    println!("settlement view: {c:?}");
    assert!(c.violet > c.total / 100 && c.blue > 0, "the moved blocks and the thrust curve: {c:?}");

    let s = shot(report, "shake");
    let shake = &s["shake"];
    assert!((shake["static_load_factor"].as_f64().unwrap() - 0.2).abs() < 1e-4, "{s}");
    assert_eq!((shake["collapsed"].as_bool(), shake["played"].as_bool()), (Some(true), Some(true)), "{s}");
    assert_eq!(s["thrust_plot_shown"], true, "{s}");
    assert!(s["caption"].as_str().unwrap().starts_with("shake (exact)"), "{s}");
    assert!(physics_beside_main(&s), "{s}");
    let c = picture(&s, "physics_viewport");
    println!("shake view: {c:?}");
    assert!(c.violet > c.total / 200, "the fallen block: {c:?}");
}

/// A 0.2 × 0.2 × 1 m block on the ground (λ* = 0.2) whose scene shakes it by a 0.3 g
/// rectangular pulse of 1.5 s.
fn shaken_block() -> voussoir::model::Scene {
    use voussoir::model::shaking::{PulseSpec, Shaking, ShakingComponent};
    let mesh = voussoir::geometry::Mesh::cuboid(
        voussoir::geometry::Point3::new(-0.1, -0.1, 0.0),
        voussoir::geometry::Point3::new(0.1, 0.1, 1.0),
    );
    let mut scene = voussoir::model::Scene::new("shaken block", vec![voussoir::model::Block::new("block", mesh)]);
    scene.ground = true;
    let pulse = PulseSpec { shape: "rect".into(), amplitude: 0.3, duration: 1.5 };
    scene.ground_motion = Some(Shaking {
        components: vec![ShakingComponent { pulse: Some(pulse), ..Default::default() }],
        scale: 1.0,
        supports: Vec::new(),
    });
    scene
}

/// The motion pane is right of the design's view.
fn physics_beside_main(s: &Value) -> bool {
    rect(&s["physics_viewport"])[0] >= rect(&s["main_viewport"])[2]
}
