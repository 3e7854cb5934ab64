//! A structure-exploiting interior-point method for the polyhedral problems (pyramid8, box4,
//! no friction): clarabel's algorithm (homogeneous self-dual embedding with the QP extension,
//! Mehrotra predictor–corrector, its termination and infeasibility tests and default
//! tolerances), with the Newton system reduced to the 6-per-block equality rows
//! ([`kkt`]) instead of a general LDL of the whole KKT matrix.
//!
//! Why: clarabel's QDLDL factors a KKT matrix of ~57 000 rows for the Armadillo (15 000
//! variables, 40 000 pyramid rows) in scalar code; here each force point's few variables are
//! eliminated in closed form and a supernodal Cholesky factors the 2 400-row system. The
//! answer is the same problem's optimum to the same tolerances; tests compare both solvers.
//!
//! Problems of another shape (second-order cones, large groups) return `None` and go to
//! clarabel, which stays the reference and the solver of the cone model.

// Numerical kernels index several parallel arrays with one loop variable.
#![allow(clippy::needless_range_loop)]

mod kkt;
mod structure;

use super::assemble::Problem;
use super::result::SolverStatus;
use kkt::Kkt;
use structure::Structured;

/// Outcome in the original variables.
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

/// Tolerances: clarabel's defaults with `tol` for feasibility and gap.
struct Tolerances {
    feas: f64,
    gap_abs: f64,
    gap_rel: f64,
    infeas_abs: f64,
    infeas_rel: f64,
    ktratio: f64,
}

impl Tolerances {
    fn full(tol: f64) -> Self {
        Self { feas: tol, gap_abs: tol, gap_rel: tol, infeas_abs: 1e-8, infeas_rel: 1e-8, ktratio: 1e-6 }
    }
    fn reduced() -> Self {
        Self { feas: 1e-4, gap_abs: 5e-5, gap_rel: 5e-5, infeas_abs: 5e-12, infeas_rel: 5e-5, ktratio: 1e-4 }
    }
}

#[derive(Clone)]
struct Vars {
    x: Vec<f64>,
    /// Row order: equality rows (s = 0), then inequality rows.
    s: Vec<f64>,
    z: Vec<f64>,
    tau: f64,
    kappa: f64,
}

/// Residuals and the measures of clarabel's `DefaultInfo`.
#[derive(Clone, Default)]
struct Info {
    rx: Vec<f64>,
    rz: Vec<f64>,
    rtau: f64,
    dot_qx: f64,
    dot_bz: f64,
    dot_sz: f64,
    res_primal: f64,
    res_dual: f64,
    res_primal_inf: f64,
    res_dual_inf: f64,
    gap_abs: f64,
    gap_rel: f64,
    ktratio: f64,
}

struct Data {
    st: Structured,
    /// b = [b_E; h].
    b: Vec<f64>,
    norm_b: f64,
    norm_q: f64,
    is_qp: bool,
}

impl Data {
    fn m(&self) -> usize {
        self.b.len()
    }

    /// A x as [E x; G x].
    fn a_mul(&self, x: &[f64], out: &mut [f64]) {
        for (i, row) in self.st.e_rows.iter().chain(&self.st.g_rows).enumerate() {
            out[i] = row.iter().map(|&(j, v)| v * x[j]).sum();
        }
    }

    /// Aᵀ z.
    fn at_mul(&self, z: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for (i, row) in self.st.e_rows.iter().chain(&self.st.g_rows).enumerate() {
            for &(j, v) in row {
                out[j] += v * z[i];
            }
        }
    }

    fn info(&self, v: &Vars) -> Info {
        let (n, m) = (self.st.n, self.m());
        let p = &self.st.p;
        let px: Vec<f64> = (0..n).map(|j| p[j] * v.x[j]).collect();
        let xpx = dot(&v.x, &px);
        let (qx, bz, sz) = (dot(&self.st.q, &v.x), dot(&self.b, &v.z), dot(&v.s, &v.z));
        let mut rx_inf = vec![0.0; n];
        self.at_mul(&v.z, &mut rx_inf);
        rx_inf.iter_mut().for_each(|r| *r = -*r);
        let mut rz_inf = vec![0.0; m];
        self.a_mul(&v.x, &mut rz_inf);
        for i in 0..m {
            rz_inf[i] += v.s[i];
        }
        let rx: Vec<f64> = (0..n).map(|j| rx_inf[j] - px[j] - v.tau * self.st.q[j]).collect();
        let rz: Vec<f64> = (0..m).map(|i| rz_inf[i] - v.tau * self.b[i]).collect();
        let rtau = qx + bz + v.kappa + xpx / v.tau;
        let tinv = 1.0 / v.tau;
        let half_xpx = xpx * tinv * tinv / 2.0;
        let cost_primal = qx * tinv + half_xpx;
        let cost_dual = -bz * tinv - half_xpx;
        let (normx, normz, norms) = (norm_inf(&v.x), norm_inf(&v.z), norm_inf(&v.s));
        let res_primal_inf = norm_inf(&rx_inf) / normz.max(1.0);
        let res_dual_inf = (norm_inf(&px) / normx.max(1.0)).max(norm_inf(&rz_inf) / (normx + norms).max(1.0));
        let (normx, normz, norms) = (normx * tinv, normz * tinv, norms * tinv);
        let res_primal = norm_inf(&rz) * tinv / (self.norm_b + normx + norms).max(1.0);
        let res_dual = norm_inf(&rx) * tinv / (self.norm_q + normx + normz).max(1.0);
        let gap_abs = (cost_primal - cost_dual).abs();
        let gap_rel = gap_abs / cost_primal.abs().min(cost_dual.abs()).max(1.0);
        Info {
            rx,
            rz,
            rtau,
            dot_qx: qx,
            dot_bz: bz,
            dot_sz: sz,
            res_primal,
            res_dual,
            res_primal_inf,
            res_dual_inf,
            gap_abs,
            gap_rel,
            ktratio: v.kappa * tinv,
        }
    }
}

fn convergence(info: &Info, t: &Tolerances, almost: bool) -> Option<SolverStatus> {
    let solved =
        (info.gap_abs < t.gap_abs || info.gap_rel < t.gap_rel) && info.res_primal < t.feas && info.res_dual < t.feas;
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

/// Shifts the inequality part of `v` into the interior (clarabel's symmetric initialisation).
fn shift_to_interior(v: &mut [f64]) {
    if v.is_empty() {
        return;
    }
    let min = v.iter().cloned().fold(f64::INFINITY, f64::min);
    let pos: f64 = v.iter().map(|x| x.max(0.0)).sum();
    let target = (0.1 * pos / v.len() as f64).max(1.0);
    let shift = if min <= 0.0 {
        -min + target
    } else if min < target {
        target - min
    } else {
        0.0
    };
    v.iter_mut().for_each(|x| *x += shift);
}

/// Largest step in (0, cap] keeping `v + α dv ≥ 0`.
fn max_step(v: &[f64], dv: &[f64], cap: f64) -> f64 {
    let mut a = cap;
    for (x, d) in v.iter().zip(dv) {
        if *d < 0.0 {
            a = a.min(-x / d);
        }
    }
    a
}

/// Solves `p` if it has the structure (see [`structure`]); `None` hands it to clarabel.
pub fn solve(p: &Problem, tol: f64, max_iter: u32) -> Option<IpmOutcome> {
    let st = Structured::new(p)?;
    let mut kkt = Kkt::new(&st)?;
    let m_e = st.e_rows.len();
    let b: Vec<f64> = st.b_e.iter().chain(&st.h).cloned().collect();
    let data = Data { norm_b: norm_inf(&b), norm_q: norm_inf(&st.q), is_qp: st.p.iter().any(|v| *v != 0.0), b, st };
    let (n, m) = (data.st.n, data.m());
    let mg = m - m_e;
    let p_diag = data.st.p.clone();
    let outcome = |status: SolverStatus, v: &Vars, iterations: u32| -> IpmOutcome {
        let scale = if v.tau > 0.0 { 1.0 / v.tau } else { 1.0 };
        let xr: Vec<f64> = v.x.iter().map(|x| x * scale).collect();
        let x = data.st.expand(&xr);
        let objective = (0..p.n).map(|j| 0.5 * p.p_diag[j] * x[j] * x[j] + p.q[j] * x[j]).sum();
        IpmOutcome { status, x, objective, iterations }
    };

    // Initial point: identity scaling, then the shifted least-squares points.
    let mut v = Vars { x: vec![0.0; n], s: vec![0.0; m], z: vec![0.0; m], tau: 1.0, kappa: 1.0 };
    if !kkt.factor(&p_diag, &vec![1.0; mg]) {
        return Some(outcome(SolverStatus::NumericalError, &v, 0));
    }
    let zeros_n = vec![0.0; n];
    let minus_q: Vec<f64> = data.st.q.iter().map(|q| -q).collect();
    let mut tmp = vec![0.0; m];
    if data.is_qp {
        kkt.solve(&p_diag, &minus_q, &data.b, &mut v.x, &mut v.z, true);
        for i in m_e..m {
            v.s[i] = -v.z[i];
        }
    } else {
        kkt.solve(&p_diag, &zeros_n, &data.b, &mut v.x, &mut tmp, true);
        for i in m_e..m {
            v.s[i] = -tmp[i];
        }
        let mut xt = vec![0.0; n];
        kkt.solve(&p_diag, &minus_q, &vec![0.0; m], &mut xt, &mut v.z, true);
    }
    shift_to_interior(&mut v.s[m_e..]);
    shift_to_interior(&mut v.z[m_e..]);

    let full = Tolerances::full(tol);
    let mut prev: Option<(Vars, Info)> = None;
    let mut iter = 0u32;
    let mut status = None;
    let (mut x1, mut z1, mut x2, mut z2) = (vec![0.0; n], vec![0.0; m], vec![0.0; n], vec![0.0; m]);
    let mut d = vec![0.0; mg];
    let mut last_info;
    loop {
        let info = data.info(&v);
        let mu = (info.dot_sz + v.tau * v.kappa) / (mg as f64 + 1.0);
        last_info = info.clone();
        if let Some(s) = convergence(&info, &full, false) {
            status = Some(s);
            break;
        }
        if let (Some((_, pi)), true) = (&prev, iter > 1)
            && (info.res_dual > pi.res_dual || info.res_primal > pi.res_primal)
        {
            // clarabel's insufficient-progress tests.
            let stalled =
                info.ktratio < f64::EPSILON * 100.0 && (pi.gap_abs < full.gap_abs || pi.gap_rel < full.gap_rel);
            let blowing = info.ktratio < 1.0
                && ((info.res_dual > full.feas * 100.0 && info.res_dual > pi.res_dual * 100.0)
                    || (info.res_primal > full.feas * 100.0 && info.res_primal > pi.res_primal * 100.0));
            if stalled || blowing {
                status = Some(SolverStatus::InsufficientProgress);
                break;
            }
        }
        if iter >= max_iter {
            status = Some(SolverStatus::MaxIterations);
            break;
        }
        // Nesterov–Todd scaling of the non-negative rows: D = s/z.
        for k in 0..mg {
            let (s, z) = (v.s[m_e + k], v.z[m_e + k]);
            if s <= 0.0 || z <= 0.0 {
                status = Some(SolverStatus::NumericalError);
            }
            d[k] = s / z;
        }
        if status.is_some() {
            break;
        }
        iter += 1;
        if !kkt.factor(&p_diag, &d) {
            status = Some(SolverStatus::NumericalError);
            break;
        }
        // Constant part of the step: K [x2; z2] = [−q; b].
        if !kkt.solve(&p_diag, &minus_q, &data.b, &mut x2, &mut z2, true) {
            status = Some(SolverStatus::NumericalError);
            break;
        }
        // One Newton step for a right-hand side (rx, rz, rs, rτ, rκ); clarabel's
        // DefaultKKTSystem::solve for the non-negative cone. `c` is the Δs constant term.
        let mut step = |rhs_x: &[f64],
                        rhs_z: &[f64],
                        c: &[f64],
                        r_tau: f64,
                        r_kappa: f64,
                        refine: bool,
                        kkt: &mut Kkt|
         -> Option<Vars> {
            let mut wz = vec![0.0; m];
            for i in 0..m {
                wz[i] = c[i] - rhs_z[i];
            }
            if !kkt.solve(&p_diag, rhs_x, &wz, &mut x1, &mut z1, refine) {
                return None;
            }
            let xi: Vec<f64> = v.x.iter().map(|x| x / v.tau).collect();
            let quad = |a: &[f64], b2: &[f64]| -> f64 { (0..n).map(|j| a[j] * p_diag[j] * b2[j]).sum() };
            let num = r_tau - r_kappa / v.tau + dot(&data.st.q, &x1) + dot(&data.b, &z1) + 2.0 * quad(&xi, &x1);
            let xi_x2: Vec<f64> = (0..n).map(|j| xi[j] - x2[j]).collect();
            let den =
                v.kappa / v.tau - dot(&data.st.q, &x2) - dot(&data.b, &z2) + quad(&xi_x2, &xi_x2) - quad(&x2, &x2);
            let dtau = num / den;
            let dx: Vec<f64> = (0..n).map(|j| x1[j] + dtau * x2[j]).collect();
            let dz: Vec<f64> = (0..m).map(|i| z1[i] + dtau * z2[i]).collect();
            let mut ds = vec![0.0; m];
            for k in 0..mg {
                let i = m_e + k;
                ds[i] = -(d[k] * dz[i] + c[i]);
            }
            let dkappa = -(r_kappa + v.kappa * dtau) / v.tau;
            if !dtau.is_finite() || !dkappa.is_finite() {
                return None;
            }
            Some(Vars { x: dx, s: ds, z: dz, tau: dtau, kappa: dkappa })
        };
        let step_len = |dv: &Vars| -> f64 {
            let mut a: f64 = 1.0;
            if dv.tau < 0.0 {
                a = a.min(-v.tau / dv.tau);
            }
            if dv.kappa < 0.0 {
                a = a.min(-v.kappa / dv.kappa);
            }
            let az = max_step(&v.z[m_e..], &dv.z[m_e..], a);
            let as_ = max_step(&v.s[m_e..], &dv.s[m_e..], a);
            az.min(as_)
        };
        // Affine (predictor) step.
        let c_aff: Vec<f64> = v.s.clone();
        let Some(aff) = step(&info.rx, &info.rz, &c_aff, info.rtau, v.tau * v.kappa, false, &mut kkt) else {
            status = Some(SolverStatus::NumericalError);
            break;
        };
        let alpha_aff = step_len(&aff);
        let sigma = (1.0 - alpha_aff).powi(3);
        let mfac = if iter > 1 { 1.0 } else { alpha_aff };
        // Combined (corrector) step: rs = s∘z + m Δs_a∘Δz_a − σμ, Δs constant term rs / z.
        let mut c_comb = vec![0.0; m];
        for k in 0..mg {
            let i = m_e + k;
            let rs = v.s[i] * v.z[i] + mfac * aff.s[i] * aff.z[i] - sigma * mu;
            c_comb[i] = rs / v.z[i];
        }
        let rx_c: Vec<f64> = info.rx.iter().map(|r| (1.0 - sigma) * r).collect();
        let rz_c: Vec<f64> = info.rz.iter().map(|r| (1.0 - sigma) * r).collect();
        let r_kappa = -sigma * mu + mfac * aff.tau * aff.kappa + v.tau * v.kappa;
        let Some(comb) = step(&rx_c, &rz_c, &c_comb, (1.0 - sigma) * info.rtau, r_kappa, true, &mut kkt) else {
            status = Some(SolverStatus::NumericalError);
            break;
        };
        let alpha = step_len(&comb) * 0.99;
        if alpha < 1e-4 {
            status = Some(SolverStatus::InsufficientProgress);
            break;
        }
        prev = Some((v.clone(), info));
        for j in 0..n {
            v.x[j] += alpha * comb.x[j];
        }
        for i in 0..m {
            v.s[i] += alpha * comb.s[i];
            v.z[i] += alpha * comb.z[i];
        }
        v.tau += alpha * comb.tau;
        v.kappa += alpha * comb.kappa;
    }
    let mut status = status.unwrap_or(SolverStatus::NumericalError);
    // Like clarabel: on insufficient progress go back to the last iterate; on trouble or the
    // iteration limit, accept the reduced tolerances.
    if status == SolverStatus::InsufficientProgress
        && let Some((pv, pi)) = prev.take()
    {
        v = pv;
        last_info = pi;
    }
    if matches!(status, SolverStatus::InsufficientProgress | SolverStatus::NumericalError | SolverStatus::MaxIterations)
        && let Some(s) = convergence(&last_info, &Tolerances::reduced(), true)
    {
        status = match s {
            SolverStatus::Solved => SolverStatus::AlmostSolved,
            other => other,
        };
    }
    Some(outcome(status, &v, iter))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::assemble::Cone;

    /// x0 + x1 (+ x2) = 1, x ≥ 0, x0 ≤ `cap0`, x1 ≤ `cap1`; x2 fixed to 0.3 by a singleton row
    /// when `fixed`.
    fn problem(q: [f64; 2], p: [f64; 2], cap0: f64, cap1: f64, fixed: bool) -> Problem {
        let n = if fixed { 3 } else { 2 };
        let mut a = vec![(0, 0, 1.0), (0, 1, 1.0)];
        let mut b = vec![1.0];
        if fixed {
            a.push((0, 2, 1.0));
            a.push((1, 2, 1.0));
            b[0] = 1.3;
            b.push(0.3);
        }
        let z = b.len();
        for (k, (col, v, rhs)) in
            [(0, -1.0, 0.0), (1, -1.0, 0.0), (0, 1.0, cap0), (1, 1.0, cap1)].into_iter().enumerate()
        {
            a.push((z + k, col, v));
            b.push(rhs);
        }
        let mut p_diag = p.to_vec();
        let mut qv = q.to_vec();
        if fixed {
            p_diag.push(0.0);
            qv.push(5.0);
        }
        Problem { n, p_diag, q: qv, a, b, cones: vec![Cone::Zero(z), Cone::Nonnegative(4)] }
    }

    #[test]
    fn lp_optimum_at_a_vertex() {
        // min x0 + 2 x1 with x0 ≤ 0.6: x = (0.6, 0.4), objective 1.4.
        let o = solve(&problem([1.0, 2.0], [0.0, 0.0], 0.6, 10.0, false), 1e-10, 100).unwrap();
        assert_eq!(o.status, SolverStatus::Solved);
        assert!((o.x[0] - 0.6).abs() < 1e-8 && (o.x[1] - 0.4).abs() < 1e-8, "{:?}", o.x);
        assert!((o.objective - 1.4).abs() < 1e-8, "{}", o.objective);
    }

    #[test]
    fn qp_optimum_in_the_interior() {
        // min ½(x0² + 3 x1²) on x0 + x1 = 1: x = (0.75, 0.25).
        let o = solve(&problem([0.0, 0.0], [1.0, 3.0], 10.0, 10.0, false), 1e-10, 100).unwrap();
        assert_eq!(o.status, SolverStatus::Solved);
        assert!((o.x[0] - 0.75).abs() < 1e-8 && (o.x[1] - 0.25).abs() < 1e-8, "{:?}", o.x);
    }

    #[test]
    fn infeasible_problem_is_reported() {
        // x0 + x1 = 1 with both ≤ 0.2.
        let o = solve(&problem([1.0, 1.0], [0.0, 0.0], 0.2, 0.2, false), 1e-10, 100).unwrap();
        assert_eq!(o.status, SolverStatus::Infeasible);
    }

    #[test]
    fn singleton_rows_fix_their_variable() {
        // x2 = 0.3 leaves x0 + x1 = 1 as before; the objective counts 5 x2 = 1.5.
        let o = solve(&problem([1.0, 2.0], [0.0, 0.0], 0.6, 10.0, true), 1e-10, 100).unwrap();
        assert_eq!(o.status, SolverStatus::Solved);
        assert_eq!(o.x[2], 0.3);
        assert!((o.x[0] - 0.6).abs() < 1e-8, "{:?}", o.x);
        assert!((o.objective - 2.9).abs() < 1e-8, "{}", o.objective);
    }

    #[test]
    fn second_order_cones_are_left_to_clarabel() {
        let mut p = problem([1.0, 2.0], [0.0, 0.0], 0.6, 10.0, false);
        p.cones.push(Cone::SecondOrder(2));
        p.a.push((5, 0, -1.0));
        p.a.push((6, 1, -1.0));
        p.b.extend([0.0, 0.0]);
        assert!(solve(&p, 1e-10, 100).is_none());
    }
}
