//! Automatic design (issue #22), default swarm (12 particles × 16 rounds = 193 evaluations,
//! plus 192 per focused round when the design still fails):
//! - `repair_m_fig4a`: the paper's M, its cut through the V moved until it stands;
//! - `decompose_optimize_m`: the M given as one solid, cut by courses of 0.2 m (10 pieces)
//!   and repaired (the whole swarm, then one focused round: 385 evaluations);
//! - `decompose_optimize_arch20` / `decompose_thrust_optimize_arch20`: a semicircular arch
//!   given as one solid (0.15 m deep, shallower than a voussoir is long: 20 pieces), cut into
//!   20 radial courses, or by the thrust strategy, then optimised for its load factor.
//!
//! Evaluations per second = evaluations / the median.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Block, Scene};
use voussoir::pipeline::AnalysisSettings;
use voussoir::synthesis::{BlockSize, Field, RepairSettings, ThrustSettings, courses, repair, thrust};

/// A semicircular arch (radius 1 m, t/R = 0.15, 0.15 m deep) as one solid on the ground.
fn solid_arch() -> Scene {
    let arc = |r: f64| -> Vec<Point3> {
        (0..=96)
            .map(|k| std::f64::consts::PI * k as f64 / 96.0)
            .map(|a| Point3::new(r * a.cos(), 0.0, r * a.sin()))
            .collect()
    };
    let mut outline = arc(1.075);
    outline.extend(arc(0.925).into_iter().rev());
    let mut scene = Scene::new("arch", vec![Block::new("arch", Mesh::prism(&outline, Vector3::new(0.0, 0.15, 0.0)))]);
    scene.ground = true;
    scene
}

fn design(c: &mut Criterion) {
    let mut g = c.benchmark_group("design");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    let m = voussoir::io::load_scene(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases/fig4a_m_cut.json"),
    )
    .unwrap();
    let analysis = AnalysisSettings::default();
    g.bench_function("repair_m_fig4a", |b| {
        b.iter(|| black_box(repair(&m, &analysis, &RepairSettings::default(), &|_, _, _| {}).unwrap()))
    });
    let mut m_solid = m.clone();
    m_solid.cuts.clear();
    g.bench_function("decompose_optimize_m", |b| {
        b.iter(|| {
            let generated = courses(&m_solid, &Field::Vertical, &BlockSize::Max(0.2), true).unwrap();
            black_box(repair(&generated.design, &analysis, &RepairSettings::default(), &|_, _, _| {}).unwrap())
        })
    });
    let arch = solid_arch();
    let radial = Field::Radial { center: [0.0; 3], axis: [0.0, 1.0, 0.0] };
    g.bench_function("decompose_optimize_arch20", |b| {
        b.iter(|| {
            let generated = courses(&arch, &radial, &BlockSize::Count(20), true).unwrap();
            black_box(repair(&generated.design, &analysis, &RepairSettings::default(), &|_, _, _| {}).unwrap())
        })
    });
    g.bench_function("decompose_thrust_optimize_arch20", |b| {
        b.iter(|| {
            let generated =
                thrust(&arch, &radial, &BlockSize::Count(20), true, &ThrustSettings::default(), &analysis).unwrap();
            black_box(repair(&generated.design, &analysis, &RepairSettings::default(), &|_, _, _| {}).unwrap())
        })
    });
    g.finish();
}

criterion_group!(benches, design);
criterion_main!(benches);
