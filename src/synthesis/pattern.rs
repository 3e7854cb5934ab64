//! Generate, strategy *pattern*: the seed paper's Fig 9 kind of design — a running bond laid on
//! the shape's outer surface and extruded to an apex, so every joint is a plane through the apex
//! (a cone of joints converging on it: the beds of a vault or shell, its head joints).
//!
//! The bond is drawn in the pattern plane: the plane normal to the axis from the apex to the free
//! shape's centroid, at the distance of the shape's farthest point along that axis (its outer
//! surface there, where the bond's sizes are true). Seen from the apex, the plane and the surface
//! show the same pattern (a segment and its central projection on the surface make the same
//! cut), so the bond covers the whole shape as the apex sees it: strips of width L/2 across the
//! plane, bricks of length L along them, staggered by half a brick in every other strip. The
//! strip lines come first (each a plane through the apex across the whole shape), then each
//! strip's head joints (each cutting only the strip piece its cone meets). The result is one
//! ordinary pattern cut in the history, editable and repairable like a hand-drawn one.
//!
//! The shape must lie in front of the apex (every free vertex farther along the axis than the
//! apex). Units: metres.

use super::DesignError;
use super::generate::{BlockSize, pieces};
use super::generated::Generated;
use crate::geometry::{Point3, Vector3};
use crate::history::CutCache;
use crate::model::{Block, Cut, Scene};

/// The pattern plane's frame: the apex, the axis `a` (unit, from the apex into the shape), the
/// plane's in-plane axes `e1`, `e2` and its distance `depth` from the apex.
struct PatternPlane {
    apex: Point3,
    a: Vector3,
    e1: Vector3,
    e2: Vector3,
    depth: f64,
}

impl PatternPlane {
    /// The plane of `points` (the free vertices) seen from `apex`.
    fn new(apex: Point3, points: &[Point3]) -> Result<Self, DesignError> {
        let bad = |why: String| Err(DesignError::Settings(why));
        if !apex.iter().all(|c| c.is_finite()) {
            return bad(format!("apex {:?} is not a finite point", apex.coords.as_slice()));
        }
        let centroid = Point3::from(points.iter().map(|p| p.coords).sum::<Vector3>() / points.len() as f64);
        let size = points.iter().map(|p| (p - centroid).norm()).fold(0.0, f64::max);
        let to = centroid - apex;
        if to.norm() <= 1e-9 * size.max(f64::MIN_POSITIVE) {
            return bad("the apex is at the shape's centre: the joints would not converge anywhere".into());
        }
        let a = to.normalize();
        let nearest = points.iter().map(|p| (p - apex).dot(&a)).fold(f64::INFINITY, f64::min);
        if nearest <= 1e-6 * size {
            return bad(format!(
                "the shape reaches {:.4} m behind the apex along the axis to its centre: put the apex outside the shape, on the side away from the pattern",
                -nearest
            ));
        }
        // e1 from the world axis least aligned with the axis (x for a vertical one).
        let world = [Vector3::x(), Vector3::y(), Vector3::z()];
        let least = world.iter().min_by(|u, v| u.dot(&a).abs().total_cmp(&v.dot(&a).abs())).expect("three axes");
        let e1 = (least - a * least.dot(&a)).normalize();
        let e2 = a.cross(&e1);
        let depth = points.iter().map(|p| (p - apex).dot(&a)).fold(0.0, f64::max);
        Ok(Self { apex, a, e1, e2, depth })
    }

    /// `p`'s central projection from the apex onto the plane, in (e1, e2) coordinates.
    fn project(&self, p: &Point3) -> [f64; 2] {
        let d = p - self.apex;
        let s = self.depth / d.dot(&self.a);
        [s * d.dot(&self.e1), s * d.dot(&self.e2)]
    }

    /// The point of the plane at coordinates `uv`.
    fn point(&self, uv: [f64; 2]) -> [f64; 3] {
        let p = self.apex + self.a * self.depth + self.e1 * uv[0] + self.e2 * uv[1];
        [p.x, p.y, p.z]
    }
}

/// Cuts `shape` (its free blocks; supports stay whole) by a running bond extruded to `apex`
/// (module docs); `size` is the bricks' length L on the pattern plane, or about how many pieces.
pub fn pattern(shape: &Scene, apex: [f64; 3], size: &BlockSize, stagger: bool) -> Result<Generated, DesignError> {
    if !shape.cuts.is_empty() {
        return Err(DesignError::Settings(
            "the shape already has a cut history: decompose starts from the source shapes".into(),
        ));
    }
    let free: Vec<&Block> = shape.blocks.iter().filter(|b| !b.support).collect();
    let points: Vec<Point3> = free.iter().flat_map(|b| b.mesh.vertices.iter().copied()).collect();
    if points.is_empty() {
        return Err(DesignError::Settings("the shape has no free block to cut".into()));
    }
    let plane = PatternPlane::new(Point3::from(apex), &points)?;
    let uv: Vec<[f64; 2]> = points.iter().map(|p| plane.project(p)).collect();
    let lo = [0, 1].map(|k| uv.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1].map(|k| uv.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max));
    let l = brick_length(size, lo, hi)?;
    let segments = bond(lo, hi, l, stagger);
    let strips = segments.strips;
    let mut design = shape.clone();
    let cut: Vec<[[f64; 3]; 2]> = segments.lines.iter().map(|s| s.map(|p| plane.point(p))).collect();
    design.cuts.push(Cut::pattern(apex, cut));
    let out = pieces(&design, &mut CutCache::new())?;
    let pieces = out.iter().filter(|b| !b.support).count();
    Ok(Generated { design, max_size: l, courses: strips, pieces, rounds: None })
}

/// The brick length L on the pattern plane for `size` over the pattern's extent `lo`–`hi`:
/// a given length, or the one that gives about that many bricks of L × L/2.
fn brick_length(size: &BlockSize, lo: [f64; 2], hi: [f64; 2]) -> Result<f64, DesignError> {
    let area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    let l = match *size {
        BlockSize::Max(l) => l,
        BlockSize::Count(n) if n > 0 => (2.0 * area / n as f64).sqrt(),
        BlockSize::Count(_) => return Err(DesignError::Settings("0 blocks: give at least 1".into())),
    };
    if !(l > 0.0 && l.is_finite()) {
        return Err(DesignError::Settings(format!("block size {l}: not a positive length (m)")));
    }
    Ok(l)
}

/// The bond's segments on the pattern plane, strip lines first, and how many strips.
struct Bond {
    lines: Vec<[[f64; 2]; 2]>,
    strips: usize,
}

/// A running bond over `lo`–`hi`: strips across u of width about L/2, bricks along v of length
/// about L (both evened out to fill the extent), every other strip's joints offset by half a
/// brick when `stagger`. Lines reach 1 % past the extent so that they cross the whole shape.
fn bond(lo: [f64; 2], hi: [f64; 2], l: f64, stagger: bool) -> Bond {
    let margin = 0.01 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let strips = ((hi[0] - lo[0]) / (0.5 * l)).ceil().max(1.0) as usize;
    let w = (hi[0] - lo[0]) / strips as f64;
    let bricks = ((hi[1] - lo[1]) / l).ceil().max(1.0) as usize;
    let h = (hi[1] - lo[1]) / bricks as f64;
    let u = |i: usize| match i {
        0 => lo[0] - margin,
        i if i == strips => hi[0] + margin,
        i => lo[0] + i as f64 * w,
    };
    let mut lines: Vec<[[f64; 2]; 2]> = (1..strips).map(|i| [[u(i), lo[1] - margin], [u(i), hi[1] + margin]]).collect();
    for i in 0..strips {
        let offset = if stagger && i % 2 == 1 { 0.5 } else { 0.0 };
        let joints = (0..=bricks)
            .map(|j| lo[1] + (j as f64 + offset) * h)
            .filter(|&v| v > lo[1] + 0.25 * h && v < hi[1] - 0.25 * h);
        // Inside the strip: the joint's cone meets only the strip's piece, which its plane
        // then cuts across.
        let (a, b) = (u(i) + 0.1 * (u(i + 1) - u(i)), u(i + 1) - 0.1 * (u(i + 1) - u(i)));
        lines.extend(joints.map(|v| [[a, v], [b, v]]));
    }
    Bond { lines, strips }
}
