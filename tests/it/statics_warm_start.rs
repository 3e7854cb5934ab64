//! Invariant: with warm starts (`StaticsSettings::warm_start`, the editor's setting) a pipeline
//! run after an edit gives a cold analysis's answer to the solver's tolerance — the same
//! verdict, the same minimum tension and friction excess (to 1e-7 W, W the free weight), the
//! same forces (the strict QP is strictly convex: its forces are unique) to 1e-5 W, an
//! equilibrium residual at round-off (1e-9 W) — and takes fewer iterations when the edit keeps the layout. A failing
//! design (the relaxed stages start cold) and an edit too large for its start (a standing stack
//! made to fail) give the cold answers. The fall-back of a warm run that does not end solved is
//! tested on the solver (src/statics/backend_tests.rs).

use voussoir::model::{Cut, Scene, builtin};
use voussoir::pipeline::{Analysis, AnalysisSettings, Pipeline, analyze};
use voussoir::statics::Verdict;

fn warm_settings() -> AnalysisSettings {
    let mut settings = AnalysisSettings::default();
    settings.statics.warm_start = true;
    settings
}

/// The largest difference of any vertex force component between two analyses (N).
fn force_difference(a: &Analysis, b: &Analysis) -> f64 {
    assert_eq!(a.statics.interfaces.len(), b.statics.interfaces.len());
    let mut worst = 0.0f64;
    for (ia, ib) in a.statics.interfaces.iter().zip(&b.statics.interfaces) {
        assert_eq!(ia.vertices.len(), ib.vertices.len());
        for (va, vb) in ia.vertices.iter().zip(&ib.vertices) {
            for (x, y) in [
                (va.compression, vb.compression),
                (va.tension, vb.tension),
                (va.friction_u, vb.friction_u),
                (va.friction_v, vb.friction_v),
            ] {
                worst = worst.max((x - y).abs());
            }
        }
    }
    worst
}

/// `warm` (a pipeline run) against a cold analysis of the same scene. The forces, where unique
/// (a standing design), are held against a solve to 1e-10 (100× tighter): within 1e-5 W. What
/// a gap of 1e-8 allows a strictly convex objective of unit curvature is √(2·1e-8) ≈ 1.4e-4 W;
/// the cold solves come within 1.0e-6–1.2e-6 W on the wall, 1.4e-6 W on the arch near its
/// limit (clarabel's forces are 4.5e-7 W from the structured solver's on the wall).
fn assert_as_cold(warm: &Analysis, scene: &Scene, what: &str) -> Analysis {
    let cold = analyze(scene, &AnalysisSettings::default()).unwrap();
    let mut tight = AnalysisSettings::default();
    tight.statics.solver_tolerance = 1e-10;
    let reference = analyze(scene, &tight).unwrap();
    let (ws, cs) = (&warm.statics, &cold.statics);
    let w = cs.free_weight;
    assert_eq!(ws.verdict, cs.verdict, "{what}");
    // In units of the weight W (the ratios are minima / W).
    let dt = (ws.tension_ratio - cs.tension_ratio).abs();
    let df = (ws.friction_excess_ratio - cs.friction_excess_ratio).abs();
    let forces = force_difference(warm, &reference);
    let cold_forces = force_difference(&cold, &reference);
    assert!(dt <= 1e-7 && df <= 1e-7, "{what}: minima differ by {dt:e} / {df:e} W");
    if cs.verdict == Verdict::Stands {
        assert!(
            forces <= 1e-5 * w,
            "{what}: forces {forces:e} N from the 1e-10 solve's (the cold solve's: {cold_forces:e} N, W = {w:e} N)"
        );
    }
    assert!(ws.solver.residual <= 1e-9 * w, "{what}: residual {:e} N", ws.solver.residual);
    cold
}

#[test]
fn moving_a_cut_in_a_wall_gives_the_cold_answer_in_fewer_iterations() {
    let wall = builtin("wall?courses=10&bricks=10").unwrap();
    let brick = &wall.blocks[wall.blocks.len() / 2];
    let (name, c0) = (brick.name.clone(), brick.mesh.aabb().center());
    let mut pipeline = Pipeline::new();
    let settings = warm_settings();
    let (mut warm_iterations, mut cold_iterations) = (0, 0);
    for (k, dx) in [0.0, 0.01, 0.0, 0.01, 0.02, 0.03].into_iter().enumerate() {
        let mut scene = wall.clone();
        scene.cuts.push(Cut::plane([c0.x + dx, c0.y, c0.z], [1.0, 0.0, 0.0]).on(&name));
        let warm = pipeline.run(&scene, &settings).unwrap();
        let cold = assert_as_cold(&warm, &scene, &format!("wall, cut at +{dx} m"));
        if k > 0 {
            warm_iterations += warm.statics.solver.iterations;
            cold_iterations += cold.statics.solver.iterations;
        }
    }
    assert!(warm_iterations * 3 < cold_iterations * 2, "warm {warm_iterations} vs cold {cold_iterations} iterations");
}

/// `scene` with block `k`'s density multiplied by `factor`.
fn heavier(scene: &Scene, k: usize, factor: f64) -> Scene {
    let mut s = scene.clone();
    let density = match s.blocks[k].density {
        Some(voussoir::model::Density::Uniform(d)) => d,
        _ => s.material.density,
    };
    s.blocks[k].density = Some((density * factor).into());
    s
}

#[test]
fn a_failing_arch_edited_gives_the_cold_minima() {
    let arch = builtin("arch?n=21&t=0.08").unwrap();
    let mut pipeline = Pipeline::new();
    let settings = warm_settings();
    for (k, factor) in [(5, 1.0), (5, 1.5), (5, 2.0), (6, 2.0), (6, 1.0)] {
        let scene = heavier(&arch, k, factor);
        let warm = pipeline.run(&scene, &settings).unwrap();
        let cold = assert_as_cold(&warm, &scene, &format!("arch t 0.08, block {k} ×{factor}"));
        assert_ne!(cold.statics.verdict, Verdict::Stands);
    }
}

#[test]
fn a_standing_stack_made_to_fail_gives_the_cold_answers() {
    // Six blocks overhanging by 0.9 of the harmonic limit: a heavy enough top block moves the
    // centre of mass of the top two beyond the third's edge (s > 2/3).
    let stack = builtin("harmonic?n=6&s=0.9").unwrap();
    let top = stack.blocks.len() - 1;
    let mut pipeline = Pipeline::new();
    let settings = warm_settings();
    let mut verdicts = Vec::new();
    for factor in [1.0, 1.1, 10.0, 12.0, 1.0] {
        let scene = heavier(&stack, top, factor);
        let warm = pipeline.run(&scene, &settings).unwrap();
        let cold = assert_as_cold(&warm, &scene, &format!("harmonic stack, top ×{factor}"));
        verdicts.push(cold.statics.verdict);
    }
    assert_eq!(verdicts[..2], [Verdict::Stands, Verdict::Stands]);
    assert_eq!(verdicts[2..4], [Verdict::NeedsTension, Verdict::NeedsTension]);
}
