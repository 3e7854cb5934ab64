//! Overlaps projected out without doing work. A step's contacts keep Signorini's condition at
//! velocity level (a closed contact stops closing); rotations about a hinge and round-off let
//! the faces drift into each other by O(dt² ω² r) per step. Pushing them apart through the
//! velocities (a penalty or a recovery speed) would feed kinetic energy from nothing, so
//! instead, once a contact overlaps by more than [`crate::dynamics::settings::ExactSettings::projection`]
//! of its scale, the component's blocks are moved apart by the least mass-weighted
//! displacement Δ that leaves every contact unpenetrated:
//!
//! minimise ½ Δᵀ M Δ subject to gap_p + n_p · (Δ_b − Δ_a)(p) ≥ 0,
//!
//! the step problem with no velocity, no load and no friction (dt = the time unit). It is
//! solved by an active set of normal rows on the states' linear solve (`active_set`): the
//! overlapping contacts held at gap 0, then those that pull released and those still
//! overlapping held, until M Δ = Σ n λ, λ ≥ 0, gaps ≥ 0 and λ × gap = 0 all hold — the QP's
//! unique minimiser, every held contact left exactly touching. Where that does not settle, the
//! step's builder with those terms zeroed goes to the interior point (clarabel), whose barrier
//! leaves the contacts slightly open. Velocities are untouched; the loads' work on Δ is
//! accounted apart ([`super::EnergyBalance::correction`]).

use super::World;
use super::active_set::{Tolerances, Unknown};
use super::bodies::Body;
use super::component::{Component, relative_velocity};
use super::problem::{self, Active, StepContext};
use crate::dynamics::settings::Coulomb;
use crate::geometry::Vector3;
use crate::statics::solve_conic;
use nalgebra::DVector;

/// Passes of the frictionless active set before the interior point takes the projection.
const PASSES: usize = 20;

/// A gap left or a pull counted as none: this fraction of the smallest contact's scale (and
/// that length × the component's mass, per the time unit, as an impulse).
const TOLERANCE: f64 = 1e-9;

/// One component's projection problem: the bodies held still (no velocity, no load), the
/// component's bodies and their local indices, its contacts, and the time unit (s) its
/// displacements are per.
#[derive(Clone, Copy)]
struct Problem<'a> {
    still: &'a [Body],
    comp: &'a [usize],
    local: &'a [usize],
    active: &'a [Active],
    unit: f64,
}

impl World {
    /// Projects out the overlaps deeper than the setting among `near`'s contacts at the poses
    /// now, component by component.
    pub(super) fn project_overlaps(&mut self, near: &[Active]) {
        // A crushing joint's faces close into each other by design ([`super::crushing`]).
        if self.ctx.strength.is_some() {
            return;
        }
        let depth = self.settings.projection;
        let now: Vec<Active> = near.iter().filter_map(|a| self.near(a.contact, &self.contacts[a.contact])).collect();
        let deep: Vec<bool> = now.iter().map(|a| a.geometry.gap < -depth * self.contacts[a.contact].scale).collect();
        if !deep.iter().any(|&d| d) {
            return;
        }
        for comp in self.components(&now) {
            let mine = |a: &Active| comp.iter().any(|&k| self.contacts[a.contact].touches(k));
            if !now.iter().zip(&deep).any(|(a, &d)| d && mine(a)) {
                continue;
            }
            let active: Vec<Active> = now
                .iter()
                .filter(|a| mine(a))
                .map(|a| Active { prescribed: Vector3::zeros(), capacity: 0.0, ..*a })
                .collect();
            self.project(&comp, &active);
        }
    }

    /// Moves component `comp`'s bodies by the projection of the module docs over `active`: by
    /// an active set of normal rows (the states' linear solve, [`super::active_set`]) where
    /// [`ExactSettings::by_states`][crate::dynamics::settings::ExactSettings] asks for it and it
    /// settles, else by one interior-point solve.
    fn project(&mut self, comp: &[usize], active: &[Active]) {
        let mut local = vec![usize::MAX; self.bodies.len()];
        comp.iter().enumerate().for_each(|(j, &k)| local[k] = j);
        let still: Vec<Body> = self
            .bodies
            .iter()
            .map(|b| Body { v: Vector3::zeros(), w: Vector3::zeros(), load: [0.0; 6], ..b.clone() })
            .collect();
        // dt = the time unit: the step's "velocities" are then displacements per that unit, and
        // an unbounded push-out lets the gaps enter whole.
        let unit = self.ctx.units.time();
        self.stats.projections += 1;
        let projection = Problem { still: &still, comp, local: &local, active, unit };
        let by_active_set = self.settings.by_states.then(|| self.by_active_set(&projection));
        let Some(moves) = by_active_set.flatten().or_else(|| self.on_clarabel(&projection)) else {
            return;
        };
        for (&k, &(dx, dq)) in comp.iter().zip(&moves) {
            let b = &mut self.bodies[k];
            self.stats.energy.correction += unit * b.load_power(&dx, &dq);
            let (v, w) = (b.v, b.w);
            let before = b.kinetic_energy();
            (b.v, b.w) = (dx, dq);
            let beyond = b.advance(unit);
            (b.v, b.w) = (v, w);
            // A turned block's spin keeps its world vector: its kinetic energy moves with it.
            self.stats.energy.retiming += b.kinetic_energy() - before;
            self.stats.energy.correction += b.load_power(&beyond, &Vector3::zeros());
        }
    }

    /// The projection's displacements per `unit` s by an active set of frictionless normal
    /// rows: the overlapping contacts held at gap 0, then those that pull released and those
    /// still overlapping held, until the answer meets the problem's optimality conditions
    /// (M Δ = Σ n λ, λ ≥ 0, gaps ≥ 0, λ × gap = 0: the QP's unique Δ). None where it does not
    /// settle within [`PASSES`].
    fn by_active_set(&self, projection: &Problem) -> Option<Vec<(Vector3, Vector3)>> {
        let Problem { still, comp, local, active, unit } = *projection;
        let parts = Component::new(still, comp, local, unit);
        let smallest = active.iter().map(|a| self.contacts[a.contact].scale).fold(f64::INFINITY, f64::min);
        let mass: f64 = comp.iter().map(|&k| still[k].mass).sum();
        let tol = Tolerances { speed: TOLERANCE * smallest / unit, impulse: TOLERANCE * mass * smallest / unit };
        let gap = |a: &Active| a.geometry.gap / unit;
        let mut held: Vec<bool> = active.iter().map(|a| a.geometry.gap < 0.0).collect();
        let mut system = self.states_pattern(&parts, active)?;
        for _ in 0..PASSES {
            let unknowns: Vec<Unknown> = (0..active.len())
                .filter(|&i| held[i])
                .map(|i| {
                    let n = active[i].geometry.frame[0];
                    Unknown { contact: i, force: n, row: n, target: -gap(&active[i]) }
                })
                .collect();
            let start = DVector::zeros(unknowns.len());
            let (u, lambda, converged) = self.solve_states(&parts, active, (&unknowns, start), tol, &mut system)?;
            if !converged {
                return None;
            }
            let mut next = held.clone();
            for (q, l) in unknowns.iter().zip(lambda.iter()) {
                next[q.contact] = *l >= -tol.impulse;
            }
            for (i, a) in active.iter().enumerate().filter(|(i, _)| !held[*i]) {
                let c = &self.contacts[a.contact];
                let rel = relative_velocity(&parts, c.a, c.b, &a.geometry.point, &u);
                next[i] = rel.dot(&a.geometry.frame[0]) + gap(a) < -tol.speed;
            }
            if next == held {
                return Some(parts.velocities(&u));
            }
            held = next;
        }
        None
    }

    /// The projection's displacements per `unit` s by one interior-point solve (clarabel),
    /// counted in the run's solves; None where it reaches no answer (its status is kept).
    fn on_clarabel(&mut self, projection: &Problem) -> Option<Vec<(Vector3, Vector3)>> {
        let Problem { still, comp, local, active, unit } = *projection;
        let ctx = StepContext { h: unit, recovery: f64::INFINITY, coulomb: Coulomb::Exact, strength: None, ..self.ctx };
        let p = problem::build(&ctx, still, comp, local, &self.contacts, active, None);
        let out = solve_conic(&p.conic, self.acc, self.settings.max_iterations);
        self.stats.solves += 1;
        self.stats.iterations += u64::from(out.iterations);
        if !out.status.solved() {
            self.stats.status = self.stats.status.max(out.status);
            return None;
        }
        Some(p.read(&ctx, still, comp, active, &out.x).velocities)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::DropSettings;
    use crate::geometry::{Mesh, Point3};
    use crate::model::{Assembly, Block, Scene};
    use nalgebra::UnitQuaternion;

    /// A 2 × 1 m slab (support) under a 0.5 m cube, a 0.3 m cube on that one.
    fn stack() -> World {
        let cuboid = |name: &str, min: [f64; 3], max: [f64; 3]| {
            Block::new(name, Mesh::cuboid(Point3::from(min), Point3::from(max)))
        };
        let scene = Scene::new(
            "stack",
            vec![
                cuboid("slab", [0.0, 0.0, 0.0], [2.0, 1.0, 0.2]).support(true),
                cuboid("a", [0.2, 0.2, 0.2], [0.7, 0.7, 0.7]),
                cuboid("b", [0.3, 0.3, 0.7], [0.6, 0.6, 1.0]),
            ],
        );
        let assembly = Assembly::new(&scene, &Default::default()).unwrap();
        World::new(&assembly, &DropSettings::default())
    }

    /// The projection problem of the stack's bodies at their poses now: still bodies, every
    /// near contact, the time unit.
    fn problem(world: &World) -> (Vec<Body>, Vec<Active>, f64) {
        let still =
            world.bodies.iter().map(|b| Body { v: Vector3::zeros(), w: Vector3::zeros(), load: [0.0; 6], ..b.clone() });
        let near = world.near_contacts(&[]);
        let active = near.iter().map(|a| Active { prescribed: Vector3::zeros(), capacity: 0.0, ..*a }).collect();
        (still.collect(), active, world.ctx.units.time())
    }

    /// ½ Δᵀ M Δ of displacements per unit `moves`, and the least gap they leave (m).
    fn measure(
        world: &World,
        still: &[Body],
        active: &[Active],
        unit: f64,
        moves: &[(Vector3, Vector3)],
    ) -> (f64, f64) {
        let kinetic: f64 = still
            .iter()
            .zip(moves)
            .map(|(b, (dx, dq))| 0.5 * (b.mass * dx.norm_squared() + dq.dot(&(b.inertia_now() * dq))))
            .sum();
        let least = active
            .iter()
            .map(|a| {
                let c = &world.contacts[a.contact];
                let velocity = |side: super::super::Side| match side {
                    super::super::Side::Free(k) => moves[k].0 + moves[k].1.cross(&(a.geometry.point - still[k].x)),
                    _ => Vector3::zeros(),
                };
                a.geometry.gap + unit * (velocity(c.b) - velocity(c.a)).dot(&a.geometry.frame[0])
            })
            .fold(f64::INFINITY, f64::min);
        (kinetic * unit * unit, least)
    }

    /// Invariant (closed form): the lower cube pushed 2 mm into the slab, level, with the upper
    /// cube on it, comes out by exactly 2 mm straight up with the upper cube riding along (the
    /// least mass-weighted displacement that leaves every contact unpenetrated), to 1e-9 m.
    #[test]
    fn a_level_overlap_comes_out_straight_up_by_its_depth() {
        let mut world = stack();
        world.bodies.iter_mut().for_each(|b| b.x.z -= 2e-3);
        let (still, active, unit) = problem(&world);
        let projection = Problem { still: &still, comp: &[0, 1], local: &[0, 1], active: &active, unit };
        let moves = world.by_active_set(&projection).expect("settles");
        for (dx, dq) in &moves {
            let d = dx * unit;
            assert!((d - Vector3::new(0.0, 0.0, 2e-3)).norm() < 1e-9, "{d:?}");
            assert!(dq.norm() * unit < 1e-9, "{dq:?}");
        }
    }

    /// Invariant (the QP's optimality): with the lower cube sunk and the upper one tilted into
    /// it, the active set's displacements leave every contact unpenetrated (to 1e-9 m) and
    /// move the blocks no more (½ Δᵀ M Δ) than the interior point's answer to the same problem.
    #[test]
    fn a_tilted_overlap_takes_the_least_displacement() {
        let mut world = stack();
        world.bodies[0].x.z -= 1e-3;
        world.bodies[1].q = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.02);
        let (still, active, unit) = problem(&world);
        let projection = Problem { still: &still, comp: &[0, 1], local: &[0, 1], active: &active, unit };
        let by_set = world.by_active_set(&projection).expect("settles");
        let by_ip = world.clone().on_clarabel(&projection).expect("solves");
        let (cost, least) = measure(&world, &still, &active, unit, &by_set);
        let (ip_cost, ip_least) = measure(&world, &still, &active, unit, &by_ip);
        assert!(least >= -1e-9, "least gap {least}");
        assert!(ip_least >= -1e-6, "the interior point's least gap {ip_least}");
        assert!(cost <= ip_cost * (1.0 + 1e-9), "{cost} vs the interior point's {ip_cost}");
        assert!(cost > 0.0);
    }
}
