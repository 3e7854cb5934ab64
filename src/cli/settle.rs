//! `voussoir settle`: the design on supports that move (`--move`, or the scene's `movements`),
//! followed until it collapses — quasi-statically, and in the exact-contact engine and rapier
//! side by side; the movement at collapse, the hinges and slides stage by stage, the thrust
//! against the movement (`--plot`). Exit codes: 0 it stands to the end of the path, 1 it
//! collapses (or does not stand as drawn, or a solve failed: solver trouble), 2 bad input.

use super::options::SolverOptions;
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::model::Movement;
use crate::pipeline::analyze;
use crate::studies::settlement::{Outcome, QUASI_STATIC, Run, SettleSettings, settle_with_progress};
use crate::viz::plot::{Clock, FrameStrip, ThrustPlot, write_strip, write_thrust};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

/// The options of `voussoir settle`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct SettleArgs {
    /// Scene file or `builtin:NAME?k=v&...`. Default: the embedded default scene.
    pub scene: Option<String>,
    /// The solver options (friction model, μ, tolerances).
    #[command(flatten)]
    pub solver: SolverOptions,
    /// A support's whole path: NAME:dx,dy,dz (model units) or NAME:dx,dy,dz:rx,ry,rz (a
    /// rotation vector, degrees, about its centroid). Repeat for several supports; replaces the
    /// scene's `movements`.
    #[arg(long = "move", value_name = "NAME:DX,DY,DZ[:RX,RY,RZ]")]
    pub moves: Vec<String>,
    /// Quasi-static increments over the path.
    #[arg(long, default_value_t = SettleSettings::default().increments)]
    pub increments: usize,
    /// The supports' speed in the engines' runs, a fraction of √(g × block size) (slower is
    /// nearer the quasi-static limit, and takes longer).
    #[arg(long, default_value_t = SettleSettings::default().speed)]
    pub speed: f64,
    /// Only the quasi-static analysis (no exact-engine or rapier run).
    #[arg(long)]
    pub quasi_static: bool,
    /// Write the JSON report here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// The horizontal reaction on the first moved support against its movement (.png, .svg).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// The quasi-static run's increments as a glTF animation (.glb; the whole path plays in
    /// 5 s, the moved supports with it, up to just past the collapse).
    #[arg(long, value_name = "OUT.glb")]
    pub frames: Option<PathBuf>,
    /// The quasi-static run as a strip of six key frames along the path (.png, .svg).
    #[arg(long, value_name = "OUT.png")]
    pub strip: Option<PathBuf>,
}

/// Runs `settle`: prints each run's outcome; exit code 0 when it stands to the end of the path.
pub fn run(args: &SettleArgs) -> Result<i32, BadInput> {
    for out in [&args.json, &args.plot, &args.frames, &args.strip].into_iter().flatten() {
        refuse_overwrite(args.scene.as_deref(), out, "output")?;
    }
    let name = scene_name(args.scene.as_deref()).to_string();
    let mut scene = load(args.scene.as_deref())?;
    if !args.moves.is_empty() {
        scene.movements = args.moves.iter().map(|m| Movement::parse(m)).collect::<Result<_, _>>().map_err(BadInput)?;
    }
    let solver = args.solver.settings();
    let analysis = analyze(&scene, &solver).map_err(|e| BadInput(format!("{name}: {e}")))?;
    let settings = SettleSettings {
        increments: args.increments,
        friction: args.solver.mu,
        strength: args.solver.strength,
        engines: !args.quasi_static,
        speed: args.speed,
        backend: args.solver.solver,
        ..Default::default()
    };
    let bar = super::LateBar::new(Some("{bar:30} {percent:>3}% of the path, {msg} ({elapsed})"));
    // Each run's first and last report: its wall-clock time.
    let clocks = std::cell::RefCell::new(Vec::<(&str, Instant, Instant)>::new());
    let progress = |method: &'static str, fraction: f64| {
        bar.update((PERMILLE * fraction).round() as usize, PERMILLE as usize, Some(method.to_string()));
        let mut clocks = clocks.borrow_mut();
        match clocks.last_mut() {
            Some((m, _, end)) if *m == method => *end = Instant::now(),
            _ => clocks.push((method, Instant::now(), Instant::now())),
        }
    };
    let result = settle_with_progress(&analysis, &scene.movements, &settings, &progress)
        .map_err(|e| BadInput(format!("{name}: {e}")))?;
    drop(bar);
    let seconds = |run: &Run| {
        let clocks = clocks.borrow();
        clocks.iter().find(|c| c.0 == run.method).map_or(0.0, |(_, start, end)| (*end - *start).as_secs_f64())
    };
    // The largest turn of a moved support over the whole path, degrees: a tilting base moves
    // by its turn, not by its (zero) translation.
    let turn = scene.movements.iter().map(|m| m.rotation.iter().map(|r| r * r).sum::<f64>().sqrt()).fold(0.0, f64::max);
    println!(
        "SETTLE '{}': {} moved ({:.4e} m{} at the end of the path)",
        analysis.assembly.name,
        result.supports.join(", "),
        result.path_movement,
        if turn > 0.0 { format!(", turned {turn:.3}°") } else { String::new() }
    );
    if let Some(sigma) = result.strength {
        println!("  crushing at {sigma:.4e} Pa (quasi-static and exact engine; rapier's contacts do not crush)");
    }
    for run in [Some(&result.quasi_static), result.exact.as_ref(), result.rapier.as_ref()].into_iter().flatten() {
        println!("{}", line(run, turn, seconds(run)));
    }
    if let Some(out) = &args.json {
        let text = serde_json::to_string_pretty(&result).map_err(|e| BadInput(e.to_string()))?;
        write_output(out, text.as_bytes())?;
        println!("report written to {}", out.display());
    }
    if let Some(out) = &args.plot {
        let plot = ThrustPlot {
            title: format!("{}: reaction against support movement", analysis.assembly.name),
            settlement: &result,
        };
        write_thrust(&plot, out).map_err(|e| BadInput(e.to_string()))?;
        println!("thrust plot written to {}", out.display());
    }
    write_motion(args, &analysis.assembly, &result.quasi_static)?;
    Ok(match result.quasi_static.outcome {
        Outcome::Stands => 0,
        Outcome::Collapses { .. } | Outcome::Unresolved { .. } => 1,
    })
}

/// Writes `run`'s motion as `--frames`' animation and `--strip`'s key frames.
fn write_motion(args: &SettleArgs, assembly: &crate::model::Assembly, run: &Run) -> Result<(), BadInput> {
    if let Some(out) = &args.frames {
        write_output(out, &crate::viz::gltf::path_glb(assembly, &run.motion))?;
        println!("increments written to {} ({} frames)", out.display(), run.motion.times.len());
    }
    if let Some(out) = &args.strip {
        let strip = FrameStrip { clock: Clock::Path, ..FrameStrip::new(assembly, &run.motion) };
        write_strip(&strip, out).map_err(|e| BadInput(e.to_string()))?;
        println!("key frames written to {}", out.display());
    }
    Ok(())
}

/// One run in a line: how it ended (with the supports' turn then, of `turn` degrees over the
/// path), the joints of its mechanism, and its pace (`seconds` of wall-clock time).
fn line(run: &Run, turn: f64, seconds: f64) -> String {
    let how = match run.outcome {
        Outcome::Stands => "stands to the end of the path".to_string(),
        Outcome::Unresolved { fraction, status } => format!(
            "solver trouble at {:.2} % of the path: a step's solve ended {status:?}; the run stops there",
            100.0 * fraction
        ),
        Outcome::Collapses { fraction, movement, relative } => format!(
            "collapses at {:.2} % of the path: {movement:.4e} m ({:.3} % of the model size){}",
            100.0 * fraction,
            100.0 * relative,
            if turn > 0.0 { format!(", turned {:.3}°", fraction * turn) } else { String::new() }
        ),
    };
    let joints: Vec<String> =
        run.mechanism.iter().map(|j| format!("{} → {} {:?}", j.a, j.b, j.state).to_lowercase()).collect();
    let mechanism = if joints.is_empty() { String::new() } else { format!("; mechanism: {}", joints.join(", ")) };
    let crushed = run.crushed.map_or(String::new(), |d| format!("; joints crushed up to {d:.3e} m"));
    format!("  {:<12} {how}{mechanism}{crushed} ({})", run.method, pace(run, seconds))
}

/// The bar's resolution: a thousandth of the path.
const PERMILLE: f64 = 1000.0;

/// How long a run took: its engine steps and `seconds`, and the quasi-static run's increments
/// a second (its stages: the increments that held).
fn pace(run: &Run, seconds: f64) -> String {
    let steps = format!("{} steps in {seconds:.2} s", run.steps);
    if run.method != QUASI_STATIC {
        return steps;
    }
    let increments = run.stages.len();
    format!("{steps}; {increments} increments, {:.2} a second", increments as f64 / seconds.max(1e-9))
}
