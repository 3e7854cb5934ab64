//! The exact-contact engine: rigid blocks with hard (unilateral) contacts and Coulomb friction,
//! stepped by solving one convex problem per moving component and step — the time stepping of
//! the non-smooth dynamics codes (Moreau–Jean; Anitescu–Tasora's cone complementarity), with
//! voussoir's exact contact polygons and interior-point solves. Beside rapier's soft contacts
//! it has a limit: as dt → 0 it is the rigid-block answer, and its first step from rest is the
//! kinematic check's rate problem (so a design starts to move exactly where the statics say).
//!
//! ## A step (dt = h), per connected component of moving blocks
//! - Momentum: M (v⁺ − v) = h w + Σ_p G_p γ_p (w the weight and dead loads, γ_p the impulse
//!   at contact point p in its frame (n, u, v), G_p its wrench on the two blocks: + on b, − on a).
//! - Signorini at velocity level: max(gap_p, 0)/h + n·(v⁺_b − v⁺_a)(p) ≥ 0 ⊥ γ_n,p ≥ 0: an
//!   open contact may close within the step, a closed one stops closing. Nothing pushes an
//!   overlap out through the velocities (that would create energy): overlaps beyond a setting
//!   are projected out at the step's end without touching velocities (`projection`: the least
//!   mass-weighted displacement, by an active set of normal rows).
//! - Friction: γ_t,p within the friction model's set (cone, pyramid8, box4) of capacity c_p,
//!   opposing the slip; [`Coulomb::Exact`] takes c_p = μ γ_n,p by a fixed point within the step
//!   (warm-started from the last step's normal forces; a round whose changed capacities bind
//!   nowhere is the fixed point, else Anderson acceleration picks the next capacities:
//!   `anderson`; rounds that stall or reach the limit keep their best round: `best`);
//!   [`Coulomb::Relaxed`] couples them in the
//!   one solve (Anitescu's relaxation: sliding contacts separate at μ |v_t|).
//! - Gauss's principle in impulses makes it one QP/SOCP: minimise ½ |M v⁺|²_{M⁻¹} + Σ_p (gap_p/h) γ_n,p
//!   over the friction sets; v⁺ is unique (M positive definite) however redundant the contacts.
//! - Positions: x += h v⁺, R ← exp(h ω⁺) R (symplectic Euler). Restitution 0 (masonry: plastic
//!   impacts). A step in which an open contact closes is split at the impact's time
//!   (`impacts`): the impact acts at its instant, second order in h.
//! - With [`ExactSettings::rest_when_admissible`][crate::dynamics::settings::ExactSettings]
//!   (the settlement's runs), a component at rest first takes the step with Coulomb's coupled
//!   sets (the limit-analysis model): where that keeps it at rest, its forces are an equilibrium within the exact sets
//!   too (nothing slips) and it stays — the static theorem's pick where the exact sets also
//!   admit a motion (a flat arch whose halves could slide down their vertical joints with no
//!   force on them stands, as its statics say); otherwise those forces start the rounds.
//! - A moving component's step is first taken by its contacts' last states (`active_set`):
//!   open, sticking or sliding one way, the step is one linear system, solved by the method of
//!   multipliers and checked against every exact-Coulomb condition; states that fail are changed
//!   and the system solved again, a few times; where they do not settle, the states
//!   Gauss–Seidel's sweeps give or, where the sweeps settled, their answer (`gauss_seidel`),
//!   then the states Lemke's pivoting on the step's LCP gives (`lcp`: a conflict the passes
//!   cycle through), then one Tresca round's, then each later round's before the next round.
//!   In smooth motion (a block rocking between impacts, an arch's hinges turning) the states
//!   hold and a step costs one small factorisation; impacts and new slips may need the rounds.
//!   Drops only: a settlement's runs take the rounds' pick ([`ExactSettings::by_states`][crate::dynamics::settings::ExactSettings]).
//! - A component touching nothing falls freely: M v⁺ = M v + h w, no solve.
//! - A component whose step leaves every vertex slower than `still` × g h is set at rest; one
//!   at rest whose step leaves it at rest sleeps — the next steps would repeat the same problem
//!   and answer — until a moving block touches it.
//!
//! ## Contacts (`contacts`)
//! The interface polygons' vertices (the statics' force points), as pairs of material points
//! on the two blocks, normal turning with block a; and every vertex of a free block against
//! the ground or the floor ([`crate::dynamics::scene::floor_level`]). Released when the faces slip apart by more than the interface's
//! diameter, turned apart by 60°, or pass each other by a fifth of a block. Contacts that close
//! under large motion come from the blocks' exact convex parts (`touches`). Every tolerance
//! of a contact (its envelope, how deep is too deep) is a fraction of its own smaller block,
//! whatever the other blocks' sizes.
//!
//! ## Crushing (`crushing`)
//! With a compressive strength (the material's, or [`DropSettings::strength`]), each interface's
//! normal forces stay within its rectangular stress block (the statics' crushing cones); a joint
//! at that bound yields and its faces close into each other.
//!
//! ## What a run reports ([`ExactStats`])
//! Solves, rounds, iterations; the worst solver status and largest momentum residual; the
//! largest overlap (a fraction of the median block size); the energy balance: the work of
//! the loads = kinetic energy + the contacts' dissipation (friction, closing contacts) + the
//! impacts' (½ Δvᵀ M Δv, plastic) — an identity of the scheme, so its error measures the solves.
//!
//! Units SI (m, kg, s, N), z up; solved non-dimensionally (`bodies::Units`). Same input,
//! same trajectory (the same solves in the same order).

mod active_set;
mod anderson;
mod best;
mod bodies;
mod component;
mod contact_form;
mod contacts;
mod crushing;
mod gauss_seidel;
mod impacts;
mod lcp;
mod pivoting;
mod problem;
mod projection;
mod step;
mod touches;

use crate::dynamics::scene::SupportPath;
use crate::dynamics::settings::Coulomb;
use crate::dynamics::settings::DropSettings;
use crate::geometry::{Point3, Vector3};
use crate::model::{Assembly, FrictionModel};
use crate::statics::{Accuracy, SolverStatus, WarmStart};
use bodies::{Body, Units};
use contacts::{Contact, Poses, Side};
use problem::{Active, StepContext};
use serde::Serialize;
use std::collections::HashMap;

/// Faces turned further apart than this cosine (60°) no longer make a contact.
const FACING: f64 = 0.5;

/// Faces overlapping by more than this fraction of the median block size are not in contact
/// (a block that passed another's face plane far from it), whatever their planes say.
const DEEP: f64 = 0.2;

/// The energy balance of a run, J.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct EnergyBalance {
    /// Work of the weight and dead loads on the blocks' motion.
    pub load_work: f64,
    /// Kinetic energy now.
    pub kinetic: f64,
    /// Dissipated at the contacts: friction, and contacts closing within a step.
    pub contact: f64,
    /// Dissipated by the velocity jumps of plastic impacts (½ Δvᵀ M Δv summed).
    pub impact: f64,
    /// Work of the moved supports on the blocks (0 when none moves).
    pub support_work: f64,
    /// The least contact work of any one component's step (J; ≤ 0 only by the solver's
    /// tolerance: a contact that closes, slides or releases dissipates).
    pub least_step_contact: f64,
    /// Work of the loads on the overlaps' position corrections and on the drift not paid for
    /// by a kick (a screw's turn, a split step's halves) (J; not part of the balance: these move
    /// blocks without changing their velocities).
    pub correction: f64,
    /// Kinetic energy changed without a force: by timing a split step's velocities to its
    /// start, and by turning a block other than about its spin (a split step's mean spin, an
    /// overlap's projection) (J; in the balance, with its sign).
    pub retiming: f64,
    /// |load_work + support_work + retiming − kinetic − contact − impact| relative to max(load_work, the free weight × the median block size × 1e-6).
    pub error: f64,
}

/// The exact engine's account of a run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExactStats {
    /// How friction was bounded: exact Coulomb by rounds, or Anitescu's relaxation.
    pub coulomb: Coulomb,
    /// The friction set of every contact point (cone, pyramid8, box4).
    pub friction_model: FrictionModel,
    /// Interior-point solves over the run.
    pub solves: u64,
    /// Their interior-point iterations.
    pub iterations: u64,
    /// Of the solves, those clarabel did not run: on the structured solver, or in closed form
    /// (a force selection whose contacts all open).
    pub structured_solves: u64,
    /// The most Tresca rounds any one step took.
    pub max_rounds: u32,
    /// Steps of a component whose capacities did not settle within the round limit.
    pub unsettled_steps: u64,
    /// Steps of a component whose solve reached no answer (the component kept its velocities:
    /// what follows is not the dynamics').
    pub failed_steps: u64,
    /// Steps of a component skipped because it slept.
    pub sleeping_steps: u64,
    /// Steps split at an impact's instant (each one solve more).
    pub split_steps: u64,
    /// Steps of a moving component taken by its contacts' states (one linear solve, no
    /// interior point: `active_set`).
    pub state_steps: u64,
    /// Overlaps projected out at a step's end (by an active set of normal rows, else by one
    /// interior-point solve more).
    pub projections: u64,
    /// The worst solve's status.
    pub status: SolverStatus,
    /// The largest momentum residual of a solve, N.
    pub residual: f64,
    /// The deepest overlap at a contact over the run, a fraction of the smaller of its two
    /// blocks' sizes.
    pub max_penetration: f64,
    /// The run's energy account, J.
    pub energy: EnergyBalance,
}

/// The engine's world: free blocks and their contacts.
#[derive(Clone)]
pub struct World {
    bodies: Vec<Body>,
    /// The moved supports as bodies driven along their paths, and the paths.
    movers: Vec<Body>,
    paths: Vec<SupportPath>,
    /// Per moved support, the force (N) and moment about its centroid (N·m) the blocks put on
    /// it over the last step.
    reactions: Vec<[Vector3; 2]>,
    /// The interface and ground contacts (the first `persistent`), then the step's touches.
    contacts: Vec<Contact>,
    persistent: usize,
    /// Per assembly block, whether an interface contact holds it at the start.
    interfaced: Vec<bool>,
    /// Each assembly block's side in a contact.
    sides: Vec<Side>,
    solids: touches::Solids,
    /// Every interface's stress block, when the stone crushes (else none).
    bearings: Vec<crushing::Bearing>,
    /// The last structured solve's kept iterate per (force selection?, component's first
    /// body), with its layout ([`step`]'s `layout_key`).
    warm_starts: HashMap<(bool, usize), (u64, WarmStart)>,
    /// The states' systems' block patterns by (bodies, links), ordered once for the steps
    /// that share them ([`active_set`]).
    patterns: HashMap<active_set::PatternKey, crate::statics::BlockLu>,
    ctx: StepContext,
    acc: Accuracy,
    settings: crate::dynamics::settings::ExactSettings,
    /// The median block size, m.
    size: f64,
    /// The deepest overlap at a contact over the run, m.
    deepest: f64,
    /// Per interface vertex contact, its tangential offset at the last [`Self::mark_slips`] (m,
    /// in a's axes; empty before any).
    slip_marks: Vec<Vector3>,
    /// The base's acceleration (m/s²) and each free body's force without it (N): a shaken
    /// design steps in the base's frame ([`Self::set_base_acceleration`]).
    base_acceleration: Vector3,
    steady_force: Vec<Vector3>,
    stats: ExactStats,
}

impl World {
    /// The engine at the assembly's start, every block at rest, no support moving.
    pub fn new(assembly: &Assembly, settings: &DropSettings) -> Self {
        Self::with_paths(assembly, settings, &[])
    }

    /// A world whose supports `paths` name move along them ([`Self::step_supports`]); each
    /// path's block must be a support (the caller checks).
    pub fn with_paths(assembly: &Assembly, settings: &DropSettings, paths: &[SupportPath]) -> Self {
        let s = &settings.exact;
        let g = assembly.gravity.norm().max(f64::MIN_POSITIVE);
        let mut sides = vec![Side::Fixed; assembly.blocks.len()];
        let mut bodies = Vec::new();
        for (i, b) in assembly.blocks.iter().enumerate().filter(|(_, b)| !b.support) {
            sides[i] = Side::Free(bodies.len());
            let mut body = Body::new(i, b, assembly.gravity, assembly.loads[i].dead);
            if settings.perturbation > 0.0 {
                body.v.x = settings.perturbation * (g * b.aabb.diagonal()).sqrt();
                // A given speed is an instant's: the first step kicks by half (`impacts`). A
                // block at rest takes a whole kick: its first step is the kinematic check's.
                body.instant = true;
            }
            bodies.push(body);
        }
        let movers: Vec<Body> = paths
            .iter()
            .enumerate()
            .map(|(m, p)| {
                sides[p.block] = Side::Moved(m);
                Body::new(p.block, &assembly.blocks[p.block], Vector3::zeros(), [0.0; 6])
            })
            .collect();
        let interfaces = crate::interfaces::detect(assembly);
        let strength = settings.strength.or(assembly.material.strength);
        let floor = crate::dynamics::scene::floor_level(assembly, settings);
        let contacts =
            contacts::build(assembly, &interfaces, &sides, Poses { bodies: &bodies, movers: &movers }, floor);
        let size = assembly.median_block_size().unwrap_or(1.0).max(f64::MIN_POSITIVE);
        let solids = touches::Solids::new(&assembly.blocks);
        let weight: f64 = bodies.iter().map(|b| b.mass * g).sum();
        let units = Units { length: assembly.scale.max(f64::MIN_POSITIVE), force: weight.max(f64::MIN_POSITIVE), g };
        let ctx = StepContext {
            units,
            h: settings.dt,
            mu: settings.friction.unwrap_or(assembly.material.friction),
            model: s.friction_model,
            coulomb: s.coulomb,
            recovery: 0.0,
            strength: strength.map(|sigma| sigma * units.length * units.length / units.force),
        };
        let bearings = if strength.is_some() { crushing::bearings(&interfaces, units.length) } else { Vec::new() };
        let stats = ExactStats {
            coulomb: s.coulomb,
            friction_model: s.friction_model,
            solves: 0,
            iterations: 0,
            structured_solves: 0,
            max_rounds: 0,
            unsettled_steps: 0,
            failed_steps: 0,
            sleeping_steps: 0,
            split_steps: 0,
            state_steps: 0,
            projections: 0,
            status: SolverStatus::Solved,
            residual: 0.0,
            max_penetration: 0.0,
            energy: EnergyBalance::default(),
        };
        let acc = Accuracy::uniform(s.solver_tolerance);
        let reactions = vec![[Vector3::zeros(); 2]; movers.len()];
        let mut interfaced = vec![false; assembly.blocks.len()];
        contacts.iter().filter_map(|c| c.pair).flatten().for_each(|k| interfaced[k] = true);
        let steady_force = bodies.iter().map(|b| Vector3::new(b.load[0], b.load[1], b.load[2])).collect();
        Self {
            bodies,
            movers,
            paths: paths.to_vec(),
            reactions,
            persistent: contacts.len(),
            interfaced,
            contacts,
            sides,
            solids,
            bearings,
            warm_starts: HashMap::new(),
            patterns: HashMap::new(),
            ctx,
            acc,
            settings: s.clone(),
            size,
            deepest: 0.0,
            slip_marks: Vec::new(),
            base_acceleration: Vector3::zeros(),
            steady_force,
            stats,
        }
    }

    /// The base's acceleration `a` (m/s², world axes) for the next steps: the engine steps in
    /// the base's frame, where every free block carries the inertial load −m a beside its
    /// weight (its work counts in the energy account's load work). A change wakes every block.
    pub fn set_base_acceleration(&mut self, a: Vector3) {
        if a == self.base_acceleration {
            return;
        }
        self.base_acceleration = a;
        for (b, steady) in self.bodies.iter_mut().zip(&self.steady_force) {
            let force = steady - a * b.mass;
            b.load[..3].copy_from_slice(force.as_slice());
            b.asleep = false;
        }
    }

    fn poses(&self) -> Poses<'_> {
        Poses { bodies: &self.bodies, movers: &self.movers }
    }

    /// One step of every component that is awake, the supports held still.
    pub fn step(&mut self) {
        self.step_supports(0.0);
    }

    /// One step in which every moved support covers `fraction` of its path (at the constant
    /// speed that takes it there within the step; 0 holds it still). A moving support wakes
    /// every block it touches.
    pub fn step_supports(&mut self, fraction: f64) {
        let h = self.ctx.h;
        for (mover, path) in self.movers.iter_mut().zip(&self.paths) {
            mover.v = path.translation * (fraction / h);
            mover.w = path.rotation * (fraction / h);
        }
        self.step_movers(fraction != 0.0);
    }

    /// One step in which every moved support translates by `displacement` (m, at the constant
    /// speed that takes it there within the step): named supports shaken by a ground motion.
    pub fn step_supports_by(&mut self, displacement: Vector3) {
        let h = self.ctx.h;
        for mover in &mut self.movers {
            (mover.v, mover.w) = (displacement / h, Vector3::zeros());
        }
        self.step_movers(displacement != Vector3::zeros());
    }

    /// One step with the movers' velocities set; `moving` wakes every block they touch.
    fn step_movers(&mut self, moving: bool) {
        let h = self.ctx.h;
        if moving {
            for c in &self.contacts {
                if c.mover().is_some() {
                    for side in [c.a, c.b] {
                        if let Side::Free(k) = side {
                            self.bodies[k].asleep = false;
                        }
                    }
                }
            }
        }
        self.reactions.iter_mut().for_each(|r| *r = [Vector3::zeros(); 2]);
        let known = self.find_touches();
        let near = self.near_contacts(&known);
        for comp in self.components(&near) {
            if comp.iter().all(|&k| self.bodies[k].asleep) {
                self.stats.sleeping_steps += 1;
                continue;
            }
            comp.iter().for_each(|&k| self.bodies[k].asleep = false);
            self.step_timed(&comp, &near);
        }
        for m in &mut self.movers {
            m.advance_along_path(h);
        }
        self.project_overlaps(&near);
    }

    /// Advances component `comp`'s awake bodies by `h` s with the velocities of its last solve.
    fn advance(&mut self, comp: &[usize], h: f64) {
        for &k in comp {
            let b = &mut self.bodies[k];
            if !b.asleep {
                let beyond = b.advance(h);
                self.stats.energy.correction += b.load_power(&beyond, &Vector3::zeros());
            }
        }
    }

    /// The fastest vertex of any block now, m/s (bounded by |v| + |ω| r).
    pub fn fastest_vertex(&self) -> f64 {
        self.bodies.iter().map(|b| b.v.norm() + b.w.norm() * b.radius).fold(0.0, f64::max)
    }

    /// Sets the time step, s (a quasi-static analysis takes each increment in one step long
    /// enough for the blocks to follow the supports under their weight).
    pub fn set_step(&mut self, h: f64) {
        self.ctx.h = h;
    }

    /// One step with the supports still (no step pushes overlaps out through the velocities, so
    /// a contact overlapping by the round-off of earlier steps counts as touching): from rest,
    /// the blocks stay at rest exactly when an equilibrium holds them — a quasi-static
    /// analysis's check.
    pub fn step_held(&mut self) {
        self.step_supports(0.0);
    }

    /// Stops every block (a quasi-static analysis: no velocity carried from one increment to
    /// the next).
    pub fn stop(&mut self) {
        for b in &mut self.bodies {
            b.v = Vector3::zeros();
            b.w = Vector3::zeros();
        }
    }

    /// Whether every block is at rest (after a step that found no motion, or [`Self::stop`]).
    pub fn at_rest(&self) -> bool {
        self.bodies.iter().all(Body::at_rest)
    }

    /// The force (N) and moment about its centroid now (N·m) the blocks put on moved support
    /// `m` over the last step.
    pub fn support_reaction(&self, m: usize) -> [Vector3; 2] {
        self.reactions[m]
    }

    /// g × the time step, m/s: how fast a block falls freely in one step.
    pub fn free_fall_speed(&self) -> f64 {
        self.ctx.units.g * self.ctx.h
    }

    /// The largest rotation of a free block since the start, rad.
    pub fn largest_rotation(&self) -> f64 {
        self.bodies.iter().map(|b| b.q.angle()).fold(0.0, f64::max)
    }

    /// The free blocks' centroids now, m (in body order).
    pub fn centroids(&self) -> Vec<Point3> {
        self.bodies.iter().map(|b| b.x).collect()
    }

    /// How many supports move.
    pub fn moved_supports(&self) -> usize {
        self.movers.len()
    }

    /// Per interface vertex contact now: its interface, vertex, and the velocity of b's point
    /// relative to a's, normal (> 0 opening) and tangential speed, m/s; in the contacts' order.
    pub fn joint_rates(&self) -> Vec<(usize, usize, f64, f64)> {
        self.per_joint_contact(|c, g, poses| {
            let v = c.relative_velocity(poses, &g.point);
            let vn = v.dot(&g.frame[0]);
            (vn, (v - g.frame[0] * vn).norm())
        })
    }

    /// Per interface vertex contact now: its interface, vertex, gap (m, > 0 open) and slip
    /// since the last [`Self::mark_slips`] (m; since the start before any), in the contacts'
    /// order.
    pub fn joint_gaps(&self) -> Vec<(usize, usize, f64, f64)> {
        let offsets = self.joint_offsets().into_iter();
        let marks = self.slip_marks.iter().copied().chain(std::iter::repeat(Vector3::zeros()));
        offsets.zip(marks).map(|((i, v, gap, t), m)| (i, v, gap, (t - m).norm())).collect()
    }

    /// Takes the joints' tangential offsets now as the origin of [`Self::joint_gaps`]' slips: a
    /// stage's reading is then how far a joint slipped since the last stage. (A hinge on a
    /// translating support drifts along its face by ½ h² ω × u a step — the screw of the
    /// block's twist against the support's straight path, O(h) over a path — which summed from
    /// the start would read as a slide.)
    pub fn mark_slips(&mut self) {
        self.slip_marks = self.joint_offsets().into_iter().map(|o| o.3).collect();
    }

    /// Per interface vertex contact now: its interface, vertex, gap (m) and the tangential
    /// offset of b's point from a's, in a's axes (m), in the contacts' order.
    fn joint_offsets(&self) -> Vec<(usize, usize, f64, Vector3)> {
        let poses = self.poses();
        let offset = |c: &Contact, g: &contacts::Geometry| {
            // The geometry's point is the two points' middle.
            let d = (c.point_b(poses) - g.point) * 2.0;
            let t = d - g.frame[0] * g.gap;
            poses.of(c.a).map_or(t, |a| a.q.inverse() * t)
        };
        self.contacts
            .iter()
            .filter_map(|c| match c.origin {
                contacts::Origin::Interface { interface, vertex } => {
                    let g = c.geometry(poses);
                    Some((interface, vertex, g.gap, offset(c, &g)))
                }
                contacts::Origin::Ground { .. } | contacts::Origin::Touch { .. } => None,
            })
            .collect()
    }

    /// `measure` of every interface vertex contact at its geometry now, with its interface and
    /// vertex, in the contacts' order (ground contacts left out).
    fn per_joint_contact(
        &self,
        measure: impl Fn(&Contact, &contacts::Geometry, Poses) -> (f64, f64),
    ) -> Vec<(usize, usize, f64, f64)> {
        let poses = self.poses();
        self.contacts
            .iter()
            .filter_map(|c| match c.origin {
                contacts::Origin::Interface { interface, vertex } => {
                    let (x, y) = measure(c, &c.geometry(poses), poses);
                    Some((interface, vertex, x, y))
                }
                contacts::Origin::Ground { .. } | contacts::Origin::Touch { .. } => None,
            })
            .collect()
    }

    /// The median block size, m (the engine's length for joint states and the energy scale;
    /// a contact's tolerances are in its own blocks' size).
    pub fn block_size(&self) -> f64 {
        self.size
    }

    /// The deepest overlap at a contact over the run, m.
    pub fn deepest_overlap(&self) -> f64 {
        self.deepest
    }

    /// The contacts that may act within the step: not slipped off, and closer than the envelope
    /// or closing it within two steps. With their geometry now. Those of the awake bodies, and
    /// through them of every sleeping body they reach (a support that moves the end of a
    /// sleeping chain moves the whole chain), in the contacts' order.
    ///
    /// Contact i's [`Self::near`] is `known[i]` where that holds one (read at the same poses).
    fn near_contacts(&self, known: &[Option<Option<Active>>]) -> Vec<Active> {
        let mut reached: Vec<bool> = self.bodies.iter().map(|b| !b.asleep).collect();
        let mut seen = vec![false; self.contacts.len()];
        let mut out = Vec::new();
        loop {
            let mut grew = false;
            for (i, c) in self.contacts.iter().enumerate() {
                let free = [c.a, c.b].map(|s| if let Side::Free(k) = s { Some(k) } else { None });
                if seen[i] || !free.iter().flatten().any(|&k| reached[k]) {
                    continue;
                }
                seen[i] = true;
                if let Some(active) = known.get(i).copied().flatten().unwrap_or_else(|| self.near(i, c)) {
                    out.push(active);
                    for k in free.into_iter().flatten() {
                        grew |= !reached[k];
                        reached[k] = true;
                    }
                }
            }
            if !grew {
                break;
            }
        }
        out.sort_by_key(|a| a.contact);
        out
    }

    /// Contact `i` if it may act within the step (see [`Self::near_contacts`]).
    fn near(&self, i: usize, c: &Contact) -> Option<Active> {
        let envelope = self.settings.envelope * c.scale;
        let poses = self.poses();
        let g = c.geometry(poses);
        let closing = -c.relative_velocity(poses, &g.point).dot(&g.frame[0]);
        let faces = g.slip <= c.reach && g.facing >= FACING && g.gap >= -DEEP * c.scale;
        // Deeper than a hinge's overlap: is it an overlap or a vertex beside the face?
        let interface = matches!(c.origin, contacts::Origin::Interface { .. });
        let faces = faces && !(interface && g.gap < -envelope && !self.really_overlaps(c));
        // A touch is near by being found (its pair is within reach).
        let touch = matches!(c.origin, contacts::Origin::Touch { .. });
        (faces && (touch || g.gap <= envelope + 2.0 * self.ctx.h * closing.max(0.0))).then_some(Active {
            contact: i,
            geometry: g,
            prescribed: c.prescribed_velocity(poses, &g.point),
            capacity: 0.0,
        })
    }

    /// The awake bodies in groups linked by near contacts (sleeping ones join the group of a
    /// moving block that touches them), each ascending, in order of their first body.
    fn components(&self, near: &[Active]) -> Vec<Vec<usize>> {
        let n = self.bodies.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        for a in near {
            let c = &self.contacts[a.contact];
            if let (Side::Free(i), Side::Free(j)) = (c.a, c.b) {
                let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut index = vec![usize::MAX; n];
        for k in 0..n {
            let r = find(&mut parent, k);
            if index[r] == usize::MAX {
                index[r] = groups.len();
                groups.push(Vec::new());
            }
            groups[index[r]].push(k);
        }
        groups
    }

    /// Block `i`'s centroid drift (m) and rotation (rad) since the start; (0, 0) for a support.
    pub fn displacement(&self, i: usize) -> (f64, f64) {
        self.free(i).map_or((0.0, 0.0), |k| {
            let b = &self.bodies[k];
            ((b.x - b.start).norm(), b.q.angle())
        })
    }

    /// Block `i`'s centroid (m) and rotation since the start ([w, x, y, z]); a moved support's
    /// along its path, a fixed one's `start`.
    pub fn pose(&self, i: usize, start: Point3) -> (Point3, [f64; 4]) {
        let body = match self.sides[i] {
            Side::Free(k) => &self.bodies[k],
            Side::Moved(m) => &self.movers[m],
            Side::Fixed => return (start, [1.0, 0.0, 0.0, 0.0]),
        };
        (body.x, [body.q.w, body.q.i, body.q.j, body.q.k])
    }

    /// Block `i`'s body when it is free.
    fn free(&self, i: usize) -> Option<usize> {
        match self.sides[i] {
            Side::Free(k) => Some(k),
            _ => None,
        }
    }

    /// Every block's pose now ([`Self::pose`]), in block order.
    pub fn all_poses(&self) -> Vec<(Point3, [f64; 4])> {
        self.solids.starts().enumerate().map(|(i, c)| self.pose(i, c)).collect()
    }

    /// Block `i`'s velocity (m/s) and angular velocity (rad/s); zero for a support.
    pub fn velocity(&self, i: usize) -> (crate::geometry::Vector3, crate::geometry::Vector3) {
        self.free(i).map_or((Default::default(), Default::default()), |k| (self.bodies[k].v, self.bodies[k].w))
    }

    /// Block `i`'s kinetic energy, J (0 for a support).
    pub fn kinetic_energy(&self, i: usize) -> f64 {
        self.free(i).map_or(0.0, |k| self.bodies[k].kinetic_energy())
    }

    /// The run so far.
    pub fn stats(&self) -> ExactStats {
        let mut s = self.stats.clone();
        let e = &mut s.energy;
        e.kinetic = self.bodies.iter().map(Body::kinetic_energy).sum();
        let scale = e.load_work.abs().max(1e-6 * self.ctx.units.force * self.size);
        e.error = (e.load_work + e.support_work + e.retiming - e.kinetic - e.contact - e.impact).abs() / scale;
        s
    }
}
