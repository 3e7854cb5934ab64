//! The cuts an optimiser may move, as a vector of numbers within bounds.
//!
//! A plane cut has three: its offset along its normal (m) and two turns (radians) about two
//! axes in the plane, pivoting about the offset point; a pattern cut has three too, the moves
//! of its apex along x, y, z (m). The zero vector is the design as given.

use super::DesignError;
use crate::geometry::{Point3, Vector3};
use crate::model::{Cut, CutShape, Scene};
use crate::pipeline::Analysis;
use nalgebra::{Unit, UnitQuaternion};

/// What may move and how far ([`super::RepairSettings`] holds the user's values).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Freedom {
    /// Largest turn of a plane cut about each of its two in-plane axes, degrees.
    pub max_turn_degrees: f64,
    /// Largest move of a pattern cut's apex along each axis, as a fraction of the model size.
    pub apex_move: f64,
}

/// How one cut of the history moves with its three parameters.
#[derive(Clone, Debug, PartialEq)]
enum Motion {
    Plane { point: Point3, normal: Vector3, axes: [Vector3; 2], offsets: (f64, f64), turn: f64 },
    Pattern { apex: Point3, segments: Vec<[[f64; 3]; 2]>, reach: f64 },
}

/// The moving cuts of a design.
#[derive(Clone, Debug, PartialEq)]
pub struct CutParameters {
    /// (index in the history, how it moves).
    cuts: Vec<(usize, Motion)>,
}

/// Every dimension of a cut's parameters.
const PER_CUT: usize = 3;

impl CutParameters {
    /// The parameters of `selection` (indices into `scene.cuts`; every cut when `None`).
    /// A plane cut's offsets range over the source shapes' extent along its normal, and it
    /// turns about its own point.
    pub fn new(scene: &Scene, selection: Option<&[usize]>, freedom: &Freedom) -> Result<Self, DesignError> {
        Self::build(scene, None, selection, freedom)
    }

    /// As [`Self::new`], but a plane cut that holds joints of `analysis` (of `scene`) turns
    /// about their centre and moves only within the pieces on either side of them: further,
    /// it would run through a neighbouring cut (what matters in a design of many cuts, such as
    /// the courses of an arch, where a move over the whole extent makes a different design).
    pub fn around(
        scene: &Scene,
        analysis: &Analysis,
        selection: Option<&[usize]>,
        freedom: &Freedom,
    ) -> Result<Self, DesignError> {
        Self::build(scene, Some(analysis), selection, freedom)
    }

    fn build(
        scene: &Scene,
        analysis: Option<&Analysis>,
        selection: Option<&[usize]>,
        freedom: &Freedom,
    ) -> Result<Self, DesignError> {
        let all: Vec<usize> = (0..scene.cuts.len()).collect();
        let chosen = selection.unwrap_or(&all);
        let mut cuts = Vec::with_capacity(chosen.len());
        for &index in chosen {
            let cut = scene.cuts.get(index).ok_or(DesignError::UnknownCut { index, count: scene.cuts.len() })?;
            let mut m = motion(scene, index, cut, freedom)?;
            if let Some(a) = analysis {
                m = m.around_joints(cut, a, scene.scale());
            }
            cuts.push((index, m));
        }
        Ok(Self { cuts })
    }

    /// Number of parameters.
    pub fn len(&self) -> usize {
        PER_CUT * self.cuts.len()
    }

    /// Whether there are no cuts to move.
    pub fn is_empty(&self) -> bool {
        self.cuts.is_empty()
    }

    /// The indices of the moving cuts in the history.
    pub fn indices(&self) -> Vec<usize> {
        self.cuts.iter().map(|c| c.0).collect()
    }

    /// Lower and upper bounds of every parameter.
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let mut lo = Vec::with_capacity(self.len());
        let mut hi = Vec::with_capacity(self.len());
        for (_, m) in &self.cuts {
            match m {
                Motion::Plane { offsets, turn, .. } => {
                    lo.extend([offsets.0, -turn, -turn]);
                    hi.extend([offsets.1, *turn, *turn]);
                }
                Motion::Pattern { reach, .. } => {
                    lo.extend([-reach; 3]);
                    hi.extend([*reach; 3]);
                }
            }
        }
        (lo, hi)
    }

    /// How close `x` is to the design as given, in [0, 1] (1 at zero): one minus the mean
    /// squared parameter as a fraction of its range.
    pub fn closeness(&self, x: &[f64]) -> f64 {
        let (lo, hi) = self.bounds();
        let spread: f64 =
            x.iter().zip(lo.iter().zip(&hi)).map(|(v, (l, h))| (v / (h - l).max(f64::MIN_POSITIVE)).powi(2)).sum();
        1.0 - (spread / x.len().max(1) as f64).min(1.0)
    }

    /// `scene` with its moving cuts placed by `x` (clamped to the bounds).
    pub fn apply(&self, scene: &Scene, x: &[f64]) -> Scene {
        let (lo, hi) = self.bounds();
        let mut out = scene.clone();
        for (k, (index, m)) in self.cuts.iter().enumerate() {
            let p: Vec<f64> =
                (0..PER_CUT).map(|j| x[PER_CUT * k + j].clamp(lo[PER_CUT * k + j], hi[PER_CUT * k + j])).collect();
            out.cuts[*index].shape = shape(m, &p);
        }
        out
    }
}

/// How cut `index` moves.
fn motion(scene: &Scene, index: usize, cut: &Cut, freedom: &Freedom) -> Result<Motion, DesignError> {
    match &cut.shape {
        CutShape::Plane { point, normal } => {
            let n = Vector3::from(*normal);
            if !(n.norm() > 0.0 && n.iter().all(|c| c.is_finite()) && point.iter().all(|c| c.is_finite())) {
                return Err(DesignError::BadCut {
                    index,
                    why: "its point or normal is not finite and non-zero".into(),
                });
            }
            let n = n.normalize();
            let p = Point3::from(*point);
            let along = scene
                .blocks
                .iter()
                .filter(|b| !b.support)
                .flat_map(|b| b.mesh.vertices.iter())
                .map(|v| (v - p).dot(&n));
            let offsets = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)));
            if offsets.0 >= offsets.1 || !offsets.0.is_finite() {
                return Err(DesignError::BadCut { index, why: "there is no free source shape for it to cut".into() });
            }
            Ok(Motion::Plane {
                point: p,
                normal: n,
                axes: in_plane_axes(&n),
                offsets,
                turn: freedom.max_turn_degrees.to_radians(),
            })
        }
        CutShape::Pattern { apex, segments } => Ok(Motion::Pattern {
            apex: Point3::from(*apex),
            segments: segments.clone(),
            reach: freedom.apex_move * scene.scale(),
        }),
    }
}

impl Motion {
    /// A plane's pivot moved to the centre of the joints it holds in `analysis`, its offsets
    /// narrowed to the pieces on either side of them (see [`CutParameters::around`]).
    fn around_joints(self, cut: &Cut, analysis: &Analysis, scale: f64) -> Self {
        let Motion::Plane { point, normal, axes, offsets, turn } = self else { return self };
        let joints: Vec<&crate::interfaces::Interface> =
            analysis.interfaces.iter().filter(|itf| holds(cut, itf, 1e-6 * scale)).collect();
        let area: f64 = joints.iter().map(|j| j.area).sum();
        if joints.is_empty() || area <= 0.0 {
            return Motion::Plane { point, normal, axes, offsets, turn };
        }
        let centre = joints.iter().fold(Vector3::zeros(), |c, j| c + j.centroid().coords * j.area) / area;
        let pivot = Point3::from(centre);
        let blocks = joints.iter().flat_map(|j| [j.a.block(), j.b.block()]).flatten();
        let along = blocks
            .flat_map(|b| analysis.assembly.blocks[b.0].mesh.vertices.iter())
            .map(|v| (v - pivot).dot(&normal))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)));
        // The source extent, measured from the new pivot.
        let shift = (pivot - point).dot(&normal);
        let narrowed = (along.0.max(offsets.0 - shift), along.1.min(offsets.1 - shift));
        let offsets = if narrowed.0 < narrowed.1 { narrowed } else { (offsets.0 - shift, offsets.1 - shift) };
        // The pivot in the plane (its centre lies in it up to the tolerance).
        let pivot = pivot - normal * (pivot - point).dot(&normal);
        Motion::Plane { point: pivot, normal, axes, offsets, turn }
    }
}

/// Whether joint `itf` lies in cut's surface: a plane cut whose plane holds it, a pattern cut
/// whose apex lies in its plane (within `tolerance`, m).
pub(super) fn holds(cut: &Cut, itf: &crate::interfaces::Interface, tolerance: f64) -> bool {
    let (n, c) = (itf.frame.n, itf.centroid());
    match &cut.shape {
        CutShape::Plane { point, normal } => {
            let m = Vector3::from(*normal).normalize();
            m.dot(&n).abs() > 1.0 - 1e-6 && (c - Point3::from(*point)).dot(&m).abs() < tolerance
        }
        CutShape::Pattern { apex, .. } => (Point3::from(*apex) - c).dot(&n).abs() < tolerance,
    }
}

/// Two unit axes spanning the plane normal to `n`: the first horizontal where the plane is
/// not (so that its turn tilts the cut), both fixed by `n` alone.
fn in_plane_axes(n: &Vector3) -> [Vector3; 2] {
    let up = Vector3::z();
    let first = if n.cross(&up).norm() > 1e-9 { n.cross(&up).normalize() } else { Vector3::x() };
    [first, n.cross(&first).normalize()]
}

/// The cut shape of `m` moved by `p`.
fn shape(m: &Motion, p: &[f64]) -> CutShape {
    match m {
        Motion::Plane { point, normal, axes, .. } => {
            let pivot = point + normal * p[0];
            let turn = UnitQuaternion::from_axis_angle(&Unit::new_normalize(axes[1]), p[2])
                * UnitQuaternion::from_axis_angle(&Unit::new_normalize(axes[0]), p[1]);
            let n = turn * normal;
            CutShape::Plane { point: pivot.into(), normal: n.into() }
        }
        Motion::Pattern { apex, segments, .. } => {
            let moved = apex + Vector3::new(p[0], p[1], p[2]);
            CutShape::Pattern { apex: moved.into(), segments: segments.clone() }
        }
    }
}
