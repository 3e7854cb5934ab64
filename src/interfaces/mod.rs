//! Contact interfaces between blocks, and between blocks and supports or the ground plane.
//!
//! Two faces form an interface when their outward normals are opposite (within the angle
//! tolerance), each lies in the other's plane (within the coplanarity tolerance: relative to the
//! model size, and at most a fraction of the thinner block's thickness) and their overlap has a
//! non-negligible area. The overlap is computed in 2D with a
//! polygon-clipping crate, so non-convex faces, holes and several disjoint overlap pieces are
//! handled; each piece is one [`Interface`].
//!
//! Sign rule (docs/design.md#interface-sign-rule): an interface a→b has frame (u, v, n) with n the outward normal of a's
//! face (pointing into b). A force f at an interface point acts on b as +f and on a as −f, so a
//! positive normal component is compression. For the ground, a is the ground and n = +z.

pub(crate) mod broad;
mod cache;
pub mod penetration;

use crate::geometry::polygon::{Frame, Plane, centroid, signed_area_2d};
use crate::geometry::{Point3, Vector3};
use crate::model::{Assembly, BlockId};
pub use cache::{DetectCache, DetectStats, block_keys, detect_cached};
pub use penetration::{OverlapCache, overlaps, overlaps_cached};
use serde::Serialize;

/// One side of an interface: a block or the ground plane z = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Body {
    /// A block of the assembly (a support or a free block).
    Block(BlockId),
    /// The ground plane z = 0 (a fixed body, when the scene has `ground`).
    Ground,
}

impl Body {
    /// The block, or `None` for the ground.
    pub fn block(self) -> Option<BlockId> {
        match self {
            Body::Block(b) => Some(b),
            Body::Ground => None,
        }
    }

    /// The block's name, or "ground".
    pub fn name(self, assembly: &Assembly) -> &str {
        match self {
            Body::Block(b) => &assembly.block(b).name,
            Body::Ground => "ground",
        }
    }

    /// Fixed bodies (supports and the ground) have no equilibrium rows.
    pub fn is_fixed(self, assembly: &Assembly) -> bool {
        match self {
            Body::Block(b) => assembly.block(b).support,
            Body::Ground => true,
        }
    }
}

/// A planar contact region between two bodies.
#[derive(Clone, Debug, PartialEq)]
pub struct Interface {
    /// The body whose face normal is `frame.n`.
    pub a: Body,
    /// The body the normal points into; receives +f.
    pub b: Body,
    /// Outer boundary, counter-clockwise about `frame.n`.
    pub polygon: Vec<Point3>,
    /// Holes (clockwise about `frame.n`); they do not change the statics (the forces act at the
    /// outer boundary, whose convex hull is the same) but they count for the area.
    pub holes: Vec<Vec<Point3>>,
    /// Origin at the area centroid; (u, v, n) right-handed, n from a into b.
    pub frame: Frame,
    /// Area of the contact polygon less its holes (m²).
    pub area: f64,
    /// Face indices in a's and b's meshes (None for the ground).
    pub faces: (Option<usize>, Option<usize>),
}

impl Interface {
    /// The area centroid of the contact polygon (the frame's origin).
    pub fn centroid(&self) -> Point3 {
        self.frame.origin
    }

    /// The interface with its contact polygon shrunk by `delta` (m) from every edge — chipped
    /// or rounded arrises (`geometry::overlap::shrink`): one interface per piece that
    /// remains (same bodies, frame and faces), none when nothing does.
    pub fn shrunk(&self, delta: f64) -> Vec<Interface> {
        let f = &self.frame;
        let flat: Vec<[f64; 2]> =
            self.polygon.iter().map(|p| [(p - f.origin).dot(&f.u), (p - f.origin).dot(&f.v)]).collect();
        let lift = |q: &[f64; 2]| f.origin + f.u * q[0] + f.v * q[1];
        let ring_area = crate::geometry::polygon::signed_area_2d;
        crate::geometry::overlap::shrink(&flat, delta)
            .into_iter()
            .filter_map(|piece| {
                let (outer, holes) = piece.split_first()?;
                let area = ring_area(outer).abs() - holes.iter().map(|h| ring_area(h).abs()).sum::<f64>();
                Some(Interface {
                    polygon: outer.iter().map(lift).collect(),
                    holes: holes.iter().map(|h| h.iter().map(lift).collect()).collect(),
                    area,
                    ..self.clone()
                })
            })
            .collect()
    }

    /// Whether the interface touches `block`.
    pub fn touches(&self, block: BlockId) -> bool {
        self.a == Body::Block(block) || self.b == Body::Block(block)
    }
}

/// Detects every interface of the assembly: block–block (supports included, support–support
/// pairs left out) and, when the ground is enabled, block–ground. Deterministic order: by pair
/// (a, b), then by face indices, then by piece.
pub fn detect(assembly: &Assembly) -> Vec<Interface> {
    let mut out = Vec::new();
    for (i, j) in broad::candidate_pairs(assembly) {
        detect_pair(assembly, BlockId(i), BlockId(j), &mut out);
    }
    if assembly.ground {
        for i in 0..assembly.blocks.len() {
            detect_ground(assembly, BlockId(i), &mut out);
        }
    }
    out
}

/// Interfaces between blocks `ia` and `ib` (the first is a), appended to `out`.
pub fn detect_pair(assembly: &Assembly, ia: BlockId, ib: BlockId, out: &mut Vec<Interface>) {
    let tol = &assembly.tolerances;
    let (ba, bb) = (assembly.block(ia), assembly.block(ib));
    if ba.support && bb.support {
        return;
    }
    let coplanar = tol.coplanar.min(tol.coplanar_thickness * ba.thickness.min(bb.thickness));
    for (fa, face_a) in ba.faces.iter().enumerate() {
        if face_a.area == 0.0 {
            continue;
        }
        let box_a = face_a.aabb.loosened(coplanar);
        for (fb, face_b) in bb.faces.iter().enumerate() {
            if face_a.normal.dot(&face_b.normal) > -tol.cos_angle
                || face_b.area == 0.0
                || !box_a.intersects(&face_b.aabb)
            {
                continue;
            }
            let pa: Vec<Point3> = ba.mesh.face_points(fa).collect();
            let pb: Vec<Point3> = bb.mesh.face_points(fb).collect();
            let plane_a = Plane::from_point_normal(&face_a.centroid, &face_a.normal);
            let plane_b = Plane::from_point_normal(&face_b.centroid, &face_b.normal);
            let within = |plane: &Plane, pts: &[Point3]| pts.iter().all(|p| plane.distance(p).abs() <= coplanar);
            if !within(&plane_a, &pb) || !within(&plane_b, &pa) {
                continue;
            }
            // Work in the mid-plane between the two faces.
            let gap = pb.iter().map(|p| plane_a.distance(p)).sum::<f64>() / pb.len() as f64;
            let origin = face_a.centroid + face_a.normal * (0.5 * gap);
            let frame = Frame::from_normal(origin, face_a.normal);
            let ring_a: Vec<[f64; 2]> = pa.iter().map(|p| frame.to_2d(p)).collect();
            // b's face is CCW about −n: reverse it to CCW about n.
            let ring_b: Vec<[f64; 2]> = pb.iter().rev().map(|p| frame.to_2d(p)).collect();
            let min_area = (tol.min_area_rel * face_a.area.min(face_b.area)).max(tol.min_area_abs);
            for piece in crate::geometry::overlap::intersect(&ring_a, &ring_b) {
                push_piece(&frame, piece, min_area, Body::Block(ia), Body::Block(ib), (Some(fa), Some(fb)), out);
            }
        }
    }
}

/// Interfaces between a free block's downward faces lying on z = 0 and the ground.
pub fn detect_ground(assembly: &Assembly, ib: BlockId, out: &mut Vec<Interface>) {
    let tol = &assembly.tolerances;
    let block = assembly.block(ib);
    let coplanar = tol.coplanar.min(tol.coplanar_thickness * block.thickness);
    if block.support || block.aabb.min.z > coplanar {
        return;
    }
    for (f, face) in block.faces.iter().enumerate() {
        if face.area == 0.0 || face.normal.z > -tol.cos_angle || face.aabb.max.z.abs() > coplanar {
            continue;
        }
        if block.mesh.face_points(f).any(|p| p.z.abs() > coplanar) {
            continue;
        }
        let frame = Frame::from_normal(Point3::origin(), Vector3::z());
        let ring: Vec<[f64; 2]> =
            block.mesh.face_points(f).collect::<Vec<_>>().iter().rev().map(|p| frame.to_2d(p)).collect();
        let min_area = (tol.min_area_rel * face.area).max(tol.min_area_abs);
        // Intersecting with itself normalises the ring (orientation, collinear points).
        for piece in crate::geometry::overlap::intersect(&ring, &ring) {
            push_piece(&frame, piece, min_area, Body::Ground, Body::Block(ib), (None, Some(f)), out);
        }
    }
}

fn push_piece(
    plane_frame: &Frame,
    piece: Vec<Vec<[f64; 2]>>,
    min_area: f64,
    a: Body,
    b: Body,
    faces: (Option<usize>, Option<usize>),
    out: &mut Vec<Interface>,
) {
    let Some((outer, holes_2d)) = piece.split_first() else { return };
    let area = signed_area_2d(outer).abs() - holes_2d.iter().map(|h| signed_area_2d(h).abs()).sum::<f64>();
    if area < min_area || outer.len() < 3 {
        return;
    }
    let lift = |ring: &[[f64; 2]]| -> Vec<Point3> { ring.iter().map(|&q| plane_frame.to_3d(q)).collect() };
    let mut polygon = lift(outer);
    if signed_area_2d(outer) < 0.0 {
        polygon.reverse();
    }
    let holes: Vec<Vec<Point3>> = holes_2d.iter().map(|h| lift(h)).collect();
    // Area centroid of the region: outer minus holes.
    let mut c = centroid(&polygon).coords * signed_area_2d(outer).abs();
    for (h3, h2) in holes.iter().zip(holes_2d) {
        c -= centroid(h3).coords * signed_area_2d(h2).abs();
    }
    let origin = Point3::from(c / area);
    let frame = Frame::from_normal(origin, plane_frame.n);
    out.push(Interface { a, b, polygon, holes, frame, area, faces });
}
