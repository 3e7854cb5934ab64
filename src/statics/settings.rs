//! Statics settings with documented defaults.

use super::StaticsError;
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

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Structured => "structured",
            Self::Clarabel => "clarabel",
        })
    }
}

/// Settings of [`super::analyze`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct StaticsSettings {
    /// Default [`FrictionModel::Pyramid8`].
    pub friction_model: FrictionModel,
    /// Friction coefficient; `None` (default) takes the scene material's.
    pub friction: Option<f64>,
    /// Weight of Σ(c_n⁺)² in the distribution QP. Default 1.
    pub w_compression: f64,
    /// Weight of Σ(c_n⁻)². Default 1e6 (compas_cra's). Only shapes the distribution: the total
    /// tension is fixed at its exact minimum first.
    pub w_tension: f64,
    /// Weight of Σ(c_u² + c_v²). Default 1.
    pub w_friction: f64,
    /// Weight of Σ s² (friction slack). Default 1e6.
    pub w_slack: f64,
    /// The assembly stands when, in every connected component, the minimum total tension and
    /// the minimum friction excess are both at most this fraction of the weight of the
    /// component's lightest block (so a light block that would fall off is not hidden by heavy
    /// ones), or below 1e-8 of the component's weight (what the LPs resolve). Default 1e-6.
    pub stand_tolerance: f64,
    /// Interior-point feasibility and gap tolerance (clarabel's tol_feas, tol_gap_abs/rel).
    /// Default 1e-8 (clarabel's); the equilibrium residual is then polished to round-off.
    pub solver_tolerance: f64,
    /// Default 200.
    pub max_iterations: u32,
    /// Solve independent components on two threads when the problem is big enough. Default
    /// true; results are identical either way.
    pub parallel: bool,
    /// Solve each connected component of free blocks on its own (default true). Off puts every
    /// free block in one problem: the same answer, only slower (kept to measure the saving).
    pub split_components: bool,
    /// On a design that does not stand, also solve the force-distribution QP (default true).
    /// Off keeps the exact minimum tension and friction excess and reports the forces of the
    /// last LP (an equilibrium with those minima): about a third of the time on failing designs
    /// where only the graded numbers matter (sequence checks, order search).
    pub distribution: bool,
    /// Which interior-point solver runs the problems. Default [`Backend::Structured`].
    pub backend: Backend,
    /// Which stage a component's solve starts with. Default [`FirstStage::Strict`].
    pub first_stage: FirstStage,
}

/// Where a component's solve starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FirstStage {
    /// The strict QP (compression only, friction within μ): most designs being checked stand,
    /// and a standing one then costs one solve.
    #[default]
    Strict,
    /// Straight to the exact minimum-tension and friction-excess LPs: the same verdict and
    /// graded numbers with one solve fewer on a design that does not stand (a sequence check
    /// switches to it while its steps fail). A design that stands then costs the two LPs, and
    /// the strict QP after them for its force distribution when `distribution` is on.
    Relaxed,
}

/// The interior-point solver of the equilibrium problems (`--solver structured|clarabel`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Backend {
    /// clarabel's algorithm with the Newton system reduced to the equilibrium rows
    /// (`statics::ipm`); falls back to clarabel for any problem of another shape.
    #[default]
    Structured,
    /// clarabel with its general sparse LDL (QDLDL) on the whole KKT matrix.
    Clarabel,
}

impl Default for StaticsSettings {
    fn default() -> Self {
        Self {
            friction_model: FrictionModel::default(),
            friction: None,
            w_compression: 1.0,
            w_tension: 1e6,
            w_friction: 1.0,
            w_slack: 1e6,
            stand_tolerance: 1e-6,
            solver_tolerance: 1e-8,
            max_iterations: 200,
            parallel: true,
            split_components: true,
            distribution: true,
            backend: Backend::default(),
            first_stage: FirstStage::default(),
        }
    }
}

impl StaticsSettings {
    pub fn validate(&self) -> Result<(), StaticsError> {
        for (name, value) in [
            ("w_compression", self.w_compression),
            ("w_tension", self.w_tension),
            ("w_friction", self.w_friction),
            ("w_slack", self.w_slack),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(StaticsError::BadWeight { name, value });
            }
        }
        if let Some(mu) = self.friction
            && !(mu >= 0.0 && mu.is_finite())
        {
            return Err(StaticsError::BadFriction(mu));
        }
        for t in [self.stand_tolerance, self.solver_tolerance] {
            if !(t > 0.0 && t.is_finite()) {
                return Err(StaticsError::BadTolerance(t));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::FrictionModel;

    /// The largest |f_t| a model's rows allow in direction θ (μ f_n = 1), found from the rows
    /// as assembled: |u|, |v| ≤ 1 (box and pyramid), |u ± v| ≤ √2 (pyramid), u² + v² ≤ 1 (cone).
    fn reach(model: FrictionModel, theta: f64) -> f64 {
        let (c, s) = (theta.cos().abs(), theta.sin().abs());
        let r2 = std::f64::consts::SQRT_2;
        match model {
            FrictionModel::Cone => 1.0,
            FrictionModel::Box4 => 1.0 / c.max(s),
            FrictionModel::Pyramid8 => (1.0 / c.max(s)).min(r2 / (c + s)),
        }
    }

    #[test]
    fn max_utilization_is_the_farthest_corner_of_the_model() {
        for model in [FrictionModel::Pyramid8, FrictionModel::Cone, FrictionModel::Box4] {
            let far = (0..=7200).map(|k| reach(model, k as f64 * std::f64::consts::TAU / 7200.0)).fold(0.0, f64::max);
            assert!((far - model.max_utilization()).abs() < 1e-9, "{model}: {far} vs {}", model.max_utilization());
        }
        assert!((FrictionModel::Pyramid8.max_utilization() - 1.0823922).abs() < 1e-7);
    }
}
