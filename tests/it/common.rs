//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use voussoir::geometry::{Mesh, Point3};
use voussoir::model::{Assembly, Block, Scene};
use voussoir::pipeline::{Analysis, AnalysisSettings, analyze};

/// This run's folder for the files of the tests of `kind`, in cargo's scratch space for
/// integration tests (`CARGO_TARGET_TMPDIR`, inside the target directory), emptied on its first
/// use in a run: the tests leave nothing in the system's temporary folder, and a run does not see
/// the files of the run before.
pub fn scratch(kind: &str) -> PathBuf {
    static EMPTIED: Mutex<BTreeSet<String>> = Mutex::new(BTreeSet::new());
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(kind);
    let mut emptied = EMPTIED.lock().unwrap_or_else(|e| e.into_inner());
    if emptied.insert(kind.to_string()) {
        let _ = std::fs::remove_dir_all(&dir);
    }
    std::fs::create_dir_all(&dir).expect("cargo's scratch folder for tests");
    dir
}

/// `assets/compas/<rel>` in the checkout (the BRG reference assemblies).
pub fn compas_data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/compas").join(rel)
}

/// Every compas Assembly file of the reference data (compas_assembly and compas_cra), sorted,
/// as paths relative to `assets/compas`.
pub fn assembly_files() -> Vec<String> {
    let mut files = Vec::new();
    for dir in ["compas_assembly", "compas_cra"] {
        for e in std::fs::read_dir(compas_data(dir)).expect("assets/compas in the checkout") {
            files.push(format!("{dir}/{}", e.expect("a directory entry").file_name().to_string_lossy()));
        }
    }
    files.sort();
    files
}

pub fn cube(name: &str, min: [f64; 3], size: f64) -> Block {
    Block::new(name, Mesh::cuboid(Point3::from(min), Point3::new(min[0] + size, min[1] + size, min[2] + size)))
}

pub fn cuboid(name: &str, min: [f64; 3], max: [f64; 3]) -> Block {
    Block::new(name, Mesh::cuboid(Point3::from(min), Point3::from(max)))
}

pub fn assembly(scene: &Scene) -> Assembly {
    Assembly::new(scene, &Default::default()).expect("valid scene")
}

pub fn run(scene: &Scene, settings: &AnalysisSettings) -> Analysis {
    analyze(scene, settings).expect("analysis runs")
}

pub fn assert_close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!((actual - expected).abs() <= tol, "{what}: {actual} vs {expected} (tolerance {tol})");
}

/// A 3 × 1 × 0.3 lintel on two 1 m piers, "left" under x ∈ [0, 0.5] and "right" under
/// x ∈ [2.5, 3.5] (both supports).
pub fn lintel() -> Scene {
    Scene::new(
        "lintel",
        vec![
            cuboid("left", [0.0, 0.0, -1.0], [0.5, 1.0, 0.0]).support(true),
            cuboid("right", [2.5, 0.0, -1.0], [3.5, 1.0, 0.0]).support(true),
            cuboid("lintel", [0.0, 0.0, 0.0], [3.0, 1.0, 0.3]),
        ],
    )
}
