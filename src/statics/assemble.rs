//! Assembles the conic problem of one component and one stage as plain data (triplets), in
//! the row and variable order documented in the module above. No solver types here.

use super::components::Component;
use super::settings::{FrictionModel, StaticsSettings};
use crate::geometry::{Point3, Vector3};
use crate::interfaces::{Body, Interface};
use crate::model::{Assembly, BlockId};
use std::collections::HashMap;

/// Cones in row order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cone {
    Zero(usize),
    Nonnegative(usize),
    SecondOrder(usize),
}

/// minimise ½ xᵀ diag(p) x + qᵀ x subject to A x + s = b, s ∈ cones.
#[derive(Clone, Debug, Default)]
pub struct Problem {
    pub n: usize,
    pub p_diag: Vec<f64>,
    pub q: Vec<f64>,
    /// (row, column, value) of A.
    pub a: Vec<(usize, usize, f64)>,
    pub b: Vec<f64>,
    pub cones: Vec<Cone>,
}

impl Problem {
    pub fn m(&self) -> usize {
        self.b.len()
    }
}

/// Variables of a force point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Var {
    CnPos,
    CnNeg,
    Cu,
    Cv,
    Slack,
}

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
    /// Equilibrium triplets (rows 0..eq_rows) and right-hand side, non-dimensional.
    pub eq: Vec<(usize, usize, f64)>,
    pub eq_rhs: Vec<f64>,
    /// Force scale: the component's free weight, N (lengths are scaled by the model size).
    pub force_scale: f64,
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
        let length_scale = assembly.scale;
        let local: HashMap<BlockId, usize> = comp.blocks.iter().enumerate().map(|(i, &b)| (b, i)).collect();
        let mut points = Vec::new();
        for &k in &comp.interfaces {
            for p in &interfaces[k].polygon {
                points.push(ForcePoint { interface: k, position: *p });
            }
        }
        let mut eq = Vec::with_capacity(points.len() * layout.per_point * 12);
        for (i, fp) in points.iter().enumerate() {
            let itf = &interfaces[fp.interface];
            let f = &itf.frame;
            let dirs = [(Var::CnPos, f.n), (Var::CnNeg, -f.n), (Var::Cu, f.u), (Var::Cv, f.v)];
            for (body, sign) in [(itf.b, 1.0), (itf.a, -1.0)] {
                let Body::Block(id) = body else { continue };
                let Some(&row_block) = local.get(&id) else { continue };
                let r: Vector3 = (fp.position - assembly.block(id).mass.centroid) / length_scale;
                let row = 6 * row_block;
                for &(var, d) in &dirs {
                    let Some(off) = layout.offset(var) else { continue };
                    let col = i * layout.per_point + off;
                    let d = d * sign;
                    let m = r.cross(&d);
                    for k in 0..3 {
                        if d[k] != 0.0 {
                            eq.push((row + k, col, d[k]));
                        }
                        if m[k] != 0.0 {
                            eq.push((row + 3 + k, col, m[k]));
                        }
                    }
                }
            }
        }
        let mut eq_rhs = vec![0.0; 6 * comp.blocks.len()];
        for (i, &b) in comp.blocks.iter().enumerate() {
            let w = g * assembly.block(b).mass() / force_scale;
            for k in 0..3 {
                eq_rhs[6 * i + k] = -w[k];
            }
        }
        Self { points, layout, mu, model, eq, eq_rhs, force_scale }
    }

    fn residual_vector(&self, x: &[f64]) -> Vec<f64> {
        let mut r: Vec<f64> = self.eq_rhs.iter().map(|b| -b).collect();
        for &(i, j, v) in &self.eq {
            r[i] += v * x[j];
        }
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
        let apply_at = |y: &[f64], out: &mut Vec<f64>| {
            out.iter_mut().for_each(|v| *v = 0.0);
            for &(i, j, v) in &self.eq {
                out[j] += v * y[i];
            }
        };
        let apply_a = |z: &[f64], out: &mut Vec<f64>| {
            out.iter_mut().for_each(|v| *v = 0.0);
            for &(i, j, v) in &self.eq {
                out[i] += v * z[j];
            }
        };
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
    /// Relaxed: Σ s with Σ c_n⁻ ≤ the tension budget.
    FrictionExcess { tension: f64 },
    /// Relaxed: the weighted quadratic with both budgets.
    Distribution { tension: f64, excess: f64 },
}

/// The full problem of one stage over `sys` (strict stage ⇔ strict layout).
pub fn problem(sys: &System, stage: Stage, settings: &StaticsSettings) -> Problem {
    let n = sys.n();
    let np = sys.points.len();
    let lay = sys.layout;
    let mut p_diag = vec![0.0; n];
    let mut q = vec![0.0; n];
    let set = |v: &mut Vec<f64>, i: usize, var: Var, value: f64| {
        if let Some(c) = sys.col(i, var) {
            v[c] = value;
        }
    };
    for i in 0..np {
        match stage {
            Stage::Tension => set(&mut q, i, Var::CnNeg, 1.0),
            Stage::FrictionExcess { .. } => set(&mut q, i, Var::Slack, 1.0),
            Stage::Strict | Stage::Distribution { .. } => {
                // ½ xᵀPx: the diagonal holds 2w.
                set(&mut p_diag, i, Var::CnPos, 2.0 * settings.w_compression);
                set(&mut p_diag, i, Var::CnNeg, 2.0 * settings.w_tension);
                set(&mut p_diag, i, Var::Cu, 2.0 * settings.w_friction);
                set(&mut p_diag, i, Var::Cv, 2.0 * settings.w_friction);
                set(&mut p_diag, i, Var::Slack, 2.0 * settings.w_slack);
            }
        }
    }
    let mut a = sys.eq.clone();
    let mut b = sys.eq_rhs.clone();
    // When the minimum tension is zero (to what the LP resolves), the later stages pin every
    // c_n⁻ to 0 by equality rows instead of a budget Σ c_n⁻ ≤ ~0: an inequality budget at zero
    // leaves the interior-point method no interior (the friction-excess LP then took 60–200
    // iterations on partial vaults instead of ~20).
    let pinned = match stage {
        Stage::FrictionExcess { tension } | Stage::Distribution { tension, .. } => tension <= PINNED_TENSION,
        _ => false,
    };
    if pinned {
        for i in 0..np {
            if let Some(col) = sys.col(i, Var::CnNeg) {
                a.push((b.len(), col, 1.0));
                b.push(0.0);
            }
        }
    }
    let mut cones = vec![Cone::Zero(b.len())];
    let nonneg_start = b.len();
    let push_row = |a: &mut Vec<(usize, usize, f64)>, b: &mut Vec<f64>, entries: &[(Option<usize>, f64)], rhs: f64| {
        let row = b.len();
        for &(col, v) in entries {
            if let Some(col) = col {
                a.push((row, col, v));
            }
        }
        b.push(rhs);
    };
    // Sign rows −x ≤ 0. With friction in the strict layout, c_n⁺ ≥ 0 follows from the friction
    // rows (|c_u| ≤ μ c_n⁺), so the row is left out.
    for i in 0..np {
        if lay.relaxed || !lay.friction {
            push_row(&mut a, &mut b, &[(sys.col(i, Var::CnPos), -1.0)], 0.0);
        }
        if lay.relaxed && !pinned {
            push_row(&mut a, &mut b, &[(sys.col(i, Var::CnNeg), -1.0)], 0.0);
        }
        if lay.relaxed && lay.friction {
            push_row(&mut a, &mut b, &[(sys.col(i, Var::Slack), -1.0)], 0.0);
        }
    }
    // Budgets, loosened by 1e-6 (relative) and 1e-9 W (absolute): the optimum of the previous
    // stage stays strictly feasible, and the interior-point method keeps room to move (a
    // budget at exactly the minimum leaves a degenerate feasible set).
    let budget = |value: f64| value * (1.0 + 1e-6) + 1e-9;
    let tension_budget = match stage {
        Stage::FrictionExcess { tension } | Stage::Distribution { tension, .. } if !pinned => Some(budget(tension)),
        _ => None,
    };
    if let Some(t) = tension_budget {
        let entries: Vec<(Option<usize>, f64)> = (0..np).map(|i| (sys.col(i, Var::CnNeg), 1.0)).collect();
        push_row(&mut a, &mut b, &entries, t);
    }
    if let (Stage::Distribution { excess, .. }, true) = (stage, lay.friction) {
        let entries: Vec<(Option<usize>, f64)> = (0..np).map(|i| (sys.col(i, Var::Slack), 1.0)).collect();
        push_row(&mut a, &mut b, &entries, budget(excess));
    }
    if lay.friction && sys.model != FrictionModel::Cone {
        let mu = sys.mu;
        let r2 = std::f64::consts::SQRT_2;
        for i in 0..np {
            let (cn, cu, cv, s) =
                (sys.col(i, Var::CnPos), sys.col(i, Var::Cu), sys.col(i, Var::Cv), sys.col(i, Var::Slack));
            for (du, dv) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
                let (eu, ev) = (if du != 0.0 { cu } else { None }, if dv != 0.0 { cv } else { None });
                push_row(&mut a, &mut b, &[(eu, du), (ev, dv), (cn, -mu), (s, -1.0)], 0.0);
            }
            if sys.model == FrictionModel::Pyramid8 {
                for (du, dv) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    push_row(&mut a, &mut b, &[(cu, du), (cv, dv), (cn, -r2 * mu), (s, -r2)], 0.0);
                }
            }
        }
    }
    cones.push(Cone::Nonnegative(b.len() - nonneg_start));
    if lay.friction && sys.model == FrictionModel::Cone {
        for i in 0..np {
            // s = b − A x = (μ c_n⁺ + s, c_u, c_v) ∈ SOC(3).
            push_row(&mut a, &mut b, &[(sys.col(i, Var::CnPos), -sys.mu), (sys.col(i, Var::Slack), -1.0)], 0.0);
            push_row(&mut a, &mut b, &[(sys.col(i, Var::Cu), -1.0)], 0.0);
            push_row(&mut a, &mut b, &[(sys.col(i, Var::Cv), -1.0)], 0.0);
            cones.push(Cone::SecondOrder(3));
        }
    }
    Problem { n, p_diag, q, a, b, cones }
}
