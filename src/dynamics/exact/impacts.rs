//! Impacts at their instant: a step in which a contact open at its start closes is split at the
//! time of impact τ (its gap over its closing speed at the step's start), so the motion up to
//! the impact is the free one and the plastic impact acts on the velocities of that instant —
//! not on those of the step's end, which would lose a dt's worth of motion per impact (first
//! order). The first sub-step (τ) ends with the contact at gap ≈ 0; the second (h − τ) carries
//! the impact: restitution 0 at the new contact, any other free to lift (Housner's η for a
//! rocking block). An impact within 1 % of a step of the step's start is met by the whole
//! step. Symplectic Euler's velocities are a step's middle's (it is leapfrog): a split step
//! first times them to its start, and the step after it kicks by half a step to time them back
//! ([`World::retime`]). Components with a moved support are stepped whole (their supports'
//! paths are per step).

use super::World;
use super::problem::Active;
use crate::geometry::Vector3;

/// A kick whose fastest vertex's change exceeds this many g × dt was an impulse.
const SMOOTH: f64 = 2.0;

/// Fraction of the step within which an impact's time counts as the step's start or end.
const EDGE: f64 = 0.01;

/// Gaps below this fraction of a contact's scale are closed: a hinge's drift (O(dt² ω² r) per
/// step) stays below it, and an impact closer than it to its step's start is within 2 % of a
/// step of its time at any speed that rocks a block.
const OPEN: f64 = 1e-5;

impl World {
    /// Steps component `comp` over the step, split at its first impact when
    /// [`crate::dynamics::settings::ExactSettings::split_impacts`] asks for it, and advances its bodies.
    pub(super) fn step_timed(&mut self, comp: &[usize], near: &[Active]) {
        let h = self.ctx.h;
        let Some((tau, closing)) = self.impact_time(comp, near) else {
            self.step_whole(comp, near);
            return;
        };
        self.stats.split_steps += 1;
        self.retime(comp);
        if tau < EDGE * h {
            // At the step's start: the impact step is the whole step.
            self.step_component(comp, near);
            self.advance(comp, h);
            comp.iter().for_each(|&k| self.bodies[k].instant = true);
            return;
        }
        let start = self.velocities(comp);
        // Up to the impact the closing contacts are left out: held by their gap over τ, they
        // would stop the motion a little early, with the other contacts of the step acting.
        let before: Vec<Active> = near.iter().filter(|a| !closing.contains(&a.contact)).copied().collect();
        self.ctx.h = tau;
        self.step_component(comp, &before);
        self.advance_mean(comp, &start, tau);
        self.ctx.h = h - tau;
        let again = self.renewed(comp, near);
        self.step_component(comp, &again);
        self.advance(comp, h - tau);
        comp.iter().for_each(|&k| self.bodies[k].instant = true);
        self.ctx.h = h;
    }

    /// One step of `comp` whole. After a split step the velocities are its end's (see
    /// [`Self::retime`]): this step's kick is then half a step's, which makes them the half
    /// step's again, and the loads' work on the other half of the drift is a correction's.
    fn step_whole(&mut self, comp: &[usize], near: &[Active]) {
        let h = self.ctx.h;
        let instant = comp.iter().any(|&k| self.bodies[k].instant);
        let kick = if instant { 0.5 } else { 1.0 };
        let start = self.velocities(comp);
        self.ctx.h = kick * h;
        self.step_component(comp, near);
        self.ctx.h = h;
        for (&k, [v, w]) in comp.iter().zip(start) {
            let b = &mut self.bodies[k];
            b.kick = [(b.v - v) / kick, (b.w - w) / kick];
            b.instant = false;
            if instant && !b.asleep {
                self.stats.energy.correction += 0.5 * h * b.load_power(&b.v, &b.w);
            }
        }
        self.advance(comp, h);
    }

    /// Symplectic Euler is leapfrog: a step's velocities are its middle's. Before a split step
    /// they are timed to its start by half the last step's kick, so the impact meets the
    /// velocities of its instant (else each impact loses half a step of the motion: first
    /// order). The kinetic energy this changes is accounted ([`super::EnergyBalance::retiming`]).
    fn retime(&mut self, comp: &[usize]) {
        let smooth = SMOOTH * self.ctx.units.g * self.ctx.h;
        for &k in comp {
            let b = &mut self.bodies[k];
            // A kick beyond what the loads give in a step was an impulse (a contact closing),
            // no acceleration to time by.
            if b.kick[0].norm() + b.kick[1].norm() * b.radius > smooth {
                continue;
            }
            let before = b.kinetic_energy();
            b.v += b.kick[0] * 0.5;
            b.w += b.kick[1] * 0.5;
            self.stats.energy.retiming += b.kinetic_energy() - before;
        }
    }

    /// `comp`'s velocities now, in its order.
    fn velocities(&self, comp: &[usize]) -> Vec<[Vector3; 2]> {
        comp.iter().map(|&k| [self.bodies[k].v, self.bodies[k].w]).collect()
    }

    /// Advances `comp`'s awake bodies by `h` s at the mean of the velocities at `start` and now
    /// (the trapezoid: exact under a constant acceleration), keeping the velocities now.
    fn advance_mean(&mut self, comp: &[usize], start: &[[Vector3; 2]], h: f64) {
        for (&k, [v0, w0]) in comp.iter().zip(start) {
            let b = &mut self.bodies[k];
            if b.asleep {
                continue;
            }
            let (v, w) = (b.v, b.w);
            (b.v, b.w) = ((v + v0) * 0.5, (w + w0) * 0.5);
            // The account booked h × the loads' power at the step's end velocities.
            let beyond = h * (b.load_power(&b.v, &b.w) - b.load_power(&v, &w));
            let before = 0.5 * w.dot(&(b.inertia_now() * w));
            let screw = b.advance(h);
            (b.v, b.w) = (v, w);
            self.stats.energy.correction += beyond + b.load_power(&screw, &Vector3::zeros());
            // Turned about the mean spin, not the spin now: its kinetic energy moved with it.
            self.stats.energy.retiming += 0.5 * w.dot(&(b.inertia_now() * w)) - before;
        }
    }

    /// The time within the step (s) at which the first of `comp`'s contacts open at its start
    /// (gap above [`OPEN`] of its scale, or closing faster than that per step) closes at its
    /// closing speed now, when that
    /// falls inside the step; with the contacts that close within [`EDGE`] of a step of it.
    fn impact_time(&self, comp: &[usize], near: &[Active]) -> Option<(f64, Vec<usize>)> {
        if !self.settings.split_impacts {
            return None;
        }
        let h = self.ctx.h;
        let poses = self.poses();
        let mut times = Vec::new();
        for a in near {
            let c = &self.contacts[a.contact];
            if !comp.iter().any(|&k| c.touches(k)) {
                continue;
            }
            if c.mover().is_some() {
                return None;
            }
            let g = &a.geometry;
            // Open, or closing by more than that within the step (a hinge's drift does not).
            let closing = -c.relative_velocity(poses, &g.point).dot(&g.frame[0]);
            let open = OPEN * c.scale;
            if closing > 0.0 && (g.gap > open || closing * h > open) && g.gap > -open {
                times.push((g.gap.max(0.0) / closing, a.contact));
            }
        }
        let first = times.iter().map(|t| t.0).fold(f64::INFINITY, f64::min);
        let closing = times.iter().filter(|t| t.0 <= first + EDGE * h).map(|t| t.1).collect();
        (first < h).then_some((first, closing))
    }

    /// `near`'s contacts of component `comp` at the poses now (those that may still act).
    pub(super) fn renewed(&self, comp: &[usize], near: &[Active]) -> Vec<Active> {
        near.iter()
            .filter(|a| comp.iter().any(|&k| self.contacts[a.contact].touches(k)))
            .filter_map(|a| self.near(a.contact, &self.contacts[a.contact]))
            .collect()
    }
}
