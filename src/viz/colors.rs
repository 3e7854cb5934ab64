//! The seed paper's diagram colours as pure functions (docs/design.md#diagrams), shared by the glTF export and
//! the viewer, and the verdict colours of the viewer's panel and the plots. Diagram colours are
//! linear RGB in [0, 1]; verdict colours are sRGB ([`Srgb`]).
//!
//! - Compression–tension: per interface vertex, the net normal force normalised by the largest
//!   |net normal force| on the same face; blue for compression (light → deep with the share),
//!   red for tension, grey where the vertex carries nothing.
//! - Friction: per vertex, the friction utilisation u = |f_t| / (μ · compression); grey without
//!   friction, yellow up to a user threshold, orange shades from the threshold up to the allowed
//!   maximum (u = 1), red beyond it (and where friction acts without compression).
//! - Verdicts and joint states: the colour of what an analysis says (the viewer's panel, the
//!   plots' strips and text, the mechanism's moving interfaces).

use crate::statics::{JointState, Verdict};

/// Linear RGB.
pub type Rgb = [f32; 3];

pub const GREY: Rgb = [0.55, 0.55, 0.55];
pub const YELLOW: Rgb = [1.0, 0.9, 0.1];
pub const RED: Rgb = [0.85, 0.05, 0.05];
const BLUE_LIGHT: Rgb = [0.72, 0.82, 1.0];
const BLUE_DEEP: Rgb = [0.02, 0.15, 0.75];
const RED_LIGHT: Rgb = [1.0, 0.72, 0.72];
const ORANGE_LIGHT: Rgb = [1.0, 0.72, 0.25];
const ORANGE_DEEP: Rgb = [0.9, 0.38, 0.0];

/// sRGB as displayed, in [0, 1]: text and plot marks, which are not shaded.
pub type Srgb = [f32; 3];

/// An sRGB colour from 8-bit channels.
pub const fn srgb8(r: u8, g: u8, b: u8) -> Srgb {
    [r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0]
}

// Verdicts on the viewer's dark panel: light shades.
pub const STANDS: Srgb = [0.35, 0.85, 0.45];
pub const FAILS: Srgb = [0.95, 0.3, 0.25];
pub const FRICTION_EXCEEDED: Srgb = [0.95, 0.5, 0.15];
pub const UNRESOLVED: Srgb = [0.9, 0.8, 0.2];
pub const NO_VERDICT: Srgb = [0.7, 0.7, 0.7];

// Verdicts on a plot's white: deep shades of the same hues, legible as text.
pub const STANDS_ON_WHITE: Srgb = srgb8(30, 120, 50);
pub const FAILS_ON_WHITE: Srgb = srgb8(190, 20, 20);

/// The colour of `verdict` on the viewer's dark panel (`None`: no analysis yet).
pub fn verdict(verdict: Option<Verdict>) -> Srgb {
    match verdict {
        Some(Verdict::Stands) => STANDS,
        Some(Verdict::NeedsTension | Verdict::NeedsTensionAndFriction | Verdict::Unsupported) => FAILS,
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

/// Friction colour of a vertex with friction magnitude `friction` (N) and capacity
/// `capacity` = μ · compression (N); `threshold` in (0, 1] is the user's "low friction" limit
/// as a fraction of the capacity.
pub fn friction(friction: f64, capacity: f64, threshold: f64) -> Rgb {
    let scale = friction.abs().max(capacity.abs());
    let acts = scale > 0.0 && friction.abs() > ZERO_SHARE * scale;
    if !acts {
        return GREY;
    }
    let allowed = capacity > 0.0;
    if !allowed {
        return RED; // friction without compression: nothing allows it
    }
    let u = friction.abs() / capacity;
    let threshold = threshold.clamp(0.0, 1.0);
    if u <= threshold {
        YELLOW
    } else if u <= 1.0 + 1e-9 {
        let t = if threshold < 1.0 { (u - threshold) / (1.0 - threshold) } else { 1.0 };
        lerp(ORANGE_LIGHT, ORANGE_DEEP, t)
    } else {
        RED
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
    fn friction_grey_yellow_orange_red() {
        let t = 0.5;
        assert_eq!(friction(0.0, 10.0, t), GREY);
        assert_eq!(friction(0.0, 0.0, t), GREY);
        assert_eq!(friction(2.0, 10.0, t), YELLOW);
        assert_eq!(friction(5.0, 10.0, t), YELLOW, "the threshold itself is still low");
        assert_eq!(friction(10.0, 10.0, t), ORANGE_DEEP, "the allowed maximum");
        let just_above = friction(5.0001, 10.0, t);
        assert!((just_above[1] - ORANGE_LIGHT[1]).abs() < 1e-3, "orange starts light: {just_above:?}");
        assert_eq!(friction(10.5, 10.0, t), RED);
        assert_eq!(friction(1.0, 0.0, t), RED, "friction without compression");
        // Threshold 1: everything allowed is yellow.
        assert_eq!(friction(9.9, 10.0, 1.0), YELLOW);
        assert_eq!(friction(10.1, 10.0, 1.0), RED);
    }
}
