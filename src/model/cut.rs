//! A cut of a design's history (see [`crate::history`] for how it is replayed).
//!
//! In a scene file a cut is either a plane, `{"point": [x,y,z], "normal": [x,y,z]}`, or a
//! pattern cut, `{"apex": [x,y,z], "segments": [[[x,y,z],[x,y,z]], …]}`; both take an optional
//! `"target": "piece name"`. Lengths in metres.

use crate::geometry::{Plane, Point3, Vector3};
use serde::{Deserialize, Serialize};

/// What a cut cuts with.
#[derive(Clone, Debug, PartialEq)]
pub enum CutShape {
    /// The plane through `point` with normal `normal` (any length > 0).
    Plane {
        /// A point of the plane, m.
        point: [f64; 3],
        /// Its normal (any length > 0); the `-` pieces are on the side it points away from.
        normal: [f64; 3],
    },
    /// A pattern of line segments (typically drawn on a face) extruded to one apex: segment
    /// `[p, q]` cuts with the plane through `apex`, `p` and `q`, but only the pieces that the
    /// cone from the apex through the segment meets. Segments are applied in order, so a
    /// segment drawn between two earlier ones cuts only the piece between them (brick bonds,
    /// voussoir courses). The interfaces are planar and converge on the apex.
    Pattern {
        /// The point every cutting plane passes through, m.
        apex: [f64; 3],
        /// The segments `[p, q]`, m, in the order they cut.
        segments: Vec<[[f64; 3]; 2]>,
    },
}

/// One cut of the history.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawCut", into = "RawCut")]
pub struct Cut {
    /// The plane, or the pattern and its apex.
    pub shape: CutShape,
    /// Only this piece (and, in a pattern, the pieces cut from it) is cut. Default: every piece
    /// the cut crosses, supports excepted.
    pub target: Option<String>,
}

impl Cut {
    /// A plane cut of every piece it crosses.
    pub fn plane(point: [f64; 3], normal: [f64; 3]) -> Self {
        Self { shape: CutShape::Plane { point, normal }, target: None }
    }

    /// A pattern cut of every piece it crosses.
    pub fn pattern(apex: [f64; 3], segments: Vec<[[f64; 3]; 2]>) -> Self {
        Self { shape: CutShape::Pattern { apex, segments }, target: None }
    }

    /// The same cut restricted to one named piece.
    pub fn on(mut self, target: &str) -> Self {
        self.target = Some(target.to_string());
        self
    }

    /// The cut a fraction `s` (0 to 1) of the way from this one to `other` (an animation of a
    /// cut moving): points, apexes and segment ends move on straight lines, a plane's normal
    /// turns in the plane of the two normals (normalised linear blend; `other`'s normal is
    /// flipped into this one's hemisphere for the blend — the same plane — and back from
    /// halfway, so that the end is `other` exactly). The target is `other`'s.
    /// `None` when the two are not the same kind or have different numbers of segments.
    pub fn toward(&self, other: &Cut, s: f64) -> Option<Cut> {
        let lerp = |a: [f64; 3], b: [f64; 3]| -> [f64; 3] { std::array::from_fn(|i| a[i] + s * (b[i] - a[i])) };
        let shape = match (&self.shape, &other.shape) {
            (CutShape::Plane { point: p0, normal: n0 }, CutShape::Plane { point: p1, normal: n1 }) => {
                let (a, b) = (Vector3::from(*n0).normalize(), Vector3::from(*n1).normalize());
                let flip = if a.dot(&b) < 0.0 { -1.0 } else { 1.0 };
                let b = b * flip;
                let n = a + (b - a) * s;
                let n = if n.norm() > 1e-12 { n.normalize() } else { b };
                let n = if s >= 0.5 { n * flip } else { n };
                CutShape::Plane { point: lerp(*p0, *p1), normal: n.into() }
            }
            (CutShape::Pattern { apex: a0, segments: s0 }, CutShape::Pattern { apex: a1, segments: s1 })
                if s0.len() == s1.len() =>
            {
                let segments = s0.iter().zip(s1).map(|(u, v)| [lerp(u[0], v[0]), lerp(u[1], v[1])]).collect();
                CutShape::Pattern { apex: lerp(*a0, *a1), segments }
            }
            _ => return None,
        };
        Some(Cut { shape, target: other.target.clone() })
    }
}

/// The plane through a point with a normal.
pub fn plane_of(point: [f64; 3], normal: [f64; 3]) -> Plane {
    Plane::from_point_normal(&Point3::from(point), &Vector3::from(normal))
}

/// The file form: either `point` + `normal` or `apex` + `segments`.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCut {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    point: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    normal: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    apex: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    segments: Option<Vec<[[f64; 3]; 2]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    target: Option<String>,
}

impl TryFrom<RawCut> for Cut {
    type Error = String;
    fn try_from(r: RawCut) -> Result<Self, String> {
        let shape = match (r.point, r.normal, r.apex, r.segments) {
            (Some(point), Some(normal), None, None) => CutShape::Plane { point, normal },
            (None, None, Some(apex), Some(segments)) => CutShape::Pattern { apex, segments },
            _ => {
                return Err("a cut has either \"point\" and \"normal\" (a plane) or \"apex\" and \"segments\" \
                            (a pattern cut), nothing else"
                    .into());
            }
        };
        Ok(Cut { shape, target: r.target })
    }
}

impl From<Cut> for RawCut {
    fn from(c: Cut) -> Self {
        let mut r = RawCut { point: None, normal: None, apex: None, segments: None, target: c.target };
        match c.shape {
            CutShape::Plane { point, normal } => {
                r.point = Some(point);
                r.normal = Some(normal);
            }
            CutShape::Pattern { apex, segments } => {
                r.apex = Some(apex);
                r.segments = Some(segments);
            }
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::{Cut, CutShape};

    /// Invariant: `toward` is the cut itself at 0 and the other at 1 (a flipped normal is the
    /// same plane), halfway the points meet in the middle and the normal is the unit bisector;
    /// cuts of different kinds do not blend.
    #[test]
    fn toward_runs_from_one_cut_to_the_other() {
        let a = Cut::plane([0.0, 0.0, 0.0], [0.0, 0.0, 2.0]);
        let b = Cut::plane([2.0, 0.0, 1.0], [0.0, -1.0, 0.0]).on("piece");
        assert_eq!(a.toward(&b, 0.0).unwrap().shape, CutShape::Plane { point: [0.0; 3], normal: [0.0, 0.0, 1.0] });
        assert_eq!(
            a.toward(&b, 1.0).unwrap().shape,
            CutShape::Plane { point: [2.0, 0.0, 1.0], normal: [0.0, -1.0, 0.0] }
        );
        let half = a.toward(&b, 0.5).unwrap();
        assert_eq!(half.target.as_deref(), Some("piece"));
        let CutShape::Plane { point, normal } = half.shape else { panic!("a plane") };
        assert_eq!(point, [1.0, 0.0, 0.5]);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((normal[1] + h).abs() < 1e-15 && (normal[2] - h).abs() < 1e-15 && normal[0] == 0.0, "{normal:?}");
        let flipped = Cut::plane([0.0; 3], [0.0, 0.0, -1.0]);
        let CutShape::Plane { normal, .. } = a.toward(&flipped, 0.5).unwrap().shape else { panic!("a plane") };
        assert_eq!(normal, [0.0, 0.0, -1.0], "the same plane: its own orientation kept at the end");
        assert!(a.toward(&Cut::pattern([0.0; 3], vec![]), 0.5).is_none());
    }
}
