//! Assembly sequences: the blocks placed one by one, and for every prefix (the blocks placed so
//! far plus the supports) the static analysis — and on request the drop test. The pipeline's
//! memory makes a step cost about the component the new block joins, not a cold solve.

use crate::analysis::{AnalysisError, AnalysisSettings, Pipeline};
use crate::decompose::{CutCache, resolve};
use crate::dynamics::{DropResult, DropSettings, drop_test};
use crate::model::Scene;
use serde::Serialize;
use std::collections::HashSet;
use thiserror::Error;

/// Which order to place the free blocks in.
#[derive(Clone, Debug, PartialEq)]
pub enum OrderSpec {
    /// By the height of the lowest point, then of the centroid, then by name.
    BottomUp,
    /// These block names, each free block exactly once.
    Given(Vec<String>),
}

/// Why a sequence cannot be checked.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SequenceError {
    #[error("order: '{0}' is not a block of the design")]
    Unknown(String),
    #[error("order: '{0}' is listed twice")]
    Repeated(String),
    #[error("order: '{0}' is a support (supports are in place from the start)")]
    Support(String),
    #[error("order: the free block '{0}' is missing")]
    Missing(String),
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    #[error("drop test: {0}")]
    Drop(String),
}

/// One step: the block placed and the verdicts of the blocks placed so far.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Step {
    pub placed: String,
    pub stands: bool,
    pub verdict: crate::statics::Verdict,
    pub tension_ratio: f64,
    pub friction_excess_ratio: f64,
    /// Interfaces needing tension or more friction at this step, `a | b`.
    pub offending: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dynamic: Option<DropResult>,
}

/// The check of one order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SequenceReport {
    pub order: Vec<String>,
    pub steps: Vec<Step>,
    /// Index (from 0) of the first step that does not stand.
    pub first_failure: Option<usize>,
    /// Blocks to prop and the step until which (exclusive) they are props; empty here (the
    /// order search fills it).
    pub temporary_supports: Vec<(String, usize)>,
}

/// The free blocks of the resolved design in the order asked for.
pub fn order(resolved: &Scene, spec: &OrderSpec) -> Result<Vec<String>, SequenceError> {
    let free: Vec<&crate::model::Block> = resolved.blocks.iter().filter(|b| !b.support).collect();
    match spec {
        OrderSpec::BottomUp => {
            let mut keyed: Vec<(f64, f64, &str)> = free
                .iter()
                .map(|b| {
                    let a = b.mesh.aabb();
                    (a.min.z, a.center().z, b.name.as_str())
                })
                .collect();
            keyed.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)).then(x.2.cmp(y.2)));
            Ok(keyed.into_iter().map(|k| k.2.to_string()).collect())
        }
        OrderSpec::Given(names) => {
            let mut seen = HashSet::new();
            for n in names {
                let Some(b) = resolved.blocks.iter().find(|b| &b.name == n) else {
                    return Err(SequenceError::Unknown(n.clone()));
                };
                if b.support {
                    return Err(SequenceError::Support(n.clone()));
                }
                if !seen.insert(n.as_str()) {
                    return Err(SequenceError::Repeated(n.clone()));
                }
            }
            if let Some(m) = free.iter().find(|b| !seen.contains(b.name.as_str())) {
                return Err(SequenceError::Missing(m.name.clone()));
            }
            Ok(names.clone())
        }
    }
}

/// Checks every prefix of `spec`'s order of `scene` (its cut history replayed first).
pub fn check(
    scene: &Scene,
    spec: &OrderSpec,
    settings: &AnalysisSettings,
    dynamic: Option<&DropSettings>,
    tick: &mut dyn FnMut(),
) -> Result<SequenceReport, SequenceError> {
    let (resolved, _) = resolve(scene, &settings.tolerances, &mut CutCache::new()).map_err(AnalysisError::from)?;
    let order = order(&resolved, spec)?;
    let mut pipeline = Pipeline::new();
    let mut placed: HashSet<&str> = HashSet::new();
    let mut steps = Vec::with_capacity(order.len());
    for name in &order {
        placed.insert(name);
        let mut prefix = resolved.clone();
        prefix.blocks.retain(|b| b.support || placed.contains(b.name.as_str()));
        let a = pipeline.run(&prefix, settings)?;
        let s = &a.statics;
        let offending = s
            .interfaces
            .iter()
            .filter(|r| r.tension > 1e-6 * s.free_weight || r.friction_excess > 1e-6 * s.free_weight)
            .map(|r| format!("{} | {}", r.a, r.b))
            .collect();
        let dynamic = match dynamic {
            Some(ds) => Some(drop_test(&a.assembly, ds).map_err(|e| SequenceError::Drop(e.to_string()))?),
            None => None,
        };
        steps.push(Step {
            placed: name.clone(),
            stands: s.stands,
            verdict: s.verdict,
            tension_ratio: s.tension_ratio,
            friction_excess_ratio: s.friction_excess_ratio,
            offending,
            dynamic,
        });
        tick();
    }
    let first_failure = steps.iter().position(|s| !s.stands);
    Ok(SequenceReport { order, steps, first_failure, temporary_supports: Vec::new() })
}
