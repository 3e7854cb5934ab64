//! The shake table against closed forms: Newmark's sliding block, Housner's rectangular pulse
//! (the rocking equation integrated here independently), the static load factor as the long
//! pulse's limit, the size effect, and a motion of zero amplitude as the drop test bit for bit.
//! All on the exact-contact engine at the default step (1/240 s).

use crate::common::{assembly, cuboid};
use voussoir::dynamics::{
    DropRun, DropSettings, Engine, Excitation, GroundMotion, PulseShape, Stepper, drop_test, run::record_run,
};
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Block, Scene};
use voussoir::stability::{JointState, assess_parts, with_horizontal_field};
use voussoir::studies::shake::{
    ShakeSettings, SpectrumSettings, collapse_spectrum, shake, shake_run, static_load_factor, time_scale,
};

/// The scenes' gravity, m/s².
fn gravity(scene: &Scene) -> f64 {
    scene.gravity.norm()
}

/// A rectangular pulse of `a` m/s² for `duration` s along +x.
fn rect(a: f64, duration: f64) -> GroundMotion {
    GroundMotion::horizontal(Excitation::Pulse { shape: PulseShape::Rectangular, amplitude: a, duration }, 0.0)
}

/// A 2b × 2b × 2h block standing on the ground plane (or on a wide support slab 0.2 thick).
fn standing(b: f64, h: f64, on_slab: bool) -> Scene {
    let z0 = if on_slab { 0.2 } else { 0.0 };
    let mut blocks = vec![cuboid("block", [-b, -b, z0], [b, b, z0 + 2.0 * h])];
    if on_slab {
        let mut slab: Block = cuboid("slab", [-20.0 * b, -20.0 * b, 0.0], [20.0 * b, 20.0 * b, 0.2]);
        slab.support = true;
        blocks.push(slab);
    }
    let mut scene = Scene::new("block", blocks);
    scene.ground = !on_slab;
    scene
}

/// Invariant (Newmark 1965): a squat block (b/h 2.5, so it slides, not rocks) with friction μ
/// on a base that a rectangular pulse A > μg accelerates for t₀ slides relative to the base
/// by A t₀² (A − μg) / (2 μ g) within 1 % — in the exact engine and in rapier, on the ground
/// plane and on a support slab; under A < μg it does not move (drift ≤ 1e-9 of its size in the
/// exact engine, 1e-4 in rapier's soft contacts).
#[test]
fn a_block_slides_as_newmark_says() {
    let mu = 0.3;
    for (engine, still) in [(Engine::Exact, 1e-9), (Engine::Rapier, 1e-4)] {
        for on_slab in [false, true] {
            let scene = standing(0.5, 0.2, on_slab);
            let asm = assembly(&scene);
            let g = gravity(&scene);
            let mut settings = ShakeSettings {
                // ≈ 1.2 s after the pulse: it stops sliding within 0.42 s of the pulse's end.
                after: 3.0,
                ..ShakeSettings::default()
            };
            (settings.drop.engine, settings.drop.friction) = (engine, Some(mu));
            let what = format!("{} slab {on_slab}", engine.name());
            for (a_g, t0) in [(0.5, 0.4), (0.8, 0.25)] {
                let a = a_g * g;
                let expected = a * t0 * t0 * (a - mu * g) / (2.0 * mu * g);
                let r = shake(&asm, &settings, &rect(a, t0)).expect("the shake runs");
                let slid = r.blocks[0].final_drift;
                assert!(
                    (slid / expected - 1.0).abs() < 0.01,
                    "{what}, {a_g} g for {t0} s: slid {slid:.5} m vs Newmark's {expected:.5} m"
                );
                assert!(r.fell.is_none() && r.blocks[0].max_rotation < 1e-3, "{what}: {r:?}");
            }
            let r = shake(&asm, &settings, &rect(0.25 * g, 0.4)).expect("the shake runs");
            let size = asm.blocks[0].aabb.diagonal();
            assert!(r.blocks[0].max_drift < still * size, "{what}: below μg it drifted {:e}", r.blocks[0].max_drift);
        }
    }
}

/// Invariant: a motion that names the slab moves only it, as a kinematic body along the
/// integrated path: the block slides on it — the slab's displacement less the block's — by
/// Newmark's A t₀² (A − μg) / (2 μ g) within 0.1 % in the exact engine and 2 % in rapier
/// (its kinematic body's soft friction: +1.4 %; the slab carried 1.9 m); a name that is no
/// support is one error naming it.
#[test]
fn a_named_support_carries_the_motion() {
    let mu = 0.3;
    let scene = standing(0.5, 0.2, true);
    let asm = assembly(&scene);
    let g = gravity(&scene);
    let (a, t0) = (0.5 * g, 0.4);
    let expected = a * t0 * t0 * (a - mu * g) / (2.0 * mu * g);
    for (engine, within) in [(Engine::Exact, 1e-3), (Engine::Rapier, 0.02)] {
        let mut settings = ShakeSettings { after: 3.0, ..ShakeSettings::default() };
        (settings.drop.engine, settings.drop.friction) = (engine, Some(mu));
        let mut motion = rect(a, t0);
        motion.supports = vec!["slab".into()];
        let mut run = shake_run(&asm, &settings, &motion).expect("the shake runs");
        run.advance(run.total_steps());
        let x = |i: usize| run.pose(i).0.x - asm.blocks[i].mass.centroid.x;
        let (block, slab) = (x(0), x(1));
        let slid = slab - block;
        assert!(slab > 1.5, "{}: the slab moved {slab} m", engine.name());
        let e = slid / expected - 1.0;
        assert!(e.abs() < within, "{}: slid {slid:.5} m on the slab vs {expected:.5} m", engine.name());
    }
    let mut motion = rect(a, t0);
    motion.supports = vec!["block".into()];
    let err = shake(&asm, &ShakeSettings::default(), &motion).expect_err("a free block");
    assert!(err.to_string().contains("support 'block': it is a free block"), "{err}");
}

/// Whether the rocking equation θ'' = p² (A/g cos(α − θ) − sin(α − θ)) during a rectangular
/// pulse of A (m/s²) for `tp`, free after it, overturns a block (α, p² = 3g / 4R) from rest:
/// RK4 at 1e-6 s through the pulse, then the free rocking's energy ½θ'² − p² cos(α − θ) against
/// the top's (θ = α). After the pulse the block either passes θ = α on its first swing or comes
/// back and loses energy at every impact, so that is the whole question.
fn rocking_overturns(alpha: f64, p: f64, a_over_g: f64, tp: f64) -> bool {
    if a_over_g <= alpha.tan() {
        return false;
    }
    let f = |th: f64, w: f64| (w, p * p * (a_over_g * (alpha - th).cos() - (alpha - th).sin()));
    let steps = (tp / 1e-6).ceil() as usize;
    let dt = tp / steps as f64;
    let (mut th, mut w) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        let k1 = f(th, w);
        let k2 = f(th + 0.5 * dt * k1.0, w + 0.5 * dt * k1.1);
        let k3 = f(th + 0.5 * dt * k2.0, w + 0.5 * dt * k2.1);
        let k4 = f(th + dt * k3.0, w + dt * k3.1);
        th += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        w += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        if th >= alpha {
            return true;
        }
    }
    0.5 * w * w >= p * p * (1.0 - (alpha - th).cos())
}

/// The least A/g that overturns by [`rocking_overturns`], bisected to 1e-9.
fn rocking_threshold(alpha: f64, p: f64, tp: f64) -> f64 {
    let (mut lo, mut hi) = (alpha.tan(), 100.0);
    while hi - lo > 1e-9 * hi {
        let mid = 0.5 * (lo + hi);
        if rocking_overturns(alpha, p, mid, tp) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// Invariant (Housner 1963): a slender block (b/h 0.1) overturns under a rectangular pulse
/// exactly from the amplitude at which the rocking equation, integrated independently, says
/// it does — within 1 % for p t_p ∈ {0.5, 1, 2, 4}; the same block ×4 needs the larger
/// amplitude the equation gives at the same duration (the size effect: p halves). The small-α
/// closed form a / (g α) = 1 / (1 − e^(−p t_p)) is within 2 % of the equation's threshold.
#[test]
fn a_slender_block_overturns_as_housner_says() {
    let mut small = Vec::new();
    for scale in [1.0, 4.0] {
        let (b, h) = (0.05 * scale, 0.5 * scale);
        let scene = standing(b, h, false);
        let asm = assembly(&scene);
        let g = gravity(&scene);
        let (alpha, r) = (b.atan2(h), b.hypot(h));
        let p = (3.0 * g / (4.0 * r)).sqrt();
        let pts: &[f64] = if scale == 1.0 { &[0.5, 1.0, 2.0, 4.0] } else { &[1.0] };
        let settings =
            SpectrumSettings { durations: pts.iter().map(|pt| pt / p).collect(), ..SpectrumSettings::default() };
        let spectrum = collapse_spectrum(&asm, b / h, &settings, &|| {}).expect("the spectrum runs");
        for point in &spectrum.points {
            let reference = rocking_threshold(alpha, p, point.duration);
            let got = point.collapses_g.expect("it overturns");
            let what = format!("×{scale}, p t_p {:.2}", p * point.duration);
            assert!(
                (got / reference - 1.0).abs() < 0.01,
                "{what}: {got:.5} g vs the rocking equation's {reference:.5} g"
            );
            let closed = alpha / (1.0 - (-p * point.duration).exp());
            assert!((closed / reference - 1.0).abs() < 0.02, "{what}: closed form {closed} vs {reference}");
            if scale == 1.0 {
                small.push((point.duration, got, reference));
            } else {
                // The small block at this duration is its p t_p = 2 point.
                let (d, engine_small, reference_small) = small[2];
                assert!((d / point.duration - 1.0).abs() < 1e-12);
                let (ratio, expected) = (got / engine_small, reference / reference_small);
                assert!(
                    expected > 1.2 && (ratio / expected - 1.0).abs() < 0.02,
                    "size effect ×4: {ratio} vs {expected}"
                );
            }
        }
    }
}

/// Invariant: a motion of zero amplitude is the drop test bit for bit: the same verdict,
/// motions and energy account, and every recorded pose equal.
#[test]
fn a_motion_of_zero_amplitude_is_the_drop_test() {
    // Leaning on its edge 8°, so that it rocks.
    let (s, c) = 8f64.to_radians().sin_cos();
    let mesh = Mesh::cuboid(Point3::new(-0.1, -0.1, 0.0), Point3::new(0.1, 0.1, 1.0)).map_points(|q| {
        let x = q.x - 0.1;
        Point3::new(0.1 + c * x + s * q.z, q.y, -s * x + c * q.z)
    });
    let mut scene = Scene::new("leaning", vec![Block::new("block", mesh)]);
    scene.ground = true;
    let asm = assembly(&scene);
    let settings = DropSettings { engine: Engine::Exact, duration: 1.5, ..DropSettings::default() };
    let plain = record_run(DropRun::new(&asm, &settings).expect("runs"), &asm, 60.0).expect("records");
    let shaken =
        record_run(DropRun::shaken(&asm, &settings, rect(0.0, 1.0)).expect("runs"), &asm, 60.0).expect("records");
    assert_eq!(plain.1, shaken.1, "the poses");
    let strip = |mut r: voussoir::dynamics::DropResult| {
        r.wall_s = 0.0;
        r
    };
    assert_eq!(strip(plain.0.clone()), strip(shaken.0), "the verdicts");
    assert!(plain.0.blocks[0].max_rotation > 0.1, "it rocked: {:?}", plain.0.blocks[0]);
    let dropped = drop_test(&asm, &settings).expect("drops");
    assert_eq!(strip(dropped), strip(plain.0));
}

/// A column of four blocks 0.5 tall narrowing upwards (0.3, 0.25, 0.2, 0.15 wide) on a
/// support base.
fn column() -> Scene {
    let mut blocks = Vec::new();
    for (k, w) in [0.3, 0.25, 0.2, 0.15].into_iter().enumerate() {
        let z = 0.2 + 0.5 * k as f64;
        blocks.push(cuboid(&format!("c{k}"), [-w / 2.0, -0.15, z], [w / 2.0, 0.15, z + 0.5]));
    }
    let mut base = cuboid("base", [-1.0, -1.0, 0.0], [1.0, 1.0, 0.2]);
    base.support = true;
    blocks.push(base);
    Scene::new("column", blocks)
}

/// Invariant: for long pulses (p t_p = 20, p = √(3g / 4R), R half the free blocks' size) the
/// least amplitude of a rectangular pulse that collapses a slender block, a tapered column and
/// a 16-voussoir arch is the statics' horizontal load factor λ* within 0.5 %, and the joints
/// the exact engine opens at the first instant of a pulse 1 % above it are the statics'
/// mechanism's.
#[test]
fn the_long_pulse_limit_is_the_static_load_factor() {
    let mut on_base = standing(0.05, 0.5, true);
    on_base.name = "slender block".into();
    let arch = voussoir::model::builtin("arch?n=16&t=0.15").expect("the arch");
    let settings = voussoir::pipeline::AnalysisSettings::default();
    for scene in [on_base, column(), arch] {
        let analysis = voussoir::pipeline::analyze(&scene, &settings).expect("analyses");
        let asm = &analysis.assembly;
        let lambda = static_load_factor(&analysis, &settings.statics, 0.0).expect("λ*");
        let g = gravity(&scene);
        let r = 0.5 * (time_scale(asm).powi(2) * g);
        let p = (3.0 * g / (4.0 * r)).sqrt();
        let spectrum_settings = SpectrumSettings { durations: vec![20.0 / p], ..SpectrumSettings::default() };
        let spectrum = collapse_spectrum(asm, lambda, &spectrum_settings, &|| {}).expect("the spectrum runs");
        let got = spectrum.points[0].collapses_g.expect("a long pulse collapses it");
        let what = &scene.name;
        assert!((got / lambda - 1.0).abs() < 0.005, "{what}: collapses from {got:.5} g, λ* = {lambda:.5} g");

        let field = with_horizontal_field(asm, 180.0);
        let robustness = assess_parts(&field, &analysis.interfaces, true, &settings.statics).expect("λ*");
        let mechanism = robustness.mechanism.expect("a mechanism");
        let mut statics: Vec<usize> =
            mechanism.interfaces.iter().filter(|j| j.state != JointState::Closed).map(|j| j.index).collect();
        statics.sort();
        let drop = DropSettings { engine: Engine::Exact, ..DropSettings::default() };
        let Stepper::Exact(mut world) = Stepper::with_paths(asm, &drop, &[]) else { unreachable!() };
        world.set_base_acceleration(Vector3::new(1.01 * lambda * gravity(&scene), 0.0, 0.0));
        (0..3).for_each(|_| world.step());
        let rates = world.joint_rates();
        let largest = rates.iter().map(|r| r.2.abs().max(r.3)).fold(0.0, f64::max);
        let mut engine: Vec<usize> =
            rates.iter().filter(|r| r.2.abs().max(r.3) > 1e-3 * largest).map(|r| r.0).collect();
        engine.sort();
        engine.dedup();
        assert!(largest > 0.0 && engine == statics, "{what}: the engine opens {engine:?}, the statics {statics:?}");
    }
}
