//! The intersection of two convex rings by clipping one against each edge of the other
//! (Sutherland–Hodgman), written to give i_overlay's answer for such a pair: one ring, CCW,
//! without repeated or collinear vertices, starting at the vertex before the leftmost-lowest
//! one. Detection meets this case in nearly every pair of faces (the Armadillo: 3 032 of
//! 3 045 faces are convex), where i_overlay's general overlay (segment splitting, graph,
//! contour tracing) costs ~6 µs a call.
//!
//! Points within [`EPS`] of the rings' extent of a clipping line count as on it (a shared
//! face's vertices, projected to the plane with round-off, stay where they are), and so do
//! repeated and collinear vertices (dropped): i_overlay snaps to a grid of ~2⁻⁵⁰ of the
//! extent; this keeps within a few hundred times that.

use crate::geometry::polygon::signed_area_2d;

/// Distances below this fraction of the extent are zero.
const EPS: f64 = 1e-13;

/// Pairs with more vertex pairs than this go to i_overlay: the clip takes time n·m, the
/// overlay n log n (a 1 000-gon against itself would be a million clip steps).
const MAX_PAIRS: usize = 4096;

/// `Some` ring (empty when the rings do not overlap in an area) when both rings are convex,
/// `None` when either is not, or they are too large for clipping (the general overlay answers
/// then).
pub(super) fn intersect(a: &[[f64; 2]], b: &[[f64; 2]]) -> Option<Vec<[f64; 2]>> {
    if a.len() * b.len() > MAX_PAIRS {
        return None;
    }
    let eps = EPS * extent(a.iter().chain(b));
    let a = convex_ccw(a, eps)?;
    let b = convex_ccw(b, eps)?;
    let mut ring = a;
    for (i, p) in b.iter().enumerate() {
        let q = b[(i + 1) % b.len()];
        ring = clip(&ring, *p, q, eps);
        if ring.len() < 3 {
            return Some(Vec::new());
        }
    }
    let ring = simplify(ring, eps);
    if ring.len() < 3 || signed_area_2d(&ring) <= 0.0 {
        return Some(Vec::new());
    }
    Some(start_as_overlay(ring))
}

/// The largest coordinate span of the points (at least the smallest positive number).
fn extent<'a>(points: impl Iterator<Item = &'a [f64; 2]>) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE)
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The ring without repeated and collinear vertices, CCW, when it is convex (every turn left
/// or straight within `eps`); `None` otherwise, or when it has no area.
fn convex_ccw(ring: &[[f64; 2]], eps: f64) -> Option<Vec<[f64; 2]>> {
    let mut ring = simplify(ring.to_vec(), eps);
    if ring.len() < 3 {
        return None;
    }
    let area = signed_area_2d(&ring);
    if area == 0.0 {
        return None;
    }
    if area < 0.0 {
        ring.reverse();
    }
    let n = ring.len();
    let convex = (0..n).all(|i| {
        let (u, v, w) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
        cross(u, v, w) > eps * distance(u, w)
    });
    convex.then_some(ring)
}

/// Drops vertices within `eps` of the previous one, then vertices within `eps` of the line
/// through their neighbours, until none is left to drop.
fn simplify(mut ring: Vec<[f64; 2]>, eps: f64) -> Vec<[f64; 2]> {
    loop {
        let n = ring.len();
        if n < 3 {
            return ring;
        }
        let drop = (0..n).find(|&i| {
            let (u, v, w) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            distance(u, v) <= eps || cross(u, v, w).abs() <= eps * distance(u, w)
        });
        match drop {
            Some(i) => {
                ring.remove(i);
            }
            None => return ring,
        }
    }
}

/// The part of `ring` left of the directed line p → q (within `eps`).
fn clip(ring: &[[f64; 2]], p: [f64; 2], q: [f64; 2], eps: f64) -> Vec<[f64; 2]> {
    let length = distance(p, q);
    let side = |x: [f64; 2]| cross(p, q, x) / length;
    let mut out = Vec::with_capacity(ring.len() + 1);
    for (i, &e) in ring.iter().enumerate() {
        let s = ring[(i + ring.len() - 1) % ring.len()];
        let (ds, de) = (side(s), side(e));
        let (s_in, e_in) = (ds >= -eps, de >= -eps);
        if s_in != e_in {
            // One side is below −eps and the other at least −eps: ds − de is not 0.
            let t = (ds / (ds - de)).clamp(0.0, 1.0);
            out.push([s[0] + t * (e[0] - s[0]), s[1] + t * (e[1] - s[1])]);
        }
        if e_in {
            out.push(e);
        }
    }
    out
}

/// The ring turned to start at the vertex before its leftmost-lowest one (i_overlay's start).
fn start_as_overlay(mut ring: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    let lowest = (0..ring.len())
        .min_by(|&i, &j| ring[i][0].total_cmp(&ring[j][0]).then(ring[i][1].total_cmp(&ring[j][1])))
        .unwrap_or(0);
    let n = ring.len();
    ring.rotate_left((lowest + n - 1) % n);
    ring
}

#[cfg(test)]
mod tests {
    //! Invariant: for two convex rings the clip gives i_overlay's ring — the same number of
    //! vertices, in the same order, each within 1e-12 of the extent — and no ring where they
    //! share no area.
    use super::*;

    fn overlay(a: &[[f64; 2]], b: &[[f64; 2]]) -> Vec<Vec<Vec<[f64; 2]>>> {
        use i_overlay::core::fill_rule::FillRule;
        use i_overlay::core::overlay_rule::OverlayRule;
        use i_overlay::float::single::SingleFloatOverlay;
        a.to_vec().overlay_as::<i64>(&b.to_vec(), OverlayRule::Intersect, FillRule::NonZero)
    }

    fn assert_same(a: &[[f64; 2]], b: &[[f64; 2]]) {
        let mine = intersect(a, b).expect("convex rings");
        let theirs = overlay(a, b);
        let tol = 1e-12 * extent(a.iter().chain(b));
        if theirs.is_empty() {
            assert!(mine.is_empty(), "{a:?} ∩ {b:?}: overlay has none, clip {mine:?}");
            return;
        }
        assert_eq!(theirs.len(), 1, "convex pieces are one ring");
        let ring = &theirs[0][0];
        assert_eq!(mine.len(), ring.len(), "{a:?} ∩ {b:?}: {mine:?} against {ring:?}");
        for (p, q) in mine.iter().zip(ring) {
            assert!(distance(*p, *q) <= tol, "{a:?} ∩ {b:?}: {mine:?} against {ring:?}");
        }
    }

    /// A convex ring: points on an ellipse at sorted random angles, in either orientation.
    fn random_ring(next: &mut impl FnMut() -> f64) -> Vec<[f64; 2]> {
        let n = 3 + (next() * 6.0) as usize;
        let mut angles: Vec<f64> = (0..n).map(|_| next() * std::f64::consts::TAU).collect();
        angles.sort_by(f64::total_cmp);
        let (rx, ry, cx, cy, turn) = (0.5 + next(), 0.5 + next(), next() - 0.5, next() - 0.5, next() * 3.0);
        let mut ring: Vec<[f64; 2]> = angles
            .iter()
            .map(|t| {
                let (x, y) = (rx * t.cos(), ry * t.sin());
                [cx + x * turn.cos() - y * turn.sin(), cy + x * turn.sin() + y * turn.cos()]
            })
            .collect();
        if next() < 0.5 {
            ring.reverse();
        }
        ring
    }

    #[test]
    fn random_convex_pairs_give_the_overlay_s_ring() {
        let mut seed = 11u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let (a, b) = (random_ring(&mut next), random_ring(&mut next));
            assert_same(&a, &b);
        }
    }

    /// The cases detection meets most: a face against its twin (projected with round-off),
    /// a face with a vertex on an edge, faces touching along an edge only, one inside the
    /// other, and a ring against itself (detection's normalisation of ground faces).
    #[test]
    fn shared_faces_collinear_vertices_and_edge_contacts() {
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        let twin = [[1e-17, 0.0], [2.0, -1e-16], [2.0 + 2e-16, 1.0], [0.0, 1.0 - 1e-16]];
        assert_same(&square, &twin);
        let reversed: Vec<[f64; 2]> = twin.iter().rev().copied().collect();
        assert_same(&square, &reversed);
        let with_midpoint = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0], [0.0, 1.0]];
        assert_same(&with_midpoint, &square);
        assert_eq!(intersect(&with_midpoint, &with_midpoint).unwrap().len(), 4);
        let beside = [[2.0, 0.0], [3.0, 0.0], [3.0, 1.0], [2.0, 1.0]];
        assert_same(&square, &beside);
        let inside = [[0.5, 0.25], [1.5, 0.25], [1.0, 0.75]];
        assert_same(&square, &inside);
        assert_same(&inside, &square);
        let far = [[5.0, 5.0], [6.0, 5.0], [6.0, 6.0]];
        assert_same(&square, &far);
    }

    /// A 60-gon against itself is clipped; a 1 000-gon is left to the overlay.
    #[test]
    fn large_rings_are_left_to_the_overlay() {
        let gon = |n: usize| -> Vec<[f64; 2]> {
            (0..n).map(|k| (k as f64 / n as f64) * std::f64::consts::TAU).map(|t| [t.cos(), t.sin()]).collect()
        };
        assert_same(&gon(60), &gon(60));
        assert!(intersect(&gon(1000), &gon(1000)).is_none());
    }

    #[test]
    fn a_ring_that_is_not_convex_is_left_to_the_overlay() {
        let ell = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        assert!(intersect(&ell, &square).is_none());
        assert!(intersect(&square, &ell).is_none());
    }
}
