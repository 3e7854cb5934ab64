//! What the solver measures of an iterate (clarabel's `DefaultInfo`: residuals, costs, gap,
//! κ/τ) and its termination rules against the tolerances.

use super::iterate::{Rhs, Step, Vars, dot, norm_inf};
use super::points::{ApplyWork, apply};
use super::shape::Shape;
use crate::statics::problem::{Accuracy, SolverStatus};

/// Tolerances: clarabel's defaults with the caller's for feasibility and gap.
pub(super) struct Tolerances {
    pub feas: f64,
    pub gap_abs: f64,
    pub gap_rel: f64,
    /// The relative gap's denominator is max(`rel_floor`, |objective|).
    pub rel_floor: f64,
    pub infeas_abs: f64,
    pub infeas_rel: f64,
    pub ktratio: f64,
}

impl Tolerances {
    pub fn full(acc: Accuracy) -> Self {
        Self {
            feas: acc.feas,
            gap_abs: acc.gap_abs,
            gap_rel: acc.gap_rel,
            rel_floor: if acc.pure_relative { 0.0 } else { 1.0 },
            infeas_abs: 1e-8,
            infeas_rel: 1e-8,
            ktratio: 1e-6,
        }
    }
    pub fn reduced() -> Self {
        Self {
            feas: 1e-4,
            gap_abs: 5e-5,
            gap_rel: 5e-5,
            rel_floor: 1.0,
            infeas_abs: 5e-12,
            infeas_rel: 5e-5,
            ktratio: 1e-4,
        }
    }
}

/// Residuals and the measures of clarabel's `DefaultInfo`.
#[derive(Clone, Default)]
pub(super) struct Info {
    pub rx: Vec<f64>,
    pub re: Vec<f64>,
    pub rg: Vec<f64>,
    pub rtau: f64,
    pub dot_qx: f64,
    pub dot_bz: f64,
    pub dot_sz: f64,
    pub res_primal: f64,
    pub res_dual: f64,
    pub res_primal_inf: f64,
    pub res_dual_inf: f64,
    pub gap_abs: f64,
    /// min(|primal cost|, |dual cost|).
    pub cost: f64,
    pub ktratio: f64,
}

/// What [`info`] works with: scratch for P x, A x's two blocks and K's products, and the
/// problem's constants −q, ‖b‖_∞ and ‖q‖_∞ (computed once).
pub(super) struct MeasureWork {
    pub products: [Vec<f64>; 3],
    pub apply: ApplyWork,
    pub minus_q: Vec<f64>,
    pub norm_b: f64,
    pub norm_q: f64,
}

impl MeasureWork {
    pub fn new<const C: usize>(sh: &Shape<C>) -> Self {
        let (n, me, mg) = (sh.n(), sh.m_e(), sh.m_g());
        Self {
            products: [vec![0.0; n], vec![0.0; me], vec![0.0; mg]],
            apply: ApplyWork::new(sh),
            minus_q: (0..n).map(|j| -sh.q_at(j)).collect(),
            norm_b: sh.norm_b(),
            norm_q: sh.norm_q(),
        }
    }
}

pub(super) fn info<const C: usize>(sh: &Shape<C>, v: &Vars, info: &mut Info, work: &mut MeasureWork) {
    let MeasureWork { products: [px, ex, gx], apply: apply_work, minus_q, norm_b, norm_q } = work;
    let (norm_b, norm_q) = (*norm_b, *norm_q);
    sh.p_mul(&v.x, px);
    let xpx = dot(&v.x, px);
    let (qx, bz, sz) = (sh.q_dot(&v.x), sh.b_dot(&v.ze, &v.z), dot(&v.s, &v.z));
    // rx_inf = −Aᵀz (kept in info.rx first), rz_inf = A x + s.
    let sol = Rhs { x: &v.x, eq: &v.ze, ineq: &v.z };
    apply(sh, None, sol, Step { x: &mut info.rx, eq: ex, ineq: gx }, apply_work);
    info.rx.iter_mut().for_each(|r| *r = -*r);
    for (g, s) in gx.iter_mut().zip(&v.s) {
        *g += s;
    }
    let normx = norm_inf(&v.x);
    let normz = norm_inf(&v.ze).max(norm_inf(&v.z));
    let norms = norm_inf(&v.s);
    let res_primal_inf = norm_inf(&info.rx) / normz.max(1.0);
    let rz_inf = norm_inf(ex).max(norm_inf(gx));
    let res_dual_inf = (norm_inf(px) / normx.max(1.0)).max(rz_inf / (normx + norms).max(1.0));
    // px + τ q, as px − τ (−q): the same bits.
    for ((r, p), mq) in info.rx.iter_mut().zip(px.iter()).zip(minus_q.iter()) {
        *r -= p - v.tau * mq;
    }
    for (i, r) in info.re.iter_mut().enumerate() {
        *r = ex[i] - v.tau * sh.b_e[i];
    }
    // Only the tail's rows and the points' own (`b_points`) have a right-hand side.
    let row0 = sh.tail_row0();
    for (g, b) in gx[row0..].iter_mut().zip(&sh.b_tail) {
        *g -= v.tau * b;
    }
    if let Some(bp) = sh.b_points {
        for (g, b) in gx[..row0].iter_mut().zip(bp) {
            *g -= v.tau * b;
        }
    }
    // gx is scratch, rewritten whole by the next A x: swapped, not copied.
    std::mem::swap(&mut info.rg, gx);
    let tinv = 1.0 / v.tau;
    let half_xpx = xpx * tinv * tinv / 2.0;
    let cost_primal = qx * tinv + half_xpx;
    let cost_dual = -bz * tinv - half_xpx;
    let (normx, normz, norms) = (normx * tinv, normz * tinv, norms * tinv);
    let rz = norm_inf(&info.re).max(norm_inf(&info.rg));
    info.rtau = qx + bz + v.kappa + xpx / v.tau;
    info.dot_qx = qx;
    info.dot_bz = bz;
    info.dot_sz = sz;
    info.res_primal = rz * tinv / (norm_b + normx + norms).max(1.0);
    info.res_dual = norm_inf(&info.rx) * tinv / (norm_q + normx + normz).max(1.0);
    info.res_primal_inf = res_primal_inf;
    info.res_dual_inf = res_dual_inf;
    info.gap_abs = (cost_primal - cost_dual).abs();
    info.cost = cost_primal.abs().min(cost_dual.abs());
    info.ktratio = v.kappa * tinv;
}

impl Info {
    pub fn gap_small(&self, t: &Tolerances) -> bool {
        self.gap_abs < t.gap_abs || self.gap_abs < t.gap_rel * self.cost.max(t.rel_floor)
    }
}

pub(super) fn convergence(info: &Info, t: &Tolerances, almost: bool) -> Option<SolverStatus> {
    let solved = info.gap_small(t) && info.res_primal < t.feas && info.res_dual < t.feas;
    if info.ktratio <= 1.0 && solved {
        return Some(if almost { SolverStatus::AlmostSolved } else { SolverStatus::Solved });
    }
    if info.ktratio > 1000.0 / t.ktratio {
        let pinf = info.dot_bz < -t.infeas_abs && info.res_primal_inf < -t.infeas_rel * info.dot_bz;
        let dinf = info.dot_qx < -t.infeas_abs && info.res_dual_inf < -t.infeas_rel * info.dot_qx;
        if pinf {
            return Some(SolverStatus::Infeasible);
        }
        if dinf {
            return Some(SolverStatus::Unbounded);
        }
    }
    None
}
