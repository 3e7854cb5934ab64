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
//! the step problem with no velocity, no load and no friction (the step's builder with those
//! zeroed, dt = the time unit). Velocities are untouched; the loads' work on Δ is accounted apart
//! ([`super::EnergyBalance::correction`]).

use super::World;
use super::bodies::Body;
use super::problem::{self, Active, StepContext};
use crate::dynamics::settings::Coulomb;
use crate::geometry::Vector3;
use crate::statics::solve_conic;

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

    /// Moves component `comp`'s bodies by the projection of the module docs over `active`.
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
        let ctx = StepContext { h: unit, recovery: f64::INFINITY, coulomb: Coulomb::Exact, strength: None, ..self.ctx };
        let p = problem::build(&ctx, &still, comp, &local, &self.contacts, active, None);
        let out = solve_conic(&p.conic, self.acc, self.settings.max_iterations);
        self.stats.projections += 1;
        self.stats.solves += 1;
        self.stats.iterations += u64::from(out.iterations);
        if !out.status.solved() {
            self.stats.status = self.stats.status.max(out.status);
            return;
        }
        let sol = p.read(&ctx, &still, comp, active, &out.x);
        for (&k, &(dx, dq)) in comp.iter().zip(&sol.velocities) {
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
}
