//! Load factors and collapse mechanisms against closed forms, and the duality invariant.
//!
//! Invariants: λ* is the largest multiple of the live load that compression-only forces with
//! friction within the model carry (tipping b/h, sliding μ, the lever rule of a point load);
//! the mechanism does work λ*·1 + (dead work) = 0 with the live load's work 1 and opens no
//! interface negatively; λ* does not change with the unit or the density; dead loads enter
//! every analysis; bad loads are one clear error each.

use crate::common::*;
use std::f64::consts::{FRAC_PI_4, FRAC_PI_8, SQRT_2};
use voussoir::geometry::{Point3, Vector3};
use voussoir::interfaces::Interface;
use voussoir::model::{Assembly, Block, BlockId, Load, LoadKind, ModelError, Scene};
use voussoir::pipeline::{Analysis, AnalysisSettings, analyze};
use voussoir::stability::{self, DirectionSettings, JointState, Robustness, RobustnessError, Safety};
use voussoir::statics::{FrictionModel, StaticsSettings};

const G: f64 = 9.81;

pub(crate) fn settings(model: FrictionModel) -> AnalysisSettings {
    AnalysisSettings { statics: StaticsSettings { friction_model: model, ..Default::default() }, ..Default::default() }
}

/// `blocks` on a support slab under z = 0 reaching `reach` in x and y, friction `mu`.
pub(crate) fn on_base(blocks: Vec<Block>, reach: f64, mu: f64) -> Scene {
    let mut all = vec![cuboid("base", [-1.0, -1.0, -1.0], [reach, reach, 0.0]).support(true)];
    all.extend(blocks);
    let mut s = Scene::new("test", all);
    s.material.friction = mu;
    s
}

/// A b × b × h block on the base.
fn block(b: f64, h: f64, mu: f64) -> Scene {
    on_base(vec![cuboid("block", [0.0; 3], [b, b, h])], b + 1.0, mu)
}

pub(crate) fn assess(scene: &Scene, model: FrictionModel) -> (Analysis, Robustness) {
    let s = settings(model);
    let a = analyze(scene, &s).unwrap();
    let r = stability::assess(&a, &s.statics).unwrap();
    check_duality(&a.assembly, &a.interfaces, &r);
    (a, r)
}

pub(crate) fn lambda(r: &Robustness) -> f64 {
    match r.safety {
        Safety::Collapses { load_factor } => load_factor,
        other => panic!("expected a load factor, got {other:?}"),
    }
}

/// The duality invariant: live work 1, λ*·1 + dead work = 0 (1e-6 relative), and no interface
/// vertex closing into its neighbour (normal relative motion ≥ −1e-6 of the largest).
fn check_duality(asm: &Assembly, interfaces: &[Interface], r: &Robustness) {
    let Some(m) = &r.mechanism else { return };
    let free = || (0..asm.blocks.len()).filter(|&i| !asm.blocks[i].support).map(BlockId);
    let live = m.work(free().map(|b| (b, asm.loads[b.0].live)));
    let dead = m.work(free().map(|b| {
        let w = asm.gravity * asm.block(b).mass();
        let d = asm.loads[b.0].dead;
        (b, [w.x + d[0], w.y + d[1], w.z + d[2], d[3], d[4], d[5]])
    }));
    if let Safety::Collapses { load_factor } = r.safety {
        assert_close(live, 1.0, 1e-6, "the live load does unit work");
        let scale = dead.abs().max(load_factor.abs()).max(1e-12);
        assert!((load_factor * live + dead).abs() <= 1e-6 * scale, "work balance: λ* {load_factor} dead {dead}");
    }
    let largest = m.largest_motion(asm);
    for im in &m.interfaces {
        let itf = &interfaces[im.index];
        for (dn, _) in m.vertex_motions(asm, itf) {
            assert!(dn >= -1e-6 * largest, "{} → {} closes by {dn} (largest {largest})", im.a, im.b);
        }
    }
}

fn base_state(r: &Robustness) -> JointState {
    let m = r.mechanism.as_ref().expect("a mechanism");
    m.interfaces.iter().find(|i| i.a == "base" || i.b == "base").expect("the base interface").state
}

/// Tipping: λ* = b/h when μ > b/h, the base hinging, the block turning about +y (the top
/// towards +x); sliding: λ* = μ when μ < b/h, the base sliding. Every model along a face
/// normal (the frame's u axis is x on a horizontal joint).
#[test]
fn a_block_tips_at_b_over_h_and_slides_at_mu() {
    for model in [FrictionModel::Cone, FrictionModel::Pyramid8, FrictionModel::Box4] {
        let mut s = block(0.5, 1.0, 0.8);
        s.loads.push(Load::horizontal(0.0, 1.0));
        let (_, r) = assess(&s, model);
        assert_close(lambda(&r), 0.5, 1e-6, &format!("{model} tipping"));
        assert_eq!(base_state(&r), JointState::Hinging, "{model}");
        let m = &r.mechanism.as_ref().unwrap().blocks[0];
        assert!(m.rotation[1] > 0.0 && m.rotation[0].abs() < 1e-6 * m.rotation[1], "{model}: {m:?}");

        let mut s = block(0.5, 1.0, 0.3);
        s.loads.push(Load::horizontal(0.0, 1.0));
        let (_, r) = assess(&s, model);
        assert_close(lambda(&r), 0.3, 1e-6, &format!("{model} sliding"));
        assert_eq!(base_state(&r), JointState::Sliding, "{model}");
    }
}

/// In a diagonal direction the models differ: the cone holds μ in every direction; the
/// 8-sided pyramid μ at 45° (a facet |u + v| ≤ √2 μ) and μ / cos 22.5° at 22.5° (a corner);
/// the box √2 μ at 45° (a corner) and μ / cos 22.5° at 22.5°. b/h = 2 keeps tipping away.
#[test]
fn diagonal_sliding_shows_what_each_model_allows() {
    let mu = 0.3;
    let cases = [
        (FrictionModel::Cone, FRAC_PI_4, mu),
        (FrictionModel::Pyramid8, FRAC_PI_4, mu),
        (FrictionModel::Box4, FRAC_PI_4, SQRT_2 * mu),
        (FrictionModel::Cone, FRAC_PI_8, mu),
        (FrictionModel::Pyramid8, FRAC_PI_8, mu / FRAC_PI_8.cos()),
        (FrictionModel::Box4, FRAC_PI_8, mu / FRAC_PI_8.cos()),
    ];
    for (model, azimuth, expected) in cases {
        let mut s = block(1.0, 0.5, mu);
        s.loads.push(Load::horizontal(azimuth, 1.0));
        let (_, r) = assess(&s, model);
        assert_close(lambda(&r), expected, 1e-6, &format!("{model} at {:.1}°", azimuth.to_degrees()));
        assert_eq!(base_state(&r), JointState::Sliding, "{model}");
    }
}

/// A column of n blocks b × b × h with μ > b/(n h): the whole column turns about the base
/// edge at λ* = b/(n h); the joints inside it stay closed.
#[test]
fn a_column_tips_as_one() {
    let (b, h, n) = (0.5, 1.0, 3);
    let blocks =
        (0..n).map(|k| cuboid(&format!("b{k}"), [0.0, 0.0, k as f64 * h], [b, b, (k + 1) as f64 * h])).collect();
    let mut s = on_base(blocks, b + 1.0, 0.8);
    s.loads.push(Load::horizontal(0.0, 1.0));
    let (_, r) = assess(&s, FrictionModel::Pyramid8);
    assert_close(lambda(&r), b / (n as f64 * h), 1e-6, "column");
    let m = r.mechanism.as_ref().unwrap();
    for i in &m.interfaces {
        let expected = if i.a == "base" || i.b == "base" { JointState::Hinging } else { JointState::Closed };
        assert_eq!(i.state, expected, "{} → {}", i.a, i.b);
    }
}

/// A horizontal point load P at height z on a side face: P* = W b / (2 z) (tipping) or μ W
/// (sliding), whichever is smaller.
#[test]
fn a_point_load_on_the_side_tips_or_slides() {
    let (b, h, z) = (0.5, 1.0, 0.8);
    let weight = 600.0 * G * b * b * h;
    for mu in [0.8, 0.2] {
        let mut s = block(b, h, mu);
        s.loads.push(Load::Point {
            block: "block".into(),
            point: Point3::new(0.0, b / 2.0, z),
            force: Vector3::new(1.0, 0.0, 0.0),
            kind: LoadKind::Live,
        });
        let (_, r) = assess(&s, FrictionModel::Cone);
        let expected = (weight * b / (2.0 * z)).min(mu * weight);
        assert_close(lambda(&r), expected, 1e-6 * expected, &format!("μ = {mu}"));
    }
}

/// A block overhanging its support, a vertical live point load at its tip:
/// P* = W (x_edge − x_c) / (x_tip − x_edge).
#[test]
fn a_cantilever_tips_over_its_edge() {
    let (edge, tip) = (0.6, 1.0);
    let mut s = Scene::new(
        "cantilever",
        vec![
            cuboid("base", [-1.0, -1.0, -1.0], [edge, 2.0, 0.0]).support(true),
            cuboid("arm", [0.0; 3], [tip, 1.0, 0.5]),
        ],
    );
    s.loads.push(Load::Point {
        block: "arm".into(),
        point: Point3::new(tip, 0.5, 0.5),
        force: Vector3::new(0.0, 0.0, -1.0),
        kind: LoadKind::Live,
    });
    let weight = 600.0 * G * tip * 1.0 * 0.5;
    let (_, r) = assess(&s, FrictionModel::Pyramid8);
    let expected = weight * (edge - 0.5) / (tip - edge);
    assert_close(lambda(&r), expected, 1e-6 * expected, "cantilever");
    assert_eq!(base_state(&r), JointState::Hinging);
}

/// Dead loads enter `analyze`: a dead point load on a block resting on one interface moves the
/// reaction's resultant by the lever rule, x_r = (W x_c + P a)/(W + P), and adds P to it; a dead
/// horizontal 0.6 g tips a block with b/h = 0.5 (0.4 g does not).
#[test]
fn dead_loads_move_the_reaction_by_the_lever_rule() {
    let (p, at) = (500.0, 1.6);
    let mut s = on_base(vec![cuboid("beam", [0.0; 3], [2.0, 1.0, 0.5])], 3.0, 0.8);
    s.loads.push(Load::Point {
        block: "beam".into(),
        point: Point3::new(at, 0.5, 0.5),
        force: Vector3::new(0.0, 0.0, -p),
        kind: LoadKind::Dead,
    });
    let a = analyze(&s, &settings(FrictionModel::Pyramid8)).unwrap();
    assert!(a.statics.stands);
    let weight = 600.0 * G * 2.0 * 0.5;
    let r = &a.statics.interfaces[0];
    assert_close(r.normal_force, weight + p, 1e-9, "the reaction carries W + P");
    let x = r.resultant_point.expect("a resultant")[0];
    assert_close(x, (weight * 1.0 + p * at) / (weight + p), 1e-9, "lever rule");

    for (g, stands) in [(0.6, false), (0.4, true)] {
        let mut s = block(0.5, 1.0, 0.8);
        s.loads.push(Load::Acceleration { accel: Vector3::new(g, 0.0, 0.0), kind: LoadKind::Dead });
        assert_eq!(analyze(&s, &AnalysisSettings::default()).unwrap().statics.stands, stands, "{g} g dead");
    }
}

/// A design that does not stand under its dead load gets the mechanism of its failure — a
/// block reaching past its support's edge tips (dead work 1, its joint hinging) — and the load
/// factor that would hold it: weight W 0.1 m beyond the edge, a live W λ at 0.25 m height
/// along +x: 0.1 + 0.25 λ ≤ 0, λ* = −0.4 (sliding at |λ| = μ = 0.84 and tipping back at |λ| = 2
/// come later).
#[test]
fn a_failing_design_gets_its_failure_mechanism() {
    let mut s = Scene::new(
        "overhang",
        vec![
            cuboid("base", [-1.0, -1.0, -1.0], [0.4, 2.0, 0.0]).support(true),
            cuboid("arm", [0.0; 3], [1.0, 1.0, 0.5]),
        ],
    );
    s.loads.push(Load::horizontal(0.0, 1.0));
    let st = settings(FrictionModel::Pyramid8);
    let a = analyze(&s, &st).unwrap();
    assert!(!a.statics.stands);
    let r = stability::assess(&a, &st.statics).unwrap();
    let Safety::DoesNotStand { load_factor: Some(l) } = r.safety else { panic!("{:?}", r.safety) };
    assert_close(l, -0.4, 1e-6, "λ* of a failing design");
    let m = r.mechanism.as_ref().expect("a failure mechanism");
    let asm = &a.assembly;
    let dead = m.work((1..2).map(|i| {
        let w = asm.gravity * asm.blocks[i].mass();
        (BlockId(i), [w.x, w.y, w.z, 0.0, 0.0, 0.0])
    }));
    assert_close(dead, 1.0, 1e-6, "the dead load does unit work");
    assert_eq!(base_state(&r), JointState::Hinging);
}

/// The same λ* in mm as in m, and with the density × 1e6 (an acceleration field scales with
/// the mass as the weight does).
#[test]
fn the_load_factor_is_unit_and_density_invariant() {
    let column = |unit: f64, density: f64| {
        let blocks = (0..3)
            .map(|k| {
                cuboid(&format!("b{k}"), [0.0, 0.0, k as f64 * unit], [0.5 * unit, 0.5 * unit, (k + 1) as f64 * unit])
            })
            .collect();
        let mut s = on_base(blocks, 1.5 * unit, 0.8);
        if unit != 1.0 {
            s.blocks[0] = cuboid("base", [-unit, -unit, -unit], [1.5 * unit, 1.5 * unit, 0.0]).support(true);
        }
        s.material.density = density;
        s.loads.push(Load::horizontal(0.3, 1.0));
        lambda(&assess(&s, FrictionModel::Cone).1)
    };
    let reference = column(1.0, 600.0);
    assert_close(column(1000.0, 600.0), reference, 1e-6, "mm");
    assert_close(column(1.0, 6e8), reference, 1e-6, "density × 1e6");
}

/// The worst horizontal direction of a square block: λ*(θ) = b / (h max(|cos θ|, |sin θ|)),
/// smallest (b/h) along the faces, √2 b/h on the diagonals.
#[test]
fn the_worst_direction_of_a_square_block_is_along_a_face() {
    let (b, h) = (0.5, 1.0);
    let s = block(b, h, 0.8);
    let st = settings(FrictionModel::Cone);
    let a = analyze(&s, &st).unwrap();
    let sweep = DirectionSettings { directions: 8, ..Default::default() };
    let found = stability::worst_direction(&a.assembly, &a.interfaces, &st.statics, &sweep, &|_, _| {}).unwrap();
    for (az, l) in found.azimuths.iter().zip(&found.load_factors) {
        let t = az.to_radians();
        assert_close(*l, b / (h * t.cos().abs().max(t.sin().abs())), 1e-6, &format!("λ* at {az}°"));
    }
    assert_close(found.worst_load_factor, b / h, 1e-6, "the worst");
    let k = (found.worst_azimuth / 90.0).round();
    assert!((found.worst_azimuth - 90.0 * k).abs() < 0.5, "along a face: {}", found.worst_azimuth);
    let field = stability::directions::with_horizontal_field(&a.assembly, found.worst_azimuth);
    check_duality(&field, &a.interfaces, &found.worst);
}

/// A worst direction between grid points: a block 1 × b_y × h (b_y = 0.5 < 1) tips most easily
/// across its narrow side, λ*(θ) = min(1 / (h |cos θ|), b_y / (h |sin θ|)), smallest (b_y / h)
/// at 90° and 270°. Seven azimuths (every 51.4°) miss both; the refinement (the root of the
/// mechanism's normal offset, bracketed by the grid) lands on one of them to 1e-3° with λ* to
/// 1e-6, in fewer solves than the limit, and its mechanism satisfies the work balance.
#[test]
fn the_refined_worst_direction_lands_between_grid_points() {
    let (by, h) = (0.5, 1.0);
    let s = on_base(vec![cuboid("block", [0.0; 3], [1.0, by, h])], 2.0, 0.8);
    let st = settings(FrictionModel::Cone);
    let a = analyze(&s, &st).unwrap();
    let sweep = DirectionSettings { directions: 7, ..Default::default() };
    let found = stability::worst_direction(&a.assembly, &a.interfaces, &st.statics, &sweep, &|_, _| {}).unwrap();
    let on_grid = found.load_factors.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(on_grid > by / h * (1.0 + 1e-3), "the grid misses the worst: {on_grid}");
    assert_close(found.worst_load_factor, by / h, 1e-6, "the worst");
    let off = (found.worst_azimuth - 90.0).rem_euclid(180.0);
    assert!(off.min(180.0 - off) < 1e-3, "across the narrow side: {}", found.worst_azimuth);
    assert!(found.solves > 7 && found.solves < 7 + sweep.refine as usize, "solves: {}", found.solves);
    let field = stability::directions::with_horizontal_field(&a.assembly, found.worst_azimuth);
    check_duality(&field, &a.interfaces, &found.worst);
}

/// The Armadillo vault (399 blocks) under a horizontal acceleration: a finite load factor whose
/// mechanism satisfies the duality invariant.
#[test]
fn the_armadillo_load_factor_satisfies_the_work_balance() {
    let mut s = voussoir::io::load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
    s.material.friction = 0.84;
    s.loads.push(Load::horizontal(0.0, 1.0));
    let (_, r) = assess(&s, FrictionModel::Pyramid8);
    let l = lambda(&r);
    assert!(l > 0.0 && l < 10.0, "λ* = {l}");
    let m = r.mechanism.as_ref().expect("a mechanism");
    // Its optimal face is a point (HiGHS's crossover agrees: docs/benchmarks.md).
    assert_eq!(m.uniqueness, voussoir::statics::Uniqueness::Unique);
}

/// Bad loads: one clear error each.
#[test]
fn bad_loads_are_named_errors() {
    let point = |block: &str, p: [f64; 3], f: [f64; 3]| Load::Point {
        block: block.into(),
        point: Point3::new(p[0], p[1], p[2]),
        force: Vector3::new(f[0], f[1], f[2]),
        kind: LoadKind::Live,
    };
    let cases = [
        (point("nope", [0.0; 3], [1.0, 0.0, 0.0]), "load #0: the scene has no block named 'nope'"),
        (point("block", [0.0; 3], [f64::NAN, 0.0, 0.0]), "is not finite"),
        (point("block", [0.0, 0.0, 50.0], [1.0, 0.0, 0.0]), "outside block 'block'"),
    ];
    for (load, message) in cases {
        let mut s = block(0.5, 1.0, 0.8);
        s.loads.push(load);
        let e = analyze(&s, &AnalysisSettings::default()).unwrap_err();
        assert!(e.to_string().contains(message), "{e}");
        assert!(matches!(e, voussoir::pipeline::AnalysisError::Model(ModelError::BadLoad { index: 0, .. })));
    }
    // A load on a support is ignored with a warning; no live load left: no load factor.
    let mut s = block(0.5, 1.0, 0.8);
    s.loads.push(point("base", [0.0, 0.0, -0.5], [1.0, 0.0, 0.0]));
    let a = analyze(&s, &AnalysisSettings::default()).unwrap();
    assert!(a.assembly.warnings.iter().any(|w| w.to_string().contains("load #0 on support block 'base' ignored")));
    let e = stability::assess(&a, &StaticsSettings::default()).unwrap_err();
    assert_eq!(e, RobustnessError::NoLiveLoad);
    assert!(a.assembly.loads.iter().all(|l| l.live == [0.0; 6]));
}

/// Loads survive the scene JSON: written and read back the same.
#[test]
fn loads_round_trip_through_the_scene_json() {
    let mut s = block(0.5, 1.0, 0.8);
    s.loads.push(Load::Point {
        block: "block".into(),
        point: Point3::new(0.0, 0.25, 0.8),
        force: Vector3::new(1.0, 2.0, 3.0),
        kind: LoadKind::Dead,
    });
    s.loads.push(Load::horizontal(0.5, 0.2));
    let text = voussoir::io::scene_json::scene_to_string(&s);
    let back = voussoir::io::scene_json::scene_from_str(std::path::Path::new("x.json"), &text).unwrap();
    assert_eq!(back.loads, s.loads);
    let e = voussoir::io::scene_json::scene_from_str(
        std::path::Path::new("x.json"),
        &text.replace("\"acceleration\"", "\"block\": \"block\", \"acceleration\""),
    )
    .unwrap_err();
    assert!(e.to_string().contains("load #1: give either"), "{e}");
}

/// Invariant: the two solvers of the load factor agree — the structured backend's bordered
/// λ ≥ 0 column and clarabel's free λ — on every model (a block tipping, sliding, diagonal)
/// and on the Armadillo, to 1e-6 relative.
#[test]
fn both_backends_give_the_same_load_factor() {
    use voussoir::statics::{component_load_factor, components, standing_load_factor};
    let mut cases: Vec<(Scene, FrictionModel)> = Vec::new();
    for model in [FrictionModel::Cone, FrictionModel::Pyramid8, FrictionModel::Box4] {
        for (b, h, mu, az) in [(0.5, 1.0, 0.8, 180.0f64), (0.5, 1.0, 0.2, 0.0), (1.0, 0.5, 0.3, 30.0)] {
            let mut s = block(b, h, mu);
            s.loads.push(Load::horizontal(az.to_radians(), 1.0));
            cases.push((s, model));
        }
    }
    let mut arm = voussoir::io::load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
    arm.material.friction = 0.84;
    arm.loads.push(Load::horizontal(0.7, 1.0));
    cases.push((arm, FrictionModel::Pyramid8));
    for (s, model) in cases {
        let st = settings(model);
        let a = analyze(&s, &st).unwrap();
        let mu = s.material.friction;
        for c in components(&a.assembly, &a.interfaces) {
            let structured = standing_load_factor(&a.assembly, &a.interfaces, &c, mu, &st.statics).lambda;
            let clarabel = component_load_factor(&a.assembly, &a.interfaces, &c, mu, &st.statics).lambda;
            assert_close(structured, clarabel, 1e-6 * clarabel.abs(), &format!("{} {model}", s.name));
        }
    }
}

/// A running-bond wall on the ground (6 courses × 8 bricks, μ = 0.6) pushed by 1 g at 30°
/// slides as a whole on the ground: the base friction forces lie on the 8-sided pyramid's
/// facet whose normal is at 45° (15° from the load), so λ* = μ / cos 15° exactly. Invariant:
/// the statics' default backend reaches it to 1e-7 relative with a full-accuracy status.
#[test]
fn a_wall_sliding_on_the_ground_reaches_mu_over_cos_15() {
    let mut s = voussoir::model::builtin("wall?courses=6&bricks=8").unwrap();
    s.material.friction = 0.6;
    s.loads.push(Load::horizontal(30f64.to_radians(), 1.0));
    let (_, r) = assess(&s, FrictionModel::Pyramid8);
    let expected = 0.6 / 15f64.to_radians().cos();
    assert_close(lambda(&r), expected, 1e-7 * expected, "λ* of the sliding wall");
    assert_eq!(r.status, voussoir::statics::SolverStatus::Solved);
    assert_eq!(base_state(&r), JointState::Sliding);
}
