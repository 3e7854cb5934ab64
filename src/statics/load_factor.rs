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
//! With a compressive strength (`StaticsSettings::strength`, resolved from the material by
//! the caller) the crushing rows bound every joint's compression ([`super::problem`]); a
//! crushing joint then shows in the mechanism as a hinge whose compressed zone is used up.
//!
//! Units: the problems are non-dimensional as every stage's (forces by the component's free
//! weight W, lengths by the model size ℓ); motions come back in m and rad, so that the
//! normalised load's work is 1 N·m.

use super::assemble::{Stage, System, contact_problem, live_load};
use super::backend::{Backend, QpOutcome, run};
use super::components::Component;

use super::problem::{Accuracy, ContactProblem, LoadColumn, SolverStatus, Strength};
use super::settings::StaticsSettings;
use super::stages::LP_TOLERANCE;
use super::vertex::{FaceOutcome, Uniqueness, vertex};
use crate::interfaces::Interface;
use crate::model::Assembly;

/// A block's virtual motion: translation (m) then rotation about its centroid (rad), world
/// axes.
pub type Motion = [f64; 6];

/// How a component's load-factor problem ended.
#[derive(Clone, Debug)]
pub struct FactorOutcome {
    /// How the load-factor solve ended.
    pub status: SolverStatus,
    /// λ*; +∞ when the live load can grow without bound (the LP is unbounded), NaN when the
    /// problem has no solution (no λ at all admits equilibrium, or solver trouble).
    pub lambda: f64,
    /// Per block of the component, in its order; the live load does unit work (N·m). Empty
    /// when there is no mechanism (unbounded, or not solved).
    pub motions: Vec<Motion>,
    /// ‖A x + λ L + D‖_∞ of the solution, N.
    pub residual: f64,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Seconds inside the solver.
    pub solver_seconds: f64,
    /// Whether `motions` is the only mechanism at λ* (a vertex of the optimal face when not).
    pub uniqueness: Uniqueness,
}

/// The physical motions of a component's blocks from the duals `z` of its equilibrium rows
/// (the first 6 per block), divided by `norm` (the normalised load's non-dimensional work).
pub(super) fn motions(z: &[f64], blocks: usize, force_scale: f64, length_scale: f64, norm: f64) -> Vec<Motion> {
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

/// ‖A x + λ L − rhs‖_∞ over `sys`'s equilibrium rows for a solution `x` of `cp` (its own
/// variables; λ last when `cp` has a load factor), N.
fn residual(sys: &System, cp: &ContactProblem, x: &[f64], lambda: f64) -> f64 {
    let points = sys.points.len() * cp.per_point();
    let r = sys.residual_vector(&sys.stage_values(cp, &x[..points]));
    let column = cp.factor.as_ref().map_or(&[][..], |f| f.column.as_slice());
    let lambda = if lambda.is_finite() { lambda } else { 0.0 };
    let lam = |i: usize| column.get(i).map_or(0.0, |l| lambda * l);
    r.iter().enumerate().fold(0.0f64, |m, (i, r)| m.max((r + lam(i)).abs())) * sys.force_scale
}

/// The load factor to the statics' solver tolerance (relative: λ* to ~1e-8 of itself); the
/// failure LPs to the stages' LP tolerance, as the graded answer they explain.
fn accuracy(settings: &StaticsSettings, lp: bool) -> Accuracy {
    let tol = if lp { settings.solver_tolerance.min(LP_TOLERANCE) } else { settings.solver_tolerance };
    Accuracy { feas: tol, gap_abs: tol, gap_rel: tol, pure_relative: false }
}

/// The load-factor problem on the statics' backend; when the structured solver ends short of
/// `Solved`, again on clarabel (the iterations of both counted).
///
/// Why: at λ* the design is on the edge of collapse, where the structured solver's reduced
/// Newton system can lose its last digits; a safety net, rarely taken (docs/benchmarks.md).
fn solve_to_full_accuracy(cp: &ContactProblem, settings: &StaticsSettings) -> QpOutcome {
    let acc = accuracy(settings, false);
    let first = run(cp, settings.backend, acc, settings.max_iterations);
    if first.backend != Backend::Structured || matches!(first.status, SolverStatus::Solved | SolverStatus::Unbounded) {
        return first;
    }
    let second = run(cp, Backend::Clarabel, acc, settings.max_iterations);
    let iterations = first.iterations + second.iterations;
    let mut better = if answer_rank(second.status) < answer_rank(first.status) { second } else { first };
    better.iterations = iterations;
    better
}

/// 0 for a definite answer, 1 for one at reduced tolerances, 2 for none.
fn answer_rank(status: SolverStatus) -> u8 {
    match status {
        SolverStatus::Solved | SolverStatus::Unbounded | SolverStatus::Infeasible => 0,
        SolverStatus::AlmostSolved => 1,
        _ => 2,
    }
}

/// λ* ≥ 0 of a component that stands under its dead load (λ = 0 is feasible), on the
/// statics' backend: the structured solver keeps the λ ≥ 0 column beside its sparse factor.
pub fn standing_load_factor(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
) -> FactorOutcome {
    load_factor(assembly, interfaces, comp, mu, settings, true)
}

/// λ* of `comp` with λ free (for a design that does not stand, λ* may be negative): the
/// structured solver takes only λ ≥ 0, so this runs on clarabel.
pub fn component_load_factor(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
) -> FactorOutcome {
    load_factor(assembly, interfaces, comp, mu, settings, false)
}

/// λ* of `comp` for its blocks' live loads (at least one non-zero), λ ≥ 0 when `bounded`, and
/// the mechanism from the block rows' duals.
fn load_factor(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
    bounded: bool,
) -> FactorOutcome {
    let t = std::time::Instant::now();
    let mut sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, false);
    if settings.strength.is_some() {
        sys = sys.with_stress();
    }
    let mut cp = contact_problem(&sys, Stage::Strict, settings);
    cp.p.iter_mut().for_each(|v| *v = 0.0);
    cp.q.iter_mut().for_each(|v| *v = 0.0);
    cp.factor = Some(LoadColumn { column: live_load(assembly, comp, sys.force_scale), cost: -1.0, bounded });
    // The stone's strength bounds every joint's compression (clarabel: the crushing rows).
    cp.crushing = settings.strength.map(|s| sys.crushing(Strength::Fixed(s * sys.strength_scale(assembly.scale))));
    let out = solve_to_full_accuracy(&cp, settings);
    let mut uniqueness = Uniqueness::NotExamined;
    let (lambda, motions) = match out.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            let blocks = comp.blocks.len();
            // The crushing rows' duals enter admissibility: their face is left as solved.
            let (z, face) = if cp.crushing.is_none() && settings.one_mechanism {
                let live = cp.factor.as_ref().map_or(&[][..], |f| f.column.as_slice());
                one_mechanism(&sys, live, &out.duals, &out.x)
            } else {
                (None, uniqueness)
            };
            uniqueness = face;
            // λ's column follows the points' (the crushing cones' own columns follow it).
            (
                out.x[sys.points.len() * cp.per_point()],
                motions(z.as_deref().unwrap_or(&out.duals), blocks, sys.force_scale, assembly.scale, 1.0),
            )
        }
        SolverStatus::Unbounded => (f64::INFINITY, Vec::new()),
        _ => (f64::NAN, Vec::new()),
    };
    FactorOutcome {
        status: out.status,
        lambda,
        motions,
        residual: residual(&sys, &cp, &out.x, lambda),
        iterations: out.iterations,
        solver_seconds: t.elapsed().as_secs_f64(),
        uniqueness,
    }
}

/// A vertex of the optimal face from the interior point's duals `z` and forces `x` (None: keep `z`), and
/// what it says of the mechanism's uniqueness.
fn one_mechanism(sys: &System, live: &[f64], z: &[f64], x: &[f64]) -> (Option<Vec<f64>>, Uniqueness) {
    let forces: Vec<[f64; 3]> = (0..sys.points.len()).map(|p| sys.frame_force(x, p)).collect();
    match vertex(&sys.geometry, sys.model, sys.mu, live, z, &forces) {
        FaceOutcome::Unique => (None, Uniqueness::Unique),
        FaceOutcome::Vertex { vertex, dimension, vertices, .. } => {
            (Some(vertex), Uniqueness::OneOfMany { dimension, vertices })
        }
        FaceOutcome::NoVertices => (None, Uniqueness::NotExamined),
        FaceOutcome::Failed { dimension, residual } => (None, Uniqueness::Blend { dimension, residual }),
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
    let t = std::time::Instant::now();
    let sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, true);
    let mut iterations = 0;
    let mut last = None;
    for stage in [Stage::Tension, Stage::FrictionExcess { tension: 0.0, penalty: 0.0 }] {
        let cp = contact_problem(&sys, stage, settings);
        let out = run(&cp, settings.backend, accuracy(settings, true), settings.max_iterations);
        iterations += out.iterations;
        let solved = out.status.solved();
        // The dead load's work Dᵀz = −rhsᵀz: the LP's optimum (strong duality).
        let work: f64 = -sys.eq_rhs.iter().zip(&out.duals).map(|(b, z)| b * z).sum::<f64>();
        let found = solved && work > super::assemble::PINNED_TENSION;
        let blocks = comp.blocks.len();
        let motions =
            if found { motions(&out.duals, blocks, sys.force_scale, assembly.scale, work) } else { Vec::new() };
        let outcome = FactorOutcome {
            status: out.status,
            lambda: out.objective,
            motions,
            residual: residual(&sys, &cp, &out.x, 0.0),
            iterations,
            solver_seconds: t.elapsed().as_secs_f64(),
            uniqueness: Uniqueness::NotExamined,
        };
        if found || !solved {
            return outcome;
        }
        last = Some(outcome);
    }
    last.expect("two stages ran")
}
