//! The exact-contact engine (`voussoir::dynamics::exact`, `--engine exact`) against closed
//! forms: a block on a slope sticks or slides with g(sin θ − μ cos θ); a b × h block tips at
//! tan θ = b/h; free fall follows the scheme's own closed form; a dropped block comes to rest
//! with its energy accounted for; the first step from rest is the kinematic check's rate
//! problem; thresholds land on the statics'; same input, same trajectory.

use crate::common::assembly;
use crate::kinematic_check::{compas_cra, seated};
use voussoir::dynamics::exact::World;
use voussoir::dynamics::{DropResult, DropRun, DropSettings, Engine, ExactSettings, Selection, SupportPath, drop_test};
use voussoir::geometry::Vector3;
use voussoir::model::{Scene, builtin};
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::stability::kinematic::check;
use voussoir::statics::KinematicSettings;

fn exact() -> DropSettings {
    DropSettings { engine: Engine::Exact, ..Default::default() }
}

/// The drop test, its energy balance checked: an identity of the scheme, so its error is the
/// solves' (tolerance 1e-10; a block that tips over and lands on the ground, 2e-8; a thin arch
/// collapsing through split impact steps, 6e-7).
fn drop(scene: &Scene, settings: &DropSettings) -> DropResult {
    let r = drop_test(&assembly(scene), settings).expect("the drop test runs");
    let e = r.exact.as_ref().expect("the exact engine's account");
    assert!(e.energy.error < 1e-6, "{}: energy balance {:?}", scene.name, e.energy);
    r
}

/// Block `name`'s index in the scene.
fn index(scene: &Scene, name: &str) -> usize {
    scene.blocks.iter().position(|b| b.name == name).expect("the block exists")
}

/// Invariant: below the friction angle (tan θ ≤ μ, square block: no tipping below 45°) the
/// block never moves — its drift is at most 1e-9 of its size over 2 s; above it the block
/// slides down with the constant acceleration a = g(sin θ − μ cos θ), which symplectic Euler
/// integrates as d_n = a h² n(n + 1)/2 after n steps: a measured to 1e-6 relative — with
/// either force selection (the sliding block's resultant is determinate: both settle on it).
#[test]
fn slope_sticks_below_the_friction_angle_and_slides_above_it() {
    for selection in [Selection::Round, Selection::Coulomb] {
        let mut settings = exact();
        settings.exact.selection = selection;
        let sticks = builtin("slope?angle=25&mu=0.5").unwrap();
        let r = drop(&sticks, &settings);
        assert!(r.stands && r.max_drift <= 1e-9, "{selection:?}: {r:?}");
        let (theta, mu) = (35f64.to_radians(), 0.5);
        let scene = builtin("slope?angle=35&mu=0.5").unwrap();
        let mut run = DropRun::new(&assembly(&scene), &settings).unwrap();
        let n = 120;
        run.advance(n);
        let i = index(&scene, "block");
        let a0 = assembly(&scene).blocks[i].mass.centroid;
        let (x, q) = run.pose(i);
        let d = x - a0;
        let expected = 9.81 * (theta.sin() - mu * theta.cos());
        let h = settings.dt;
        let measured = d.norm() / (h * h * (n * (n + 1)) as f64 / 2.0);
        assert!((measured / expected - 1.0).abs() < 1e-6, "{selection:?}: a = {measured} vs {expected}");
        // Down the slope (tilted about y: +x, −z at 35°), not turning.
        assert!((-d.z / d.x - theta.tan()).abs() < 1e-6 && d.x > 0.0, "{d:?}");
        assert!((q[0] - 1.0).abs() < 1e-12, "{q:?}");
    }
}

/// Invariant: a b × h block (b = 0.2, h = 1, μ = 0.8 > b/h: it cannot slide first) on a slope
/// stands below atan(b/h) = 11.31° and tips above it (at 0.99 and 1.01 of the angle's tangent).
#[test]
fn a_slender_block_tips_at_atan_b_over_h() {
    let tip = (0.2f64).atan().to_degrees();
    for (factor, stands) in [(0.99, true), (1.01, false)] {
        let angle = (factor * 0.2f64).atan().to_degrees();
        let scene = builtin(&format!("slope?angle={angle}&mu=0.8&b=0.2&h=1")).unwrap();
        let r = drop(&scene, &exact());
        assert_eq!(r.stands, stands, "at {angle}° (tips at {tip}°): {r:?}");
        if !stands {
            assert!(r.max_rotation > 0.05, "it turns: {r:?}");
        }
    }
}

/// Invariant: with nothing to touch a block falls freely — after n steps v = n h g exactly and
/// the centroid has dropped g h² n(n + 1)/2 (the scheme's closed form), to 1e-12 relative.
#[test]
fn free_fall_is_the_schemes_closed_form() {
    let scene = Scene::new("alone", vec![crate::common::cube("a", [0.0, 0.0, 1.0], 0.5)]);
    let asm = assembly(&scene);
    let settings = exact();
    let mut world = World::new(&asm, &settings);
    let n = 50;
    (0..n).for_each(|_| world.step());
    let (v, w) = world.velocity(0);
    let h = settings.dt;
    assert!((v.z + 9.81 * h * n as f64).abs() < 1e-12 * 9.81 * h * n as f64, "{v:?}");
    assert!(v.x == 0.0 && v.y == 0.0 && w == Vector3::zeros());
    let (x, _) = world.pose(0, asm.blocks[0].mass.centroid);
    let drop = asm.blocks[0].mass.centroid.z - x.z;
    let expected = 9.81 * h * h * (n * (n + 1)) as f64 / 2.0;
    assert!((drop / expected - 1.0).abs() < 1e-12, "{drop} vs {expected}");
}

/// Invariant: a block released 0.3 m above the ground (no restitution) lands and comes to rest:
/// kinetic energy 0 at the end, resting on its face (overlap below 1e-3 of its size), and the
/// energy balance — the weight's work m g Δz = kinetic + contact + impact dissipation — holds
/// to 1e-8, with the work (the kicks' and the drift's beyond them) equal to m g × the fall.
#[test]
fn a_dropped_block_comes_to_rest_with_its_energy_accounted_for() {
    let mut scene = Scene::new("dropped", vec![crate::common::cube("a", [0.0, 0.0, 0.3], 0.5)]);
    scene.ground = true;
    let r = drop(&scene, &exact());
    let e = r.exact.as_ref().unwrap();
    assert!(r.at_rest && r.blocks[0].final_kinetic_energy == 0.0, "{r:?}");
    assert!(e.max_penetration < 1e-3, "{e:?}");
    let asm = assembly(&scene);
    let (m, size) = (asm.blocks[0].mass(), asm.blocks[0].aabb.diagonal());
    let fallen = r.blocks[0].max_drift;
    assert!((fallen - 0.3).abs() < 1e-3 * size, "fell {fallen}");
    // The weight's work on the whole motion: the kicks' share and the drift's beyond it.
    let work = e.energy.load_work + e.energy.correction;
    assert!((work / (m * 9.81 * fallen) - 1.0).abs() < 1e-6, "{:?}", e.energy);
}

/// Invariant: from rest, the first step's velocities are dt × the kinematic check's initial
/// accelerations (its rate problem is the step with no velocity), to 1e-6 g: compas_cra's H
/// (the bar drops at g), a keystone widening downwards (drops at g), one narrowing (stays), and
/// a block on a 35° slope (slides).
#[test]
fn the_first_step_is_the_kinematic_checks_rate_problem() {
    let slope = builtin("slope?angle=35&mu=0.5").unwrap();
    for scene in [compas_cra("H"), seated("widening", 0.6, 0.4, 1.0), seated("keystone", 0.4, 0.6, 0.5), slope] {
        let settings = AnalysisSettings::default();
        let analysis = analyze(&scene, &settings).unwrap();
        let k = check(&analysis, &settings.statics, &KinematicSettings::default()).unwrap();
        let dt = exact().dt;
        let mut world = World::new(&analysis.assembly, &exact());
        world.step();
        for (i, block) in analysis.assembly.blocks.iter().enumerate().filter(|(_, b)| !b.support) {
            let (v, w) = world.velocity(i);
            let (a, alpha) = k
                .mechanism
                .as_ref()
                .and_then(|m| m.blocks.iter().find(|b| b.block == block.name))
                .map_or((Vector3::zeros(), Vector3::zeros()), |b| {
                    (Vector3::from(b.translation), Vector3::from(b.rotation))
                });
            let r = block.aabb.diagonal();
            let err = (v / dt - a).norm() + (w / dt - alpha).norm() * r;
            assert!(err < 1e-6 * 9.81, "{} {}: {:?} {:?} vs {a:?} {alpha:?}", scene.name, block.name, v / dt, w / dt);
        }
    }
}

/// Invariant: the same input gives the same trajectory, bit for bit (a collapsing arch).
#[test]
fn same_input_same_trajectory() {
    let asm = assembly(&builtin("arch?n=9&t=0.08").unwrap());
    let settings = DropSettings { duration: 0.3, ..exact() };
    let a = drop_test(&asm, &settings).unwrap();
    let b = drop_test(&asm, &settings).unwrap();
    assert!(!a.stands);
    assert_eq!(a.blocks, b.blocks);
    assert_eq!(a.exact.as_ref().map(|e| (e.solves, e.energy)), b.exact.as_ref().map(|e| (e.solves, e.energy)));
}

/// Invariant: the structured solver (each contact a force point, the bodies' rows reduced as
/// in the statics) takes every step problem of a collapsing arch (n 9, t 0.08, 0.3 s) — with
/// the outer pyramid, the exact cone and the relaxed box alike — and steps it as clarabel
/// does: each block's largest drift and rotation the same to 1e-6 (m, rad; they agree to
/// ~1e-11) and the same verdict.
#[test]
fn both_solvers_step_alike() {
    use voussoir::dynamics::Coulomb;
    use voussoir::model::FrictionModel;
    use voussoir::statics::Backend;
    let asm = assembly(&builtin("arch?n=9&t=0.08").unwrap());
    let cases = [
        (FrictionModel::Pyramid8, Coulomb::Exact),
        (FrictionModel::Cone, Coulomb::Exact),
        (FrictionModel::Box4, Coulomb::Relaxed),
    ];
    for (friction_model, coulomb) in cases {
        let run = |backend: Backend| {
            let mut settings = DropSettings { duration: 0.3, ..exact() };
            settings.exact = ExactSettings { friction_model, coulomb, backend, ..settings.exact.clone() };
            drop_test(&asm, &settings).unwrap()
        };
        let (s, c) = (run(Backend::Structured), run(Backend::Clarabel));
        let (es, ec) = (s.exact.as_ref().unwrap(), c.exact.as_ref().unwrap());
        let case = format!("{friction_model:?} {coulomb:?}");
        assert!(es.solves > 0 && es.structured_solves == es.solves, "{case}: {es:?}");
        assert_eq!(ec.structured_solves, 0, "{case}");
        assert_eq!((s.stands, c.stands), (false, false), "{case}");
        for (a, b) in s.blocks.iter().zip(&c.blocks) {
            assert!((a.max_drift - b.max_drift).abs() < 1e-6, "{case} {}: {} vs {}", a.name, a.max_drift, b.max_drift);
            assert!(
                (a.max_rotation - b.max_rotation).abs() < 1e-6,
                "{case} {}: {} vs {}",
                a.name,
                a.max_rotation,
                b.max_rotation
            );
        }
    }
}

/// The collapsing arch (n 15, t 0.08) dropped for 0.5 s in the exact engine with one of its
/// settings switched on by `switch`, then off.
fn collapsing_arch_half_second(switch: impl Fn(&mut ExactSettings, bool)) -> (DropResult, DropResult) {
    let asm = assembly(&builtin("arch?n=15&t=0.08").unwrap());
    let run = |on: bool| {
        let mut settings = DropSettings { duration: 0.5, ..exact() };
        // Every step by the rounds: their warm starts and acceleration are what is measured.
        settings.exact.by_states = false;
        switch(&mut settings.exact, on);
        drop_test(&asm, &settings).unwrap()
    };
    (run(true), run(false))
}

/// Invariant: a structured solve started from the iterate the component's previous solve of
/// the same layout kept answers as a cold one does — the collapsing arch (n 15, t 0.08, 0.5 s)
/// with and without warm starts: each block's largest drift and rotation the same to 1e-4
/// relative or 1e-6 (m, rad; the collapse grows the solves' tolerance-level differences to up
/// to 2e-5 relative by then) — in fewer interior-point iterations (measured: ~30 % fewer over
/// 2 s; here at least 10 %).
#[test]
fn warm_starts_keep_the_answer_in_fewer_iterations() {
    let (w, c) = collapsing_arch_half_second(|s, warm| s.warm_start = warm);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-4 * a.abs().max(b.abs()) + 1e-6;
    for (a, b) in w.blocks.iter().zip(&c.blocks) {
        assert!(close(a.max_drift, b.max_drift), "{}: {} vs {}", a.name, a.max_drift, b.max_drift);
        assert!(close(a.max_rotation, b.max_rotation), "{}: {} vs {}", a.name, a.max_rotation, b.max_rotation);
    }
    let (iw, ic) = (w.exact.as_ref().unwrap().iterations, c.exact.as_ref().unwrap().iterations);
    assert!((iw as f64) < 0.9 * ic as f64, "warm {iw} against cold {ic} iterations");
}

/// Invariant: a moving component's step taken by its contacts' states (one linear solve, kept
/// where it meets every exact-Coulomb condition) is the rounds' step — the collapsing arch (n
/// 15, t 0.08, 0.5 s) by states and by rounds alone: each block's largest drift and rotation
/// the same to 1e-4 of the largest block's (as the accelerated rounds' test: the crown's
/// rotation, 2.4e-3 rad beside its neighbours' 1 rad, is the symmetry's round-off; measured:
/// 4e-5 relative on the others), the energy balance as tight,
/// no step's contacts creating energy beyond the solver's tolerance — with most moving steps
/// taken by the states and at most half the interior-point solves.
#[test]
fn steps_by_the_contacts_states_are_the_rounds_steps() {
    let (states, rounds) = collapsing_arch_half_second(|s, on| s.by_states = on);
    let largest = |f: fn(&voussoir::dynamics::BlockMotion) -> f64| rounds.blocks.iter().map(f).fold(0.0, f64::max);
    let (drift, rotation) = (largest(|b| b.max_drift), largest(|b| b.max_rotation));
    for (a, b) in states.blocks.iter().zip(&rounds.blocks) {
        assert!((a.max_drift - b.max_drift).abs() <= 1e-4 * drift, "{}: {} vs {}", a.name, a.max_drift, b.max_drift);
        let turned = (a.max_rotation - b.max_rotation).abs();
        assert!(turned <= 1e-4 * rotation, "{}: {} vs {}", a.name, a.max_rotation, b.max_rotation);
    }
    let (s, r) = (states.exact.as_ref().unwrap(), rounds.exact.as_ref().unwrap());
    assert!(s.energy.error < 1e-7 && s.energy.least_step_contact > -1e-6, "{:?}", s.energy);
    assert_eq!(r.state_steps, 0);
    assert!(2 * s.solves <= r.solves, "{} solves by states against {} by rounds", s.solves, r.solves);
    println!("states: {} state steps, {} solves; rounds: {} solves", s.state_steps, s.solves, r.solves);
}

/// Invariant: the accelerated Tresca rounds (a round is the fixed point when the capacities
/// that changed bind nowhere; Anderson's next capacities otherwise) settle on the capacities
/// the plain rounds c ← μ f_n settle on — the collapsing arch (n 15, t 0.08, 0.5 s): each
/// block's largest drift and rotation the same to 1e-4 of the largest block's (the crown's
/// rotation, 3e-4 rad where its neighbours' are 1 rad, is the symmetry's round-off and the
/// plain rounds' looser fixed points: 2.76e-4 plain, 2.976e-4 accelerated, 2.977e-4
/// accelerated at settle 1e-9), the energy balance as tight — in fewer solves (measured: a
/// third fewer over 2 s; here at least 20 %), and no step left unsettled where the plain
/// rounds leave some.
#[test]
fn accelerated_rounds_settle_on_the_same_capacities_in_fewer_solves() {
    let (fast, plain) = collapsing_arch_half_second(|s, accelerate| s.accelerate_rounds = accelerate);
    let largest = |f: fn(&voussoir::dynamics::BlockMotion) -> f64| plain.blocks.iter().map(f).fold(0.0, f64::max);
    let (drift, rotation) = (largest(|b| b.max_drift), largest(|b| b.max_rotation));
    for (a, b) in fast.blocks.iter().zip(&plain.blocks) {
        assert!((a.max_drift - b.max_drift).abs() <= 1e-4 * drift, "{}: {} vs {}", a.name, a.max_drift, b.max_drift);
        let turned = (a.max_rotation - b.max_rotation).abs();
        assert!(turned <= 1e-4 * rotation, "{}: {} vs {}", a.name, a.max_rotation, b.max_rotation);
    }
    let (f, p) = (fast.exact.as_ref().unwrap(), plain.exact.as_ref().unwrap());
    assert!(f.energy.error < 1e-7, "{:?}", f.energy);
    assert!((f.solves as f64) < 0.8 * p.solves as f64, "accelerated {} against plain {} solves", f.solves, p.solves);
    assert!(f.unsettled_steps <= p.unsettled_steps, "{f:?} against {p:?}");
}

/// Invariant: with the exact engine the drop-test thresholds land on the statics' — the
/// 15-voussoir arch (t/R) and the 6-block harmonic stack within 1 %, the slope within 0.1° (a
/// block sliding just past the friction angle needs 2 s to pass the drift tolerance), and a
/// 16-voussoir arch of t/R 0.15 under a horizontal acceleration (ground tilt) within 1 % in
/// tan — where rapier misses the arch by 10 % and the tilt by 43 %.
#[test]
fn thresholds_land_on_the_statics() {
    use voussoir::studies::threshold::{Family, bisect_thresholds};
    let settings = exact();
    let run = |family: Family, range| bisect_thresholds(&family, range, 10, &settings, &mut || {}).unwrap();
    let r = run(Family::Arch { n: 15 }, (0.08, 0.14));
    assert!((r.dynamic.mid() / r.statics.mid() - 1.0).abs() < 0.01, "arch: {r:?}");
    let r = run(Family::Harmonic { n: 6 }, (0.8, 1.1));
    assert!((r.dynamic.mid() / r.statics.mid() - 1.0).abs() < 0.01, "harmonic: {r:?}");
    let r = run(Family::Slope { mu: 0.6 }, (25.0, 35.0));
    assert!((r.dynamic.mid() - 0.6f64.atan().to_degrees()).abs() < 0.1, "slope: {r:?}");
    let scene = builtin("arch?n=16&t=0.15").unwrap();
    let r = run(Family::Tilt { scene: Box::new(scene) }, (0.0, 15.0));
    let tan = |deg: f64| deg.to_radians().tan();
    assert!((tan(r.dynamic.mid()) / tan(r.statics.mid()) - 1.0).abs() < 0.01, "tilt: {r:?}");
}

/// Invariant: an arch too thin to stand (t/R 0.08, 15 voussoirs) collapses — its blocks turn
/// far past the tolerance, the energy balance holds through the collapse — and its first step
/// is the kinematic check's mechanism, whose joints hinge.
#[test]
fn a_thin_arch_collapses_from_its_mechanism() {
    let scene = builtin("arch?n=15&t=0.08").unwrap();
    let settings = AnalysisSettings::default();
    let analysis = analyze(&scene, &settings).unwrap();
    assert!(!analysis.statics.stands);
    let k = check(&analysis, &settings.statics, &KinematicSettings::default()).unwrap();
    let m = k.mechanism.as_ref().expect("a mechanism");
    let hinges = m.interfaces.iter().filter(|i| i.state == voussoir::stability::JointState::Hinging).count();
    assert!(hinges >= 3, "{:?}", m.interfaces);
    let mut world = World::new(&analysis.assembly, &exact());
    world.step();
    let dt = exact().dt;
    for b in &m.blocks {
        let i = index(&scene, &b.block);
        let (v, w) = world.velocity(i);
        let err = (v / dt - Vector3::from(b.translation)).norm()
            + (w / dt - Vector3::from(b.rotation)).norm() * analysis.assembly.blocks[i].aabb.diagonal();
        assert!(err < 1e-6 * 9.81, "{}: {err}", b.block);
    }
    let r = drop(&scene, &DropSettings { duration: 1.0, ..exact() });
    assert!(!r.stands && r.max_rotation > 0.5, "{r:?}");
}

/// Invariant: real designs that stand by the statics stand with the exact engine for 2 s (the
/// Armadillo with compas_cra's supports and μ = 0.84; the compas dome on its lowest course),
/// without a block moving at all: the kinematic check holds them at rest, so after the first
/// step they sleep.
#[test]
fn real_vaults_stand_for_two_seconds() {
    let mut armadillo = voussoir::io::load_scene(&crate::common::compas_data("compas_cra/armadillo_cra.json")).unwrap();
    armadillo.material.friction = 0.84;
    let mut dome = voussoir::io::load_scene(&crate::common::compas_data("compas_assembly/dome_assembly.json")).unwrap();
    dome.mark_lowest_as_supports(1e-3);
    for scene in [armadillo, dome] {
        let r = drop(&scene, &exact());
        assert!(r.stands && r.max_drift == 0.0, "{}: {r:?}", scene.name);
        assert!(r.exact.as_ref().unwrap().solves <= 10, "{}: {:?}", scene.name, r.exact);
    }
}

/// Invariant: a block released 0.3 m above another that stands on the ground — no interface
/// between them at the start — lands on it and rests there (contacts that close under large
/// motion): it falls 0.3 m, not through the lower block, within 1e-3 of its size; the lower
/// block stays where it was (drift below 1e-3 of its size); the overlap stays below 1e-3.
#[test]
fn a_block_lands_on_another_it_did_not_touch() {
    let mut scene = Scene::new(
        "landing",
        vec![
            crate::common::cuboid("base", [0.0, 0.0, 0.0], [1.0, 1.0, 0.5]),
            crate::common::cube("top", [0.25, 0.25, 0.8], 0.5),
        ],
    );
    scene.ground = true;
    let r = drop(&scene, &exact());
    let e = r.exact.as_ref().unwrap();
    let asm = assembly(&scene);
    let size = asm.blocks[1].aabb.diagonal();
    let [base, top] = [0, 1].map(|i| &r.blocks[i]);
    assert!(
        (top.max_drift - 0.3).abs() < 1e-3 * size,
        "the top fell {} (0.3 onto the base, 0.8 through it)",
        top.max_drift
    );
    assert!(base.max_drift < 1e-3 * size, "the base moved {}", base.max_drift);
    assert!(r.at_rest && e.max_penetration < 1e-3, "{r:?}");
}

/// Invariant: through the collapse of a thin arch (t/R 0.08, 15 voussoirs, 1.5 s) no two
/// blocks pass into each other: at every 0.1 s, the blocks placed at the engine's poses
/// overlap by at most 1 % of the block size (parry's penetration depth between their convex
/// parts, computed apart from the engine), and the engine's own largest overlap agrees.
#[test]
fn a_collapsing_arch_keeps_its_blocks_apart() {
    let scene = builtin("arch?n=15&t=0.08").unwrap();
    let asm = assembly(&scene);
    let settings = DropSettings { duration: 1.5, ..exact() };
    let mut run = DropRun::new(&asm, &settings).unwrap();
    let size = asm.median_block_size().unwrap();
    let every = (0.1 / settings.dt).round() as usize;
    let mut deepest: f64 = 0.0;
    while !run.finished() {
        run.advance(every);
        let mut moved = scene.clone();
        for (i, block) in moved.blocks.iter_mut().enumerate() {
            let (x, q) = run.pose(i);
            let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
            let c = asm.blocks[i].mass.centroid;
            block.mesh.vertices.iter_mut().for_each(|p| *p = x + q * (*p - c));
        }
        let placed = assembly(&moved);
        for o in voussoir::interfaces::overlaps(&placed) {
            deepest = deepest.max(o.depth / size);
        }
    }
    let r = run.result();
    assert!(!r.stands && r.max_rotation > 0.5, "{r:?}");
    let e = r.exact.as_ref().unwrap();
    assert!(deepest < 0.01 && e.max_penetration < 0.01, "overlap {deepest} (engine: {})", e.max_penetration);
}

/// Invariant: a thin arch (t/R 0.08) collapsing onto the ground comes to rest there within 2 s
/// — blocks that turn over keep their ground contacts, voussoirs landing on each other and on
/// the springers do not pass through — every vertex of every block ends above the ground
/// (within 1 % of a block), the engine's deepest overlap stays below 1 %, and the energy
/// balance holds to 1e-5 through the impacts.
#[test]
fn a_thin_arch_collapses_onto_the_ground_and_rests_there() {
    let mut scene = builtin("arch?n=15&t=0.08").unwrap();
    scene.ground = true;
    let asm = assembly(&scene);
    let settings = DropSettings { duration: 2.0, ..exact() };
    let mut run = DropRun::new(&asm, &settings).unwrap();
    run.advance(run.total_steps());
    let r = run.result();
    let e = r.exact.as_ref().unwrap();
    assert!(!r.stands && r.at_rest && r.max_rotation > 1.5, "{r:?}");
    assert!(e.max_penetration < 0.01 && e.energy.error < 1e-5, "{e:?}");
    let size = asm.median_block_size().unwrap();
    for (i, block) in asm.blocks.iter().enumerate() {
        let (x, q) = run.pose(i);
        let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
        let lowest =
            block.mesh.vertices.iter().map(|p| (x + q * (p - block.mass.centroid)).z).fold(f64::INFINITY, f64::min);
        let floor = if block.support { -0.08 } else { 0.0 };
        assert!(lowest > floor - 0.01 * size, "{} reaches {lowest}", block.name);
    }
}

/// Invariant: a step whose solve reaches no answer is counted, not passed off as dynamics —
/// with one interior-point iteration allowed, every step of a block on a slab fails, and the
/// account says so with the status (a settlement stops there: `Outcome::Unresolved`).
#[test]
fn a_step_whose_solve_fails_is_counted() {
    let scene = builtin("stack?n=1&a=0.5").unwrap();
    let mut settings = exact();
    settings.exact.max_iterations = 1;
    let mut world = World::new(&assembly(&scene), &settings);
    for _ in 0..3 {
        world.step();
    }
    let stats = world.stats();
    assert_eq!(stats.failed_steps, 3, "{stats:?}");
    assert_eq!(stats.status, voussoir::statics::SolverStatus::MaxIterations);
    let mut fine = World::new(&assembly(&scene), &exact());
    fine.step();
    assert_eq!(fine.stats().failed_steps, 0);
}

/// The compas cross vault's free weight, N (`voussoir analyze`: W = 5.499295e5 N).
const WEIGHT: f64 = 5.499295e5;

/// The compas cross vault (184 blocks, 488 joints, μ 0.84) held from rest, then support 180
/// settling in `increments` of 4.85 mm (1 % of 5 % of its span) as `settle` takes them (the
/// support's step, then steps held still until the blocks rest; quasi-static tolerance 1e-8):
/// the engine's account.
fn crossvault_settling(selection: Selection, increments: usize) -> voussoir::dynamics::ExactStats {
    let mut scene = voussoir::io::load_scene(&crate::common::compas_data("compas_assembly/crossvault_assembly.json"))
        .expect("the vault loads");
    scene.material.friction = 0.84;
    let asm = assembly(&scene);
    let mut settings = exact();
    settings.exact.solver_tolerance = 1e-8;
    settings.exact.selection = selection;
    let travel = 4.85e-3 * increments as f64;
    let path = SupportPath {
        block: index(&scene, "180"),
        translation: Vector3::new(0.0, 0.0, -travel),
        rotation: Vector3::zeros(),
    };
    let mut world = World::with_paths(&asm, &settings, &[path]);
    world.set_step((10.0 * 4.85e-3 / 9.81f64).sqrt());
    for k in 0..=increments {
        if k > 0 {
            world.stop();
            world.step_supports(1.0 / increments as f64);
        }
        let held = (0..8).any(|_| {
            world.stop();
            world.step_held();
            world.at_rest() || world.fastest_vertex() <= 1e-4 * world.free_fall_speed()
        });
        assert!(held, "{selection:?}: the vault holds after increment {k}");
    }
    world.stats()
}

/// Invariant: on a hyperstatic vault near rest, the force selection within Coulomb's cones
/// settles each step's Tresca rounds in fewer — the cross vault held, then settling by two
/// increments: at most half the solves the round's own sets take and fewer rounds in its
/// longest step (measured: 23 solves against 59, 3 rounds against 8; over the `settle` CLI's
/// first 4 increments, 41 against 264 and 3 against 30), no step left unsettled, and the
/// selected forces in equilibrium with the steps' momentum to 1e-9 of the vault's weight.
#[test]
fn coulomb_selection_settles_a_settling_vault_in_few_rounds() {
    let (coulomb, round) = (crossvault_settling(Selection::Coulomb, 2), crossvault_settling(Selection::Round, 2));
    assert_eq!(coulomb.unsettled_steps, 0, "{coulomb:?}");
    assert!(coulomb.max_rounds < round.max_rounds, "{coulomb:?} against {round:?}");
    assert!(2 * coulomb.solves <= round.solves, "Coulomb {} against round {} solves", coulomb.solves, round.solves);
    assert!(coulomb.residual <= 1e-9 * WEIGHT, "{coulomb:?}");
}
