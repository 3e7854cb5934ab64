//! The equilibrium solve: the Armadillo full pipeline (load + validate + detect + solve), the
//! dome, running-bond walls of 100 … 4000 bricks and semicircular arches of 10 … 1000
//! voussoirs, for each friction model (default backend: structured), and pyramid8 on clarabel
//! (`pyramid8-clarabel`) for the ratio. Sizes can be narrowed with criterion's filter
//! (`cargo bench --bench statics -- wall`); `statics/factorisation` compares S factored by 6×6
//! blocks and by faer in one run.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;
use voussoir::interfaces::detect;
use voussoir::io::load_scene;
use voussoir::model::{Assembly, builtin};
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::statics::{self, Backend, FrictionModel, StaticsSettings, kernel_profile};

const MODELS: [FrictionModel; 3] = [FrictionModel::Pyramid8, FrictionModel::Cone, FrictionModel::Box4];

fn compas_data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/compas").join(rel)
}

fn settings(model: FrictionModel) -> StaticsSettings {
    StaticsSettings { friction_model: model, ..Default::default() }
}

fn real_data(c: &mut Criterion) {
    let mut g = c.benchmark_group("statics/real");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let armadillo = load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
    let armadillo = Assembly::new(&armadillo, &Default::default()).unwrap();
    let armadillo_ifs = detect(&armadillo);
    for model in MODELS {
        // The solve alone (issue #43's goal: ≤ 45 ms for pyramid8).
        let mut solve_settings = settings(model);
        solve_settings.friction = Some(0.84);
        g.bench_function(BenchmarkId::new("armadillo_solve", model), |b| {
            b.iter(|| black_box(statics::solve(&armadillo, &armadillo_ifs, &solve_settings).unwrap()))
        });
        g.bench_function(BenchmarkId::new("armadillo_pipeline", model), |b| {
            b.iter(|| {
                let scene = load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
                let mut s = AnalysisSettings { statics: settings(model), ..Default::default() };
                s.statics.friction = Some(0.84);
                black_box(analyze(&scene, &s).unwrap())
            })
        });
        if model == FrictionModel::Pyramid8 {
            // The same on clarabel's general LDL: the structured backend's gain.
            g.bench_function(BenchmarkId::new("armadillo_pipeline", "pyramid8-clarabel"), |b| {
                b.iter(|| {
                    let scene = load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
                    let mut s = AnalysisSettings { statics: settings(model), ..Default::default() };
                    s.statics.friction = Some(0.84);
                    s.statics.backend = Backend::Clarabel;
                    black_box(analyze(&scene, &s).unwrap())
                })
            });
        }
        let scene = load_scene(&compas_data("compas_assembly/dome_assembly.json")).unwrap();
        let asm = Assembly::new(&scene, &Default::default()).unwrap();
        let ifs = detect(&asm);
        g.bench_function(BenchmarkId::new("dome_solve", model), |b| {
            b.iter(|| black_box(statics::solve(&asm, &ifs, &settings(model)).unwrap()))
        });
    }
    g.finish();
}

fn parametric(c: &mut Criterion, group: &str, specs: &[(usize, String)]) {
    let mut g = c.benchmark_group(group);
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    for model in MODELS {
        for (size, spec) in specs {
            let asm = Assembly::new(&builtin(spec).unwrap(), &Default::default()).unwrap();
            let ifs = detect(&asm);
            let inputs = (asm, ifs);
            g.bench_with_input(BenchmarkId::new(model.to_string(), size), &inputs, |b, (asm, ifs)| {
                b.iter(|| black_box(statics::solve(asm, ifs, &settings(model)).unwrap()))
            });
            if model == FrictionModel::Pyramid8 {
                let clarabel = StaticsSettings { backend: Backend::Clarabel, ..settings(model) };
                g.bench_with_input(BenchmarkId::new("pyramid8-clarabel", size), &inputs, |b, (asm, ifs)| {
                    b.iter(|| black_box(statics::solve(asm, ifs, &clarabel).unwrap()))
                });
            }
        }
    }
    g.finish();
}

fn walls(c: &mut Criterion) {
    // courses × bricks ≈ 100, 400, 1000, 4000 (odd courses have one piece more).
    let specs: Vec<(usize, String)> = [(10, 10), (20, 20), (32, 31), (63, 63)]
        .iter()
        .map(|&(c, b)| (c * b, format!("wall?courses={c}&bricks={b}")))
        .collect();
    parametric(c, "statics/wall", &specs);
}

fn arches(c: &mut Criterion) {
    let specs: Vec<(usize, String)> =
        [10, 30, 100, 300, 1000].iter().map(|&n| (n, format!("arch?n={n}&t=0.15"))).collect();
    parametric(c, "statics/arch", &specs);
}

/// What solving independent components separately saves: 40 stacks of 5 cubes (and the same
/// stacks with one leaning block so that the relaxed stages run), split vs one merged problem.
fn skip(c: &mut Criterion) {
    let mut g = c.benchmark_group("statics/skip");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    let mut leaning = builtin("stacks?k=40&n=5").unwrap();
    // Shift the top block of the first stack sideways past its support's edge: it needs tension.
    let top = leaning.blocks.iter_mut().find(|b| b.name == "s0b4").unwrap();
    top.mesh = top.mesh.scaled_translated(1.0, voussoir::geometry::Vector3::new(0.0, 0.6, 0.0));
    for (name, scene) in [("stacks_standing", builtin("stacks?k=40&n=5").unwrap()), ("stacks_one_failing", leaning)] {
        let asm = Assembly::new(&scene, &Default::default()).unwrap();
        let ifs = detect(&asm);
        for split in [true, false] {
            let s = StaticsSettings { split_components: split, ..Default::default() };
            let id = if split { "split" } else { "merged" };
            g.bench_function(BenchmarkId::new(name, id), |b| {
                b.iter(|| black_box(statics::solve(&asm, &ifs, &s).unwrap()))
            });
        }
    }
    g.finish();
}

/// S factored by 6×6 blocks (the default at these sizes) against faer's supernodal Cholesky,
/// in one run: the Armadillo, the dome and a 1000-brick wall, pyramid8.
fn factorisation(c: &mut Criterion) {
    let mut g = c.benchmark_group("statics/factorisation");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let scenes = [
        ("armadillo", load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap()),
        ("dome", load_scene(&compas_data("compas_assembly/dome_assembly.json")).unwrap()),
        ("wall1000", builtin("wall?courses=32&bricks=31").unwrap()),
    ];
    for (name, scene) in scenes {
        let asm = Assembly::new(&scene, &Default::default()).unwrap();
        let ifs = detect(&asm);
        let mut s = settings(FrictionModel::Pyramid8);
        s.friction = Some(0.84);
        for (id, blocks) in [("blocks", true), ("faer", false)] {
            g.bench_function(BenchmarkId::new(name, id), |b| {
                kernel_profile::factor_by_blocks(blocks);
                b.iter(|| black_box(statics::solve(&asm, &ifs, &s).unwrap()));
                kernel_profile::factor_by_blocks(true);
            });
        }
    }
    g.finish();
}

criterion_group!(benches, real_data, walls, arches, skip, factorisation);
criterion_main!(benches);
