//! Densities as variables: which per-block densities within bounds let a component stand by
//! compression and friction, the lightest such, and a mechanism that proves when none does.
//!
//! A block's self-weight and its acceleration fields scale with its mass, so with a uniform
//! density ρ_j per cell — a whole block, or a cell of it ([`crate::geometry::cells`]) — the
//! equilibrium rows `A x = −D` become `A x + Σ_j ρ_j c_j = −p`: c_j is cell j's load per unit
//! density on its block's rows (its volume times gravity plus the block's dead fields' N/kg,
//! at the cell's centroid: a moment about the block's centroid when the cell is off it), p the
//! loads that do not scale (point loads). Linear in (x, ρ): one LP for the pyramid and box
//! models, one SOCP for the cone, on clarabel.
//!
//! - [`DensityGoal::Lightest`]: minimise the component's mass over the densities that stand.
//! - [`DensityGoal::Carries`]: the same, among densities that also stand under each live case
//!   at a given factor λ — one copy of the forces per case, the densities shared (a live field
//!   scales with the mass too, so λ·ρ is bilinear: the caller searches λ, see
//!   [`crate::synthesis::infill`]).
//!
//! When no density within the bounds stands, the minimum-tension LP (then the minimum
//! friction-excess LP) over the same bounds has a positive optimum T*, and by minimax duality
//! its equilibrium duals are a mechanism u whose dead-load work is at least T* for every
//! admissible density: `min over the bounds of (p + Σ ρ_j c_j)·u = T*`. Normalised so that
//! this least work is 1 N·m.
//!
//! Units: densities in kg/m³ outside, ρ / ρ_ref inside (ρ_ref the largest upper bound), forces
//! by the component's free weight at its current densities, lengths by the model size.

use super::assemble::{PINNED_TENSION, Stage, System, contact_problem};
use super::backend::{self, Backend, QpOutcome, solve_conic};
use super::components::Component;
use super::load_factor::{Motion, motions};
use super::problem::{Accuracy, BlockColumn, Cone, ConicProblem, ContactProblem, SolverStatus, Strength};
use super::settings::StaticsSettings;
use super::stages::LP_TOLERANCE;
use crate::geometry::{Point3, Vector3};
use crate::interfaces::Interface;
use crate::model::Assembly;
use crate::model::loads::Wrench;

/// One density variable: a block of the component (its index there) or a cell of it, with
/// its volume (m³), centroid (m) and bounds (kg/m³, 0 < lo ≤ hi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DensityCell {
    /// The block's index in the component.
    pub block: usize,
    /// Volume of the block or cell, m³.
    pub volume: f64,
    /// Its centroid, m.
    pub centroid: Point3,
    /// The lowest density allowed, kg/m³.
    pub lo: f64,
    /// The highest density allowed, kg/m³.
    pub hi: f64,
}

/// A live load case, per block of the assembly: the N/kg of its acceleration fields and the
/// wrench (N, N·m about the centroid) of the rest.
#[derive(Clone, Debug, PartialEq)]
pub struct LiveCase {
    /// Per block, the acceleration fields' force per kg of its mass, N/kg.
    pub per_kg: Vec<[f64; 3]>,
    /// Per block, the wrench of the point loads (N, N·m about its centroid), independent of the mass.
    pub fixed: Vec<Wrench>,
}

impl LiveCase {
    /// The assembly's own live loads.
    pub fn of(assembly: &Assembly) -> Self {
        let (per_kg, fixed) = assembly
            .blocks
            .iter()
            .zip(&assembly.loads)
            .map(|(b, l)| {
                let mut fixed = l.live;
                (0..3).for_each(|k| fixed[k] -= l.live_per_kg[k] * b.mass());
                (l.live_per_kg, fixed)
            })
            .unzip();
        Self { per_kg, fixed }
    }

    /// A horizontal field of 1 g along `azimuth` (degrees from +x towards +y) on every block.
    pub fn horizontal(assembly: &Assembly, azimuth: f64) -> Self {
        let (s, c) = azimuth.to_radians().sin_cos();
        let g = assembly.gravity.norm();
        let n = assembly.blocks.len();
        Self { per_kg: vec![[c * g, s * g, 0.0]; n], fixed: vec![[0.0; 6]; n] }
    }
}

/// What the densities are chosen for.
#[derive(Clone, Copy, Debug)]
pub enum DensityGoal<'c> {
    /// The lightest densities that stand under the dead load.
    Lightest,
    /// The lightest that stand under the dead load and under each case at factor `lambda`.
    Carries {
        /// The factor on each live case (for an acceleration field, in g).
        lambda: f64,
        /// The live load cases, each carried on its own.
        cases: &'c [LiveCase],
    },
}

/// How a component's density problem ended.
#[derive(Clone, Debug)]
pub struct DensityOutcome {
    /// How the density problem's solve ended.
    pub status: SolverStatus,
    /// Per cell, kg/m³; empty when no density within the bounds stands.
    pub densities: Vec<f64>,
    /// When none stands (and the goal is [`DensityGoal::Lightest`]): the mechanism, per block
    /// of the component, normalised so that its least dead-load work over the bounds is 1 N·m.
    pub motions: Vec<Motion>,
    /// That least work before normalisation, relative to the component's weight (the LP's T*).
    pub excess: f64,
    /// ‖A x + Σ ρ_i c_i + p‖_∞ of the dead-load copy, N (NaN without a solution).
    pub residual: f64,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Seconds inside the solver.
    pub solver_seconds: f64,
    /// The solver that ran the density problem (clarabel for several loadings side by side).
    pub backend: Backend,
}

/// The density columns and the fixed right-hand side of a component's dead or live rows.
struct Loading {
    /// Per cell: its block rows' entries (6) per unit of ρ / ρ_ref (non-dimensional).
    columns: Vec<[f64; 6]>,
    /// Minus the loads that do not scale with mass, 6 per block (non-dimensional).
    rhs: Vec<f64>,
}

impl Loading {
    /// The dead loading of `comp`, plus `lambda` times `case` when given.
    fn new(
        assembly: &Assembly,
        comp: &Component,
        sys: &System,
        cells: &[DensityCell],
        rho_ref: f64,
        live: Option<(f64, &LiveCase)>,
    ) -> Self {
        let (f, l) = (sys.force_scale, assembly.scale);
        let mut rhs = vec![0.0; 6 * comp.blocks.len()];
        let mut per_kg = Vec::with_capacity(comp.blocks.len());
        for (i, &b) in comp.blocks.iter().enumerate() {
            let loads = &assembly.loads[b.0];
            let mut a = Vector3::from_fn(|k, _| assembly.gravity[k] + loads.dead_per_kg[k]);
            let mut fixed = loads.dead;
            (0..3).for_each(|k| fixed[k] -= loads.dead_per_kg[k] * assembly.block(b).mass());
            if let Some((lambda, case)) = live {
                a += Vector3::from(case.per_kg[b.0]) * lambda;
                (0..6).for_each(|k| fixed[k] += lambda * case.fixed[b.0][k]);
            }
            per_kg.push(a);
            for k in 0..3 {
                rhs[6 * i + k] = -fixed[k] / f;
                rhs[6 * i + 3 + k] = -fixed[3 + k] / (f * l);
            }
        }
        let columns = cells
            .iter()
            .map(|c| {
                let force = per_kg[c.block] * (rho_ref * c.volume / f);
                let arm = (c.centroid - assembly.block(comp.blocks[c.block]).mass.centroid) / l;
                let moment = arm.cross(&force);
                [force.x, force.y, force.z, moment.x, moment.y, moment.z]
            })
            .collect();
        Self { columns, rhs }
    }
}

/// The stage's contact problem over `sys`, without densities.
fn stage_problem<'s>(
    sys: &'s System,
    stage: Stage,
    settings: &StaticsSettings,
    length_scale: f64,
) -> ContactProblem<'s> {
    let mut cp = contact_problem(sys, stage, settings);
    if matches!(stage, Stage::Strict) {
        // Feasibility: the objective is the densities' (the caller's).
        cp.p.iter_mut().for_each(|v| *v = 0.0);
        cp.q.iter_mut().for_each(|v| *v = 0.0);
    }
    if let Some(s) = settings.strength {
        cp.crushing = Some(sys.crushing(Strength::Fixed(s * sys.strength_scale(length_scale))));
    }
    cp
}

/// The density variables of one loading (non-dimensional bounds, linear cost).
/// `scale` multiplies the density variables (`scale` ρ/ρ_ref is solved for): their columns and
/// costs divided by it, their bounds multiplied.
fn density_columns(
    cells: &[DensityCell],
    loading: &Loading,
    bounds: &[(f64, f64)],
    cost: &[f64],
    scale: f64,
) -> Vec<BlockColumn> {
    cells
        .iter()
        .zip(&loading.columns)
        .zip(bounds.iter().zip(cost))
        .map(|((cell, &column), (&(lo, hi), &cost))| BlockColumn {
            block: cell.block,
            column: column.map(|c| c / scale),
            p: 0.0,
            cost: cost / scale,
            bounds: Some((lo * scale, hi * scale)),
        })
        .collect()
}

/// The density variables' scale: the mass gradient (each cell's share of the volume) with unit
/// norm. Unscaled, a design of n cells has a gradient of norm ~1/√n, and the interior point
/// crawls along the density bounds (the Armadillo's 366: steps of 0.05–0.4 for ten iterations,
/// 19 in all; scaled, 12 — the strict QP's count).
fn density_scale(cost: &[f64]) -> f64 {
    let norm = cost.iter().map(|c| c * c).sum::<f64>().sqrt();
    if norm > 0.0 && norm.is_finite() { norm } else { 1.0 }
}

/// The stage's problem over `sys` with the dead loading's density columns, on the statics'
/// backend (the structured solver eliminates each density into its block's rows); `sys`'s
/// block rows' right-hand side is set to the loading's. The outcome and its densities.
fn solve_dead(
    sys: &mut System,
    stage: Stage,
    settings: &StaticsSettings,
    length_scale: f64,
    columns: Vec<BlockColumn>,
    dead: &Loading,
) -> (QpOutcome, Vec<f64>) {
    sys.geometry.rhs.clone_from(&dead.rhs);
    let mut cp = stage_problem(sys, stage, settings, length_scale);
    cp.columns = columns;
    let out = backend::run(&cp, settings.backend, accuracy(settings), settings.max_iterations);
    let rho = backend::block_columns(&cp, &out).to_vec();
    (out, rho)
}

/// One copy of `base` per loading side by side (block-diagonal), each with its block rows'
/// right-hand side and its density columns; the densities as the last variables with their
/// bounds (non-dimensional) and linear cost `cost`.
fn stack(
    base: &ConicProblem,
    loadings: &[Loading],
    cells: &[DensityCell],
    bounds: &[(f64, f64)],
    cost: &[f64],
) -> ConicProblem {
    let n_own = base.n * loadings.len();
    let mut out = ConicProblem::default();
    for (copy, loading) in loadings.iter().enumerate() {
        let (row0, col0) = (copy * base.b.len(), copy * base.n);
        out.a.extend(base.a.iter().map(|&(r, c, v)| (row0 + r, col0 + c, v)));
        for (j, (cell, c)) in cells.iter().zip(&loading.columns).enumerate() {
            out.a.extend((0..6).filter(|&k| c[k] != 0.0).map(|k| (row0 + 6 * cell.block + k, n_own + j, c[k])));
        }
        out.b.extend(&loading.rhs);
        out.b.extend(&base.b[loading.rhs.len()..]);
        out.cones.extend(&base.cones);
        out.p_diag.extend(&base.p_diag);
        out.q.extend(&base.q);
    }
    for (i, &(lo, hi)) in bounds.iter().enumerate() {
        out.a.push((out.b.len(), n_own + i, -1.0));
        out.b.push(-lo);
        out.a.push((out.b.len(), n_own + i, 1.0));
        out.b.push(hi);
    }
    out.cones.push(Cone::Nonnegative(2 * bounds.len()));
    out.p_diag.extend(std::iter::repeat_n(0.0, bounds.len()));
    out.q.extend(cost);
    out.n = out.p_diag.len();
    out
}

/// The densities of `cells` (of `comp`'s blocks; each block's cells together its whole
/// volume) for `goal`.
pub fn component_densities(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
    cells: &[DensityCell],
    goal: DensityGoal,
) -> DensityOutcome {
    let t = std::time::Instant::now();
    let mut sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, false);
    if settings.strength.is_some() {
        sys = sys.with_stress();
    }
    let rho_ref = cells.iter().map(|c| c.hi).fold(0.0, f64::max);
    let bounds: Vec<(f64, f64)> = cells.iter().map(|c| (c.lo / rho_ref, c.hi / rho_ref)).collect();
    // The mass relative to the component's at ρ_ref.
    let total: f64 = cells.iter().map(|c| c.volume).sum();
    let cost: Vec<f64> = cells.iter().map(|c| c.volume / total).collect();
    let mut loadings = vec![Loading::new(assembly, comp, &sys, cells, rho_ref, None)];
    if let DensityGoal::Carries { lambda, cases } = goal {
        loadings
            .extend(cases.iter().map(|case| Loading::new(assembly, comp, &sys, cells, rho_ref, Some((lambda, case)))));
    }
    let forces = sys.n();
    let (status, iterations, backend, x, r) = if loadings.len() == 1 {
        let scale = density_scale(&cost);
        let columns = density_columns(cells, &loadings[0], &bounds, &cost, scale);
        let (out, r) = solve_dead(&mut sys, Stage::Strict, settings, assembly.scale, columns, &loadings[0]);
        let r: Vec<f64> = r.iter().map(|r| r / scale).collect();
        (out.status, out.iterations, out.backend, out.x, r)
    } else {
        let base = stage_problem(&sys, Stage::Strict, settings, assembly.scale).to_conic();
        let problem = stack(&base, &loadings, cells, &bounds, &cost);
        let out = solve_conic(&problem, accuracy(settings), settings.max_iterations);
        let r = out.x[out.x.len() - cells.len()..].to_vec();
        (out.status, out.iterations, Backend::Clarabel, out.x, r)
    };
    let found = status.solved();
    let mut outcome = DensityOutcome {
        status,
        densities: Vec::new(),
        motions: Vec::new(),
        excess: 0.0,
        residual: f64::NAN,
        iterations,
        solver_seconds: 0.0,
        backend,
    };
    if found {
        outcome.densities = r.iter().zip(cells).map(|(r, c)| (r * rho_ref).clamp(c.lo, c.hi)).collect();
        outcome.residual = residual(&sys, cells, &loadings[0], &x[..forces], &r);
    } else if status == SolverStatus::Infeasible && matches!(goal, DensityGoal::Lightest) {
        let cert = certificate(assembly, interfaces, comp, mu, settings, cells, rho_ref);
        outcome.iterations += cert.iterations;
        outcome.motions = cert.motions;
        outcome.excess = cert.excess;
    }
    outcome.solver_seconds = t.elapsed().as_secs_f64();
    outcome
}

/// The statics' solver tolerance, no looser than the stages' LP tolerance: the densities are an
/// answer at a limit, as a load factor is.
fn accuracy(settings: &StaticsSettings) -> Accuracy {
    let tol = settings.solver_tolerance.min(LP_TOLERANCE);
    Accuracy { feas: tol, gap_abs: tol, gap_rel: tol, pure_relative: false }
}

/// ‖A x + C r − rhs‖_∞ of the dead copy, N (`x`: the strict stage's variables, which on a
/// strict system are the system's own, in its layout).
fn residual(sys: &System, cells: &[DensityCell], dead: &Loading, x: &[f64], r: &[f64]) -> f64 {
    let mut out = vec![0.0; dead.rhs.len()];
    sys.a_mul(&x[..sys.n()], &mut out);
    for ((cell, c), r) in cells.iter().zip(&dead.columns).zip(r) {
        (0..6).for_each(|k| out[6 * cell.block + k] += c[k] * r);
    }
    out.iter().zip(&dead.rhs).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) * sys.force_scale
}

/// The mechanism of a component no density within the bounds makes stand (module docs).
struct Certificate {
    motions: Vec<Motion>,
    excess: f64,
    iterations: u32,
}

fn certificate(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
    cells: &[DensityCell],
    rho_ref: f64,
) -> Certificate {
    let mut sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, true);
    let dead = Loading::new(assembly, comp, &sys, cells, rho_ref, None);
    let bounds: Vec<(f64, f64)> = cells.iter().map(|c| (c.lo / rho_ref, c.hi / rho_ref)).collect();
    let columns = density_columns(cells, &dead, &bounds, &vec![0.0; bounds.len()], 1.0);
    let mut iterations = 0;
    for stage in [Stage::Tension, Stage::FrictionExcess { tension: 0.0, penalty: 0.0 }] {
        let (out, _) = solve_dead(&mut sys, stage, settings, assembly.scale, columns.clone(), &dead);
        iterations += out.iterations;
        let solved = out.status.solved();
        if solved && out.objective > PINNED_TENSION {
            let blocks = comp.blocks.len();
            let m = motions(&out.duals, blocks, sys.force_scale, assembly.scale, out.objective);
            return Certificate { motions: m, excess: out.objective, iterations };
        }
        if !solved {
            break;
        }
    }
    Certificate { motions: Vec::new(), excess: 0.0, iterations }
}
