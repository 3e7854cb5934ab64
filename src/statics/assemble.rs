//! Assembles the problem of one component and one stage as plain data (contact form; the
//! equilibrium operator A_eq and its transpose for residuals and polishing come from the same
//! form), in the row and variable order documented in the statics module. No solver types here.

use super::components::Component;
use super::problem::{
    Budget, Contact, ContactProblem, Crushing, FrictionModel, Geometry, Side, Strength, StressBlock, Var, motion_at,
    wrench,
};
use super::settings::StaticsSettings;
use crate::geometry::{Point3, Vector3};
use crate::interfaces::{Body, Interface};
use crate::model::{Assembly, BlockId};
use std::collections::HashMap;

/// Which variables a point has, and their offsets within its block of columns.
/// Strict systems (no tension, no friction slack) have `[c_n⁺, c_u, c_v]`; relaxed ones
/// `[c_n⁺, c_n⁻, c_u, c_v, s]`; without friction `c_u, c_v, s` are left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub relaxed: bool,
    pub friction: bool,
    pub per_point: usize,
}

impl Layout {
    pub fn new(relaxed: bool, friction: bool) -> Self {
        let per_point = 1 + relaxed as usize + 2 * friction as usize + (relaxed && friction) as usize;
        Self { relaxed, friction, per_point }
    }

    pub fn offset(&self, var: Var) -> Option<usize> {
        let r = self.relaxed as usize;
        match var {
            Var::CnPos => Some(0),
            Var::CnNeg => self.relaxed.then_some(1),
            Var::Cu => self.friction.then_some(1 + r),
            Var::Cv => self.friction.then_some(2 + r),
            Var::Slack => (self.relaxed && self.friction).then_some(4),
        }
    }
}

/// One force point: an interface vertex.
#[derive(Clone, Copy, Debug)]
pub struct ForcePoint {
    pub interface: usize,
    pub position: Point3,
}

/// The stage-independent part of a component's problem: variable layout and equilibrium rows.
#[derive(Clone, Debug)]
pub struct System {
    pub points: Vec<ForcePoint>,
    pub layout: Layout,
    pub mu: f64,
    pub model: FrictionModel,
    /// Right-hand side of the equilibrium rows (6 per block), non-dimensional. The rows
    /// themselves are applied from `geometry` ([`Self::a_mul`], [`Self::at_mul`]): stored as
    /// triplets beside it they were 18–30 entries of 24 bytes per force point, half the memory
    /// between detection and the solve (0.5 GB on a 100 000-brick wall).
    pub eq_rhs: Vec<f64>,
    /// Force scale: the component's free weight, N (lengths are scaled by the model size).
    pub force_scale: f64,
    /// The same rows in contact form (what the stages' problems are made of).
    pub geometry: Geometry,
    /// Each interface's stress block, when crushing is checked ([`Self::with_stress`]).
    pub stress: Vec<StressBlock>,
}

impl System {
    pub fn n(&self) -> usize {
        self.points.len() * self.layout.per_point
    }

    /// Column of `var` of point `point`, if the layout has it.
    pub fn col(&self, point: usize, var: Var) -> Option<usize> {
        self.layout.offset(var).map(|o| point * self.layout.per_point + o)
    }

    /// Value of `var` of point `point` in `x` (0 when the layout has no such variable).
    pub fn value(&self, x: &[f64], point: usize, var: Var) -> f64 {
        self.col(point, var).map_or(0.0, |c| x[c])
    }

    /// Builds the layout and equilibrium rows of `comp`.
    pub fn new(
        assembly: &Assembly,
        interfaces: &[Interface],
        comp: &Component,
        mu: f64,
        model: FrictionModel,
        relaxed: bool,
    ) -> Self {
        // μ = 0: the strict problem has no friction columns at all; the relaxed one keeps them
        // (capacity 0 + slack) so that a sliding failure is measured as friction excess
        // rather than reported as "no equilibrium".
        let layout = Layout::new(relaxed, mu > 0.0 || relaxed);
        let g = assembly.gravity;
        let force_scale: f64 =
            comp.blocks.iter().map(|&b| assembly.block(b).mass() * g.norm()).sum::<f64>().max(f64::MIN_POSITIVE);
        let local: HashMap<BlockId, usize> = comp.blocks.iter().enumerate().map(|(i, &b)| (b, i)).collect();
        let mut points = Vec::new();
        for &k in &comp.interfaces {
            for p in &interfaces[k].polygon {
                points.push(ForcePoint { interface: k, position: *p });
            }
        }
        let eq_rhs = dead_load_rhs(assembly, comp, force_scale);
        let geometry = contact_geometry(assembly, interfaces, comp, &local, eq_rhs.clone());
        Self { points, layout, mu, model, eq_rhs, force_scale, geometry, stress: Vec::new() }
    }

    /// The system with its interfaces' stress blocks, for the crushing rows.
    pub fn with_stress(mut self) -> Self {
        self.stress = self.geometry.stress_blocks();
        self
    }

    /// A compressive strength σ_c (Pa) in the problems' units: forces by the component's free
    /// weight, areas by the model size squared.
    pub fn strength_scale(&self, length_scale: f64) -> f64 {
        length_scale * length_scale / self.force_scale
    }

    /// The strength (non-dimensional) the normal forces in `x` need at each of `blocks` (this
    /// system's stress blocks, [`StressBlock::demand`]).
    pub fn stress_demands(&self, blocks: &[StressBlock], x: &[f64]) -> Vec<f64> {
        let g = &self.geometry;
        blocks
            .iter()
            .map(|block| {
                let at: Vec<[f64; 2]> = g.rho[block.points.clone()].iter().map(|r| [r[1], r[2]]).collect();
                let cn: Vec<f64> = block.points.clone().map(|p| self.frame_force(x, p)[0]).collect();
                block.demand(&at, &cn)
            })
            .collect()
    }

    /// The crushing rows at `strength` over this system's stress blocks.
    pub fn crushing(&self, strength: Strength) -> Crushing<'_> {
        Crushing { blocks: &self.stress, strength }
    }

    /// `x` of a stage's problem (its own variables) in this system's layout (the variables a
    /// stage leaves out are 0; the budgets' slacks are dropped).
    pub fn stage_values(&self, cp: &ContactProblem, x: &[f64]) -> Vec<f64> {
        let c = cp.per_point();
        let mut out = vec![0.0; self.n()];
        for i in 0..self.points.len() {
            for (k, &v) in cp.vars.iter().enumerate() {
                if let Some(col) = self.col(i, v) {
                    out[col] = x[i * c + k];
                }
            }
        }
        out
    }

    /// Σ over points of the friction beyond the model's capacity in `x` (non-dimensional): the
    /// slack each point would need, `max(0, max_row (±c_u ± c_v)/k − μ c_n⁺)` for the pyramid
    /// and box rows (k = 1 on the axes, √2 on the pyramid's diagonals), `max(0, ‖(c_u, c_v)‖ −
    /// μ c_n⁺)` for the cone. An upper bound of the minimum friction excess when `x` is an
    /// equilibrium without tension.
    pub fn friction_violation(&self, x: &[f64]) -> f64 {
        (0..self.points.len()).map(|i| self.friction_beyond(x, i)).sum()
    }

    /// Point `i`'s friction beyond the model's capacity in `x` ([`Self::friction_violation`]).
    fn friction_beyond(&self, x: &[f64], i: usize) -> f64 {
        if !self.layout.friction {
            return 0.0;
        }
        let (cn, cu, cv) = (self.value(x, i, Var::CnPos), self.value(x, i, Var::Cu), self.value(x, i, Var::Cv));
        let need = match self.model {
            FrictionModel::Cone => cu.hypot(cv),
            FrictionModel::Box4 => cu.abs().max(cv.abs()),
            FrictionModel::Pyramid8 => cu.abs().max(cv.abs()).max((cu.abs() + cv.abs()) / std::f64::consts::SQRT_2),
        };
        (need - self.mu * cn).max(0.0)
    }

    /// Makes an interior-point solution `x` of a relaxed stage exactly feasible, in place, and
    /// returns its total tension Σ c_n⁻ and friction excess Σ s (non-dimensional): the minima
    /// a stage reports are those of a force state that exists, so each is an upper bound of
    /// the true minimum.
    ///
    /// Why: the interior-point method meets the cone rows to its feasibility tolerance only,
    /// and the LPs of a partial shell have duals (the mechanism's velocities, times the
    /// penalty weight) up to 10⁵: rows missed by 10⁻¹⁰ moved the objective by up to 10⁻⁵ of
    /// itself, below the true optimum (c_n⁻ came back at −2.5e-7 in sum). Checked against
    /// HiGHS (simplex-verified optima, primal = dual to 10 digits) on prefixes of the
    /// Armadillo: the tension of the feasible point is within 1.3e-7 of the optimum, the raw
    /// objective 3e-6 below it.
    ///
    /// The steps: the equilibrium residual polished away; where c_n⁺ or c_n⁻ is negative,
    /// both raised by the same amount (c_n unchanged); each point's slack set to the friction
    /// its forces need beyond μ c_n⁺.
    pub fn make_feasible(&self, x: &mut [f64]) -> (f64, f64) {
        self.polish(x);
        let (mut tension, mut excess) = (0.0, 0.0);
        for i in 0..self.points.len() {
            if let (Some(pos), Some(neg)) = (self.col(i, Var::CnPos), self.col(i, Var::CnNeg)) {
                let lift = 0f64.max(-x[pos]).max(-x[neg]);
                x[pos] += lift;
                x[neg] += lift;
                tension += x[neg];
            }
            let beyond = self.friction_beyond(x, i);
            if let Some(slack) = self.col(i, Var::Slack) {
                x[slack] = beyond;
            }
            excess += beyond;
        }
        (tension, excess)
    }

    /// Point `i`'s force in its interface frame (n, u, v): (c_n⁺ − c_n⁻, c_u, c_v).
    pub(super) fn frame_force(&self, x: &[f64], i: usize) -> [f64; 3] {
        let v = |var| self.value(x, i, var);
        [v(Var::CnPos) - v(Var::CnNeg), v(Var::Cu), v(Var::Cv)]
    }

    /// `A_eq x` into `out` (one entry per equilibrium row): the wrench of the point forces `x`
    /// on each block (non-dimensional), summed per interface about its origin and mapped to its
    /// blocks, as the solvers do ([`Geometry`]).
    pub fn a_mul(&self, x: &[f64], out: &mut [f64]) {
        let g = &self.geometry;
        out.fill(0.0);
        for contact in &g.contacts {
            let mut w = [0.0; 6];
            for p in contact.points.clone() {
                let wp = wrench(&g.rho[p], &self.frame_force(x, p));
                w.iter_mut().zip(wp).for_each(|(a, b)| *a += b);
            }
            for side in contact.sides.iter().flatten() {
                side.add_wrench(&w, &mut out[6 * side.block..6 * side.block + 6]);
            }
        }
    }

    /// `A_eqᵀ y` into `out` (one entry per column of x): per interface the blocks' rows seen
    /// in its frame, u = Σ Ψᵀ y, then per point T_pᵀ u = force part + moment part × ρ_p.
    pub fn at_mul(&self, y: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        let g = &self.geometry;
        for contact in &g.contacts {
            let mut u = [0.0; 6];
            for side in contact.sides.iter().flatten() {
                side.add_seen(&y[6 * side.block..6 * side.block + 6], &mut u);
            }
            for p in contact.points.clone() {
                let t = motion_at(&u, &g.rho[p]);
                for (var, v) in [(Var::CnPos, t[0]), (Var::CnNeg, -t[0]), (Var::Cu, t[1]), (Var::Cv, t[2])] {
                    if let Some(col) = self.col(p, var) {
                        out[col] = v;
                    }
                }
            }
        }
    }

    /// The equilibrium rows as (row, column, value) triplets, for a solver that takes a matrix
    /// (the kinematic check's rounds).
    pub fn eq_triplets(&self) -> Vec<(usize, usize, f64)> {
        let g = &self.geometry;
        let units = [
            (Var::CnPos, [1.0, 0.0, 0.0]),
            (Var::CnNeg, [-1.0, 0.0, 0.0]),
            (Var::Cu, [0.0, 1.0, 0.0]),
            (Var::Cv, [0.0, 0.0, 1.0]),
        ];
        let mut out = Vec::new();
        for contact in &g.contacts {
            for p in contact.points.clone() {
                for (var, e) in units {
                    if let Some(col) = self.col(p, var) {
                        contact.force_rows(&g.rho[p], &e, |row, v| out.push((row, col, v)));
                    }
                }
            }
        }
        out
    }

    /// `A_eq x − b_eq` (non-dimensional).
    pub fn residual_vector(&self, x: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; self.eq_rhs.len()];
        self.a_mul(x, &mut r);
        r.iter_mut().zip(&self.eq_rhs).for_each(|(r, b)| *r -= b);
        r
    }

    /// ‖A_eq x − b_eq‖_∞ (non-dimensional).
    pub fn residual(&self, x: &[f64]) -> f64 {
        self.residual_vector(x).iter().fold(0.0, |m, v| m.max(v.abs()))
    }

    /// Removes the equilibrium residual an interior-point solution keeps (≈ its tolerance) by
    /// the minimum-norm correction x ← x − Aᵀy with A Aᵀ y = r, solved by conjugate gradients
    /// (CGNE). The correction is of the size of the residual, so the cone constraints move by
    /// as little. Stops when the residual no longer shrinks.
    pub fn polish(&self, x: &mut [f64]) {
        let m = self.eq_rhs.len();
        let apply_at = |y: &[f64], out: &mut Vec<f64>| self.at_mul(y, out);
        let apply_a = |z: &[f64], out: &mut Vec<f64>| self.a_mul(z, out);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let r0 = self.residual_vector(x);
        let start = self.residual(x);
        // Already at round-off (the usual case for the strict QP): nothing to gain.
        if start <= 1e-13 {
            return;
        }
        // CG on (A Aᵀ) y = r0.
        let mut y = vec![0.0; m];
        let mut r = r0.clone();
        let mut p = r.clone();
        let mut rr = dot(&r, &r);
        let (mut atp, mut q) = (vec![0.0; x.len()], vec![0.0; m]);
        for _ in 0..200 {
            apply_at(&p, &mut atp);
            apply_a(&atp, &mut q);
            let pq = dot(&p, &q);
            if pq <= 0.0 {
                break;
            }
            let alpha = rr / pq;
            y.iter_mut().zip(&p).for_each(|(yi, pi)| *yi += alpha * pi);
            r.iter_mut().zip(&q).for_each(|(ri, qi)| *ri -= alpha * qi);
            let rr_new = dot(&r, &r);
            if rr_new.sqrt() <= 1e-6 * start {
                break;
            }
            let beta = rr_new / rr;
            rr = rr_new;
            p.iter_mut().zip(&r).for_each(|(pi, ri)| *pi = ri + beta * *pi);
        }
        let mut correction = vec![0.0; x.len()];
        apply_at(&y, &mut correction);
        let candidate: Vec<f64> = x.iter().zip(&correction).map(|(a, c)| a - c).collect();
        if self.residual(&candidate) < start {
            x.copy_from_slice(&candidate);
        }
    }
}

/// Minus the dead load of each block of `comp` — self-weight and the dead [`BlockLoads`] —
/// non-dimensional (forces by `force_scale`, moments also by the model size): the right-hand
/// side of the equilibrium rows.
///
/// [`BlockLoads`]: crate::model::BlockLoads
pub fn dead_load_rhs(assembly: &Assembly, comp: &Component, force_scale: f64) -> Vec<f64> {
    let mut rhs = vec![0.0; 6 * comp.blocks.len()];
    for (i, &b) in comp.blocks.iter().enumerate() {
        let w = assembly.gravity * assembly.block(b).mass();
        let dead = assembly.loads[b.0].dead;
        for k in 0..3 {
            rhs[6 * i + k] = -(w[k] + dead[k]) / force_scale;
            rhs[6 * i + 3 + k] = -dead[3 + k] / (force_scale * assembly.scale);
        }
    }
    rhs
}

/// The live load of each block of `comp` in the same rows and scaling as [`dead_load_rhs`]
/// (with the opposite sign: the load itself, what λ multiplies).
pub fn live_load(assembly: &Assembly, comp: &Component, force_scale: f64) -> Vec<f64> {
    let mut out = vec![0.0; 6 * comp.blocks.len()];
    for (i, &b) in comp.blocks.iter().enumerate() {
        let live = assembly.loads[b.0].live;
        for k in 0..3 {
            out[6 * i + k] = live[k] / force_scale;
            out[6 * i + 3 + k] = live[3 + k] / (force_scale * assembly.scale);
        }
    }
    out
}

/// The contact form of a component's rows (module docs of [`super::problem`]).
fn contact_geometry(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    local: &HashMap<BlockId, usize>,
    rhs: Vec<f64>,
) -> Geometry {
    let l = assembly.scale;
    let mut contacts = Vec::with_capacity(comp.interfaces.len());
    let mut rho = Vec::new();
    for &k in &comp.interfaces {
        let itf = &interfaces[k];
        let f = &itf.frame;
        let o = itf.frame.origin.coords / l;
        let start = rho.len();
        for p in &itf.polygon {
            let d = p.coords / l - o;
            rho.push([d.dot(&f.n), d.dot(&f.u), d.dot(&f.v)]);
        }
        let cols = [f.n, f.u, f.v];
        let side = |body: Body, sign: f64| -> Option<Side> {
            let Body::Block(id) = body else { return None };
            let &block = local.get(&id)?;
            let arm: Vector3 = o - assembly.block(id).mass.centroid.coords / l;
            Some(Side::new(block, cols.map(|c| [c.x, c.y, c.z]), [arm.x, arm.y, arm.z], sign))
        };
        contacts.push(Contact { points: start..rho.len(), sides: [side(itf.a, -1.0), side(itf.b, 1.0)] });
    }
    Geometry { blocks: comp.blocks.len(), rhs, contacts, rho }
}

/// A minimum tension (relative to the component's weight) at or below this is zero: the
/// minimum-tension LP is solved to 1e-10, so smaller values are its round-off.
pub const PINNED_TENSION: f64 = 1e-10;

/// What a stage minimises and which budgets it respects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stage {
    /// Strict system: the weighted quadratic, no tension, friction within μ.
    Strict,
    /// Relaxed: Σ c_n⁻ (friction slack free).
    Tension,
    /// Relaxed: Σ s with the tension at its minimum `tension`. With `penalty` M > 0 the exact
    /// penalty form `M Σ c_n⁻ + Σ s` (no budget; the caller checks that Σ c_n⁻ came back at
    /// the minimum, i.e. that M was large enough); with 0 the budget Σ c_n⁻ ≤ `tension`.
    FrictionExcess { tension: f64, penalty: f64 },
    /// Relaxed: the weighted quadratic with both budgets.
    Distribution { tension: f64, excess: f64 },
    /// Strict system with the crushing rows: the least strength σ (non-dimensional) its
    /// equilibria need, minimised.
    Strength,
    /// Strict system with the crushing rows at `strength` (non-dimensional): the weighted
    /// quadratic over the equilibria the stone can carry.
    Capped { strength: f64 },
}

/// The tension budget of the later stages for a minimum tension `t` (relative): loosened by
/// 1e-6 (relative) and 1e-9 (absolute), so that the optimum of the previous stage stays
/// strictly feasible.
pub fn tension_budget(t: f64) -> f64 {
    t * (1.0 + 1e-6) + 1e-9
}

/// The problem of one stage over `sys` (strict stage ⇔ strict layout) in contact form.
///
/// When the minimum tension is zero (to what the LP resolves), the budget forms leave c_n⁻
/// out altogether instead of a budget Σ c_n⁻ ≤ ~0: an inequality budget at zero leaves the
/// interior-point method no interior. Budgets are [`tension_budget`]s.
pub fn contact_problem<'a>(sys: &'a System, stage: Stage, settings: &StaticsSettings) -> ContactProblem<'a> {
    let lay = sys.layout;
    let pinned = match stage {
        Stage::FrictionExcess { tension, penalty } => penalty == 0.0 && tension <= PINNED_TENSION,
        Stage::Distribution { tension, .. } => tension <= PINNED_TENSION,
        _ => false,
    };
    let vars: Vec<Var> = [Var::CnPos, Var::CnNeg, Var::Cu, Var::Cv, Var::Slack]
        .into_iter()
        .filter(|&v| lay.offset(v).is_some() && !(pinned && v == Var::CnNeg))
        .collect();
    let weight = |v: Var| -> f64 {
        2.0 * match v {
            Var::CnPos => settings.w_compression,
            Var::CnNeg => settings.w_tension,
            Var::Cu | Var::Cv => settings.w_friction,
            Var::Slack => settings.w_slack,
        }
    };
    let (p, q): (Vec<f64>, Vec<f64>) = vars
        .iter()
        .map(|&v| match stage {
            Stage::Tension => (0.0, (v == Var::CnNeg) as u8 as f64),
            Stage::FrictionExcess { penalty, .. } => match v {
                Var::Slack => (0.0, 1.0),
                Var::CnNeg => (0.0, penalty),
                _ => (0.0, 0.0),
            },
            Stage::Strength => (0.0, 0.0),
            Stage::Strict | Stage::Distribution { .. } | Stage::Capped { .. } => (weight(v), 0.0),
        })
        .unzip();
    let mut budgets = Vec::new();
    match stage {
        Stage::FrictionExcess { tension, penalty: 0.0 } | Stage::Distribution { tension, .. } if !pinned => {
            budgets.push(Budget { var: Var::CnNeg, limit: tension_budget(tension) });
        }
        _ => {}
    }
    if let (Stage::Distribution { excess, .. }, true) = (stage, lay.friction) {
        budgets.push(Budget { var: Var::Slack, limit: tension_budget(excess) });
    }
    let threads = if settings.parallel { 2 } else { 1 };
    let crushing = match stage {
        Stage::Strength => Some(sys.crushing(Strength::Least)),
        Stage::Capped { strength } => Some(sys.crushing(Strength::Fixed(strength))),
        _ => None,
    };
    ContactProblem {
        geometry: &sys.geometry,
        vars,
        model: sys.model,
        mu: sys.mu,
        p,
        q,
        budgets,
        factor: None,
        threads,
        crushing,
        columns: Vec::new(),
        rows: None,
        point_q: Vec::new(),
        point_b: Vec::new(),
    }
}
