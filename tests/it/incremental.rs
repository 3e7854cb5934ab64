//! Invariant: a pipeline run after an edit gives exactly the results of a fresh analysis, and
//! recomputes only what the edit touched (splits, block pairs, components).

use crate::common::*;
use voussoir::model::builtin;
use voussoir::pipeline::{AnalysisSettings, Pipeline, analyze};

#[test]
fn rerun_of_an_unchanged_design_reuses_everything() {
    let scene = voussoir::io::load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
    let settings = AnalysisSettings::default();
    let mut p = Pipeline::new();
    let first = p.run(&scene, &settings).unwrap();
    assert_eq!((first.work.pairs_reused, first.work.components_reused), (0, 0));
    let again = p.run(&scene, &settings).unwrap();
    assert_eq!((again.work.pairs_detected, again.work.components_solved), (0, 0), "{:?}", again.work);
    assert_eq!(again.interfaces, first.interfaces);
    assert_eq!(again.statics.interfaces, first.statics.interfaces);
    assert_eq!(again.statics.verdict, first.statics.verdict);

    // A heavier block: no pair is detected again, the one component is solved again, and the
    // result is a fresh analysis's, bit for bit.
    let mut heavier = scene.clone();
    let k = heavier.blocks.iter().position(|b| !b.support).unwrap();
    heavier.blocks[k].density = Some(5000.0.into());
    let edited = p.run(&heavier, &settings).unwrap();
    assert_eq!((edited.work.pairs_detected, edited.work.components_solved), (0, 1), "{:?}", edited.work);
    let fresh = analyze(&heavier, &settings).unwrap();
    assert_eq!(edited.statics.interfaces, fresh.statics.interfaces);
}

#[test]
fn moving_one_stack_redetects_its_pairs_and_resolves_its_component_only() {
    let mut scene = builtin("stacks?k=4&n=3").unwrap();
    let settings = AnalysisSettings::default();
    let mut p = Pipeline::new();
    let first = p.run(&scene, &settings).unwrap();
    assert_eq!(first.work.components_solved, 4);
    // Shift the top block of the last stack sideways (still on its neighbour).
    let last = scene.blocks.len() - 1;
    scene.blocks[last].mesh = scene.blocks[last].mesh.scaled_translated(1.0, nalgebra::Vector3::new(0.1, 0.0, 0.0));
    let moved = p.run(&scene, &settings).unwrap();
    assert_eq!((moved.work.components_solved, moved.work.components_reused), (1, 3), "{:?}", moved.work);
    let fresh = analyze(&scene, &settings).unwrap();
    assert_eq!(moved.interfaces, fresh.interfaces);
    assert_eq!(moved.statics.interfaces, fresh.statics.interfaces);
    assert_eq!(moved.statics.tension_ratio, fresh.statics.tension_ratio);
}

/// A pipeline keeping `keep` outcomes of earlier runs comes back to a design it analysed
/// before without solving again — the fresh analysis's results — while one that keeps none (or
/// whose outcome was pushed out by `keep` more recent ones) solves that component again.
#[test]
fn a_pipeline_keeping_components_comes_back_without_solving() {
    let scene = builtin("stacks?k=4&n=3").unwrap();
    let settings = AnalysisSettings::default();
    let last = scene.blocks.len() - 1;
    let shifted = |dx: f64| {
        let mut s = scene.clone();
        s.blocks[last].mesh = s.blocks[last].mesh.scaled_translated(1.0, nalgebra::Vector3::new(dx, 0.0, 0.0));
        s
    };
    // The last stack changes in each run; the other three stacks stay.
    let runs = [shifted(0.0), shifted(0.1), shifted(0.05), shifted(0.0)];
    let solved_last = |keep: usize| {
        let mut p = Pipeline::keeping_components(keep);
        let mut out = Vec::new();
        for s in &runs {
            out.push(p.run(s, &settings).unwrap());
        }
        out.pop().unwrap()
    };
    for (keep, solved) in [(0, 1), (1, 1), (2, 0)] {
        let a = solved_last(keep);
        assert_eq!((a.work.components_solved, a.work.components_reused), (solved, 4 - solved), "keep {keep}");
        let fresh = analyze(&runs[3], &settings).unwrap();
        assert_eq!(a.statics.interfaces, fresh.statics.interfaces, "keep {keep}");
    }
}
