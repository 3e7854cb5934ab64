//! Make it stand by mass (`synthesis::infill`): per-block densities within bounds.
//!
//! The scene: a plank A (x ∈ [−0.8, 1.2], 0.2 thick) on a support whose edge is x = 0, a tail
//! block B (x ∈ [−0.8, 0], 0.125 thick) on the plank's back. About the edge, A's weight turns
//! it over with arm 0.2 and B's holds it back with arm 0.4: with V_A = 0.4, V_B = 0.1 it stands
//! exactly when 0.04 ρ_B ≥ 0.08 ρ_A, i.e. ρ_B / ρ_A ≥ 2 (the lever rule).
//!
//! Invariants: the lightest densities within [150, 600] are ρ_A = 150, ρ_B = 300 (1e-9
//! relative); with ρ_B ≤ 250 none stands, and the mechanism returned does positive work at
//! every corner of the bounds (the least of it 1 N·m); the answer does not depend on the unit
//! of length; the robust design's load factor is the one its densities carry when analysed
//! again, and both drop-test engines keep it standing where the uniform design falls.

use crate::common::*;
use voussoir::dynamics::{DropSettings, Engine, drop_test};
use voussoir::geometry::Vector3;
use voussoir::model::Scene;
use voussoir::pipeline::AnalysisSettings;
use voussoir::stability::{self, Safety};
use voussoir::statics::Verdict;
use voussoir::synthesis::{InfillObjective, InfillOutcome, InfillReport, InfillSettings, infill};

/// The overhang of the module docs, lengths times `unit` (1: metres; 1000: millimetres with
/// gravity in mm/s²).
fn overhang(unit: f64) -> Scene {
    let c = |name: &str, lo: [f64; 3], hi: [f64; 3]| cuboid(name, lo.map(|v| v * unit), hi.map(|v| v * unit));
    let mut s = Scene::new(
        "overhang",
        vec![
            c("support", [-1.0, 0.0, -1.0], [0.0, 1.0, 0.0]).support(true),
            c("plank", [-0.8, 0.0, 0.0], [1.2, 1.0, 0.2]),
            c("tail", [-0.8, 0.0, 0.2], [0.0, 1.0, 0.325]),
        ],
    );
    s.gravity = Vector3::new(0.0, 0.0, -9.81 * unit);
    s
}

fn run_infill(scene: &Scene, settings: &InfillSettings) -> InfillReport {
    infill(scene, &AnalysisSettings::default(), settings).expect("infill runs")
}

fn density(r: &InfillReport, block: &str) -> f64 {
    r.blocks.iter().find(|b| b.block == block).expect("a free block").after
}

fn range(lo: f64, hi: f64) -> InfillSettings {
    InfillSettings { range: Some((lo, hi)), ..Default::default() }
}

#[test]
fn the_lightest_densities_meet_the_lever_rule() {
    let scene = overhang(1.0);
    assert_eq!(run(&scene, &AnalysisSettings::default()).statics.verdict, Verdict::NeedsTension, "uniform tips");
    let r = run_infill(&scene, &range(150.0, 600.0));
    assert_eq!(r.outcome, InfillOutcome::Stands);
    assert_eq!(r.verdict_before, Verdict::NeedsTension, "the design's statics, solved beside the densities");
    assert_close(density(&r, "plank"), 150.0, 150.0 * 1e-9, "plank at its lower bound");
    assert_close(density(&r, "tail"), 300.0, 300.0 * 1e-9, "tail at twice the plank");
    assert_close(r.mass_after, 0.4 * 150.0 + 0.1 * 300.0, 90.0 * 1e-9, "mass of the infilled design");
    assert_eq!(r.solves, 1);
}

#[test]
fn no_admissible_density_is_certified_by_a_mechanism() {
    let (lo, hi) = (150.0, 250.0);
    let r = run_infill(&overhang(1.0), &range(lo, hi));
    assert_eq!(r.outcome, InfillOutcome::Impossible);
    assert!(r.design.is_none() && r.verdict_after.is_none());
    let m = r.mechanism.as_ref().expect("a mechanism");
    // Work of gravity on the blocks' centroids, at a corner (ρ_A, ρ_B) of the bounds.
    let down = |name: &str| -m.blocks.iter().find(|b| b.block == name).map_or(0.0, |b| b.translation[2]);
    let work = |ra: f64, rb: f64| 9.81 * (ra * 0.4 * down("plank") + rb * 0.1 * down("tail"));
    let corners = [work(lo, lo), work(lo, hi), work(hi, lo), work(hi, hi)];
    assert!(corners.iter().all(|&w| w > 0.0), "positive work at every corner: {corners:?}");
    let least = corners.iter().copied().fold(f64::INFINITY, f64::min);
    assert_close(least, 1.0, 1e-6, "least work over the bounds, normalised");
    // The least work lies at (ρ_A, ρ_B) = (lo, hi): 9.81 θ (0.08·150 − 0.04·250) = 2·9.81 θ.
    assert_eq!(least, corners[1]);
    assert!(r.least_work > 0.0);
}

#[test]
fn densities_do_not_depend_on_the_unit_of_length() {
    let m = run_infill(&overhang(1.0), &range(150.0, 600.0));
    let mm = run_infill(&overhang(1000.0), &range(150.0, 600.0));
    for b in ["plank", "tail"] {
        assert_close(density(&mm, b), density(&m, b), density(&m, b) * 1e-9, b);
    }
}

/// A bad range is one error naming it.
#[test]
fn a_bad_range_is_an_error() {
    for (lo, hi) in [(0.0, 600.0), (700.0, 600.0), (150.0, f64::INFINITY)] {
        let e = infill(&overhang(1.0), &AnalysisSettings::default(), &range(lo, hi)).unwrap_err();
        assert!(e.to_string().contains("density range"), "{e}");
    }
}

#[test]
fn the_robust_design_carries_its_load_factor_and_stands_in_both_engines() {
    let scene = overhang(1.0);
    let settings = InfillSettings { objective: InfillObjective::Robust, azimuth: Some(0.0), ..range(150.0, 600.0) };
    let r = run_infill(&scene, &settings);
    assert_eq!(r.outcome, InfillOutcome::Stands);
    assert_eq!(r.verdict_after, Some(Verdict::Stands));
    let lambda = r.load_factor.expect("a load factor");
    let design = r.design.as_ref().expect("a design");
    // Analysed again under a horizontal field along +x.
    let analysis = run(design, &AnalysisSettings::default());
    let settings = voussoir::statics::StaticsSettings::default();
    let field = stability::with_horizontal_field(&analysis.assembly, 0.0);
    let again = stability::assess_parts(&field, &analysis.interfaces, true, &settings).expect("load factor");
    let Safety::Collapses { load_factor } = again.safety else { panic!("{:?}", again.safety) };
    assert!(load_factor >= lambda * (1.0 - 1e-6), "{load_factor} carries {lambda}");
    assert!(load_factor <= lambda * (1.0 + 3e-4), "{load_factor} is λ* to the precision 1e-4 ({lambda})");
    for engine in [Engine::Rapier, Engine::Exact] {
        let drop = DropSettings { engine, ..Default::default() };
        let uniform = drop_test(&assembly(&scene), &drop).expect("drop test");
        assert!(!uniform.stands, "{engine}: the uniform design tips");
        let infilled = drop_test(&analysis.assembly, &drop).expect("drop test");
        assert!(infilled.stands, "{engine}: the infilled design stands ({:?})", infilled.max_rotation);
    }
}

/// A 2 × 1 × 1 block (x ∈ [0, 2]) on a support whose edge is x = 0.8: uniform, its centroid
/// (x = 1) is past the edge. With octants the left cells (centroids x = 0.5) hold it back and the
/// right ones (x = 1.5) turn it over: it stands when 0.3 Σ_left ρ ≥ 0.7 Σ_right ρ, so the
/// lightest fill puts the right cells at the lower bound and the left ones at 7/3 of that in
/// sum, which brings the centroid exactly over the edge.
#[test]
fn cells_move_the_centroid_over_the_support() {
    let mut scene = Scene::new(
        "cantilever",
        vec![
            cuboid("support", [-1.0, 0.0, -1.0], [0.8, 1.0, 0.0]).support(true),
            cuboid("block", [0.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
        ],
    );
    scene.material.friction = 0.8;
    assert_eq!(run(&scene, &AnalysisSettings::default()).statics.verdict, Verdict::NeedsTension);
    let lo = 100.0;
    let r = run_infill(&scene, &InfillSettings { cells: 2, ..range(lo, 600.0) });
    assert_eq!(r.outcome, InfillOutcome::Stands);
    let cells = &r.blocks[0].cells;
    assert_eq!(cells.len(), 8);
    let (left, right): (Vec<_>, Vec<_>) = cells.iter().enumerate().partition(|(c, _)| c % 2 == 0);
    let sum = |v: &[(usize, &f64)]| v.iter().map(|(_, d)| **d).sum::<f64>();
    assert_close(sum(&right), 4.0 * lo, 4.0 * lo * 1e-9, "right cells at the lower bound");
    assert_close(sum(&left), 4.0 * lo * 7.0 / 3.0, lo * 1e-8, "left cells by the moment balance");
    let design = r.design.as_ref().expect("a design");
    let a = assembly(&voussoir::history::resolve(design, &Default::default(), &mut Default::default()).unwrap().0);
    assert_close(a.blocks[1].mass.centroid.x, 0.8, 1e-9, "centroid over the edge");
    assert_close(a.blocks[1].mass(), r.mass_after, 1e-9 * r.mass_after, "the design's mass is the report's");
    assert_eq!(r.verdict_after, Some(Verdict::Stands));
}

/// Cell densities that are not k³ numbers, or negative, are one error naming the block.
#[test]
fn bad_cell_densities_are_errors() {
    for (cells, why) in [(vec![1.0; 7], "not k³"), (vec![-1.0; 8], "negative"), (vec![0.0; 8], "all are zero")] {
        let mut scene = overhang(1.0);
        scene.blocks[1].density = Some(voussoir::model::Density::Cells(cells));
        let e = voussoir::model::Assembly::new(&scene, &Default::default()).unwrap_err().to_string();
        assert!(e.contains("'plank'") && e.contains(why), "{e}");
    }
}

/// The scene's own bounds per piece take precedence: with the tail held to [150, 250] in the
/// scene, the range 150–600 given for all cannot make it stand (ρ_tail / ρ_plank ≥ 2 needs
/// ρ_plank ≤ 125 < 150); a bound on a name that is no piece, or a bad bound, is one error naming it.
#[test]
fn the_scene_s_own_bounds_per_piece_hold() {
    let mut scene = overhang(1.0);
    scene.density_ranges.insert("tail".into(), [150.0, 250.0]);
    let r = run_infill(&scene, &range(150.0, 600.0));
    assert_eq!(r.outcome, InfillOutcome::Impossible);
    scene.density_ranges.insert("tail".into(), [150.0, 400.0]);
    let r = run_infill(&scene, &range(100.0, 600.0));
    assert_close(density(&r, "plank"), 100.0, 1e-7, "plank at the settings' lower bound");
    assert_close(density(&r, "tail"), 200.0, 2e-7, "tail at twice it, within its own bounds");
    scene.density_ranges.insert("nowhere".into(), [1.0, 2.0]);
    let e = infill(&scene, &AnalysisSettings::default(), &range(150.0, 600.0)).unwrap_err().to_string();
    assert!(e.contains("'nowhere'"), "{e}");
    scene.density_ranges.remove("nowhere");
    scene.density_ranges.insert("tail".into(), [300.0, 200.0]);
    let e = infill(&scene, &AnalysisSettings::default(), &range(150.0, 600.0)).unwrap_err().to_string();
    assert!(e.contains("'tail'") && e.contains("density range"), "{e}");
}

/// The structured solver takes the density problem (each density eliminated into its own
/// block's rows of the reduced system) and agrees with clarabel on it. The thin arch (n 15,
/// t 0.07), which needs tension at uniform density, made to stand by its lightest densities
/// within [150, 600] kg/m³ with octant cells (8 per block, so the centroids move): both
/// solved (each to the reduced tolerance here: the gap stalls near 1e-8 in both), the same
/// least mass to 1e-7 relative, each cell's density within 1e-4 of the range, and each answer
/// in equilibrium (residual below 1e-9 of the arch's weight).
#[test]
fn both_solvers_find_the_same_lightest_densities() {
    use voussoir::geometry::cells::grid;
    use voussoir::statics::{Backend, DensityCell, DensityGoal, SolverStatus, component_densities, components};
    let a = run(&voussoir::model::builtin("arch?n=15&t=0.07").unwrap(), &AnalysisSettings::default());
    assert_eq!(a.statics.verdict, Verdict::NeedsTension, "uniform needs tension");
    let comps = components(&a.assembly, &a.interfaces);
    assert_eq!(comps.len(), 1);
    let comp = &comps[0];
    let cells: Vec<DensityCell> =
        comp.blocks
            .iter()
            .enumerate()
            .flat_map(|(i, &b)| {
                let mesh = &a.assembly.block(b).mesh;
                grid(mesh, 2, a.assembly.tolerances.weld).into_iter().filter(|c| c.volume > 0.0).map(move |c| {
                    DensityCell { block: i, volume: c.volume, centroid: c.centroid, lo: 150.0, hi: 600.0 }
                })
            })
            .collect();
    let weight: f64 = comp.blocks.iter().map(|&b| a.assembly.block(b).mass()).sum::<f64>() * 9.81;
    let statics = AnalysisSettings::default().statics.resolved(&a.assembly);
    let mu = a.assembly.material.friction;
    let solve = |backend: Backend| {
        let settings = voussoir::statics::StaticsSettings { backend, ..statics.clone() };
        let out = component_densities(&a.assembly, &a.interfaces, comp, mu, &settings, &cells, DensityGoal::Lightest);
        assert_eq!(out.backend, backend, "the density problem ran on the solver asked for");
        let solved = matches!(out.status, SolverStatus::Solved | SolverStatus::AlmostSolved);
        assert!(solved, "{backend}: {:?}", out.status);
        assert!(out.residual < 1e-9 * weight, "{backend}: residual {} N", out.residual);
        out
    };
    let (s, c) = (solve(Backend::Structured), solve(Backend::Clarabel));
    let mass = |d: &[f64]| d.iter().zip(&cells).map(|(r, c)| r * c.volume).sum::<f64>();
    let (ms, mc) = (mass(&s.densities), mass(&c.densities));
    assert_close(ms, mc, 1e-7 * mc, "least mass");
    assert!(ms < mass(&vec![600.0; cells.len()]) * 0.99, "a lighter design than the solid one");
    for (k, (x, y)) in s.densities.iter().zip(&c.densities).enumerate() {
        assert_close(*x, *y, 1e-4 * 450.0, &format!("cell {k}"));
    }
}

/// Invariant: the density problem converges like the design's own statics — the Armadillo's
/// 366 block densities within [150, 600] kg/m³ (one component) take at most two more
/// interior-point iterations than its analysis' strict QP (12). The density variables are
/// scaled so the mass gradient has unit norm; unscaled (a gradient of norm ~1/√366) the bound
/// slacks blocked the steps at 0.05–0.4 for ten iterations, 19 in all.
#[test]
fn the_armadillo_s_densities_converge_like_its_statics() {
    use voussoir::statics::{DensityCell, DensityGoal, component_densities, components};
    let mut scene = voussoir::io::load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
    scene.material.friction = 0.84;
    let settings = AnalysisSettings::default();
    let a = run(&scene, &settings);
    let comps = components(&a.assembly, &a.interfaces);
    assert_eq!(comps.len(), 1, "the Armadillo is one component");
    let cells: Vec<DensityCell> = comps[0]
        .blocks
        .iter()
        .enumerate()
        .map(|(i, &b)| {
            let mass = &a.assembly.block(b).mass;
            DensityCell { block: i, volume: mass.volume, centroid: mass.centroid, lo: 150.0, hi: 600.0 }
        })
        .collect();
    let out = component_densities(
        &a.assembly,
        &a.interfaces,
        &comps[0],
        0.84,
        &settings.statics,
        &cells,
        DensityGoal::Lightest,
    );
    assert!(!out.densities.is_empty(), "{:?}", out.status);
    assert!(
        out.iterations <= a.statics.solver.iterations + 2,
        "densities in {} iterations against the statics' {}",
        out.iterations,
        a.statics.solver.iterations
    );
}
