//! How safely a design stands: the load factor λ* of its live loads — the largest multiple of
//! them that forces with no tension and friction within the model still carry on top of the
//! dead load (self-weight and dead loads) — with the collapse mechanism it ends in, and for a
//! horizontal acceleration the worst direction ([`directions`]).
//!
//! λ* is the optimum of an LP (pyramid8, box4) or SOCP (cone) on the same contact problem as
//! the statics ([`crate::statics::component_load_factor`]); the mechanism is its dual:
//! every free block's virtual translation (m) and rotation (rad, about its centroid), scaled so
//! that the live load does unit work (1 N·m), and every interface classified ([`JointState`]).
//! A design that does not stand under its dead load keeps its graded answer (the analysis) and
//! gets the mechanism of its failure, scaled so that the dead load does unit work.
//!
//! Unit-invariant: λ* is a ratio of loads; for an acceleration field it does not depend on the
//! density (mass scales both the weight and the live load).

pub mod directions;
pub mod kinematic;
mod question;
pub mod tolerance;

pub use crate::statics::{BlockMotion, InterfaceMotion, JointState, Mechanism};
pub use directions::{DirectionSettings, DirectionSweep, with_horizontal_field, worst_direction};
pub use question::{Answer, Question, answer};

use crate::interfaces::Interface;
use crate::model::Assembly;
use crate::pipeline::Analysis;
use crate::statics::{
    self, Component, FactorOutcome, SolverStatus, StaticsError, StaticsSettings, component_load_factor,
    failure_mechanism, standing_load_factor,
};
use serde::Serialize;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use thiserror::Error;

/// Why a load factor cannot be computed (bad input or settings; solver trouble is a
/// [`Safety::SolverFailed`]).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RobustnessError {
    /// No free block carries a live load, so there is nothing to multiply.
    #[error("no live load on a free block: a load factor needs a live load (a point load or an acceleration)")]
    NoLiveLoad,
    /// The statics refused the assembly or the settings.
    #[error(transparent)]
    Statics(#[from] StaticsError),
    /// A setting is out of range (the message names it).
    #[error("{0}")]
    Settings(String),
}

/// What the load factor says.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Safety {
    /// Stands under the dead load and collapses at λ* × the live load (λ* ≥ 0).
    Collapses {
        /// λ*, a multiple of the live load (for an acceleration field, in g).
        load_factor: f64,
    },
    /// Stands, and no multiple of the live load makes it collapse (the LP is unbounded).
    Unlimited,
    /// Does not stand under the dead load alone (λ = 0): the analysis's graded answer holds,
    /// and the mechanism shows how it fails. `load_factor`: the largest λ that would hold it
    /// (negative when only taking live load away would; positive when the live load itself is
    /// needed), `None` when no multiple of the live load gives an equilibrium (or there is no
    /// live load, or a failing part carries none).
    DoesNotStand {
        /// The largest λ that would hold it, as above.
        load_factor: Option<f64>,
    },
    /// A solver did not reach an answer.
    SolverFailed {
        /// How the solve ended.
        status: SolverStatus,
        /// ‖equilibrium residual‖_∞ where it stopped, N.
        residual: f64,
    },
}

/// The load factor of a design and its mechanism.
#[derive(Clone, Debug, Serialize)]
pub struct Robustness {
    /// The answer: collapses at λ*, unlimited, does not stand, or solver trouble.
    pub safety: Safety,
    /// λ* (+∞ when unlimited, NaN when the design does not stand or a solve failed).
    pub load_factor: f64,
    /// The collapse mechanism (of the component that fails first, or of every failing one).
    pub mechanism: Option<Mechanism>,
    /// How the critical solve ended: `Solved`, or `AlmostSolved` when even clarabel reached
    /// only its reduced tolerances (λ* then to ~1e-5 of itself; the text report says so).
    pub status: SolverStatus,
    /// ‖equilibrium residual‖_∞ of the critical solve, N.
    pub residual: f64,
    /// Interior-point iterations of the critical solve (both solvers' when clarabel solved it
    /// again).
    pub iterations: u32,
    /// Seconds inside the solvers, over every component.
    pub solver_seconds: f64,
}

/// The load factor of the live loads of `analysis`'s assembly (its dead loads and self-weight
/// applied), under `settings` (friction model, μ, tolerances: the analysis's own).
pub fn assess(analysis: &Analysis, settings: &StaticsSettings) -> Result<Robustness, RobustnessError> {
    assess_parts(&analysis.assembly, &analysis.interfaces, analysis.statics.stands, settings)
}

/// [`assess`] from its parts: the assembly, its interfaces and whether it stands under its dead
/// load (the analysis's verdict).
pub fn assess_parts(
    assembly: &Assembly,
    interfaces: &[Interface],
    stands: bool,
    settings: &StaticsSettings,
) -> Result<Robustness, RobustnessError> {
    assess_cached(assembly, interfaces, stands, settings, None)
}

/// Load factors kept by component content (its blocks, interfaces, dead and live loads, μ and
/// the settings), so that after an edit only the components it touched are solved again.
#[derive(Debug, Default)]
pub struct FactorCache {
    map: HashMap<u64, FactorOutcome>,
    next: HashMap<u64, FactorOutcome>,
    /// Components solved and reused by the last run.
    pub solved: usize,
    /// Components whose load factor the last run took from the cache.
    pub reused: usize,
}

fn factor_key(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    block_keys: &[u64],
    settings: &StaticsSettings,
    mu: f64,
) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!("{settings:?}").hash(&mut h);
    mu.to_bits().hash(&mut h);
    assembly.gravity.iter().for_each(|g| g.to_bits().hash(&mut h));
    let common = h.finish();
    let mut h = std::collections::hash_map::DefaultHasher::new();
    statics::component_key(assembly, interfaces, comp, block_keys, common).hash(&mut h);
    for b in &comp.blocks {
        assembly.loads[b.0].live.iter().for_each(|c| c.to_bits().hash(&mut h));
    }
    h.finish()
}

/// [`assess_parts`] with a cache of component load factors (`block_keys` from
/// [`crate::interfaces::block_keys`]).
pub fn assess_cached(
    assembly: &Assembly,
    interfaces: &[Interface],
    stands: bool,
    settings: &StaticsSettings,
    mut cache: Option<(&[u64], &mut FactorCache)>,
) -> Result<Robustness, RobustnessError> {
    settings.validate()?;
    let resolved = settings.resolved(assembly);
    let settings = &resolved;
    let mut reused = 0;
    let mu = settings.friction.unwrap_or(assembly.material.friction);
    let comps = statics::components(assembly, interfaces);
    let loaded: Vec<&Component> =
        comps.iter().filter(|c| c.blocks.iter().any(|b| assembly.loads[b.0].live.iter().any(|&v| v != 0.0))).collect();
    if !stands {
        return Ok(failure(assembly, interfaces, &comps, &loaded, mu, settings));
    }
    if loaded.is_empty() {
        return Err(RobustnessError::NoLiveLoad);
    }
    let outcomes: Vec<(&Component, FactorOutcome)> = loaded
        .iter()
        .map(|c| {
            let key = cache.as_ref().map(|(keys, _)| factor_key(assembly, interfaces, c, keys, settings, mu));
            let known = key.and_then(|k| cache.as_ref().and_then(|(_, m)| m.map.get(&k).cloned()));
            let out = match known {
                Some(out) => {
                    reused += 1;
                    out
                }
                None => standing_load_factor(assembly, interfaces, c, mu, settings),
            };
            if let (Some(k), Some((_, m))) = (key, cache.as_mut()) {
                m.next.insert(k, out.clone());
            }
            (*c, out)
        })
        .collect();
    if let Some((_, m)) = cache.as_mut() {
        m.map = std::mem::take(&mut m.next);
        m.solved = outcomes.len() - reused;
        m.reused = reused;
    }
    let iterations = outcomes.iter().map(|o| o.1.iterations).sum();
    let solver_seconds = outcomes.iter().map(|o| o.1.solver_seconds).sum();
    if let Some((_, bad)) = outcomes.iter().find(|o| !answered(o.1.status)) {
        return Ok(Robustness {
            safety: Safety::SolverFailed { status: bad.status, residual: bad.residual },
            load_factor: f64::NAN,
            mechanism: None,
            status: bad.status,
            residual: bad.residual,
            iterations,
            solver_seconds,
        });
    }
    let (comp, critical) =
        outcomes.iter().min_by(|a, b| a.1.lambda.total_cmp(&b.1.lambda)).expect("at least one loaded component");
    let lambda = critical.lambda;
    let safety = if lambda.is_infinite() { Safety::Unlimited } else { Safety::Collapses { load_factor: lambda } };
    let mechanism = (!critical.motions.is_empty()).then(|| {
        Mechanism::new(assembly, interfaces, &[(*comp, &critical.motions)]).with_uniqueness(critical.uniqueness)
    });
    Ok(Robustness {
        safety,
        load_factor: lambda,
        mechanism,
        status: critical.status,
        residual: critical.residual,
        iterations,
        solver_seconds,
    })
}

/// A status the load factor can be read from: solved, or unbounded (λ* = ∞).
fn answered(status: SolverStatus) -> bool {
    matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved | SolverStatus::Unbounded)
}

/// A design that does not stand: the mechanism of each failing supported component, and the
/// load factor that would hold it when every failing component carries live load.
fn failure(
    assembly: &Assembly,
    interfaces: &[Interface],
    comps: &[Component],
    loaded: &[&Component],
    mu: f64,
    settings: &StaticsSettings,
) -> Robustness {
    let supported = comps.iter().filter(|c| c.is_supported(assembly, interfaces));
    let outcomes: Vec<(&Component, FactorOutcome)> =
        supported.map(|c| (c, failure_mechanism(assembly, interfaces, c, mu, settings))).collect();
    let failing: Vec<(&Component, &[statics::Motion])> =
        outcomes.iter().filter(|o| !o.1.motions.is_empty()).map(|o| (o.0, o.1.motions.as_slice())).collect();
    let mechanism = (!failing.is_empty()).then(|| Mechanism::new(assembly, interfaces, &failing));
    // Unsupported components and failing ones without live load: no λ can hold them.
    let helpable = comps.iter().all(|c| {
        let fails = !c.is_supported(assembly, interfaces) || failing.iter().any(|f| std::ptr::eq(f.0, c));
        !fails || loaded.iter().any(|l| std::ptr::eq(*l, c))
    });
    let load_factor = if helpable && !loaded.is_empty() {
        let factors: Vec<FactorOutcome> =
            loaded.iter().map(|c| component_load_factor(assembly, interfaces, c, mu, settings)).collect();
        factors
            .iter()
            .map(|f| match f.status {
                SolverStatus::Solved | SolverStatus::AlmostSolved | SolverStatus::Unbounded => Some(f.lambda),
                _ => None,
            })
            .collect::<Option<Vec<f64>>>()
            .and_then(|ls| ls.into_iter().reduce(f64::min))
    } else {
        None
    };
    Robustness {
        safety: Safety::DoesNotStand { load_factor },
        load_factor: load_factor.unwrap_or(f64::NAN),
        mechanism,
        status: outcomes.iter().map(|o| o.1.status).max().unwrap_or(SolverStatus::Solved),
        residual: outcomes.iter().map(|o| o.1.residual).fold(0.0, f64::max),
        iterations: outcomes.iter().map(|o| o.1.iterations).sum(),
        solver_seconds: outcomes.iter().map(|o| o.1.solver_seconds).sum(),
    }
}
