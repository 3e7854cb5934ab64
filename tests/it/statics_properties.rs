//! Invariants that hold on any valid assembly, checked on random members of the built-in
//! families (arches, walls, stacks, slopes, domes with random proportions, μ and friction model):
//! 1. the equilibrium residual of a solved design is below 1e-8 of its weight;
//! 2. both backends (structured, clarabel) give the same verdict, and the same minima (to 1e-6
//!    of W plus their stated relative accuracy), unless a minimum sits within 10× the stand tolerance of the verdict's threshold;
//! 3. the same design in millimetres gives the same verdict and ratios;
//! 4. a warm-started re-solve after an edit gives the cold solve's verdict and ratios.

use crate::common::*;
use proptest::prelude::*;
use voussoir::model::{Scene, builtin};
use voussoir::pipeline::{AnalysisSettings, Pipeline};
use voussoir::statics::{Backend, FrictionModel, StaticsResult};

/// A built-in design from the family `family` with proportions `x`, `y` ∈ [0, 1].
fn design(family: u8, x: f64, y: f64, mu: f64) -> Scene {
    let spec = match family % 5 {
        0 => format!("arch?n={}&t={:.4}", 5 + (x * 10.0) as usize, 0.06 + 0.3 * y),
        1 => format!("wall?courses={}&bricks={}", 1 + (x * 4.0) as usize, 1 + (y * 4.0) as usize),
        2 => format!("harmonic?n={}&s={:.4}", 2 + (x * 5.0) as usize, 0.5 + 0.6 * y),
        3 => format!("slope?angle={:.3}", 5.0 + 50.0 * x),
        _ => format!("dome?courses={}&blocks={}", 2 + (x * 2.0) as usize, 4 + (y * 4.0) as usize),
    };
    let mut scene = builtin(&spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
    scene.material.friction = mu;
    scene
}

fn settings(model: u8, backend: Backend) -> AnalysisSettings {
    let mut s = AnalysisSettings::default();
    s.statics.friction_model = [FrictionModel::Pyramid8, FrictionModel::Cone, FrictionModel::Box4][model as usize % 3];
    s.statics.backend = backend;
    s
}

/// Whether a minimum of `r` lies near the stand threshold, where round-off may decide.
fn near_threshold(r: &StaticsResult) -> bool {
    let band = 10.0 * voussoir::statics::StaticsSettings::default().stand_tolerance;
    [r.tension_ratio, r.friction_excess_ratio].iter().any(|&x| x > 0.0 && x < band)
}

fn same_answer(a: &StaticsResult, b: &StaticsResult, what: &str) {
    assert_eq!(a.verdict, b.verdict, "{what}");
    // The minima are read at feasible force states: accurate to 1e-7 (T) and 1.2e-4 (F) relative.
    let tol = |x: f64| 1e-6 + 2e-4 * x.abs();
    assert_close(b.tension_ratio, a.tension_ratio, tol(a.tension_ratio), &format!("{what}: tension ratio"));
    assert_close(
        b.friction_excess_ratio,
        a.friction_excess_ratio,
        tol(a.friction_excess_ratio),
        &format!("{what}: excess ratio"),
    );
}

fn in_millimetres(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    for b in &mut s.blocks {
        b.mesh.vertices.iter_mut().for_each(|p| *p *= 1000.0);
    }
    // Density per mm³ so that the weights, and with them every ratio, stay the same.
    s.material.density *= 1e-9;
    s
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn residual_backends_and_units(family in 0u8..5, x in 0.0..1.0f64, y in 0.0..1.0f64,
                                   mu in 0.2..1.0f64, model in 0u8..3) {
        let scene = design(family, x, y, mu);
        let what = format!("{} (μ {mu:.3}, model {model})", scene.name);
        let structured = run(&scene, &settings(model, Backend::Structured)).statics;
        if structured.verdict != voussoir::statics::Verdict::Unsupported {
            prop_assert!(structured.solver.residual <= 1e-8 * structured.free_weight,
                "{what}: residual {:e} of W {:e}", structured.solver.residual, structured.free_weight);
        }
        let clarabel = run(&scene, &settings(model, Backend::Clarabel)).statics;
        if !near_threshold(&structured) && !near_threshold(&clarabel) {
            same_answer(&structured, &clarabel, &format!("{what}: structured vs clarabel"));
        }
        let mm = run(&in_millimetres(&scene), &settings(model, Backend::Structured)).statics;
        if !near_threshold(&structured) && !near_threshold(&mm) {
            same_answer(&structured, &mm, &format!("{what}: m vs mm"));
        }
    }

    #[test]
    fn warm_starts_give_the_cold_answer(family in 0u8..5, x in 0.0..1.0f64, y in 0.0..1.0f64,
                                        mu in 0.2..1.0f64, heavier in 0.8..1.25f64) {
        let scene = design(family, x, y, mu);
        let mut edited = scene.clone();
        let free = edited.blocks.iter().position(|b| !b.support).expect("a free block");
        edited.blocks[free].density = Some((edited.material.density * heavier).into());
        let mut warm = settings(0, Backend::Structured);
        warm.statics.warm_start = true;
        let mut pipeline = Pipeline::new();
        pipeline.run(&scene, &warm).expect("a valid design");
        let warm_answer = pipeline.run(&edited, &warm).expect("a valid design").statics;
        let cold = run(&edited, &settings(0, Backend::Structured)).statics;
        if !near_threshold(&warm_answer) && !near_threshold(&cold) {
            same_answer(&cold, &warm_answer, &format!("{}: warm vs cold", scene.name));
        }
    }
}
