//! `voussoir shake`: the design on a shaking ground — a pulse, a harmonic or a recorded
//! accelerogram — on the exact engine, rapier or both, with the static load factor λ* beside
//! the dynamic answer; or (`--spectrum`) the least collapsing pulse amplitude against the
//! pulse's duration. Exit codes: 0 it survives (every run), 1 it collapses (or does not stand
//! as drawn), 2 bad input.

use super::choice::Choice;
use super::options::SolverOptions;
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::dynamics::ground_motion::{GroundMotion, PulseShape};
use crate::dynamics::{DropResult, DropSettings, Engine};
use crate::io::accelerogram::{NamedMotion, named_motion};
use crate::pipeline::{Analysis, analyze};
use crate::studies::shake::{
    ShakeSettings, ShakeStudy, Spectrum, SpectrumSettings, collapse_spectrum, shake_study, static_load_factor,
};
use crate::viz::plot::{FrameStrip, ShakePlot, SpectrumPlot, write_shake, write_spectrum, write_strip};
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::path::PathBuf;

/// Which engines shake the design.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engines {
    /// The exact-contact engine.
    Exact,
    /// rapier3d.
    Rapier,
    /// Both, side by side.
    Both,
}

impl std::fmt::Display for Engines {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&super::choice::name(self))
    }
}

/// The options of `voussoir shake`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct ShakeArgs {
    /// Scene file or `builtin:NAME?k=v&...`. Default: the embedded default scene.
    pub scene: Option<String>,
    /// The solver options (friction model, μ, tolerances).
    #[command(flatten)]
    pub solver: SolverOptions,
    /// A pulse: SHAPE:AMP_G,DURATION_S — rect (AMP for DURATION), sine (one full sine cycle of
    /// DURATION) or ricker (the Ricker wavelet of period DURATION).
    #[arg(long, value_name = "SHAPE:AMP_G,DURATION_S", conflicts_with_all = ["sine", "record", "spectrum"])]
    pub pulse: Option<String>,
    /// A harmonic: AMP_G,PERIOD_S,CYCLES.
    #[arg(long, value_name = "AMP_G,PERIOD_S,CYCLES", conflicts_with_all = ["record", "spectrum"])]
    pub sine: Option<String>,
    /// A recorded accelerogram: a PEER NGA .AT2 or a two-column .csv file, builtin:elcentro
    /// (1940, north–south), or builtin:synthetic?seed=N&pga=G&duration=S.
    #[arg(long, value_name = "FILE", conflicts_with = "spectrum")]
    pub record: Option<String>,
    /// Shake only this support (repeat for several; the others and the floor stay still, and
    /// drifts are in the world frame). Default: every support and the floor, as one base.
    #[arg(long = "shake-support", value_name = "NAME")]
    pub shake_supports: Vec<String>,
    /// A factor on the motion's acceleration.
    #[arg(long, default_value_t = 1.0)]
    pub scale: f64,
    /// The horizontal direction the ground accelerates along, degrees from +x towards +y.
    #[arg(long, default_value_t = 0.0)]
    pub direction: f64,
    /// The engine: exact, rapier or both side by side.
    #[arg(long, value_parser = Choice::<Engines>::new(), default_value_t = Engines::Exact)]
    pub engine: Engines,
    /// Simulated seconds in all (default: the motion's end + 15 √(D / g), D the free blocks'
    /// size).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Time step, s.
    #[arg(long, default_value_t = DropSettings::default().dt)]
    pub dt: f64,
    /// A collapse spectrum for this pulse shape (rect, sine, ricker): the least collapsing
    /// amplitude at each of --durations, against λ*.
    #[arg(long, value_name = "SHAPE")]
    pub spectrum: Option<String>,
    /// The spectrum's pulse durations, s (comma-separated).
    #[arg(long, value_delimiter = ',', default_values_t = SpectrumSettings::default().durations)]
    pub durations: Vec<f64>,
    /// Write the JSON report here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// The ground acceleration, the response and λ* (or the spectrum) as a plot (.png, .svg).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// The first engine's motion as a glTF animation (.glb).
    #[arg(long, value_name = "OUT.glb")]
    pub frames: Option<PathBuf>,
    /// The first engine's motion as a strip of six key frames (.png, .svg).
    #[arg(long, value_name = "OUT.png")]
    pub strip: Option<PathBuf>,
}

/// The JSON report of one shake: the study with the scene and the motion named.
#[derive(Serialize)]
struct ShakeReport<'a> {
    scene: &'a str,
    motion: &'a str,
    #[serde(flatten)]
    study: &'a ShakeStudy,
}

/// Runs `shake`: prints each engine's answer; exit code 0 when it survives.
pub fn run(args: &ShakeArgs) -> Result<i32, BadInput> {
    for out in [&args.json, &args.plot, &args.frames, &args.strip].into_iter().flatten() {
        refuse_overwrite(args.scene.as_deref(), out, "output")?;
    }
    let name = scene_name(args.scene.as_deref()).to_string();
    let scene = load(args.scene.as_deref())?;
    let analysis = analyze(&scene, &args.solver.settings()).map_err(|e| BadInput(format!("{name}: {e}")))?;
    if !analysis.statics.stands {
        println!("SHAKE '{}': does not stand as drawn (the statics); nothing to shake", analysis.assembly.name);
        return Ok(1);
    }
    let statics = args.solver.settings().statics;
    if let Some(shape) = &args.spectrum {
        let lambda =
            static_load_factor(&analysis, &statics, args.direction).map_err(|e| BadInput(format!("{name}: {e}")))?;
        return spectrum(args, &analysis, shape, lambda);
    }
    let (motion, label) = motion(args, &scene)?;
    let engines: &[Engine] = match args.engine {
        Engines::Exact => &[Engine::Exact],
        Engines::Rapier => &[Engine::Rapier],
        Engines::Both => &[Engine::Exact, Engine::Rapier],
    };
    let fps = (args.frames.is_some() || args.strip.is_some()).then_some(30.0);
    let study = shake_study(&analysis, &statics, &motion, &shake_settings(args, engines[0]), engines, fps)
        .map_err(|e| BadInput(format!("{name}: {e}")))?;
    println!(
        "SHAKE '{}': {label}, peak {:.4} g along {}°; static load factor λ* = {}",
        analysis.assembly.name,
        study.peak_g,
        study.azimuth,
        lambda_text(study.static_load_factor)
    );
    for run in &study.runs {
        println!("{}", line(&run.result));
    }
    if let Some(frames) = study.runs.first().and_then(|r| r.frames.as_ref()) {
        write_frames(args, &analysis, frames)?;
    }
    write_reports(args, &analysis, &label, &study)?;
    Ok(if study.runs.iter().any(|r| r.collapsed) { 1 } else { 0 })
}

/// The motion the options name (one of --pulse, --sine, --record; amplitudes in the design's
/// g), else the scene's `ground_motion`, and how to call it.
fn motion(args: &ShakeArgs, scene: &crate::model::Scene) -> Result<(GroundMotion, String), BadInput> {
    let named = NamedMotion {
        pulse: args.pulse.as_deref(),
        sine: args.sine.as_deref(),
        record: args.record.as_deref(),
        scale: args.scale,
        direction: args.direction,
        supports: &args.shake_supports,
    };
    let path = std::path::Path::new(args.scene.as_deref().unwrap_or("."));
    named_motion(&named, scene, path, "--").map_err(BadInput)
}

/// λ* as text: a number, unlimited or none.
fn lambda_text(lambda: f64) -> String {
    match lambda {
        l if l.is_finite() => format!("{l:.4} g"),
        l if l == f64::INFINITY => "unlimited".into(),
        _ => "not found (a solve failed)".into(),
    }
}

/// A run's settings: the engine, the step and the duration the options give.
fn shake_settings(args: &ShakeArgs, engine: Engine) -> ShakeSettings {
    let mut settings = ShakeSettings { duration: args.duration, ..ShakeSettings::default() };
    settings.drop.engine = engine;
    settings.drop.dt = args.dt;
    settings.drop.friction = args.solver.mu;
    let statics = args.solver.settings().statics;
    (settings.drop.exact.friction_model, settings.drop.exact.backend) = (statics.friction_model, statics.backend);
    settings
}

/// One engine's answer in a line.
fn line(r: &DropResult) -> String {
    let how = match r.fell {
        Some(t) => format!("COLLAPSES at {t:.3} s ({} fell first)", first_fallen(r)),
        None => "survives".to_string(),
    };
    let worst = r.blocks.iter().max_by(|a, b| a.max_rotation.total_cmp(&b.max_rotation));
    let rocking =
        worst.map_or(String::new(), |b| format!("; largest rotation {:.3}° ({})", b.max_rotation.to_degrees(), b.name));
    let slid = r.blocks.iter().map(|b| b.final_drift).fold(0.0, f64::max);
    format!(
        "  {:<7} {how}{rocking}; largest residual displacement {slid:.4e} m; {} steps, {:.2} s{}",
        r.engine.name(),
        r.steps,
        r.wall_s,
        if r.at_rest { "" } else { "; still moving at the end" }
    )
}

/// The block that fell first.
fn first_fallen(r: &DropResult) -> String {
    let first = r.blocks.iter().filter_map(|b| b.fell.map(|t| (t, &b.name))).min_by(|a, b| a.0.total_cmp(&b.0));
    first.map_or_else(String::new, |(_, n)| n.clone())
}

/// `--frames` and `--strip` of the first engine's motion.
fn write_frames(args: &ShakeArgs, analysis: &Analysis, frames: &crate::dynamics::Trajectory) -> Result<(), BadInput> {
    if let Some(out) = &args.frames {
        write_output(out, &crate::viz::gltf::animation_glb(&analysis.assembly, frames))?;
        println!("motion written to {} ({} frames)", out.display(), frames.times.len());
    }
    if let Some(out) = &args.strip {
        let strip = FrameStrip::new(&analysis.assembly, frames);
        write_strip(&strip, out).map_err(|e| BadInput(e.to_string()))?;
        println!("key frames written to {}", out.display());
    }
    Ok(())
}

/// `--json` and `--plot` of a shake.
fn write_reports(args: &ShakeArgs, analysis: &Analysis, label: &str, study: &ShakeStudy) -> Result<(), BadInput> {
    if let Some(out) = &args.json {
        let report = ShakeReport { scene: &analysis.assembly.name, motion: label, study };
        let text = serde_json::to_string_pretty(&report).map_err(|e| BadInput(e.to_string()))?;
        write_output(out, text.as_bytes())?;
        println!("report written to {}", out.display());
    }
    if let Some(out) = &args.plot {
        let plot = ShakePlot { title: format!("{}: {label}", analysis.assembly.name), study };
        write_shake(&plot, out).map_err(|e| BadInput(e.to_string()))?;
        println!("plot written to {}", out.display());
    }
    Ok(())
}

/// `--spectrum SHAPE`: the bisection at every duration, printed, written and plotted.
fn spectrum(args: &ShakeArgs, analysis: &Analysis, shape: &str, lambda: f64) -> Result<i32, BadInput> {
    let shape = PulseShape::from_name(shape.trim())
        .ok_or_else(|| BadInput(format!("--spectrum '{shape}': expected rect, sine or ricker")))?;
    let engine = match args.engine {
        Engines::Rapier => Engine::Rapier,
        _ => Engine::Exact,
    };
    let shake = shake_settings(args, engine);
    let settings = SpectrumSettings {
        shape,
        durations: args.durations.clone(),
        azimuth: args.direction,
        shake,
        ..Default::default()
    };
    println!(
        "SHAKE '{}': collapse spectrum of {} pulses along {}° ({}); static load factor λ* = {}",
        analysis.assembly.name,
        shape.name(),
        args.direction,
        engine.name(),
        lambda_text(lambda)
    );
    let bar = super::LateBar::new(Some("{bar:30} {pos}/{len} durations ({elapsed})"));
    let done = std::sync::atomic::AtomicUsize::new(0);
    let total = settings.durations.len();
    let tick = || {
        let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        bar.update(n, total, None);
    };
    let spectrum =
        collapse_spectrum(&analysis.assembly, lambda, &settings, &tick).map_err(|e| BadInput(e.to_string()))?;
    drop(bar);
    for p in &spectrum.points {
        let collapses = p.collapses_g.map_or(format!("none up to {} g", p.stands_g), |g| format!("{g:.4} g"));
        let ratio = p
            .collapses_g
            .filter(|_| lambda.is_finite() && lambda > 0.0)
            .map_or(String::new(), |g| format!(" ({:.3} λ*)", g / lambda));
        println!("  {:>8.4} s: collapses from {collapses}{ratio} ({} runs)", p.duration, p.runs);
    }
    write_spectrum_reports(args, analysis, &spectrum)?;
    Ok(0)
}

/// `--json` and `--plot` of a spectrum.
fn write_spectrum_reports(args: &ShakeArgs, analysis: &Analysis, spectrum: &Spectrum) -> Result<(), BadInput> {
    if let Some(out) = &args.json {
        let text = serde_json::to_string_pretty(spectrum).map_err(|e| BadInput(e.to_string()))?;
        write_output(out, text.as_bytes())?;
        println!("report written to {}", out.display());
    }
    if let Some(out) = &args.plot {
        let plot = SpectrumPlot { title: format!("{}: collapse spectrum", analysis.assembly.name), spectrum };
        write_spectrum(&plot, out).map_err(|e| BadInput(e.to_string()))?;
        println!("spectrum plot written to {}", out.display());
    }
    Ok(())
}
