//! The only clarabel touchpoint: a plain-data [`ContactProblem`] in (as its general conic
//! form, [`ContactProblem::to_conic`]), a plain-data [`QpOutcome`] out (x in the problem's own
//! variables, and the equality rows' duals: with a load factor, the collapse mechanism); or a
//! general [`ConicProblem`] in and a [`ConicOutcome`] out ([`solve_conic`]).

use super::outcome::{Backend, QpOutcome};
use crate::statics::problem::{Accuracy, Cone, ConicProblem, ContactProblem, SolverStatus};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus as ClStatus, SupportedConeT};
use std::time::Instant;

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

/// Solves `cp` on clarabel (verbose off, presolve on) to `acc`, at most `max_iter` iterations.
pub fn solve(cp: &ContactProblem, acc: Accuracy, max_iter: u32) -> QpOutcome {
    let t0 = Instant::now();
    let p = cp.to_conic();
    let convert = t0.elapsed().as_secs_f64();
    let o = solve_conic(&p, acc, max_iter);
    let rows = cp.geometry.rhs.len().min(o.z.len());
    QpOutcome {
        status: o.status,
        x: o.x,
        duals: o.z[..rows].to_vec(),
        objective: o.objective,
        iterations: o.iterations,
        backend: Backend::Clarabel,
        convert_seconds: convert + o.convert_seconds,
        solver_seconds: o.solver_seconds,
    }
}

/// What clarabel returned for a [`ConicProblem`]: the primal `x`, and the duals `z` of every
/// row (A x + s = b, s in the cones; z in the dual cones, P x + Aᵀ z + q = 0).
#[derive(Clone, Debug)]
pub struct ConicOutcome {
    /// How the solve ended.
    pub status: SolverStatus,
    /// The primal solution, one entry per column of the problem.
    pub x: Vec<f64>,
    /// The duals, one per row (in the dual cones).
    pub z: Vec<f64>,
    /// The objective's value at `x`.
    pub objective: f64,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Seconds converting the problem to clarabel's matrices.
    pub convert_seconds: f64,
    /// Seconds inside clarabel's solve.
    pub solver_seconds: f64,
}

/// Solves a general conic problem on clarabel (verbose off, presolve on) to `acc`, at most
/// `max_iter` iterations: for problems that are not of the contact form (the kinematic rate
/// problem's free acceleration columns).
pub fn solve_conic(p: &ConicProblem, acc: Accuracy, max_iter: u32) -> ConicOutcome {
    let t0 = Instant::now();
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
        max_iter,
        tol_feas: acc.feas,
        tol_gap_abs: acc.gap_abs,
        tol_gap_rel: acc.gap_rel,
        ..DefaultSettings::default()
    };
    let mut solver = match DefaultSolver::new(&pm, &p.q, &am, &p.b, &cones, cl) {
        Ok(s) => s,
        Err(_) => {
            return ConicOutcome {
                status: SolverStatus::NumericalError,
                x: vec![0.0; p.n],
                z: vec![0.0; p.m()],
                objective: f64::NAN,
                iterations: 0,
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
    ConicOutcome {
        status,
        x: s.x.clone(),
        z: s.z.clone(),
        objective: s.obj_val,
        iterations: s.iterations,
        convert_seconds,
        solver_seconds: t1.elapsed().as_secs_f64(),
    }
}
