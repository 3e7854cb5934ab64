//! Assembly sequences: the check of every prefix (steps on two threads, pipelines reused), the
//! order search and the temporary supports. The Armadillo's 399-step bottom-up check takes
//! minutes (most prefixes fail, and each failing prefix needs the two exact LPs); its timing is
//! taken with the CLI and reported in docs/benchmarks.md, not here.

use criterion::{Criterion, criterion_group, criterion_main};
use std::time::Duration;
use voussoir::model::builtin;
use voussoir::pipeline::AnalysisSettings;
use voussoir::studies::sequence::{OrderSpec, SearchSettings, check, check_with_props, search};

fn sequences(c: &mut Criterion) {
    let s = AnalysisSettings::default();
    let wall = builtin("wall?courses=5&bricks=10").unwrap();
    c.bench_function("sequence: wall 5×10 bottom-up (every step stands)", |b| {
        b.iter(|| check(&wall, &OrderSpec::BottomUp, &s, &Default::default(), &|| {}).unwrap())
    });
    let arch = builtin("arch?n=15&t=0.15").unwrap();
    c.bench_function("sequence: arch 15 bottom-up (fails until the keystone)", |b| {
        b.iter(|| check(&arch, &OrderSpec::BottomUp, &s, &Default::default(), &|| {}).unwrap())
    });
    for local_checks in [true, false] {
        let settings = SearchSettings { local_checks, ..Default::default() };
        let on = if local_checks { "on" } else { "off" };
        c.bench_function(&format!("search: arch 15 (no order; temporary supports; neighbourhood checks {on})"), |b| {
            b.iter(|| search(&arch, &s, &settings, &Default::default(), &|| {}).unwrap())
        });
    }
    // The props' neighbourhood checks against none, in one run (the same props either way).
    let dome = builtin("dome?courses=6&blocks=12").unwrap();
    for local_checks in [true, false] {
        let search = SearchSettings { local_checks, ..Default::default() };
        let name =
            format!("props: dome 6×12 bottom-up (neighbourhood checks {})", if local_checks { "on" } else { "off" });
        c.bench_function(&name, |b| {
            b.iter(|| check_with_props(&dome, &OrderSpec::BottomUp, &s, &search, &Default::default(), &|| {}).unwrap())
        });
    }
    let dmsc = voussoir::io::load_scene(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases/fig6_dmsc_sequence.json"),
    )
    .unwrap();
    c.bench_function("search: DMSC ligature (an order is found)", |b| {
        b.iter(|| search(&dmsc, &s, &SearchSettings::default(), &Default::default(), &|| {}).unwrap())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).measurement_time(Duration::from_secs(5));
    targets = sequences
}
criterion_main!(benches);
