//! Generate: a cut history for a source shape, strategy *courses* — bed joints across the load
//! path, then head joints staggered between courses (running bond) so that no head joint runs
//! through two courses. The result is an ordinary design (plane cuts, head joints targeted at
//! their course's piece), editable and repairable like a hand-made one.
//!
//! The load path is a direction field:
//! - [`Field::Vertical`]: horizontal beds (walls, piers, letters on the ground); head joints
//!   across the shape's longer horizontal extent;
//! - [`Field::Radial`]: beds are planes through an axis (arches, barrel vaults: the voussoir
//!   joints of a thrust line that follows the centre line); head joints along the axis. The
//!   shape must lie within a half-turn about the axis (a plane through the axis would cut the
//!   far side too).
//!
//! Size: a largest block dimension `L` (courses no higher, blocks no longer), or a target
//! block count. Pieces come out within `L` along the cut directions; a shape thicker than `L`
//! across them is reported, not silently produced, and so is a sliver (the replay refuses
//! pieces below [`crate::history`]'s sliver fraction). Units: metres.

use super::DesignError;
use super::generated::Generated;
use crate::geometry::{Point3, Tolerances, Vector3};
use crate::history::{CutCache, made_by, resolve};
use crate::model::{Block, Cut, Scene};

/// The direction field the courses cross.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Field {
    /// Horizontal beds (walls, piers, lettering): courses across a vertical load path.
    Vertical,
    /// Beds through the line `center + s·axis` (unit axis any length > 0).
    Radial {
        /// A point of the axis, m.
        center: [f64; 3],
        /// The axis's direction.
        axis: [f64; 3],
    },
}

/// How big the blocks are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BlockSize {
    /// Largest dimension along the cut directions, m.
    Max(f64),
    /// About this many blocks.
    Count(usize),
}

/// Cuts `shape` (its free blocks; supports stay whole) into courses (see the module docs).
pub fn courses(shape: &Scene, field: &Field, size: &BlockSize, stagger: bool) -> Result<Generated, DesignError> {
    let (frame, l, beds) = candidate_beds(shape, field, size)?;
    let bed_cuts: Vec<Cut> = beds.iter().map(|&t| frame.bed_cut(t)).collect();
    with_head_joints(shape, &frame, &beds, bed_cuts, l, stagger)
}

/// The field's frame over a source shape without a history, the block size and the course
/// coordinates of the bed joints (the candidates of every strategy).
pub(super) fn candidate_beds(
    shape: &Scene,
    field: &Field,
    size: &BlockSize,
) -> Result<(Frame, f64, Vec<f64>), DesignError> {
    if !shape.cuts.is_empty() {
        return Err(DesignError::Settings(
            "the shape already has a cut history: decompose starts from the source shapes".into(),
        ));
    }
    let frame = Frame::new(shape, field)?;
    let l = frame.block_size(size)?;
    let beds = frame.beds(l);
    Ok((frame, l, beds))
}

/// `shape` cut by `bed_cuts` (at course coordinates `beds` of the field), then by head joints
/// across every course piece; checked against the block size.
pub(super) fn with_head_joints(
    shape: &Scene,
    frame: &Frame,
    beds: &[f64],
    bed_cuts: Vec<Cut>,
    l: f64,
    stagger: bool,
) -> Result<Generated, DesignError> {
    let mut design = shape.clone();
    design.cuts.extend(bed_cuts);
    let mut cache = CutCache::new();
    let course_pieces: Vec<Block> = pieces(&design, &mut cache)?.into_iter().filter(|b| !b.support).collect();
    for piece in &course_pieces {
        let course = frame.course_of(&piece.mesh.vertices, beds);
        head_joints(&mut design, &mut cache, frame, piece, l, stagger && course % 2 == 1)?;
    }
    let out = pieces(&design, &mut cache)?;
    let free: Vec<&Block> = out.iter().filter(|b| !b.support).collect();
    if let Some(b) = free.iter().find(|b| frame.thickness_of(&b.mesh.vertices) > l * (1.0 + 1e-6)) {
        return Err(DesignError::Settings(format!(
            "piece '{}' is {:.4} m thick across the courses, more than the block size {l:.4} m: this strategy does not cut across the thickness",
            b.name,
            frame.thickness_of(&b.mesh.vertices)
        )));
    }
    Ok(Generated { courses: beds.len() + 1, pieces: free.len(), max_size: l, design, rounds: None })
}

/// The shape's pieces after its history.
pub(super) fn pieces(design: &Scene, cache: &mut CutCache) -> Result<Vec<Block>, DesignError> {
    let (resolved, _) = resolve(design, &Tolerances::default(), cache).map_err(|e| DesignError::Analysis(e.into()))?;
    Ok(resolved.blocks)
}

/// The field's coordinates: `course` along the load path (z, or the angle about the axis), `run`
/// along the courses (the longer horizontal extent, or along the axis), and across them.
pub(super) struct Frame {
    field: Field,
    /// Vertical: the run axis (horizontal unit) and the thickness axis. Radial: the axis, and
    /// the in-plane reference directions e0 (angle 0) and e1 (angle 90°).
    run: Vector3,
    across: Vector3,
    center: Point3,
    /// The free vertices' range along the course coordinate, and their largest radius (radial).
    range: (f64, f64),
    radius: f64,
    volume: f64,
    /// The free shape's extent across the courses and the run.
    thickness: f64,
}

impl Frame {
    pub(super) fn new(shape: &Scene, field: &Field) -> Result<Self, DesignError> {
        let free: Vec<&Block> = shape.blocks.iter().filter(|b| !b.support).collect();
        let points: Vec<Point3> = free.iter().flat_map(|b| b.mesh.vertices.iter().copied()).collect();
        if points.is_empty() {
            return Err(DesignError::Settings("the shape has no free block to cut".into()));
        }
        let volume = free.iter().map(|b| crate::geometry::MassProperties::of_mesh(&b.mesh).volume).sum();
        let (run, across, center) = match field {
            Field::Vertical => {
                let a = crate::geometry::Aabb3::from_points(points.iter());
                let d = a.max - a.min;
                if d.x >= d.y { (Vector3::x(), Vector3::y(), a.min) } else { (Vector3::y(), Vector3::x(), a.min) }
            }
            Field::Radial { center, axis } => {
                let u = Vector3::from(*axis);
                if !(u.norm() > 0.0 && u.iter().all(|c| c.is_finite())) {
                    return Err(DesignError::Settings(format!("radial axis {axis:?}: not a finite non-zero vector")));
                }
                let u = u.normalize();
                let e0 = if u.cross(&Vector3::z()).norm() > 1e-9 {
                    u.cross(&Vector3::z()).normalize()
                } else {
                    Vector3::x()
                };
                (u, e0, Point3::from(*center))
            }
        };
        let mut frame =
            Self { field: *field, run, across, center, range: (0.0, 0.0), radius: 0.0, volume, thickness: 0.0 };
        frame.thickness = frame.thickness_of(&points);
        let coords: Vec<f64> = points.iter().map(|p| frame.course_coordinate(p)).collect();
        frame.range = coords.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &c| (lo.min(c), hi.max(c)));
        frame.radius = points.iter().map(|p| frame.radial(p).norm()).fold(0.0, f64::max);
        if let Field::Radial { .. } = field
            && frame.range.1 - frame.range.0 > std::f64::consts::PI * (1.0 + 1e-9)
        {
            return Err(DesignError::Settings(format!(
                "the shape spans {:.1}° about the radial axis: courses through an axis need it within a half-turn",
                (frame.range.1 - frame.range.0).to_degrees()
            )));
        }
        Ok(frame)
    }

    /// The reference direction at angle 90° about the axis (radial field).
    fn e1(&self) -> Vector3 {
        self.across.cross(&self.run)
    }

    /// The component of `p − center` normal to the axis (radial field).
    fn radial(&self, p: &Point3) -> Vector3 {
        let r = p - self.center;
        r - self.run * r.dot(&self.run)
    }

    /// z, or the angle about the axis from e0 towards e1.
    fn course_coordinate(&self, p: &Point3) -> f64 {
        match self.field {
            Field::Vertical => p.z,
            Field::Radial { .. } => {
                let r = self.radial(p);
                r.dot(&self.e1()).atan2(r.dot(&self.across))
            }
        }
    }

    /// The block size L of `size`: given, or from a count — blocks of L × L × thickness for
    /// the vertical field, N voussoirs along the outer arc for the radial one.
    pub(super) fn block_size(&self, size: &BlockSize) -> Result<f64, DesignError> {
        let l = match *size {
            BlockSize::Max(l) => l,
            BlockSize::Count(n) if n > 0 => match self.field {
                Field::Vertical => (self.volume / (n as f64 * self.thickness)).sqrt(),
                Field::Radial { .. } => self.radius * (self.range.1 - self.range.0) / n as f64,
            },
            BlockSize::Count(_) => 0.0,
        };
        if !(l > 0.0 && l.is_finite()) {
            return Err(DesignError::Settings(format!("block size {l}: expected a length > 0 (or a block count ≥ 1)")));
        }
        Ok(l)
    }

    /// Course coordinates of the bed joints: equal courses no larger than L (along the outer
    /// arc for the radial field).
    pub(super) fn beds(&self, l: f64) -> Vec<f64> {
        let span = self.range.1 - self.range.0;
        let length = match self.field {
            Field::Vertical => span,
            Field::Radial { .. } => span * self.radius,
        };
        let n = (length / l - 1e-9).ceil().max(1.0) as usize;
        (1..n).map(|k| self.range.0 + span * k as f64 / n as f64).collect()
    }

    /// The bed joint at course coordinate `t`.
    pub(super) fn bed_cut(&self, t: f64) -> Cut {
        let (point, normal) = self.bed_plane(t);
        Cut::plane(point.into(), normal.into())
    }

    /// The plane of the bed joint at course coordinate `t`: a point and the unit normal along
    /// the course coordinate.
    pub(super) fn bed_plane(&self, t: f64) -> (Point3, Vector3) {
        match self.field {
            Field::Vertical => (Point3::new(0.0, 0.0, t), Vector3::z()),
            Field::Radial { .. } => (self.center, -self.across * t.sin() + self.e1() * t.cos()),
        }
    }

    /// Which course the vertices lie in (0 the first).
    pub(super) fn course_of(&self, vertices: &[Point3], beds: &[f64]) -> usize {
        let mid = vertices.iter().map(|p| self.course_coordinate(p)).sum::<f64>() / vertices.len().max(1) as f64;
        beds.iter().filter(|&&t| t < mid).count()
    }

    /// A piece's extent across the courses and the run (its thickness): along `across` for
    /// the vertical field, radially for the radial one.
    pub(super) fn thickness_of(&self, vertices: &[Point3]) -> f64 {
        let along = |p: &Point3| match self.field {
            Field::Vertical => (p - self.center).dot(&self.across),
            Field::Radial { .. } => self.radial(p).norm(),
        };
        let (lo, hi) =
            vertices.iter().map(along).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)));
        hi - lo
    }
}

/// Head joints across one course piece: equal blocks no longer than L along the run, shifted
/// by half a block (half blocks at the ends) in staggered courses longer than one block. Each is a plane cut targeted
/// at one piece of the course, so that it runs through this course only; where a non-convex
/// course falls apart, every part the joint crosses gets its own cut.
fn head_joints(
    design: &mut Scene,
    cache: &mut CutCache,
    frame: &Frame,
    piece: &Block,
    l: f64,
    shifted: bool,
) -> Result<(), DesignError> {
    let along = |p: &Point3| (p - frame.center).dot(&frame.run);
    let extent = |b: &Block| {
        b.mesh.vertices.iter().map(along).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)))
    };
    let (lo, hi) = extent(piece);
    let n = ((hi - lo) / l - 1e-9).ceil().max(1.0) as usize;
    let step = (hi - lo) / n as f64;
    // A course one block long stays whole: there is nothing to stagger against.
    let joints: Vec<f64> = if shifted && n > 1 {
        (0..n).map(|k| lo + step * (k as f64 + 0.5)).collect()
    } else {
        (1..n).map(|k| lo + step * k as f64).collect()
    };
    let margin = 1e-6 * step;
    let mut parts = vec![piece.clone()];
    for s in joints {
        let point = frame.center + frame.run * s;
        let mut next = Vec::with_capacity(parts.len() + 1);
        for part in parts {
            let (a, b) = extent(&part);
            if !(a + margin < s && s < b - margin) {
                next.push(part);
                continue;
            }
            design.cuts.push(Cut::plane(point.into(), frame.run.into()).on(&part.name));
            let index = design.cuts.len() - 1;
            let children = |p: &Block| p.name.strip_prefix(&part.name).is_some_and(|rest| made_by(rest, index));
            next.extend(pieces(design, cache)?.into_iter().filter(children));
        }
        parts = next;
    }
    Ok(())
}
