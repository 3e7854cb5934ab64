//! The shake table (issue #70's goals): the 15-voussoir arch under 10 s of the shipped El
//! Centro record at the default dt on both engines — one that stands (t/R 0.25, λ* 0.41 g
//! above the record's 0.28 g) and one that collapses (t/R 0.15, λ* 0.15 g); a 20-duration
//! rectangular-pulse collapse spectrum of the slender block (0.1 × 0.1 × 1 m) on the exact
//! engine; and an 84-block dome (6 courses × 14) under 10 s of the record.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;
use voussoir::dynamics::{Engine, Excitation, GroundMotion, Record};
use voussoir::geometry::{Mesh, Point3};
use voussoir::model::{Assembly, Block, Scene, builtin};
use voussoir::studies::shake::{ShakeSettings, SpectrumSettings, collapse_spectrum, shake};

/// The allocator the `voussoir` binary runs on (src/main.rs): the engines timed as they run there.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// El Centro's first 10 s along +x.
fn elcentro() -> GroundMotion {
    let record = voussoir::io::accelerogram::load_record("builtin:elcentro").unwrap();
    GroundMotion::horizontal(Excitation::Record(Arc::new(Record::new(record))), 0.0)
}

fn ten_seconds(engine: Engine) -> ShakeSettings {
    let mut settings = ShakeSettings { duration: Some(10.0), ..Default::default() };
    settings.drop.engine = engine;
    settings
}

fn assembly(spec: &str) -> Assembly {
    Assembly::new(&builtin(spec).unwrap(), &Default::default()).unwrap()
}

fn arches(c: &mut Criterion) {
    let motion = elcentro();
    let mut g = c.benchmark_group("shake/arch_elcentro_10s");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    for spec in ["arch?n=15&t=0.25", "arch?n=15&t=0.15"] {
        let asm = assembly(spec);
        for engine in [Engine::Exact, Engine::Rapier] {
            let settings = ten_seconds(engine);
            g.bench_function(format!("{}/{spec}", engine.name()), |b| {
                b.iter(|| black_box(shake(&asm, &settings, &motion).unwrap()))
            });
        }
    }
    g.finish();
}

fn spectrum(c: &mut Criterion) {
    let mesh = Mesh::cuboid(Point3::new(-0.05, -0.05, 0.0), Point3::new(0.05, 0.05, 1.0));
    let mut block = Scene::new("slender block", vec![Block::new("block", mesh)]);
    block.ground = true;
    let asm = Assembly::new(&block, &Default::default()).unwrap();
    let p = (3.0 * 9.81 / (4.0 * 0.5025f64)).sqrt();
    // p t_p from 0.5 to 20, evenly in its logarithm.
    let durations = (0..20).map(|k| 0.5 * 40f64.powf(k as f64 / 19.0) / p).collect();
    let settings = SpectrumSettings { durations, ..Default::default() };
    let mut g = c.benchmark_group("shake/spectrum_20_durations");
    g.sample_size(10).measurement_time(Duration::from_secs(60));
    g.bench_function("exact/slender block", |b| {
        b.iter(|| black_box(collapse_spectrum(&asm, 0.1, &settings, &|| {}).unwrap()))
    });
    g.finish();
}

fn dome(c: &mut Criterion) {
    let motion = elcentro();
    let asm = assembly("dome?courses=6&blocks=14");
    let mut g = c.benchmark_group("shake/dome_84_elcentro_10s");
    g.sample_size(10).measurement_time(Duration::from_secs(60));
    for engine in [Engine::Exact, Engine::Rapier] {
        let settings = ten_seconds(engine);
        g.bench_function(engine.name(), |b| b.iter(|| black_box(shake(&asm, &settings, &motion).unwrap())));
    }
    g.finish();
}

criterion_group!(benches, arches, spectrum, dome);
criterion_main!(benches);
