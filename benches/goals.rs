//! The long goals of issue #24 as criterion benches (by hand: minutes per sample), beside the
//! edit loop's (`benches/edit_loop.rs`) and the Armadillo pipeline's (`benches/statics.rs`):
//! the Armadillo's bottom-up sequence check (goal ≤ 10 s) and running-bond walls towards the
//! 10⁵-brick goal (≤ 60 s, ≤ 3 GB). The largest wall runs only with `VOUSSOIR_BENCH_LARGE=1`
//! (ten samples of about 100 s); its peak memory, which criterion cannot measure, comes from
//! `scripts/scale_walls.py`. The Armadillo's bottom-up order with temporary supports (issue
//! #43: ≤ 60 s) runs only with `VOUSSOIR_BENCH_PROPS=1` (ten samples of about a minute).

use criterion::{Criterion, criterion_group, criterion_main};
use std::time::Duration;
use voussoir::model::builtin;
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::studies::sequence::{OrderSpec, SearchSettings, check, check_with_props};

fn goals(c: &mut Criterion) {
    let mut g = c.benchmark_group("goals");
    g.sample_size(10).measurement_time(Duration::from_secs(1));
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/armadillo_cra.json");
    let mut armadillo = voussoir::io::load_scene(&path).unwrap();
    armadillo.material.friction = 0.84;
    let s = AnalysisSettings::default();
    g.bench_function("sequence_armadillo_bottom_up", |b| {
        b.iter(|| check(&armadillo, &OrderSpec::BottomUp, &s, &Default::default(), &|| {}).unwrap())
    });
    if std::env::var_os("VOUSSOIR_BENCH_PROPS").is_some() {
        let search = SearchSettings::default();
        g.bench_function("props_armadillo_bottom_up", |b| {
            b.iter(|| {
                check_with_props(&armadillo, &OrderSpec::BottomUp, &s, &search, &Default::default(), &|| {}).unwrap()
            })
        });
    }
    let mut walls = vec![("wall_10051", "wall?courses=100&bricks=100")];
    if std::env::var_os("VOUSSOIR_BENCH_LARGE").is_some() {
        walls.push(("wall_100101", "wall?courses=200&bricks=500"));
    }
    for (name, spec) in walls {
        let wall = builtin(spec).unwrap();
        g.bench_function(name, |b| b.iter(|| analyze(&wall, &s).unwrap()));
    }
    g.finish();
}

criterion_group!(benches, goals);
criterion_main!(benches);
