//! The only clarabel touchpoint: a plain-data [`ContactProblem`] in, a plain-data
//! [`QpOutcome`] out (x in the problem's own variables).

use super::assemble::Cone;
use super::problem::ContactProblem;
use super::result::SolverStatus;
use super::settings::{Backend, StaticsSettings};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus as ClStatus, SupportedConeT};
use std::time::Instant;

/// What a solve must reach: clarabel's feasibility and duality-gap tolerances. The relative
/// gap is taken against max(1, |objective|) (clarabel's definition), or with `pure_relative`
/// against |objective| itself — then near a zero optimum only `gap_abs` decides, and a large
/// optimum needs only `gap_rel` of itself (the structured solver; clarabel keeps its own).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accuracy {
    pub feas: f64,
    pub gap_abs: f64,
    pub gap_rel: f64,
    pub pure_relative: bool,
}

impl Accuracy {
    /// clarabel's definition with one tolerance for all three.
    pub fn uniform(tol: f64) -> Self {
        Self { feas: tol, gap_abs: tol, gap_rel: tol, pure_relative: false }
    }
}

/// Result of one conic solve.
#[derive(Clone, Debug)]
pub struct QpOutcome {
    pub status: SolverStatus,
    pub x: Vec<f64>,
    pub objective: f64,
    pub iterations: u32,
    /// Which solver ran it.
    pub backend: Backend,
    /// Seconds converting to clarabel's matrices, and in clarabel (set-up and solve).
    pub convert_seconds: f64,
    pub solver_seconds: f64,
}

fn csc_from_triplets(m: usize, n: usize, triplets: &[(usize, usize, f64)]) -> CscMatrix<f64> {
    // Counting sort by column (O(nnz)), then each short column sorted by row, duplicates summed.
    let mut colptr = vec![0usize; n + 1];
    for &(_, j, _) in triplets {
        colptr[j + 1] += 1;
    }
    for j in 0..n {
        colptr[j + 1] += colptr[j];
    }
    let mut next = colptr.clone();
    let mut entries = vec![(0usize, 0.0f64); triplets.len()];
    for &(i, j, v) in triplets {
        entries[next[j]] = (i, v);
        next[j] += 1;
    }
    let mut rowval = Vec::with_capacity(triplets.len());
    let mut nzval = Vec::with_capacity(triplets.len());
    let mut out_colptr = vec![0usize; n + 1];
    for j in 0..n {
        let col = &mut entries[colptr[j]..colptr[j + 1]];
        col.sort_unstable_by_key(|e| e.0);
        let start = rowval.len();
        for &(i, v) in col.iter() {
            if rowval.len() > start && rowval.last() == Some(&i) {
                *nzval.last_mut().expect("the column has an entry") += v;
            } else {
                rowval.push(i);
                nzval.push(v);
            }
        }
        out_colptr[j + 1] = rowval.len();
    }
    CscMatrix::new(m, n, out_colptr, rowval, nzval)
}

/// Solves one problem: the structured interior-point method when the settings ask for it and
/// the problem has its shape, else clarabel (verbose off, presolve on).
pub fn run(cp: &ContactProblem, settings: &StaticsSettings, acc: Accuracy) -> QpOutcome {
    if settings.backend == Backend::Structured {
        let t = Instant::now();
        if let Some(o) = super::ipm::solve(cp, acc, settings.max_iterations) {
            return QpOutcome {
                status: o.status,
                x: o.x,
                objective: o.objective,
                iterations: o.iterations,
                backend: Backend::Structured,
                convert_seconds: 0.0,
                solver_seconds: t.elapsed().as_secs_f64(),
            };
        }
    }
    let t0 = Instant::now();
    let p = &cp.to_conic();
    let diag: Vec<(usize, usize, f64)> =
        p.p_diag.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(i, &v)| (i, i, v)).collect();
    let pm = csc_from_triplets(p.n, p.n, &diag);
    let am = csc_from_triplets(p.m(), p.n, &p.a);
    let cones: Vec<SupportedConeT<f64>> = p
        .cones
        .iter()
        .filter_map(|c| match *c {
            Cone::Zero(0) | Cone::Nonnegative(0) => None,
            Cone::Zero(k) => Some(SupportedConeT::ZeroConeT(k)),
            Cone::Nonnegative(k) => Some(SupportedConeT::NonnegativeConeT(k)),
            Cone::SecondOrder(k) => Some(SupportedConeT::SecondOrderConeT(k)),
        })
        .collect();
    let convert_seconds = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let cl = DefaultSettings {
        verbose: false,
        max_iter: settings.max_iterations,
        tol_feas: acc.feas,
        tol_gap_abs: acc.gap_abs,
        tol_gap_rel: acc.gap_rel,
        ..DefaultSettings::default()
    };
    let mut solver = match DefaultSolver::new(&pm, &p.q, &am, &p.b, &cones, cl) {
        Ok(s) => s,
        Err(_) => {
            return QpOutcome {
                status: SolverStatus::NumericalError,
                x: vec![0.0; p.n],
                objective: f64::NAN,
                iterations: 0,
                backend: Backend::Clarabel,
                convert_seconds,
                solver_seconds: t1.elapsed().as_secs_f64(),
            };
        }
    };
    solver.solve();
    let s = &solver.solution;
    let status = match s.status {
        ClStatus::Solved => SolverStatus::Solved,
        ClStatus::AlmostSolved => SolverStatus::AlmostSolved,
        ClStatus::PrimalInfeasible | ClStatus::AlmostPrimalInfeasible => SolverStatus::Infeasible,
        ClStatus::DualInfeasible | ClStatus::AlmostDualInfeasible => SolverStatus::Unbounded,
        ClStatus::MaxIterations | ClStatus::MaxTime => SolverStatus::MaxIterations,
        ClStatus::InsufficientProgress => SolverStatus::InsufficientProgress,
        _ => SolverStatus::NumericalError,
    };
    QpOutcome {
        status,
        x: s.x.clone(),
        objective: s.obj_val,
        iterations: s.iterations,
        backend: Backend::Clarabel,
        convert_seconds,
        solver_seconds: t1.elapsed().as_secs_f64(),
    }
}
