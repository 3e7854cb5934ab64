//! Crushing: a compressive strength σ_c bounds every joint's resultant by the rectangular
//! stress block (module docs of `statics::problem`).
//!
//! Invariants: a column of n blocks needs n·W/A at its base (W one block's weight, A the
//! joint's area) and crushes just below it; an eccentric resultant at distance a from the
//! near edge of a rectangular joint of width b needs N / (2 a b), and at a₀, a₁ from the near
//! edges of both axes N / (4 a₀ a₁); the forces reported for a
//! design that stands are ones the stone carries; the load factor honours the strength
//! (λ* = (σ_c A − n W) / P under a vertical live load P); σ_c → ∞ gives the answers without a
//! strength bit for bit; a bad strength is one clear error.

use crate::common::*;
use voussoir::geometry::Vector3;
use voussoir::model::{Load, LoadKind, ModelError, Scene};
use voussoir::pipeline::AnalysisSettings;
use voussoir::stability::{self, Safety};
use voussoir::statics::{StaticsResult, Verdict};

/// Density 1 and g = 1: a block's weight is its volume, a stress needed is in units of length.
fn unit_scene(blocks: Vec<voussoir::model::Block>) -> Scene {
    let mut s = Scene::new("crushing", blocks);
    s.material.density = 1.0;
    s.gravity = Vector3::new(0.0, 0.0, -1.0);
    s
}

/// n blocks of b × d × h stacked on a support slab.
fn column(n: usize, b: f64, d: f64, h: f64) -> Scene {
    let mut blocks = vec![cuboid("base", [-1.0, -1.0, -1.0], [b + 1.0, d + 1.0, 0.0]).support(true)];
    for i in 0..n {
        let z = i as f64 * h;
        blocks.push(cuboid(&format!("b{i}"), [0.0, 0.0, z], [b, d, z + h]));
    }
    unit_scene(blocks)
}

fn statics(scene: &Scene, strength: Option<f64>) -> StaticsResult {
    let mut settings = AnalysisSettings::default();
    settings.statics.strength = strength;
    run(scene, &settings).statics
}

#[test]
fn a_column_crushes_at_n_w_over_a() {
    let (n, b, d, h) = (4, 0.5, 0.3, 0.8);
    let scene = column(n, b, d, h);
    let needed = n as f64 * b * d * h / (b * d);
    let r = statics(&scene, Some(1.0));
    let c = r.crushing.as_ref().expect("a crushing report on a design that stands");
    assert_close(c.needed, needed, 1e-6 * needed, "least strength of the column");
    assert!([&c.a, &c.b].contains(&&"base".to_string()), "the base joint governs: {c:?}");
    assert_eq!(statics(&scene, Some(needed * 1.001)).verdict, Verdict::Stands);
    assert_eq!(statics(&scene, Some(needed * 0.999)).verdict, Verdict::Crushes);
}

/// A 1 × 1 × h block overhanging its support: the joint spans x ∈ [0.3, 1], the weight acts
/// at x = 0.5, a = 0.2 from the joint's near edge: σ = W / (2 a · 1).
#[test]
fn an_eccentric_resultant_needs_n_over_twice_its_distance_to_the_edge() {
    let h = 0.6;
    let scene = unit_scene(vec![
        cuboid("pier", [0.3, 0.0, -1.0], [2.0, 1.0, 0.0]).support(true),
        cuboid("block", [0.0, 0.0, 0.0], [1.0, 1.0, h]),
    ]);
    let needed = h / (2.0 * 0.2);
    let r = statics(&scene, Some(10.0));
    assert_eq!(r.verdict, Verdict::Stands);
    assert_close(r.crushing.as_ref().unwrap().needed, needed, 1e-6 * needed, "eccentric joint");
    assert_eq!(statics(&scene, Some(needed * 0.999)).verdict, Verdict::Crushes);
}

/// A 1 × 1 × h block on a pier's corner: the joint spans x ∈ [0.3, 1] × y ∈ [0.2, 1], the
/// weight acts at (0.5, 0.5), a₀ = 0.2 and a₁ = 0.3 from the near edges: the biaxial stress
/// block needs σ = W / (4 a₀ a₁) (a bound per axis would give W / (2 a₀ · 0.8), a third less).
#[test]
fn a_resultant_eccentric_along_both_axes_needs_n_over_four_a0_a1() {
    let h = 0.6;
    let scene = unit_scene(vec![
        cuboid("pier", [0.3, 0.2, -1.0], [2.0, 2.0, 0.0]).support(true),
        cuboid("block", [0.0, 0.0, 0.0], [1.0, 1.0, h]),
    ]);
    let needed = h / (4.0 * 0.2 * 0.3);
    let r = statics(&scene, Some(10.0));
    assert_eq!(r.verdict, Verdict::Stands);
    assert_close(r.crushing.as_ref().unwrap().needed, needed, 1e-6 * needed, "corner joint");
    assert_eq!(statics(&scene, Some(needed * 1.001)).verdict, Verdict::Stands);
    assert_eq!(statics(&scene, Some(needed * 0.999)).verdict, Verdict::Crushes);
}

/// The stress a joint x ∈ [x0, x1] × y ∈ [0, 1] needs under the reported vertex forces,
/// computed here from the vertices (the resultant along x; y is symmetric).
fn demand(r: &StaticsResult, index: usize, x0: f64, x1: f64) -> f64 {
    let itf = &r.interfaces[index];
    let n: f64 = itf.vertices.iter().map(|v| v.compression - v.tension).sum();
    let e = itf.vertices.iter().map(|v| (v.compression - v.tension) * v.position[0]).sum::<f64>() / n;
    n / (2.0 * (e - x0).min(x1 - e))
}

/// A lintel on a narrow and a wide pier: the least-squares forces load the narrow joint
/// harder than a strength between the least needed and theirs allows; with that strength the
/// forces reported are another equilibrium, one each joint carries.
#[test]
fn the_forces_reported_are_ones_the_stone_carries() {
    let scene = unit_scene(vec![
        cuboid("narrow", [0.0, 0.0, -1.0], [0.2, 1.0, 0.0]).support(true),
        cuboid("wide", [2.0, 0.0, -1.0], [3.0, 1.0, 0.0]).support(true),
        cuboid("lintel", [0.0, 0.0, 0.0], [3.0, 1.0, 0.3]),
    ]);
    let free = statics(&scene, None);
    let joints: Vec<(usize, f64, f64)> = free
        .interfaces
        .iter()
        .enumerate()
        .map(|(k, i)| if i.a == "narrow" || i.b == "narrow" { (k, 0.0, 0.2) } else { (k, 2.0, 3.0) })
        .collect();
    let own = joints.iter().map(|&(k, x0, x1)| demand(&free, k, x0, x1)).fold(0.0, f64::max);
    let least = statics(&scene, Some(1e9)).crushing.unwrap().needed;
    assert!(least < 0.8 * own, "the case must leave room: least {least}, the forces' own {own}");
    let sigma = 0.5 * (least + own);
    let r = statics(&scene, Some(sigma));
    assert_eq!(r.verdict, Verdict::Stands);
    for &(k, x0, x1) in &joints {
        let d = demand(&r, k, x0, x1);
        assert!(d <= sigma * (1.0 + 1e-6), "joint {k} needs {d} > σ_c {sigma}");
    }
    assert!(r.solver.residual <= 1e-9 * r.free_weight, "residual {}", r.solver.residual);
}

/// A column under a vertical live load P on its top block: λ* = (σ_c A − n W) / P.
#[test]
fn the_load_factor_honours_the_strength() {
    let (n, b, d, h) = (3, 0.5, 0.5, 1.0);
    let mut scene = column(n, b, d, h);
    let top = format!("b{}", n - 1);
    let p = 0.1;
    scene.loads.push(Load::Point {
        block: top,
        point: voussoir::geometry::Point3::new(b / 2.0, d / 2.0, n as f64 * h),
        force: Vector3::new(0.0, 0.0, -p),
        kind: LoadKind::Live,
    });
    let sigma = 20.0;
    let mut settings = AnalysisSettings::default();
    settings.statics.strength = Some(sigma);
    let a = run(&scene, &settings);
    assert_eq!(a.statics.verdict, Verdict::Stands);
    let r = stability::assess(&a, &settings.statics).unwrap();
    let expected = (sigma * b * d - n as f64 * b * d * h) / p;
    match r.safety {
        Safety::Collapses { load_factor } => assert_close(load_factor, expected, 1e-6 * expected, "λ* crushing"),
        other => panic!("expected a load factor, got {other:?}"),
    }
}

/// σ_c far above any stress: the same forces and numbers as without a strength, bit for bit.
#[test]
fn a_strength_far_above_every_stress_changes_nothing() {
    let scene = voussoir::model::builtin::builtin("arch").unwrap();
    let plain = statics(&scene, None);
    let strong = statics(&scene, Some(1e15));
    assert!(strong.crushing.as_ref().unwrap().utilization < 1e-6);
    assert_eq!(plain.verdict, strong.verdict);
    assert_eq!(plain.tension_ratio.to_bits(), strong.tension_ratio.to_bits());
    assert_eq!(plain.interfaces, strong.interfaces);
}

#[test]
fn a_bad_strength_is_one_clear_error() {
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let mut scene = column(1, 1.0, 1.0, 1.0);
        scene.material.strength = Some(bad);
        let err = voussoir::model::Assembly::new(&scene, &Default::default()).unwrap_err();
        assert!(matches!(err, ModelError::BadStrength(_)), "{bad}: {err}");
        let mut settings = AnalysisSettings::default();
        settings.statics.strength = Some(bad);
        let err = voussoir::pipeline::analyze(&column(1, 1.0, 1.0, 1.0), &settings).unwrap_err();
        assert!(err.to_string().contains("compressive strength"), "{bad}: {err}");
    }
}

/// Invariant (the exact engine): an overloaded joint yields. A block's centred resultant has
/// the whole joint as its stress block, so the joint carries at most σ_c A and the block sinks
/// with a = g (1 − σ_c A / W): after n steps its speed is a n h, to 1e-6 relative, without
/// turning or drifting sideways (1e-7 m/s, rad/s); with σ_c above W/A it stays at rest.
#[test]
fn the_exact_engine_lets_an_overloaded_joint_crush() {
    use voussoir::dynamics::exact::World;
    use voussoir::dynamics::{DropSettings, Engine};
    // Density 1, g = 1, h = 1: W / A = 1.
    let scene = column(1, 0.5, 0.4, 1.0);
    let asm = assembly(&scene);
    for (sigma, sinking) in [(0.5, 0.5), (0.8, 0.2), (2.0, 0.0)] {
        let settings = DropSettings { engine: Engine::Exact, strength: Some(sigma), ..Default::default() };
        let mut world = World::new(&asm, &settings);
        let n = 10;
        for _ in 0..n {
            world.step();
        }
        let (v, w) = world.velocity(1);
        let expected = -sinking * n as f64 * settings.dt;
        assert!((v.z - expected).abs() <= 1e-6 * (n as f64 * settings.dt), "σ {sigma}: v_z {} vs {expected}", v.z);
        assert!(v.x.abs() + v.y.abs() + w.norm() < 1e-7, "σ {sigma}: {v:?} {w:?}");
    }
}

/// The biaxial stress-block demand of an interface's reported vertex forces, computed here
/// from the report alone: the polygon in its (u, v) plane, axes along its longest edge and
/// across it, κ = 4 A / (L₀ L₁), N / (κ a₀ a₁).
fn reported_demand(itf: &voussoir::statics::InterfaceResult) -> f64 {
    let p: Vec<Vector3> = itf.vertices.iter().map(|v| Vector3::from(v.position)).collect();
    let (u, v) = (Vector3::from(itf.u), Vector3::from(itf.v));
    let uv: Vec<[f64; 2]> = p.iter().map(|q| [(q - p[0]).dot(&u), (q - p[0]).dot(&v)]).collect();
    let n = uv.len();
    let edge = |i: usize| [uv[(i + 1) % n][0] - uv[i][0], uv[(i + 1) % n][1] - uv[i][1]];
    let e = (0..n).map(edge).fold([0.0f64, 0.0], |b, e| if e[0].hypot(e[1]) > b[0].hypot(b[1]) { e } else { b });
    let len = e[0].hypot(e[1]);
    let axes = [[e[0] / len, e[1] / len], [-e[1] / len, e[0] / len]];
    let area = 0.5 * (0..n).map(|i| uv[i][0] * uv[(i + 1) % n][1] - uv[(i + 1) % n][0] * uv[i][1]).sum::<f64>().abs();
    let cn: Vec<f64> = itf.vertices.iter().map(|v| v.compression - v.tension).collect();
    let total: f64 = cn.iter().sum();
    if total <= 0.0 {
        return 0.0;
    }
    let mut extents = [0.0; 2];
    let mut reach = [0.0; 2];
    for k in 0..2 {
        let t: Vec<f64> = uv.iter().map(|q| q[0] * axes[k][0] + q[1] * axes[k][1]).collect();
        let (lo, hi) = t.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
        let at = t.iter().zip(&cn).map(|(x, f)| x * f).sum::<f64>() / total;
        extents[k] = hi - lo;
        reach[k] = (at - lo).min(hi - at);
    }
    if reach[0] <= 0.0 || reach[1] <= 0.0 {
        return f64::INFINITY;
    }
    total / (4.0 * area / (extents[0] * extents[1]) * reach[0] * reach[1])
}

/// Invariant: on a real design (the Armadillo, 399 blocks), with a strength a fifth above the
/// least it needs, every interface's reported forces need at most that strength — checked
/// from the report alone ([`reported_demand`]) — whatever the solve that found them.
#[test]
fn the_armadillo_s_reported_forces_are_ones_its_stone_carries() {
    let mut scene = voussoir::io::load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
    scene.material.friction = 0.84;
    let needed = statics(&scene, Some(1e9)).crushing.expect("a crushing report").needed;
    let sigma = 1.2 * needed;
    let r = statics(&scene, Some(sigma));
    assert_eq!(r.verdict, Verdict::Stands);
    let (worst, at) =
        r.interfaces.iter().map(|i| (reported_demand(i), i.index)).fold((0.0, 0), |b, d| if d.0 > b.0 { d } else { b });
    assert!(worst <= sigma * (1.0 + 1e-4), "interface {at} needs {worst} Pa of {sigma} Pa");
}
