//! How precisely a design must be cut: its fabrication tolerance margins, each the largest
//! imperfection of one kind for which the statics still say it stands, found by bisection.
//!
//! - **Shrink** δ* (m): every interface polygon shrunk by δ from every edge — chipped or rounded
//!   arrises, joints that bear short of their drawn edges ([`Interface::shrunk`]). A joint whose
//!   resultant lies e inside its edge keeps standing until δ = e (and a joint narrower than 2δ
//!   is gone).
//! - **Tilt** θ* (degrees): every joint plane turned by up to θ, both faces together, in its
//!   worst direction. A force at angle α from the drawn normal lies in the friction cone about
//!   every normal turned by θ exactly when α + θ ≤ atan μ: the joints' friction angle is cut to
//!   atan μ − θ. The blocks' small change of shape with the turn is left out (first order in
//!   θ × the joint's size against the cone's first order in θ): this margin is the sliding
//!   part of a tilt; the bearing part is the shrink's.
//!
//! Both relative to the typical block size (the cube root of the free blocks' mean volume), and
//! each with the interface that governs: where, just past the margin, the design needs the
//! most tension (shrink) or friction (tilt). Angles in degrees, lengths in model units (m).

use crate::interfaces::Interface;
use crate::model::Assembly;
use crate::pipeline::Analysis;
use crate::statics::{self, StaticsError, StaticsResult, StaticsSettings};
use serde::Serialize;
use thiserror::Error;

/// Settings of [`margins`]; each default written once, in `Default`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToleranceSettings {
    /// Each margin to this fraction of the model size (δ*) or of the friction angle (θ*).
    pub precision: f64,
}

impl Default for ToleranceSettings {
    fn default() -> Self {
        // ~20 statics solves per margin; finer than any fabrication tolerance is known.
        Self { precision: 1e-6 }
    }
}

impl ToleranceSettings {
    /// Refuses a precision outside (0, 1).
    pub fn validate(&self) -> Result<(), ToleranceError> {
        if !(self.precision > 0.0 && self.precision < 1.0) {
            return Err(ToleranceError::BadPrecision(self.precision));
        }
        Ok(())
    }
}

/// Why the margins cannot be computed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ToleranceError {
    /// The precision is not in (0, 1).
    #[error("tolerance precision {0} must be a number in (0, 1)")]
    BadPrecision(f64),
    /// A shrink is negative or not finite.
    #[error("joint shrink {0} must be a finite number ≥ 0 (model units)")]
    BadShrink(f64),
    /// The design does not stand as drawn (the reason, in words), so it has no margin.
    #[error("the design does not stand as drawn ({0}): it has no tolerance margin")]
    DoesNotStand(&'static str),
    /// The statics refused the assembly or the settings.
    #[error(transparent)]
    Statics(#[from] StaticsError),
}

/// The interface that governs a margin: its index and the names of its two sides.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Governing {
    /// The interface's index in the analysis's interfaces.
    pub interface: usize,
    /// The name of its side a (a block, or `ground`).
    pub a: String,
    /// The name of its side b.
    pub b: String,
}

/// One margin: its value, relative to the typical block size (shrink) or to the friction angle
/// (tilt), and the interface that governs it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Margin {
    /// The margin: a shrink in model units (m), or a tilt in degrees.
    pub value: f64,
    /// The margin over the typical block size (shrink) or over the friction angle atan μ (tilt).
    pub relative: f64,
    /// The interface that needs the most tension or friction just past the margin (none when no joint governs).
    pub governing: Option<Governing>,
}

/// The design's fabrication tolerance margins ([`margins`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Margins {
    /// δ*, m; relative to `block_size`.
    pub shrink: Margin,
    /// θ*, degrees; relative to the friction angle atan μ.
    pub tilt: Margin,
    /// The typical block size, m: the cube root of the free blocks' mean volume.
    pub block_size: f64,
    /// Statics solves spent.
    pub solves: usize,
}

/// The interfaces with every polygon shrunk by `delta` (m), and for each the index of the
/// interface it came from.
pub fn shrunk(interfaces: &[Interface], delta: f64) -> (Vec<Interface>, Vec<usize>) {
    if delta <= 0.0 {
        return (interfaces.to_vec(), (0..interfaces.len()).collect());
    }
    interfaces.iter().enumerate().flat_map(|(k, i)| i.shrunk(delta).into_iter().map(move |s| (s, k))).unzip()
}

/// `analysis` with every joint shrunk by `delta` (m) and its statics solved again: the design
/// as it may be built, for a load factor with a fabrication tolerance applied.
pub fn chipped(analysis: &Analysis, delta: f64, settings: &StaticsSettings) -> Result<Analysis, ToleranceError> {
    if !(delta >= 0.0 && delta.is_finite()) {
        return Err(ToleranceError::BadShrink(delta));
    }
    let interfaces = shrunk(&analysis.interfaces, delta).0;
    let statics = statics::solve(&analysis.assembly, &interfaces, settings)?;
    Ok(Analysis { assembly: analysis.assembly.clone(), interfaces, statics, ..*analysis })
}

/// μ of joints turned by `theta` (radians) in their worst direction: tan(atan μ − θ).
pub fn tilted_friction(mu: f64, theta: f64) -> f64 {
    (mu.atan() - theta).max(0.0).tan()
}

/// The shrink and tilt margins of `analysis`'s design (which must stand as drawn).
pub fn margins(
    analysis: &Analysis,
    settings: &StaticsSettings,
    tolerance: &ToleranceSettings,
) -> Result<Margins, ToleranceError> {
    tolerance.validate()?;
    if !analysis.statics.stands {
        return Err(ToleranceError::DoesNotStand(analysis.statics.verdict.words()));
    }
    let (assembly, interfaces) = (&analysis.assembly, analysis.interfaces.as_slice());
    let mut solves = 0;
    let mut solve = |interfaces: &[Interface], settings: &StaticsSettings| {
        solves += 1;
        statics::solve(assembly, interfaces, settings)
    };
    let reach = interfaces.iter().map(radius).fold(0.0, f64::max);
    let step = tolerance.precision * assembly.scale;
    let (delta, past) = bisect(reach, step, |d| solve(&shrunk(interfaces, d).0, settings))?;
    let shrink_governing = past.as_ref().and_then(|(d, r)| {
        let (_, origin) = shrunk(interfaces, *d);
        governing(assembly, interfaces, r, |k| origin.get(k).copied())
    });
    let mu = settings.friction.unwrap_or(assembly.material.friction);
    let angle = mu.atan();
    let (theta, past) = bisect(angle, tolerance.precision * angle.max(f64::MIN_POSITIVE), |t| {
        solve(interfaces, &StaticsSettings { friction: Some(tilted_friction(mu, t)), ..settings.clone() })
    })?;
    let tilt_governing = past.as_ref().and_then(|(_, r)| governing(assembly, interfaces, r, Some));
    let size = block_size(assembly);
    Ok(Margins {
        shrink: Margin { value: delta, relative: delta / size, governing: shrink_governing },
        tilt: Margin {
            value: theta.to_degrees(),
            relative: if angle > 0.0 { theta / angle } else { 0.0 },
            governing: tilt_governing,
        },
        block_size: size,
        solves,
    })
}

/// The largest x in [0, hi] at which `stands_at(x)` stands, to `step`, and the first x found
/// past it with its statics (None when it still stands at `hi`). Standing is taken as monotone
/// in x.
fn bisect(
    hi: f64,
    step: f64,
    mut stands_at: impl FnMut(f64) -> Result<StaticsResult, StaticsError>,
) -> Result<(f64, Option<(f64, StaticsResult)>), ToleranceError> {
    let at_hi = stands_at(hi)?;
    if at_hi.stands {
        return Ok((hi, None));
    }
    let (mut lo, mut past) = (0.0, (hi, at_hi));
    while past.0 - lo > step {
        let mid = 0.5 * (lo + past.0);
        let r = stands_at(mid)?;
        if r.stands {
            lo = mid;
        } else {
            past = (mid, r);
        }
    }
    Ok((lo, Some(past)))
}

/// The interface of `failed` that needs the most tension and friction beyond μ, as the
/// interface of `interfaces` that `origin` maps its index to.
fn governing(
    assembly: &Assembly,
    interfaces: &[Interface],
    failed: &StaticsResult,
    origin: impl Fn(usize) -> Option<usize>,
) -> Option<Governing> {
    let need = |r: &statics::InterfaceResult| r.tension + r.friction_excess;
    let worst = failed.interfaces.iter().filter(|r| need(r) > 0.0).max_by(|x, y| need(x).total_cmp(&need(y)))?;
    let index = origin(worst.index)?;
    let itf = interfaces.get(index)?;
    Some(Governing { interface: index, a: itf.a.name(assembly).to_string(), b: itf.b.name(assembly).to_string() })
}

/// The largest distance of an interface's vertices from its origin: shrunk by this, it is gone.
fn radius(interface: &Interface) -> f64 {
    interface.polygon.iter().map(|p| (p - interface.frame.origin).norm()).fold(0.0, f64::max)
}

/// The cube root of the free blocks' mean volume (the model size when there are none).
fn block_size(assembly: &Assembly) -> f64 {
    let volumes: Vec<f64> = assembly.blocks.iter().filter(|b| !b.support).map(|b| b.mass.volume).collect();
    if volumes.is_empty() {
        return assembly.scale;
    }
    (volumes.iter().sum::<f64>() / volumes.len() as f64).cbrt()
}
