//! Decomposition: a design is source shapes plus an ordered history of cuts; replaying the
//! history gives the blocks. Piece names derive from the history, so results, supports and
//! assembly orders keep pointing at the right block after an edit: cutting `body` with cut 3
//! gives `body.3-` and `body.3+` (the negative and positive side of the plane), and when a
//! side falls apart, `body.3-0`, `body.3-1`, … in a deterministic order.
//!
//! Replays are deterministic. A [`CutCache`] keyed by content (piece geometry + plane) makes a
//! replay after an edit recompute only what the edit touches: the pieces downstream of the
//! edited cut.
//!
//! Plane convention: a cut `{point, normal}` keeps `normal · (x − point) < 0` on the `-` side.
//! Supports are never cut unless a cut names them as its target.

use crate::geometry::cut::{SplitResult, split};
use crate::geometry::{MassProperties, Mesh, Plane, Vector3};
use crate::model::{Block, Cut, Scene};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use thiserror::Error;

/// Why a history cannot be replayed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CutError {
    #[error("cut {index}: the normal {normal:?} is not a finite non-zero vector")]
    BadNormal { index: usize, normal: [f64; 3] },
    #[error("cut {index}: the point {point:?} is not finite")]
    BadPoint { index: usize, point: [f64; 3] },
    #[error("cut {index} targets '{target}', which is not a piece at that step of the history")]
    UnknownTarget { index: usize, target: String },
    #[error("source shape '{block}' cannot be cut: {source}")]
    Source {
        block: String,
        #[source]
        source: crate::geometry::MeshError,
    },
    #[error(
        "cut {index} cuts a sliver of {fraction:e} of the volume of '{piece}': move the plane \
         (slivers make unstable blocks and ill-conditioned statics)"
    )]
    Sliver { index: usize, piece: String, fraction: f64 },
}

/// What a replay computed and what it reused.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReplayStats {
    /// Plane splits computed.
    pub splits: usize,
    /// Plane splits taken from the cache.
    pub cached: usize,
}

/// Split results keyed by (piece geometry, plane, tolerance) content.
#[derive(Debug, Default)]
pub struct CutCache {
    map: HashMap<u64, SplitResult>,
}

impl CutCache {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn len(&self) -> usize {
        self.map.len()
    }

    pub fn is_empty(&self) -> bool {
        self.map.is_empty()
    }
}

/// Content hash of a source shape. SipHash with fixed keys: the same content gives the same
/// key in every run.
fn mesh_key(mesh: &Mesh) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for p in &mesh.vertices {
        p.iter().for_each(|c| c.to_bits().hash(&mut h));
    }
    mesh.faces.hash(&mut h);
    h.finish()
}

/// Key of splitting the piece with key `piece` by `plane`. A piece made by a split is keyed by
/// its derivation (parent key, plane, side, index) — equivalent to its content, since splits
/// are deterministic — so a replay hashes each source mesh once, not every piece at every cut.
fn split_key(piece: u64, plane: &Plane, eps: f64) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    piece.hash(&mut h);
    plane.normal.iter().for_each(|c| c.to_bits().hash(&mut h));
    plane.offset.to_bits().hash(&mut h);
    eps.to_bits().hash(&mut h);
    h.finish()
}

fn child_key(split: u64, side: char, index: usize) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    (split, side, index).hash(&mut h);
    h.finish()
}

/// Pieces below this fraction of the volume of the piece they were cut from are slivers.
pub const SLIVER_FRACTION: f64 = 1e-6;

/// Replays `cuts` on `sources`; `eps` is the distance under which a vertex is on a plane.
pub fn replay(
    sources: &[Block],
    cuts: &[Cut],
    eps: f64,
    cache: &mut CutCache,
) -> Result<(Vec<Block>, ReplayStats), CutError> {
    let mut pieces: Vec<(Block, u64)> = sources.iter().map(|b| (b.clone(), mesh_key(&b.mesh))).collect();
    let mut stats = ReplayStats::default();
    for (index, cut) in cuts.iter().enumerate() {
        let n = Vector3::from(cut.normal);
        if !(n.iter().all(|c| c.is_finite()) && n.norm() > 0.0) {
            return Err(CutError::BadNormal { index, normal: cut.normal });
        }
        if !cut.point.iter().all(|c| c.is_finite()) {
            return Err(CutError::BadPoint { index, point: cut.point });
        }
        if let Some(t) = &cut.target
            && !pieces.iter().any(|(p, _)| &p.name == t)
        {
            return Err(CutError::UnknownTarget { index, target: t.clone() });
        }
        let plane = cut.plane();
        let mut next = Vec::with_capacity(pieces.len() + 2);
        for (piece, piece_key) in pieces {
            let targeted = cut.target.as_ref().is_some_and(|t| *t == piece.name);
            // Untargeted cuts skip supports; targeted cuts skip everything else.
            if !targeted && (cut.target.is_some() || piece.support) {
                next.push((piece, piece_key));
                continue;
            }
            let key = split_key(piece_key, &plane, eps);
            let result = match cache.map.get(&key) {
                Some(r) => {
                    stats.cached += 1;
                    r.clone()
                }
                None => {
                    stats.splits += 1;
                    let r = split(&piece.mesh, &plane, eps);
                    cache.map.insert(key, r.clone());
                    r
                }
            };
            match result {
                SplitResult::Negative | SplitResult::Positive => next.push((piece, piece_key)),
                SplitResult::Pair { negative, positive } => {
                    let whole = MassProperties::of_mesh(&piece.mesh).volume;
                    for (sign, side) in [('-', negative), ('+', positive)] {
                        let several = side.len() > 1;
                        for (j, mesh) in side.into_iter().enumerate() {
                            let fraction = MassProperties::of_mesh(&mesh).volume / whole;
                            if fraction < SLIVER_FRACTION {
                                return Err(CutError::Sliver { index, piece: piece.name.clone(), fraction });
                            }
                            let name = if several {
                                format!("{}.{index}{sign}{j}", piece.name)
                            } else {
                                format!("{}.{index}{sign}", piece.name)
                            };
                            let block = Block { name, mesh, support: piece.support, density: piece.density };
                            next.push((block, child_key(key, sign, j)));
                        }
                    }
                }
            }
        }
        pieces = next;
    }
    Ok((pieces.into_iter().map(|(b, _)| b).collect(), stats))
}

/// The scene's blocks after its cut history (the scene itself when it has no cuts). The source
/// shapes are validated and repaired first (the cutter needs closed, outward, planar meshes);
/// a vertex within `tolerances.weld` (relative to the model size) of a plane is on it.
pub fn resolve(
    scene: &Scene,
    tolerances: &crate::geometry::Tolerances,
    cache: &mut CutCache,
) -> Result<(Scene, ReplayStats), CutError> {
    if scene.cuts.is_empty() {
        return Ok((scene.clone(), ReplayStats::default()));
    }
    let tol = tolerances.resolve(scene.scale());
    let mut sources = scene.blocks.clone();
    for b in &mut sources {
        b.mesh = crate::geometry::repair(&b.mesh, &tol)
            .map_err(|source| CutError::Source { block: b.name.clone(), source })?
            .mesh;
    }
    let (blocks, stats) = replay(&sources, &scene.cuts, tol.weld, cache)?;
    let mut out = scene.clone();
    out.blocks = blocks;
    out.cuts.clear();
    Ok((out, stats))
}
