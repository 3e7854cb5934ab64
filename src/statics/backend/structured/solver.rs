//! clarabel's solver loop as named steps over the reduced Newton system ([`solve_c`]): initial
//! point, termination check, scaling update, predictor–corrector step, finish.

// Numerical kernels index several parallel arrays with one loop variable.
#![allow(clippy::needless_range_loop)]

use super::cones::{Layout, Scaling, shift_to_interior};
use super::iterate::Vars;
use super::kkt::{Blocks, FactorPlan, Kkt, Pattern, Rhs, Step};
use super::measures::{Info, MeasureWork, Tolerances, convergence, info};
use super::profile::{self, Dims, Kernel, Timer};
use super::shape::{Shape, split_point};
use crate::statics::problem::{Accuracy, ContactProblem, SolverStatus};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Outcome in the problem's variables (the points', then the budgets' slacks, then λ), and
/// the duals of the equality rows (clarabel's sign: A x + s = b, Aᵀz + P x + q = 0).
pub struct IpmOutcome {
    pub status: SolverStatus,
    pub x: Vec<f64>,
    pub ze: Vec<f64>,
    pub objective: f64,
    pub iterations: u32,
    /// With [`Warm::Keep`] or [`Warm::From`] and a solved problem: where a nearby problem's
    /// solve can start.
    pub kept: Option<WarmStart>,
}

/// The barrier parameter, relative to the cold start's, at which a solve keeps its iterate for
/// the next nearby problem: earlier iterates are far from the new optimum, later ones so close
/// to their own boundary that the new problem's first steps are short.
const KEEP_AT: f64 = 1e-4;

/// A kept iterate whose primal or dual residual on the new problem (clarabel's relative
/// measures) is above this is not used: the edit was not small, and the warm run would likely
/// cost a cold one's iterations on top of its own.
const START_RESIDUAL_MAX: f64 = 0.05;

/// An interior iterate of a solved problem, kept to start a nearby one from: the same rows
/// and columns (an edit that moved a cut a little), slightly different numbers. The
/// homogeneous embedding takes any interior point, so the start only has to be interior and
/// near the new central path; what it saves is the early iterations.
#[derive(Clone)]
pub struct WarmStart {
    v: Vars,
    /// Where the next solve keeps its own iterate (absolute μ: the cold start's μ₀ × [`KEEP_AT`]).
    mu_keep: f64,
    /// Iterations of the cold solve this start descends from: a warm solve that needs more
    /// is abandoned for a cold one.
    cold_iterations: u32,
    /// S's pattern and symbolic factorisation, reused when the next problem's is the same.
    pattern: Arc<Pattern>,
}

impl std::fmt::Debug for WarmStart {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "WarmStart {{ n: {}, m: {}, mu_keep: {:e} }}", self.v.x.len(), self.v.s.len(), self.mu_keep)
    }
}

/// Whether a solve starts cold or from a kept iterate, and whether it keeps one.
#[derive(Clone, Copy, Debug)]
pub enum Warm<'a> {
    /// Cold start; nothing kept.
    Off,
    /// Cold start; keep an iterate for the next nearby problem.
    Keep,
    /// Start from this iterate when it has the problem's dimensions (else cold), keep a new
    /// one. A warm solve that does not end `Solved` within the cold solve's iterations is
    /// run again cold: the status and answer are always a cold solve's, to its tolerance.
    From(&'a WarmStart),
}

/// Runs `solve` on one of rayon's two threads while the other waits beside it, taking the
/// halves the kernels hand over ([`super::points`]) at once: a thread woken per kernel would
/// take ~65 µs on this VM, a third of a split kernel's half (docs/benchmarks.md).
fn beside_a_helper<R: Send>(solve: impl FnOnce() -> R + Send) -> R {
    let done = AtomicBool::new(false);
    let help = || {
        while !done.load(Ordering::Acquire) {
            if rayon::yield_now() != Some(rayon::Yield::Executed) {
                std::hint::spin_loop();
            }
        }
    };
    let finish = || {
        let out = solve();
        done.store(true, Ordering::Release);
        (out, profile::take())
    };
    let ((out, times), ()) = rayon::join(finish, help);
    profile::merge(times);
    out
}

pub(super) fn solve_c<const C: usize>(
    cp: &ContactProblem,
    acc: Accuracy,
    max_iter: u32,
    plan: FactorPlan,
    warm: Warm,
) -> Option<IpmOutcome> {
    let splits = split_point(cp.geometry.points(), cp.threads, cp.budgets.len()).is_some();
    if splits && rayon::current_thread_index().is_none() {
        return beside_a_helper(|| solve_c::<C>(cp, acc, max_iter, plan, warm));
    }
    let _solve = Timer::start(Kernel::Solve);
    let setup = Timer::start(Kernel::Setup);
    let sh = Shape::<C>::new(cp)?;
    let reuse = match warm {
        Warm::From(ws) => Some(&ws.pattern),
        _ => None,
    };
    let kkt = Kkt::<C>::new(&sh, cp.threads, plan, reuse)?;
    let pattern = kkt.pattern();
    drop(setup);
    profile::record_dims(|| {
        let (s_values, l_values, factor_flops) = pattern.sizes();
        Dims {
            points: sh.points(),
            per_point: C,
            rows_per_point: sh.m_p,
            soc: sh.soc.is_some(),
            contacts: sh.contacts.len(),
            blocks: sh.blocks,
            m_e: sh.m_e(),
            s_values,
            l_values,
            factor_flops,
        }
    });
    let mut ip = Solver::new(&sh, kkt, acc);
    let keep = !matches!(warm, Warm::Off);
    let mut spent = 0;
    if let Warm::From(ws) = warm
        && ws.fits(&ip.v)
        && ip.start_from(&ws.v)
    {
        let run = ip.iterate(max_iter.min(ws.cold_iterations), true, Some(ws.mu_keep));
        if run.status == SolverStatus::Solved {
            ip.settle();
            let (mu_keep, cold_iterations) = (ws.mu_keep, ws.cold_iterations);
            let kept = run.kept.map(|v| WarmStart { v, mu_keep, cold_iterations, pattern });
            return Some(ip.finish(run.status, run.iterations, kept));
        }
        spent = run.iterations;
        ip.reset();
    }
    let run = if ip.initial_point() {
        ip.iterate(max_iter, keep, None)
    } else {
        Run { status: SolverStatus::NumericalError, iterations: 0, kept: None, mu_keep: 0.0 }
    };
    let cold_iterations = run.iterations;
    let kept = run.kept.filter(|_| keep && run.status == SolverStatus::Solved);
    let kept = kept.map(|v| WarmStart { v, mu_keep: run.mu_keep, cold_iterations, pattern });
    let mut out = ip.finish(run.status, run.iterations, kept);
    out.iterations += spent;
    Some(out)
}

impl WarmStart {
    /// This start with the warm run's iteration cap set to `cap` (tests reach the fall-back
    /// with it).
    #[cfg(test)]
    pub(crate) fn capped(mut self, cap: u32) -> Self {
        self.cold_iterations = cap;
        self
    }

    /// Whether both carry the same symbolic factorisation (tests).
    #[cfg(test)]
    pub(crate) fn shares_pattern(&self, other: &WarmStart) -> bool {
        Arc::ptr_eq(&self.pattern, &other.pattern)
    }

    fn fits(&self, v: &Vars) -> bool {
        (self.v.x.len(), self.v.ze.len(), self.v.s.len()) == (v.x.len(), v.ze.len(), v.s.len())
    }
}

/// How one run of the solver loop ended, and the iterate it kept.
struct Run {
    status: SolverStatus,
    iterations: u32,
    kept: Option<Vars>,
    /// The μ at which it kept it.
    mu_keep: f64,
}

/// The right-hand side of one Newton solve: the residuals (r_x, r_E, r_G), the Δs constant
/// term `c`, rτ and rκ (clarabel's `DefaultKKTSystem::solve`).
struct NewtonRhs<'a> {
    r: Rhs<'a>,
    c: &'a [f64],
    r_tau: f64,
    r_kappa: f64,
}

/// What every Newton solve of an iteration shares: its variable part (x1, z1) and its constant
/// part (x2, z2), each one solve of the reduced system (x, z_E, z_G; Δs comes from Δz
/// afterwards), x / τ, and the right-hand side buffers of the equality and inequality rows.
struct Newton {
    c1: Blocks,
    c2: Blocks,
    xi: Vec<f64>,
    rhs_eq: Vec<f64>,
    rhs_ineq: Vec<f64>,
    /// Δτ's denominator terms of the constant part: qᵀx2, bᵀz2 and the quadratic term
    /// (x/τ − x2)ᵀP(x/τ − x2) − x2ᵀP x2, the same for both solves of an iteration.
    qx2: f64,
    bz2: f64,
    quad: f64,
}

impl Newton {
    /// [`Newton::qx2`], [`Newton::bz2`] and [`Newton::quad`] from c2 and x/τ.
    fn constant_terms<const C: usize>(&mut self, sh: &Shape<C>) {
        let (c2, xi) = (&self.c2, &self.xi);
        // One sum per variable of a point: C independent chains.
        let mut sums = [0.0f64; C];
        let np = sh.points() * C;
        for (xp, cp) in xi[..np].chunks_exact(C).zip(c2.x[..np].chunks_exact(C)) {
            for k in 0..C {
                let d = xp[k] - cp[k];
                sums[k] += sh.p[k] * (d * d - cp[k] * cp[k]);
            }
        }
        let mut quad: f64 = sums.iter().sum();
        for (i, c) in sh.columns.iter().enumerate() {
            let j = sh.column0() + i;
            let d = xi[j] - c2.x[j];
            quad += c.p * (d * d - c2.x[j] * c2.x[j]);
        }
        (self.qx2, self.bz2, self.quad) = (sh.q_dot(&c2.x), sh.b_dot(&c2.eq, &c2.ineq), quad);
    }
}

/// The corrector's right-hand side (the residuals scaled by 1 − σ, the Δs constant term).
struct Corrector {
    r: Blocks,
    c: Vec<f64>,
}

/// The interior-point method's state over one problem: clarabel's solver loop as named steps
/// ([`solve_c`]: initial point, termination check, scaling update, predictor–corrector step,
/// finish).
struct Solver<'a, const C: usize> {
    sh: &'a Shape<'a, C>,
    kkt: Kkt<C>,
    sc: Scaling,
    layout: Layout,
    tol: Tolerances,
    v: Vars,
    inf: Info,
    /// The previous iterate and its measures (for the progress tests and the fall-back).
    prev: Option<(Vars, Info)>,
    /// The barrier parameter of the current iterate.
    mu: f64,
    newton: Newton,
    corrector: Corrector,
    /// The affine (predictor) direction, then the combined (corrector) one in the same
    /// buffers (one set of iterate-sized vectors fewer): the corrector's right-hand side takes
    /// what it needs of the first before the second is solved.
    dir: Vars,
    /// The measures' work and the problem's constants (−q over all variables, ‖b‖, ‖q‖).
    measure_work: MeasureWork,
}

impl<'a, const C: usize> Solver<'a, C> {
    fn new(sh: &'a Shape<'a, C>, kkt: Kkt<C>, acc: Accuracy) -> Self {
        let (n, me, mg) = (sh.n(), sh.m_e(), sh.m_g());
        let layout = Layout {
            points: sh.points(),
            per_point: sh.m_p,
            nonneg: sh.nonneg.len(),
            soc: sh.soc.is_some(),
            tail: sh.tail_rows(),
        };
        let newton = Newton {
            c1: Blocks::zeros(n, me, mg),
            c2: Blocks::zeros(n, me, mg),
            xi: vec![0.0; n],
            rhs_eq: vec![0.0; me],
            rhs_ineq: vec![0.0; mg],
            qx2: 0.0,
            bz2: 0.0,
            quad: 0.0,
        };
        let corrector = Corrector { r: Blocks::zeros(n, me, mg), c: vec![0.0; mg] };
        let mut v = Vars::zeros(n, me, mg);
        v.tau = 1.0;
        v.kappa = 1.0;
        Self {
            sh,
            kkt,
            sc: Scaling::identity(layout),
            layout,
            tol: Tolerances::full(acc),
            v,
            inf: Info { rx: vec![0.0; n], re: vec![0.0; me], rg: vec![0.0; mg], ..Default::default() },
            prev: None,
            mu: 0.0,
            newton,
            corrector,
            dir: Vars::zeros(n, me, mg),
            measure_work: MeasureWork::new(sh),
        }
    }

    /// The outcome for `status` at the current iterate, x scaled back by τ.
    fn outcome(&self, status: SolverStatus, iterations: u32, kept: Option<WarmStart>) -> IpmOutcome {
        let v = &self.v;
        let scale = if v.tau > 0.0 { 1.0 / v.tau } else { 1.0 };
        let x: Vec<f64> = v.x.iter().map(|x| x * scale).collect();
        let ze: Vec<f64> = v.ze.iter().map(|z| z * scale).collect();
        let objective = 0.5 * self.sh.p_quad(&x, &x) + self.sh.q_dot(&x);
        IpmOutcome { status, x, ze, objective, iterations, kept }
    }

    /// The solver loop from the current iterate: termination check, scaling update and step
    /// until a status. With `keep`, keeps a copy of the first iterate after the start whose μ
    /// is at most `mu_keep` (from a cold start: μ₀ × [`KEEP_AT`]); without, copies nothing (an
    /// iterate is a few hundred MB on a 100 000-brick wall).
    fn iterate(&mut self, max_iter: u32, keep: bool, mu_keep: Option<f64>) -> Run {
        let mut iter = 0u32;
        let mut mu_keep = mu_keep.unwrap_or(f64::NAN);
        let mut kept = None;
        let status = loop {
            let status = self.check_termination(iter, max_iter);
            if iter == 0 && mu_keep.is_nan() {
                mu_keep = self.mu * KEEP_AT;
            }
            if keep && kept.is_none() && iter > 0 && self.mu <= mu_keep {
                kept = Some(self.v.clone());
            }
            if let Some(status) = status {
                break status;
            }
            let scaling = Timer::start(Kernel::Scaling);
            let updated = self.sc.update(&self.v.s, &self.v.z);
            drop(scaling);
            if !updated {
                break SolverStatus::NumericalError;
            }
            iter += 1;
            if let Err(status) = self.step(iter) {
                break status;
            }
        };
        Run { status, iterations: iter, kept, mu_keep }
    }

    /// Takes `v` as the current iterate when its residuals on this problem are below
    /// [`START_RESIDUAL_MAX`]; else leaves the solver as it was (false).
    fn start_from(&mut self, v: &Vars) -> bool {
        self.v.clone_from(v);
        info(self.sh, &self.v, &mut self.inf, &mut self.measure_work);
        if self.inf.res_primal.max(self.inf.res_dual) <= START_RESIDUAL_MAX {
            return true;
        }
        self.reset();
        false
    }

    /// Removes the equality residual a warm run ends with (its start was interior for the
    /// previous problem, not feasible for this one, and each step removes only the fraction α
    /// of it), which would leave the caller's polish far more to do than a cold run's: one
    /// Newton solve with the last factored system, x ← x − H⁻¹Eᵀ S⁻¹ (E x − τ b), the
    /// H-weighted least correction (active rows, with a small H⁻¹, barely move); kept only
    /// where it lowers the residual.
    fn settle(&mut self) {
        let sh = self.sh;
        let (n, me, mg) = (sh.n(), sh.m_e(), sh.m_g());
        let (mut ex, mut gx) = (vec![0.0; me], vec![0.0; mg]);
        let residual = |x: &[f64], ex: &mut Vec<f64>, gx: &mut Vec<f64>, tau: f64| -> f64 {
            sh.a_mul(x, ex, gx);
            ex.iter_mut().zip(&sh.b_e).fold(0.0f64, |m, (e, b)| {
                *e -= tau * b;
                m.max(e.abs())
            })
        };
        let tau = self.v.tau;
        let before = residual(&self.v.x, &mut ex, &mut gx, tau);
        let (zeros_n, zeros_g) = (vec![0.0; n], vec![0.0; mg]);
        let mut d = Blocks::zeros(n, me, mg);
        if !self.kkt.solve(sh, &self.sc, Rhs { x: &zeros_n, eq: &ex, ineq: &zeros_g }, d.step(), true) {
            return;
        }
        let candidate: Vec<f64> = self.v.x.iter().zip(&d.x).map(|(x, d)| x - d).collect();
        if residual(&candidate, &mut ex, &mut gx, tau) < before {
            self.v.x = candidate;
        }
    }

    /// Back to the state before the initial point (after an abandoned warm start).
    fn reset(&mut self) {
        let (n, me, mg) = (self.sh.n(), self.sh.m_e(), self.sh.m_g());
        self.v = Vars::zeros(n, me, mg);
        self.v.tau = 1.0;
        self.v.kappa = 1.0;
        self.sc = Scaling::identity(self.layout);
        self.prev = None;
    }

    /// Initial point: identity scaling, then the shifted least-squares points (clarabel's).
    fn initial_point(&mut self) -> bool {
        let sh = self.sh;
        let (n, me, mg) = (sh.n(), sh.m_e(), sh.m_g());
        if !self.kkt.factor(sh, &self.sc) {
            return false;
        }
        let (zeros_n, zeros_e, zeros_g) = (vec![0.0; n], vec![0.0; me], vec![0.0; mg]);
        let mut b_g = vec![0.0; mg];
        sh.b_g_into(&mut b_g);
        let (v, sc, minus_q) = (&mut self.v, &self.sc, &self.measure_work.minus_q);
        if sh.quadratic() {
            let rhs = Rhs { x: minus_q, eq: &sh.b_e, ineq: &b_g };
            self.kkt.solve(sh, sc, rhs, Step { x: &mut v.x, eq: &mut v.ze, ineq: &mut v.z }, true);
            for i in 0..mg {
                v.s[i] = -v.z[i];
            }
        } else {
            let mut tmp_e = vec![0.0; me];
            let rhs = Rhs { x: &zeros_n, eq: &sh.b_e, ineq: &b_g };
            self.kkt.solve(sh, sc, rhs, Step { x: &mut v.x, eq: &mut tmp_e, ineq: &mut v.s }, true);
            v.s.iter_mut().for_each(|s| *s = -*s);
            let mut xt = vec![0.0; n];
            let rhs = Rhs { x: minus_q, eq: &zeros_e, ineq: &zeros_g };
            self.kkt.solve(sh, sc, rhs, Step { x: &mut xt, eq: &mut v.ze, ineq: &mut v.z }, true);
        }
        shift_to_interior(&self.layout, &mut v.s);
        shift_to_interior(&self.layout, &mut v.z);
        true
    }

    /// Measures the current iterate; a status when the solve ends here: converged or
    /// infeasible, insufficient progress (clarabel's tests), or the iteration limit.
    fn check_termination(&mut self, iter: u32, max_iter: u32) -> Option<SolverStatus> {
        let measures = Timer::start(Kernel::Measures);
        info(self.sh, &self.v, &mut self.inf, &mut self.measure_work);
        drop(measures);
        let inf = &self.inf;
        self.mu = (inf.dot_sz + self.v.tau * self.v.kappa) / (self.layout.degree() as f64 + 1.0);
        if let Some(s) = convergence(inf, &self.tol, false) {
            return Some(s);
        }
        if let (Some((_, pi)), true) = (&self.prev, iter > 1)
            && (inf.res_dual > pi.res_dual || inf.res_primal > pi.res_primal)
        {
            let full = &self.tol;
            let stalled = inf.ktratio < f64::EPSILON * 100.0 && pi.gap_small(full);
            let blowing = inf.ktratio < 1.0
                && ((inf.res_dual > full.feas * 100.0 && inf.res_dual > pi.res_dual * 100.0)
                    || (inf.res_primal > full.feas * 100.0 && inf.res_primal > pi.res_primal * 100.0));
            if stalled || blowing {
                return Some(SolverStatus::InsufficientProgress);
            }
        }
        (iter >= max_iter).then_some(SolverStatus::MaxIterations)
    }

    /// One predictor–corrector step (the scaling already updated): factor, the constant part
    /// of the Newton solves, the affine direction, the combined direction, the step.
    fn step(&mut self, iter: u32) -> Result<(), SolverStatus> {
        let sh = self.sh;
        if !self.kkt.factor(sh, &self.sc) {
            return Err(SolverStatus::NumericalError);
        }
        // Constant part of the step: K [x2; z2] = [−q; b_E; b_G] (r_G's buffer is free until
        // the Newton solves below fill it).
        let Newton { c2, rhs_ineq: b_g, .. } = &mut self.newton;
        sh.b_g_into(b_g);
        let rhs = Rhs { x: &self.measure_work.minus_q, eq: &sh.b_e, ineq: b_g };
        if !self.kkt.solve(sh, &self.sc, rhs, c2.step(), true) {
            return Err(SolverStatus::NumericalError);
        }
        let tau = self.v.tau;
        self.newton.xi.iter_mut().zip(&self.v.x).for_each(|(xi, x)| *xi = x / tau);
        self.newton.constant_terms(sh);
        // Affine (predictor) step: Δs constant term s.
        let (inf, v) = (&self.inf, &self.v);
        let r = Rhs { x: &inf.rx, eq: &inf.re, ineq: &inf.rg };
        let rhs = NewtonRhs { r, c: &v.s, r_tau: inf.rtau, r_kappa: v.tau * v.kappa };
        if !newton(sh, &mut self.kkt, &self.sc, v, &mut self.newton, &rhs, false, &mut self.dir) {
            return Err(SolverStatus::NumericalError);
        }
        let alpha_aff = self.step_length(&self.dir);
        let sigma = (1.0 - alpha_aff).powi(3);
        let mfac = if iter > 1 { 1.0 } else { alpha_aff };
        // Combined (corrector) step.
        let (v, inf, aff, cr) = (&self.v, &self.inf, &self.dir, &mut self.corrector);
        self.sc.combined_const(&v.s, &v.z, &aff.s, &aff.z, mfac, sigma * self.mu, &mut cr.c);
        let scaled = |out: &mut [f64], r: &[f64]| out.iter_mut().zip(r).for_each(|(o, r)| *o = (1.0 - sigma) * r);
        scaled(&mut cr.r.x, &inf.rx);
        scaled(&mut cr.r.eq, &inf.re);
        scaled(&mut cr.r.ineq, &inf.rg);
        let r_kappa = -sigma * self.mu + mfac * aff.tau * aff.kappa + v.tau * v.kappa;
        let rhs = NewtonRhs { r: cr.r.rhs(), c: &cr.c, r_tau: (1.0 - sigma) * inf.rtau, r_kappa };
        if !newton(sh, &mut self.kkt, &self.sc, v, &mut self.newton, &rhs, true, &mut self.dir) {
            return Err(SolverStatus::NumericalError);
        }
        let alpha = self.step_length(&self.dir) * 0.99;
        if alpha < 1e-4 {
            return Err(SolverStatus::InsufficientProgress);
        }
        self.take_step(alpha);
        Ok(())
    }

    /// The longest step in [0, 1] along `dv` that keeps τ, κ, s and z in their cones.
    fn step_length(&self, dv: &Vars) -> f64 {
        let _t = Timer::start(Kernel::StepLength);
        let v = &self.v;
        let mut a: f64 = 1.0;
        if dv.tau < 0.0 {
            a = a.min(-v.tau / dv.tau);
        }
        if dv.kappa < 0.0 {
            a = a.min(-v.kappa / dv.kappa);
        }
        let az = self.sc.step_length(&v.z, &dv.z, a);
        let as_ = self.sc.step_length(&v.s, &dv.s, a);
        az.min(as_)
    }

    /// v ← v + α Δ (the combined direction), keeping the previous iterate. The new iterate is
    /// written into the previous one's buffers and the two swapped, and so are the measures
    /// (the next termination check overwrites every field), so that an iteration allocates
    /// nothing.
    fn take_step(&mut self, alpha: f64) {
        let (prev_v, prev_inf) = self.prev.get_or_insert_with(|| (self.v.clone(), self.inf.clone()));
        let (v, d) = (&self.v, &self.dir);
        let axpy = |out: &mut [f64], x: &[f64], dx: &[f64]| {
            for ((o, x), dx) in out.iter_mut().zip(x).zip(dx) {
                *o = x + alpha * dx;
            }
        };
        axpy(&mut prev_v.x, &v.x, &d.x);
        axpy(&mut prev_v.ze, &v.ze, &d.ze);
        axpy(&mut prev_v.s, &v.s, &d.s);
        axpy(&mut prev_v.z, &v.z, &d.z);
        prev_v.tau = v.tau + alpha * d.tau;
        prev_v.kappa = v.kappa + alpha * d.kappa;
        std::mem::swap(&mut self.v, prev_v);
        std::mem::swap(&mut self.inf, prev_inf);
    }

    /// Like clarabel: on insufficient progress go back to the last iterate; on trouble or the
    /// iteration limit, accept the reduced tolerances.
    fn finish(mut self, status: SolverStatus, iterations: u32, kept: Option<WarmStart>) -> IpmOutcome {
        let mut status = status;
        let mut last = std::mem::take(&mut self.inf);
        if status == SolverStatus::InsufficientProgress
            && let Some((pv, pi)) = self.prev.take()
        {
            self.v = pv;
            last = pi;
        }
        if matches!(
            status,
            SolverStatus::InsufficientProgress | SolverStatus::NumericalError | SolverStatus::MaxIterations
        ) && let Some(s) = convergence(&last, &Tolerances::reduced(), true)
        {
            status = match s {
                SolverStatus::Solved => SolverStatus::AlmostSolved,
                other => other,
            };
        }
        self.outcome(status, iterations, kept)
    }
}

/// One Newton solve for `rhs` into `out` (clarabel's `DefaultKKTSystem::solve`): the variable
/// part from the factored system, then Δτ from the constant part, Δs and Δκ.
#[allow(clippy::too_many_arguments)]
fn newton<const C: usize>(
    sh: &Shape<C>,
    kkt: &mut Kkt<C>,
    sc: &Scaling,
    v: &Vars,
    w: &mut Newton,
    rhs: &NewtonRhs,
    refine: bool,
    out: &mut Vars,
) -> bool {
    // The z right-hand side is c − r_z (c = 0 on the equality rows).
    w.rhs_eq.iter_mut().zip(rhs.r.eq).for_each(|(o, r)| *o = -r);
    w.rhs_ineq.iter_mut().zip(rhs.c.iter().zip(rhs.r.ineq)).for_each(|(o, (c, r))| *o = c - r);
    let r = Rhs { x: rhs.r.x, eq: &w.rhs_eq, ineq: &w.rhs_ineq };
    if !kkt.solve(sh, sc, r, w.c1.step(), refine) {
        return false;
    }
    let (c1, c2, xi) = (&w.c1, &w.c2, &w.xi);
    let num =
        rhs.r_tau - rhs.r_kappa / v.tau + sh.q_dot(&c1.x) + sh.b_dot(&c1.eq, &c1.ineq) + 2.0 * sh.p_quad(xi, &c1.x);
    let den = v.kappa / v.tau - w.qx2 - w.bz2 + w.quad;
    let dtau = num / den;
    let combine = |out: &mut [f64], a: &[f64], b: &[f64]| {
        out.iter_mut().zip(a.iter().zip(b)).for_each(|(o, (a, b))| *o = a + dtau * b);
    };
    combine(&mut out.x, &c1.x, &c2.x);
    combine(&mut out.ze, &c1.eq, &c2.eq);
    combine(&mut out.z, &c1.ineq, &c2.ineq);
    sc.ds_from_dz(&out.z, rhs.c, &mut out.s);
    out.tau = dtau;
    out.kappa = -(rhs.r_kappa + v.kappa * dtau) / v.tau;
    dtau.is_finite() && out.kappa.is_finite()
}
