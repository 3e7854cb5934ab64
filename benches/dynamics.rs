//! The rapier drop test: 2 s simulated at the default dt (1/240 s) for a 15-voussoir arch and
//! a 10 × 10 running-bond wall; the cost per body-step is the median / (steps × bodies).
//! (The Armadillo, 399 bodies, 10 s simulated, is timed with `voussoir drop` — see
//! docs/benchmarks.md — as one run takes tens of seconds.)

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
}

criterion_group!(benches, drops);
criterion_main!(benches);
