//! The drop test: 2 s simulated at the default dt (1/240 s) for a 15-voussoir arch and a
//! 10 × 10 running-bond wall on both engines; the goal of issue #7: the Armadillo (399 bodies),
//! 10 s simulated (2400 steps) on rapier, and 2 s on both engines; and the exact engine on a
//! collapsing arch (t/R 0.08, 2 s: every step solved), its steps on the structured solver warm-
//! started and cold, with plain Tresca rounds, and on clarabel. The cost per body-step is the
//! median / (steps × bodies).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::dynamics::{DropSettings, Engine, drop_test};
use voussoir::geometry::{Mesh, Point3};
use voussoir::model::{Assembly, Block, Scene, builtin};
use voussoir::statics::Backend;

/// The allocator the `voussoir` binary runs on (src/main.rs): the engines timed as they run there.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn drops(c: &mut Criterion) {
    let mut g = c.benchmark_group("dynamics/drop_2s");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let exact = DropSettings { engine: Engine::Exact, ..Default::default() };
    for spec in ["arch?n=15&t=0.15", "wall?courses=10&bricks=10"] {
        let mut scene = builtin(spec).unwrap();
        if spec.starts_with("wall") {
            scene.ground = true;
        }
        let asm = Assembly::new(&scene, &Default::default()).unwrap();
        g.bench_function(spec, |b| b.iter(|| black_box(drop_test(&asm, &DropSettings::default()).unwrap())));
        g.bench_function(format!("exact/{spec}"), |b| b.iter(|| black_box(drop_test(&asm, &exact).unwrap())));
    }
    let asm = Assembly::new(&builtin("arch?n=15&t=0.08").unwrap(), &Default::default()).unwrap();
    g.bench_function("exact/collapsing arch?n=15&t=0.08", |b| b.iter(|| black_box(drop_test(&asm, &exact).unwrap())));
    g.bench_function("collapsing arch?n=15&t=0.08", |b| {
        b.iter(|| black_box(drop_test(&asm, &DropSettings::default()).unwrap()))
    });
    // Every moving step by the Tresca rounds (no step by the contacts' states): the states' share.
    let mut rounds = exact.clone();
    rounds.exact.by_states = false;
    g.bench_function("exact_rounds/collapsing arch?n=15&t=0.08", |b| {
        b.iter(|| black_box(drop_test(&asm, &rounds).unwrap()))
    });
    // Each structured solve cold (no kept iterate): the warm starts' share.
    let mut cold = exact.clone();
    cold.exact.warm_start = false;
    g.bench_function("exact_cold/collapsing arch?n=15&t=0.08", |b| {
        b.iter(|| black_box(drop_test(&asm, &cold).unwrap()))
    });
    // The Tresca rounds plain (c ← μ f_n until the capacities stop changing): the accelerated
    // rounds' share.
    let mut plain = exact.clone();
    plain.exact.accelerate_rounds = false;
    g.bench_function("exact_plain_rounds/collapsing arch?n=15&t=0.08", |b| {
        b.iter(|| black_box(drop_test(&asm, &plain).unwrap()))
    });
    // The same steps on clarabel (every step problem as a general conic problem): the ratio.
    let mut on_clarabel = exact.clone();
    on_clarabel.exact.backend = Backend::Clarabel;
    g.bench_function("exact_clarabel/collapsing arch?n=15&t=0.08", |b| {
        b.iter(|| black_box(drop_test(&asm, &on_clarabel).unwrap()))
    });
    g.finish();
    arches(c, &exact);
    rocking(c, &exact, &rounds);
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/armadillo_cra.json");
    let mut scene = voussoir::io::load_scene(&path).unwrap();
    scene.material.friction = 0.84;
    let asm = Assembly::new(&scene, &Default::default()).unwrap();
    let mut g = c.benchmark_group("dynamics/armadillo_2s");
    g.sample_size(10).measurement_time(Duration::from_secs(60));
    g.bench_function("rapier", |b| b.iter(|| black_box(drop_test(&asm, &DropSettings::default()).unwrap())));
    g.bench_function("exact", |b| b.iter(|| black_box(drop_test(&asm, &exact).unwrap())));
    g.finish();
    let settings = DropSettings { duration: 10.0, ..Default::default() };
    let mut g = c.benchmark_group("dynamics/drop_10s");
    g.sample_size(10).measurement_time(Duration::from_secs(45));
    g.bench_function("armadillo", |b| b.iter(|| black_box(drop_test(&asm, &settings).unwrap())));
    g.finish();
}

/// Six collapsing arches (15/13/17/11/19/9 voussoirs, t/R 0.06–0.08), 2 s each, one after
/// another: a collapse is chaotic after its blocks land (round-off picks the trajectory, and
/// with it how many steps need the rounds), so one arch's time is partly its draw; the six
/// together measure the engine.
fn arches(c: &mut Criterion, exact: &DropSettings) {
    let specs = [
        "arch?n=15&t=0.08",
        "arch?n=13&t=0.08",
        "arch?n=17&t=0.07",
        "arch?n=11&t=0.06",
        "arch?n=19&t=0.08",
        "arch?n=9&t=0.07",
    ];
    let arches: Vec<Assembly> =
        specs.iter().map(|s| Assembly::new(&builtin(s).unwrap(), &Default::default()).unwrap()).collect();
    let all = |s: &DropSettings| arches.iter().filter(|a| !drop_test(a, s).unwrap().stands).count();
    let mut g = c.benchmark_group("dynamics/six_collapsing_arches_2s");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.bench_function("exact", |b| b.iter(|| black_box(all(exact))));
    g.bench_function("rapier", |b| b.iter(|| black_box(all(&DropSettings::default()))));
    g.finish();
}

/// Housner's slender block (0.2 × 0.2 × 1 m, leaning 8° on its edge on the ground plane), 4 s
/// at the default dt: by the contacts' states, by the rounds, and on rapier.
fn rocking(c: &mut Criterion, exact: &DropSettings, rounds: &DropSettings) {
    let (b, h, theta) = (0.1f64, 0.5f64, 8f64.to_radians());
    let (s, co) = theta.sin_cos();
    let mesh = Mesh::cuboid(Point3::new(-b, -b, 0.0), Point3::new(b, b, 2.0 * h)).map_points(|p| {
        let x = p.x - b;
        Point3::new(b + co * x + s * p.z, p.y, -s * x + co * p.z)
    });
    let mut scene = Scene::new("rocking", vec![Block::new("block", mesh)]);
    scene.ground = true;
    let asm = Assembly::new(&scene, &Default::default()).unwrap();
    let four = |s: &DropSettings| DropSettings { duration: 4.0, ..s.clone() };
    let mut g = c.benchmark_group("dynamics/rocking_4s");
    g.sample_size(20).measurement_time(Duration::from_secs(8));
    g.bench_function("exact", |bch| bch.iter(|| black_box(drop_test(&asm, &four(exact)).unwrap())));
    g.bench_function("exact_rounds", |bch| bch.iter(|| black_box(drop_test(&asm, &four(rounds)).unwrap())));
    g.bench_function("rapier", |bch| bch.iter(|| black_box(drop_test(&asm, &four(&DropSettings::default())).unwrap())));
    g.finish();
}

criterion_group!(benches, drops);
criterion_main!(benches);
