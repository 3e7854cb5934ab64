//! Ground motion: the shake table's input, a base acceleration history in up to three
//! components, each a shape (a pulse, a harmonic or a recorded accelerogram, read from records
//! by [`crate::io::accelerogram`]) along a direction. Time in s from the motion's start;
//! acceleration in m/s², world axes, z up.
//!
//! The engines step a shaken design in the base's frame: every support and the floor move as
//! one rigid base, so relative to it every free block carries the inertial load −m a(t) on top
//! of its weight ([`GroundMotion::mean_acceleration`] over each step). That is Newton's law of
//! the same motion with the supports as kinematic bodies on the integrated path, without the
//! integrated displacement's drift — and the blocks' reported drifts and rotations are the
//! ones relative to the ground. A motion that names its supports ([`GroundMotion::supports`])
//! moves only those, as kinematic bodies along the integrated path (by
//! [`GroundMotion::displacement`] each step), the other supports and the floor still; the
//! drifts are then the ones in the world frame.
//!
//! Shapes, for amplitude A and duration (period) T, zero outside them:
//! - rectangular pulse: A for 0 ≤ t < T;
//! - one-sine pulse: A sin(2π t / T) for 0 ≤ t ≤ T (one full cycle);
//! - Ricker wavelet: A (1 − 2c τ²) e^(−c τ²), τ = t − T, c = π² / T² (peak frequency 1 / T),
//!   for 0 ≤ t ≤ 2T;
//! - harmonic: A sin(2π t / T) for `cycles` periods;
//! - record: its samples joined linearly, zero before the first and after the last (times
//!   from its first).

pub mod synthetic;

use crate::geometry::Vector3;
use std::sync::Arc;
use thiserror::Error;

/// Standard gravity, m/s² (a history given in g is converted with it).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// The largest acceleration a ground motion may hold, in g (strong-motion peaks stay below
/// 5 g; a larger value is a wrong unit or a corrupt record).
pub const LARGEST: f64 = 20.0;

/// The longest pulse, period or motion, s.
pub const LONGEST: f64 = 3600.0;

/// A base acceleration history.
#[derive(Clone, Debug, PartialEq)]
pub struct Accelerogram {
    /// Sample times, s, strictly increasing from the history's first.
    pub times: Vec<f64>,
    /// Acceleration at each time, m/s².
    pub acceleration: Vec<f64>,
}

impl Accelerogram {
    /// The largest |acceleration|, m/s².
    pub fn peak(&self) -> f64 {
        self.acceleration.iter().fold(0.0, |m, a| m.max(a.abs()))
    }

    /// The history's length, s.
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0) - self.times.first().copied().unwrap_or(0.0)
    }
}

/// A record with its velocity integrated at the samples (trapezoids: exact for the linear
/// joins), so that a step's mean acceleration costs one search.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    history: Accelerogram,
    velocity: Vec<f64>,
}

impl Record {
    /// The record of `history` (times relative to its first sample).
    pub fn new(history: Accelerogram) -> Self {
        let mut velocity = Vec::with_capacity(history.times.len());
        let mut v = 0.0;
        for k in 0..history.times.len() {
            if k > 0 {
                let dt = history.times[k] - history.times[k - 1];
                v += 0.5 * dt * (history.acceleration[k] + history.acceleration[k - 1]);
            }
            velocity.push(v);
        }
        Self { history, velocity }
    }

    /// The samples.
    pub fn history(&self) -> &Accelerogram {
        &self.history
    }

    /// Velocity (m/s) at `t` s after the first sample.
    fn velocity(&self, t: f64) -> f64 {
        let h = &self.history;
        let (Some(&t0), Some(&last)) = (h.times.first(), self.velocity.last()) else { return 0.0 };
        let t = t + t0;
        let k = h.times.partition_point(|&s| s <= t);
        if k == 0 {
            return 0.0;
        }
        if k == h.times.len() {
            return last;
        }
        let (a0, a1, dt, tau) =
            (h.acceleration[k - 1], h.acceleration[k], h.times[k] - h.times[k - 1], t - h.times[k - 1]);
        self.velocity[k - 1] + a0 * tau + 0.5 * (a1 - a0) / dt * tau * tau
    }
}

/// A pulse's shape (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PulseShape {
    /// A for the whole duration.
    Rectangular,
    /// One full sine cycle.
    OneSine,
    /// The Ricker wavelet of period T centred at T.
    Ricker,
}

impl PulseShape {
    /// Its name on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rectangular => "rect",
            Self::OneSine => "sine",
            Self::Ricker => "ricker",
        }
    }

    /// The shape a name gives (`rect`, `sine`, `ricker`).
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Rectangular, Self::OneSine, Self::Ricker].into_iter().find(|s| s.name() == name)
    }
}

/// One component's shape in time (module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum Excitation {
    /// A pulse of `amplitude` (m/s²) and `duration` (s).
    Pulse {
        /// Its shape.
        shape: PulseShape,
        /// Peak acceleration, m/s² (signed).
        amplitude: f64,
        /// Duration (the Ricker wavelet's period), s.
        duration: f64,
    },
    /// `cycles` periods of a sine.
    Harmonic {
        /// Amplitude, m/s².
        amplitude: f64,
        /// Period, s.
        period: f64,
        /// Number of periods (any positive number).
        cycles: f64,
    },
    /// A recorded accelerogram.
    Record(Arc<Record>),
}

impl Excitation {
    /// When it ends, s.
    pub fn end(&self) -> f64 {
        match self {
            Self::Pulse { shape: PulseShape::Ricker, duration, .. } => 2.0 * duration,
            Self::Pulse { duration, .. } => *duration,
            Self::Harmonic { period, cycles, .. } => period * cycles,
            Self::Record(r) => r.history.duration(),
        }
    }

    /// Acceleration at `t`, m/s².
    pub fn acceleration(&self, t: f64) -> f64 {
        if !(0.0..=self.end()).contains(&t) {
            return 0.0;
        }
        let sine = |a: f64, period: f64| a * (std::f64::consts::TAU * t / period).sin();
        match self {
            Self::Pulse { shape: PulseShape::Rectangular, amplitude, duration } => {
                if t < *duration {
                    *amplitude
                } else {
                    0.0
                }
            }
            Self::Pulse { shape: PulseShape::OneSine, amplitude, duration } => sine(*amplitude, *duration),
            Self::Pulse { shape: PulseShape::Ricker, amplitude, duration } => {
                let (tau, c) = (t - duration, (std::f64::consts::PI / duration).powi(2));
                amplitude * (1.0 - 2.0 * c * tau * tau) * (-c * tau * tau).exp()
            }
            Self::Harmonic { amplitude, period, .. } => sine(*amplitude, *period),
            Self::Record(r) if r.history.times.len() < 2 => 0.0,
            Self::Record(r) => {
                let h = &r.history;
                let t = t + h.times[0];
                let k = h.times.partition_point(|&s| s <= t).clamp(1, h.times.len() - 1);
                let f = (t - h.times[k - 1]) / (h.times[k] - h.times[k - 1]);
                h.acceleration[k - 1] + f * (h.acceleration[k] - h.acceleration[k - 1])
            }
        }
    }

    /// The base's velocity at `t` (m/s): the acceleration's integral from 0, in closed form.
    pub fn velocity(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, self.end());
        let cosine = |a: f64, period: f64| {
            a * period / std::f64::consts::TAU * (1.0 - (std::f64::consts::TAU * t / period).cos())
        };
        match self {
            Self::Pulse { shape: PulseShape::Rectangular, amplitude, .. } => amplitude * t,
            Self::Pulse { shape: PulseShape::OneSine, amplitude, duration } => cosine(*amplitude, *duration),
            Self::Pulse { shape: PulseShape::Ricker, amplitude, duration } => {
                let (tau, c) = (t - duration, (std::f64::consts::PI / duration).powi(2));
                amplitude * (tau * (-c * tau * tau).exp() + duration * (-c * duration * duration).exp())
            }
            Self::Harmonic { amplitude, period, .. } => cosine(*amplitude, *period),
            Self::Record(r) => r.velocity(t),
        }
    }

    /// The largest |acceleration|, m/s².
    pub fn peak(&self) -> f64 {
        match self {
            Self::Pulse { amplitude, .. } | Self::Harmonic { amplitude, .. } => amplitude.abs(),
            Self::Record(r) => r.history.peak(),
        }
    }
}

impl Excitation {
    /// A pulse from `SHAPE:AMP_G,DURATION_S` (SHAPE rect, sine or ricker; the amplitude in g of
    /// `g` m/s²); the message names what is wrong.
    pub fn parse_pulse(text: &str, g: f64) -> Result<Self, String> {
        let (shape, rest) = text
            .split_once(':')
            .ok_or_else(|| format!("'{text}': expected SHAPE:AMP_G,DURATION_S (SHAPE rect, sine or ricker)"))?;
        let shape = PulseShape::from_name(shape.trim())
            .ok_or_else(|| format!("'{text}': unknown shape '{shape}': expected rect, sine or ricker"))?;
        let [amplitude, duration] = numbers::<2>(text, rest, "AMP_G,DURATION_S")?;
        Ok(Self::Pulse { shape, amplitude: amplitude * g, duration })
    }

    /// A harmonic from `AMP_G,PERIOD_S,CYCLES` (the amplitude in g of `g` m/s²).
    pub fn parse_harmonic(text: &str, g: f64) -> Result<Self, String> {
        let [amplitude, period, cycles] = numbers::<3>(text, text, "AMP_G,PERIOD_S,CYCLES")?;
        Ok(Self::Harmonic { amplitude: amplitude * g, period, cycles })
    }
}

/// `N` comma-separated numbers in `part` of `text` (`form` names them in the message).
fn numbers<const N: usize>(text: &str, part: &str, form: &str) -> Result<[f64; N], String> {
    let v: Vec<f64> = part
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}': expected {N} numbers {form}"))?;
    let n = v.len();
    v.try_into().map_err(|_| format!("'{text}': expected {N} numbers {form}, got {n}"))
}

/// One component: a shape along a direction.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// The shape in time.
    pub excitation: Excitation,
    /// The direction it accelerates the base along (normalised when the motion is checked).
    pub direction: Vector3,
}

/// A ground motion: up to three components, summed, times a scale.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundMotion {
    /// Its components.
    pub components: Vec<Component>,
    /// A factor on every component's acceleration.
    pub scale: f64,
    /// The supports it moves, by name; empty: the whole base (every support and the floor).
    pub supports: Vec<String>,
}

/// Why a ground motion cannot run; each names the component (1-based) and the value.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GroundMotionError {
    /// No component, or more than three.
    #[error("ground motion: {0} components (one to three)")]
    Components(usize),
    /// An amplitude (or a record's peak times the scale) is not finite or beyond [`LARGEST`] g.
    #[error("ground motion component {component}: amplitude {g} g must be finite and at most {LARGEST} g")]
    Amplitude {
        /// The component, 1-based.
        component: usize,
        /// The amplitude times the scale, g.
        g: f64,
    },
    /// A duration, period or number of cycles is not finite, not > 0, or too long.
    #[error(
        "ground motion component {component}: {name} = {value} must be finite, > 0 and its motion at most {LONGEST} s long"
    )]
    Length {
        /// The component, 1-based.
        component: usize,
        /// What is wrong (`duration`, `period`, `cycles`).
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The component lasts longer than [`LONGEST`].
    #[error(
        "ground motion component {component}: it lasts {end} s (duration × cycles), more than the {LONGEST} s allowed"
    )]
    TooLong {
        /// The component, 1-based.
        component: usize,
        /// When it would end, s.
        end: f64,
    },
    /// A direction that is zero or not finite.
    #[error("ground motion component {component}: direction {direction:?} must be finite and non-zero")]
    Direction {
        /// The component, 1-based.
        component: usize,
        /// The direction given.
        direction: [f64; 3],
    },
    /// The scale is not finite.
    #[error("ground motion: scale {0} must be finite")]
    Scale(f64),
    /// A shaken support that is no support of the design.
    #[error("ground motion: support '{name}': {why}")]
    Support {
        /// The name given.
        name: String,
        /// What is wrong.
        why: &'static str,
    },
    /// A record with fewer than two samples.
    #[error("ground motion component {0}: a record needs at least two samples")]
    ShortRecord(usize),
}

impl GroundMotion {
    /// One component along the horizontal `azimuth` (degrees from +x towards +y).
    pub fn horizontal(excitation: Excitation, azimuth: f64) -> Self {
        let (s, c) = azimuth.to_radians().sin_cos();
        let components = vec![Component { excitation, direction: Vector3::new(c, s, 0.0) }];
        Self { components, scale: 1.0, supports: Vec::new() }
    }

    /// Every amplitude, length, direction and the scale checked (one error naming the first
    /// that is wrong), the directions normalised.
    pub fn validated(mut self) -> Result<Self, GroundMotionError> {
        if self.components.is_empty() || self.components.len() > 3 {
            return Err(GroundMotionError::Components(self.components.len()));
        }
        if !self.scale.is_finite() {
            return Err(GroundMotionError::Scale(self.scale));
        }
        for (k, c) in self.components.iter_mut().enumerate() {
            let component = k + 1;
            let norm = c.direction.norm();
            if !(norm.is_finite() && norm > 0.0) {
                return Err(GroundMotionError::Direction { component, direction: c.direction.into() });
            }
            c.direction /= norm;
            let lengths: Vec<(&'static str, f64)> = match &c.excitation {
                Excitation::Pulse { duration, .. } => vec![("duration", *duration)],
                Excitation::Harmonic { period, cycles, .. } => vec![("period", *period), ("cycles", *cycles)],
                Excitation::Record(r) if r.history.times.len() < 2 => {
                    return Err(GroundMotionError::ShortRecord(component));
                }
                Excitation::Record(r) => vec![("duration", r.history.duration())],
            };
            for (name, value) in lengths {
                if !(value > 0.0 && value.is_finite()) {
                    return Err(GroundMotionError::Length { component, name, value });
                }
            }
            if c.excitation.end() > LONGEST {
                return Err(GroundMotionError::TooLong { component, end: c.excitation.end() });
            }
            let g = c.excitation.peak() * self.scale.abs() / STANDARD_GRAVITY;
            if !(g.is_finite() && g <= LARGEST) {
                return Err(GroundMotionError::Amplitude { component, g });
            }
        }
        Ok(self)
    }

    /// When the last component ends, s.
    pub fn end(&self) -> f64 {
        self.components.iter().map(|c| c.excitation.end()).fold(0.0, f64::max)
    }

    /// The base's acceleration at `t`, m/s².
    pub fn acceleration(&self, t: f64) -> Vector3 {
        self.components.iter().map(|c| c.direction * c.excitation.acceleration(t)).sum::<Vector3>() * self.scale
    }

    /// The base's velocity at `t`, m/s.
    pub fn velocity(&self, t: f64) -> Vector3 {
        self.components.iter().map(|c| c.direction * c.excitation.velocity(t)).sum::<Vector3>() * self.scale
    }

    /// A shaken support's displacement over the step [t0, t1] (m): the base's velocity at the
    /// step's end times the step — symplectic Euler's own position update, the blocks'. Their
    /// motion relative to the support is then the base frame's to round-off: the path's
    /// trapezoid would leave the support ½ h V ahead of what the blocks, updated with their
    /// end-of-step velocities, can follow (a sliding block's slip off by ½ μ g h t).
    pub fn displacement(&self, t0: f64, t1: f64) -> Vector3 {
        self.velocity(t1) * (t1 - t0)
    }

    /// The paths of the named supports it moves (their vectors unused: the run moves them by
    /// [`Self::displacement`]); none when it moves the whole base. A name that is no block,
    /// or a free block, is an error naming it.
    pub fn shaken_supports(
        &self,
        assembly: &crate::model::Assembly,
    ) -> Result<Vec<crate::dynamics::SupportPath>, GroundMotionError> {
        let mut paths = Vec::new();
        for name in &self.supports {
            let block = assembly.blocks.iter().position(|b| &b.name == name);
            let why = match block {
                None => Some("no block has this name"),
                Some(i) if !assembly.blocks[i].support => Some("it is a free block, not a support"),
                Some(i) if paths.iter().any(|p: &crate::dynamics::SupportPath| p.block == i) => {
                    Some("it is named twice")
                }
                Some(_) => None,
            };
            if let Some(why) = why {
                return Err(GroundMotionError::Support { name: name.clone(), why });
            }
            let zero = Vector3::zeros();
            paths.push(crate::dynamics::SupportPath { block: block.unwrap_or(0), translation: zero, rotation: zero });
        }
        Ok(paths)
    }

    /// The mean acceleration over [t0, t1] (m/s²): the velocity's change over the interval,
    /// so that a step takes the base's whole impulse whatever the step's length (a pulse's
    /// edge inside a step included).
    pub fn mean_acceleration(&self, t0: f64, t1: f64) -> Vector3 {
        (self.velocity(t1) - self.velocity(t0)) / (t1 - t0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: each shape's velocity is its acceleration's integral (Simpson's rule on a
    /// fine grid, to 1e-9 of the peak × the length) and starts at 0.
    #[test]
    fn velocity_integrates_acceleration() {
        let record = Accelerogram { times: vec![1.0, 1.3, 1.5, 2.2], acceleration: vec![0.0, 2.0, -1.0, 0.5] };
        let shapes = [
            Excitation::Pulse { shape: PulseShape::Rectangular, amplitude: 2.0, duration: 0.7 },
            Excitation::Pulse { shape: PulseShape::OneSine, amplitude: -1.5, duration: 0.4 },
            Excitation::Pulse { shape: PulseShape::Ricker, amplitude: 3.0, duration: 0.5 },
            Excitation::Harmonic { amplitude: 1.0, period: 0.3, cycles: 2.5 },
            Excitation::Record(Arc::new(Record::new(record))),
        ];
        for e in &shapes {
            assert_eq!(e.velocity(0.0), 0.0, "{e:?}");
            let end = e.end() * 1.2;
            let n = 240_000;
            let h = end / n as f64;
            let mut integral = 0.0;
            for k in 0..n / 2 {
                let t = 2.0 * k as f64 * h;
                integral += h / 3.0 * (e.acceleration(t) + 4.0 * e.acceleration(t + h) + e.acceleration(t + 2.0 * h));
            }
            // The rectangle's edge and the record's kinks are inside one Simpson panel.
            let tolerance = 1e-9 * e.peak() * end + 2.0 * h * e.peak();
            assert!((integral - e.velocity(end)).abs() < tolerance, "{e:?}: {integral} vs {}", e.velocity(end));
        }
    }

    /// Invariant: a bad amplitude, length, direction or scale is one error naming it.
    #[test]
    fn bad_motions_are_refused() {
        let pulse = |amplitude: f64, duration: f64| {
            GroundMotion::horizontal(Excitation::Pulse { shape: PulseShape::Rectangular, amplitude, duration }, 0.0)
        };
        assert!(matches!(pulse(f64::NAN, 1.0).validated(), Err(GroundMotionError::Amplitude { .. })));
        assert!(matches!(pulse(25.0 * STANDARD_GRAVITY, 1.0).validated(), Err(GroundMotionError::Amplitude { .. })));
        assert!(matches!(pulse(1.0, 0.0).validated(), Err(GroundMotionError::Length { name: "duration", .. })));
        assert!(matches!(pulse(1.0, 1e5).validated(), Err(GroundMotionError::TooLong { .. })));
        let mut m = pulse(1.0, 1.0);
        m.scale = f64::INFINITY;
        assert!(matches!(m.validated(), Err(GroundMotionError::Scale(_))));
        let mut m = pulse(1.0, 1.0);
        m.components[0].direction = Vector3::zeros();
        assert!(matches!(m.validated(), Err(GroundMotionError::Direction { component: 1, .. })));
        let ok = pulse(-2.0, 0.5).validated().expect("a valid pulse");
        assert_eq!(ok.mean_acceleration(0.25, 0.75), Vector3::new(-1.0, 0.0, 0.0));
    }
}
