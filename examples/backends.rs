//! Structured interior-point method against clarabel on the same problems: medians of 5
//! runs, verdicts, graded numbers and the largest per-interface force difference.
//! `cargo run --release --example backends [scene …]` (default: a mixed set).
use std::time::Instant;
use voussoir::interfaces::detect;
use voussoir::io::load_scene;
use voussoir::model::{Assembly, Scene, builtin};
use voussoir::statics::{self, Backend, FrictionModel, StaticsResult, StaticsSettings};

fn scene(spec: &str) -> Scene {
    match spec.strip_prefix("builtin:") {
        Some(b) => builtin(b).unwrap(),
        None => load_scene(std::path::Path::new(spec)).unwrap(),
    }
}

fn main() {
    let compas_data = |rel: &str| format!("{}/assets/compas/{rel}", env!("CARGO_MANIFEST_DIR"));
    let mut specs: Vec<String> = std::env::args().skip(1).collect();
    if specs.is_empty() {
        specs = vec![
            compas_data("compas_cra/armadillo_cra.json"),
            compas_data("compas_assembly/dome_assembly.json"),
            "builtin:wall?courses=10&bricks=10".into(),
            "builtin:wall?courses=20&bricks=20".into(),
            "builtin:arch?n=40&t=0.10".into(),
            "builtin:arch?n=40&t=0.115".into(),
            "builtin:slope?angle=35".into(),
        ];
    }
    for spec in specs {
        let asm = Assembly::new(&scene(&spec), &Default::default()).unwrap();
        let ifs = detect(&asm);
        let name = spec.rsplit('/').next().unwrap().to_string();
        for model in [FrictionModel::Pyramid8, FrictionModel::Box4] {
            let run = |backend: Backend| -> (f64, StaticsResult) {
                let settings = StaticsSettings { friction_model: model, backend, ..Default::default() };
                let mut times = Vec::new();
                let mut last = None;
                for _ in 0..5 {
                    let t = Instant::now();
                    last = Some(statics::solve(&asm, &ifs, &settings).unwrap());
                    times.push(t.elapsed().as_secs_f64());
                }
                times.sort_by(f64::total_cmp);
                (times[2], last.unwrap())
            };
            let (ts, rs) = run(Backend::Structured);
            let (tc, rc) = run(Backend::Clarabel);
            let w = rs.free_weight;
            let df = rs
                .interfaces
                .iter()
                .zip(&rc.interfaces)
                .map(|(a, b)| (a.normal_force - b.normal_force).abs().max((a.friction - b.friction).abs()))
                .fold(0.0, f64::max)
                / w;
            println!(
                "{name:28} {model:?}: structured {:7.1} ms it {:3} {:?} | clarabel {:7.1} ms it {:3} {:?} | ×{:.1} | T {:.3e}/{:.3e} F {:.3e}/{:.3e} | Δforce {:.1e} W res {:.0e}/{:.0e}",
                1e3 * ts,
                rs.solver.iterations,
                rs.solver.status,
                1e3 * tc,
                rc.solver.iterations,
                rc.solver.status,
                tc / ts,
                rs.tension_ratio,
                rc.tension_ratio,
                rs.friction_excess_ratio,
                rc.friction_excess_ratio,
                df,
                rs.solver.residual / w,
                rc.solver.residual / w,
            );
        }
    }
}
