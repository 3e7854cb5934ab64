//! Broad phase: candidate block pairs whose loosened bounding boxes overlap, through parry's
//! BVH (with [`super::penetration`]'s overlap query, the parry touchpoints of interface
//! detection and of the checks at load). Cost about n log n.

use crate::model::Assembly;
use rapier3d::parry::bounding_volume::Aabb;
use rapier3d::parry::math::Vector;
use rapier3d::parry::partitioning::{Bvh, BvhBuildStrategy};

/// Pairs (i, j), i < j, of blocks that may touch, sorted; support–support pairs left out.
pub fn candidate_pairs(assembly: &Assembly) -> Vec<(usize, usize)> {
    let margin = assembly.tolerances.coplanar;
    // parry works in f32: loosen by the tolerance plus the f32 rounding of the coordinates.
    let aabbs: Vec<Aabb> = assembly
        .blocks
        .iter()
        .map(|b| {
            let m = margin + 1e-6 * (b.aabb.min.coords.amax().max(b.aabb.max.coords.amax()));
            let lo = b.aabb.min.coords.add_scalar(-m);
            let hi = b.aabb.max.coords.add_scalar(m);
            Aabb::new(
                Vector::new(lo.x as f32, lo.y as f32, lo.z as f32),
                Vector::new(hi.x as f32, hi.y as f32, hi.z as f32),
            )
        })
        .collect();
    let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &aabbs);
    let mut pairs = Vec::new();
    for (i, aabb) in aabbs.iter().enumerate() {
        for j in bvh.intersect_aabb(aabb) {
            let j = j as usize;
            if j > i && !(assembly.blocks[i].support && assembly.blocks[j].support) {
                pairs.push((i, j));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}
