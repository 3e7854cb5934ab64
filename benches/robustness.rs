//! The load factor (issue #21): the Armadillo vault's λ* for a horizontal 1 g along x beside its
//! `analyze` time (statics alone, the same settings, measured in the same run), and its
//! worst-direction sweep over 36 azimuths with its refinement (the root of the mechanism's
//! normal offset between the grid's neighbours). `load_factor_x` against `load_factor_x_blend`:
//! what recovering one vertex mechanism (`statics::vertex`) adds to the load-factor solve.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::stability::{self, DirectionSettings, directions};

fn load_factor(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/armadillo_cra.json");
    let mut scene = voussoir::io::load_scene(&path).unwrap();
    scene.material.friction = 0.84;
    let settings = AnalysisSettings::default();
    let a = analyze(&scene, &settings).unwrap();
    let field = directions::with_horizontal_field(&a.assembly, 0.0);
    let mut g = c.benchmark_group("robustness/armadillo");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.bench_function("statics", |b| {
        b.iter(|| black_box(voussoir::statics::solve(&a.assembly, &a.interfaces, &settings.statics).unwrap()))
    });
    g.bench_function("load_factor_x", |b| {
        b.iter(|| black_box(stability::assess_parts(&field, &a.interfaces, true, &settings.statics).unwrap()))
    });
    // The same solve without the vertex recovery (issue #73: the recovery ≤ 20 % of the solve).
    let blend = voussoir::statics::StaticsSettings { one_mechanism: false, ..settings.statics.clone() };
    g.bench_function("load_factor_x_blend", |b| {
        b.iter(|| black_box(stability::assess_parts(&field, &a.interfaces, true, &blend).unwrap()))
    });
    g.finish();
    let mut g = c.benchmark_group("robustness/armadillo_sweep");
    g.sample_size(10).measurement_time(Duration::from_secs(60));
    g.bench_function("36_directions", |b| {
        b.iter(|| {
            black_box(
                stability::worst_direction(
                    &a.assembly,
                    &a.interfaces,
                    &settings.statics,
                    &DirectionSettings::default(),
                    &|_, _| {},
                )
                .unwrap(),
            )
        })
    });
    g.finish();
}

criterion_group!(benches, load_factor);
criterion_main!(benches);
