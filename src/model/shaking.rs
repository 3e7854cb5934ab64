//! A ground motion as a scene gives it (the `ground_motion` key; `voussoir shake` runs it when
//! no motion is named on the command line): one to three components, each a pulse, a harmonic
//! or a record along a direction, and a scale. Amplitudes in g (the design's gravity),
//! durations and periods in s, directions as an azimuth (degrees from +x towards +y) or a
//! vector. The engines' form, with records read, is [`crate::dynamics::ground_motion`].

use serde::{Deserialize, Serialize};

/// The scene's ground motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shaking {
    /// Its components.
    pub components: Vec<ShakingComponent>,
    /// A factor on every component.
    #[serde(default = "one")]
    pub scale: f64,
    /// The supports it moves, by name (default: every support and the floor, as one base).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub supports: Vec<String>,
}

fn one() -> f64 {
    1.0
}

/// One component: exactly one of `pulse`, `harmonic`, `record`, and a direction (`azimuth` or
/// `direction`; default +x).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShakingComponent {
    /// A pulse.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pulse: Option<PulseSpec>,
    /// A harmonic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub harmonic: Option<HarmonicSpec>,
    /// A record: a `.AT2` or `.csv` path (relative to the scene file), or `builtin:elcentro`,
    /// `builtin:synthetic?…`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<String>,
    /// A horizontal direction, degrees from +x towards +y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub azimuth: Option<f64>,
    /// A direction vector (for a vertical component: [0, 0, 1]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f64; 3]>,
}

/// A pulse: `shape` rect, sine or ricker.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PulseSpec {
    /// `rect`, `sine` or `ricker`.
    pub shape: String,
    /// Peak acceleration, g.
    pub amplitude: f64,
    /// Duration (the Ricker wavelet's period), s.
    pub duration: f64,
}

/// A harmonic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicSpec {
    /// Amplitude, g.
    pub amplitude: f64,
    /// Period, s.
    pub period: f64,
    /// Number of periods.
    pub cycles: f64,
}
