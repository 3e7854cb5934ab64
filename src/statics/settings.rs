//! Statics settings with documented defaults.

use super::backend::Backend;
use super::error::StaticsError;
use super::problem::FrictionModel;
use serde::{Deserialize, Serialize};

/// Settings of [`super::solve`]; each default is written once, in `Default` (with why).
/// `voussoir analyze --help` prints the ones the command line sets.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct StaticsSettings {
    /// How friction capacity is modelled (the enum's `#[default]`).
    pub friction_model: FrictionModel,
    /// Friction coefficient; `None` takes the scene material's.
    pub friction: Option<f64>,
    /// Compressive strength σ_c, Pa; `None` takes the scene material's (which may have none:
    /// then the stone does not crush and no crushing rows are built).
    pub strength: Option<f64>,
    /// Weight of Σ(c_n⁺)² in the distribution QP.
    pub w_compression: f64,
    /// Weight of Σ(c_n⁻)². Only shapes the distribution: the total tension is fixed at its
    /// exact minimum first.
    pub w_tension: f64,
    /// Weight of Σ(c_u² + c_v²).
    pub w_friction: f64,
    /// Weight of Σ s² (friction slack).
    pub w_slack: f64,
    /// The assembly stands when, in every connected component, the minimum total tension and
    /// the minimum friction excess are both at most this fraction of the weight of the
    /// component's lightest block (so a light block that would fall off is not hidden by heavy
    /// ones), or below `stages::STAND_FLOOR` (1e-8) of the component's weight (what the LPs
    /// resolve).
    pub stand_tolerance: f64,
    /// Interior-point feasibility and gap tolerance (clarabel's tol_feas, tol_gap_abs/rel); the
    /// equilibrium residual is then polished to round-off.
    pub solver_tolerance: f64,
    /// Interior-point iterations allowed per problem.
    pub max_iterations: u32,
    /// Use both cores: independent components on two threads, and a large component's
    /// per-point kernels split in two (its solve then keeps the second core busy). Off where
    /// the caller already runs two solves at once. Results are identical either way.
    pub parallel: bool,
    /// Solve each connected component of free blocks on its own. Off puts every free block in
    /// one problem: the same answer, only slower (kept to measure the saving).
    pub split_components: bool,
    /// On a design that does not stand, also solve the force-distribution QP. Off keeps the exact minimum tension and friction excess and reports the forces of the
    /// last LP (an equilibrium with those minima): about a third of the time on failing designs
    /// where only the graded numbers matter (sequence checks, order search).
    pub distribution: bool,
    /// Start each component's solve from the iterates its previous solve kept, when the
    /// component has the same blocks and interface layout (a cut moved a little, a block
    /// nudged): an interactive editor's loop, through a long-lived pipeline (`Pipeline`, the
    /// ECS app). The answers are those of cold solves to the solver's tolerance (a warm solve
    /// that does not end `Solved` within the cold one's iterations is run again cold), not bit
    /// for bit: so off by default, where the same input must give the same output.
    pub warm_start: bool,
    /// Where several mechanisms collapse at the same load factor, report one of them — a vertex
    /// of the optimal face (`statics::vertex`) — rather than the interior point's blend. Off
    /// where only λ* is wanted (the design search's objective) and to measure what the recovery
    /// costs: λ* is the same either way.
    pub one_mechanism: bool,
    /// Which interior-point solver runs the problems (the enum's `#[default]`).
    pub backend: Backend,
    /// Which stage a component's solve starts with (the enum's `#[default]`).
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
    /// switches to it while its steps fail). A design that stands then costs the penalty LP
    /// (which finds no tension) and, when `distribution` is on, the distribution QP with
    /// tension left out.
    Relaxed,
}

impl Default for StaticsSettings {
    fn default() -> Self {
        Self {
            friction_model: FrictionModel::default(),
            friction: None,
            strength: None,
            w_compression: 1.0,
            // compas_cra's tension weight.
            w_tension: 1e6,
            w_friction: 1.0,
            w_slack: 1e6,
            stand_tolerance: 1e-6,
            // clarabel's own default.
            solver_tolerance: 1e-8,
            max_iterations: 200,
            parallel: true,
            split_components: true,
            distribution: true,
            warm_start: false,
            one_mechanism: true,
            backend: Backend::default(),
            first_stage: FirstStage::default(),
        }
    }
}

impl StaticsSettings {
    /// These settings with the strength taken from `assembly`'s material when not given: what
    /// the stages, the load factor, the verdict and the caches' keys read.
    pub fn resolved(&self, assembly: &crate::model::Assembly) -> Self {
        Self { strength: self.strength.or(assembly.material.strength), ..self.clone() }
    }

    /// Refuses a μ, a strength, a weight or a tolerance that is not a finite number in range.
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
            && !crate::model::Material::valid_friction(mu)
        {
            return Err(StaticsError::BadFriction(mu));
        }
        if let Some(s) = self.strength
            && !crate::model::Material::valid_strength(s)
        {
            return Err(StaticsError::BadStrength(s));
        }
        for t in [self.stand_tolerance, self.solver_tolerance] {
            if !(t > 0.0 && t.is_finite()) {
                return Err(StaticsError::BadTolerance(t));
            }
        }
        Ok(())
    }
}
