//! The rapier world of the drop test (with [`super::colliders`], the only rapier touchpoint): the
//! assembly as rigid bodies, stepped.

use super::colliders::{Colliders, v32};
use crate::dynamics::scene::SupportPath;
use crate::dynamics::settings::DropSettings;
use crate::geometry::{Point3, Vector3};
use crate::model::Assembly;
use rapier3d::math::{Matrix, Vector};
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
    /// The supports on prescribed paths (kinematic bodies), with the fraction covered.
    paths: Vec<(SupportPath, f64)>,
    /// The design's gravity, m/s².
    gravity: Vector3,
    /// How far the shaken supports have moved ([`Self::step_supports_by`]), m.
    shaken: Vector3,
}

impl Simulation {
    /// The rapier world of the assembly at its start, no support moving.
    pub fn new(assembly: &Assembly, settings: &DropSettings) -> Self {
        Self::with_paths(assembly, settings, &[])
    }

    /// A simulation whose supports `paths` name are kinematic bodies moved along them
    /// ([`Self::step_supports`]).
    pub fn with_paths(assembly: &Assembly, settings: &DropSettings, paths: &[SupportPath]) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = v32(assembly.gravity);
        let unit = assembly.median_block_size().unwrap_or(1.0).max(1e-6);
        configure(&mut world.integration_parameters, settings, unit);
        let mu = settings.friction.unwrap_or(assembly.material.friction) as f32;
        let mut all = crate::geometry::Aabb3::empty();
        assembly.blocks.iter().for_each(|b| all.merge(&b.aabb));
        let c = all.center();
        let offset = Vector3::new(c.x, c.y, 0.0);
        let shapes = Colliders::new(assembly, settings, unit);
        let (max_volume_error, initial_overlap) = (shapes.max_volume_error, shapes.initial_overlap.clone());
        let bodies: Vec<RigidBodyHandle> = (assembly.blocks.iter().zip(shapes.builders).enumerate())
            .map(|(i, (b, builder))| {
                let moved = paths.iter().any(|p| p.block == i);
                let (body, collider) = block_body(b, builder, mu, moved, offset, settings, assembly.gravity);
                world.insert(body, collider).0
            })
            .collect();
        apply_dead_loads(&mut world, assembly, &bodies);
        let ground = crate::dynamics::scene::floor_level(assembly, settings)
            .map(|level| insert_ground(&mut world, (10.0 * all.diagonal()).max(1.0), unit, mu, level));
        let start = bodies.iter().map(|&h| (world.bodies[h].translation(), *world.bodies[h].rotation())).collect();
        let deep = DeepContacts { depth: (settings.max_contact_depth * unit) as f32, ground };
        let paths = paths.iter().map(|p| (*p, 0.0)).collect();
        let gravity = assembly.gravity;
        let shaken = Vector3::zeros();
        Self { world, bodies, offset, start, max_volume_error, initial_overlap, deep, paths, gravity, shaken }
    }

    /// One step of dt.
    pub fn step(&mut self) {
        self.world.step_with_events(&self.deep, &());
    }

    /// One step in which every moved support covers `fraction` more of its path (its next
    /// kinematic pose: translated, and turned about its centroid).
    pub fn step_supports(&mut self, fraction: f64) {
        for (path, done) in &mut self.paths {
            *done += fraction;
            let (t0, r0) = self.start[path.block];
            let turn = Rotation::from_scaled_axis(v32(path.rotation * *done));
            if let Some(body) = self.world.bodies.get_mut(self.bodies[path.block]) {
                body.set_next_kinematic_position(Pose::from_parts(t0 + v32(path.translation * *done), turn * r0));
            }
        }
        self.step();
    }

    /// One step in which every moved support translates by `displacement` (m) more: named
    /// supports shaken by a ground motion (their paths' own vectors unused).
    pub fn step_supports_by(&mut self, displacement: Vector3) {
        self.shaken += displacement;
        for (path, _) in &self.paths {
            let (t0, r0) = self.start[path.block];
            if let Some(body) = self.world.bodies.get_mut(self.bodies[path.block]) {
                body.set_next_kinematic_position(Pose::from_parts(t0 + v32(self.shaken), r0));
            }
        }
        self.step();
    }

    /// The base's acceleration `a` (m/s², world axes) for the next steps: the world steps in
    /// the base's frame, its gravity g − a (no body sleeps).
    pub fn set_base_acceleration(&mut self, a: Vector3) {
        self.world.gravity = v32(self.gravity - a);
    }

    /// The speed of block `i`'s centroid (m/s) and its angular speed (rad/s).
    pub fn speeds(&self, i: usize) -> (f64, f64) {
        let body = &self.world.bodies[self.bodies[i]];
        (body.linvel().length() as f64, body.angvel().length() as f64)
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

    /// The force (N) the other bodies put on block `i` over the last step: its contacts' normal
    /// impulses (along the manifold normal, from collider 1 to collider 2, collider 2 pushed
    /// along it) and friction impulses (the solver's world-space tangent impulse, the other way)
    /// over the time step. Checked: the vertical share of a lintel on a settling pier within
    /// 5 %; the friction part reads about half the rigid thrust at an arch's springers.
    pub fn contact_force(&self, i: usize) -> Vector3 {
        let body = &self.world.bodies[self.bodies[i]];
        let mut total = Vector::ZERO;
        for &c in body.colliders() {
            for pair in self.world.narrow_phase.contact_pairs_with(c) {
                let sign = if pair.collider2 == c { 1.0 } else { -1.0 };
                for m in pair.solver_manifolds() {
                    for p in &m.points {
                        total += (m.data.normal * p.data.impulse - p.data.warmstart_tangent_world) * sign;
                    }
                }
            }
        }
        let dt = self.world.integration_parameters.dt as f64;
        Vector3::new(total.x as f64, total.y as f64, total.z as f64) / dt
    }

    /// Block `i`'s kinetic energy, J (rapier's, in f32).
    pub fn kinetic_energy(&self, i: usize) -> f64 {
        self.world.bodies[self.bodies[i]].kinetic_energy() as f64
    }
}

/// Drops solver contacts deeper than `depth` (m): rapier's manifolds between many-sided hulls
/// sometimes carry points reported tens of centimetres deep where the shapes only touch; their
/// corrective impulses burst a vault open in the first step.
struct DeepContacts {
    depth: f32,
    /// The ground's collider: a block landing on it at speed overlaps it deeper than a joint's
    /// spurious contacts, and must still meet it.
    ground: Option<ColliderHandle>,
}

impl PhysicsHooks for DeepContacts {
    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        if self.ground.is_some_and(|g| g == context.collider1 || g == context.collider2) {
            return;
        }
        if let Some(m) = context.rigid_mut() {
            m.solver_contacts.retain(|c| c.dist > -self.depth);
        }
    }
}

/// The step, solver iterations and contact softness of the settings; `unit` (m) is rapier's length unit.
fn configure(p: &mut IntegrationParameters, settings: &DropSettings, unit: f64) {
    p.dt = settings.dt as f32;
    p.num_solver_iterations = settings.solver_iterations;
    p.length_unit = unit as f32;
    p.contact_softness.natural_frequency = settings.contact_frequency as f32;
    p.contact_softness.damping_ratio = settings.contact_damping as f32;
    p.static_contact_softness.natural_frequency = settings.contact_frequency as f32;
    p.static_contact_softness.damping_ratio = settings.contact_damping as f32;
    // Recycled contacts let touching wedges hinge (a standing arch drifts under any dt).
    p.contact_recycling = false;
}

/// A block's body (fixed, kinematic when its path moves it, or dynamic, nudged by the
/// settings' perturbation) and its collider with the block's mass and inertia about its centroid.
fn block_body(
    b: &crate::model::AssemblyBlock,
    builder: ColliderBuilder,
    mu: f32,
    moved: bool,
    offset: Vector3,
    settings: &DropSettings,
    g: Vector3,
) -> (RigidBodyBuilder, ColliderBuilder) {
    let i = b.mass.inertia * b.density;
    let inertia = Matrix::from_cols_array(&std::array::from_fn(|k| i[(k % 3, k / 3)] as f32));
    let collider = builder
        .friction(mu)
        .friction_combine_rule(CoefficientCombineRule::Min)
        .restitution(0.0)
        .restitution_combine_rule(CoefficientCombineRule::Min)
        .contact_skin(0.0)
        .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        .mass_properties(MassProperties::with_inertia_matrix(Vector::ZERO, b.mass() as f32, inertia));
    let body = match (b.support, moved) {
        (true, true) => RigidBodyBuilder::kinematic_position_based(),
        (true, false) => RigidBodyBuilder::fixed(),
        (false, _) => RigidBodyBuilder::dynamic(),
    };
    let mut body = body.translation(v32(b.mass.centroid.coords - offset)).can_sleep(false);
    if !b.support && settings.perturbation > 0.0 {
        let speed = settings.perturbation * (g.norm() * b.aabb.diagonal()).sqrt();
        body = body.linvel(Vector::new(speed as f32, 0.0, 0.0));
    }
    (body, collider)
}

/// Dead loads (self-weight is the gravity): a constant world force and torque about the
/// centroid — the small motions of a drop test do not turn a point load's arm.
fn apply_dead_loads(world: &mut PhysicsWorld, assembly: &Assembly, bodies: &[RigidBodyHandle]) {
    for (i, &h) in bodies.iter().enumerate() {
        let d = assembly.loads[i].dead;
        if let Some(body) = world.bodies.get_mut(h).filter(|_| d != [0.0; 6]) {
            body.add_force(v32(Vector3::new(d[0], d[1], d[2])), true);
            body.add_torque(v32(Vector3::new(d[3], d[4], d[5])), true);
        }
    }
}

/// A fixed ground slab, `half` out each way and a block size thick, its top at z = 0.
fn insert_ground(world: &mut PhysicsWorld, half: f64, unit: f64, mu: f32, level: f64) -> ColliderHandle {
    let depth = (0.5 * unit) as f32;
    let ground = RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, level as f32 - depth));
    let collider = ColliderBuilder::cuboid(half as f32, half as f32, depth)
        .friction(mu)
        .friction_combine_rule(CoefficientCombineRule::Min)
        .restitution(0.0)
        .contact_skin(0.0);
    world.insert(ground, collider).1
}
