//! Quick wall-clock timing of the statics on a few scenes (medians of 5 runs); the criterion
//! benches are the reference, this is for fast experiments: `cargo run --release --example timing`.
use std::time::Instant;
use voussoir::interfaces::detect;
use voussoir::io::load_scene;
use voussoir::model::{Assembly, Scene, builtin};
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::{self, FrictionModel, StaticsSettings};

fn main() {
    let tol: f64 = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(1e-10);
    let compas_data = |rel: &str| format!("{}/assets/compas/{rel}", env!("CARGO_MANIFEST_DIR"));
    let scenes: Vec<(String, Scene)> = vec![
        ("armadillo".into(), load_scene(std::path::Path::new(&compas_data("compas_cra/armadillo_cra.json"))).unwrap()),
        ("dome".into(), load_scene(std::path::Path::new(&compas_data("compas_assembly/dome_assembly.json"))).unwrap()),
        ("wall400".into(), builtin("wall?courses=20&bricks=20").unwrap()),
        ("wall1000".into(), builtin("wall?courses=32&bricks=31").unwrap()),
        ("arch1000".into(), builtin("arch?n=1000&t=0.15").unwrap()),
    ];
    let _ = AnalysisSettings::default();
    for (name, scene) in scenes {
        let asm = Assembly::new(&scene, &Default::default()).unwrap();
        let ifs = detect(&asm);
        for model in [FrictionModel::Pyramid8, FrictionModel::Cone] {
            let settings = StaticsSettings { friction_model: model, solver_tolerance: tol, ..Default::default() };
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..5 {
                let t = Instant::now();
                last = Some(statics::solve(&asm, &ifs, &settings).unwrap());
                times.push(t.elapsed().as_secs_f64());
            }
            times.sort_by(f64::total_cmp);
            let r = last.unwrap();
            let pts: usize = ifs.iter().map(|i| i.polygon.len()).sum();
            println!(
                "{name:10} {model:9} pts {pts:6} median {:8.1} ms  it {:3} {:?} res {:.1e} W",
                1e3 * times[2],
                r.solver.iterations,
                r.verdict,
                r.solver.residual / r.free_weight
            );
        }
    }
}
