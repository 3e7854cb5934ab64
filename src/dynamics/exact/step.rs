//! One component's step: the rounds of solves, then its new velocities, forces and account.

use super::World;
use super::active_set::state_after;
use super::anderson::Anderson;
use super::best::Best;
use super::contact_form::{self, StepData};
use super::contacts::State;
use super::crushing::{self, Crush};
use super::problem::{self, Active, Solution, StepProblem};
use crate::dynamics::settings::{Coulomb, Selection};
use crate::geometry::Vector3;
use crate::statics::{Backend, ConicOutcome, solve_conic};
use std::collections::BTreeSet;

/// The component a solve is for, which of its active contacts take part, whether it is the
/// force selection, and the context its rows were built in (the selection's friction sets
/// may be Coulomb's).
#[derive(Clone, Copy)]
struct Part<'a> {
    comp: &'a [usize],
    local: &'a [usize],
    active: &'a [Active],
    taking_part: &'a [bool],
    selection: bool,
    ctx: problem::StepContext,
}

/// What a kept iterate must share with the next problem to start it: the component's bodies,
/// its contacts, which take part and which have friction columns.
fn layout_key(part: &Part, cols: &problem::Columns) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    part.comp.hash(&mut h);
    part.active.iter().map(|a| a.contact).for_each(|c| c.hash(&mut h));
    part.taking_part.hash(&mut h);
    cols.friction.iter().map(Option::is_some).for_each(|f| f.hash(&mut h));
    h.finish()
}

/// Gaps (fraction of the median block size) beyond which an open contact is left out of the
/// force selection.
const OPEN: f64 = 1e-3;

impl World {
    /// Solves `comp`'s step (module docs of [`super`]) and sets its velocities.
    pub(super) fn step_component(&mut self, comp: &[usize], near: &[Active]) {
        let mut local = vec![usize::MAX; self.bodies.len()];
        comp.iter().enumerate().for_each(|(j, &k)| local[k] = j);
        let mu = self.ctx.mu;
        let mut active = self.component_contacts(comp, near);
        if active.is_empty() {
            let sol = self.free_flight(comp);
            let rest = self.stays_still(comp, &sol);
            self.accept(comp, &active, sol, rest);
            return;
        }
        let exact = self.ctx.coulomb == Coulomb::Exact;
        let moving = !comp.iter().all(|&k| self.bodies[k].at_rest());
        // Where the states do not settle, the interior-point round they tried starts the rounds.
        let mut first_round = None;
        if exact && moving && self.by_states() {
            match self.step_taken_by_states(comp, &local, &active) {
                ByStates::Taken => return,
                ByStates::Rounds(round) => first_round = round.map(|r| *r),
            }
        }
        if exact && self.settings.rest_when_admissible && comp.iter().all(|&k| self.bodies[k].at_rest()) {
            match self.step_from_rest(comp, &local, &active) {
                FromRest::Stays(sol) => return self.accept(comp, &active, sol, true),
                FromRest::Moves(normal) => {
                    let start = capacities(&normal, mu, self.settings.solver_tolerance);
                    active.iter_mut().zip(start).for_each(|(a, c)| a.capacity = c);
                }
                FromRest::Failed => return self.stats.failed_steps += 1,
            }
        }
        let mut rounds = 0;
        let mut bound = BTreeSet::new();
        let mut anderson = Anderson::default();
        let mut best = Best::<Solution>::default();
        let accepted = loop {
            rounds += 1;
            let round = first_round.take().or_else(|| self.round(comp, &local, &active, &bound));
            let Some((p, out)) = round else { break None };
            let sol = p.read(&self.ctx, &self.bodies, comp, &active, &out.x);
            let rest = self.stays_still(comp, &sol);
            // Each later round's states may settle where the first round's did not.
            if exact && moving && self.by_states() && rounds > 1 {
                let states = self.states_of(&sol, &local, &active);
                if let Some(sol) = self.step_by_states(comp, &local, &active, (states, Some(&sol.impulses))) {
                    return self.accept_by_states(comp, &active, sol);
                }
            }
            if rest || !exact {
                if self.bind(&active, &sol, &mut bound) && rounds < self.settings.max_rounds {
                    continue;
                }
                break Some((sol, rest));
            }
            let open = self.open_contacts(&local, &active, &sol);
            let (selection, sel_ctx) = self.selection_problem(p, &out.x, (comp, &local, &active), &bound, &open);
            // Without the selection the round's own forces stand (its velocities are the step's).
            let closed: Vec<bool> = open.iter().map(|o| !o).collect();
            let part =
                Part { comp, local: &local, active: &active, taking_part: &closed, selection: true, ctx: sel_ctx };
            let Some(forces) = self.solve(&selection, part) else {
                self.stats.unsettled_steps += 1;
                break Some((best.take(sol), false));
            };
            let selected = selection.read(&sel_ctx, &self.bodies, comp, &active, &forces.x);
            // The round's velocities and the work of the forces that made them; the selection's
            // forces for the next capacities and the reactions.
            let sol = Solution { velocities: sol.velocities, work: sol.work, ..selected };
            let next = capacities(&sol.normal, mu, self.settings.solver_tolerance);
            let (settled, change) = self.round_change(&active, &next, &selection, &forces.x);
            let grew = self.bind(&active, &sol, &mut bound);
            if settled && !grew {
                break Some((sol, false));
            }
            let stalled = best.record(change, &sol, self.settings.stall_rounds.unwrap_or(u32::MAX));
            if stalled || rounds >= self.settings.max_rounds {
                self.stats.unsettled_steps += 1;
                break Some((best.take(sol), false));
            }
            let next = if !self.settings.accelerate_rounds {
                next
            } else if grew {
                anderson.restart();
                next
            } else {
                anderson.next(&active.iter().map(|a| a.capacity).collect::<Vec<_>>(), &next)
            };
            active.iter_mut().zip(next).for_each(|(a, c)| a.capacity = c);
        };
        self.stats.max_rounds = self.stats.max_rounds.max(rounds);
        // A failed solve leaves the component as it was (its status is the run's answer).
        match accepted {
            Some((sol, rest)) => self.accept(comp, &active, sol, rest),
            None => self.stats.failed_steps += 1,
        }
    }

    /// `near`'s contacts of component `comp`, each with its capacity from the last step's
    /// normal force (μ f_n, non-dimensional): the rounds' start.
    fn component_contacts(&self, comp: &[usize], near: &[Active]) -> Vec<Active> {
        let (mu, force) = (self.ctx.mu, self.ctx.units.force);
        near.iter()
            .filter(|a| comp.iter().any(|&k| self.contacts[a.contact].touches(k)))
            .map(|a| Active { capacity: mu * self.contacts[a.contact].last_normal / force, ..*a })
            .collect()
    }

    /// How far a round's capacities `next` moved from `active`'s, relative to the largest
    /// capacity, and whether that has settled: within `settings.settle` of it, or (with
    /// accelerated rounds) binding nowhere, by the selection's forces `x` of `selection`.
    fn round_change(&self, active: &[Active], next: &[f64], selection: &StepProblem, x: &[f64]) -> (bool, f64) {
        // Against the mean capacity per point at the least: capacities of ~0 that merely
        // wobble have settled.
        let mean = self.ctx.mu / active.len().max(1) as f64;
        let largest =
            next.iter().chain(active.iter().map(|a| &a.capacity)).fold(mean.max(f64::MIN_POSITIVE), |m, c| m.max(*c));
        let slack = self.settings.settle * largest;
        let change = next.iter().zip(active).fold(0.0f64, |m, (c, a)| m.max((c - a.capacity).abs()));
        let unbinding = self.settings.accelerate_rounds && {
            let gauge = problem::friction_gauge(self.ctx.model, &selection.cols, x);
            binds_nowhere(active, next, &gauge, slack)
        };
        (change <= slack || unbinding, change / largest)
    }

    /// The force selection of round problem `p` solved at `first` ([`Selection`]), and the
    /// context it was built in: the round's own problem, or one with Coulomb's coupled sets
    /// (the relaxed form's rows, in its column layout).
    fn selection_problem(
        &self,
        p: StepProblem,
        first: &[f64],
        (comp, local, active): (&[usize], &[usize], &[Active]),
        bound: &BTreeSet<usize>,
        open: &[bool],
    ) -> (StepProblem, problem::StepContext) {
        let first_residual = p.cols.residual;
        let (mut selection, ctx) = match self.settings.selection {
            Selection::Round => (p, self.ctx),
            Selection::Coulomb => {
                let ctx = problem::StepContext { coulomb: Coulomb::Relaxed, ..self.ctx };
                let crush = self.ctx.strength.map(|sigma| Crush { bearings: &self.bearings, sigma, bound });
                (problem::build(&ctx, &self.bodies, comp, local, &self.contacts, active, crush.as_ref()), ctx)
            }
        };
        selection.select_forces(first, first_residual, open);
        (selection, ctx)
    }

    /// Whether a moving component's step is first tried by its contacts' states: exact Coulomb
    /// with the round's own force selection, no crushing. (A settlement's runs turn it off:
    /// where exact Coulomb admits several answers they take the rounds' pick.)
    fn by_states(&self) -> bool {
        let s = &self.settings;
        s.by_states && s.selection == Selection::Round && self.ctx.strength.is_none()
    }

    /// A component at rest: the step with Coulomb's coupled sets (friction bounded by μ f_n of
    /// the same solve, the limit-analysis model). Where it keeps the blocks at rest its forces
    /// are an equilibrium within the exact sets too (nothing slips, so its dilatancy never
    /// acts), and rest is the answer: the static theorem's pick where the exact sets also admit
    /// a motion (a flat arch whose halves could slide down their vertical joints with no force
    /// on them stands, as its statics say). Otherwise its forces start the Tresca rounds.
    fn step_from_rest(&mut self, comp: &[usize], local: &[usize], active: &[Active]) -> FromRest {
        let ctx = problem::StepContext { coulomb: Coulomb::Relaxed, ..self.ctx };
        let mut bound = BTreeSet::new();
        let crush = self.ctx.strength.map(|sigma| Crush { bearings: &self.bearings, sigma, bound: &bound });
        let p = problem::build(&ctx, &self.bodies, comp, local, &self.contacts, active, crush.as_ref());
        let all = vec![true; active.len()];
        let part = Part { comp, local, active, taking_part: &all, selection: false, ctx };
        let Some(out) = self.solve(&p, part) else { return FromRest::Failed };
        let sol = p.read(&ctx, &self.bodies, comp, active, &out.x);
        if self.bind(active, &sol, &mut bound) {
            // A joint the forces would crush: the rounds with its stress block decide.
            return FromRest::Moves(sol.normal);
        }
        if self.stays_still(comp, &sol) { FromRest::Stays(sol) } else { FromRest::Moves(sol.normal) }
    }

    /// With a strength: adds the closed joints whose forces in `sol` come near it to `bound`
    /// ([`crushing::binding`]); whether any was added.
    fn bind(&self, active: &[Active], sol: &Solution, bound: &mut BTreeSet<usize>) -> bool {
        let Some(sigma) = self.ctx.strength else { return false };
        let normals = active.iter().zip(&sol.normal).map(|(a, &f)| (a.contact, a.geometry.gap, f));
        crushing::binding(&self.bearings, sigma, &self.contacts, normals, OPEN * self.size, bound)
    }

    /// One solve of `p` — in the contact form on the structured solver when it has that shape
    /// and the settings ask for it, else on clarabel — counted in the run's account; `None`
    /// when it did not reach an answer.
    fn solve(&mut self, p: &StepProblem, part: Part) -> Option<ConicOutcome> {
        let (conic, max_iter) = (&p.conic, self.settings.max_iterations);
        let key = (part.selection, part.comp[0]);
        let structured = (self.settings.backend == Backend::Structured)
            .then(|| {
                let layout = layout_key(&part, &p.cols);
                let data = StepData {
                    ctx: &part.ctx,
                    bodies: &self.bodies,
                    comp: part.comp,
                    local: part.local,
                    contacts: &self.contacts,
                    active: part.active,
                    cols: &p.cols,
                    taking_part: part.taking_part,
                };
                let warm = self.warm_starts.get(&key).filter(|w| w.0 == layout && self.settings.warm_start);
                let solved = contact_form::solve(&data, conic, self.acc, max_iter, warm.map(|w| &w.1));
                solved.map(|(out, kept)| (out, kept.map(|k| (layout, k))))
            })
            .flatten()
            .map(|(out, kept)| {
                if let Some(kept) = kept {
                    self.warm_starts.insert(key, kept);
                }
                out
            });
        if let Some(out) = structured.as_ref().filter(|out| !out.status.solved())
            && part.selection
            && self.settings.selection == Selection::Coulomb
        {
            // A Coulomb selection the structured solver cannot end comes from a round far from
            // the fixed point: the round's own forces stand (the step unsettled), not
            // clarabel's ~10× longer solve of it.
            self.stats.solves += 1;
            self.stats.iterations += u64::from(out.iterations);
            return None;
        }
        let structured = structured.filter(|out| out.status.solved());
        self.stats.structured_solves += u64::from(structured.is_some());
        let out = structured.unwrap_or_else(|| solve_conic(conic, self.acc, max_iter));
        self.stats.solves += 1;
        self.stats.iterations += u64::from(out.iterations);
        self.stats.status = self.stats.status.max(out.status);
        out.status.solved().then_some(out)
    }

    /// Takes a moving component's step by its contacts' last states, else by the states and
    /// impulses nonsmooth Gauss–Seidel gives ([`super::gauss_seidel`]) or, where its sweeps
    /// settled, by their answer, else by the states Lemke's pivoting gives ([`super::lcp`]),
    /// else by the states one Tresca round gives ([`super::active_set`]); where none settles,
    /// that round (its problem and solve) for the rounds to start from.
    fn step_taken_by_states(&mut self, comp: &[usize], local: &[usize], active: &[Active]) -> ByStates {
        let last = active.iter().map(|a| self.contacts[a.contact].state).collect();
        let mut round = None;
        let by_states = self
            .step_by_states(comp, local, active, (last, None))
            .or_else(|| {
                let sweeps = self.states_by_gauss_seidel(comp, local, active)?;
                self.step_by_states(comp, local, active, (sweeps.states, Some(&sweeps.impulses))).or(sweeps.settled)
            })
            .or_else(|| {
                let (states, impulses) = self.states_by_lcp(comp, local, active)?;
                self.step_by_states(comp, local, active, (states, Some(&impulses)))
            })
            .or_else(|| {
                let (states, impulses, p, out) = self.one_round(comp, local, active)?;
                let sol = self.step_by_states(comp, local, active, (states, Some(&impulses)));
                round = Some(Box::new((p, out)));
                sol
            });
        let Some(sol) = by_states else { return ByStates::Rounds(round) };
        self.accept_by_states(comp, active, sol);
        ByStates::Taken
    }

    /// Accepts a step the contacts' states settled, counted as such.
    fn accept_by_states(&mut self, comp: &[usize], active: &[Active], sol: Solution) {
        self.stats.state_steps += 1;
        let rest = self.stays_still(comp, &sol);
        self.accept(comp, active, sol, rest);
    }

    /// One Tresca round's problem with `active`'s capacities (and, crushing, the stress blocks
    /// of the joints in `bound`), and its solve; None where the solve fails.
    fn round(
        &mut self,
        comp: &[usize],
        local: &[usize],
        active: &[Active],
        bound: &BTreeSet<usize>,
    ) -> Option<(StepProblem, ConicOutcome)> {
        let crush = self.ctx.strength.map(|sigma| Crush { bearings: &self.bearings, sigma, bound });
        let p = problem::build(&self.ctx, &self.bodies, comp, local, &self.contacts, active, crush.as_ref());
        let all = vec![true; active.len()];
        let part = Part { comp, local, active, taking_part: &all, selection: false, ctx: self.ctx };
        let out = self.solve(&p, part)?;
        Some((p, out))
    }

    /// One Tresca round (one interior-point solve with the last step's capacities) and the
    /// contacts' states after it, and its impulses: where the last step's states no longer
    /// settle (a contact closing, a slip starting), the round's velocities and forces say which
    /// contacts are open, sticking or sliding, and the states' step from there (its multipliers
    /// started from the round's impulses) needs no more rounds. None where the solve fails.
    fn one_round(
        &mut self,
        comp: &[usize],
        local: &[usize],
        active: &[Active],
    ) -> Option<(Vec<State>, Vec<Vector3>, StepProblem, ConicOutcome)> {
        let (p, out) = self.round(comp, local, active, &BTreeSet::new())?;
        let sol = p.read(&self.ctx, &self.bodies, comp, active, &out.x);
        Some((self.states_of(&sol, local, active), sol.impulses, p, out))
    }

    /// The contacts' states after a round's solve `sol`: open without force, else sticking or
    /// sliding by their slip.
    fn states_of(&self, sol: &Solution, local: &[usize], active: &[Active]) -> Vec<State> {
        let noise = force_noise(&sol.normal, self.settings.solver_tolerance);
        let slow = self.settings.still * self.ctx.units.g * self.ctx.h;
        let states = active.iter().zip(&sol.normal).map(|(a, &n)| {
            let c = &self.contacts[a.contact];
            let relative = self.velocity_in(sol, local, c.b, &a.geometry.point)
                - self.velocity_in(sol, local, c.a, &a.geometry.point)
                + a.prescribed;
            let slip = relative - a.geometry.frame[0] * relative.dot(&a.geometry.frame[0]);
            state_after((n, noise), &a.geometry.frame, &slip, slow)
        });
        states.collect()
    }

    /// The velocity of side `side`'s material point at `p` in solve `sol` (0 for a fixed or
    /// moved side: the latter's is the contact's prescribed part), m/s.
    fn velocity_in(&self, sol: &Solution, local: &[usize], side: super::Side, p: &crate::geometry::Point3) -> Vector3 {
        match side {
            super::Side::Free(k) => {
                let (v, w) = sol.velocities[local[k]];
                v + w.cross(&(p - self.bodies[k].x))
            }
            _ => Vector3::zeros(),
        }
    }

    /// Per active contact, whether it is open by more than [`OPEN`] of a block and the step's
    /// velocities leave it open at the step's end (its gap term plus its closing speed above the
    /// rest criterion's speed): complementarity gives it no force, and the force selection must
    /// not hand it any (a hinge's far side would carry load). Joints closed to within round-off
    /// and warps stay in the selection: dropping them there starves it.
    fn open_contacts(&self, local: &[usize], active: &[Active], sol: &Solution) -> Vec<bool> {
        let h = self.ctx.h;
        let recovery = self.ctx.recovery * self.ctx.units.speed();
        let tol = self.settings.still * self.ctx.units.g * h;
        let velocity = |side, p: &crate::geometry::Point3| self.velocity_in(sol, local, side, p);
        active
            .iter()
            .map(|a| {
                let c = &self.contacts[a.contact];
                let g = &a.geometry;
                let relative = velocity(c.b, &g.point) - velocity(c.a, &g.point) + a.prescribed;
                g.gap > OPEN * c.scale && (g.gap / h).max(-recovery) + relative.dot(&g.frame[0]) > tol
            })
            .collect()
    }

    /// A component touching nothing: the step's problem has no forces, and its solution is
    /// the closed form M v⁺ = M v + h × load (no solve).
    fn free_flight(&self, comp: &[usize]) -> Solution {
        let h = self.ctx.h;
        let velocities = comp
            .iter()
            .map(|&k| {
                let b = &self.bodies[k];
                let a = b.axes_now();
                let moment = Vector3::new(b.load[3], b.load[4], b.load[5]);
                let local = a.transpose() * (b.inertia_now() * b.w + moment * h);
                let w = a * Vector3::new(local.x / b.moments[0], local.y / b.moments[1], local.z / b.moments[2]);
                (b.v + Vector3::new(b.load[0], b.load[1], b.load[2]) * (h / b.mass), w)
            })
            .collect();
        Solution { velocities, normal: Vec::new(), impulses: Vec::new(), work: Vec::new(), residual: 0.0 }
    }

    /// Whether the component's every vertex after the step is slower than the rest criterion's
    /// speed, `still` g h.
    fn stays_still(&self, comp: &[usize], sol: &Solution) -> bool {
        self.peak_speed(comp, sol) <= self.settings.still * self.ctx.units.g * self.ctx.h
    }

    /// The fastest vertex of the component after the step, m/s (bounded by |v| + |ω| r).
    fn peak_speed(&self, comp: &[usize], sol: &Solution) -> f64 {
        comp.iter()
            .zip(&sol.velocities)
            .map(|(&k, (v, w))| v.norm() + w.norm() * self.bodies[k].radius)
            .fold(0.0, f64::max)
    }

    /// Takes a solve's velocities (zero at rest; a component at rest that stays at rest
    /// sleeps), its forces for the next step's capacities, and its energy and overlap account.
    fn accept(&mut self, comp: &[usize], active: &[Active], sol: Solution, rest: bool) {
        let h = self.ctx.h;
        let e = &mut self.stats.energy;
        for (&k, &(v, w)) in comp.iter().zip(&sol.velocities) {
            let b = &mut self.bodies[k];
            let (v, w) = if rest { (Vector3::zeros(), Vector3::zeros()) } else { (v, w) };
            if rest && b.at_rest() {
                b.asleep = true;
            }
            let (dv, dw) = (v - b.v, w - b.w);
            e.impact += 0.5 * (b.mass * dv.norm_squared() + dw.dot(&(b.inertia_now() * dw)));
            e.load_work += h * b.load_power(&v, &w);
            b.v = v;
            b.w = w;
        }
        for c in self.contacts.iter_mut().filter(|c| comp.iter().any(|&k| c.touches(k))) {
            c.last_normal = 0.0;
            c.last_force = Vector3::zeros();
            c.state = State::Open;
        }
        let slow = self.settings.still * self.ctx.units.g * h;
        let noise = force_noise(&sol.normal, self.settings.solver_tolerance);
        let mut contact_work = 0.0;
        for (((a, &n), impulse), work) in active.iter().zip(&sol.normal).zip(&sol.impulses).zip(&sol.work) {
            let c = &self.contacts[a.contact];
            let poses = super::contacts::Poses { bodies: &self.bodies, movers: &self.movers };
            let relative = c.relative_velocity(poses, &a.geometry.point);
            contact_work -= work.dot(&relative);
            self.stats.energy.support_work -= work.dot(&a.prescribed);
            let (sides, scale) = ((c.a, c.b), c.scale);
            self.add_reaction(sides.0, sides.1, impulse, &a.geometry.point);
            if n > 0.0 {
                self.stats.max_penetration = self.stats.max_penetration.max(-a.geometry.gap / scale);
                self.deepest = self.deepest.max(-a.geometry.gap);
            }
            let slip = relative - a.geometry.frame[0] * relative.dot(&a.geometry.frame[0]);
            let state = state_after((n, noise), &a.geometry.frame, &slip, slow);
            let c = &mut self.contacts[a.contact];
            c.last_normal = n * self.ctx.units.force;
            c.last_force = impulse / h;
            c.state = state;
        }
        let e = &mut self.stats.energy;
        e.contact += contact_work;
        e.least_step_contact = e.least_step_contact.min(contact_work);
        self.stats.residual = self.stats.residual.max(sol.residual);
    }
}

impl World {
    /// Adds a contact's impulse (on b; −impulse on a) over the step to the reaction of a moved
    /// support on either side.
    fn add_reaction(&mut self, a: super::Side, b: super::Side, impulse: &Vector3, point: &crate::geometry::Point3) {
        let h = self.ctx.h;
        for (side, sign) in [(a, -1.0), (b, 1.0)] {
            if let super::Side::Moved(m) = side {
                let force = impulse * (sign / h);
                let arm = point - self.movers[m].x;
                self.reactions[m][0] += force;
                self.reactions[m][1] += arm.cross(&force);
            }
        }
    }
}

/// How a moving component's step by its contacts' states ended.
enum ByStates {
    /// Settled and accepted.
    Taken,
    /// Not settled: the rounds take the step, from this interior-point round where one ran.
    Rounds(Option<Box<(StepProblem, ConicOutcome)>>),
}

/// What a component at rest does in its step ([`World::step_from_rest`]).
enum FromRest {
    /// An equilibrium holds it: this solve's forces.
    Stays(Solution),
    /// It moves; the relaxed solve's normal forces (non-dimensional) start the rounds.
    Moves(Vec<f64>),
    Failed,
}

/// Whether capacities `next` would give the round's answer again: each contact's capacity
/// either stayed within `slack`, or its friction (`gauge`, the model's own measure) lies
/// `slack` inside both its old and its new capacity. Such a contact's friction bound binds in
/// neither problem (its multiplier is 0), so the round's forces and velocities meet the next
/// round's optimality conditions, and its force selection's, as they are: the fixed point
/// is reached without that round. (A contact sticking while its normal force changes: the
/// common case of a moving assembly.)
fn binds_nowhere(active: &[Active], next: &[f64], gauge: &[f64], slack: f64) -> bool {
    active
        .iter()
        .zip(next)
        .zip(gauge)
        .all(|((a, &c), &t)| (c - a.capacity).abs() <= slack || t <= a.capacity.min(c) - slack)
}

/// The normal force (non-dimensional) below which a solve's force is its noise: √(tol × max(1, Σ f²)).
fn force_noise(normal: &[f64], tolerance: f64) -> f64 {
    let sum_sq: f64 = normal.iter().map(|f| f * f).sum();
    (tolerance * sum_sq.max(1.0)).sqrt()
}

/// The next round's capacities μ f_n, a normal force within the solver's noise counted as none
/// (non-dimensional). The force selection resolves Σ f² to the tolerance, so a force with f²
/// below tol × max(1, Σ f²) is invisible to it: where no force is needed (a bar sliding down
/// between posts) the barrier leaves ~√tol on every contact, which would become friction.
fn capacities(normal: &[f64], mu: f64, tolerance: f64) -> Vec<f64> {
    let noise = force_noise(normal, tolerance);
    normal.iter().map(|&f| if f > noise { mu * f } else { 0.0 }).collect()
}
