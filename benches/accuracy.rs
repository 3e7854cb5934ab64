//! Run time against error: for each friction model and interior-point tolerance, the error of
//! the statics against analytic limits, and its cost. Writes docs/accuracy.md (table) and
//! docs/accuracy.svg (plot). Run: `cargo bench --bench accuracy`.
//!
//! Experiments (each a bisection on the verdict, 1e-7 relative):
//! - friction: a block on a flat support under gravity tilted by θ towards azimuth φ from the
//!   interface's u axis; Coulomb slides at tan θ = μ. Error = tan θ*/μ − 1 (φ = 0: every model
//!   exact; φ = 22.5°: the octagon's worst, +8.2 %; φ = 45°: the box's worst, +41 %).
//! - harmonic stack, n = 10: the overhang scale s* at the limit (exact: 1).
//! - semicircular arch, N = 100 voussoirs: the minimum thickness t*/R (Milankovitch's
//!   N → ∞ value 0.1075; finite N differ).
//! - beam on two narrow supports: reaction vs the lever rule (w = 1e-3: O(w²) ≈ 1e-7).
//! - mixed friction, arch N = 100 (Cocchetti & Rizzi 2020, N → ∞): at 1.001 × its own minimum
//!   thickness the arch keeps standing down to μ = 0.3958 (purely rotational collapse above);
//!   and no thickness stands below μ = 0.3092 (minimum over t of the lowest μ at which the arch
//!   of thickness t stands; golden section over t, cone at 1e-8 only — 300 solves).

use plotters::prelude::*;
use std::time::Instant;
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Block, Scene, builtin};
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::statics::FrictionModel;

struct Row {
    model: FrictionModel,
    tol: f64,
    experiment: &'static str,
    value: f64,
    error: f64,
    solves: usize,
    ms_per_solve: f64,
}

fn settings(model: FrictionModel, tol: f64) -> AnalysisSettings {
    let mut s = AnalysisSettings::default();
    s.statics.friction_model = model;
    s.statics.solver_tolerance = tol;
    s
}

/// Bisection on `stands(x)` between a standing `ok` and a failing `fail` (either order).
fn bisect(mut ok: f64, mut fail: f64, mut stands: impl FnMut(f64) -> bool) -> (f64, usize) {
    let mut n = 0;
    while (fail - ok).abs() > 1e-7 * fail.abs().max(1e-3) {
        let mid = 0.5 * (ok + fail);
        n += 1;
        if stands(mid) { ok = mid } else { fail = mid }
    }
    (0.5 * (ok + fail), n)
}

fn tilted(theta: f64, phi: f64) -> Scene {
    let mut s = Scene::new(
        "tilted gravity",
        vec![
            Block::new("base", Mesh::cuboid(Point3::new(-1.0, -1.0, -0.5), Point3::new(2.0, 2.0, 0.0))).support(true),
            Block::new("block", Mesh::cuboid(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 0.1))),
        ],
    );
    s.material.friction = 0.5;
    s.gravity = Vector3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), -theta.cos()) * 9.81;
    s
}

fn arch_stands(t: f64, mu: f64, set: &AnalysisSettings) -> bool {
    let mut set = set.clone();
    set.statics.friction = Some(mu);
    analyze(&builtin(&format!("arch?n=100&t={t}")).unwrap(), &set).unwrap().statics.stands
}

/// min over t of μ*(t), the lowest μ at which the arch of thickness t stands (golden section on
/// t ∈ [0.11, 0.6], above the rotational minimum); returns (μ, solves).
fn lowest_mu_any_thickness(set: &AnalysisSettings) -> (f64, usize) {
    let mut solves = 0;
    let mut mu_star = |t: f64| {
        let (mu, n) = bisect(1.0, 0.1, |mu| arch_stands(t, mu, set));
        solves += n;
        mu
    };
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (0.11, 0.6);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (mu_star(c), mu_star(d));
    for _ in 0..14 {
        if fc < fd {
            b = d;
            (d, fd) = (c, fc);
            c = b - g * (b - a);
            fc = mu_star(c);
        } else {
            a = c;
            (c, fc) = (d, fd);
            d = a + g * (b - a);
            fd = mu_star(d);
        }
    }
    (fc.min(fd), solves)
}

fn run_all() -> Vec<Row> {
    let mut rows = Vec::new();
    for model in [FrictionModel::Box4, FrictionModel::Pyramid8, FrictionModel::Cone] {
        for tol in [1e-6, 1e-8, 1e-10] {
            let set = settings(model, tol);
            let mut time = |experiment: &'static str, f: &mut dyn FnMut() -> (f64, usize), exact: f64| {
                let t = Instant::now();
                let (value, solves) = f();
                let ms = 1e3 * t.elapsed().as_secs_f64() / solves.max(1) as f64;
                rows.push(Row { model, tol, experiment, value, error: value / exact - 1.0, solves, ms_per_solve: ms });
            };
            for (name, phi) in [("slide φ=0°", 0.0f64), ("slide φ=22.5°", 22.5), ("slide φ=45°", 45.0)] {
                time(
                    name,
                    &mut || {
                        let (th, n) =
                            bisect(0.1, 1.0, |th| analyze(&tilted(th, phi.to_radians()), &set).unwrap().statics.stands);
                        (th.tan(), n)
                    },
                    0.5,
                );
            }
            time(
                "harmonic n=10 s*",
                &mut || {
                    bisect(0.95, 1.05, |s| {
                        analyze(&builtin(&format!("harmonic?n=10&s={s}")).unwrap(), &set).unwrap().statics.stands
                    })
                },
                1.0,
            );
            let mut t_rot = 0.1075;
            time(
                "arch N=100 t*/R",
                &mut || {
                    let (t, n) = bisect(0.2, 0.05, |t| {
                        analyze(&builtin(&format!("arch?n=100&t={t}")).unwrap(), &set).unwrap().statics.stands
                    });
                    t_rot = t;
                    (t, n)
                },
                0.1075,
            );
            time(
                "arch μ keeping t* (0.3958)",
                &mut || bisect(0.8, 0.25, |mu| arch_stands(1.001 * t_rot, mu, &set)),
                0.3958,
            );
            if model == FrictionModel::Cone && tol == 1e-8 {
                time("arch μ for any t (0.3092)", &mut || lowest_mu_any_thickness(&set), 0.3092);
            }
            time(
                "beam lever rule",
                &mut || {
                    let (xa, xb, w) = (0.5, 3.0, 1e-3);
                    let s = Scene::new(
                        "beam",
                        vec![
                            Block::new(
                                "sa",
                                Mesh::cuboid(Point3::new(xa - w / 2.0, 0.0, -0.2), Point3::new(xa + w / 2.0, 0.2, 0.0)),
                            )
                            .support(true),
                            Block::new(
                                "sb",
                                Mesh::cuboid(Point3::new(xb - w / 2.0, 0.0, -0.2), Point3::new(xb + w / 2.0, 0.2, 0.0)),
                            )
                            .support(true),
                            Block::new("beam", Mesh::cuboid(Point3::new(0.0, 0.0, 0.0), Point3::new(4.0, 0.2, 0.2))),
                        ],
                    );
                    let r = analyze(&s, &set).unwrap().statics;
                    let ra = r.interfaces.iter().find(|i| i.a == "sa").unwrap().normal_force;
                    (ra / r.free_weight, 1)
                },
                (3.0 - 2.0) / (3.0 - 0.5),
            );
        }
    }
    rows
}

fn write(rows: &[Row]) -> std::io::Result<()> {
    let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
    let mut md = String::from(
        "## Log\n\nGenerated by `cargo bench --bench accuracy` (benches/accuracy.rs explains each \
         experiment). Error = value / exact − 1; time = wall time per analysis (validate + detect + solve), \
         averaged over the bisection's solves, on the shared 2-core machine.\n\n\
         | experiment | model | tolerance | value | exact | error | solves | ms / solve |\n|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let exact = r.value / (1.0 + r.error);
        md.push_str(&format!(
            "| {} | {} | {:.0e} | {:.7} | {:.4} | {:+.2e} | {} | {:.2} |\n",
            r.experiment, r.model, r.tol, r.value, exact, r.error, r.solves, r.ms_per_solve
        ));
    }
    md.push_str("\n![error against time](accuracy.svg)\n");
    let page = with_summary(&docs.join("accuracy.md"), &md)?;
    voussoir::io::write_atomic(&docs.join("accuracy.md"), page.as_bytes()).map_err(std::io::Error::other)?;

    voussoir::viz::plot::register_font();
    let svg = docs.join("accuracy.svg");
    let root = SVGBackend::new(&svg, (900, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(std::io::Error::other)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("|error| against time per analysis (● cone, ▲ pyramid8, ✕ box4)", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((0.05f64..500.0).log_scale(), (1e-10f64..1.0).log_scale())
        .map_err(std::io::Error::other)?;
    chart
        .configure_mesh()
        .x_desc("ms per analysis")
        .y_desc("|value / exact − 1|")
        .x_label_formatter(&|x| format!("{x}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(std::io::Error::other)?;
    let colors = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];
    let experiments: Vec<&str> = {
        let mut e: Vec<&str> = rows.iter().map(|r| r.experiment).collect();
        e.dedup();
        e.sort();
        e.dedup();
        e
    };
    for (k, exp) in experiments.iter().enumerate() {
        let color = colors[k % colors.len()];
        let pts: Vec<(f64, f64, FrictionModel)> = rows
            .iter()
            .filter(|r| r.experiment == *exp)
            .map(|r| (r.ms_per_solve.max(0.05), r.error.abs().clamp(1e-10, 1.0), r.model))
            .collect();
        let marker = move |(x, y, m): (f64, f64, FrictionModel)| -> DynElement<'static, SVGBackend, (f64, f64)> {
            match m {
                FrictionModel::Cone => Circle::new((x, y), 4, color.filled()).into_dyn(),
                FrictionModel::Pyramid8 => TriangleMarker::new((x, y), 5, color.filled()).into_dyn(),
                FrictionModel::Box4 => Cross::new((x, y), 4, color.stroke_width(2)).into_dyn(),
            }
        };
        chart
            .draw_series(pts.into_iter().map(marker))
            .map_err(std::io::Error::other)?
            .label(*exp)
            .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(std::io::Error::other)?;
    root.present().map_err(std::io::Error::other)?;
    Ok(())
}

fn main() {
    // `cargo bench` passes criterion-style flags; `cargo test --benches` passes none and only
    // checks that this builds, so run the study only under `cargo bench`.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let rows = run_all();
    for r in &rows {
        println!(
            "{:18} {:9} {:.0e}  value {:.7}  error {:+.2e}  {:.2} ms/solve",
            r.experiment, r.model, r.tol, r.value, r.error, r.ms_per_solve
        );
    }
    if let Err(e) = write(&rows) {
        eprintln!("cannot write docs/accuracy.*: {e}");
        std::process::exit(1);
    }
    println!("wrote docs/accuracy.md and docs/accuracy.svg");
}

/// The page with `log` as its Log section: the summary above "## Log" (written by hand from
/// the log, "Where things stand") is kept; a page without one gets a title.
fn with_summary(path: &std::path::Path, log: &str) -> std::io::Result<String> {
    let old = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(e) => return Err(e),
    };
    let summary = old.find("## Log").map_or("# Accuracy: run time against error\n\n", |at| &old[..at]);
    Ok(format!("{summary}{log}"))
}
