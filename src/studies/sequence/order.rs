//! Orders: bottom-up by height, by graph distance from the supports, or given by name (a source
//! shape's name stands for all its pieces, bottom-up).

use super::SequenceError;
use crate::interfaces::Body;
use crate::model::{Assembly, Block, BlockId, Scene};
use crate::pipeline::{AnalysisError, AnalysisSettings};
use std::collections::{HashMap, HashSet, VecDeque};

/// Which order to place the free blocks in.
#[derive(Clone, Debug, PartialEq)]
pub enum OrderSpec {
    /// By the height of the lowest point, then of the centroid, then by name.
    BottomUp,
    /// By the number of interfaces between the block and a support or the ground (graph
    /// distance), then bottom-up.
    FromSupports,
    /// These names, each free block exactly once. A name that is not a piece but the source
    /// shape of pieces (`D` for `D.0+`, `D.0-`, …) stands for all its pieces, bottom-up.
    Given(Vec<String>),
}

/// The free blocks' adjacency in the complete design (by index into the resolved scene's
/// blocks): neighbours over interfaces, and whether the block touches a fixed body.
#[derive(Clone, Debug)]
pub(crate) struct Adjacency {
    pub neighbours: Vec<Vec<usize>>,
    pub grounded: Vec<bool>,
    /// The complete design's free weight, N: at least that of any prefix.
    pub free_weight: f64,
    /// Each block's index by name ([`index`]).
    pub index: HashMap<String, BlockId>,
}

pub(crate) fn adjacency(resolved: &Scene, settings: &AnalysisSettings) -> Result<Adjacency, SequenceError> {
    let asm = Assembly::new(resolved, &settings.tolerances).map_err(AnalysisError::from)?;
    let n = asm.blocks.len();
    let mut adj = Adjacency {
        neighbours: vec![Vec::new(); n],
        grounded: vec![false; n],
        free_weight: asm.free_weight(),
        index: index(resolved),
    };
    for i in crate::interfaces::detect(&asm) {
        let free = |b: Body| b.block().filter(|&b| !asm.block(b).support);
        match (free(i.a), free(i.b)) {
            (Some(a), Some(b)) => {
                adj.neighbours[a.0].push(b.0);
                adj.neighbours[b.0].push(a.0);
            }
            (Some(a), None) | (None, Some(a)) => adj.grounded[a.0] = true,
            (None, None) => {}
        }
    }
    for list in &mut adj.neighbours {
        list.sort_unstable();
        list.dedup();
    }
    Ok(adj)
}

/// Graph distance of every block from the fixed bodies (`usize::MAX` when it reaches none).
fn distances(adj: &Adjacency) -> Vec<usize> {
    let mut dist = vec![usize::MAX; adj.grounded.len()];
    let mut queue = VecDeque::new();
    for (k, &g) in adj.grounded.iter().enumerate() {
        if g {
            dist[k] = 1;
            queue.push_back(k);
        }
    }
    while let Some(k) = queue.pop_front() {
        for &m in &adj.neighbours[k] {
            if dist[m] == usize::MAX {
                dist[m] = dist[k] + 1;
                queue.push_back(m);
            }
        }
    }
    dist
}

fn bottom_up<'a>(blocks: impl Iterator<Item = &'a Block>) -> Vec<String> {
    let mut keyed: Vec<(f64, f64, &str)> = blocks
        .map(|b| {
            let a = b.mesh.aabb();
            (a.min.z, a.center().z, b.name.as_str())
        })
        .collect();
    keyed.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)).then(x.2.cmp(y.2)));
    keyed.into_iter().map(|k| k.2.to_string()).collect()
}

/// The pieces a name stands for: the piece of that name, or the pieces derived from the source
/// shape of that name (`name.` followed by the cut history).
fn expand<'a>(resolved: &'a Scene, name: &str) -> Vec<&'a Block> {
    if let Some(b) = resolved.blocks.iter().find(|b| b.name == name) {
        return vec![b];
    }
    let prefix = format!("{name}.");
    resolved.blocks.iter().filter(|b| b.name.starts_with(&prefix)).collect()
}

/// The free blocks by graph distance from the fixed bodies over `adj`, then bottom-up.
pub(crate) fn from_supports(resolved: &Scene, adj: &Adjacency) -> Vec<String> {
    let dist = distances(adj);
    let index = index(resolved);
    let mut keyed: Vec<(usize, usize, String)> = bottom_up(resolved.blocks.iter().filter(|b| !b.support))
        .into_iter()
        .enumerate()
        .map(|(k, name)| (dist[index[&name].0], k, name))
        .collect();
    keyed.sort();
    keyed.into_iter().map(|k| k.2).collect()
}

/// The free blocks of the resolved design in the order asked for.
pub fn order(resolved: &Scene, spec: &OrderSpec, settings: &AnalysisSettings) -> Result<Vec<String>, SequenceError> {
    let free = || resolved.blocks.iter().filter(|b| !b.support);
    match spec {
        OrderSpec::BottomUp => Ok(bottom_up(free())),
        OrderSpec::FromSupports => Ok(from_supports(resolved, &adjacency(resolved, settings)?)),
        OrderSpec::Given(names) => {
            let mut seen = HashSet::new();
            let mut out = Vec::new();
            for n in names {
                let pieces = expand(resolved, n);
                if pieces.is_empty() {
                    return Err(SequenceError::Unknown(n.clone()));
                }
                if pieces.iter().all(|b| b.support) {
                    return Err(SequenceError::Support(n.clone()));
                }
                for name in bottom_up(pieces.into_iter().filter(|b| !b.support)) {
                    if !seen.insert(name.clone()) {
                        return Err(SequenceError::Repeated(name));
                    }
                    out.push(name);
                }
            }
            if let Some(m) = free().find(|b| !seen.contains(&b.name)) {
                return Err(SequenceError::Missing(m.name.clone()));
            }
            Ok(out)
        }
    }
}

/// Index of every block of `resolved` by name.
pub(crate) fn index(resolved: &Scene) -> HashMap<String, BlockId> {
    resolved.blocks.iter().enumerate().map(|(k, b)| (b.name.clone(), BlockId(k))).collect()
}
