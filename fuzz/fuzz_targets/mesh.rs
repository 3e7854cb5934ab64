//! Fuzz target: a mesh built from arbitrary bytes (vertex coordinates as f64, faces as small
//! indices) through validation, repair, mass properties and interface detection must never
//! panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use voussoir::geometry::{Mesh, Point3};
use voussoir::model::{Assembly, Block, Scene};

fuzz_target!(|data: &[u8]| {
    if data.len() < 2 {
        return;
    }
    let nv = (data[0] % 16) as usize;
    let (coords, rest) = data[1..].split_at((nv * 24).min(data.len() - 1));
    let vertices: Vec<Point3> = coords
        .chunks_exact(24)
        .map(|c| {
            let f = |k: usize| f64::from_le_bytes(c[8 * k..8 * k + 8].try_into().unwrap());
            Point3::new(f(0), f(1), f(2))
        })
        .collect();
    // Faces: a length byte then that many index bytes, repeatedly.
    let mut faces = Vec::new();
    let mut i = 0;
    while i < rest.len() {
        let len = (rest[i] % 8) as usize;
        let end = (i + 1 + len).min(rest.len());
        faces.push(rest[i + 1..end].iter().map(|&b| (b % 20) as usize).collect());
        i = end;
    }
    let scene = Scene::new("fuzz", vec![Block::new("m", Mesh::new(vertices, faces))]);
    if let Ok(a) = Assembly::new(&scene, &Default::default()) {
        let _ = voussoir::interfaces::detect(&a);
    }
});
