//! Assembly sequences: the blocks placed one by one, and for every prefix (the blocks placed so
//! far plus the supports) the static analysis — and on request the drop test and the kinematic
//! check ([`StepChecks`]). The pipeline's
//! memory makes a step cost about the component the new block joins, not a cold solve, and the
//! steps of a check run on two threads. [`search`] finds an order in which every step stands,
//! or proposes temporary supports ([`search`] module docs).

mod order;
mod search;
mod steps;

pub use order::{OrderSpec, order};
pub use search::{SearchInfo, SearchSettings};

use crate::dynamics::{DropResult, DropSettings};
use crate::history::{CutCache, resolve};
use crate::model::Scene;
use crate::pipeline::{AnalysisError, AnalysisSettings};
use crate::stability::kinematic::Kinematic;
use crate::statics::KinematicSettings;
use serde::Serialize;
use steps::Stepper;
use thiserror::Error;

/// Why a sequence cannot be checked.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SequenceError {
    /// The order names a block the design does not have.
    #[error("order: '{0}' is not a block of the design")]
    Unknown(String),
    /// The order names a block twice.
    #[error("order: '{0}' is listed twice")]
    Repeated(String),
    /// The order names a support (supports are in place from the start).
    #[error("order: '{0}' is a support (supports are in place from the start)")]
    Support(String),
    /// The order leaves out a free block.
    #[error("order: the free block '{0}' is missing")]
    Missing(String),
    /// A step's blocks cannot be analysed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// A step's drop test cannot run (the message says why).
    #[error("drop test: {0}")]
    Drop(String),
    /// A step's kinematic check cannot run (the message says why).
    #[error("kinematic check: {0}")]
    Kinematic(String),
}

/// The checks run at every step besides the statics (none by default: each costs more than
/// the step's statics).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepChecks {
    /// The drop test of the blocks placed so far.
    pub dynamic: Option<DropSettings>,
    /// The kinematic check of the blocks placed so far.
    pub kinematic: Option<KinematicSettings>,
}

impl StepChecks {
    /// Whether any check besides the statics runs (each needs the step's analysis).
    pub fn any(&self) -> bool {
        self.dynamic.is_some() || self.kinematic.is_some()
    }
}

/// One step: the block placed and the verdicts of the blocks placed so far.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Step {
    /// The block placed at this step.
    pub placed: String,
    /// Whether the blocks placed so far stand (with the props in place).
    pub stands: bool,
    /// The statics' verdict on the blocks placed so far.
    pub verdict: crate::statics::Verdict,
    /// Minimum tension, a fraction of the placed blocks' weight.
    pub tension_ratio: f64,
    /// Minimum friction excess, a fraction of the placed blocks' weight.
    pub friction_excess_ratio: f64,
    /// Interfaces needing tension or more friction at this step, `a | b`.
    pub offending: Vec<String>,
    /// Blocks propped (fixed) at this step.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub props: Vec<String>,
    /// With `--dynamic`: the drop test of the blocks placed so far.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dynamic: Option<DropResult>,
    /// With `--kinematic`: the kinematic check of the blocks placed so far.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kinematic: Option<Kinematic>,
}

impl Step {
    /// A step that stands by construction, with no analysis of its own: no tension, no friction
    /// excess, nothing offending — what a standing analysis reports — and no other checks.
    fn standing(placed: &str, props: Vec<String>) -> Self {
        Self {
            placed: placed.to_string(),
            stands: true,
            verdict: crate::statics::Verdict::Stands,
            tension_ratio: 0.0,
            friction_excess_ratio: 0.0,
            offending: Vec::new(),
            props,
            dynamic: None,
            kinematic: None,
        }
    }
}

/// A block propped (treated as a support) at steps `from..until` (step indices from 0; at step
/// `until` it is released; `until` = the number of steps when it never can be).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct TemporarySupport {
    /// The propped block's name.
    pub block: String,
    /// The step at which it is propped, from 0.
    pub from: usize,
    /// The step at which it is released.
    pub until: usize,
}

impl TemporarySupport {
    fn new(block: &str, from: usize, until: usize) -> Self {
        Self { block: block.to_string(), from, until }
    }
}

/// The check of one order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SequenceReport {
    /// The order checked: the free blocks' names.
    pub order: Vec<String>,
    /// Each step's verdicts, in order.
    pub steps: Vec<Step>,
    /// Index (from 0) of the first step that does not stand (with the props, if any).
    pub first_failure: Option<usize>,
    /// Props needed so that every step stands; empty when none are.
    pub temporary_supports: Vec<TemporarySupport>,
    /// The order search's account, when the order was searched.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchInfo>,
}

impl SequenceReport {
    fn new(order: Vec<String>, steps: Vec<Step>, props: Vec<TemporarySupport>, search: Option<SearchInfo>) -> Self {
        let first_failure = steps.iter().position(|s| !s.stands);
        Self { order, steps, first_failure, temporary_supports: props, search }
    }

    /// Every step stands without props.
    pub fn stands_unpropped(&self) -> bool {
        self.first_failure.is_none() && self.temporary_supports.is_empty()
    }
}

fn resolved(scene: &Scene, settings: &AnalysisSettings) -> Result<Scene, SequenceError> {
    Ok(resolve(scene, &settings.tolerances, &mut CutCache::new()).map_err(AnalysisError::from)?.0)
}

/// The full analysis of step `k` of `report` (a report of `scene`): the blocks of
/// `report.order[..=k]` placed, that step's props fixed, with the force distribution (which
/// the checks skip). What a viewer draws for the step.
pub fn step_analysis(
    scene: &Scene,
    report: &SequenceReport,
    k: usize,
    settings: &AnalysisSettings,
) -> Result<crate::pipeline::Analysis, SequenceError> {
    let resolved = resolved(scene, settings)?;
    let k = k.min(report.order.len().saturating_sub(1));
    let placed = report.order.iter().take(k + 1).map(String::as_str).collect();
    let props = report.steps.get(k).map(|s| s.props.iter().map(String::as_str).collect()).unwrap_or_default();
    let prefix = Stepper::new(&resolved, settings).prefix(&placed, &props);
    Ok(crate::pipeline::analyze(&prefix, &steps::prefix_settings(&resolved, settings))?)
}

/// `scene` with its cut history replayed, and `spec`'s order of its free blocks.
fn resolved_order(
    scene: &Scene,
    spec: &OrderSpec,
    settings: &AnalysisSettings,
) -> Result<(Scene, Vec<String>), SequenceError> {
    let resolved = resolved(scene, settings)?;
    let order = order(&resolved, spec, settings)?;
    Ok((resolved, order))
}

/// Checks every prefix of `spec`'s order of `scene` (its cut history replayed first).
pub fn check(
    scene: &Scene,
    spec: &OrderSpec,
    settings: &AnalysisSettings,
    per_step: &StepChecks,
    tick: &(dyn Fn() + Sync),
) -> Result<SequenceReport, SequenceError> {
    let (resolved, order) = resolved_order(scene, spec, settings)?;
    let steps = steps::check_order(&resolved, &order, settings, per_step, tick)?;
    Ok(SequenceReport::new(order, steps, Vec::new(), None))
}

/// `spec`'s order with temporary supports wherever a step would not stand ([`search`] module
/// docs); `temporary_supports` is empty when the order stands as it is.
pub fn check_with_props(
    scene: &Scene,
    spec: &OrderSpec,
    settings: &AnalysisSettings,
    search: &SearchSettings,
    per_step: &StepChecks,
    tick: &(dyn Fn() + Sync),
) -> Result<SequenceReport, SequenceError> {
    let (resolved, order) = resolved_order(scene, spec, settings)?;
    let adj = order::adjacency(&resolved, settings)?;
    let mut stepper = Stepper::new(&resolved, settings);
    let (steps, props, _) = search::with_props(&mut stepper, &resolved, &adj, &order, search, per_step, tick)?;
    Ok(SequenceReport::new(order, steps, props, None))
}

/// Searches an order in which every step stands (reusing work between the checks); when there
/// is none (or the budget runs out), the longest standing prefix found followed by the other
/// blocks in the from-supports order, with temporary supports.
pub fn search(
    scene: &Scene,
    settings: &AnalysisSettings,
    search: &SearchSettings,
    per_step: &StepChecks,
    tick: &(dyn Fn() + Sync),
) -> Result<SequenceReport, SequenceError> {
    let resolved = resolved(scene, settings)?;
    // One detection of the complete design serves the ranking, the search and the props.
    let adj = order::adjacency(&resolved, settings)?;
    let ranked = order::from_supports(&resolved, &adj);
    let mut stepper = Stepper::new(&resolved, settings);
    let (mut order, mut info) = search::search_order(&mut stepper, &resolved, &adj, &ranked, search, tick)?;
    if !info.found {
        let placed: std::collections::HashSet<String> = order.iter().cloned().collect();
        order.extend(ranked.into_iter().filter(|n| !placed.contains(n)));
    }
    let (steps, props, local) = search::with_props(&mut stepper, &resolved, &adj, &order, search, per_step, tick)?;
    info.checks = stepper.checks;
    info.local_checks += local;
    Ok(SequenceReport::new(order, steps, props, Some(info)))
}
