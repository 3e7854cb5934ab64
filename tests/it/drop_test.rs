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
