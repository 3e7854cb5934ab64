//! Automatic design (issue #22): repairing the paper's M (fig4a, the cut through the V) and
//! decomposing a 20-voussoir arch given as one solid then optimising it (radial courses +
//! repair), default swarm (12 particles × 16 rounds = 193 evaluations). Evaluations per second
//! = 193 / the median.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::analysis::AnalysisSettings;
use voussoir::design::{BlockSize, Field, RepairSettings, courses, repair};
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Block, Scene};

/// A semicircular arch (radius 1 m, t/R = 0.15, 0.25 m deep) as one solid on the ground.
fn solid_arch() -> Scene {
    let arc = |r: f64| -> Vec<Point3> {
        (0..=96)
            .map(|k| std::f64::consts::PI * k as f64 / 96.0)
            .map(|a| Point3::new(r * a.cos(), 0.0, r * a.sin()))
            .collect()
    };
    let mut outline = arc(1.075);
    outline.extend(arc(0.925).into_iter().rev());
    let mut scene = Scene::new("arch", vec![Block::new("arch", Mesh::prism(&outline, Vector3::new(0.0, 0.25, 0.0)))]);
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
    let arch = solid_arch();
    let radial = Field::Radial { center: [0.0; 3], axis: [0.0, 1.0, 0.0] };
    g.bench_function("decompose_optimize_arch20", |b| {
        b.iter(|| {
            let generated = courses(&arch, &radial, &BlockSize::Count(20), true).unwrap();
            black_box(repair(&generated.design, &analysis, &RepairSettings::default(), &|_, _, _| {}).unwrap())
        })
    });
    g.finish();
}

criterion_group!(benches, design);
criterion_main!(benches);
