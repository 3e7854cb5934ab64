//! Rigid-block equilibrium (RBE): the penalty QP of Whiting (2009/2012) and Livesley, graded.
//!
//! ## Variables, per interface vertex
//! Relaxed layout `[c_n⁺, c_n⁻, c_u, c_v, s]` in the interface frame (n, u, v) of
//! [`crate::interfaces`]: net normal force `c_n⁺ − c_n⁻` (compression positive), friction
//! `c_u, c_v`, and a friction slack `s ≥ 0` that relaxes the capacity to `μ c_n⁺ + s`. The strict
//! layout `[c_n⁺, c_u, c_v]` has no tension and no slack. When μ = 0 the strict layout has no
//! friction columns (`[c_n⁺]` only); the relaxed one keeps them with capacity `0 + s`.
//!
//! ## Rows (the contact form of `problem`: module docs there)
//! 1. Equality, 6 per free block: Σ forces + weight = 0 (x, y, z) and Σ moments about the
//!    block's volume centroid = 0 (x, y, z). A vertex force f acts on b as +f and on a as −f.
//! 2. Per vertex: the sign rows `c_n⁺ ≥ 0` (left out in the strict layout with friction,
//!    where the friction rows imply it), `c_n⁻ ≥ 0`, `s ≥ 0`; for the pyramid models
//!    `±c_u − μc_n⁺ − s ≤ 0`, `±c_v − μc_n⁺ − s ≤ 0` (box4 and pyramid8) and
//!    `±c_u ± c_v − √2(μc_n⁺ + s) ≤ 0` (pyramid8 only); for the cone model one second-order
//!    cone `‖(c_u, c_v)‖ ≤ μc_n⁺ + s`.
//! 3. Budgets `Σ c_n⁻ ≤ T`, `Σ s ≤ F` in the later stages.
//!
//! ## Stages (the verdict does not depend on the penalty weights)
//! 1. Strict QP: minimise w_c Σ(c_n⁺)² + w_f Σ(c_u² + c_v²) with no tension and friction
//!    within μ. Solved ⇒ minimum tension and friction excess are exactly zero: it stands, and
//!    this is the force distribution (one solve for the common case).
//! 2. Otherwise the relaxed stages: the exact-penalty LP min M Σ c_n⁻ + Σ s first — when its
//!    optimum uses no tension, T* = 0 and F* is its Σ s; else the minimum-tension LP
//!    T* = min Σ c_n⁻ (friction slack free, i.e. unlimited friction), M raised until the penalty
//!    LP's tension comes back at T*, and past its largest the budget form F* = min Σ s with
//!    Σ c_n⁻ ≤ T* — then the QP w_c Σ(c_n⁺)² + w_t Σ(c_n⁻)² + w_f Σ(c_u² + c_v²) + w_s Σ s²
//!    with the budgets Σ c_n⁻ ≤ T*, Σ s ≤ F*: the distribution (docs/design.md#stages).
//!
//! Units: the problem is solved non-dimensionally (lengths / model size, forces / the
//! component's free weight) and scaled back to N and m. Each connected component of free
//! blocks is solved on its own (components in parallel when there are several big ones).
//!
//! ## Solvers ([`Backend`])
//! Every stage is one conic problem as plain data (`problem::ContactProblem`). By default
//! it runs on `backend`'s structured solver, clarabel's interior-point algorithm with the
//! Newton system reduced to the equilibrium rows (`Backend::Structured`); `Backend::Clarabel`
//! runs the same data on clarabel itself (`backend/clarabel.rs`, the one clarabel call), to
//! cross-check.
//!
//! ## Layers (each module imports only those below it; none imports this front module)
//! 1. `problem`: the shared vocabulary, a leaf — variables, friction models, cones, the
//!    problem as plain data, [`Accuracy`], [`SolverStatus`]; and
//!    `error` ([`StaticsError`]), [`components`] (connected components of free blocks).
//! 2. `backend`: the solvers, over `problem` only; `settings` ([`StaticsSettings`]), over `backend`'s
//!    [`Backend`] and `problem`.
//! 3. `assemble`: a component's rows and each stage's problem; `vertex`: one vertex of a load
//!    factor's optimal face (the mechanism's recovery) and what it says of its uniqueness, over
//!    `problem` only.
//! 4. `stages`: a component's solve stage by stage, and the verdict rule; `load_factor`: a
//!    component's load factor and collapse mechanism (an LP/SOCP on the same rows, its dual);
//!    `infill`: the densities that make a component stand (the same rows with the
//!    densities as variables, and the dual mechanism when none does);
//!    `kinematic`: a component's rate problem from rest (the same rows with the blocks'
//!    accelerations, a fixed point of QPs on clarabel).
//! 5. `result`: per-interface results and the global answer from the stages' outcomes;
//!    `cache`: outcomes kept by component content ([`solve_cached`]).

mod assemble;
mod backend;
#[cfg(test)]
mod backend_tests;
mod cache;
mod components;
mod error;
mod infill;
mod load_factor;
pub mod mechanism;
mod problem;
mod rate;
mod result;
mod settings;
mod stages;
mod vertex;

pub use backend::{Backend, ConicOutcome, kernel_profile, solve_conic};
pub(crate) use cache::component_key;
pub use cache::{SolveStats, StaticsCache, solve_cached};
pub use components::{Component, components};
pub use error::StaticsError;
pub use infill::{DensityCell, DensityGoal, DensityOutcome, LiveCase, component_densities};
pub use load_factor::{FactorOutcome, Motion, component_load_factor, failure_mechanism, standing_load_factor};
pub use mechanism::{BlockMotion, InterfaceMotion, JointState, Mechanism, Uniqueness};
pub use problem::{Accuracy, BlockColumn, Cone, ConicProblem, FrictionModel, SolverStatus, StressBlock};
// The contact form, for the exact-contact engine's steps on the structured solver.
pub(crate) use backend::{BlockLu, Warm, WarmStart, run_warm as solve_contact_problem};
pub(crate) use problem::{Contact, ContactProblem, Geometry, PointRows, Side, Var};
pub(crate) use problem::{StrengthColumn, stress_block, stress_block_cones};
pub use rate::{KinematicSettings, RateOutcome, RateState, rate_problem};
pub use result::{CrushingReport, InterfaceResult, SolverReport, StaticsResult, VertexForce};
pub use settings::{FirstStage, StaticsSettings};
pub use stages::{Verdict, stand_threshold};

use crate::interfaces::Interface;
use crate::model::Assembly;

/// Solves the equilibrium of `assembly` over `interfaces` (as returned by
/// [`crate::interfaces::detect`]). μ comes from the settings when given, else the material.
pub fn solve(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
) -> Result<StaticsResult, StaticsError> {
    let keys = crate::interfaces::block_keys(assembly);
    Ok(solve_cached(assembly, interfaces, settings, &keys, &mut StaticsCache::default())?.0)
}
