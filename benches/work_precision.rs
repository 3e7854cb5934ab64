//! Work against precision of both engines, dt from 1/60 to 1/4000 s: the error of the fourth
//! rocking peak of Housner's slender block (0.2 × 0.2 × 1 m leaning 8° on its edge on the ground
//! plane, 4 s; the closed form: the energy at a peak m g R (cos(α − θ) − cos α), times η² per
//! impact, η = 1 − 1.5 sin² α) and of the 16-voussoir arch's (t/R 0.15) tilt threshold (bisection
//! on the drop test's verdict, 10 halvings of 0–20°, 2 s a test, in tan; the reference the statics'
//! threshold by 30 halvings), each against its wall time (a rocking run; a drop test). Writes
//! docs/drop_work_precision.md (table) and docs/drop_work_precision.svg (plot). Run:
//! `cargo bench --bench work_precision`.

use plotters::prelude::*;
use std::fmt::Write;
use std::time::Instant;
use voussoir::dynamics::{DropRun, DropSettings, Engine, drop_test};
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Assembly, Block, Scene, builtin};
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::studies::threshold::Family;

mod common;

use common::bisect;

/// The allocator the `voussoir` binary runs on (src/main.rs): the engines timed as they run there.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const STEPS: [f64; 7] = [60.0, 120.0, 240.0, 480.0, 1000.0, 2000.0, 4000.0];
const ENGINES: [Engine; 2] = [Engine::Exact, Engine::Rapier];

/// One measurement: what, on which engine, at which dt, its error and its wall time (ms).
struct Row {
    what: &'static str,
    engine: Engine,
    per_second: f64,
    error: f64,
    ms: f64,
}

/// Housner's peak after four impacts of a 2b × 2h block released at `theta0` (rad).
fn housner_fourth(b: f64, h: f64, theta0: f64) -> f64 {
    let alpha = b.atan2(h);
    let eta = 1.0 - 1.5 * alpha.sin().powi(2);
    let energy = ((alpha - theta0).cos() - alpha.cos()) * eta.powi(8);
    alpha - (energy + alpha.cos()).acos()
}

/// The slender block on the ground, turned by `theta` about its edge at x = b.
fn leaning(theta: f64, b: f64, h: f64) -> Scene {
    let (s, c) = theta.sin_cos();
    let mesh = Mesh::cuboid(Point3::new(-b, -b, 0.0), Point3::new(b, b, 2.0 * h)).map_points(|p| {
        let x = p.x - b;
        Point3::new(b + c * x + s * p.z, p.y, -s * x + c * p.z)
    });
    let mut scene = Scene::new("rocking", vec![Block::new("block", mesh)]);
    scene.ground = true;
    scene
}

/// The engine's fourth peak after the start (rad; each peak the vertex of the parabola through
/// the samples around a sampled extreme) and the run's wall time (ms).
fn rocked(asm: &Assembly, settings: &DropSettings, theta0: f64) -> (f64, f64) {
    let t = Instant::now();
    let mut run = DropRun::new(asm, settings).unwrap();
    let mut angles = vec![theta0];
    while !run.finished() {
        run.advance(1);
        let (_, q) = run.pose(0);
        let axis = Vector3::new(q[1], q[2], q[3]);
        angles.push(2.0 * axis.norm().atan2(q[0]) * axis.y.signum() + theta0);
    }
    let ms = 1e3 * t.elapsed().as_secs_f64();
    let peaks: Vec<f64> = angles
        .windows(3)
        .filter(|w| w[1].abs() > w[0].abs() && w[1].abs() >= w[2].abs() && w[0].signum() == w[2].signum())
        .map(|w| {
            let curvature = w[0] - 2.0 * w[1] + w[2];
            let offset = if curvature != 0.0 { 0.5 * (w[0] - w[2]) / curvature } else { 0.0 };
            (w[1] - 0.25 * (w[0] - w[2]) * offset).abs()
        })
        .collect();
    (peaks.get(3).copied().unwrap_or(0.0), ms)
}

fn rocking(rows: &mut Vec<Row>) {
    let (b, h, theta0) = (0.1, 0.5, 8f64.to_radians());
    let asm = Assembly::new(&leaning(theta0, b, h), &Default::default()).unwrap();
    let exact = housner_fourth(b, h, theta0);
    for engine in ENGINES {
        for per_second in STEPS {
            let settings = DropSettings { engine, dt: 1.0 / per_second, duration: 4.0, ..Default::default() };
            let (peak, ms) = rocked(&asm, &settings, theta0);
            rows.push(Row { what: "rocking block, 4th peak", engine, per_second, error: peak / exact - 1.0, ms });
        }
    }
}

fn tilt_threshold(rows: &mut Vec<Row>) {
    let statics = AnalysisSettings::default();
    let family = Family::Tilt { scene: Box::new(builtin("arch?n=16&t=0.15").unwrap()) };
    let reference =
        bisect(0.0, 20.0, 30, &mut |p| analyze(&family.scene(p).unwrap(), &statics).unwrap().statics.stands);
    let tan = |d: f64| d.to_radians().tan();
    for engine in ENGINES {
        for per_second in STEPS {
            let settings = DropSettings { engine, dt: 1.0 / per_second, ..Default::default() };
            let (mut tests, t) = (0, Instant::now());
            let threshold = bisect(0.0, 20.0, 10, &mut |p| {
                tests += 1;
                let asm = Assembly::new(&family.scene(p).unwrap(), &statics.tolerances).unwrap();
                drop_test(&asm, &settings).unwrap().stands
            });
            let ms = 1e3 * t.elapsed().as_secs_f64() / f64::from(tests);
            let error = tan(threshold) / tan(reference) - 1.0;
            rows.push(Row { what: "16-voussoir arch, tilt threshold", engine, per_second, error, ms });
        }
    }
}

fn write(rows: &[Row]) -> std::io::Result<()> {
    let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
    let mut md = String::from(
        "# Work against precision: both engines, dt from 1/60 to 1/4000 s\n\nGenerated by `cargo bench --bench \
         work_precision` (benches/work_precision.rs states the two measures). Error: the rocking block's fourth \
         peak against Housner's closed form; the arch's tilt threshold (bisection, 10 halvings, the bisection's \
         resolution is 0.02°) against the statics', in tan. Time: the wall time of one 4 s rocking run, or of one \
         2 s drop test of the arch, on the shared 2-core machine.\n\n\
         | measure | engine | dt | error | ms |\n|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(md, "| {} | {} | 1/{:.0} | {:+.2e} | {:.1} |", r.what, r.engine, r.per_second, r.error, r.ms);
    }
    md.push_str("\n![error against time](drop_work_precision.svg)\n");
    voussoir::io::write_atomic(&docs.join("drop_work_precision.md"), md.as_bytes()).map_err(std::io::Error::other)?;
    plot(rows, &docs.join("drop_work_precision.svg"))
}

fn plot(rows: &[Row], svg: &std::path::Path) -> std::io::Result<()> {
    voussoir::viz::plot::register_font();
    let root = SVGBackend::new(svg, (900, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(std::io::Error::other)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("|error| against wall time, dt 1/60 … 1/4000 s (● exact engine, ▲ rapier)", ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((0.5f64..1e5).log_scale(), (1e-5f64..1.0).log_scale())
        .map_err(std::io::Error::other)?;
    chart
        .configure_mesh()
        .x_desc("ms per run")
        .y_desc("|value / exact − 1|")
        .x_label_formatter(&|x| format!("{x}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(std::io::Error::other)?;
    for (k, what) in ["rocking block, 4th peak", "16-voussoir arch, tilt threshold"].into_iter().enumerate() {
        for engine in ENGINES {
            let color = [RED, BLUE][k];
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.what == what && r.engine == engine)
                .map(|r| (r.ms.clamp(0.5, 1e5), r.error.abs().clamp(1e-5, 1.0)))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(1)))
                .map_err(std::io::Error::other)?
                .label(format!("{what}, {engine}"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color));
            if engine == Engine::Exact {
                chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 4, color.filled())))
            } else {
                chart.draw_series(pts.into_iter().map(|p| TriangleMarker::new(p, 5, color.filled())))
            }
            .map_err(std::io::Error::other)?;
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(std::io::Error::other)?;
    root.present().map_err(std::io::Error::other)
}

fn main() {
    // `cargo test --benches` passes no `--bench` and only checks that this builds.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let mut rows = Vec::new();
    rocking(&mut rows);
    tilt_threshold(&mut rows);
    for r in &rows {
        println!("{:34} {:6} 1/{:<5.0} error {:+.2e} {:9.1} ms", r.what, r.engine, r.per_second, r.error, r.ms);
    }
    if let Err(e) = write(&rows) {
        eprintln!("cannot write docs/drop_work_precision.*: {e}");
        std::process::exit(1);
    }
    println!("wrote docs/drop_work_precision.md and docs/drop_work_precision.svg");
}
