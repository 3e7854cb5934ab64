//! Detection that remembers: interfaces of a block pair (or a block and the ground) are kept
//! by the pair's content — both meshes, their support flags and the resolved tolerances — so
//! after an edit only the pairs with a changed block are detected again.

use super::{Body, Interface, broad, detect_ground, detect_pair};
use crate::model::{Assembly, BlockId};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};

/// Interfaces by pair key, with the blocks written as `Block(0)` (a) and `Block(1)` (b).
#[derive(Debug, Default)]
pub struct DetectCache {
    map: HashMap<u64, Vec<Interface>>,
}

/// What a cached detection computed and what it reused (block pairs, ground pairs included).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DetectStats {
    /// Block pairs whose interfaces were detected in this run.
    pub detected: usize,
    /// Block pairs whose interfaces came from the cache unchanged.
    pub reused: usize,
}

fn hasher() -> std::collections::hash_map::DefaultHasher {
    std::collections::hash_map::DefaultHasher::new()
}

/// Content key of each validated block: its mesh and support flag (SipHash with fixed keys:
/// the same content gives the same key in every run).
pub fn block_keys(assembly: &Assembly) -> Vec<u64> {
    assembly
        .blocks
        .iter()
        .map(|b| {
            let mut h = hasher();
            (b.mesh.content_key(), b.support).hash(&mut h);
            h.finish()
        })
        .collect()
}

fn remap(found: &[Interface], a: Body, b: Body) -> impl Iterator<Item = Interface> + '_ {
    let map = move |body: Body| match body {
        Body::Block(BlockId(0)) => a,
        Body::Block(_) => b,
        Body::Ground => Body::Ground,
    };
    found.iter().map(move |i| Interface { a: map(i.a), b: map(i.b), ..i.clone() })
}

/// [`super::detect`] with a cache; the same interfaces in the same order. The cache keeps only
/// the pairs of this assembly afterwards.
pub fn detect_cached(assembly: &Assembly, keys: &[u64], cache: &mut DetectCache) -> (Vec<Interface>, DetectStats) {
    let tol_key = {
        let mut h = hasher();
        format!("{:?}", assembly.tolerances).hash(&mut h);
        h.finish()
    };
    let mut next = HashMap::new();
    let mut stats = DetectStats::default();
    let mut out = Vec::new();
    let mut lookup = |key: u64, a: Body, b: Body, compute: &dyn Fn(&mut Vec<Interface>)| {
        let found = match cache.map.remove(&key).or_else(|| next.remove(&key)) {
            Some(found) => {
                stats.reused += 1;
                found
            }
            None => {
                stats.detected += 1;
                let mut found = Vec::new();
                compute(&mut found);
                // Canonical form: a → Block(0), b → Block(1).
                let canon = |body: Body| match body {
                    Body::Ground => Body::Ground,
                    x if x == a => Body::Block(BlockId(0)),
                    _ => Body::Block(BlockId(1)),
                };
                found.into_iter().map(|i| Interface { a: canon(i.a), b: canon(i.b), ..i }).collect()
            }
        };
        out.extend(remap(&found, a, b));
        next.insert(key, found);
    };
    for (i, j) in broad::candidate_pairs(assembly) {
        let mut h = hasher();
        (keys[i], keys[j], tol_key).hash(&mut h);
        let (a, b) = (Body::Block(BlockId(i)), Body::Block(BlockId(j)));
        lookup(h.finish(), a, b, &|v| detect_pair(assembly, BlockId(i), BlockId(j), v));
    }
    if assembly.ground {
        for (i, key) in keys.iter().enumerate() {
            let mut h = hasher();
            (key, "ground", tol_key).hash(&mut h);
            lookup(h.finish(), Body::Block(BlockId(i)), Body::Ground, &|v| detect_ground(assembly, BlockId(i), v));
        }
    }
    cache.map = next;
    (out, stats)
}
