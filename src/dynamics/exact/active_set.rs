//! A step by its contacts' states: the fast path of exact Coulomb steps in smooth motion.
//!
//! The Tresca rounds solve a step's exact-Coulomb problem as a sequence of convex problems
//! (each an interior-point solve, and a force selection): about ten solves a step on a
//! collapsing arch. Between impacts the contacts keep their states from step to step — open,
//! sticking, or sliding one way — and with the states known the step is linear:
//! M (u⁺ − u*) = Σ Jᵀ B λ (u* the free motion, λ the unknown impulses along each state's
//! force directions B: n, u, v for a sticking point; n + μ e for one sliding with its friction at
//! e on the unit friction set; a facet's free direction too), with the states' rows
//! R J u⁺ = r (a sticking point's relative velocity 0 up to its gap term, a sliding one's
//! normal velocity, a facet's slip along its normal only). It is solved by the method of
//! multipliers: (M + ρ JᵀB R J) u = M u* + JᵀB (λ + ρ r), λ ← λ + ρ (r − R J u), one
//! factorisation and a few back-substitutions, from the last step's impulses (contacts that share
//! a face have no unique forces; the last step's split carries on). The system's pattern is the
//! component's contact graph, so it is factorised by the bodies' 6×6 blocks
//! ([`crate::statics::BlockLu`]: the work of a chain of n blocks grows as n, not n³), each solve
//! refined twice against the system's own product. Rows that cannot all hold keep their error
//! from step to step while the multipliers grow along the conflict by the same amount each step:
//! the loop stops at the first step that does not halve the error, the multipliers carried as far
//! as all [`MULTIPLIER_STEPS`] steps would take them (the check reads the conflict from them).
//!
//! Its answer is then checked against every condition of the exact-Coulomb step (each
//! contact's Signorini condition, its friction within μ λ_n, a sliding contact's friction at
//! the set's point opposing its slip): where a state is wrong it is changed (a point pulling
//! opens, one whose friction is beyond its set slides, a slide that reverses sticks, an open
//! point closing sticks) and the step solved again, up to [`PASSES`] times: every change of
//! the most basic kind at once, and once those changes cycle (states met before, a slide's
//! angle to its round-off), one contact's a pass (the lowest-numbered, Murty's rule) for up to
//! [`SINGLE_PASSES`] more. An answer that meets every condition is the rounds' fixed point (the
//! same conditions; velocities unique where the forces are); otherwise the caller tries the
//! states Gauss–Seidel gives ([`super::gauss_seidel`]), then one round's, then runs the rounds.
//! Friction sets: the cone, and the regular polygons (box4, pyramid8: facets at unit distance,
//! `model.facets()`).

use super::World;
use super::component::{Component, Sparse, relative_velocity};
use super::contacts::State;
use super::problem::{Active, Solution};
use crate::geometry::Vector3;
use crate::model::FrictionModel;
use crate::statics::BlockLu;
use nalgebra::{DVector, Matrix6};
use std::f64::consts::PI;

/// A row's error, a closing speed or a slip counted as none, as a fraction of the rest
/// criterion's speed `still` g h.
const SPEED: f64 = 0.1;

/// A pull counted as none, as a fraction of the component's weight × h.
const IMPULSE: f64 = 1e-9;

/// Solves of changed states before the rounds take over.
const PASSES: usize = 10;

/// Further passes of one change each once the block changes cycle.
const SINGLE_PASSES: usize = 20;

/// Friction beyond its capacity by this fraction of it is within it (the Tresca rounds'
/// capacities settle to 1e-4 of the largest: `ExactSettings::settle`).
const SLACK: f64 = 1e-6;

/// Back-substitutions of the method of multipliers within one factorisation.
const MULTIPLIER_STEPS: usize = 10;

/// A multiplier step that leaves the worst row error above this fraction of the last one's has
/// met rows that cannot all hold (a converging step shrinks it ~ρ / m-fold): the next steps would
/// only grow the multipliers along the conflict, whose signs the check reads.
const STALL: f64 = 0.5;

/// Refinement steps of each solve of the states' system ([`refined_solve`]).
const REFINEMENTS: usize = 2;

/// The penalty ρ as a multiple of the component's smallest mass: each multiplier step shrinks
/// a row's error by ~1 / (1 + ρ / m), and the factorisation keeps ~16 − 7 digits.
const PENALTY: f64 = 1e7;

/// A slip direction within this angle (rad) of a facet's normal slides on that facet (the
/// interior point's slips point to ~1e-6 rad).
const ON_FACET: f64 = 1e-5;

/// A cone's sliding direction that turns by less than this (rad) within a step's passes has
/// settled: its friction is μ f_n to 1e-9 of it.
const ON_CONE: f64 = 1e-9;

/// One unknown impulse: its contact, the direction its force acts along at the contact point
/// (on b; −on a) and the direction of the relative velocity its row holds at `target`.
pub(super) struct Unknown {
    pub contact: usize,
    pub force: Vector3,
    pub row: Vector3,
    pub target: f64,
}

/// The friction set's place for a friction force pointing at `angle`: on the cone, that
/// direction; on a polygon of `sides` facets at unit distance, the facet whose normal it is
/// (with the facet's free direction) or the vertex nearest it.
fn friction_point(sides: Option<usize>, angle: f64) -> (Vector3, Option<Vector3>) {
    let Some(n) = sides else { return (Vector3::new(angle.cos(), angle.sin(), 0.0), None) };
    let spacing = 2.0 * PI / n as f64;
    let facet = (angle / spacing).round() * spacing;
    if (angle - facet).abs() <= ON_FACET {
        let d = Vector3::new(facet.cos(), facet.sin(), 0.0);
        return (d, Some(Vector3::new(-facet.sin(), facet.cos(), 0.0)));
    }
    let vertex = (angle / spacing).floor() * spacing + 0.5 * spacing;
    let r = 1.0 / (0.5 * spacing).cos();
    (Vector3::new(vertex.cos(), vertex.sin(), 0.0) * r, None)
}

/// The next state of a contact sliding with its friction at `angle` (a facet's normal, or
/// inside a vertex's cone), by its slip `vt` and its friction `gt` against the capacity:
/// a slip that turns back sticks; friction beyond a facet's end goes to that end's
/// vertex; a slip that leaves a vertex's cone goes to the facet it crosses (the polygon's
/// states move one face at a time, so they do not cycle between neighbouring vertices); on the
/// cone the slip's direction.
fn slide_state(
    sides: Option<usize>,
    angle: f64,
    frame: &[Vector3; 3],
    vt: &Vector3,
    (gt, capacity): ((f64, f64), f64),
    tol: Tolerances,
) -> State {
    let (e, free) = friction_point(sides, angle);
    let along = -(vt.dot(&frame[1]) * e.x + vt.dot(&frame[2]) * e.y);
    if along < -tol.speed {
        return State::Stick;
    }
    // Sliding at no speed yet (a slip that starts): friction at capacity holds it, whatever
    // the round-off direction of its slip.
    if vt.norm() <= tol.speed && gauge(sides, gt) <= capacity * (1.0 + SLACK) + tol.impulse {
        return State::Slide { angle };
    }
    let turned = angle_in(frame, &(-vt));
    let Some(n) = sides else {
        return State::Slide { angle: if (turned - angle).abs() > ON_CONE { turned } else { angle } };
    };
    let spacing = 2.0 * PI / n as f64;
    if free.is_some() {
        if gauge(sides, gt) <= capacity + tol.impulse {
            return State::Slide { angle };
        }
        // The friction along the facet beyond its end: that end's vertex.
        let across = -gt.0 * angle.sin() + gt.1 * angle.cos();
        return State::Slide { angle: angle + 0.5 * spacing * across.signum() };
    }
    let vertex = (angle / spacing).floor() * spacing + 0.5 * spacing;
    let off = wrap(turned - vertex);
    if off.abs() <= 0.5 * spacing + ON_FACET {
        State::Slide { angle }
    } else {
        State::Slide { angle: vertex + 0.5 * spacing * off.signum() }
    }
}

/// Whether two steps' contact states are the same, a slide's friction angle to [`ON_FACET`]
/// (the round-off of a slip's direction): states met again within that are a cycle.
fn alike(a: &[State], b: &[State]) -> bool {
    a.iter().zip(b).all(|(x, y)| match (x, y) {
        (State::Slide { angle: p }, State::Slide { angle: q }) => wrap(p - q).abs() <= ON_FACET,
        _ => x == y,
    })
}

/// The kinds of state a contact has taken within a step's passes.
#[derive(Clone, Copy, Default)]
struct Tried {
    open: bool,
    stick: bool,
    slide: bool,
}

impl Tried {
    fn of(s: &State) -> Self {
        Self::default().with(s)
    }

    fn with(self, s: &State) -> Self {
        match s {
            State::Open => Self { open: true, ..self },
            State::Stick => Self { stick: true, ..self },
            State::Slide { .. } => Self { slide: true, ..self },
        }
    }
}

/// How basic a change of state is: opening a pulling contact, closing a penetrating one,
/// then friction's changes.
fn kind(from: &State, to: &State) -> u8 {
    match (from, to) {
        (_, State::Open) => 0,
        (State::Open, _) => 1,
        (State::Stick, _) => 2,
        _ => 3,
    }
}

/// An angle brought within (−π, π].
fn wrap(a: f64) -> f64 {
    let b = a.rem_euclid(2.0 * PI);
    if b > PI { b - 2.0 * PI } else { b }
}

/// The normal angle of the facet on which friction `t` is largest (its direction on the cone).
fn widest_facet(sides: Option<usize>, t: (f64, f64)) -> f64 {
    let Some(n) = sides else { return t.1.atan2(t.0) };
    let spacing = 2.0 * PI / n as f64;
    (t.1.atan2(t.0) / spacing).round() * spacing
}

/// The polygon's facet count, None for the cone.
fn polygon(model: FrictionModel) -> Option<usize> {
    match model {
        FrictionModel::Cone => None,
        m => Some(m.facets().len()),
    }
}

/// A tangent vector's angle in the frame (u, v).
fn angle_in(frame: &[Vector3; 3], t: &Vector3) -> f64 {
    t.dot(&frame[2]).atan2(t.dot(&frame[1]))
}

/// The least capacity whose set holds friction `t` (in the frame's u, v components).
pub(super) fn gauge(sides: Option<usize>, t: (f64, f64)) -> f64 {
    let Some(n) = sides else { return t.0.hypot(t.1) };
    // The facets' normals by turning the first one n times (one sine and cosine a call).
    let (s, c) = (2.0 * PI / n as f64).sin_cos();
    let (mut dx, mut dy, mut largest) = (1.0, 0.0, 0.0f64);
    for _ in 0..n {
        largest = largest.max(t.0 * dx + t.1 * dy);
        (dx, dy) = (dx * c - dy * s, dx * s + dy * c);
    }
    largest
}

impl World {
    /// The step of moving component `comp` from its contacts' `states` (module docs), its
    /// multipliers started from `seed`'s impulses where given, else the last step's; None where
    /// no states within [`PASSES`] (and [`SINGLE_PASSES`]) changes meet the exact-Coulomb
    /// conditions.
    pub(super) fn step_by_states(
        &mut self,
        comp: &[usize],
        local: &[usize],
        active: &[Active],
        start: (Vec<State>, Option<&[Vector3]>),
    ) -> Option<Solution> {
        let key = self.pattern_key(comp.len(), local, active);
        let mut system = match self.patterns.remove(&key) {
            Some(system) => system,
            None => ordered(&key)?,
        };
        let sol = self.states_step(comp, local, active, start, &mut system);
        if self.patterns.len() >= KEPT_PATTERNS {
            self.patterns.clear();
        }
        self.patterns.insert(key, system);
        sol
    }

    /// The states' systems' pattern of a component of `bodies` bodies with `active`'s
    /// contacts: the links of every contact between two of its bodies, whatever their states,
    /// so one ordering serves every pass.
    fn pattern_key(&self, bodies: usize, local: &[usize], active: &[Active]) -> PatternKey {
        let body = |s: super::Side| if let super::Side::Free(k) = s { Some(local[k]) } else { None };
        let mut links: Vec<[usize; 2]> = active
            .iter()
            .filter_map(|a| {
                let c = &self.contacts[a.contact];
                body(c.a).zip(body(c.b)).map(|(x, y)| [x.min(y), x.max(y)])
            })
            .filter(|[x, y]| x != y)
            .collect();
        links.sort_unstable();
        links.dedup();
        (bodies, links)
    }

    /// [`Self::step_by_states`] on the pattern `system`.
    fn states_step(
        &self,
        comp: &[usize],
        local: &[usize],
        active: &[Active],
        (mut states, seed): (Vec<State>, Option<&[Vector3]>),
        system: &mut BlockLu,
    ) -> Option<Solution> {
        let h = self.ctx.h;
        let sides = polygon(self.ctx.model);
        let parts = Component::new(&self.bodies, comp, local, h);
        let weight: f64 = parts.bodies.iter().map(|b| b.mass * self.ctx.units.g).sum();
        // A tenth of the rest criterion's speed: far below any motion a verdict reads, above the
        // gap terms of joints closed to round-off (1e-11 m / h), which tighter rows cannot all meet.
        let tol =
            Tolerances { speed: SPEED * self.settings.still * self.ctx.units.g * h, impulse: IMPULSE * weight * h };
        let mut tried: Vec<Tried> = states.iter().map(Tried::of).collect();
        let mut seen = vec![states.clone()];
        // Every change of the most basic kind at once, until the changes cycle; then one
        // contact's change a pass (the lowest-numbered: Murty's rule, which ends where the
        // block rule cycles).
        let mut single = false;
        let mut passes = 0;
        while passes < PASSES + if single { SINGLE_PASSES } else { 0 } {
            passes += 1;
            let unknowns = self.unknowns(active, &states, sides);
            let start = match seed {
                Some(impulses) => seeded_impulses(&unknowns, impulses),
                None => self.last_impulses(active, &unknowns),
            };
            let (u, lambda, converged) = self.solve_states(&parts, active, (&unknowns, start), tol, system)?;
            let check = self.check(&parts, active, (&states, &tried), &unknowns, (&u, &lambda), tol, sides);
            let changes = match check {
                // Rows that cannot all hold (states asking for more than the blocks' motion
                // allows) whose impulses still meet every condition: no answer of these states.
                Check::Holds(..) if !converged => return None,
                Check::Holds(normal, impulses) => {
                    return Some(self.solution(&parts, active, &u, normal, impulses));
                }
                Check::Change(changes) => changes,
            };
            let apply = |changes: &[(usize, State)]| {
                let mut next = states.clone();
                changes.iter().for_each(|&(i, s)| next[i] = s);
                next
            };
            let mut next = apply(if single { &changes[..1] } else { &changes });
            if seen.iter().any(|s| alike(s, &next)) {
                // States met before: more passes of this rule would repeat them.
                if single {
                    return None;
                }
                single = true;
                next = apply(&changes[..1]);
                seen = vec![states.clone()];
            }
            seen.push(next.clone());
            tried.iter_mut().zip(&next).for_each(|(t, s)| *t = t.with(s));
            states = next
        }
        None
    }

    /// Each contact's unknowns by its state.
    fn unknowns(&self, active: &[Active], states: &[State], sides: Option<usize>) -> Vec<Unknown> {
        let (h, mu) = (self.ctx.h, self.ctx.mu);
        let recovery = self.ctx.recovery * self.ctx.units.speed();
        let mut out = Vec::with_capacity(3 * active.len());
        for (i, (a, s)) in active.iter().zip(states).enumerate() {
            let f = &a.geometry.frame;
            let gap_term = (a.geometry.gap / h).max(-recovery) + a.prescribed.dot(&f[0]);
            let normal = |force| Unknown { contact: i, force, row: f[0], target: -gap_term };
            match *s {
                State::Open => {}
                State::Stick => {
                    out.push(normal(f[0]));
                    for t in [f[1], f[2]] {
                        out.push(Unknown { contact: i, force: t, row: t, target: -a.prescribed.dot(&t) });
                    }
                }
                State::Slide { angle } => {
                    let (e, free) = friction_point(sides, angle);
                    out.push(normal(f[0] + (f[1] * e.x + f[2] * e.y) * mu));
                    if let Some(t) = free {
                        let t = f[1] * t.x + f[2] * t.y;
                        out.push(Unknown { contact: i, force: t, row: t, target: -a.prescribed.dot(&t) });
                    }
                }
            }
        }
        out
    }

    /// The states' systems' block pattern for `active`'s contacts in component `parts`
    /// ([`Self::pattern_key`]).
    pub(super) fn states_pattern(&self, parts: &Component, active: &[Active]) -> Option<BlockLu> {
        ordered(&self.pattern_key(parts.mass.len(), parts.local, active))
    }

    /// u⁺ and the impulses λ of the states' linear step by the method of multipliers, from
    /// impulses `start` (the last step's), and whether every row holds (where they cannot all hold the
    /// multipliers grow along the conflict: their signs say which states to change); None where
    /// the factorisation fails.
    /// Each unknown's penalty is [`PENALTY`] over its row's own compliance r M⁻¹ rᵀ, so every
    /// row's error shrinks alike; the answer's velocities are M⁻¹ (M u* + Σ Jᵀ B λ) (the
    /// momentum exact, the rows to the tolerance).
    pub(super) fn solve_states(
        &self,
        parts: &Component,
        active: &[Active],
        (unknowns, start): (&[Unknown], DVector<f64>),
        tol: Tolerances,
        system: &mut BlockLu,
    ) -> Option<(DVector<f64>, DVector<f64>, bool)> {
        let n = parts.free.len();
        let sparse: Vec<(Sparse, Sparse)> = unknowns
            .iter()
            .map(|q| {
                let a = &active[q.contact];
                let c = &self.contacts[a.contact];
                let p = &a.geometry.point;
                (parts.sparse_row(c.a, c.b, p, &q.row), parts.sparse_row(c.a, c.b, p, &q.force))
            })
            .collect();
        let rho: Vec<f64> = sparse.iter().map(|(row, _)| PENALTY / parts.compliance(row)).collect();
        // M + Σ ρ f rᵀ by the bodies' 6×6 blocks, on `system`'s pattern (the contact graph).
        system.clear();
        for (j, m) in parts.mass.iter().enumerate() {
            system.add(j, j, m);
        }
        for ((row, force), r) in sparse.iter().zip(&rho) {
            for (jf, f) in force.iter() {
                let f = f * *r;
                for (jr, w) in row.iter() {
                    // The outer product entry by entry (a general 6×1 · 1×6 product is slower).
                    if !system.add(*jf, *jr, &Matrix6::from_fn(|i, j| f[i] * w[j])) {
                        return None;
                    }
                }
            }
        }
        if !system.factor() {
            return None;
        }
        let mut lambda = start;
        let mut rhs = DVector::zeros(n);
        let (mut u, mut residual) = (DVector::zeros(n), DVector::zeros(n));
        let (mut converged, mut last) = (false, f64::INFINITY);
        for step in 1..=MULTIPLIER_STEPS {
            rhs.copy_from(&parts.free);
            for (((_, force), l), (q, r)) in sparse.iter().zip(lambda.iter()).zip(unknowns.iter().zip(&rho)) {
                force.add_to(&mut rhs, l + r * q.target);
            }
            refined_solve(system, parts, (&sparse, &rho), &rhs, (&mut u, &mut residual));
            let mut worst = 0.0f64;
            for (((row, _), l), (q, r)) in sparse.iter().zip(lambda.iter_mut()).zip(unknowns.iter().zip(&rho)) {
                let error = q.target - row.dot(&u);
                *l += r * error;
                worst = worst.max(error.abs());
            }
            if worst <= tol.speed {
                converged = true;
                break;
            }
            // Rows in conflict: the error stays and each step adds the same growth to the
            // multipliers; the steps left would add it again.
            if worst > STALL * last {
                let left = (MULTIPLIER_STEPS - step) as f64;
                for (((row, _), l), (q, r)) in sparse.iter().zip(lambda.iter_mut()).zip(unknowns.iter().zip(&rho)) {
                    *l += left * (r * (q.target - row.dot(&u)));
                }
                break;
            }
            last = worst;
        }
        rhs.copy_from(&parts.free);
        for ((_, force), l) in sparse.iter().zip(lambda.iter()) {
            force.add_to(&mut rhs, *l);
        }
        Some((parts.solve_mass(&rhs), lambda, converged))
    }

    /// The last step's impulses, each unknown's part along its row ([`seeded_impulses`]), N·s:
    /// the multipliers' start.
    fn last_impulses(&self, active: &[Active], unknowns: &[Unknown]) -> DVector<f64> {
        let last: Vec<Vector3> = active.iter().map(|a| self.contacts[a.contact].last_force * self.ctx.h).collect();
        seeded_impulses(unknowns, &last)
    }

    /// Whether the states' answer meets every condition of the exact-Coulomb step; if so the
    /// normal forces (non-dimensional) and impulses (N·s, on b) of each active contact, else
    /// the states to try next.
    #[allow(clippy::too_many_arguments)]
    fn check(
        &self,
        parts: &Component,
        active: &[Active],
        (states, tried): (&[State], &[Tried]),
        unknowns: &[Unknown],
        (u, lambda): (&DVector<f64>, &DVector<f64>),
        tol: Tolerances,
        sides: Option<usize>,
    ) -> Check {
        let (h, mu) = (self.ctx.h, self.ctx.mu);
        let recovery = self.ctx.recovery * self.ctx.units.speed();
        let mut impulses = vec![Vector3::zeros(); active.len()];
        let mut normal = vec![0.0; active.len()];
        for (q, l) in unknowns.iter().zip(lambda.iter()) {
            impulses[q.contact] += q.force * *l;
        }
        let mut changes: Vec<(usize, State)> = Vec::new();
        for (i, a) in active.iter().enumerate() {
            let f = &a.geometry.frame;
            let c = &self.contacts[a.contact];
            let rel = relative_velocity(parts, c.a, c.b, &a.geometry.point, u) + a.prescribed;
            let gap_term = (a.geometry.gap / h).max(-recovery);
            let (vn, vt) = (rel.dot(&f[0]) + gap_term, rel - f[0] * rel.dot(&f[0]));
            let g = impulses[i];
            let (gn, gt) = (g.dot(&f[0]), (g.dot(&f[1]), g.dot(&f[2])));
            normal[i] = gn / (h * self.ctx.units.force);
            let state = match states[i] {
                // Closing: it sticks, or slides where sticking pulled it open before.
                State::Open if vn < -tol.speed && tried[i].stick && vt.norm() > tol.speed => {
                    State::Slide { angle: widest_facet(sides, (-vt.dot(&f[1]), -vt.dot(&f[2]))) }
                }
                State::Open if vn < -tol.speed => State::Stick,
                State::Open => State::Open,
                // Pulling while sticking where it closed when open: held by a slide, not a pull.
                State::Stick if gn < -tol.impulse && tried[i].open && !tried[i].slide => {
                    State::Slide { angle: widest_facet(sides, gt) }
                }
                _ if gn < -tol.impulse => State::Open,
                State::Stick if gauge(sides, gt) > mu * gn * (1.0 + SLACK) + tol.impulse => {
                    State::Slide { angle: widest_facet(sides, gt) }
                }
                State::Stick => State::Stick,
                State::Slide { angle } => slide_state(sides, angle, f, &vt, (gt, mu * gn), tol),
            };
            if state != states[i] {
                changes.push((i, state));
            }
        }
        if changes.is_empty() {
            return Check::Holds(normal, impulses);
        }
        // One kind of change a pass, the most basic first (a contact that pulls opens before
        // one that penetrates closes, before friction changes): all kinds at once cycle.
        let first = changes.iter().map(|(i, s)| kind(&states[*i], s)).min().unwrap_or(0);
        changes.retain(|(i, s)| kind(&states[*i], s) == first);
        Check::Change(changes)
    }

    /// The accepted states' answer as a step's [`Solution`] (its momentum residual, N).
    pub(super) fn solution(
        &self,
        parts: &Component,
        active: &[Active],
        u: &DVector<f64>,
        normal: Vec<f64>,
        impulses: Vec<Vector3>,
    ) -> Solution {
        let mut momentum = parts.mass_times(u) - &parts.free;
        for (a, g) in active.iter().zip(&impulses) {
            let c = &self.contacts[a.contact];
            parts.sparse_row(c.a, c.b, &a.geometry.point, g).add_to(&mut momentum, -1.0);
        }
        let velocities = parts.velocities(u);
        let residual = momentum.amax() / self.ctx.h;
        Solution { velocities, normal, work: impulses.clone(), impulses, residual }
    }
}

/// K u = `rhs` into `u` (`residual` its scratch) for the states' system K = M + Σ ρ f rᵀ
/// factorised in `system`, refined against K's own product: the block factorisation pivots
/// within a body's block only, so a body held by a few stiff rows loses digits that a
/// refinement step, at a product's cost, wins back.
fn refined_solve(
    system: &mut BlockLu,
    parts: &Component,
    (sparse, rho): (&[(Sparse, Sparse)], &[f64]),
    rhs: &DVector<f64>,
    (u, residual): (&mut DVector<f64>, &mut DVector<f64>),
) {
    u.copy_from(rhs);
    system.solve(u.as_mut_slice());
    for _ in 0..REFINEMENTS {
        parts.residual_of(rhs, u, residual);
        for ((row, force), r) in sparse.iter().zip(rho) {
            force.add_to(residual, -r * row.dot(u));
        }
        system.solve(residual.as_mut_slice());
        *u += &*residual;
    }
}

/// The multipliers' start from a solve's `impulses` (N·s, on b, per active contact): each
/// unknown's part along its own row (a slide's normal row reads its λ, a facet's free row its
/// free friction), so that the states' answer keeps that solve's split among a face's points.
fn seeded_impulses(unknowns: &[Unknown], impulses: &[Vector3]) -> DVector<f64> {
    DVector::from_iterator(unknowns.len(), unknowns.iter().map(|q| impulses[q.contact].dot(&q.row)))
}

/// A states' system's pattern: its bodies, and its links (local body pairs, ascending).
pub(super) type PatternKey = (usize, Vec<[usize; 2]>);

/// The block factorisation of pattern `key`, ordered (None where it cannot be).
fn ordered((bodies, links): &PatternKey) -> Option<BlockLu> {
    BlockLu::new(*bodies, links.iter().map(|&[a, b]| (a, b)))
}

/// Patterns kept at most before the store starts afresh (a collapse meets a few hundred).
const KEPT_PATTERNS: usize = 256;

#[derive(Clone, Copy)]
pub(super) struct Tolerances {
    /// m/s: a row's error, a contact's closing speed or slip counted as none.
    pub speed: f64,
    /// N·s: a pull counted as none, friction beyond its set by this much.
    pub impulse: f64,
}

enum Check {
    Holds(Vec<f64>, Vec<Vector3>),
    /// The changes of the most basic kind (module docs), by contact, lowest-numbered first.
    Change(Vec<(usize, State)>),
}

/// The state a contact ends a step in: open without a normal force (`normal` at most `noise`),
/// else sticking where its slip is below `still` and sliding against its slip.
pub(super) fn state_after((normal, noise): (f64, f64), frame: &[Vector3; 3], slip: &Vector3, still: f64) -> State {
    if normal <= noise {
        return State::Open;
    }
    if slip.norm() <= still { State::Stick } else { State::Slide { angle: angle_in(frame, &(-slip)) } }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{DropSettings, Engine};
    use crate::geometry::{Mesh, Point3};
    use crate::model::{Assembly, Block, Scene};

    /// Invariant: rows that cannot all hold stop the method of multipliers once the error
    /// stays ([`STALL`]), with the multipliers the [`MULTIPLIER_STEPS`] steps would give.
    /// Two rows along one contact's normal asking for closing speeds 0 and t: their sum settles
    /// in a step (the normal speed t / 2), and each step adds ρ t to their difference, so after
    /// all the steps λ₁ − λ₂ = −MULTIPLIER_STEPS ρ t exactly (ρ = PENALTY / the row's compliance).
    #[test]
    fn rows_in_conflict_stop_with_the_multipliers_of_every_step() {
        let cube = Mesh::cuboid(Point3::new(-0.5, -0.5, 0.0), Point3::new(0.5, 0.5, 1.0));
        let mut scene = Scene::new("cube", vec![Block::new("cube", cube)]);
        scene.ground = true;
        let asm = Assembly::new(&scene, &Default::default()).expect("a valid scene");
        let world = World::new(&asm, &DropSettings { engine: Engine::Exact, ..Default::default() });
        let near = world.near_contacts(&[]);
        assert!(!near.is_empty(), "the cube stands on the ground");
        let (comp, local) = (vec![0], vec![0]);
        let parts = Component::new(&world.bodies, &comp, &local, world.ctx.h);
        let n = near[0].geometry.frame[0];
        let t = 1e-3;
        let unknowns = [0.0, t].map(|target| Unknown { contact: 0, force: n, row: n, target });
        let mut system = world.states_pattern(&parts, &near).expect("one body's pattern");
        let tol = Tolerances { speed: 1e-9, impulse: 1e-12 };
        let start = DVector::zeros(2);
        let (u, lambda, converged) =
            world.solve_states(&parts, &near, (&unknowns, start), tol, &mut system).expect("a factorisation");
        assert!(!converged);
        let c = &world.contacts[near[0].contact];
        let row = parts.sparse_row(c.a, c.b, &near[0].geometry.point, &n);
        let rho = PENALTY / parts.compliance(&row);
        let expected = -(MULTIPLIER_STEPS as f64) * rho * t;
        let difference = lambda[0] - lambda[1];
        assert!((difference - expected).abs() <= 1e-9 * expected.abs(), "λ₁ − λ₂ {difference:e}, {expected:e}");
        // The sum's remainder after a step (~1e-7 of the free fall's g h) is carried along too.
        let speed = row.dot(&u);
        assert!((speed - 0.5 * t).abs() <= 1e-4 * t, "normal speed {speed:e} against t / 2");
    }

    /// Invariant: states met before are recognised whatever the round-off of a slide's angle
    /// (within [`ON_FACET`], across ±π too), and only then: another angle or kind is new.
    #[test]
    fn states_alike_to_a_slides_round_off() {
        let slide = |angle| State::Slide { angle };
        let base = [State::Stick, slide(-PI / 2.0), State::Open];
        assert!(alike(&base, &[State::Stick, slide(-PI / 2.0 - 3e-6), State::Open]));
        assert!(alike(&[slide(PI - 1e-6)], &[slide(-PI + 1e-6)]));
        assert!(!alike(&base, &[State::Stick, slide(-PI / 2.0 - 1e-4), State::Open]));
        assert!(!alike(&base, &[State::Stick, slide(-PI / 2.0), State::Stick]));
    }

    /// Invariant: on the polygons a friction direction exactly along a facet normal lies on that
    /// facet (its free direction across it), any other at the vertex whose cone holds it, at
    /// radius 1 / cos(π/n); on the cone the direction itself.
    #[test]
    fn friction_points_of_the_sets() {
        let (e, free) = friction_point(Some(8), 0.0);
        assert!((e - Vector3::x()).norm() < 1e-15 && free.is_some());
        let (e, free) = friction_point(Some(8), 0.3);
        let r = 1.0 / (PI / 8.0).cos();
        assert!((e - Vector3::new((PI / 8.0).cos(), (PI / 8.0).sin(), 0.0) * r).norm() < 1e-12 && free.is_none());
        let (e, _) = friction_point(Some(4), -0.2);
        assert!((e - Vector3::new(1.0, -1.0, 0.0)).norm() < 1e-12, "{e:?}");
        let (e, free) = friction_point(None, 1.0);
        assert!((e - Vector3::new(1f64.cos(), 1f64.sin(), 0.0)).norm() < 1e-15 && free.is_none());
        assert!((gauge(Some(8), (1.0, 0.0)) - 1.0).abs() < 1e-15);
        assert!((gauge(Some(4), (1.0, 1.0)) - 1.0).abs() < 1e-15);
    }
}
