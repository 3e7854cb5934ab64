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
    /// By the number of interfaces between the block and a support or the ground (graph
    /// distance), then bottom-up.
    FromSupports,
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

/// Graph distance of every free block (by name) from the fixed bodies over the interfaces of
/// the complete design; blocks that reach none get `usize::MAX`.
fn distances(
    resolved: &Scene,
    settings: &AnalysisSettings,
) -> Result<std::collections::HashMap<String, usize>, SequenceError> {
    use crate::interfaces::Body;
    let asm = crate::model::Assembly::new(resolved, &settings.tolerances).map_err(AnalysisError::from)?;
    let ifs = crate::interfaces::detect(&asm);
    let n = asm.blocks.len();
    let mut dist = vec![usize::MAX; n];
    let mut queue = std::collections::VecDeque::new();
    let fixed = |body: Body| body.is_fixed(&asm);
    for i in &ifs {
        for (x, y) in [(i.a, i.b), (i.b, i.a)] {
            if let (true, Body::Block(b)) = (fixed(x), y)
                && !asm.block(b).support
                && dist[b.0] == usize::MAX
            {
                dist[b.0] = 1;
                queue.push_back(b.0);
            }
        }
    }
    while let Some(k) = queue.pop_front() {
        for i in ifs.iter().filter(|i| i.touches(crate::model::BlockId(k))) {
            let other = if i.a == Body::Block(crate::model::BlockId(k)) { i.b } else { i.a };
            if let Body::Block(b) = other
                && !asm.block(b).support
                && dist[b.0] == usize::MAX
            {
                dist[b.0] = dist[k] + 1;
                queue.push_back(b.0);
            }
        }
    }
    Ok(asm.blocks.iter().zip(dist).map(|(b, d)| (b.name.clone(), d)).collect())
}

/// The free blocks of the resolved design in the order asked for.
pub fn order(resolved: &Scene, spec: &OrderSpec, settings: &AnalysisSettings) -> Result<Vec<String>, SequenceError> {
    let free: Vec<&crate::model::Block> = resolved.blocks.iter().filter(|b| !b.support).collect();
    match spec {
        OrderSpec::FromSupports => {
            let d = distances(resolved, settings)?;
            let bottom_up = order(resolved, &OrderSpec::BottomUp, settings)?;
            let mut keyed: Vec<(usize, usize, String)> =
                bottom_up.into_iter().enumerate().map(|(k, name)| (d[&name], k, name)).collect();
            keyed.sort();
            Ok(keyed.into_iter().map(|k| k.2).collect())
        }
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
    let order = order(&resolved, spec, settings)?;
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
