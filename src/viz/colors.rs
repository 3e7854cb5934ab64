//! The seed paper's diagram colours as pure functions (docs/design.md#diagrams), shared by the glTF export and
//! the viewer, and the verdict colours of the viewer's panel and the plots. Diagram colours are
//! linear RGB in [0, 1]; verdict colours are sRGB ([`Srgb`]).
//!
//! - Compression–tension: per interface vertex, the net normal force normalised by the largest
//!   |net normal force| on the same face; blue for compression (light → deep with the share),
//!   red for tension, grey where the vertex carries nothing.
//! - Friction (the seed paper's "solid colours between yellow and red"): one colour per
//!   interface from its friction resultant's use u = |F_t| / (μ · compression) — grey without
//!   friction, yellow up to a user threshold, orange shades from the threshold up to μ (deeper
//!   nearer μ), red where the friction model is exceeded (or friction acts without compression).
//! - Density: blocks from light sand (lightest) to deep umber (densest), an infill design's.
//! - Verdicts and joint states: the colour of what an analysis says (the viewer's panel, the
//!   plots' strips and text, the mechanism's moving interfaces).

use crate::statics::{JointState, Verdict};

/// Linear RGB.
pub type Rgb = [f32; 3];

/// Nothing carried (a face without force), and friction without use.
pub const GREY: Rgb = [0.55, 0.55, 0.55];
/// Friction used up to the diagram's threshold.
pub const YELLOW: Rgb = [1.0, 0.9, 0.1];
/// Tension, and friction beyond the model's capacity.
pub const RED: Rgb = [0.85, 0.05, 0.05];
const BLUE_LIGHT: Rgb = [0.72, 0.82, 1.0];
const BLUE_DEEP: Rgb = [0.02, 0.15, 0.75];
const RED_LIGHT: Rgb = [1.0, 0.72, 0.72];
const ORANGE_LIGHT: Rgb = [1.0, 0.45, 0.05];
const ORANGE_DEEP: Rgb = [0.85, 0.17, 0.0];

/// sRGB as displayed, in [0, 1]: text and plot marks, which are not shaded.
pub type Srgb = [f32; 3];

/// A linear RGB colour as displayed (the sRGB transfer function): what a PNG, the viewer and
/// the HTML report show of it.
pub fn linear_to_srgb(c: Rgb) -> Srgb {
    c.map(|v| {
        let v = v.clamp(0.0, 1.0);
        if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }
    })
}

/// An sRGB colour from 8-bit channels.
pub const fn srgb8(r: u8, g: u8, b: u8) -> Srgb {
    [r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0]
}

// Verdicts on the viewer's dark panel: light shades.
/// It stands: green.
pub const STANDS: Srgb = [0.35, 0.85, 0.45];
/// It needs tension (or does not stand otherwise): red.
pub const FAILS: Srgb = [0.95, 0.3, 0.25];
/// It needs friction beyond μ only: orange.
pub const FRICTION_EXCEEDED: Srgb = [0.95, 0.5, 0.15];
/// The solver could not tell: yellow.
pub const UNRESOLVED: Srgb = [0.9, 0.8, 0.2];
/// No verdict yet (nothing analysed): grey.
pub const NO_VERDICT: Srgb = [0.7, 0.7, 0.7];

// Verdicts on a plot's white: deep shades of the same hues, legible as text.
/// It stands, on white: deep green.
pub const STANDS_ON_WHITE: Srgb = srgb8(30, 120, 50);
/// It fails, on white: deep red.
pub const FAILS_ON_WHITE: Srgb = srgb8(190, 20, 20);

/// A moved block in a motion picture (the viewer's motion pane, the mechanism PNG): violet,
/// a colour no diagram legend uses.
pub const MOVED: Srgb = [0.60, 0.45, 0.88];

/// Blocks by density (an infill design's): light sand at the lowest density shown, deep umber
/// at the highest, linear between (linear RGB).
pub const DENSITY_LOW: Rgb = [0.93, 0.86, 0.66];
/// The highest density shown: deep umber.
pub const DENSITY_HIGH: Rgb = [0.25, 0.10, 0.03];

/// The colour of density `d` on the scale from `lo` to `hi` (the middle when they are equal).
pub fn density(d: f64, lo: f64, hi: f64) -> Rgb {
    let t = if hi > lo { ((d - lo) / (hi - lo)).clamp(0.0, 1.0) as f32 } else { 0.5 };
    [0, 1, 2].map(|k| DENSITY_LOW[k] + t * (DENSITY_HIGH[k] - DENSITY_LOW[k]))
}

/// The colour of `verdict` on the viewer's dark panel (`None`: no analysis yet).
pub fn verdict(verdict: Option<Verdict>) -> Srgb {
    match verdict {
        Some(Verdict::Stands) => STANDS,
        Some(Verdict::NeedsTension | Verdict::NeedsTensionAndFriction | Verdict::Crushes | Verdict::Unsupported) => {
            FAILS
        }
        Some(Verdict::NeedsFriction) => FRICTION_EXCEEDED,
        Some(Verdict::Unresolved) => UNRESOLVED,
        None => NO_VERDICT,
    }
}

/// Stands or not, on a plot's white.
pub fn stands_on_white(stands: bool) -> Srgb {
    if stands { STANDS_ON_WHITE } else { FAILS_ON_WHITE }
}

/// The colour of a mechanism's interface by what it does (linear RGB, like the diagrams).
pub fn joint_state(state: JointState) -> Rgb {
    match state {
        JointState::Closed => GREY,
        JointState::Hinging => [0.85, 0.45, 0.0],
        JointState::Opening => [0.8, 0.1, 0.1],
        JointState::Sliding => [0.1, 0.35, 0.85],
    }
}

/// Below this share of the face's largest force (or of the capacity) a value counts as zero.
pub const ZERO_SHARE: f64 = 1e-6;

fn lerp(a: Rgb, b: Rgb, t: f64) -> Rgb {
    // a(1 − t) + bt: exactly a at t = 0 and b at t = 1.
    let t = t.clamp(0.0, 1.0) as f32;
    [0, 1, 2].map(|k| a[k] * (1.0 - t) + b[k] * t)
}

/// Compression–tension colour of a vertex whose net normal force is `normal` (N, compression
/// positive) on a face whose largest |net normal force| is `face_max`.
pub fn compression_tension(normal: f64, face_max: f64) -> Rgb {
    let loaded = face_max > 0.0 && normal.is_finite() && normal.abs() > ZERO_SHARE * face_max;
    if !loaded {
        return GREY;
    }
    let share = normal.abs() / face_max;
    if normal > 0.0 { lerp(BLUE_LIGHT, BLUE_DEEP, share) } else { lerp(RED_LIGHT, RED, share) }
}

/// What an interface's friction does, by the friction diagram's bands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrictionBand {
    /// No friction acts (below the solver's resolution).
    None,
    /// Use u ≤ the threshold.
    Low(f64),
    /// Use above the threshold, within what the model allows.
    High(f64),
    /// Beyond what the friction model allows, or friction without compression.
    Exceeded,
}

impl FrictionBand {
    /// The band of a friction use `u` (|F_t| / μN, infinite without compression) whose model is
    /// `exceeded` or not, against `threshold` in [0, 1].
    pub fn of(u: f64, exceeded: bool, threshold: f64) -> Self {
        if exceeded || u.is_infinite() || u.is_nan() {
            Self::Exceeded
        } else if u <= 0.0 {
            Self::None
        } else if u <= threshold.clamp(0.0, 1.0) {
            Self::Low(u)
        } else {
            Self::High(u)
        }
    }

    /// Its colour: orange from light just above `threshold` to deep at μ (and beyond, where
    /// the 8-sided pyramid allows up to 1.08 μ on its diagonals).
    pub fn colour(self, threshold: f64) -> Rgb {
        match self {
            Self::None => GREY,
            Self::Low(_) => YELLOW,
            Self::High(u) => {
                let threshold = threshold.clamp(0.0, 1.0);
                let t = if threshold < 1.0 { (u - threshold) / (1.0 - threshold) } else { 1.0 };
                lerp(ORANGE_LIGHT, ORANGE_DEEP, t)
            }
            Self::Exceeded => RED,
        }
    }

    /// The band's name in the legend and the panel.
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "no friction",
            Self::Low(_) => "yellow",
            Self::High(_) => "orange",
            Self::Exceeded => "red",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blueish(c: Rgb) -> bool {
        c[2] > c[0] + 0.2 && c[2] > c[1]
    }
    fn reddish(c: Rgb) -> bool {
        c[0] > c[1] + 0.2 && c[0] > c[2] + 0.2
    }

    #[test]
    fn compression_is_blue_deeper_with_the_share_tension_red_nothing_grey() {
        assert_eq!(compression_tension(10.0, 10.0), BLUE_DEEP);
        assert_eq!(compression_tension(-10.0, 10.0), RED);
        assert!(blueish(compression_tension(1.0, 10.0)) && reddish(compression_tension(-1.0, 10.0)));
        // Deeper blue (darker) with a larger share.
        let (lo, hi) = (compression_tension(2.0, 10.0), compression_tension(8.0, 10.0));
        assert!(hi.iter().sum::<f32>() < lo.iter().sum::<f32>());
        for (n, m) in [(0.0, 10.0), (1e-9, 10.0), (5.0, 0.0), (f64::NAN, 1.0), (1.0, f64::NAN)] {
            assert_eq!(compression_tension(n, m), GREY, "{n} {m}");
        }
        // Normalised per face: the same share gives the same colour in any unit.
        assert_eq!(compression_tension(3.0, 4.0), compression_tension(3e6, 4e6));
    }

    #[test]
    fn friction_bands_grey_yellow_orange_red() {
        let t = 0.5;
        assert_eq!(FrictionBand::of(0.0, false, t), FrictionBand::None);
        assert_eq!(FrictionBand::of(0.2, false, t).colour(t), YELLOW);
        assert_eq!(FrictionBand::of(0.5, false, t).colour(t), YELLOW, "the threshold itself is still low");
        assert_eq!(FrictionBand::of(1.0, false, t).colour(t), ORANGE_DEEP, "μ itself");
        let just_above = FrictionBand::of(0.5001, false, t).colour(t);
        assert!((just_above[1] - ORANGE_LIGHT[1]).abs() < 1e-3, "orange starts light: {just_above:?}");
        // Deeper (less green) nearer μ.
        assert!(FrictionBand::of(0.9, false, t).colour(t)[1] < FrictionBand::of(0.6, false, t).colour(t)[1]);
        // The pyramid's diagonal allows 1.08 μ: deep orange, not red, unless the model is exceeded.
        assert_eq!(FrictionBand::of(1.05, false, t).colour(t), ORANGE_DEEP);
        assert_eq!(FrictionBand::of(0.3, true, t).colour(t), RED);
        assert_eq!(FrictionBand::of(f64::INFINITY, false, t).colour(t), RED, "friction without compression");
        // Threshold 1: everything allowed is yellow.
        assert_eq!(FrictionBand::of(0.99, false, 1.0).colour(1.0), YELLOW);
    }
}
