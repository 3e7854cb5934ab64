//! Threshold sweeps: for a parametric family of designs, the parameter where the statics stop
//! saying "stands" and where the drop test does, each found by bisection, with their gap.
//! Families (parameter, the side that stands): `arch` (thickness t/R, thick stands), `slope`
//! (angle in degrees, flat stands), `harmonic` (overhang as a fraction of the critical one,
//! small stands), `tilt` (ground tilt in degrees for any scene: gravity turned about y; upright
//! stands).

use crate::dynamics::{DropSettings, Engine, drop_test};
use crate::model::{Assembly, Scene, builtin};
use crate::pipeline::{AnalysisSettings, analyze};
use serde::Serialize;
use thiserror::Error;

/// A parametric family of designs.
#[derive(Clone, Debug, PartialEq)]
pub enum Family {
    /// Semicircular arch of `n` voussoirs; parameter t/R.
    Arch {
        /// The number of voussoirs.
        n: usize,
    },
    /// A block on a slope with friction `mu`; parameter the angle, degrees.
    Slope {
        /// The friction coefficient μ.
        mu: f64,
    },
    /// Harmonic stack of `n` blocks; parameter the overhang fraction s.
    Harmonic {
        /// The number of blocks.
        n: usize,
    },
    /// `scene` with gravity tilted about y; parameter the tilt, degrees.
    Tilt {
        /// The design to tilt.
        scene: Box<Scene>,
    },
}

/// Why a sweep cannot run.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ThresholdError {
    /// The family's design cannot be built or analysed (the message says why).
    #[error("sweep: {0}")]
    Design(String),
    /// The range does not bracket a test's threshold: both ends give the same verdict.
    #[error("sweep: the {test} says '{at_lo}' at {lo} and '{at_hi}' at {hi}: the range does not bracket its threshold")]
    NotBracketed {
        /// Which test (`statics`, `drop test`).
        test: &'static str,
        /// The range's low end.
        lo: f64,
        /// Its high end.
        hi: f64,
        /// The verdict at the low end.
        at_lo: &'static str,
        /// The verdict at the high end.
        at_hi: &'static str,
    },
}

impl Family {
    /// The design at parameter `p`.
    pub fn scene(&self, p: f64) -> Result<Scene, ThresholdError> {
        let bad = |e: crate::model::BuiltinError| ThresholdError::Design(e.to_string());
        Ok(match self {
            Family::Arch { n } => builtin(&format!("arch?n={n}&t={p}")).map_err(bad)?,
            Family::Slope { mu } => builtin(&format!("slope?angle={p}&mu={mu}")).map_err(bad)?,
            Family::Harmonic { n } => builtin(&format!("harmonic?n={n}&s={p}")).map_err(bad)?,
            Family::Tilt { scene } => {
                let mut s = (**scene).clone();
                let (g, a) = (s.gravity.norm(), p.to_radians());
                s.gravity = crate::geometry::Vector3::new(g * a.sin(), 0.0, -g * a.cos());
                s
            }
        })
    }

    /// Whether larger parameters stand (arch thickness) or smaller ones (the others).
    fn stands_high(&self) -> bool {
        matches!(self, Family::Arch { .. })
    }
}

/// One threshold: the last parameter that stands and the first that does not (bracket).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Threshold {
    /// The last parameter at which it stands.
    pub stands_at: f64,
    /// The first parameter at which it does not.
    pub fails_at: f64,
}

impl Threshold {
    /// The bracket's middle: the threshold's estimate.
    pub fn mid(&self) -> f64 {
        0.5 * (self.stands_at + self.fails_at)
    }
}

/// Both thresholds and their gap (drop test minus statics, in the parameter's unit).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ThresholdStudy {
    /// The statics' threshold.
    pub statics: Threshold,
    /// The drop test's engine.
    pub engine: Engine,
    /// The drop test's threshold.
    pub dynamic: Threshold,
    /// Drop-test threshold minus the statics', in the parameter's unit.
    pub gap: f64,
    /// Designs analysed (statics and drop tests).
    pub evaluations: usize,
}

/// Bisection of `stands` over [lo, hi] to `iterations` halvings.
fn bisect(
    test: &'static str,
    family: &Family,
    (lo, hi): (f64, f64),
    iterations: usize,
    stands: &mut dyn FnMut(f64) -> Result<bool, ThresholdError>,
    tick: &mut dyn FnMut(),
) -> Result<Threshold, ThresholdError> {
    let (mut good, mut bad) = if family.stands_high() { (hi, lo) } else { (lo, hi) };
    let word = |b: bool| if b { "stands" } else { "falls" };
    let (at_good, at_bad) = (stands(good)?, stands(bad)?);
    tick();
    tick();
    if !at_good || at_bad {
        let (at_lo, at_hi) = if family.stands_high() { (at_bad, at_good) } else { (at_good, at_bad) };
        return Err(ThresholdError::NotBracketed { test, lo, hi, at_lo: word(at_lo), at_hi: word(at_hi) });
    }
    for _ in 0..iterations {
        let mid = 0.5 * (good + bad);
        if stands(mid)? {
            good = mid;
        } else {
            bad = mid;
        }
        tick();
    }
    Ok(Threshold { stands_at: good, fails_at: bad })
}

/// Sweeps `family` over [lo, hi]; `tick` is called after every evaluation (a progress bar).
pub fn bisect_thresholds(
    family: &Family,
    range: (f64, f64),
    iterations: usize,
    drop: &DropSettings,
    tick: &mut dyn FnMut(),
) -> Result<ThresholdStudy, ThresholdError> {
    let mut studies = compare_engines(family, range, iterations, drop, &[drop.engine], tick)?;
    Ok(studies.remove(0))
}

/// [`bisect_thresholds`] for each of `engines` (the rest of `drop` the same), the statics'
/// threshold found once: one study per engine, in that order.
pub fn compare_engines(
    family: &Family,
    range: (f64, f64),
    iterations: usize,
    drop: &DropSettings,
    engines: &[Engine],
    tick: &mut dyn FnMut(),
) -> Result<Vec<ThresholdStudy>, ThresholdError> {
    let mut evaluations = 0;
    let settings = AnalysisSettings::default();
    let mut statics = |p: f64| -> Result<bool, ThresholdError> {
        evaluations += 1;
        let a = analyze(&family.scene(p)?, &settings).map_err(|e| ThresholdError::Design(e.to_string()))?;
        Ok(a.statics.stands)
    };
    let s = bisect("statics", family, range, iterations, &mut statics, tick)?;
    let mut studies = Vec::with_capacity(engines.len());
    for &engine in engines {
        let mut evaluations = evaluations;
        // Only the verdict is wanted: a run ends once a block has fallen.
        let drop = &DropSettings { engine, stop_when_falls: true, ..drop.clone() };
        let mut dynamic = |p: f64| -> Result<bool, ThresholdError> {
            evaluations += 1;
            let asm = Assembly::new(&family.scene(p)?, &settings.tolerances)
                .map_err(|e| ThresholdError::Design(e.to_string()))?;
            Ok(drop_test(&asm, drop).map_err(|e| ThresholdError::Design(e.to_string()))?.stands)
        };
        let d = bisect("drop test", family, range, iterations, &mut dynamic, tick)?;
        studies.push(ThresholdStudy { statics: s, engine, dynamic: d, gap: d.mid() - s.mid(), evaluations });
    }
    Ok(studies)
}

/// Both answers at one parameter value of a family.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScanPoint {
    /// The parameter value.
    pub parameter: f64,
    /// Whether the statics say it stands.
    pub statics_stands: bool,
    /// The graded static answer: minimum tension plus friction excess, relative to W.
    pub static_margin: f64,
    /// The largest friction use over the interfaces (> 1: exceeded).
    pub max_friction_utilization: f64,
    /// Whether the drop test says it stands.
    pub drop_stands: bool,
    /// Largest drift or rotation of a block relative to its tolerance (> 1 falls).
    pub drop_motion: f64,
}

/// Both answers at `points` evenly spaced parameters over [lo, hi] (for the plot of verdicts
/// and margins against the parameter).
pub fn scan(
    family: &Family,
    (lo, hi): (f64, f64),
    points: usize,
    drop: &DropSettings,
    tick: &mut dyn FnMut(),
) -> Result<Vec<ScanPoint>, ThresholdError> {
    let settings = AnalysisSettings::default();
    let design = |e: String| ThresholdError::Design(e);
    (0..points.max(2))
        .map(|k| {
            let p = lo + (hi - lo) * k as f64 / (points.max(2) - 1) as f64;
            let a = analyze(&family.scene(p)?, &settings).map_err(|e| design(e.to_string()))?;
            let d = drop_test(&a.assembly, drop).map_err(|e| design(e.to_string()))?;
            tick();
            let s = &a.statics;
            Ok(ScanPoint {
                parameter: p,
                statics_stands: s.stands,
                static_margin: s.tension_ratio + s.friction_excess_ratio,
                max_friction_utilization: s.max_friction_utilization,
                drop_stands: d.stands,
                drop_motion: (d.max_drift / drop.drift_tolerance).max(d.max_rotation / drop.rotation_tolerance),
            })
        })
        .collect()
}
