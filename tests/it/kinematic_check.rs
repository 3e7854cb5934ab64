//! The kinematic check (`voussoir::stability::kinematic`): does the equilibrium the statics (RBE) finds
//! arise when the blocks are released from rest with no contact squeezed? Each test states its
//! physical answer and why; every case also checks the invariants of the module: the kinematic
//! verdict never stands where RBE fails (the kinematic set is a subset), and a failing case's
//! mechanism has positive work of the loads (it moves down).

use crate::common::{compas_data, cuboid};
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Block, Scene, builtin};
use voussoir::pipeline::{Analysis, AnalysisSettings, analyze};
use voussoir::stability::kinematic::{Kinematic, KinematicVerdict, check, load_work};
use voussoir::statics::{FrictionModel, KinematicSettings};

const G: f64 = 9.81;

/// Runs the statics and the kinematic check, and checks the module's invariants on the result.
fn both(scene: &Scene, settings: &AnalysisSettings) -> (Analysis, Kinematic) {
    let analysis = analyze(scene, settings).expect("the scene analyses");
    let k = check(&analysis, &settings.statics, &KinematicSettings::default()).expect("the check runs");
    assert!(
        k.verdict != KinematicVerdict::Stands || analysis.statics.stands,
        "{}: kinematic stands where RBE fails",
        scene.name
    );
    if k.verdict == KinematicVerdict::Fails
        && let Some(m) = &k.mechanism
    {
        let work = load_work(&analysis.assembly, m);
        assert!(work > 0.0, "{}: the loads do {work} W/s along the mechanism", scene.name);
    }
    (analysis, k)
}

/// A compas_cra sample with the examples' supports — the blocks at the lowest level (`supports`
/// of them) — and μ = 0.84.
fn compas_cra_with(name: &str, supports: usize) -> Scene {
    let mut scene = voussoir::io::load_scene(&compas_data(&format!("compas_cra/{name}.json"))).expect("sample loads");
    assert_eq!(scene.mark_lowest_as_supports(1e-3), supports, "{name}: supports");
    scene.material.friction = 0.84;
    scene
}

/// The letters and wedges: supports 0 and 1.
pub(crate) fn compas_cra(name: &str) -> Scene {
    compas_cra_with(name, 2)
}

/// Both verdicts are `stands` (or both fail).
fn assert_both(analysis: &Analysis, k: &Kinematic, stands: bool, what: &str) {
    assert_eq!(analysis.statics.stands, stands, "{what}: RBE");
    let expected = if stands { KinematicVerdict::Stands } else { KinematicVerdict::Fails };
    assert_eq!(k.verdict, expected, "{what}");
}

/// A prism of the polygon `xz` (x, z pairs) in the xz-plane, 1 m deep along y.
fn prism(name: &str, xz: &[[f64; 2]]) -> Block {
    let base: Vec<Point3> = xz.iter().map(|p| Point3::new(p[0], 0.0, p[1])).collect();
    Block::new(name, Mesh::prism(&base, Vector3::new(0.0, 1.0, 0.0)))
}

/// A block of width 2w between two support posts whose inner faces run from x = ±`bottom` at
/// z = 0 to x = ±`top` at z = 1.
pub(crate) fn seated(name: &str, bottom: f64, top: f64, mu: f64) -> Scene {
    let mut scene = Scene::new(
        name,
        vec![
            prism("left", &[[-2.0, 0.0], [-bottom, 0.0], [-top, 1.0], [-2.0, 1.0]]).support(true),
            prism("block", &[[-bottom, 0.0], [bottom, 0.0], [top, 1.0], [-top, 1.0]]),
            prism("right", &[[bottom, 0.0], [2.0, 0.0], [2.0, 1.0], [top, 1.0]]).support(true),
        ],
    );
    scene.material.friction = mu;
    scene
}

/// The linear acceleration (m/s²) of block `name` in `k`'s mechanism.
fn block_acceleration(k: &Kinematic, name: &str) -> [f64; 3] {
    let m = k.mechanism.as_ref().expect("a mechanism");
    let b = m.blocks.iter().find(|b| b.block == name).unwrap_or_else(|| panic!("{name} moves"));
    b.translation
}

/// compas_cra's letters H and A (`docs/examples/16_ha.py`: the two posts are supports, μ =
/// 0.84): the bar between the posts is held in RBE by a squeeze of the posts and friction.
/// Nothing applies that squeeze (rigid posts, a bar dropped in), so the bar falls freely:
/// the H's faces are vertical, the A's widen downwards. Closed form: the bar accelerates at g
/// straight down (to 1e-6 g).
#[test]
fn compas_cra_letters_h_and_a_fall_though_rbe_holds_them() {
    for name in ["H", "A"] {
        let (analysis, k) = both(&compas_cra(name), &AnalysisSettings::default());
        assert!(analysis.statics.stands, "{name}: RBE holds the bar");
        assert_eq!(k.verdict, KinematicVerdict::Fails, "{name}");
        assert!(!k.agrees);
        let m = k.mechanism.as_ref().expect("a mechanism");
        assert_eq!(m.blocks.len(), 1, "{name}: only the bar moves");
        let a = m.blocks[0].translation;
        assert!(a[0].abs() < 1e-6 * G && a[1].abs() < 1e-6 * G, "{name}: {a:?}");
        assert!((a[2] + G).abs() < 1e-6 * G, "{name}: falls at g, got {a:?}");
    }
}

/// compas_cra's wedges (`docs/examples/05_wedge.py`): supports 0 and 1, μ = 0.84, the whole
/// assembly turned 90° about y after the interfaces are found — i.e. gravity along +x in the
/// files' frame. The wedge then rests on the lower support's face: type-a/b's faces (60° from
/// the file's horizontal) lie 30° from the turned horizontal, below the friction angle
/// (40°): they stand; type-c/d's (30°) lie 60° from it, steeper than the friction angle: the
/// wedge slides out — and the statics agrees (it needs more friction than μ: the two supports'
/// faces do not make a seat a squeeze could hold it in). Both verdicts are asserted.
#[test]
fn compas_cra_wedges_turned_as_in_the_example_a_b_stand_c_d_fall() {
    for (name, stands) in [("type-a", true), ("type-b", true), ("type-c", false), ("type-d", false)] {
        let mut scene = compas_cra(name);
        scene.gravity = Vector3::new(G, 0.0, 0.0);
        let (analysis, k) = both(&scene, &AnalysisSettings::default());
        let expected = if stands { KinematicVerdict::Stands } else { KinematicVerdict::Fails };
        assert_eq!(k.verdict, expected, "{name}: RBE stands = {}", analysis.statics.stands);
        assert_eq!(analysis.statics.stands, stands, "{name}: RBE {:?}", analysis.statics.verdict);
    }
}

/// compas_cra's shelves (`docs/examples/07_shelf.py` runs `shelf.json` with support 0 and μ =
/// 0.9): `shelf-stable` stands in both verdicts. The variants with extra struts
/// (`shelf`, `shelf-s1..s3`) fail in both at μ = 0.84 (the examples show no verdict for them;
/// RBE already needs more friction).
#[test]
fn compas_cra_shelves() {
    for (name, stands) in
        [("shelf-stable", true), ("shelf", false), ("shelf-s1", false), ("shelf-s2", false), ("shelf-s3", false)]
    {
        let (analysis, k) = both(&compas_cra_with(name, 1), &AnalysisSettings::default());
        assert_both(&analysis, &k, stands, name);
    }
}

/// A block clamped between two vertical walls with no squeeze: RBE holds it on friction with
/// any squeeze it likes; released from rest, nothing presses it against the walls, so it falls
/// at g. A keystone whose faces narrow downwards is carried by its faces whatever μ (even μ =
/// 0: the faces' normals point up): it stands in both. One whose faces widen downwards (11°
/// taper, below the friction angle of μ = 1) is held by RBE with a squeeze, and drops out.
#[test]
fn clamped_blocks_and_keystones() {
    let (analysis, k) = both(&seated("clamped", 0.5, 0.5, 0.8), &AnalysisSettings::default());
    assert!(analysis.statics.stands);
    assert_eq!(k.verdict, KinematicVerdict::Fails);
    assert!((block_acceleration(&k, "block")[2] + G).abs() < 1e-6 * G);
    for mu in [0.0, 0.5] {
        let (analysis, k) = both(&seated("keystone", 0.4, 0.6, mu), &AnalysisSettings::default());
        assert!(analysis.statics.stands, "μ = {mu}");
        assert_eq!(k.verdict, KinematicVerdict::Stands, "μ = {mu}");
        assert!(k.peak_acceleration < 1e-6);
    }
    let (analysis, k) = both(&seated("widening", 0.6, 0.4, 1.0), &AnalysisSettings::default());
    assert!(analysis.statics.stands, "RBE holds it with a squeeze");
    assert_eq!(k.verdict, KinematicVerdict::Fails);
    assert!((block_acceleration(&k, "block")[2] + G).abs() < 1e-6 * G, "it drops freely");
}

/// A block on a slope (μ = 0.5: friction angle 26.57°; square section, so it does not tip
/// below 45°): at 20° it stands in both verdicts; at 35° it fails in both, and (exact cone)
/// slides down the slope at g (sin θ − μ cos θ), to 1e-5 relative.
#[test]
fn a_block_on_a_slope_stands_below_the_friction_angle_and_slides_above_it() {
    let mut settings = AnalysisSettings::default();
    settings.statics.friction_model = FrictionModel::Cone;
    for (angle, stands) in [(20.0f64, true), (35.0, false)] {
        let mut scene = builtin(&format!("slope?angle={angle}")).expect("builtin");
        scene.material.friction = 0.5;
        let (analysis, k) = both(&scene, &settings);
        assert_both(&analysis, &k, stands, &format!("{angle}°"));
        if !stands {
            let a = block_acceleration(&k, "block");
            let th = angle.to_radians();
            let along = G * (th.sin() - 0.5 * th.cos());
            let got = (a[0] * a[0] + a[2] * a[2]).sqrt();
            assert!((got - along).abs() < 1e-5 * along, "{angle}°: {got} vs {along}");
            assert!(a[0] > 0.0 && a[2] < 0.0, "down the slope towards +x: {a:?}");
        }
    }
}

/// A ladder (0.2 × 0.2 m section, 60° from the floor) between a floor slab and a wall, both
/// supports. With friction μ on both, it stands when tan θ ≥ (1 − μ²)/(2μ): μ = 0.5 needs
/// θ ≥ 36.9° (stands), μ = 0.2 needs θ ≥ 67.4° (fails). Released from rest the ladder starts
/// to slide, the floor and the wall press it, and with μ = 0.5 that friction holds it.
#[test]
fn a_ladder_leaning_on_a_wall() {
    let th = 60f64.to_radians();
    let (d, l) = (0.2 / th.sin(), 2.0);
    for (mu, stands) in [(0.5, true), (0.2, false)] {
        let mut scene = Scene::new(
            "ladder",
            vec![
                cuboid("floor", [-1.0, -0.5, -0.5], [l + 1.0, 1.5, 0.0]).support(true),
                cuboid("wall", [l, -0.5, 0.0], [l + 1.0, 1.5, 4.0]).support(true),
                prism("ladder", &[[0.0, 0.0], [d, 0.0], [l, (l - d) * th.tan()], [l, l * th.tan()]]),
            ],
        );
        scene.material.friction = mu;
        let (analysis, k) = both(&scene, &AnalysisSettings::default());
        assert_both(&analysis, &k, stands, &format!("μ = {mu}"));
    }
}

/// Units and load scale do not change a verdict: the same designs in mm (every length × 1000)
/// and with the density × 10⁶ give the same kinematic verdict as in m.
#[test]
fn verdicts_do_not_depend_on_units_or_load_scale() {
    let mut cases = vec![compas_cra("H"), seated("keystone", 0.4, 0.6, 0.5), seated("widening", 0.6, 0.4, 1.0)];
    let mut wedge = compas_cra("type-c");
    wedge.gravity = Vector3::new(G, 0.0, 0.0);
    cases.push(wedge);
    for scene in cases {
        let (_, base) = both(&scene, &AnalysisSettings::default());
        let mut mm = scene.clone();
        mm.blocks.iter_mut().for_each(|b| b.mesh = b.mesh.scaled_translated(1000.0, Vector3::zeros()));
        let mut heavy = scene.clone();
        heavy.material.density *= 1e6;
        for (what, variant) in [("mm", mm), ("density × 1e6", heavy)] {
            let (_, k) = both(&variant, &AnalysisSettings::default());
            assert_eq!(k.verdict, base.verdict, "{}: {what}", scene.name);
            assert!(
                (k.peak_acceleration - base.peak_acceleration).abs() <= 1e-6 * base.peak_acceleration.max(1.0),
                "{}: {what}: peak {} vs {} g",
                scene.name,
                k.peak_acceleration,
                base.peak_acceleration
            );
        }
    }
}

/// Frictionless designs have one answer: with μ = 0 the rate problem is Gauss's principle
/// alone (one round), and it stands exactly when RBE does — here the compas_assembly arch
/// (which needs friction: both fail) and a keystone (both stand).
#[test]
fn without_friction_both_verdicts_agree() {
    let mut arch = voussoir::io::load_scene(&compas_data("compas_assembly/arch_assembly.json")).expect("loads");
    arch.material.friction = 0.0;
    for scene in [arch, seated("keystone", 0.4, 0.6, 0.0)] {
        let (analysis, k) = both(&scene, &AnalysisSettings::default());
        assert!(k.agrees, "{}: RBE stands = {}, kinematic {:?}", scene.name, analysis.statics.stands, k.verdict);
        assert_eq!(k.rounds, 1, "{}", scene.name);
    }
}

/// The sequence check with the kinematic check per step (`sequence --kinematic`): two free
/// posts on a slab, then a block hung between them at mid-height, touching nothing else
/// (μ = 0.8). Each post alone stands in both verdicts. With the block, RBE stands on a squeeze
/// (the heavy posts resist the push; friction carries the block); released from rest, nothing
/// squeezes it and it falls at g. Invariant: every step's kinematic verdict is the core check
/// of that prefix analysed on its own, and the hung block's step is the only kinematic failure.
#[test]
fn a_sequence_is_checked_kinematically_step_by_step() {
    use voussoir::studies::sequence::{OrderSpec, StepChecks};
    let mut scene = Scene::new(
        "hung",
        vec![
            cuboid("slab", [-2.5, -0.5, -0.5], [2.5, 1.5, 0.0]).support(true),
            prism("left", &[[-2.0, 0.0], [-0.5, 0.0], [-0.5, 2.0], [-2.0, 2.0]]),
            prism("right", &[[0.5, 0.0], [2.0, 0.0], [2.0, 2.0], [0.5, 2.0]]),
            prism("block", &[[-0.5, 1.0], [0.5, 1.0], [0.5, 2.0], [-0.5, 2.0]]),
        ],
    );
    scene.material.friction = 0.8;
    let order = ["left", "right", "block"].map(String::from).to_vec();
    let settings = AnalysisSettings::default();
    let per_step = StepChecks { kinematic: Some(KinematicSettings::default()), ..Default::default() };
    let r = voussoir::studies::sequence::check(&scene, &OrderSpec::Given(order.clone()), &settings, &per_step, &|| {})
        .expect("the sequence is checked");
    assert_eq!(r.steps.len(), 3);
    for (k, step) in r.steps.iter().enumerate() {
        let mut prefix = scene.clone();
        prefix.blocks.retain(|b| b.support || order[..=k].contains(&b.name));
        let (analysis, alone) = both(&prefix, &settings);
        let got = step.kinematic.as_ref().expect("a kinematic check per step");
        assert_eq!((got.verdict, got.statics_stands), (alone.verdict, analysis.statics.stands), "step {k}");
        assert!(step.stands, "step {k}: RBE stands");
        let expected = if k < 2 { KinematicVerdict::Stands } else { KinematicVerdict::Fails };
        assert_eq!(got.verdict, expected, "step {k} ({})", step.placed);
    }
    let last = r.steps[2].kinematic.as_ref().unwrap();
    let m = last.mechanism.as_ref().expect("the hung block's mechanism");
    for b in &m.blocks {
        let a = b.translation;
        let (expected, what) = if b.block == "block" { (-G, "falls at g") } else { (0.0, "stays") };
        assert!(a[0].abs() < 1e-6 * G && (a[2] - expected).abs() < 1e-6 * G, "{} {what}: {a:?}", b.block);
    }
    assert!(m.blocks.iter().any(|b| b.block == "block"));
}
