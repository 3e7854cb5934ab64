//! 2D polygon intersection: the only touchpoint of the polygon-clipping crate (i_overlay).

use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::single::SingleFloatOverlay;

/// Intersection of two simple rings (any orientation, non-convex allowed). Returns the pieces,
/// each as its outer ring (CCW) followed by its holes (CW).
pub fn intersect(a: &[[f64; 2]], b: &[[f64; 2]]) -> Vec<Vec<Vec<[f64; 2]>>> {
    let a = a.to_vec();
    let b = b.to_vec();
    // i64 engine: the coordinates are snapped to a grid of about 2⁻⁵⁰ of the extent, so the
    // snapping error stays far below every geometric tolerance.
    a.overlay_as::<i64>(&b, OverlayRule::Intersect, FillRule::NonZero)
}
