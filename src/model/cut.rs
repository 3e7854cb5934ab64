//! A cut of a design's history (see [`crate::decompose`] for how it is replayed).

use crate::geometry::{Plane, Point3, Vector3};
use serde::{Deserialize, Serialize};

/// One cut of the history.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cut {
    /// A point on the plane (m).
    pub point: [f64; 3],
    /// The plane normal (any length > 0).
    pub normal: [f64; 3],
    /// Only this piece is cut (default: every piece the plane crosses, supports excepted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<String>,
}

impl Cut {
    pub fn plane(&self) -> Plane {
        Plane::from_point_normal(&Point3::from(self.point), &Vector3::from(self.normal))
    }
}
