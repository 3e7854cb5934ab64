//! The coordinates a scene may have, checked before any tolerance is derived from its size.
//!
//! Every tolerance is a fraction of the model size (the bounding-box diagonal), so one vertex
//! far from the others sets the tolerances of every block: a coordinate of 1e308 in a model of
//! unit blocks makes the weld tolerance astronomical, the first block validated collapses to a
//! point and the error names that block, not the one at fault. So every vertex is checked
//! first, and the error names its block, its index and its coordinates. A coordinate is sane
//! when
//!
//! 1. it is finite;
//! 2. its magnitude is at most [`MAX_COORDINATE`] (1e15): beyond any structure in any unit
//!    (the Armadillo vault in nanometres spans 2e10), and where f64 can no longer place even a
//!    metre-sized block (its step there is 0.125); lengths within 1e±15 keep their squares
//!    inside f32's range (parry's broad phase and overlap queries) and the products of up to
//!    five lengths the analysis forms (the inertia per unit density) far inside f64's. A
//!    coordinate past it is a corrupt number, not a measurement;
//! 3. it is not cut off from the rest of the model: sorted along x, y or z, the vertices may
//!    not show a gap wider than `1 / coplanar` times (333 at the default 3e-3; at least 10)
//!    the size (bounding-box diagonal) of the larger part. Past that the model size, and with
//!    it the coplanarity tolerance, would be set by the gap: the tolerance would be as large
//!    as the whole rest of the model and could no longer tell its joints apart. The smaller
//!    part (by vertex count) is the one at fault; its first vertex in block order is named.
//!    Legitimate scenes do not come near: blocks of an assembly touch, and a support slab or
//!    a second stack beside a design leaves gaps of the order of the design's own size (every
//!    reference file passes with the limit at 10).
//!
//! For the same reasons the model as a whole must be at least [`MIN_MODEL_SIZE`] (1e-15)
//! across ([`super::ModelError::TooSmall`]): a vault scaled to 1e-100 m lost every interface,
//! its face areas (norms of products of lengths) underflowing to zero.

use super::{Block, ModelError};
use crate::geometry::{Aabb3, MeshError, Point3, Tolerances};

/// Largest coordinate magnitude accepted (see the module docs).
pub const MAX_COORDINATE: f64 = 1e15;

/// Smallest model size (bounding-box diagonal) accepted (see the module docs).
pub const MIN_MODEL_SIZE: f64 = 1e-15;

/// The model size every tolerance of `blocks` is resolved against, after the checks that must
/// come before any tolerance is derived from it (every path into an assembly or a cut replay
/// runs them first): the tolerances are valid, every coordinate is sane, and the model has an
/// extent of at least [`MIN_MODEL_SIZE`] — a model whose vertices all coincide has none, and a
/// size taken from nothing would make the weld grid's cells arbitrary.
pub(crate) fn model_size(blocks: &[Block], tolerances: &Tolerances) -> Result<f64, ModelError> {
    tolerances.validate()?;
    if let Some(l) = tolerances.reference_length.filter(|l| !(*l > 0.0 && l.is_finite())) {
        return Err(ModelError::BadReferenceLength(l));
    }
    check(blocks, tolerances.coplanar)
        .map_err(|(b, source)| ModelError::Mesh { block: blocks[b].name.clone(), source })?;
    let extent = extent(blocks);
    if extent == 0.0 {
        let first = blocks.first().ok_or(ModelError::NoBlocks)?;
        let vertices = blocks.iter().map(|b| b.mesh.vertices.len()).sum();
        let (block, source) = match blocks.iter().find_map(|b| b.mesh.vertices.first().map(|p| (b, p))) {
            Some((b, p)) => (b, MeshError::Point { vertices, coords: [p.x, p.y, p.z] }),
            None => (first, MeshError::Empty { vertices: 0, faces: first.mesh.faces.len() }),
        };
        return Err(ModelError::Mesh { block: block.name.clone(), source });
    }
    if extent < MIN_MODEL_SIZE {
        return Err(ModelError::TooSmall(extent));
    }
    Ok(tolerances.scale(extent))
}

/// The bounding-box diagonal of every finite vertex of `blocks` (0 when they all coincide or
/// there are none).
pub(crate) fn extent(blocks: &[Block]) -> f64 {
    let mut all = Aabb3::empty();
    let finite = blocks.iter().flat_map(|b| &b.mesh.vertices).filter(|p| p.iter().all(|c| c.is_finite()));
    finite.for_each(|p| all.extend(p));
    all.diagonal()
}

/// The first vertex (in block order) whose coordinates are not sane, as the index of its block
/// and the error; `coplanar` is the relative coplanarity tolerance.
pub(crate) fn check(blocks: &[Block], coplanar: f64) -> Result<(), (usize, MeshError)> {
    for (b, block) in blocks.iter().enumerate() {
        for (vertex, p) in block.mesh.vertices.iter().enumerate() {
            let coords = [p.x, p.y, p.z];
            if !coords.iter().all(|c| c.is_finite()) {
                return Err((b, MeshError::NonFinite { vertex, coords }));
            }
            if coords.iter().any(|c| c.abs() > MAX_COORDINATE) {
                return Err((b, MeshError::OutOfRange { vertex, coords, limit: MAX_COORDINATE }));
            }
        }
    }
    far_outside(blocks, (1.0 / coplanar).max(10.0))
}

/// Rule 3 of the module docs with gap limit `limit` (× the larger part's size).
fn far_outside(blocks: &[Block], limit: f64) -> Result<(), (usize, MeshError)> {
    // (block, vertex, point), in block order.
    let all: Vec<(usize, usize, Point3)> = blocks
        .iter()
        .enumerate()
        .flat_map(|(b, block)| block.mesh.vertices.iter().enumerate().map(move |(v, p)| (b, v, *p)))
        .collect();
    let n = all.len();
    if n < 2 {
        return Ok(());
    }
    // The worst gap: (gap / size, axis, the smaller part as a range of the sorted order, gap, size).
    let mut worst: Option<(f64, usize, std::ops::Range<usize>, f64, f64)> = None;
    let mut order: Vec<usize> = (0..n).collect();
    for axis in 0..3 {
        order.sort_by(|&i, &j| all[i].2[axis].total_cmp(&all[j].2[axis]));
        // Diagonals of the bounding boxes of the first k + 1 and of the last n − k points.
        let mut prefix = Vec::with_capacity(n);
        let mut bb = Aabb3::empty();
        for &i in &order {
            bb.extend(&all[i].2);
            prefix.push(bb.diagonal());
        }
        let mut suffix = vec![0.0; n];
        let mut bb = Aabb3::empty();
        for (k, &i) in order.iter().enumerate().rev() {
            bb.extend(&all[i].2);
            suffix[k] = bb.diagonal();
        }
        for k in 0..n - 1 {
            let gap = all[order[k + 1]].2[axis] - all[order[k]].2[axis];
            // The larger part by vertex count (ties: the lower one) is the rest of the model.
            let (size, smaller) = if k + 1 >= n - k - 1 { (prefix[k], k + 1..n) } else { (suffix[k + 1], 0..k + 1) };
            if size > 0.0 && gap > limit * size && worst.as_ref().is_none_or(|w| gap / size > w.0) {
                worst = Some((gap / size, axis, smaller, gap, size));
            }
        }
        if let Some(w) = worst.as_mut().filter(|w| w.1 == axis) {
            // Remember the smaller part as block-order indices before the next axis re-sorts.
            let first = order[w.2.clone()].iter().copied().min().unwrap_or(0);
            w.2 = first..first + 1;
        }
    }
    let Some((_, axis, first, gap, size)) = worst else { return Ok(()) };
    let (b, vertex, p) = all[first.start];
    Err((b, MeshError::FarOutside { vertex, coords: [p.x, p.y, p.z], axis: ['x', 'y', 'z'][axis], gap, size, limit }))
}
