//! Tolerances relative to the model size.
//!
//! Every length tolerance is a fraction of the model's bounding-box diagonal (`scale`), every
//! area tolerance a fraction of `scale²`, so a scene in millimetres and the same scene in
//! metres give the same welds, interfaces and verdicts.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A relative tolerance that cannot be used: every tolerance is a finite fraction of the model
/// size, and a zero, negative or NaN one would make the weld grid, the planes and the area
/// tests meaningless.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
#[error("tolerance '{name}' is {value}; it must be a finite number {range}")]
pub struct ToleranceError {
    /// The tolerance's name (`weld`, `coplanar`, …).
    pub name: &'static str,
    /// Its value as given.
    pub value: f64,
    /// The range it must be in, in words.
    pub range: &'static str,
}

/// Relative tolerances (dimensionless). The defaults, and the data that chose them, are in
/// `Default` (`voussoir analyze --help` prints the coplanar and angle ones).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Tolerances {
    /// Vertices closer than `weld * scale` are merged.
    pub weld: f64,
    /// A face whose vertices leave its best-fit plane by more than `planarity * scale` is
    /// triangulated (with a warning); flatter faces are used with their best-fit plane.
    pub planarity: f64,
    /// Two faces are coplanar when every vertex of each is within `coplanar * scale` of the
    /// other's plane. Tighten it for exact CAD geometry.
    pub coplanar: f64,
    /// ... and within `coplanar_thickness` times the thinner block's thickness (volume / largest
    /// face area), so that thin blocks (a 1000-voussoir arch has 3 mm voussoirs) do not reach
    /// past their neighbour.
    pub coplanar_thickness: f64,
    /// Two faces are opposite when the angle between one's normal and the reverse of the
    /// other's is below this, in degrees; for large faces the coplanarity test is the stricter
    /// one.
    pub angle_deg: f64,
    /// An overlap piece is an interface when its area is at least `min_area` times the smaller
    /// of the two face areas and at least `min_area * 1e-4 * scale²`.
    pub min_area: f64,
    /// A block whose volume is below `min_volume * (block diagonal)³` is rejected.
    pub min_volume: f64,
    /// The model size `scale` itself, m, when it should not be the scene's own bounding-box
    /// diagonal (`None`: the diagonal). A sequence check sets it to the complete
    /// design's size, so that every prefix is detected and solved with the design's absolute
    /// tolerances (the same interfaces as the design, and work reused between steps).
    pub reference_length: Option<f64>,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            weld: 1e-7,
            // Cut stone data such as the Armadillo vault has faces 1.5 cm out of plane on a
            // 20 m model; triangulating them would break their contact with the neighbours.
            planarity: 1e-2,
            // 3 mm on a 1 m model: the BRG dome and Armadillo data have joints up to 2.9 cm
            // open on 10–20 m models.
            coplanar: 3e-3,
            // The Armadillo's widest joint is 0.23 of its block.
            coplanar_thickness: 0.3,
            // The dome and Armadillo data have joints up to 5.6° open.
            angle_deg: 6.0,
            min_area: 1e-3,
            min_volume: 1e-9,
            reference_length: None,
        }
    }
}

/// Tolerances resolved to absolute values for one model of size `scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AbsTolerances {
    /// The model size every tolerance is relative to, m.
    pub scale: f64,
    /// Vertices closer than this are merged, m.
    pub weld: f64,
    /// A face leaving its best-fit plane by more than this is triangulated, m.
    pub planarity: f64,
    /// Faces within this of each other's plane are coplanar, m.
    pub coplanar: f64,
    /// The coplanar reach as a fraction of the thinner block's thickness (dimensionless).
    pub coplanar_thickness: f64,
    /// cos of the angle tolerance: faces are opposite when `n_a · n_b <= -cos_angle`.
    pub cos_angle: f64,
    /// An interface's least area as a fraction of the smaller face's (dimensionless).
    pub min_area_rel: f64,
    /// An interface's least area, m².
    pub min_area_abs: f64,
    /// A block's least volume as a fraction of its bounding-box diagonal cubed (dimensionless).
    pub min_volume_rel: f64,
}

impl Tolerances {
    /// Checks that every tolerance is a finite number in its range (lengths and the thickness
    /// factor > 0, areas and volumes ≥ 0, the angle in (0°, 90°]); the reference length is
    /// checked with the model ([`crate::model::ModelError::BadReferenceLength`]).
    pub fn validate(&self) -> Result<(), ToleranceError> {
        let positive = [
            ("weld", self.weld),
            ("planarity", self.planarity),
            ("coplanar", self.coplanar),
            ("coplanar_thickness", self.coplanar_thickness),
        ];
        let non_negative = [("min_area", self.min_area), ("min_volume", self.min_volume)];
        let bad = |name, value, range| Err(ToleranceError { name, value, range });
        if let Some(&(name, value)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            return bad(name, value, "> 0");
        }
        if let Some(&(name, value)) = non_negative.iter().find(|(_, v)| !(v.is_finite() && *v >= 0.0)) {
            return bad(name, value, ">= 0");
        }
        if !(self.angle_deg > 0.0 && self.angle_deg <= 90.0) {
            return bad("angle_deg", self.angle_deg, "in (0, 90] degrees");
        }
        Ok(())
    }

    /// The model size of a scene whose bounding-box diagonal is `diagonal`: the reference
    /// length when one is set.
    pub fn scale(&self, diagonal: f64) -> f64 {
        self.reference_length.unwrap_or(diagonal)
    }

    /// Absolute tolerances for a model whose bounding-box diagonal is `scale` (> 0).
    pub fn resolve(&self, scale: f64) -> AbsTolerances {
        AbsTolerances {
            scale,
            weld: self.weld * scale,
            planarity: self.planarity * scale,
            coplanar: self.coplanar * scale,
            coplanar_thickness: self.coplanar_thickness,
            cos_angle: self.angle_deg.to_radians().cos(),
            min_area_rel: self.min_area,
            min_area_abs: self.min_area * 1e-4 * scale * scale,
            min_volume_rel: self.min_volume,
        }
    }
}
