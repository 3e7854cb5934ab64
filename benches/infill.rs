//! Make it stand by mass (issue #42): the Armadillo vault's lightest densities within
//! [150, 600] kg/m³ (399 blocks, one LP beside two analyses: the design as given and as
//! infilled) against its `analyze` (the whole pipeline, the same settings, in the same run);
//! and the thin arch (n = 15, t = 0.07, which needs tension uniform) made to stand and to carry
//! the largest horizontal load in 8 directions (a bisection over λ).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::model::builtin;
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::synthesis::{InfillObjective, InfillSettings, infill};

fn armadillo(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/armadillo_cra.json");
    let mut scene = voussoir::io::load_scene(&path).unwrap();
    scene.material.friction = 0.84;
    let settings = AnalysisSettings::default();
    let stand = InfillSettings { range: Some((150.0, 600.0)), ..Default::default() };
    let mut g = c.benchmark_group("infill/armadillo");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.bench_function("analyze", |b| b.iter(|| black_box(analyze(&scene, &settings).unwrap())));
    g.bench_function("infill_stand", |b| b.iter(|| black_box(infill(&scene, &settings, &stand).unwrap())));
    g.finish();
}

fn arch(c: &mut Criterion) {
    let scene = builtin("arch?n=15&t=0.07").unwrap();
    let settings = AnalysisSettings::default();
    let mut g = c.benchmark_group("infill/arch_t007");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for (name, objective) in [("stand", InfillObjective::Stand), ("robust_8_directions", InfillObjective::Robust)] {
        let s = InfillSettings { objective, ..Default::default() };
        g.bench_function(name, |b| b.iter(|| black_box(infill(&scene, &settings, &s).unwrap())));
    }
    g.finish();
}

criterion_group!(benches, armadillo, arch);
criterion_main!(benches);
