//! Drop-test settings. Each default is written once, in `Default`, with why (the measurements
//! that chose them: docs/benchmarks.md); the field docs say what a setting means.

use crate::model::FrictionModel;
use crate::statics::Backend;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Which engine steps the drop test.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Engine {
    /// rapier3d: soft contacts, an iterative solver (the physics engine the seed paper
    /// contrasts with the statics).
    #[default]
    Rapier,
    /// voussoir's exact-contact engine: hard contacts, one interior-point solve per moving component
    /// and step (dynamics::exact).
    Exact,
}

impl Engine {
    /// The engine's name in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rapier => "rapier",
            Self::Exact => "exact",
        }
    }
}

impl std::fmt::Display for Engine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How rapier's colliders follow a block whose convex hull is larger than it (a curved
/// voussoir, a notched block).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum ColliderForm {
    /// The hull where it reaches into no other block at the start (the excess is where nothing
    /// is), the exact convex parts where it does: fast, and the same answer while blocks keep
    /// to their places.
    #[default]
    Fitted,
    /// The exact convex parts (a compound) for every block whose hull exceeds it by more than
    /// `hull_tolerance`: faithful when blocks move into what the hull would fill.
    Exact,
}

impl std::fmt::Display for ColliderForm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Fitted => "fitted",
            Self::Exact => "exact",
        })
    }
}

/// How the exact-contact engine meets Coulomb's law at a sliding contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Coulomb {
    /// Exact: friction capacities μ f_n by a fixed point within each step (Tresca rounds, as
    /// the kinematic check), warm-started from the last step's normal forces.
    #[default]
    Exact,
    /// Anitescu's convex relaxation: one solve per step, but a sliding contact separates at
    /// μ |v_t| (associated friction).
    Relaxed,
}

impl std::fmt::Display for Coulomb {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Exact => "exact",
            Self::Relaxed => "relaxed",
        })
    }
}

/// The friction sets of the exact engine's force selection, which picks among the forces that
/// keep a round's velocities (the smallest, Σ f²) the ones whose normals become the next
/// round's capacities.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Selection {
    /// The round's own capacities |f_t| ≤ c: the round's forces are among the candidates, so
    /// the selection keeps its velocities exactly (the energy balance to the solves'
    /// tolerance).
    #[default]
    Round,
    /// Coulomb's sets |f_t| ≤ μ f_n: the smallest forces friction can carry (the least-norm
    /// rule of the statics' strict QP, in the same sets). A hyperstatic assembly near rest then
    /// settles in a few rounds, where the round's sets shrink its normals round after round
    /// towards capacities that cycle; a selection that cannot keep the velocities exactly
    /// keeps them to the pin's stiffness. One the structured solver cannot end (a round far
    /// from the fixed point) ends the step with the round's own forces, counted unsettled.
    Coulomb,
}

/// Settings of the exact-contact engine; each default written once, in `Default` (with why).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ExactSettings {
    /// How friction is bounded: exact Coulomb (rounds of solves) or Anitescu's relaxation.
    pub coulomb: Coulomb,
    /// The friction model of every contact point (the statics' three).
    pub friction_model: FrictionModel,
    /// Tresca rounds allowed per step before the step keeps its best round (the one whose
    /// capacities changed least; counted as unsettled).
    pub max_rounds: u32,
    /// Rounds in a row that do not halve the capacities' smallest change so far, after which a
    /// step stops as at `max_rounds`: its rounds wander instead of closing in. `None`: no step
    /// stops before `max_rounds`.
    pub stall_rounds: Option<u32>,
    /// The capacities have settled when none changed by more than this fraction of the largest.
    pub settle: f64,
    /// A component is at rest when no vertex moves faster than this fraction of g × dt (an
    /// acceleration below `still` g over the step, as the kinematic check's).
    pub still: f64,
    /// Interior-point feasibility and gap tolerance of each solve.
    pub solver_tolerance: f64,
    /// Interior-point iterations allowed per solve.
    pub max_iterations: u32,
    /// An overlap deeper than this fraction of the smaller block's size at the end of a step is
    /// projected out: the blocks moved apart by the least mass-weighted displacement, their
    /// velocities untouched (no energy out of overlap; the loads' work on the correction is
    /// accounted apart). Shallower overlaps only stop closing (Signorini at velocity level).
    pub projection: f64,
    /// Split a step at the instant a contact open at its start closes (estimated from the gap
    /// and its closing speed), so the impact acts at its time, not at a step's end: impacts
    /// second order in dt.
    pub split_impacts: bool,
    /// A component at rest stays at rest where an equilibrium within Coulomb's coupled sets
    /// holds it (the static theorem's pick), even where the exact sets also admit a motion
    /// from rest with no force on it (a flat arch's halves sliding down their vertical joints,
    /// a bar between two posts). Off, the first step from rest is the kinematic check's rate
    /// problem (Gauss's principle: that free motion); the settlement's runs turn it on, since
    /// they follow a design that stands by its statics.
    pub rest_when_admissible: bool,
    /// Vertices within this fraction of the median block size of the ground, or reaching it
    /// within two steps, are ground contacts of the step.
    pub envelope: f64,
    /// Start each structured solve from the iterate the component's previous solve of the same
    /// layout kept (the last step's, or the last round's): the same answers to the solver's
    /// tolerance in fewer iterations.
    pub warm_start: bool,
    /// Settle a step's Tresca rounds faster: a round is the fixed point when the capacities
    /// that changed bind nowhere (the contacts stick inside both), and the next capacities come
    /// from Anderson acceleration of the rounds (safeguarded), not the last round alone. `false`
    /// takes c ← μ f_n until the capacities stop changing (to cross-check).
    pub accelerate_rounds: bool,
    /// The interior-point solver of the step problems: the structured one (each contact a
    /// force point, the bodies' rows reduced as in the statics) wherever a step has its shape,
    /// else clarabel; `Clarabel` runs every step on clarabel (to cross-check).
    pub backend: Backend,
    /// The force selection's friction sets.
    pub selection: Selection,
    /// Take a moving component's step first by its contacts' last states (open, sticking,
    /// sliding): one linear solve, kept where it meets every exact-Coulomb condition, the
    /// Tresca rounds otherwise (exact Coulomb with the round's selection, no crushing: a drop's
    /// and a shake's steps). `false` runs the rounds on every step (to cross-check; a
    /// settlement's runs, which take the rounds' pick where several answers are admissible).
    pub by_states: bool,
}

impl Default for ExactSettings {
    fn default() -> Self {
        Self {
            coulomb: Coulomb::Exact,
            friction_model: FrictionModel::default(),
            // Warm-started capacities settle in 1–3 rounds; the bound only stops a cycle.
            max_rounds: 30,
            // No early stop: a drop's steps that do not settle within the limit are rare (a
            // block landing), and the next steps' rounds start from where they ended.
            stall_rounds: None,
            // The kinematic check's: far inside what changes a verdict.
            settle: 1e-4,
            still: 1e-6,
            // The kinematic check's: its first step is that check's rate problem.
            solver_tolerance: 1e-10,
            max_iterations: 200,
            // Far above a hinge's O(dt² ω² r) drift per step, far below the landing test's 1e-3.
            projection: 1e-4,
            split_impacts: true,
            rest_when_admissible: false,
            envelope: 0.02,
            warm_start: true,
            accelerate_rounds: true,
            backend: Backend::default(),
            // Exact velocities for a drop's energy balance; the quasi-static runs take Coulomb.
            selection: Selection::Round,
            by_states: true,
        }
    }
}

impl ExactSettings {
    fn validate(&self) -> Result<(), DropError> {
        for (name, value) in [
            ("exact.settle", self.settle),
            ("exact.still", self.still),
            ("exact.solver_tolerance", self.solver_tolerance),
            ("exact.projection", self.projection),
            ("exact.envelope", self.envelope),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(DropError::NotPositive { name, value });
            }
        }
        if self.max_rounds == 0 || self.max_iterations == 0 || self.stall_rounds == Some(0) {
            return Err(DropError::NoIterations);
        }
        Ok(())
    }
}

/// How the drop test simulates.
#[derive(Clone, Debug, PartialEq)]
pub struct DropSettings {
    /// The engine it runs on.
    pub engine: Engine,
    /// The exact-contact engine's settings (the rapier ones below do not apply to it).
    pub exact: ExactSettings,
    /// Simulated time, s.
    pub duration: f64,
    /// End the run as soon as a block has passed the tolerances (the verdict cannot change):
    /// for threshold searches; off when the motion itself is wanted.
    pub stop_when_falls: bool,
    /// Time step, s.
    pub dt: f64,
    /// rapier's velocity solver iterations per step.
    pub solver_iterations: usize,
    /// rapier's contact stiffness as a natural frequency, Hz.
    pub contact_frequency: f64,
    /// rapier's contact damping ratio.
    pub contact_damping: f64,
    /// Friction coefficient; `None`: the material's. Combined between two blocks with the
    /// `Min` rule (all blocks share it, so any rule gives μ).
    pub friction: Option<f64>,
    /// Compressive strength σ_c, Pa; `None`: the material's. The exact engine bounds each
    /// interface's compression by it (its module `crushing`); rapier's contacts do not crush.
    pub strength: Option<f64>,
    /// Initial horizontal speed given to every free block (+x), as a fraction of √(g·size) of
    /// the block (0: no perturbation).
    pub perturbation: f64,
    /// A floor to land on ([`crate::dynamics::scene::floor_level`]) for a design with supports and no
    /// ground of its own: what falls comes to rest in view instead of falling forever.
    pub floor: bool,
    /// A block whose convex hull exceeds its volume by at most this fraction collides as its
    /// hull. Beyond it — a curved voussoir, a notched block — it still collides as its hull
    /// when the hull reaches into no other block (the excess is where nothing is); otherwise
    /// as a convex decomposition ([`ColliderForm::Fitted`]). The volume error of either is
    /// reported.
    pub hull_tolerance: f64,
    /// Whether a block beyond `hull_tolerance` may still collide as its hull.
    pub colliders: ColliderForm,
    /// Where two blocks' hulls overlap at a joint (a warped joint triangulated differently on
    /// its two sides), both are cut back to the joint plane — if the cut takes at most this
    /// fraction of the block's volume (a warp's sliver).
    pub max_joint_cut: f64,
    /// Solver contacts deeper than this fraction of the median block size are dropped for the
    /// step: rapier's manifolds between many-sided hulls sometimes carry points reported far
    /// deeper than the shapes overlap, and their impulses burst a vault open.
    pub max_contact_depth: f64,
    /// A block has moved when its centroid drifted more than this fraction of its size (the
    /// bounding-box diagonal).
    pub drift_tolerance: f64,
    /// … or turned more than this angle, rad.
    pub rotation_tolerance: f64,
    /// A block has fallen (beyond recovery: a shake's collapse) when it turned more than this
    /// angle, rad …
    pub fall_rotation: f64,
    /// … or its centroid dropped more than this fraction of its size below its start.
    pub fall_drop: f64,
}

impl Default for DropSettings {
    fn default() -> Self {
        Self {
            engine: Engine::Rapier,
            exact: ExactSettings::default(),
            duration: 2.0,
            stop_when_falls: false,
            // rapier's soft contacts make stacks sink ~g·n(n+1)/ω²; small steps and stiff
            // contacts keep that far below the drift tolerance.
            dt: 1.0 / 240.0,
            solver_iterations: 10,
            // rapier's own default is 30 Hz.
            contact_frequency: 120.0,
            // rapier's is 5; a thin arch settles least with 1.
            contact_damping: 1.0,
            friction: None,
            strength: None,
            perturbation: 0.0,
            floor: true,
            hull_tolerance: 0.02,
            colliders: ColliderForm::Fitted,
            // Below the depth that let the Armadillo burst, far above a standing stack's sinking.
            max_contact_depth: 0.01,
            // A warp's sliver, not the real material a larger cut took off the compas crossvault.
            max_joint_cut: 0.005,
            drift_tolerance: 0.02,
            // ≈ 2.9°: above what a standing arch settles by, far below what a falling block turns.
            rotation_tolerance: 0.05,
            // ≈ 29°: past the tipping angle of any block up to twice as wide as tall, ten
            // times what an arch rocks by and comes back from.
            fall_rotation: 0.5,
            // A voussoir a quarter of its size below its place has left the arch.
            fall_drop: 0.25,
        }
    }
}

/// Invalid drop-test settings.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DropError {
    /// A setting that must be a finite number > 0 is not.
    #[error("drop test setting {name} = {value} must be a finite number > 0")]
    NotPositive {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A setting that must be a finite number ≥ 0 is not.
    #[error("drop test setting {name} = {value} must be a finite number ≥ 0")]
    Negative {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// An iteration or round limit is 0.
    #[error(
        "drop test: solver_iterations (and the exact engine's max_rounds, stall_rounds, max_iterations) must be at least 1"
    )]
    NoIterations,
    /// The ground motion is not valid.
    #[error(transparent)]
    GroundMotion(#[from] crate::dynamics::ground_motion::GroundMotionError),
    /// The duration takes more steps than the limit.
    #[error("drop test: {steps} steps (duration / dt) is more than the limit of 10 000 000")]
    TooManySteps {
        /// duration / dt.
        steps: f64,
    },
}

impl DropSettings {
    /// Every setting checked: one clear error naming the first that is wrong.
    pub fn validate(&self) -> Result<(), DropError> {
        for (name, value) in [
            ("duration", self.duration),
            ("dt", self.dt),
            ("contact_frequency", self.contact_frequency),
            ("contact_damping", self.contact_damping),
            ("drift_tolerance", self.drift_tolerance),
            ("rotation_tolerance", self.rotation_tolerance),
            ("fall_rotation", self.fall_rotation),
            ("fall_drop", self.fall_drop),
            ("max_contact_depth", self.max_contact_depth),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(DropError::NotPositive { name, value });
            }
        }
        for (name, value) in [
            ("perturbation", self.perturbation),
            ("hull_tolerance", self.hull_tolerance),
            ("max_joint_cut", self.max_joint_cut),
            ("friction", self.friction.unwrap_or(0.0)),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(DropError::Negative { name, value });
            }
        }
        if let Some(value) = self.strength
            && !crate::model::Material::valid_strength(value)
        {
            return Err(DropError::NotPositive { name: "strength", value });
        }
        if self.solver_iterations == 0 {
            return Err(DropError::NoIterations);
        }
        self.exact.validate()?;
        let steps = (self.duration / self.dt).ceil();
        if steps > 1e7 {
            return Err(DropError::TooManySteps { steps });
        }
        Ok(())
    }
}
