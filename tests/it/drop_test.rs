//! Invariant: the rapier drop test agrees with statics away from the limits (stable designs
//! stand, unstable ones fall) and is deterministic.

use crate::common::*;
use voussoir::dynamics::{DropResult, DropSettings, drop_test};
use voussoir::model::builtin;

fn drop(spec: &str) -> DropResult {
    drop_test(&assembly(&builtin(spec).unwrap()), &DropSettings::default()).unwrap()
}

#[test]
fn stable_designs_stand() {
    for spec in ["stack?n=5", "arch?n=15&t=0.15", "slope?angle=20&mu=0.6", "harmonic?n=6&s=0.8"] {
        let r = drop(spec);
        assert!(r.stands, "{spec}: drift {} rotation {} ({:?})", r.max_drift, r.max_rotation, r.worst_block);
        assert!(r.max_drift < 0.01, "{spec}: drift {}", r.max_drift);
    }
}

#[test]
fn unstable_designs_fall() {
    for spec in ["harmonic?n=6&s=1.3", "slope?angle=45&mu=0.5", "arch?n=15&t=0.07"] {
        let r = drop(spec);
        assert!(!r.stands, "{spec}: drift {} rotation {}", r.max_drift, r.max_rotation);
        assert!(r.blocks.iter().any(|b| b.first_motion.is_some()));
    }
}

#[test]
fn same_input_same_trajectory() {
    let a = drop("arch?n=9&t=0.1");
    let b = drop("arch?n=9&t=0.1");
    assert_eq!(a.blocks, b.blocks, "bitwise identical motion");
}

#[test]
fn bad_settings_are_errors() {
    let asm = assembly(&builtin("stack?n=2").unwrap());
    let s = DropSettings { dt: 0.0, ..Default::default() };
    assert!(drop_test(&asm, &s).unwrap_err().to_string().contains("dt"));
    let s = DropSettings { solver_iterations: 0, ..Default::default() };
    assert!(drop_test(&asm, &s).is_err());
}

/// Invariant: rapier's colliders follow a notched block when asked. A U-shaped support (floor
/// at z = 0.2, walls to z = 0.6) and a 0.3 cube released above its notch (bottom at 0.8): with
/// `ColliderForm::Exact` the U collides as its convex parts and the cube falls into the notch,
/// 0.6 onto the floor; with the default `Fitted` form the U's hull reaches into nothing at the
/// start, so it collides as that hull and the cube lands on the hull's top, 0.2 down — the
/// case the exact form exists for. Both within rapier's settling (1 % of the fall).
#[test]
fn exact_colliders_let_a_block_fall_into_a_notch() {
    use voussoir::dynamics::ColliderForm;
    use voussoir::geometry::{Mesh, Point3, Vector3};
    use voussoir::model::{Block, Scene};
    let u = [(0.0, 0.0), (1.0, 0.0), (1.0, 0.6), (0.8, 0.6), (0.8, 0.2), (0.2, 0.2), (0.2, 0.6), (0.0, 0.6)];
    let base: Vec<Point3> = u.iter().map(|&(x, z)| Point3::new(x, 0.0, z)).collect();
    let channel = Mesh::prism(&base, Vector3::new(0.0, 1.0, 0.0));
    let scene =
        Scene::new("notch", vec![Block::new("channel", channel).support(true), cube("cube", [0.35, 0.35, 0.8], 0.3)]);
    let asm = assembly(&scene);
    for (form, fall) in [(ColliderForm::Exact, 0.6), (ColliderForm::Fitted, 0.2)] {
        let r = drop_test(&asm, &DropSettings { colliders: form, duration: 1.5, ..Default::default() }).unwrap();
        let drop = r.blocks[0].max_drift;
        assert!((drop - fall).abs() < 0.01 * fall, "{form}: the cube fell {drop}, {fall} expected");
    }
}
