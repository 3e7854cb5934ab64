//! The kinematic verdict: does the equilibrium the statics found actually arise?
//!
//! The statics (RBE) accepts any force field with no tension and friction within μ, including
//! ones that nothing produces: a bar wedged between two posts "stands" on a squeeze that no
//! one applied. Here each connected component of free blocks is released from rest with no
//! contact squeezed beforehand, and the contact forces are the ones that motion produces
//! (the rate problem, [`crate::statics::rate_problem`]: Signorini contact, Coulomb friction
//! against the slip, the fixed point of the friction capacity from zero). It stands
//! kinematically when it stays at rest; otherwise the blocks' initial accelerations are its
//! mechanism ([`Mechanism`], the load factor's representation: translation in m/s² and
//! rotation in rad/s² — a virtual motion, drawn the same way).
//!
//! - Kinematically standing implies standing by the statics (the forces at rest are an RBE
//!   solution); where the statics fails, so does this (see [`Kinematic::verdict`]).
//! - Scale-free: the rate problem is solved non-dimensionally (forces by the weight, lengths
//!   by the model size, accelerations by g), so mm vs m or the density × 10⁶ give the same
//!   verdict; there is no displacement bound and no absolute tolerance.
//! - Deterministic: the same rounds of the same QPs.
//! - Where it differs from compas_cra's CRA: CRA couples the forces with a bounded virtual
//!   displacement and calls a design stable when the displacement its non-convex program finds
//!   is below an absolute tolerance; here the motion is the acceleration from rest, so no bound
//!   is needed, and "undecided" is explicit when the friction capacities do not settle.

use crate::interfaces::Interface;
use crate::model::Assembly;
use crate::pipeline::Analysis;
use crate::stability::Mechanism;
use crate::statics::{self, KinematicSettings, Motion, RateOutcome, RateState, SolverStatus, StaticsSettings};
use serde::Serialize;
use thiserror::Error;

/// Why the kinematic check cannot run (bad settings; solver trouble is an answer,
/// [`KinematicVerdict::Undecided`]).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum KinematicError {
    /// The statics refused the assembly or the settings.
    #[error(transparent)]
    Statics(#[from] statics::StaticsError),
    /// A setting is out of range (the message names it).
    #[error("{0}")]
    Settings(String),
}

/// What the kinematic check says.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum KinematicVerdict {
    /// Every component stays at rest with the forces that arise.
    Stands,
    /// Some component moves (or the statics already fails).
    Fails,
    /// The friction capacities did not settle, or a solve failed, in a component that does not
    /// move otherwise: no answer.
    Undecided,
}

/// The kinematic check of a design.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Kinematic {
    /// Stands, fails or undecided, over every component.
    pub verdict: KinematicVerdict,
    /// The statics' verdict on the same design (RBE).
    pub statics_stands: bool,
    /// Both verdicts say the same (undecided agrees with nothing).
    pub agrees: bool,
    /// The initial accelerations of the moving components (m/s², rad/s²), when it fails.
    pub mechanism: Option<Mechanism>,
    /// The largest vertex acceleration over all components, as a fraction of g.
    pub peak_acceleration: f64,
    /// The worst solver status of any round that ran.
    pub status: SolverStatus,
    /// Fixed-point rounds (the largest over components) and interior-point iterations (summed).
    pub rounds: u32,
    /// Interior-point iterations, summed over rounds and components.
    pub iterations: u32,
    /// ‖M a − w − A f‖_∞ of the last rounds, N.
    pub residual: f64,
    /// Seconds inside the solvers.
    pub solver_seconds: f64,
}

/// The kinematic check of `analysis`'s design, with its statics settings (friction model, μ)
/// and `settings`.
pub fn check(
    analysis: &Analysis,
    statics: &StaticsSettings,
    settings: &KinematicSettings,
) -> Result<Kinematic, KinematicError> {
    check_parts(&analysis.assembly, &analysis.interfaces, analysis.statics.stands, statics, settings)
}

/// [`check`] from its parts: the assembly, its interfaces and the statics' verdict.
pub fn check_parts(
    assembly: &Assembly,
    interfaces: &[Interface],
    statics_stands: bool,
    statics: &StaticsSettings,
    settings: &KinematicSettings,
) -> Result<Kinematic, KinematicError> {
    statics.validate()?;
    settings.validate().map_err(KinematicError::Settings)?;
    let mu = statics.friction.unwrap_or(assembly.material.friction);
    let comps = statics::components(assembly, interfaces);
    let outcomes: Vec<RateOutcome> = comps
        .iter()
        .map(|c| {
            if c.is_supported(assembly, interfaces) {
                statics::rate_problem(assembly, interfaces, c, mu, statics.friction_model, settings)
            } else {
                free_fall(assembly, c.blocks.len())
            }
        })
        .collect();
    // Where the statics fails, a component whose capacities did not settle but that still
    // moves shows its last round's motion.
    let moving: Vec<(&statics::Component, &[Motion])> = comps
        .iter()
        .zip(&outcomes)
        .filter(|(_, o)| {
            o.state == RateState::Moving
                || (!statics_stands && o.state == RateState::Unsettled && o.peak > settings.still)
        })
        .map(|(c, o)| (c, o.accelerations.as_slice()))
        .collect();
    let undecided = outcomes.iter().any(|o| matches!(o.state, RateState::Unsettled | RateState::SolverFailed));
    // Standing kinematically needs the statics' equilibrium: at the edge of the two
    // tolerances, the statics' failure decides.
    let settled_moving = outcomes.iter().any(|o| o.state == RateState::Moving);
    let verdict = if settled_moving || !statics_stands {
        KinematicVerdict::Fails
    } else if undecided {
        KinematicVerdict::Undecided
    } else {
        KinematicVerdict::Stands
    };
    let agrees = verdict != KinematicVerdict::Undecided && (verdict == KinematicVerdict::Stands) == statics_stands;
    Ok(Kinematic {
        verdict,
        statics_stands,
        agrees,
        mechanism: (!moving.is_empty()).then(|| Mechanism::new(assembly, interfaces, &moving)),
        peak_acceleration: outcomes.iter().map(|o| o.peak).fold(0.0, f64::max),
        status: outcomes.iter().map(|o| o.status).max().unwrap_or(SolverStatus::Solved),
        rounds: outcomes.iter().map(|o| o.rounds).max().unwrap_or(0),
        iterations: outcomes.iter().map(|o| o.iterations).sum(),
        residual: outcomes.iter().map(|o| o.residual).fold(0.0, f64::max),
        solver_seconds: outcomes.iter().map(|o| o.solver_seconds).sum(),
    })
}

/// A component that touches no support falls freely: every block accelerates at g.
fn free_fall(assembly: &Assembly, blocks: usize) -> RateOutcome {
    let g = assembly.gravity;
    RateOutcome {
        state: RateState::Moving,
        status: SolverStatus::Unsupported,
        accelerations: vec![[g.x, g.y, g.z, 0.0, 0.0, 0.0]; blocks],
        peak: 1.0,
        rounds: 0,
        iterations: 0,
        residual: 0.0,
        solver_seconds: 0.0,
    }
}

/// The work rate of the dead loads (self-weight and dead loads) along `mechanism`'s
/// accelerations, W per s (N·m/s²): positive for a mechanism that moves down.
pub fn load_work(assembly: &Assembly, mechanism: &Mechanism) -> f64 {
    mechanism.work(assembly.blocks.iter().enumerate().filter(|(_, b)| !b.support).map(|(i, b)| {
        let w = assembly.gravity * b.mass();
        let d = assembly.loads[i].dead;
        (crate::model::BlockId(i), [w.x + d[0], w.y + d[1], w.z + d[2], d[3], d[4], d[5]])
    }))
}
