//! Decomposition: cutting a 10 000-face mesh, replaying a 50-cut history cold, and re-applying
//! it after moving one cut (with the content cache: about one cut's work, not fifty); and
//! generation without hints (issue #42): the solid arch (`assets/shapes/solid_arch.json`) in 11
//! blocks along the load path found (horizontal courses analysed, then radial about the fitted
//! axis, analysed), and the Fig 9 box by a running bond extruded to its apex.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use voussoir::geometry::cut::split;
use voussoir::geometry::{Mesh, Plane, Point3, Vector3};
use voussoir::history::{CutCache, replay};
use voussoir::model::{Block, Cut};
use voussoir::pipeline::AnalysisSettings;
use voussoir::synthesis::{BlockSize, found_courses, pattern};

/// UV sphere of radius 1 with `n` × `n` faces (quads, triangles at the poles).
fn sphere(n: usize) -> Mesh {
    let mut vertices = vec![Point3::new(0.0, 0.0, -1.0)];
    for i in 1..n {
        let phi = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * i as f64 / n as f64;
        for j in 0..n {
            let th = std::f64::consts::TAU * j as f64 / n as f64;
            vertices.push(Point3::new(phi.cos() * th.cos(), phi.cos() * th.sin(), phi.sin()));
        }
    }
    vertices.push(Point3::new(0.0, 0.0, 1.0));
    let top = vertices.len() - 1;
    let ring = |i: usize, j: usize| 1 + (i - 1) * n + j % n;
    let mut faces = Vec::new();
    for j in 0..n {
        faces.push(vec![0, ring(1, j + 1), ring(1, j)]);
        faces.push(vec![top, ring(n - 1, j), ring(n - 1, j + 1)]);
    }
    for i in 1..n - 1 {
        for j in 0..n {
            faces.push(vec![ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)]);
        }
    }
    Mesh::new(vertices, faces)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("decompose");
    g.sample_size(20);
    let ball = sphere(100);
    assert!(ball.faces.len() >= 10_000);
    let plane = Plane::from_point_normal(&Point3::new(0.1, 0.0, 0.05), &Vector3::new(0.3, 0.2, 1.0));
    g.bench_function("split_10k_faces", |b| b.iter(|| black_box(split(black_box(&ball), &plane, 1e-9))));

    let beam = vec![Block::new("beam", Mesh::cuboid(Point3::origin(), Point3::new(51.0, 1.0, 1.0)))];
    let cuts: Vec<Cut> =
        (1..=50).map(|k| Cut::plane([k as f64, 0.0, 0.0], [1.0, 0.0, 0.05 * (k % 3) as f64])).collect();
    g.bench_function("replay_50_cuts_cold", |b| {
        b.iter(|| black_box(replay(&beam, &cuts, 1e-9, &mut CutCache::new()).unwrap()))
    });
    // Warm cache; each iteration moves the last cut back and forth, so exactly one cut's
    // splits are new each time (the other position is cached after the first two runs).
    let mut cache = CutCache::new();
    replay(&beam, &cuts, 1e-9, &mut cache).unwrap();
    let mut moved = cuts.clone();
    let mut flip = false;
    g.bench_function("replay_after_moving_last_cut", |b| {
        b.iter(|| {
            flip = !flip;
            let x = if flip { 50.3 } else { 50.0 } + 1e-9 * cache.len() as f64;
            moved[49] = Cut::plane([x, 0.0, 0.0], [1.0, 0.0, 0.0]);
            black_box(replay(&beam, &moved, 1e-9, &mut cache).unwrap())
        })
    });
    g.finish();
}

fn generate(c: &mut Criterion) {
    let shape = |name: &str| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/shapes").join(name);
        voussoir::io::load_scene(&path).unwrap()
    };
    let (arch, fig9) = (shape("solid_arch.json"), shape("fig9_box.json"));
    let settings = AnalysisSettings::default();
    let mut g = c.benchmark_group("generate");
    g.sample_size(20);
    g.bench_function("solid_arch_found_11_blocks", |b| {
        b.iter(|| black_box(found_courses(&arch, &BlockSize::Count(11), true, &settings).unwrap()))
    });
    g.bench_function("fig9_box_pattern_0.4", |b| {
        b.iter(|| black_box(pattern(&fig9, [0.0, 0.0, -1.0], &BlockSize::Max(0.4), true).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, bench, generate);
criterion_main!(benches);
