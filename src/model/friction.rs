//! The friction law's model at an interface vertex: a property of the contact the statics,
//! the kinematic check and the reports share.

use serde::{Deserialize, Serialize};

/// How the friction capacity |f_t| ≤ μ f_n⁺ is modelled at each interface vertex.
///
/// The names (`pyramid8`, `cone`, `box4`) are the same in the scene and report JSON, on the
/// command line (`clap::ValueEnum`, which also takes `pyramid` and `box`) and in [`Display`].
///
/// [`Display`]: std::fmt::Display
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum FrictionModel {
    /// 8-sided outer pyramid (the seed paper's default): up to 8.2 % more friction than
    /// Coulomb in diagonal directions.
    #[default]
    #[value(alias = "pyramid")]
    Pyramid8,
    /// Exact Coulomb cone, as a second-order cone.
    Cone,
    /// 4-sided box |f_u|, |f_v| ≤ μ f_n⁺ (older tools): up to 41 % more than Coulomb.
    #[value(alias = "box")]
    Box4,
}

impl FrictionModel {
    /// The facets of the pyramid models as `(du, dv, scale)`: `du f_u + dv f_v ≤ scale × capacity`
    /// (the box's four sides, then the pyramid's four diagonals); none for the cone.
    pub fn facets(self) -> &'static [(f64, f64, f64)] {
        const R2: f64 = std::f64::consts::SQRT_2;
        const FACETS: [(f64, f64, f64); 8] = [
            (1.0, 0.0, 1.0),
            (-1.0, 0.0, 1.0),
            (0.0, 1.0, 1.0),
            (0.0, -1.0, 1.0),
            (1.0, 1.0, R2),
            (1.0, -1.0, R2),
            (-1.0, 1.0, R2),
            (-1.0, -1.0, R2),
        ];
        match self {
            Self::Pyramid8 => &FACETS,
            Self::Box4 => &FACETS[..4],
            Self::Cone => &[],
        }
    }

    /// The largest friction utilisation |f_t| / (μ f_n⁺) (measured as a circle, as reported)
    /// the model allows: at the outer pyramid's corners 1/cos 22.5° = 1.082, at the box's √2,
    /// on the cone 1.
    pub fn max_utilization(self) -> f64 {
        match self {
            Self::Pyramid8 => 1.0 / std::f64::consts::FRAC_PI_8.cos(),
            Self::Cone => 1.0,
            Self::Box4 => std::f64::consts::SQRT_2,
        }
    }
}

impl std::fmt::Display for FrictionModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Pyramid8 => "pyramid8",
            Self::Cone => "cone",
            Self::Box4 => "box4",
        })
    }
}
