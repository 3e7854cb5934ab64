//! A cut of a design's history (see [`crate::decompose`] for how it is replayed).
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
    Plane { point: [f64; 3], normal: [f64; 3] },
    /// A pattern of line segments (typically drawn on a face) extruded to one apex: segment
    /// `[p, q]` cuts with the plane through `apex`, `p` and `q`, but only the pieces that the
    /// cone from the apex through the segment meets. Segments are applied in order, so a
    /// segment drawn between two earlier ones cuts only the piece between them (brick bonds,
    /// voussoir courses). The interfaces are planar and converge on the apex.
    Pattern { apex: [f64; 3], segments: Vec<[[f64; 3]; 2]> },
}

/// One cut of the history.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawCut", into = "RawCut")]
pub struct Cut {
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
