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
//! A pattern cut (apex + segments) is a sequence of such planes, one per segment through the
//! apex, each cutting only the pieces that the cone from the apex through its segment meets;
//! its pieces are named with the segment too: `body.3/0-`, `body.3/0+.3/1-`, ….
//! Supports are never cut unless a cut names them as its target.

use crate::geometry::cut::{SplitResult, split};
use crate::geometry::polygon::signed_area_2d;
use crate::geometry::{MassProperties, Mesh, Plane, Point3, Vector3};
use crate::model::cut::plane_of;
use crate::model::{Block, Cut, CutShape, Scene};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use thiserror::Error;

/// Why a history cannot be replayed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CutError {
    /// A plane cut's normal is zero, infinite or NaN.
    #[error("cut {index}: the normal {normal:?} is not a finite non-zero vector")]
    BadNormal {
        /// The cut's position in the history, from 0.
        index: usize,
        /// The normal as given.
        normal: [f64; 3],
    },
    /// A plane cut's point (or a pattern cut's apex) is not finite.
    #[error("cut {index}: the point {point:?} is not finite")]
    BadPoint {
        /// The cut's position in the history, from 0.
        index: usize,
        /// The point as given.
        point: [f64; 3],
    },
    /// The scene's `removed` names a piece the history does not make.
    #[error("'{name}' is listed as removed but is not a piece of the design")]
    UnknownRemoved {
        /// The piece name as listed.
        name: String,
    },
    /// The scene's `supports` names a piece the history does not make.
    #[error("'{name}' is listed as a support but is not a piece of the design")]
    UnknownSupport {
        /// The piece name as listed.
        name: String,
    },
    /// The scene's `densities` names a piece the history does not make.
    #[error("'{name}' is given a density but is not a piece of the design")]
    UnknownDensity {
        /// The piece name as listed.
        name: String,
    },
    /// A pattern cut's segment cannot make a plane with the apex (degenerate, through it).
    #[error("cut {index}, segment {segment}: {why}")]
    BadSegment {
        /// The cut's position in the history, from 0.
        index: usize,
        /// The segment's position in the cut, from 0.
        segment: usize,
        /// What is wrong with it, in words.
        why: String,
    },
    /// A cut's `target` is no piece at that step of the history.
    #[error("cut {index} targets '{target}', which is not a piece at that step of the history")]
    UnknownTarget {
        /// The cut's position in the history, from 0.
        index: usize,
        /// The target name as given.
        target: String,
    },
    /// A source shape's mesh is not a closed solid that can be cut.
    #[error("source shape '{block}' cannot be cut: {source}")]
    Source {
        /// The source shape's name.
        block: String,
        /// What is wrong with its mesh.
        #[source]
        source: crate::geometry::MeshError,
    },
    /// The sources' coordinates, extent or tolerances cannot be used (checked before any cut).
    #[error("the source shapes: {0}")]
    Model(#[from] crate::model::ModelError),
    /// A cut leaves a piece too thin to analyse: move the plane.
    #[error(
        "cut {index} cuts a sliver of {fraction:e} of the volume of '{piece}': move the plane \
         (slivers make unstable blocks and ill-conditioned statics)"
    )]
    Sliver {
        /// The cut's position in the history, from 0.
        index: usize,
        /// The name of the piece it would make.
        piece: String,
        /// The piece's volume over the volume of the piece it was cut from.
        fraction: f64,
    },
}

/// What a replay computed and what it reused.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReplayStats {
    /// Plane splits computed.
    pub splits: usize,
    /// Plane splits taken from the cache.
    pub cached: usize,
}

/// Split results keyed by (piece geometry, plane, tolerance) content, and the source shapes'
/// repairs by content.
#[derive(Debug, Default)]
pub struct CutCache {
    map: HashMap<u64, SplitResult>,
    repairs: crate::geometry::RepairCache,
}

impl CutCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// The number of plane splits kept.
    pub fn len(&self) -> usize {
        self.map.len()
    }

    /// Whether no plane split is kept.
    pub fn is_empty(&self) -> bool {
        self.map.is_empty()
    }
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

/// One plane of a cut: a plane cut has one, a pattern cut one per segment.
struct Blade {
    plane: Plane,
    /// For a pattern segment: the cone from the apex through the segment; only pieces whose
    /// section meets it are cut.
    wedge: Option<Wedge>,
    /// Appended to the cut index in piece names: "" for a plane, "/j" for segment j.
    label: String,
}

struct Wedge {
    apex: Point3,
    p: Point3,
    q: Point3,
}

/// The blades of cut `index`, or why it is malformed.
fn blades(index: usize, cut: &Cut) -> Result<Vec<Blade>, CutError> {
    let finite = |v: &[f64; 3]| v.iter().all(|c| c.is_finite());
    match &cut.shape {
        CutShape::Plane { point, normal } => {
            let n = Vector3::from(*normal);
            if !(finite(normal) && n.norm() > 0.0) {
                return Err(CutError::BadNormal { index, normal: *normal });
            }
            if !finite(point) {
                return Err(CutError::BadPoint { index, point: *point });
            }
            Ok(vec![Blade { plane: plane_of(*point, *normal), wedge: None, label: String::new() }])
        }
        CutShape::Pattern { apex, segments } => {
            if !finite(apex) {
                return Err(CutError::BadPoint { index, point: *apex });
            }
            if segments.is_empty() {
                return Err(CutError::BadSegment { index, segment: 0, why: "the pattern has no segments".into() });
            }
            let a = Point3::from(*apex);
            segments
                .iter()
                .enumerate()
                .map(|(j, [p, q])| {
                    let bad = |why: &str| CutError::BadSegment { index, segment: j, why: why.into() };
                    if !finite(p) || !finite(q) {
                        return Err(bad("an end point is not finite"));
                    }
                    let (p, q) = (Point3::from(*p), Point3::from(*q));
                    let normal = (p - a).cross(&(q - a));
                    let size = (p - a).norm().max((q - a).norm());
                    if (q - p).norm() <= 1e-12 * size || normal.norm() <= 1e-9 * size * size {
                        return Err(bad("its end points and the apex do not span a plane"));
                    }
                    let plane = Plane::from_point_normal(&a, &normal);
                    Ok(Blade { plane, wedge: Some(Wedge { apex: a, p, q }), label: format!("/{j}") })
                })
                .collect()
        }
    }
}

/// Whether the section of a split piece (the caps of its negative side) meets the wedge with
/// a positive area. A section that only touches the wedge along its boundary (a segment
/// ending on an earlier one) does not count.
fn meets_wedge(negative: &[Mesh], plane: &Plane, wedge: &Wedge, eps: f64) -> bool {
    let frame = crate::geometry::polygon::Frame::from_normal(wedge.apex, plane.normal);
    let reach = negative.iter().flat_map(|m| m.vertices.iter()).map(|v| (v - wedge.apex).norm()).fold(0.0, f64::max);
    // The triangle apex, apex + s(p − apex), apex + s(q − apex) covers the cone out to 4×reach.
    let (dp, dq) = (wedge.p - wedge.apex, wedge.q - wedge.apex);
    let height = dp.cross(&dq).norm() / (wedge.q - wedge.p).norm();
    let s = 4.0 * reach / height;
    let tri = [frame.to_2d(&wedge.apex), frame.to_2d(&(wedge.apex + s * dp)), frame.to_2d(&(wedge.apex + s * dq))];
    let (mut cap_area, mut inside) = (0.0, 0.0);
    for mesh in negative {
        for face in &mesh.faces {
            let pts: Vec<Point3> = face.iter().map(|&i| mesh.vertices[i]).collect();
            let on_plane = pts.iter().all(|p| plane.distance(p).abs() <= 2.0 * eps);
            if !on_plane || crate::geometry::polygon::area_vector(&pts).dot(&plane.normal) <= 0.0 {
                continue;
            }
            let ring: Vec<[f64; 2]> = pts.iter().map(|p| frame.to_2d(p)).collect();
            cap_area += signed_area_2d(&ring).abs();
            inside += crate::geometry::overlap::intersect(&ring, &tri)
                .iter()
                .flatten()
                .map(|r| signed_area_2d(r))
                .sum::<f64>();
        }
    }
    inside > 1e-6 * cap_area
}

/// Replays `cuts` on `sources`; `eps` is the distance under which a vertex is on a plane.
pub fn replay(
    sources: &[Block],
    cuts: &[Cut],
    eps: f64,
    cache: &mut CutCache,
) -> Result<(Vec<Block>, ReplayStats), CutError> {
    // (block, content key, in the target's scope for the current cut)
    let mut pieces: Vec<(Block, u64, bool)> =
        sources.iter().map(|b| (b.clone(), b.mesh.content_key(), false)).collect();
    let mut stats = ReplayStats::default();
    for (index, cut) in cuts.iter().enumerate() {
        let blades = blades(index, cut)?;
        if let Some(t) = &cut.target
            && !pieces.iter().any(|(p, _, _)| &p.name == t)
        {
            return Err(CutError::UnknownTarget { index, target: t.clone() });
        }
        for (_, _, scope) in pieces.iter_mut() {
            *scope = false;
        }
        for blade in &blades {
            let mut next = Vec::with_capacity(pieces.len() + 2);
            for (piece, piece_key, scope) in pieces {
                let in_scope = scope || cut.target.as_ref().is_some_and(|t| *t == piece.name);
                // Untargeted cuts skip supports; targeted cuts skip everything else.
                if !in_scope && (cut.target.is_some() || piece.support) {
                    next.push((piece, piece_key, false));
                    continue;
                }
                let key = split_key(piece_key, &blade.plane, eps);
                let result = match cache.map.get(&key) {
                    Some(r) => {
                        stats.cached += 1;
                        r.clone()
                    }
                    None => {
                        stats.splits += 1;
                        let r = split(&piece.mesh, &blade.plane, eps);
                        cache.map.insert(key, r.clone());
                        r
                    }
                };
                let (negative, positive) = match result {
                    SplitResult::Pair { negative, positive }
                        if blade.wedge.as_ref().is_none_or(|w| meets_wedge(&negative, &blade.plane, w, eps)) =>
                    {
                        (negative, positive)
                    }
                    _ => {
                        next.push((piece, piece_key, in_scope));
                        continue;
                    }
                };
                let whole = MassProperties::of_mesh(&piece.mesh).volume;
                for (sign, side) in [('-', negative), ('+', positive)] {
                    let several = side.len() > 1;
                    for (j, mesh) in side.into_iter().enumerate() {
                        let fraction = MassProperties::of_mesh(&mesh).volume / whole;
                        if fraction < SLIVER_FRACTION {
                            return Err(CutError::Sliver { index, piece: piece.name.clone(), fraction });
                        }
                        let suffix = if several { j.to_string() } else { String::new() };
                        let name = format!("{}.{index}{}{sign}{suffix}", piece.name, blade.label);
                        let block = Block { name, mesh, support: piece.support, density: piece.density.clone() };
                        next.push((block, child_key(key, sign, j), in_scope));
                    }
                }
            }
            pieces = next;
        }
    }
    Ok((pieces.into_iter().map(|(b, _, _)| b).collect(), stats))
}

/// Whether piece `name` comes from cut `index` of the history (the naming above: `body.3-`,
/// `body.3+1`, `body.3/0-`).
pub fn made_by(name: &str, index: usize) -> bool {
    let tag = format!(".{index}");
    name.match_indices(&tag).any(|(at, _)| matches!(name[at + tag.len()..].chars().next(), Some('-' | '+' | '/')))
}

/// The scene's blocks after its cut history (the scene itself when it has no cuts). The source
/// shapes are validated and repaired first (the cutter needs closed, outward, planar meshes);
/// a vertex within `tolerances.weld` (relative to the model size) of a plane is on it.
pub fn resolve(
    scene: &Scene,
    tolerances: &crate::geometry::Tolerances,
    cache: &mut CutCache,
) -> Result<(Scene, ReplayStats), CutError> {
    if scene.cuts.is_empty() && scene.removed.is_empty() && scene.supports.is_empty() && scene.densities.is_empty() {
        return Ok((scene.clone(), ReplayStats::default()));
    }
    let tol = tolerances.resolve(crate::model::coordinates::model_size(&scene.blocks, tolerances)?);
    let mut sources = scene.blocks.clone();
    cache.repairs.begin();
    for b in &mut sources {
        b.mesh = cache
            .repairs
            .repair(&b.mesh, &tol)
            .map_err(|source| CutError::Source { block: b.name.clone(), source })?
            .mesh;
    }
    let (mut blocks, stats) = replay(&sources, &scene.cuts, tol.weld, cache)?;
    for name in &scene.removed {
        let Some(i) = blocks.iter().position(|b| &b.name == name) else {
            return Err(CutError::UnknownRemoved { name: name.clone() });
        };
        blocks.remove(i);
    }
    for name in &scene.supports {
        let Some(b) = blocks.iter_mut().find(|b| &b.name == name) else {
            return Err(CutError::UnknownSupport { name: name.clone() });
        };
        b.support = true;
    }
    for (name, density) in &scene.densities {
        let Some(b) = blocks.iter_mut().find(|b| &b.name == name) else {
            return Err(CutError::UnknownDensity { name: name.clone() });
        };
        b.density = Some(density.clone());
    }
    let mut out = scene.clone();
    out.blocks = blocks;
    out.cuts.clear();
    out.removed.clear();
    out.supports.clear();
    out.densities.clear();
    Ok((out, stats))
}

#[cfg(test)]
mod naming_tests {
    use super::made_by;

    /// Invariant: a piece's name tells which cuts made it, and no other cut's index matches.
    #[test]
    fn names_tell_their_cuts() {
        assert!(made_by("M.0-", 0));
        assert!(made_by("M.0+.3/1-", 3));
        assert!(made_by("M.13+0", 13));
        assert!(!made_by("M.13+0", 3));
        assert!(!made_by("M.1", 1));
        assert!(!made_by("M", 0));
    }
}
