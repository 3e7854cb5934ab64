//! The interior-point solvers of the equilibrium problems, behind one call ([`run`]). Each
//! takes a plain-data [`ContactProblem`] (the leaf vocabulary of [`crate::statics::problem`],
//! the only statics module the backends import) and returns a [`QpOutcome`] in the problem's
//! own variables:
//! - [`structured`]: clarabel's algorithm with the Newton system reduced to the 6-per-block
//!   equilibrium rows (the default, for every problem of its shape);
//! - [`clarabel`]: clarabel itself on the same data (general sparse LDL of the whole KKT matrix),
//!   to cross-check, and for any problem the structured solver does not take.

mod clarabel;
mod outcome;
pub(crate) mod structured;

pub use clarabel::{ConicOutcome, solve_conic};
pub use outcome::{Backend, QpOutcome};
pub(crate) use structured::BlockLu;
pub use structured::profile as kernel_profile;
pub use structured::{Warm, WarmStart};

use crate::statics::problem::{Accuracy, ContactProblem};
use std::time::Instant;

/// Solves one problem on `backend` to `acc`, at most `max_iter` interior-point iterations: the
/// structured solver when asked for and the problem has its shape, else clarabel.
pub fn run(cp: &ContactProblem, backend: Backend, acc: Accuracy, max_iter: u32) -> QpOutcome {
    run_warm(cp, backend, acc, max_iter, Warm::Off).0
}

/// [`run`] with a warm start ([`Warm`]; the structured solver only: clarabel starts cold and
/// keeps nothing), and the iterate it kept for the next nearby problem.
pub fn run_warm(
    cp: &ContactProblem,
    backend: Backend,
    acc: Accuracy,
    max_iter: u32,
    warm: Warm,
) -> (QpOutcome, Option<WarmStart>) {
    if backend == Backend::Structured {
        let t = Instant::now();
        if let Some(o) = structured::solve(cp, acc, max_iter, warm) {
            let out = QpOutcome {
                status: o.status,
                x: o.x,
                duals: o.ze,
                objective: o.objective,
                iterations: o.iterations,
                backend: Backend::Structured,
                convert_seconds: 0.0,
                solver_seconds: t.elapsed().as_secs_f64(),
            };
            return (out, o.kept);
        }
    }
    (clarabel::solve(cp, acc, max_iter), None)
}

/// `cp`'s block columns in `out.x`: after the points' variables, the budgets' slacks (the
/// structured solver's own columns; clarabel takes a budget as an inequality row) and λ.
pub fn block_columns<'o>(cp: &ContactProblem, out: &'o QpOutcome) -> &'o [f64] {
    let slacks = if out.backend == Backend::Structured { cp.budgets.len() } else { 0 };
    let at = cp.geometry.points() * cp.per_point() + slacks + usize::from(cp.factor.is_some());
    out.x.get(at..at + cp.columns.len()).unwrap_or(&[])
}
