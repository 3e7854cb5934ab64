//! Invariant: extreme but valid inputs — sizes 1e-3 … 1e3 m, densities 1e-3 … 1e6, slivers of
//! aspect 1e4, neighbouring masses 1e6 apart, faces 1e-9 off coplanar, interfaces with 1000
//! vertices — never panic, always end with a status, keep the residual ≤ 1e-8 W when solved,
//! and give the same verdict as the nominal case.

use crate::common::*;
use voussoir::geometry::Mesh;
use voussoir::model::{Block, Scene, builtin};
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::{SolverStatus, StaticsResult, Verdict};

fn solved(r: &StaticsResult, what: &str) {
    assert!(matches!(r.solver.status, SolverStatus::Solved | SolverStatus::AlmostSolved), "{what}: {:?}", r.solver);
    assert!(r.solver.residual <= 1e-8 * r.free_weight, "{what}: residual {:e} W", r.solver.residual / r.free_weight);
}

#[test]
fn sizes_from_a_millimetre_to_a_kilometre() {
    for (t, verdict) in [(0.13, Verdict::Stands), (0.09, Verdict::NeedsTension)] {
        let mut ratios = Vec::new();
        for r in [1e-3, 1.0, 1e3] {
            let spec = format!("arch?n=16&r={r}&t={}&d={}", t * r, 0.5 * r);
            let res = run(&builtin(&spec).unwrap(), &AnalysisSettings::default()).statics;
            solved(&res, &spec);
            assert_eq!(res.verdict, verdict, "{spec}");
            ratios.push(res.tension_ratio);
        }
        for x in &ratios {
            assert_close(*x, ratios[1], 1e-6 * ratios[1].max(1e-6), "tension ratio independent of size");
        }
    }
}

#[test]
fn densities_from_1e_minus_3_to_1e6() {
    for density in [1e-3, 1.0, 600.0, 1e6] {
        for (spec, verdict) in [("arch?n=16&t=0.13", Verdict::Stands), ("harmonic?n=5&s=1.01", Verdict::NeedsTension)] {
            let mut s = builtin(spec).unwrap();
            s.material.density = density;
            let r = run(&s, &AnalysisSettings::default()).statics;
            solved(&r, spec);
            assert_eq!(r.verdict, verdict, "{spec} at density {density}");
        }
    }
}

#[test]
fn slivers_of_aspect_1e4() {
    // Plates 1 × 1 × 1e-4 stacked five high on a base, each shifted by 0.1.
    let mut blocks = vec![cuboid("base", [-1.0, -1.0, -1.0], [2.0, 2.0, 0.0]).support(true)];
    for k in 0..5 {
        let (x, z) = (0.1 * k as f64, 1e-4 * k as f64);
        blocks.push(cuboid(&format!("plate{k}"), [x, 0.0, z], [x + 1.0, 1.0, z + 1e-4]));
    }
    let an = run(&Scene::new("slivers", blocks), &AnalysisSettings::default());
    assert_eq!(an.interfaces.len(), 5);
    solved(&an.statics, "slivers");
    // The top four plates' centroid is at x = 0.75 over the first plate (x ∈ [0, 1]): stands.
    assert_eq!(an.statics.verdict, Verdict::Stands);
    // Upright slivers: 1e-4 thick walls side by side, one interface each.
    let walls: Vec<Block> = (0..4)
        .map(|k| cuboid(&format!("w{k}"), [1e-4 * k as f64, 0.0, 0.0], [1e-4 * (k + 1) as f64, 1.0, 1.0]))
        .collect();
    let mut s = Scene::new("upright", walls);
    s.ground = true;
    let an = run(&s, &AnalysisSettings::default());
    assert_eq!(an.interfaces.len(), 3 + 4, "three joints and four ground contacts");
    solved(&an.statics, "upright slivers");
    assert_eq!(an.statics.verdict, Verdict::Stands);
}

#[test]
fn masses_a_million_apart() {
    let mut heavy = cube("heavy", [0.0, 0.0, 1.0], 1.0);
    heavy.density = Some(1e6.into());
    let mut light = cube("light", [0.0, 0.0, 0.0], 1.0);
    light.density = Some(1.0.into());
    let base = cuboid("base", [-1.0, -1.0, -1.0], [2.0, 2.0, 0.0]).support(true);
    let r = run(&Scene::new("mass ratio", vec![base, light, heavy]), &AnalysisSettings::default()).statics;
    solved(&r, "mass ratio");
    assert_eq!(r.verdict, Verdict::Stands);
    let top = r.interfaces.iter().find(|i| i.b == "heavy").unwrap();
    assert_close(top.normal_force, 1e6 * 9.81, 1e-6 * r.free_weight, "the heavy block weight");
    // A light block overhanging a little on a heavy one still needs tension, exactly as much.
    let mut light_top = cube("light_top", [0.75, 0.0, 1.0], 1.0);
    light_top.density = Some(1.0.into());
    let mut heavy_low = cube("heavy_low", [0.0, 0.0, 0.0], 1.0);
    heavy_low.density = Some(1e6.into());
    let base = cuboid("base", [-1.0, -1.0, -1.0], [2.0, 2.0, 0.0]).support(true);
    let r = run(&Scene::new("overhang", vec![base, heavy_low, light_top]), &AnalysisSettings::default()).statics;
    solved(&r, "overhang");
    assert_eq!(r.verdict, Verdict::NeedsTension);
    // Minimum tension = the light block's weight (see the offset-cube closed form), relative to
    // a total weight 1e6 times larger: a 1e-6 W failure, found because the stand tolerance is
    // relative to the lightest block.
    assert_close(r.tension_ratio, 1.0 / (1e6 + 1.0), 1e-9, "tension / W");
}

#[test]
fn faces_a_nanometre_off_coplanar() {
    for dz in [1e-9, -1e-9] {
        let s = Scene::new(
            "gap",
            vec![cube("a", [0.0, 0.0, 0.0], 1.0).support(true), cube("b", [0.0, 0.0, 1.0 + dz], 1.0)],
        );
        let an = run(&s, &AnalysisSettings::default());
        assert_eq!(an.interfaces.len(), 1, "dz = {dz}");
        assert_close(an.interfaces[0].area, 1.0, 1e-9, "area");
        solved(&an.statics, "nm gap");
        assert_eq!(an.statics.verdict, Verdict::Stands);
    }
}

#[test]
fn interface_with_a_thousand_vertices() {
    // Two regular 1000-gon prisms (radius 1) stacked: one interface with 1000 vertices.
    let ring: Vec<[f64; 2]> = (0..1000)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 1000.0;
            [t.cos(), t.sin()]
        })
        .collect();
    let base = Block::new("base", Mesh::extrude_z(&ring, -0.5, 0.0)).support(true);
    let top = Block::new("drum", Mesh::extrude_z(&ring, 0.0, 0.5));
    let an = run(&Scene::new("drums", vec![base, top]), &AnalysisSettings::default());
    assert_eq!(an.interfaces.len(), 1);
    assert!(an.interfaces[0].polygon.len() >= 990, "{} vertices", an.interfaces[0].polygon.len());
    let area = 0.5 * 1000.0 * (std::f64::consts::TAU / 1000.0).sin();
    assert_close(an.interfaces[0].area, area, 1e-9, "1000-gon area");
    solved(&an.statics, "1000-gon");
    assert_eq!(an.statics.verdict, Verdict::Stands);
    let p = an.statics.interfaces[0].resultant_point.unwrap();
    assert!(p[0].abs() < 1e-6 && p[1].abs() < 1e-6, "resultant at the axis: {p:?}");
}

#[test]
fn ten_thousand_block_wall() {
    // 100 courses × 100 bricks (10 050 blocks, 29 850 interfaces): one component, one solve
    // (≈ 35 s: the largest test, kept because scale is where solvers break).
    let an = run(&builtin("wall?courses=100&bricks=100").unwrap(), &AnalysisSettings::default());
    assert_eq!(an.assembly.blocks.len(), 10_051);
    assert_eq!(an.interfaces.len(), 29_850);
    solved(&an.statics, "10 000-block wall");
    assert_eq!(an.statics.verdict, Verdict::Stands);
}
