//! The shake table: a design under a ground motion ([`crate::dynamics::ground_motion`]) on
//! either engine, the static load factor λ* beside it, and collapse spectra.
//!
//! - [`shake`]: one run; the motion, then `after` × √(D / g) more (D the free blocks' bounding
//!   box diagonal: a block's rocking and falling go with √(size / g)) for what it set going to
//!   fall or come to rest. [`shake_traced`] (the CLI's run, with its history) ends that long
//!   after a collapse: the debris has landed. It collapsed when a block fell ([`crate::dynamics::BlockMotion::fell`]); drifts
//!   and rotations are relative to the ground.
//! - [`static_load_factor`]: λ* of a horizontal field opposite the base's acceleration — the
//!   inertial load a base accelerated along `azimuth` puts on the blocks. A rectangular pulse
//!   of λ* g held forever is the statics' collapse: λ* is the long-pulse limit of the spectrum.
//! - [`collapse_spectrum`]: for a pulse shape, the least amplitude that collapses the design
//!   at each duration, by bisection from λ* g (no pulse whose peak is below it moves a block)
//!   to a doubling upper bound, the durations shared between two threads.
//!
//! Amplitudes in g — the design's gravity, the unit of λ* (a record's g, read in standard
//! gravity, is converted to m/s² on reading) — durations in s, azimuths in degrees from +x
//! towards +y.

use crate::dynamics::ground_motion::{Excitation, GroundMotion, LARGEST, PulseShape};
use crate::dynamics::{DropError, DropResult, DropRun, DropSettings, Engine, Trajectory};
use crate::geometry::Vector3;
use crate::model::Assembly;
use crate::pipeline::Analysis;
use crate::stability::{RobustnessError, assess_parts, with_horizontal_field};
use crate::statics::StaticsSettings;
use serde::Serialize;
use std::sync::Mutex;
use thiserror::Error;

/// Why a shake or a spectrum cannot run.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ShakeError {
    /// The motion or the engine's settings are not valid.
    #[error(transparent)]
    Drop(#[from] DropError),
    /// The static load factor cannot be computed.
    #[error(transparent)]
    Robustness(#[from] RobustnessError),
    /// A spectrum setting is out of range (the message names it).
    #[error("spectrum: {0}")]
    Spectrum(String),
}

/// How a shake runs.
#[derive(Clone, Debug, PartialEq)]
pub struct ShakeSettings {
    /// The engine and its settings (its `duration` is replaced by the motion's end + the time
    /// after it).
    pub drop: DropSettings,
    /// Time simulated after the motion ends, in the design's time scale √(D / g) …
    pub after: f64,
    /// … unless the whole simulated time is given, s.
    pub duration: Option<f64>,
}

impl Default for ShakeSettings {
    fn default() -> Self {
        // A block that ends a pulse near its tipping point takes several 1/p (≈ √(D / g)) to
        // fall or come back: 4.8 s for a 1 m block.
        // At rest, the static theorem's pick (an equilibrium within Coulomb's sets holds it):
        // below λ* nothing moves, where a redundant dome's contacts admit motions too.
        let mut drop = DropSettings { engine: Engine::Exact, ..DropSettings::default() };
        drop.exact.rest_when_admissible = true;
        Self { drop, after: 15.0, duration: None }
    }
}

impl ShakeSettings {
    /// The engine's settings for `motion` on `assembly`: its duration the motion's end + the
    /// time after it.
    fn for_motion(&self, assembly: &Assembly, motion: &GroundMotion) -> Result<DropSettings, ShakeError> {
        if !(self.after >= 0.0 && self.after.is_finite()) {
            return Err(DropError::Negative { name: "after", value: self.after }.into());
        }
        let duration =
            self.duration.unwrap_or_else(|| (motion.end() + self.after * time_scale(assembly)).max(self.drop.dt));
        Ok(DropSettings { duration, ..self.drop.clone() })
    }
}

/// √(D / g), s: D the free blocks' bounding box diagonal (m), g the design's gravity.
pub fn time_scale(assembly: &Assembly) -> f64 {
    let mut free = crate::geometry::Aabb3::empty();
    assembly.blocks.iter().filter(|b| !b.support).for_each(|b| free.merge(&b.aabb));
    let g = assembly.gravity.norm();
    let scale = (free.diagonal() / g).sqrt();
    if scale.is_finite() { scale } else { 0.0 }
}

/// Shakes `assembly` by `motion` (see the module docs).
pub fn shake(assembly: &Assembly, settings: &ShakeSettings, motion: &GroundMotion) -> Result<DropResult, ShakeError> {
    let mut run = shake_run(assembly, settings, motion)?;
    run.advance(run.total_steps());
    Ok(run.result())
}

/// The run of a shake, to be advanced step by step (the ECS plugin, a recording).
pub fn shake_run(assembly: &Assembly, settings: &ShakeSettings, motion: &GroundMotion) -> Result<DropRun, ShakeError> {
    Ok(DropRun::shaken(assembly, &settings.for_motion(assembly, motion)?, motion.clone())?)
}

/// A shake's history, one sample per step (and the start).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ShakeTrace {
    /// Times, s.
    pub times: Vec<f64>,
    /// The base's acceleration along the first component's direction over the step, in the
    /// design's g.
    pub ground_g: Vec<f64>,
    /// The largest rotation of a free block, rad.
    pub rotation: Vec<f64>,
    /// The largest drift of a free block, a fraction of its size.
    pub drift: Vec<f64>,
}

/// [`shake`] with its history, and with `fps` every block's pose about `fps` times per
/// simulated second (for [`crate::viz::gltf::animation_glb`] and the frame strip).
pub fn shake_traced(
    assembly: &Assembly,
    settings: &ShakeSettings,
    motion: &GroundMotion,
    fps: Option<f64>,
) -> Result<(DropResult, ShakeTrace, Option<Trajectory>), ShakeError> {
    let mut run = shake_run(assembly, settings, motion)?;
    let direction = motion.components.first().map_or(Vector3::x(), |c| c.direction.normalize());
    let dt = run.dt();
    let g = assembly.gravity.norm();
    let every = match fps {
        Some(f) if f > 0.0 && f.is_finite() => Some(((1.0 / (f * dt)).round() as usize).max(1)),
        Some(f) => return Err(DropError::NotPositive { name: "frames per second", value: f }.into()),
        None => None,
    };
    let frame = |run: &DropRun| (0..assembly.blocks.len()).map(|i| run.pose(i)).collect();
    let mut motion_frames =
        every.map(|_| Trajectory { engine: run.engine(), times: vec![0.0], poses: vec![frame(&run)] });
    let mut trace = ShakeTrace { times: vec![0.0], ground_g: vec![0.0], rotation: vec![0.0], drift: vec![0.0] };
    let after = settings.after * time_scale(assembly);
    let mut fell = false;
    while !run.finished() {
        if !fell && let Some(t) = run.fell() {
            // What follows a collapse is the debris landing: the time after a motion, no more.
            fell = true;
            run.end_by(t + after);
        }
        let t = run.steps_done() as f64 * dt;
        let a = motion.mean_acceleration(t, t + dt).dot(&direction) / g;
        run.advance(1);
        let (drift, rotation) = run.largest_now();
        trace.times.push(t + dt);
        trace.ground_g.push(a);
        trace.rotation.push(rotation);
        trace.drift.push(drift);
        if let (Some(k), Some(m)) = (every, motion_frames.as_mut())
            && (run.steps_done() % k == 0 || run.finished())
        {
            m.times.push(run.steps_done() as f64 * dt);
            m.poses.push(frame(&run));
        }
    }
    Ok((run.result(), trace, motion_frames))
}

/// λ* (in g) of the inertial load of a base accelerated along the horizontal `azimuth`: a
/// 1 g field along azimuth + 180°, on the analysis's assembly and interfaces. +∞ when no
/// multiple collapses it; NaN when it does not stand or a solve failed.
pub fn static_load_factor(analysis: &Analysis, statics: &StaticsSettings, azimuth: f64) -> Result<f64, ShakeError> {
    let field = with_horizontal_field(&analysis.assembly, azimuth + 180.0);
    Ok(assess_parts(&field, &analysis.interfaces, analysis.statics.stands, statics)?.load_factor)
}

/// One engine's answer to a shake.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShakeOutcome {
    /// A block fell.
    pub collapsed: bool,
    /// When the first block fell, s.
    pub collapse_time_s: Option<f64>,
    /// The run's verdict and every block's motion (rocking, sliding, residual displacement).
    pub result: DropResult,
    /// Its history.
    pub trace: ShakeTrace,
    /// Its motion for playback, when asked for.
    #[serde(skip)]
    pub frames: Option<Trajectory>,
}

/// A shake with the statics beside it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShakeStudy {
    /// The horizontal direction λ* is taken along: the first component's, degrees.
    pub azimuth: f64,
    /// λ* (in g) of the inertial load opposite it ([`static_load_factor`]).
    pub static_load_factor: f64,
    /// The motion's largest acceleration, in the design's g.
    pub peak_g: f64,
    /// When the motion ends, s.
    pub motion_end_s: f64,
    /// Each engine's answer, in the order asked.
    pub runs: Vec<ShakeOutcome>,
}

/// Shakes `analysis`'s design by `motion` on each of `engines` (the rest of `settings` the
/// same), with λ* along the motion's first horizontal direction beside it; the first engine's
/// motion kept at `fps` frames a second when asked.
pub fn shake_study(
    analysis: &Analysis,
    statics: &StaticsSettings,
    motion: &GroundMotion,
    settings: &ShakeSettings,
    engines: &[Engine],
    fps: Option<f64>,
) -> Result<ShakeStudy, ShakeError> {
    let d = motion.components.first().map_or(Vector3::x(), |c| c.direction);
    let azimuth = if d.x.hypot(d.y) > 0.0 { d.y.atan2(d.x).to_degrees() } else { 0.0 };
    let static_load_factor = static_load_factor(analysis, statics, azimuth)?;
    let g = analysis.assembly.gravity.norm();
    let peak = motion.components.iter().map(|c| c.excitation.peak()).fold(0.0, f64::max) * motion.scale.abs();
    let mut runs = Vec::new();
    for (k, &engine) in engines.iter().enumerate() {
        let settings = ShakeSettings { drop: DropSettings { engine, ..settings.drop.clone() }, ..settings.clone() };
        let (result, trace, frames) = shake_traced(&analysis.assembly, &settings, motion, fps.filter(|_| k == 0))?;
        runs.push(ShakeOutcome {
            collapsed: result.fell.is_some(),
            collapse_time_s: result.fell,
            result,
            trace,
            frames,
        });
    }
    Ok(ShakeStudy { azimuth, static_load_factor, peak_g: peak / g, motion_end_s: motion.end(), runs })
}

/// How a collapse spectrum is found.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumSettings {
    /// The pulse's shape.
    pub shape: PulseShape,
    /// The pulse durations, s.
    pub durations: Vec<f64>,
    /// The base's direction, degrees from +x towards +y.
    pub azimuth: f64,
    /// Each run's settings (a run stops at the first fall).
    pub shake: ShakeSettings,
    /// The bisection ends when the bracket is within this fraction of its upper end.
    pub tolerance: f64,
}

impl Default for SpectrumSettings {
    fn default() -> Self {
        Self {
            shape: PulseShape::Rectangular,
            durations: vec![0.1, 0.2, 0.5, 1.0, 2.0, 5.0],
            azimuth: 0.0,
            shake: ShakeSettings::default(),
            // 0.2 %: finer than the engines' agreement with the closed forms (1 %).
            tolerance: 2e-3,
        }
    }
}

/// The least collapsing amplitude at one pulse duration.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SpectrumPoint {
    /// The pulse's duration, s.
    pub duration: f64,
    /// The largest amplitude found that does not collapse the design, g.
    pub stands_g: f64,
    /// The least amplitude found that does, g; `None` when none up to the largest allowed
    /// ([`LARGEST`] g) does.
    pub collapses_g: Option<f64>,
    /// Runs taken.
    pub runs: usize,
}

/// A collapse spectrum and the static load factor beside it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Spectrum {
    /// The pulse's shape.
    pub shape: PulseShape,
    /// The engine that ran it.
    pub engine: Engine,
    /// The base's direction, degrees.
    pub azimuth: f64,
    /// λ* of the statics (g): the long-pulse limit.
    pub static_load_factor: f64,
    /// One point per duration, in the settings' order.
    pub points: Vec<SpectrumPoint>,
}

/// The collapse spectrum of `assembly` (module docs) with `static_load_factor` (λ*, g) as the
/// bisection's lower end; `tick` is called after each duration (from either thread).
pub fn collapse_spectrum(
    assembly: &Assembly,
    static_load_factor: f64,
    settings: &SpectrumSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<Spectrum, ShakeError> {
    check_spectrum(settings)?;
    let results: Mutex<Vec<Option<Result<SpectrumPoint, ShakeError>>>> =
        Mutex::new(vec![None; settings.durations.len()]);
    let next = Mutex::new(0usize);
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                loop {
                    let k = {
                        let mut n = next.lock().expect("not poisoned");
                        *n += 1;
                        *n - 1
                    };
                    let Some(&duration) = settings.durations.get(k) else { break };
                    let point = least_collapsing(assembly, static_load_factor, duration, settings);
                    let failed = point.is_err();
                    results.lock().expect("not poisoned")[k] = Some(point);
                    tick();
                    if failed {
                        break;
                    }
                }
            });
        }
    });
    let points = results.into_inner().expect("not poisoned");
    let points = points.into_iter().flatten().collect::<Result<Vec<_>, _>>()?;
    if points.len() != settings.durations.len() {
        return Err(ShakeError::Spectrum("a duration was not run".into()));
    }
    Ok(Spectrum {
        shape: settings.shape,
        engine: settings.shake.drop.engine,
        azimuth: settings.azimuth,
        static_load_factor,
        points,
    })
}

/// The spectrum's durations and tolerance checked.
fn check_spectrum(settings: &SpectrumSettings) -> Result<(), ShakeError> {
    if settings.durations.is_empty() || settings.durations.len() > 200 {
        return Err(ShakeError::Spectrum(format!("{} durations (one to 200)", settings.durations.len())));
    }
    if let Some(d) = settings.durations.iter().find(|d| !(**d > 0.0 && d.is_finite() && **d <= 600.0)) {
        return Err(ShakeError::Spectrum(format!("duration {d} s must be finite, > 0 and at most 600 s")));
    }
    if !(settings.tolerance > 0.0 && settings.tolerance < 1.0) {
        return Err(ShakeError::Spectrum(format!("tolerance {} must be in (0, 1)", settings.tolerance)));
    }
    Ok(())
}

/// Whether a pulse of `amplitude_g` and `duration` collapses `assembly`.
fn collapses(
    assembly: &Assembly,
    settings: &SpectrumSettings,
    amplitude_g: f64,
    duration: f64,
) -> Result<bool, ShakeError> {
    let g = assembly.gravity.norm();
    let pulse = Excitation::Pulse { shape: settings.shape, amplitude: amplitude_g * g, duration };
    let motion = GroundMotion::horizontal(pulse, settings.azimuth);
    let shake_settings = ShakeSettings {
        drop: DropSettings { stop_when_falls: true, ..settings.shake.drop.clone() },
        ..settings.shake.clone()
    };
    Ok(shake(assembly, &shake_settings, &motion)?.fell.is_some())
}

/// The bracket of the least collapsing amplitude at `duration`: up from λ* g by doubling, then
/// bisected to the tolerance.
fn least_collapsing(
    assembly: &Assembly,
    lambda: f64,
    duration: f64,
    settings: &SpectrumSettings,
) -> Result<SpectrumPoint, ShakeError> {
    let mut runs = 0;
    let mut test = |a: f64| {
        runs += 1;
        collapses(assembly, settings, a, duration)
    };
    let mut lo = if lambda.is_finite() && lambda > 0.0 { lambda } else { 0.1 };
    while test(lo)? {
        lo *= 0.5;
        if lo < 1e-6 {
            return Ok(SpectrumPoint { duration, stands_g: 0.0, collapses_g: Some(lo), runs });
        }
    }
    let mut hi = 2.0 * lo;
    while !test(hi)? {
        lo = hi;
        hi *= 2.0;
        if hi > LARGEST {
            let top = LARGEST;
            if !test(top)? {
                return Ok(SpectrumPoint { duration, stands_g: top, collapses_g: None, runs });
            }
            hi = top;
            break;
        }
    }
    while hi - lo > settings.tolerance * hi {
        let mid = 0.5 * (lo + hi);
        if test(mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(SpectrumPoint { duration, stands_g: lo, collapses_g: Some(hi), runs })
}
