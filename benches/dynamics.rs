//! The rapier drop test: 2 s simulated at the default dt (1/240 s) for a 15-voussoir arch and
//! a 10 × 10 running-bond wall, and the goal of issue #7: the Armadillo (399 bodies), 10 s
//! simulated (2400 steps). The cost per body-step is the median / (steps × bodies).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use voussoir::dynamics::{DropSettings, drop_test};
use voussoir::model::{Assembly, builtin};

fn drops(c: &mut Criterion) {
    let mut g = c.benchmark_group("dynamics/drop_2s");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for spec in ["arch?n=15&t=0.15", "wall?courses=10&bricks=10"] {
        let mut scene = builtin(spec).unwrap();
        if spec.starts_with("wall") {
            scene.ground = true;
        }
        let asm = Assembly::new(&scene, &Default::default()).unwrap();
        g.bench_function(spec, |b| b.iter(|| black_box(drop_test(&asm, &DropSettings::default()).unwrap())));
    }
    g.finish();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/armadillo_cra.json");
    let mut scene = voussoir::io::load_scene(&path).unwrap();
    scene.material.friction = 0.84;
    let asm = Assembly::new(&scene, &Default::default()).unwrap();
    let settings = DropSettings { duration: 10.0, ..Default::default() };
    let mut g = c.benchmark_group("dynamics/drop_10s");
    g.sample_size(10).measurement_time(Duration::from_secs(45));
    g.bench_function("armadillo", |b| b.iter(|| black_box(drop_test(&asm, &settings).unwrap())));
    g.finish();
}

criterion_group!(benches, drops);
criterion_main!(benches);
