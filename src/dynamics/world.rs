//! The only touchpoint of rapier3d: the assembly as a rapier world, stepped.

use super::DropSettings;
use crate::geometry::cut::{SplitResult, split};
use crate::geometry::{Mesh, Plane, Point3, Vector3};
use crate::interfaces::Body;
use crate::model::Assembly;
use rapier3d::math::{Matrix, Pose, Vector};
use rapier3d::prelude::*;

/// A rapier world built from an assembly; bodies in block order.
pub struct Simulation {
    world: PhysicsWorld,
    bodies: Vec<RigidBodyHandle>,
    /// Model offset (x, y of the bounding-box centre): rapier's f32 coordinates are relative to it.
    offset: Vector3,
    start: Vec<(Vector, rapier3d::math::Rotation)>,
    /// Largest relative volume error of a collider (a hull's excess or a decomposition's error).
    pub max_volume_error: f64,
    /// The deepest overlap between two blocks' colliders at the start, as a fraction of the
    /// smaller block's size, and the two blocks (`None`: no overlap beyond 1e-3 of the median
    /// block size).
    pub initial_overlap: Option<(f64, [String; 2])>,
    /// Solver contacts deeper than this (m) are dropped (see `DropSettings::max_contact_depth`).
    deep: DeepContacts,
}

fn v32(v: Vector3) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}

impl Simulation {
    pub fn new(assembly: &Assembly, settings: &DropSettings) -> Self {
        let mut world = PhysicsWorld::new();
        let g = assembly.gravity;
        world.gravity = v32(g);
        let mut sizes: Vec<f64> = assembly.blocks.iter().map(|b| b.aabb.diagonal()).collect();
        sizes.sort_by(f64::total_cmp);
        let unit = sizes.get(sizes.len() / 2).copied().unwrap_or(1.0).max(1e-6);
        let p = &mut world.integration_parameters;
        p.dt = settings.dt as f32;
        p.num_solver_iterations = settings.solver_iterations;
        p.length_unit = unit as f32;
        p.contact_softness.natural_frequency = settings.contact_frequency as f32;
        p.contact_softness.damping_ratio = settings.contact_damping as f32;
        p.static_contact_softness.natural_frequency = settings.contact_frequency as f32;
        p.static_contact_softness.damping_ratio = settings.contact_damping as f32;
        // Recycled contacts let touching wedges hinge: with recycling on, a 15-voussoir arch at
        // t/R = 0.3 drifted 3 % of its size and turned 0.04 rad under any dt, stiffness or
        // iteration count; with it off it holds within 0.7 % (measured, rapier 0.36.1).
        p.contact_recycling = false;
        let mu = settings.friction.unwrap_or(assembly.material.friction) as f32;
        let mut all = crate::geometry::Aabb3::empty();
        assembly.blocks.iter().for_each(|b| all.merge(&b.aabb));
        let c = all.center();
        let offset = Vector3::new(c.x, c.y, 0.0);
        let mut bodies = Vec::with_capacity(assembly.blocks.len());
        let mut max_volume_error: f64 = 0.0;
        let hulls = joint_hulls(assembly, 1e-3 * unit, settings.max_joint_cut);
        let overlaps = overlapping_hulls(assembly, &hulls, 1e-3 * unit);
        let mut overlapping = vec![false; assembly.blocks.len()];
        for &(i, j, _) in &overlaps {
            overlapping[i] = true;
            overlapping[j] = true;
        }
        let mut as_hulls = vec![false; assembly.blocks.len()];
        for (i, b) in assembly.blocks.iter().enumerate() {
            let centroid = b.mass.centroid;
            let local: Vec<Vector> = b.mesh.vertices.iter().map(|p| v32(p - centroid)).collect();
            let hull_error = hulls[i].as_ref().map_or(f64::INFINITY, |h| h.1);
            // A curved voussoir's hull only adds volume where no neighbour is: it collides as
            // its hull. A hull reaching into another block (a notch with something in it) would
            // push that block away from the start: a convex decomposition then.
            let as_hull = hull_error <= settings.hull_tolerance || (hull_error.is_finite() && !overlapping[i]);
            as_hulls[i] = as_hull;
            let builder = if let (true, Some((shape, _))) = (as_hull, &hulls[i]) {
                max_volume_error = max_volume_error.max(hull_error.abs());
                ColliderBuilder::new(shape.clone())
            } else {
                // Exact parts by splitting along the block's own face planes; V-HACD only when
                // that needs more than 16 parts.
                let tol = 1e-3 * b.aabb.diagonal();
                // Triangles are exactly planar (warped faces within the planarity tolerance are
                // not), so the splits stay exact.
                let triangles = b.mesh.triangles();
                let tri = crate::geometry::Mesh::new(
                    b.mesh.vertices.clone(),
                    triangles.iter().map(|(t, _)| t.to_vec()).collect(),
                );
                let parts = match crate::geometry::convex::convex_parts(&tri, tol, 16) {
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
                        let indices: Vec<[u32; 3]> = triangles.iter().map(|(t, _)| t.map(|k| k as u32)).collect();
                        ColliderBuilder::convex_decomposition(&local, &indices)
                    }
                };
                let v = parts.build().volume() as f64;
                max_volume_error = max_volume_error.max((v - b.mass.volume).abs() / b.mass.volume);
                parts
            };
            let mass = b.mass() as f32;
            let i = b.mass.inertia * b.density;
            let inertia = Matrix::from_cols_array(&[
                i[(0, 0)] as f32,
                i[(1, 0)] as f32,
                i[(2, 0)] as f32,
                i[(0, 1)] as f32,
                i[(1, 1)] as f32,
                i[(2, 1)] as f32,
                i[(0, 2)] as f32,
                i[(1, 2)] as f32,
                i[(2, 2)] as f32,
            ]);
            let collider = builder
                .friction(mu)
                .friction_combine_rule(CoefficientCombineRule::Min)
                .restitution(0.0)
                .restitution_combine_rule(CoefficientCombineRule::Min)
                .contact_skin(0.0)
                .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS)
                .mass_properties(MassProperties::with_inertia_matrix(Vector::ZERO, mass, inertia));
            let body = if b.support { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() };
            let mut body = body.translation(v32(centroid.coords - offset)).can_sleep(false);
            if !b.support && settings.perturbation > 0.0 {
                let speed = settings.perturbation * (g.norm() * b.aabb.diagonal()).sqrt();
                body = body.linvel(Vector::new(speed as f32, 0.0, 0.0));
            }
            bodies.push(world.insert(body, collider).0);
        }
        if assembly.ground {
            let half = (10.0 * all.diagonal()).max(1.0) as f32;
            let depth = (0.5 * unit) as f32;
            let ground = RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -depth));
            let collider = ColliderBuilder::cuboid(half, half, depth)
                .friction(mu)
                .friction_combine_rule(CoefficientCombineRule::Min)
                .restitution(0.0)
                .contact_skin(0.0);
            world.insert(ground, collider);
        }
        let start = bodies.iter().map(|&h| (world.bodies[h].translation(), *world.bodies[h].rotation())).collect();
        // Two blocks colliding as hulls that still overlap: the input blocks themselves overlap
        // there (a decomposed block's hull overlaps by design; two supports never collide). Reported relative to the
        // smaller block's size.
        let initial_overlap = overlaps
            .iter()
            .filter(|&&(i, j, _)| as_hulls[i] && as_hulls[j])
            // Two fixed bodies never collide.
            .filter(|&&(i, j, _)| !(assembly.blocks[i].support && assembly.blocks[j].support))
            .map(|&(i, j, d)| {
                let size = assembly.blocks[i].aabb.diagonal().min(assembly.blocks[j].aabb.diagonal());
                (d / size, [assembly.blocks[i].name.clone(), assembly.blocks[j].name.clone()])
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let deep = DeepContacts { depth: (settings.max_contact_depth * unit) as f32 };
        Self { world, bodies, offset, start, max_volume_error, initial_overlap, deep }
    }

    pub fn step(&mut self) {
        self.world.step_with_events(&self.deep, &());
    }

    /// Centroid drift (m) and rotation (rad) of block `i` since the start.
    pub fn displacement(&self, i: usize) -> (f64, f64) {
        let body = &self.world.bodies[self.bodies[i]];
        let (t0, r0) = self.start[i];
        let drift = (body.translation() - t0).length() as f64;
        let rotation = body.rotation().angle_between(r0) as f64;
        (drift, rotation)
    }

    /// Block `i`'s pose: the centroid position (m, model coordinates) and the rotation from the
    /// start (a unit quaternion [w, x, y, z]).
    pub fn pose(&self, i: usize) -> (Point3, [f64; 4]) {
        let body = &self.world.bodies[self.bodies[i]];
        let t = body.translation();
        let q = *body.rotation() * self.start[i].1.inverse();
        (
            Point3::new(t.x as f64 + self.offset.x, t.y as f64 + self.offset.y, t.z as f64),
            [q.w as f64, q.x as f64, q.y as f64, q.z as f64],
        )
    }

    pub fn kinetic_energy(&self, i: usize) -> f64 {
        self.world.bodies[self.bodies[i]].kinetic_energy() as f64
    }
}

fn pose_of(assembly: &Assembly, i: usize) -> Pose {
    Pose::from_translation(v32(assembly.blocks[i].mass.centroid.coords))
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
/// Armadillo) the two blocks' hulls bulge into each other by the warp — up to 9 mm — and would
/// start out pushing apart: at such a joint, and only there, both hulls are cut back to the
/// joint plane, each keeping its side, so that they meet on it. Joints whose hulls do not
/// overlap by more than `depth` (m) are left alone (cutting a conforming but non-planar joint
/// slices real material off: the compas crossvault then fell), and so is a cut that would take
/// more than `keep` of the block's volume. `None` for a block whose points span no volume.
fn joint_hulls(assembly: &Assembly, depth: f64, keep: f64) -> Vec<Option<(SharedShape, f64)>> {
    let n = assembly.blocks.len();
    let mut meshes: Vec<Option<Mesh>> = (0..n).map(|i| hull_mesh(assembly, i)).collect();
    let plain: Vec<Option<SharedShape>> = meshes.iter().map(|m| m.as_ref().and_then(shape_of)).collect();
    let overlap = |a: usize, b: usize| match (&plain[a], &plain[b]) {
        (Some(sa), Some(sb)) => {
            let c = rapier3d::parry::query::contact(
                &pose_of(assembly, a),
                sa.as_ref(),
                &pose_of(assembly, b),
                sb.as_ref(),
                0.0,
            );
            matches!(c, Ok(Some(c)) if (c.dist as f64) < -depth)
        }
        _ => false,
    };
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
            }
        }
    }
    meshes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let shape = shape_of(m.as_ref()?)?;
            let v = assembly.blocks[i].mass.volume;
            let excess = (shape.mass_properties(1.0).mass() as f64 - v) / v;
            Some((shape, excess))
        })
        .collect()
}

/// The pairs of blocks whose hulls overlap by more than `depth` (m), with the overlap (m).
fn overlapping_hulls(
    assembly: &Assembly,
    hulls: &[Option<(SharedShape, f64)>],
    depth: f64,
) -> Vec<(usize, usize, f64)> {
    let n = assembly.blocks.len();
    let mut out = Vec::new();
    let pose = |i: usize| pose_of(assembly, i);
    for i in 0..n {
        for j in i + 1..n {
            let (Some((si, _)), Some((sj, _))) = (&hulls[i], &hulls[j]) else { continue };
            if !assembly.blocks[i].aabb.intersects(&assembly.blocks[j].aabb.loosened(depth)) {
                continue;
            }
            if let Ok(Some(c)) = rapier3d::parry::query::contact(&pose(i), si.as_ref(), &pose(j), sj.as_ref(), 0.0)
                && (c.dist as f64) < -depth
            {
                out.push((i, j, -c.dist as f64));
            }
        }
    }
    out
}

/// Drops solver contacts deeper than `depth` (m): rapier's manifolds between many-sided hulls
/// sometimes carry points reported tens of centimetres deep where the shapes only touch
/// (measured on the Armadillo: 0.79 m between support 86 and block 156, whose hulls parry's
/// contact query finds 1e-7 m apart); their corrective impulses burst a vault open in the first
/// step.
struct DeepContacts {
    depth: f32,
}

impl PhysicsHooks for DeepContacts {
    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        if let Some(m) = context.rigid_mut() {
            m.solver_contacts.retain(|c| c.dist > -self.depth);
        }
    }
}
