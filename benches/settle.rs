//! Support movement (issue #41): the quasi-static settlement analysis of the 15-voussoir arch
//! (t/R 0.15) on spreading springers (0.15 m each, 100 increments) to its collapse, and of a
//! block on a support tilting by 60° to its tipping; the compas cross vault with one support
//! settling by 5 % of its span (`-- crossvault`: ~5 minutes). Increments per second follow
//! from the medians and the increments the runs take (printed once).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::model::Movement;
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::studies::settlement::{SettleSettings, settle};

fn moved(block: &str, translation: [f64; 3], rotation: [f64; 3]) -> Movement {
    Movement { block: block.into(), translation, rotation }
}

fn quasi_static(c: &mut Criterion) {
    let only = SettleSettings { engines: false, ..Default::default() };
    let arch = analyze(&voussoir::model::builtin("arch?n=15&t=0.15").unwrap(), &AnalysisSettings::default()).unwrap();
    let spread =
        [moved("springer_left", [-0.15, 0.0, 0.0], [0.0; 3]), moved("springer_right", [0.15, 0.0, 0.0], [0.0; 3])];
    let once = settle(&arch, &spread, &only).unwrap();
    println!(
        "arch: {} stages, {} engine steps, {:?}",
        once.quasi_static.stages.len(),
        once.quasi_static.steps,
        once.quasi_static.outcome
    );
    let mut g = c.benchmark_group("settle");
    g.sample_size(10).measurement_time(Duration::from_secs(60));
    g.bench_function("arch15_spread_quasi_static", |b| b.iter(|| black_box(settle(&arch, &spread, &only).unwrap())));
    let on_clarabel = SettleSettings { backend: voussoir::statics::Backend::Clarabel, ..only.clone() };
    g.bench_function("arch15_spread_quasi_static_clarabel", |b| {
        b.iter(|| black_box(settle(&arch, &spread, &on_clarabel).unwrap()))
    });
    let mut block = voussoir::model::builtin("stack?n=1&a=0.5").unwrap();
    block.material.friction = 0.8;
    let block = analyze(&block, &AnalysisSettings::default()).unwrap();
    let tilt = [moved("base", [0.0; 3], [0.0, 60.0, 0.0])];
    g.bench_function("block_tilt_quasi_static", |b| b.iter(|| black_box(settle(&block, &tilt, &only).unwrap())));
    g.finish();
}

/// The compas cross vault (184 blocks, ~2 000 contacts) with support 180 settling by 5 % of
/// the span (0.485 m) in 20 increments: it stands to the end of the path.
fn cross_vault(c: &mut Criterion) {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_assembly/crossvault_assembly.json");
    let vault = analyze(&voussoir::io::load_scene(&path).unwrap(), &AnalysisSettings::default()).unwrap();
    let settling = [moved("180", [0.0, 0.0, -0.485], [0.0; 3])];
    let coarse = SettleSettings { engines: false, increments: 20, ..Default::default() };
    let mut g = c.benchmark_group("settle");
    g.sample_size(10).measurement_time(Duration::from_secs(300));
    g.bench_function("crossvault_settling_5pct_20_increments", |b| {
        b.iter(|| black_box(settle(&vault, &settling, &coarse).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, quasi_static, cross_vault);
criterion_main!(benches);
