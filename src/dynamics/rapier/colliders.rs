//! The colliders of the drop test (rapier3d / parry3d, as re-exported by rapier): each block's
//! convex hull, cut back to the joint plane where two hulls overlap at a joint, or — for a
//! non-convex block whose hull reaches into another block — its exact convex parts.

use crate::dynamics::settings::ColliderForm;
use crate::dynamics::settings::DropSettings;
use crate::geometry::cut::{SplitResult, split};
use crate::geometry::{Mesh, Plane, Point3};
use crate::interfaces::Body;
use crate::interfaces::penetration::overlap_depth;
use crate::model::Assembly;
use rapier3d::math::{Pose, Vector};
use rapier3d::prelude::*;

pub(super) use crate::interfaces::penetration::v32;

/// Every block's collider shape (relative to its centroid), in block order.
pub(super) struct Colliders {
    pub builders: Vec<ColliderBuilder>,
    /// Largest relative volume error of a collider (a hull's excess or a decomposition's error).
    pub max_volume_error: f64,
    /// The deepest overlap between two blocks that collide as hulls, as a fraction of the
    /// smaller block's size, and the two blocks: the input blocks themselves overlap there.
    pub initial_overlap: Option<(f64, [String; 2])>,
}

impl Colliders {
    /// `unit`: the median block size (m); overlaps under 1e-3 of it are contact, not overlap.
    pub fn new(assembly: &Assembly, settings: &DropSettings, unit: f64) -> Self {
        let n = assembly.blocks.len();
        let hulls = joint_hulls(assembly, 1e-3 * unit, settings.max_joint_cut);
        let overlaps = overlapping_hulls(assembly, &hulls, 1e-3 * unit);
        let mut overlapping = vec![false; n];
        for &(i, j, _) in &overlaps {
            overlapping[i] = true;
            overlapping[j] = true;
        }
        let mut max_volume_error: f64 = 0.0;
        let mut as_hulls = vec![false; n];
        let mut builders = Vec::with_capacity(n);
        for (i, b) in assembly.blocks.iter().enumerate() {
            let hull_error = hulls[i].as_ref().map_or(f64::INFINITY, |h| h.1);
            // A curved voussoir's hull only adds volume where no neighbour is: it collides as
            // its hull. A hull reaching into another block (a notch with something in it) would
            // push that block away from the start: a convex decomposition then.
            let fitted = settings.colliders == ColliderForm::Fitted && hull_error.is_finite() && !overlapping[i];
            as_hulls[i] = hull_error <= settings.hull_tolerance || fitted;
            let builder = match (&hulls[i], as_hulls[i]) {
                (Some((shape, _)), true) => {
                    max_volume_error = max_volume_error.max(hull_error.abs());
                    ColliderBuilder::new(shape.clone())
                }
                _ => {
                    let parts = convex_parts(assembly, i);
                    let v = parts.build().volume() as f64;
                    max_volume_error = max_volume_error.max((v - b.mass.volume).abs() / b.mass.volume);
                    parts
                }
            };
            builders.push(builder);
        }
        // Two blocks colliding as hulls that still overlap: the input blocks themselves overlap
        // there (a decomposed block's hull overlaps by design).
        let initial_overlap = overlaps
            .iter()
            .filter(|&&(i, j, _)| as_hulls[i] && as_hulls[j])
            .map(|&(i, j, d)| {
                let size = assembly.blocks[i].aabb.diagonal().min(assembly.blocks[j].aabb.diagonal());
                (d / size, [assembly.blocks[i].name.clone(), assembly.blocks[j].name.clone()])
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        Self { builders, max_volume_error, initial_overlap }
    }
}

/// Block `i`'s exact convex parts, split along its own face planes; V-HACD only when that needs
/// more than 16 parts.
fn convex_parts(assembly: &Assembly, i: usize) -> ColliderBuilder {
    let b = &assembly.blocks[i];
    let centroid = b.mass.centroid;
    let tol = 1e-3 * b.aabb.diagonal();
    // Triangles are exactly planar (warped faces within the planarity tolerance are not), so
    // the splits stay exact.
    let triangles = b.mesh.triangles();
    let tri = Mesh::new(b.mesh.vertices.clone(), triangles.iter().map(|(t, _)| t.to_vec()).collect());
    match crate::geometry::convex::convex_parts(&tri, tol, 16) {
        Some(parts) => {
            let shapes: Vec<(Pose, SharedShape)> = parts
                .iter()
                .filter_map(|m| {
                    let pts: Vec<Vector> = m.vertices.iter().map(|p| v32(p - centroid)).collect();
                    SharedShape::convex_hull(&pts).map(|s| (Pose::IDENTITY, s))
                })
                .collect();
            ColliderBuilder::compound(shapes)
        }
        None => {
            let local: Vec<Vector> = b.mesh.vertices.iter().map(|p| v32(p - centroid)).collect();
            let indices: Vec<[u32; 3]> = triangles.iter().map(|(t, _)| t.map(|k| k as u32)).collect();
            ColliderBuilder::convex_decomposition(&local, &indices)
        }
    }
}

/// Block `i`'s convex hull, relative to its centroid, as a mesh.
fn hull_mesh(assembly: &Assembly, i: usize) -> Option<Mesh> {
    use rapier3d::parry::transformation::try_convex_hull;
    let b = &assembly.blocks[i];
    let local: Vec<Vector> = b.mesh.vertices.iter().map(|p| v32(p - b.mass.centroid)).collect();
    let (vertices, triangles) = try_convex_hull(&local).ok()?;
    Some(Mesh::new(
        vertices.iter().map(|v| Point3::new(v.x as f64, v.y as f64, v.z as f64)).collect(),
        triangles.iter().map(|t| t.iter().map(|&k| k as usize).collect()).collect(),
    ))
}

fn shape_of(mesh: &Mesh) -> Option<SharedShape> {
    let points: Vec<Vector> = mesh.vertices.iter().map(|p| Vector::new(p.x as f32, p.y as f32, p.z as f32)).collect();
    SharedShape::convex_hull(&points)
}

/// Every block's collider hull (relative to its centroid) and its volume excess over the block
/// (a fraction). Where a joint is warped (its two faces triangulated differently, as on the
/// Armadillo) the two blocks' hulls bulge into each other by the warp and would start out
/// pushing apart: at such a joint, and only there, both hulls are cut back to the joint plane,
/// each keeping its side, so that they meet on it. Joints whose hulls do not
/// overlap by more than `depth` (m) are left alone (cutting a conforming but non-planar joint
/// slices real material off: the compas crossvault then fell), and so is a cut that would take
/// more than `keep` of the block's volume. `None` for a block whose points span no volume.
fn joint_hulls(assembly: &Assembly, depth: f64, keep: f64) -> Vec<Option<(SharedShape, f64)>> {
    let n = assembly.blocks.len();
    let mut meshes: Vec<Option<Mesh>> = (0..n).map(|i| hull_mesh(assembly, i)).collect();
    let plain: Vec<Option<SharedShape>> = meshes.iter().map(|m| m.as_ref().and_then(shape_of)).collect();
    let overlap = |a: usize, b: usize| match (&plain[a], &plain[b]) {
        (Some(sa), Some(sb)) => overlap_depth(assembly, a, sa, b, sb, 1.0) > depth,
        _ => false,
    };
    let mut cut = vec![false; n];
    for f in &crate::interfaces::detect(assembly) {
        let (Body::Block(a), Body::Block(b)) = (f.a, f.b) else { continue };
        if !overlap(a.0, b.0) {
            continue;
        }
        for (k, out) in [(a.0, f.frame.n), (b.0, -f.frame.n)] {
            let c = assembly.blocks[k].mass.centroid;
            let plane = Plane::from_point_normal(&Point3::from(f.frame.origin - c), &out);
            let eps = 1e-9 * assembly.blocks[k].aabb.diagonal();
            // The block's own side is the negative one; a convex solid gives one piece a side.
            // A cut taking more than a warp's sliver (`keep` of the block: the plane of a
            // non-planar or notched joint runs through real material) is not made; the hulls
            // then overlap and the blocks get convex decompositions instead.
            if let Some(mesh) = meshes[k].as_mut()
                && let SplitResult::Pair { negative, .. } = split(mesh, &plane, eps)
                && let Some(piece) = negative.into_iter().next()
                && crate::geometry::MassProperties::of_mesh(&piece).volume
                    >= (1.0 - keep) * assembly.blocks[k].mass.volume
            {
                *mesh = piece;
                cut[k] = true;
            }
        }
    }
    meshes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            // An uncut hull is the plain one.
            let shape = if cut[i] { shape_of(m.as_ref()?)? } else { plain[i].clone()? };
            let v = assembly.blocks[i].mass.volume;
            let excess = (shape.mass_properties(1.0).mass() as f64 - v) / v;
            Some((shape, excess))
        })
        .collect()
}

/// The pairs of blocks whose hulls overlap by more than `depth` (m), with the overlap (m);
/// the candidates from interface detection's broad phase (support pairs left out: two fixed
/// bodies never collide).
fn overlapping_hulls(
    assembly: &Assembly,
    hulls: &[Option<(SharedShape, f64)>],
    depth: f64,
) -> Vec<(usize, usize, f64)> {
    crate::interfaces::broad::candidate_pairs(assembly)
        .into_iter()
        .filter_map(|(i, j)| {
            let (Some((si, _)), Some((sj, _))) = (&hulls[i], &hulls[j]) else { return None };
            let d = overlap_depth(assembly, i, si, j, sj, 1.0);
            (d > depth).then_some((i, j, d))
        })
        .collect()
}
