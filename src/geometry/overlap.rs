//! 2D polygon intersection: the only touchpoint of the polygon-clipping crate (i_overlay), with
//! a clip of its own for two convex rings (nearly every pair of faces), the same ring at a
//! fraction of the cost ([`convex`]).

mod convex;

use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::single::SingleFloatOverlay;

/// Intersection of two simple rings (any orientation, non-convex allowed). Returns the pieces,
/// each as its outer ring (CCW) followed by its holes (CW).
pub fn intersect(a: &[[f64; 2]], b: &[[f64; 2]]) -> Vec<Vec<Vec<[f64; 2]>>> {
    if let Some(ring) = convex::intersect(a, b) {
        return if ring.is_empty() { Vec::new() } else { vec![vec![ring]] };
    }
    let a = a.to_vec();
    let b = b.to_vec();
    // i64 engine: the coordinates are snapped to a grid of about 2⁻⁵⁰ of the extent, so the
    // snapping error stays far below every geometric tolerance.
    a.overlay_as::<i64>(&b, OverlayRule::Intersect, FillRule::NonZero)
}

/// A simple ring shrunk by `delta` > 0 (every edge moved inward by `delta`; the erosion of the
/// region by a disc, round at reflex corners): the pieces that remain, each as its outer ring
/// (CCW) followed by its holes (CW); none when the ring is narrower than 2 `delta` everywhere.
pub fn shrink(ring: &[[f64; 2]], delta: f64) -> Vec<Vec<Vec<[f64; 2]>>> {
    use i_overlay::mesh::float::outline::offset::OutlineOffset;
    use i_overlay::mesh::float::style::{LineJoin, OutlineStyle};
    let mut ccw = ring.to_vec();
    if super::polygon::signed_area_2d(&ccw) < 0.0 {
        ccw.reverse();
    }
    // Arcs in steps of 0.1 rad: within δ·(1 − cos 0.05) ≈ 1e-3 δ of the true erosion.
    let style = OutlineStyle::new(-delta).line_join(LineJoin::Round(0.1));
    ccw.outline_as::<i64>(&style)
}

#[cfg(test)]
mod shrink_tests {
    /// Invariant: a rectangle a × b shrunk by δ is the rectangle (a − 2δ) × (b − 2δ), to the
    /// i64 grid; shrunk past half its width it is gone.
    #[test]
    fn a_rectangle_shrinks_by_delta_on_every_side() {
        let rect = [[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]];
        let out = super::shrink(&rect, 0.2);
        assert_eq!(out.len(), 1);
        let ring = &out[0][0];
        let (xs, ys): (Vec<f64>, Vec<f64>) = ring.iter().map(|p| (p[0], p[1])).unzip();
        let span = |v: &[f64]| {
            (v.iter().cloned().fold(f64::INFINITY, f64::min), v.iter().cloned().fold(f64::NEG_INFINITY, f64::max))
        };
        let (x0, x1) = span(&xs);
        let (y0, y1) = span(&ys);
        for (got, want) in [(x0, 0.2), (x1, 2.8), (y0, 0.2), (y1, 0.8)] {
            assert!((got - want).abs() < 1e-9, "{got} vs {want}");
        }
        assert!(super::shrink(&rect, 0.51).is_empty());
    }
}
