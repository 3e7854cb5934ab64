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

mod block_cholesky;
mod block_lu;
mod cones;
mod iterate;
mod kkt;
mod measures;
mod points;
pub mod profile;
mod shape;
mod solver;

use crate::statics::problem::{Accuracy, ContactProblem};
pub(crate) use block_lu::BlockLu;
pub(crate) use kkt::FactorPlan;
use solver::solve_c;
pub use solver::{IpmOutcome, Warm, WarmStart};

/// Solves `cp`; `None` when it has a shape this solver does not take (it then goes to
/// clarabel).
pub fn solve(cp: &ContactProblem, acc: Accuracy, max_iter: u32, warm: Warm) -> Option<IpmOutcome> {
    solve_from(cp, acc, max_iter, FactorPlan::default(), warm)
}

/// [`solve`] with S factored as `plan` says (tests force faer, and its parallel path on small
/// problems).
pub(crate) fn solve_from(
    cp: &ContactProblem,
    acc: Accuracy,
    max_iter: u32,
    plan: FactorPlan,
    warm: Warm,
) -> Option<IpmOutcome> {
    match cp.per_point() {
        1 => solve_c::<1>(cp, acc, max_iter, plan, warm),
        2 => solve_c::<2>(cp, acc, max_iter, plan, warm),
        3 => solve_c::<3>(cp, acc, max_iter, plan, warm),
        4 => solve_c::<4>(cp, acc, max_iter, plan, warm),
        5 => solve_c::<5>(cp, acc, max_iter, plan, warm),
        _ => None,
    }
}
