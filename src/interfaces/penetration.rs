//! Blocks that interpenetrate: the overlap-depth query of two convex shapes (parry, as
//! re-exported by rapier — shared with the drop test's colliders) and the check run at load.
//!
//! Depth is parry's penetration depth: the shortest translation that separates the two shapes
//! (two unit cubes pushed 0.2 into each other: 0.2). A block is checked as its convex hull,
//! and where the hulls overlap, as its exact convex parts ([`crate::geometry::convex`]): the
//! hull of a non-convex block (a notch, an interlocking key, the pieces of a decomposed
//! shape) legitimately reaches into its neighbour, its parts do not. Part–part depths never
//! exceed the blocks' own (the parts are inside the blocks), so a reported overlap is real.
//!
//! Most pairs are settled without parry: the joint plane of two touching blocks separates
//! their vertices (one of the blocks' face planes, up to the tolerance).
//!
//! A pair is reported when its depth exceeds the pair's coplanarity tolerance — the one
//! interface detection uses (`coplanar` × model size, at most `coplanar_thickness` × the
//! thinner block's thickness): a joint open or closed by less is an interface, and touching
//! blocks (a shared face) have depth 0. Only the broad phase's candidate pairs whose bounding
//! boxes overlap by more than that tolerance along every axis are queried (the depth is at
//! most the boxes' smallest overlap). A block that needs more than [`MAX_PARTS`] convex parts,
//! or has more than [`MAX_TRIANGLES`] triangles (a finely tessellated curved block), is only
//! checked as its hull: where that hull reaches into a neighbour nothing is reported — an
//! overlap of two such blocks goes unnoticed, never a false one is reported.

use super::broad;
use crate::geometry::{Mesh, Point3, Vector3};
use crate::model::{Assembly, AssemblyBlock, Overlap};
use rapier3d::math::{Pose, Vector};
use rapier3d::parry::query::contact;
use rapier3d::parry::shape::SharedShape;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};

/// Convex parts a block may be split into for the check.
pub const MAX_PARTS: usize = 32;

/// Triangles of a block beyond which no exact decomposition is tried: a finely tessellated
/// curved block would need far more than [`MAX_PARTS`], and finding that out is slow.
pub const MAX_TRIANGLES: usize = 256;

pub(crate) fn v32(v: Vector3) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}

/// How far block `j`'s shape `b` overlaps block `i`'s shape `a` (m; ≤ 0 when apart), the two
/// shapes given relative to their blocks' centroids in units of `unit` m and placed with the
/// offset between the centroids computed in f64 before parry's f32: a model far from the
/// origin keeps its precision.
pub(crate) fn overlap_depth(
    assembly: &Assembly,
    i: usize,
    a: &SharedShape,
    j: usize,
    b: &SharedShape,
    unit: f64,
) -> f64 {
    let offset = (assembly.blocks[j].mass.centroid - assembly.blocks[i].mass.centroid) / unit;
    match contact(&Pose::IDENTITY, a.as_ref(), &Pose::from_translation(v32(offset)), b.as_ref(), 0.0) {
        Ok(Some(c)) => -c.dist as f64 * unit,
        _ => 0.0,
    }
}

/// The convex hull of `points`, relative to `origin` in units of `unit` m.
fn hull_of<'a>(points: impl Iterator<Item = &'a Point3>, origin: &Point3, unit: f64) -> Option<SharedShape> {
    let local: Vec<Vector> = points.map(|p| v32((p - origin) / unit)).collect();
    SharedShape::convex_hull(&local)
}

/// Block `b`'s exact convex parts (convex up to `tol` m) as parry shapes relative to its
/// centroid in units of `unit` m; `None` when it has more than [`MAX_TRIANGLES`] triangles or
/// needs more than [`MAX_PARTS`] parts.
pub(crate) fn convex_shapes(b: &AssemblyBlock, tol: f64, unit: f64) -> Option<Vec<SharedShape>> {
    // Triangles are exactly planar (warped faces within the planarity tolerance are not), so
    // the splits stay exact.
    let triangles = b.mesh.triangles();
    if triangles.len() > MAX_TRIANGLES {
        return None;
    }
    let tri = Mesh::new(b.mesh.vertices.clone(), triangles.iter().map(|(t, _)| t.to_vec()).collect());
    let parts = crate::geometry::convex::convex_parts(&tri, tol, MAX_PARTS)?;
    parts.iter().map(|m| hull_of(m.vertices.iter(), &b.mass.centroid, unit)).collect()
}

/// Block `b`'s convex hull relative to its centroid in units of `unit` m.
pub(crate) fn hull_shape(b: &AssemblyBlock, unit: f64) -> Option<SharedShape> {
    hull_of(b.mesh.vertices.iter(), &b.mass.centroid, unit)
}

/// The shapes of one block, built when a pair first needs them.
#[derive(Default)]
struct Shapes {
    hull: Option<Option<SharedShape>>,
    /// Exact convex parts; `Some(None)` when the block needs more than [`MAX_PARTS`].
    parts: Option<Option<Vec<SharedShape>>>,
}

struct Checker<'a> {
    assembly: &'a Assembly,
    shapes: Vec<Shapes>,
    /// The length unit of the shapes given to parry, m: the median block size, so that its
    /// f32 queries and their built-in tolerances work on shapes of about unit size whatever
    /// the model's units (in metres, a very large model shows overlaps that are not there).
    unit: f64,
}

impl<'a> Checker<'a> {
    fn new(assembly: &'a Assembly) -> Self {
        let unit = assembly.median_block_size().filter(|u| *u > 0.0 && u.is_finite()).unwrap_or(1.0);
        Self { assembly, shapes: (0..assembly.blocks.len()).map(|_| Shapes::default()).collect(), unit }
    }

    fn hull(&mut self, i: usize) -> Option<SharedShape> {
        let b = &self.assembly.blocks[i];
        let unit = self.unit;
        self.shapes[i].hull.get_or_insert_with(|| hull_shape(b, unit)).clone()
    }

    /// Block `i`'s convex parts, convex up to `tol` (m).
    fn parts(&mut self, i: usize, tol: f64) -> Option<Vec<SharedShape>> {
        let b = &self.assembly.blocks[i];
        let unit = self.unit;
        self.shapes[i].parts.get_or_insert_with(|| convex_shapes(b, tol, unit)).clone()
    }

    /// Whether one of block `i`'s face planes separates its vertices from block `j`'s up to
    /// `tol` (m) in all: `i` reaching at most `e_i` beyond it and `j` at most `e_j` behind it
    /// with `e_i + e_j ≤ tol`, so that moving `j` by `tol` along the face normal separates
    /// them (the depth is at most `tol`). The joint of two touching blocks is such a plane:
    /// most pairs are settled here, without a hull.
    fn face_plane_separates(&self, i: usize, j: usize, tol: f64) -> bool {
        let (a, b) = (&self.assembly.blocks[i], &self.assembly.blocks[j]);
        a.faces.iter().filter(|f| f.area > 0.0).any(|f| {
            let d = |p: &Point3| (p - f.centroid).dot(&f.normal);
            let beyond = a.mesh.vertices.iter().map(d).fold(f64::NEG_INFINITY, f64::max);
            beyond <= tol && b.mesh.vertices.iter().all(|p| -d(p) <= tol - beyond)
        })
    }

    /// The pair's penetration depth when it exceeds the pair's tolerance `tol` (m).
    fn depth(&mut self, i: usize, j: usize, tol: f64) -> Option<f64> {
        let (a, b) = (&self.assembly.blocks[i].aabb, &self.assembly.blocks[j].aabb);
        let box_overlap = (0..3).map(|k| a.max[k].min(b.max[k]) - a.min[k].max(b.min[k])).fold(f64::INFINITY, f64::min);
        if box_overlap.is_nan() || box_overlap <= tol {
            return None;
        }
        if self.face_plane_separates(i, j, tol) || self.face_plane_separates(j, i, tol) {
            return None;
        }
        let (hi, hj) = (self.hull(i)?, self.hull(j)?);
        let hull_depth = overlap_depth(self.assembly, i, &hi, j, &hj, self.unit);
        if hull_depth.is_nan() || hull_depth <= tol {
            return None;
        }
        // Parts convex up to half the tolerance: two touching parts' hulls then overlap by at
        // most the tolerance.
        let (pi, pj) = (self.parts(i, 0.5 * tol)?, self.parts(j, 0.5 * tol)?);
        let depth = if pi.len() == 1 && pj.len() == 1 {
            hull_depth
        } else {
            let mut deepest: f64 = 0.0;
            for si in &pi {
                for sj in &pj {
                    deepest = deepest.max(overlap_depth(self.assembly, i, si, j, sj, self.unit));
                }
            }
            deepest
        };
        (depth > tol).then_some(depth)
    }
}

/// The pair's coplanarity tolerance (m), as in interface detection.
fn pair_tolerance(assembly: &Assembly, i: usize, j: usize) -> f64 {
    let tol = &assembly.tolerances;
    tol.coplanar.min(tol.coplanar_thickness * assembly.blocks[i].thickness.min(assembly.blocks[j].thickness))
}

fn overlap(assembly: &Assembly, i: usize, j: usize, depth: f64) -> Overlap {
    let (a, b) = (&assembly.blocks[i], &assembly.blocks[j]);
    Overlap {
        a: a.name.clone(),
        b: b.name.clone(),
        depth,
        size: a.thickness.min(b.thickness),
        tolerance: pair_tolerance(assembly, i, j),
    }
}

/// Every pair of blocks that interpenetrates beyond its coplanarity tolerance, in pair order
/// (supports with supports left out, as in interface detection: two fixed bodies carry
/// nothing between them).
pub fn overlaps(assembly: &Assembly) -> Vec<Overlap> {
    let mut checker = Checker::new(assembly);
    broad::candidate_pairs(assembly)
        .into_iter()
        .filter_map(|(i, j)| checker.depth(i, j, pair_tolerance(assembly, i, j)).map(|d| overlap(assembly, i, j, d)))
        .collect()
}

/// The depths found for block pairs, by the pair's content (both blocks' keys and the resolved
/// tolerances), so that a pipeline re-run checks only the pairs an edit changed.
#[derive(Debug, Default)]
pub struct OverlapCache {
    map: HashMap<u64, Option<f64>>,
}

/// [`overlaps`] with a cache (keys from [`super::block_keys`]); the same result. The cache keeps
/// only this assembly's pairs afterwards.
pub fn overlaps_cached(assembly: &Assembly, keys: &[u64], cache: &mut OverlapCache) -> Vec<Overlap> {
    let tol_key = {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        format!("{:?}", assembly.tolerances).hash(&mut h);
        h.finish()
    };
    let mut checker = Checker::new(assembly);
    let mut next = HashMap::new();
    let mut out = Vec::new();
    for (i, j) in broad::candidate_pairs(assembly) {
        let tol = pair_tolerance(assembly, i, j);
        let (a, b) = (&assembly.blocks[i].aabb, &assembly.blocks[j].aabb);
        if (0..3).any(|k| a.max[k].min(b.max[k]) - a.min[k].max(b.min[k]) <= tol) {
            continue; // no narrow check: nothing worth remembering
        }
        let mut h = std::collections::hash_map::DefaultHasher::new();
        (keys[i], keys[j], tol_key).hash(&mut h);
        let key = h.finish();
        let depth = match cache.map.remove(&key).or_else(|| next.get(&key).copied()) {
            Some(depth) => depth,
            None => checker.depth(i, j, tol),
        };
        next.insert(key, depth);
        if let Some(d) = depth {
            out.push(overlap(assembly, i, j, d));
        }
    }
    cache.map = next;
    out
}
