//! Interface detection on the BRG reference assemblies (dome 527 blocks, Armadillo 399):
//! validation (repair + mass properties) and detection separately.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::PathBuf;
use voussoir::interfaces::detect;
use voussoir::io::load_scene;
use voussoir::model::Assembly;

fn compas_data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/compas").join(rel)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("detection");
    for (name, rel) in [("dome", "compas_assembly/dome_assembly.json"), ("armadillo", "compas_cra/armadillo_cra.json")]
    {
        let scene = load_scene(&compas_data(rel)).expect("reference data beside the checkout");
        let asm = Assembly::new(&scene, &Default::default()).expect("valid");
        g.bench_function(format!("{name}/detect"), |b| b.iter(|| black_box(detect(black_box(&asm)))));
        g.bench_function(format!("{name}/validate"), |b| {
            b.iter(|| black_box(Assembly::new(black_box(&scene), &Default::default()).unwrap()))
        });
        g.bench_function(format!("{name}/load"), |b| b.iter(|| black_box(load_scene(&compas_data(rel)).unwrap())));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
