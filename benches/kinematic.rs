//! The kinematic check (issue #25) on the scenes its goals name, each beside the statics alone
//! (the same settings, measured in the same run): compas_cra's letter H and turned wedge type-b
//! (small cases, goal ≤ 10 ms), the 330-brick running-bond wall (20 courses × 16; compas_cra's
//! CRA: 276 s) and a 6 × 12 hemispherical dome (CRA: 452 s on such a dome), goal ≤ 5 s each,
//! and the Armadillo vault (goal ≤ 10 s).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::model::{Scene, builtin};
use voussoir::pipeline::{Analysis, AnalysisSettings, analyze};
use voussoir::stability::kinematic;

fn compas(rel: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas").join(rel);
    let mut scene = voussoir::io::load_scene(&path).unwrap();
    scene.material.friction = 0.84;
    scene
}

fn cases() -> Vec<(&'static str, Scene, usize)> {
    let mut h = compas("compas_cra/H.json");
    h.mark_lowest_as_supports(1e-3);
    let mut wedge = compas("compas_cra/type-b.json");
    wedge.mark_lowest_as_supports(1e-3);
    // compas_cra's 05_wedge.py turns the assembly 90° about y: gravity along +x.
    wedge.gravity = nalgebra::Vector3::new(9.81, 0.0, 0.0);
    vec![
        ("H", h, 100),
        ("wedge_type_b", wedge, 100),
        ("wall_330", builtin("wall?courses=20&bricks=16").unwrap(), 10),
        ("dome_6x12", builtin("dome?courses=6&blocks=12").unwrap(), 10),
        ("armadillo", compas("compas_cra/armadillo_cra.json"), 10),
    ]
}

fn kinematic(c: &mut Criterion) {
    let settings = AnalysisSettings::default();
    for (name, scene, samples) in cases() {
        let a: Analysis = analyze(&scene, &settings).unwrap();
        let mut g = c.benchmark_group(format!("kinematic/{name}"));
        g.sample_size(samples);
        if samples <= 10 {
            g.measurement_time(Duration::from_secs(30));
        }
        g.bench_function("statics", |b| {
            b.iter(|| black_box(voussoir::statics::solve(&a.assembly, &a.interfaces, &settings.statics).unwrap()))
        });
        g.bench_function("kinematic", |b| {
            b.iter(|| black_box(kinematic::check(&a, &settings.statics, &Default::default()).unwrap()))
        });
        g.finish();
    }
}

criterion_group!(benches, kinematic);
criterion_main!(benches);
