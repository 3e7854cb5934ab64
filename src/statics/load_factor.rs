//! The load factor of one component and its collapse mechanism.
//!
//! λ* = max λ such that forces with no tension and friction within the chosen model
//! equilibrate the dead load D (self-weight and dead loads) plus λ times the live load L: the
//! strict system's rows `A x = −D` become `A x + λ L = −D`, one more column, objective −λ. An
//! LP for the pyramid and box models, an SOCP for the cone. A design that stands has λ* ≥ 0:
//! then λ ≥ 0 is a [`LoadColumn`] the statics' backend solves (the structured solver keeps it
//! beside its sparse factor as a bordered system; [`standing_load_factor`]); otherwise λ is
//! free and clarabel solves it ([`component_load_factor`]). The dual solution is the
//! mechanism: the duals z of the equilibrium rows are the blocks' virtual
//! velocities (translation on the force rows, rotation on the moment rows), with
//! - Lᵀz = 1 (the λ column's dual row): the live load does unit work;
//! - Dᵀz = −λ* (strong duality): λ*·(live work) + (dead work) = 0, the virtual-work balance;
//! - every force column's dual row: at each interface vertex the normal relative velocity of
//!   b against a is ≥ 0 (no interpenetration), > μ × the sliding speed where friction acts
//!   (associated flow).
//!
//! A component that does not stand under its dead load gets its mechanism from the dual of
//! the LP that measured the failure: the minimum-tension LP when it needs tension, else the
//! minimum-friction-excess LP, normalised so that the dead load does unit work.
//!
//! Units: the problems are non-dimensional as every stage's (forces by the component's free
//! weight W, lengths by the model size ℓ); motions come back in m and rad, so that the
//! normalised load's work is 1 N·m.

use super::assemble::{Stage, System, contact_problem, live_load};
use super::backend::run;
use super::backend::{ConicOutcome, solve_conic};
use super::components::Component;
use super::problem::{Accuracy, ConicProblem, LoadColumn, SolverStatus};
use super::settings::StaticsSettings;
use super::stages::LP_TOLERANCE;
use crate::interfaces::Interface;
use crate::model::Assembly;

/// A block's virtual motion: translation (m) then rotation about its centroid (rad), world
/// axes.
pub type Motion = [f64; 6];

/// How a component's load-factor problem ended.
#[derive(Clone, Debug)]
pub struct FactorOutcome {
    pub status: SolverStatus,
    /// λ*; +∞ when the live load can grow without bound (the LP is unbounded), NaN when the
    /// problem has no solution (no λ at all admits equilibrium, or solver trouble).
    pub lambda: f64,
    /// Per block of the component, in its order; the live load does unit work (N·m). Empty
    /// when there is no mechanism (unbounded, or not solved).
    pub motions: Vec<Motion>,
    /// ‖A x + λ L + D‖_∞ of the solution, N.
    pub residual: f64,
    pub iterations: u32,
    pub solver_seconds: f64,
}

/// The load-factor problem of `comp` as plain data: the strict system's conic rows with the
/// λ column appended last, objective −λ.
fn factor_problem(sys: &System, live: &[f64], settings: &StaticsSettings) -> ConicProblem {
    let mut cp = contact_problem(sys, Stage::Strict, settings);
    cp.p.iter_mut().for_each(|v| *v = 0.0);
    cp.q.iter_mut().for_each(|v| *v = 0.0);
    let mut conic = cp.to_conic();
    let lambda = conic.n;
    conic.n += 1;
    conic.p_diag.push(0.0);
    conic.q.push(-1.0);
    conic.a.extend(live.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(r, &v)| (r, lambda, v)));
    conic
}

/// The physical motions of a component's blocks from the duals `z` of its equilibrium rows
/// (the first 6 per block), divided by `norm` (the normalised load's non-dimensional work).
fn motions(z: &[f64], blocks: usize, force_scale: f64, length_scale: f64, norm: f64) -> Vec<Motion> {
    (0..blocks)
        .map(|i| {
            let mut m = [0.0; 6];
            for k in 0..3 {
                m[k] = z[6 * i + k] / (force_scale * norm);
                m[3 + k] = z[6 * i + 3 + k] / (force_scale * length_scale * norm);
            }
            m
        })
        .collect()
}

/// ‖A x + λ L − rhs‖_∞ over the equilibrium rows, non-dimensional.
fn residual(conic: &ConicProblem, rows: usize, x: &[f64]) -> f64 {
    let mut r: Vec<f64> = conic.b[..rows].iter().map(|b| -b).collect();
    for &(i, j, v) in conic.a.iter().filter(|e| e.0 < rows) {
        r[i] += v * x[j];
    }
    r.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The load factor to the statics' solver tolerance (relative: λ* to ~1e-8 of itself); the
/// failure LPs to the stages' LP tolerance, as the graded answer they explain.
fn accuracy(settings: &StaticsSettings, lp: bool) -> Accuracy {
    let tol = if lp { settings.solver_tolerance.min(LP_TOLERANCE) } else { settings.solver_tolerance };
    Accuracy { feas: tol, gap_abs: tol, gap_rel: tol, pure_relative: false }
}

/// λ* ≥ 0 of a component that stands under its dead load (λ = 0 is feasible), on the
/// statics' backend: the strict problem with the λ ≥ 0 column ([`LoadColumn`]), which the
/// structured solver takes (a rank-one term beside its sparse factor); the mechanism from the
/// block rows' duals.
pub fn standing_load_factor(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
) -> FactorOutcome {
    let t = std::time::Instant::now();
    let sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, false);
    let live = live_load(assembly, comp, sys.force_scale);
    let mut cp = contact_problem(&sys, Stage::Strict, settings);
    cp.p.iter_mut().for_each(|v| *v = 0.0);
    cp.q.iter_mut().for_each(|v| *v = 0.0);
    cp.factor = Some(LoadColumn { column: live.clone(), cost: -1.0 });
    let out = run(&cp, settings.backend, accuracy(settings, false), settings.max_iterations);
    let blocks = comp.blocks.len();
    let points = sys.points.len() * cp.per_point();
    let (lambda, motions) = match out.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            (out.x[out.x.len() - 1], motions(&out.duals, blocks, sys.force_scale, assembly.scale, 1.0))
        }
        SolverStatus::Unbounded => (f64::INFINITY, Vec::new()),
        _ => (f64::NAN, Vec::new()),
    };
    let residual = if lambda.is_finite() {
        let x = sys.stage_values(&cp, &out.x[..points]);
        let r = sys.residual_vector(&x);
        r.iter().zip(&live).fold(0.0f64, |m, (r, l)| m.max((r + lambda * l).abs())) * sys.force_scale
    } else {
        f64::NAN
    };
    FactorOutcome {
        status: out.status,
        lambda,
        motions,
        residual,
        iterations: out.iterations,
        solver_seconds: t.elapsed().as_secs_f64(),
    }
}

/// λ* of `comp` for its blocks' live loads (at least one non-zero), and the mechanism; λ free
/// (for a design that does not stand, λ* may be negative), on clarabel.
pub fn component_load_factor(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
) -> FactorOutcome {
    let sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, false);
    let live = live_load(assembly, comp, sys.force_scale);
    let conic = factor_problem(&sys, &live, settings);
    let out: ConicOutcome = solve_conic(&conic, accuracy(settings, false), settings.max_iterations);
    let rows = 6 * comp.blocks.len();
    let (lambda, motions) = match out.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            (out.x[conic.n - 1], motions(&out.z, comp.blocks.len(), sys.force_scale, assembly.scale, 1.0))
        }
        SolverStatus::Unbounded => (f64::INFINITY, Vec::new()),
        _ => (f64::NAN, Vec::new()),
    };
    FactorOutcome {
        status: out.status,
        lambda,
        motions,
        residual: residual(&conic, rows, &out.x) * sys.force_scale,
        iterations: out.iterations,
        solver_seconds: out.solver_seconds,
    }
}

/// The mechanism of a component that does not stand under its dead load: the dual of the
/// minimum-tension LP when the component needs tension, else of the minimum-friction-excess LP
/// (tension left out); normalised so that the dead load does unit work. `lambda` of the outcome
/// is that LP's optimum (relative to the component's weight), not a load factor; no motions
/// when both optima are zero (the component stands).
pub fn failure_mechanism(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
) -> FactorOutcome {
    let sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, true);
    let rows = 6 * comp.blocks.len();
    let mut iterations = 0;
    let mut seconds = 0.0;
    let mut last = None;
    for stage in [Stage::Tension, Stage::FrictionExcess { tension: 0.0, penalty: 0.0 }] {
        let conic = contact_problem(&sys, stage, settings).to_conic();
        let out = solve_conic(&conic, accuracy(settings, true), settings.max_iterations);
        iterations += out.iterations;
        seconds += out.solver_seconds;
        let solved = matches!(out.status, SolverStatus::Solved | SolverStatus::AlmostSolved);
        // The dead load's work Dᵀz = −rhsᵀz: the LP's optimum (strong duality).
        let work: f64 = -conic.b[..rows].iter().zip(&out.z).map(|(b, z)| b * z).sum::<f64>();
        let found = solved && work > super::assemble::PINNED_TENSION;
        let motions =
            if found { motions(&out.z, comp.blocks.len(), sys.force_scale, assembly.scale, work) } else { Vec::new() };
        let outcome = FactorOutcome {
            status: out.status,
            lambda: out.objective,
            motions,
            residual: residual(&conic, rows, &out.x) * sys.force_scale,
            iterations,
            solver_seconds: seconds,
        };
        if found || !solved {
            return outcome;
        }
        last = Some(outcome);
    }
    last.expect("two stages ran")
}
