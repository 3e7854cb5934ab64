//! A structure-exploiting interior-point method for the equilibrium problems (every friction
//! model): clarabel's algorithm — homogeneous self-dual embedding with the QP extension,
//! Nesterov–Todd scaling of the non-negative and second-order cones, Mehrotra
//! predictor–corrector, its step rules, termination and infeasibility tests and default
//! tolerances — with the Newton system reduced to the 6-per-block equilibrium rows
//! ([`kkt`]) instead of a general LDL of the whole KKT matrix.
//!
//! Why: clarabel factors a KKT matrix of ~57 000 rows for the Armadillo (15 000 variables,
//! 40 000 pyramid rows) with a scalar LDL; here each force point's few variables are
//! eliminated in closed form, the points of an interface are summed in its own frame, and a
//! supernodal Cholesky factors the 2 400-row system. The answer is the same problem's optimum
//! to the same tolerances; tests compare both solvers.

// Numerical kernels index several parallel arrays with one loop variable.
#![allow(clippy::needless_range_loop)]

mod cones;
mod kkt;
mod shape;

use super::problem::ContactProblem;
use super::result::SolverStatus;
use super::solve::Accuracy;
use cones::{Layout, Scaling, shift_to_interior};
use kkt::Kkt;
use shape::Shape;

/// Outcome in the problem's variables (the points', then the budgets' slacks).
pub struct IpmOutcome {
    pub status: SolverStatus,
    pub x: Vec<f64>,
    pub objective: f64,
    pub iterations: u32,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm_inf(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Tolerances: clarabel's defaults with the caller's for feasibility and gap.
struct Tolerances {
    feas: f64,
    gap_abs: f64,
    gap_rel: f64,
    /// The relative gap's denominator is max(`rel_floor`, |objective|).
    rel_floor: f64,
    infeas_abs: f64,
    infeas_rel: f64,
    ktratio: f64,
}

impl Tolerances {
    fn full(acc: Accuracy) -> Self {
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
    fn reduced() -> Self {
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

/// The iterate: x, the equality duals z_E, the inequality slacks and duals (s, z), τ, κ.
#[derive(Clone)]
struct Vars {
    x: Vec<f64>,
    ze: Vec<f64>,
    s: Vec<f64>,
    z: Vec<f64>,
    tau: f64,
    kappa: f64,
}

impl Vars {
    fn zeros(n: usize, me: usize, mg: usize) -> Self {
        Self { x: vec![0.0; n], ze: vec![0.0; me], s: vec![0.0; mg], z: vec![0.0; mg], tau: 0.0, kappa: 0.0 }
    }
}

/// Residuals and the measures of clarabel's `DefaultInfo`.
#[derive(Clone, Default)]
struct Info {
    rx: Vec<f64>,
    re: Vec<f64>,
    rg: Vec<f64>,
    rtau: f64,
    dot_qx: f64,
    dot_bz: f64,
    dot_sz: f64,
    res_primal: f64,
    res_dual: f64,
    res_primal_inf: f64,
    res_dual_inf: f64,
    gap_abs: f64,
    /// min(|primal cost|, |dual cost|).
    cost: f64,
    ktratio: f64,
}

fn info<const C: usize>(sh: &Shape<C>, v: &Vars, info: &mut Info, work: &mut [Vec<f64>; 3]) {
    let [px, ex, gx] = work;
    sh.p_mul(&v.x, px);
    let xpx = dot(&v.x, px);
    let (qx, bz, sz) = (sh.q_dot(&v.x), dot(&sh.b_e, &v.ze), dot(&v.s, &v.z));
    // rx_inf = −Aᵀz (kept in info.rx first), rz_inf = A x + s.
    sh.at_mul(&v.ze, &v.z, &mut info.rx);
    info.rx.iter_mut().for_each(|r| *r = -*r);
    sh.a_mul(&v.x, ex, gx);
    for (g, s) in gx.iter_mut().zip(&v.s) {
        *g += s;
    }
    let normx = norm_inf(&v.x);
    let normz = norm_inf(&v.ze).max(norm_inf(&v.z));
    let norms = norm_inf(&v.s);
    let res_primal_inf = norm_inf(&info.rx) / normz.max(1.0);
    let rz_inf = norm_inf(ex).max(norm_inf(gx));
    let res_dual_inf = (norm_inf(px) / normx.max(1.0)).max(rz_inf / (normx + norms).max(1.0));
    let q = &sh.q;
    for (j, r) in info.rx.iter_mut().enumerate() {
        let qj = if j < sh.points() * C { q[j % C] } else { 0.0 };
        *r -= px[j] + v.tau * qj;
    }
    for (i, r) in info.re.iter_mut().enumerate() {
        *r = ex[i] - v.tau * sh.b_e[i];
    }
    info.rg.copy_from_slice(gx);
    let tinv = 1.0 / v.tau;
    let half_xpx = xpx * tinv * tinv / 2.0;
    let cost_primal = qx * tinv + half_xpx;
    let cost_dual = -bz * tinv - half_xpx;
    let (normx, normz, norms) = (normx * tinv, normz * tinv, norms * tinv);
    let norm_b = norm_inf(&sh.b_e);
    let norm_q = norm_inf(&sh.q);
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
    fn gap_small(&self, t: &Tolerances) -> bool {
        self.gap_abs < t.gap_abs || self.gap_abs < t.gap_rel * self.cost.max(t.rel_floor)
    }
}

fn convergence(info: &Info, t: &Tolerances, almost: bool) -> Option<SolverStatus> {
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

/// Solves `cp`; `None` when it has a shape this solver does not take (it then goes to
/// clarabel).
pub fn solve(cp: &ContactProblem, acc: Accuracy, max_iter: u32) -> Option<IpmOutcome> {
    match cp.per_point() {
        1 => solve_c::<1>(cp, acc, max_iter),
        2 => solve_c::<2>(cp, acc, max_iter),
        3 => solve_c::<3>(cp, acc, max_iter),
        4 => solve_c::<4>(cp, acc, max_iter),
        5 => solve_c::<5>(cp, acc, max_iter),
        _ => None,
    }
}

fn solve_c<const C: usize>(cp: &ContactProblem, acc: Accuracy, max_iter: u32) -> Option<IpmOutcome> {
    let sh = Shape::<C>::new(cp)?;
    let mut kkt = Kkt::<C>::new(&sh)?;
    let (n, me, mg) = (sh.n(), sh.m_e(), sh.m_g());
    let layout = Layout {
        points: sh.points(),
        per_point: sh.m_p,
        nonneg: sh.nonneg.len(),
        soc: sh.soc.is_some(),
        tail: sh.budgets(),
    };
    let is_qp = sh.p.iter().any(|v| *v != 0.0);
    let mut sc = Scaling::identity(layout);
    let outcome = |status: SolverStatus, v: &Vars, iterations: u32| -> IpmOutcome {
        let scale = if v.tau > 0.0 { 1.0 / v.tau } else { 1.0 };
        let x: Vec<f64> = v.x.iter().map(|x| x * scale).collect();
        let objective = 0.5 * sh.p_quad(&x, &x) + sh.q_dot(&x);
        IpmOutcome { status, x, objective, iterations }
    };

    // Initial point: identity scaling, then the shifted least-squares points.
    let mut v = Vars::zeros(n, me, mg);
    v.tau = 1.0;
    v.kappa = 1.0;
    if !kkt.factor(&sh, &sc) {
        return Some(outcome(SolverStatus::NumericalError, &v, 0));
    }
    let zeros_n = vec![0.0; n];
    let zeros_g = vec![0.0; mg];
    let zeros_e = vec![0.0; me];
    let mut minus_q = vec![0.0; n];
    for p in 0..sh.points() {
        for k in 0..C {
            minus_q[p * C + k] = -sh.q[k];
        }
    }
    if is_qp {
        kkt.solve(&sh, &sc, &minus_q, &sh.b_e, &zeros_g, &mut v.x, &mut v.ze, &mut v.z, true);
        for i in 0..mg {
            v.s[i] = -v.z[i];
        }
    } else {
        let mut tmp_e = vec![0.0; me];
        kkt.solve(&sh, &sc, &zeros_n, &sh.b_e, &zeros_g, &mut v.x, &mut tmp_e, &mut v.s, true);
        v.s.iter_mut().for_each(|s| *s = -*s);
        let mut xt = vec![0.0; n];
        kkt.solve(&sh, &sc, &minus_q, &zeros_e, &zeros_g, &mut xt, &mut v.ze, &mut v.z, true);
    }
    shift_to_interior(&layout, &mut v.s);
    shift_to_interior(&layout, &mut v.z);

    let full = Tolerances::full(acc);
    let mut prev: Option<(Vars, Info)> = None;
    let mut iter = 0u32;
    let status;
    let mut inf = Info { rx: vec![0.0; n], re: vec![0.0; me], rg: vec![0.0; mg], ..Default::default() };
    let mut work = [vec![0.0; n], vec![0.0; me], vec![0.0; mg]];
    // Constant part (x2, z2) and the variable part (x1, z1) of each Newton solve.
    let mut c2 = Vars::zeros(n, me, mg);
    let mut c1 = Vars::zeros(n, me, mg);
    let mut aff = Vars::zeros(n, me, mg);
    let mut comb = Vars::zeros(n, me, mg);
    let mut wg = vec![0.0; mg];
    let mut we = vec![0.0; me];
    let mut rg_c = vec![0.0; mg];
    let mut cterm = vec![0.0; mg];
    let mut rx_c = vec![0.0; n];
    let mut re_c = vec![0.0; me];
    let mut xi = vec![0.0; n];
    loop {
        info(&sh, &v, &mut inf, &mut work);
        let mu = (inf.dot_sz + v.tau * v.kappa) / (layout.degree() as f64 + 1.0);
        if let Some(s) = convergence(&inf, &full, false) {
            status = s;
            break;
        }
        if let (Some((_, pi)), true) = (&prev, iter > 1)
            && (inf.res_dual > pi.res_dual || inf.res_primal > pi.res_primal)
        {
            // clarabel's insufficient-progress tests.
            let stalled = inf.ktratio < f64::EPSILON * 100.0 && pi.gap_small(&full);
            let blowing = inf.ktratio < 1.0
                && ((inf.res_dual > full.feas * 100.0 && inf.res_dual > pi.res_dual * 100.0)
                    || (inf.res_primal > full.feas * 100.0 && inf.res_primal > pi.res_primal * 100.0));
            if stalled || blowing {
                status = SolverStatus::InsufficientProgress;
                break;
            }
        }
        if iter >= max_iter {
            status = SolverStatus::MaxIterations;
            break;
        }
        if !sc.update(&v.s, &v.z) {
            status = SolverStatus::NumericalError;
            break;
        }
        iter += 1;
        if !kkt.factor(&sh, &sc) {
            status = SolverStatus::NumericalError;
            break;
        }
        // Constant part of the step: K [x2; z2] = [−q; b].
        if !kkt.solve(&sh, &sc, &minus_q, &sh.b_e, &zeros_g, &mut c2.x, &mut c2.ze, &mut c2.z, true) {
            status = SolverStatus::NumericalError;
            break;
        }
        for j in 0..n {
            xi[j] = v.x[j] / v.tau;
        }
        // One Newton step for the right-hand side (rx, r_E, r_G, the Δs constant term `c`,
        // rτ, rκ); clarabel's DefaultKKTSystem::solve.
        #[allow(clippy::too_many_arguments)]
        let step = |rx: &[f64],
                    re: &[f64],
                    rg: &[f64],
                    c: &[f64],
                    r_tau: f64,
                    r_kappa: f64,
                    refine: bool,
                    kkt: &mut Kkt<C>,
                    c1: &mut Vars,
                    (we, wg): (&mut Vec<f64>, &mut Vec<f64>),
                    out: &mut Vars|
         -> bool {
            // The z right-hand side is c − r_z (c = 0 on the equality rows).
            for i in 0..me {
                we[i] = -re[i];
            }
            for i in 0..mg {
                wg[i] = c[i] - rg[i];
            }
            if !kkt.solve(&sh, &sc, rx, we, wg, &mut c1.x, &mut c1.ze, &mut c1.z, refine) {
                return false;
            }
            let b_z = |ze: &[f64]| dot(&sh.b_e, ze);
            let num = r_tau - r_kappa / v.tau + sh.q_dot(&c1.x) + b_z(&c1.ze) + 2.0 * sh.p_quad(&xi, &c1.x);
            let mut quad = 0.0;
            for p in 0..sh.points() {
                for k in 0..C {
                    let j = p * C + k;
                    let d = xi[j] - c2.x[j];
                    quad += sh.p[k] * (d * d - c2.x[j] * c2.x[j]);
                }
            }
            let den = v.kappa / v.tau - sh.q_dot(&c2.x) - b_z(&c2.ze) + quad;
            let dtau = num / den;
            for j in 0..n {
                out.x[j] = c1.x[j] + dtau * c2.x[j];
            }
            for i in 0..me {
                out.ze[i] = c1.ze[i] + dtau * c2.ze[i];
            }
            for i in 0..mg {
                out.z[i] = c1.z[i] + dtau * c2.z[i];
            }
            sc.ds_from_dz(&out.z, c, &mut out.s);
            out.tau = dtau;
            out.kappa = -(r_kappa + v.kappa * dtau) / v.tau;
            dtau.is_finite() && out.kappa.is_finite()
        };
        let step_len = |dv: &Vars| -> f64 {
            let mut a: f64 = 1.0;
            if dv.tau < 0.0 {
                a = a.min(-v.tau / dv.tau);
            }
            if dv.kappa < 0.0 {
                a = a.min(-v.kappa / dv.kappa);
            }
            let az = sc.step_length(&v.z, &dv.z, a);
            let as_ = sc.step_length(&v.s, &dv.s, a);
            az.min(as_)
        };
        // Affine (predictor) step: Δs constant term s.
        if !step(
            &inf.rx,
            &inf.re,
            &inf.rg,
            &v.s,
            inf.rtau,
            v.tau * v.kappa,
            false,
            &mut kkt,
            &mut c1,
            (&mut we, &mut wg),
            &mut aff,
        ) {
            status = SolverStatus::NumericalError;
            break;
        }
        let alpha_aff = step_len(&aff);
        let sigma = (1.0 - alpha_aff).powi(3);
        let mfac = if iter > 1 { 1.0 } else { alpha_aff };
        // Combined (corrector) step.
        sc.combined_const(&v.s, &v.z, &aff.s, &aff.z, mfac, sigma * mu, &mut cterm);
        for j in 0..n {
            rx_c[j] = (1.0 - sigma) * inf.rx[j];
        }
        for i in 0..me {
            re_c[i] = (1.0 - sigma) * inf.re[i];
        }
        for i in 0..mg {
            rg_c[i] = (1.0 - sigma) * inf.rg[i];
        }
        let r_kappa = -sigma * mu + mfac * aff.tau * aff.kappa + v.tau * v.kappa;
        if !step(
            &rx_c,
            &re_c,
            &rg_c,
            &cterm,
            (1.0 - sigma) * inf.rtau,
            r_kappa,
            true,
            &mut kkt,
            &mut c1,
            (&mut we, &mut wg),
            &mut comb,
        ) {
            status = SolverStatus::NumericalError;
            break;
        }
        let alpha = step_len(&comb) * 0.99;
        if alpha < 1e-4 {
            status = SolverStatus::InsufficientProgress;
            break;
        }
        prev = Some((v.clone(), inf.clone()));
        for j in 0..n {
            v.x[j] += alpha * comb.x[j];
        }
        for i in 0..me {
            v.ze[i] += alpha * comb.ze[i];
        }
        for i in 0..mg {
            v.s[i] += alpha * comb.s[i];
            v.z[i] += alpha * comb.z[i];
        }
        v.tau += alpha * comb.tau;
        v.kappa += alpha * comb.kappa;
    }
    let mut status = status;
    let mut last = inf;
    // Like clarabel: on insufficient progress go back to the last iterate; on trouble or the
    // iteration limit, accept the reduced tolerances.
    if status == SolverStatus::InsufficientProgress
        && let Some((pv, pi)) = prev.take()
    {
        v = pv;
        last = pi;
    }
    if matches!(status, SolverStatus::InsufficientProgress | SolverStatus::NumericalError | SolverStatus::MaxIterations)
        && let Some(s) = convergence(&last, &Tolerances::reduced(), true)
    {
        status = match s {
            SolverStatus::Solved => SolverStatus::AlmostSolved,
            other => other,
        };
    }
    Some(outcome(status, &v, iter))
}

#[cfg(test)]
mod tests;
