//! Invariant: real vaults that stand in the statics hold in the drop test — the Armadillo (399
//! blocks, curved voussoirs, warped joints whose two triangulations make neighbouring hulls
//! overlap) stands at μ 0.84 with a median drift under 0.5 % of a block's size and is at rest
//! after 1 s; the compas crossvault stands. Input blocks that overlap are reported, touching
//! ones are not.

use crate::common::*;
use voussoir::dynamics::{DropResult, DropSettings, drop_test};

fn drop(rel: &str, mu: f64) -> DropResult {
    let mut scene = voussoir::io::load_scene(&compas_data(rel)).expect("the vault loads");
    scene.material.friction = mu;
    drop_test(&assembly(&scene), &DropSettings { duration: 1.0, ..Default::default() }).expect("valid settings")
}

fn median_drift(r: &DropResult) -> f64 {
    let mut drift: Vec<f64> = r.blocks.iter().map(|b| b.max_drift_ratio).collect();
    drift.sort_by(f64::total_cmp);
    drift[drift.len() / 2]
}

#[test]
fn the_armadillo_stands_in_rapier_as_in_the_statics() {
    let r = drop("compas_cra/armadillo_cra.json", 0.84);
    println!(
        "armadillo: median drift {:.4}, largest {:.4}, rotation {:.4}",
        median_drift(&r),
        r.max_drift,
        r.max_rotation
    );
    assert!(r.stands, "largest drift {} (block {:?}), rotation {}", r.max_drift, r.worst_block, r.max_rotation);
    assert!(median_drift(&r) < 0.005, "median drift {}", median_drift(&r));
    assert!(r.at_rest, "the vault has settled after 1 s");
}

#[test]
fn the_compas_crossvault_stands_in_rapier_as_in_the_statics() {
    let r = drop("compas_assembly/crossvault_assembly.json", 0.84);
    println!(
        "crossvault: median drift {:.4}, largest {:.4}, rotation {:.4}",
        median_drift(&r),
        r.max_drift,
        r.max_rotation
    );
    assert!(r.stands, "largest drift {} (block {:?}), rotation {}", r.max_drift, r.worst_block, r.max_rotation);
}

#[test]
fn overlapping_input_blocks_are_reported() {
    // Two unit cubes on the ground, the second pushed 2 cm into the first.
    let mut scene =
        voussoir::model::Scene::new("overlap", vec![cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [0.98, 0.0, 0.0], 1.0)]);
    scene.ground = true;
    let r =
        drop_test(&assembly(&scene), &DropSettings { duration: 0.05, ..Default::default() }).expect("valid settings");
    let size = 3f64.sqrt();
    assert!((r.max_initial_overlap - 0.02 / size).abs() < 1e-3 / size, "{}", r.max_initial_overlap);
    assert_eq!(r.initial_overlap_blocks, Some(["a".to_string(), "b".to_string()]));
    // Touching without overlap: nothing reported.
    let mut scene =
        voussoir::model::Scene::new("touch", vec![cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [1.0, 0.0, 0.0], 1.0)]);
    scene.ground = true;
    let r =
        drop_test(&assembly(&scene), &DropSettings { duration: 0.05, ..Default::default() }).expect("valid settings");
    assert_eq!((r.max_initial_overlap, r.initial_overlap_blocks), (0.0, None));
}
