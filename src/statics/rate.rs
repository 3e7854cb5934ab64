//! The rate problem from rest: what a component's blocks do in the first instant after the
//! scaffolding goes, when no contact was squeezed beforehand — the core of the kinematic
//! verdict ([`crate::stability::kinematic`] is its front).
//!
//! ## The problem
//! From rest, the blocks' accelerations a (6 per free block: linear, then angular about the
//! centroid, world axes) and the contact forces f at the interface vertices satisfy
//! - Newton–Euler: M a = w + A f (w the dead load, A the statics' equilibrium rows);
//! - Signorini at every vertex: the normal relative acceleration g_n = (Aᵀa)_n ≥ 0 (no
//!   interpenetration), f_n ≥ 0, f_n g_n = 0 (a force only where the contact stays closed);
//! - Coulomb: f_t within μ f_n (the statics' friction model), and at full capacity against the
//!   slip where the contact slips.
//!
//! a = 0 solves it whenever the statics stands: RBE asks for no more. The question here is
//! whether the forces that *arise* hold the blocks. With the friction capacity fixed at c per
//! vertex (Tresca) the problem is convex — Gauss's principle: the forces minimise
//! ½ (w + A f)ᵀ M⁻¹ (w + A f) over f_n ≥ 0, f_t within c, and a = M⁻¹ (w + A f); the optimality
//! conditions of that QP are the three conditions above with capacity c (Signorini and a
//! friction opposing the slip are the normal cone of the force set). Coulomb is the fixed
//! point c = μ f_n.
//!
//! ## The fixed point from no squeeze
//! Round 0 has c = 0: no contact carries anything before the loads act, so no friction either.
//! Each next round takes c = μ × the normal forces the last round produced, until they settle:
//! - at rest (a = 0): the friction the release itself produced holds every block — it stands
//!   (the front also asks the statics to stand: a Coulomb equilibrium at rest exists; the
//!   per-vertex split of the forces at rest is statically indeterminate, so it is not asked to
//!   match the moving round's split vertex by vertex);
//! - moving with settled capacities: a Coulomb solution with motion — it fails, and the
//!   accelerations are its mechanism (the loads do positive work along it:
//!   wᵀa = aᵀMa + the friction's dissipation);
//! - not settled within the round limit: undecided, an explicit answer.
//!
//! Each round of a moving component is two QPs over the same rows (at rest the first is
//! enough: there is no next round to feed). The accelerations are unique (M is positive
//! definite), the forces are not: opposite faces can squeeze a sliding bar by any amount
//! without changing its motion, and a face's corners can share a load any way. So the first
//! QP finds the accelerations (Gauss), and the second the smallest forces (Σ f², the statics'
//! own distribution rule) that give them — a squeeze nothing produces is zero, and the fixed
//! point does not depend on the solver's path. The second QP keeps the accelerations by a
//! stiff quadratic pin, (1/η) × Gauss's objective centred on the first QP's residual, η
//! = [`PIN`].
//!
//! ## Units
//! Non-dimensional like the statics' problems: forces by the component's free weight W,
//! lengths by the model size L, linear accelerations by g, angular ones by g/L. The inertia
//! enters in each block's principal axes (so M⁻¹ is diagonal): the moment rows' residual r
//! (world axes) is R r' with R the principal axes, r' weighted 1/Ĩ_k with Ĩ_k = I_k g / (W L²);
//! the force rows' residual weighted 1/m̃ with m̃ = m g / W. The residual's columns are
//! scaled by √m̃ and √Ĩ_k, so that Gauss's weight on them is the identity (weights of very
//! different sizes cost the interior point accuracy per iteration).
//! Accelerations come back in m/s² and rad/s².

use super::assemble::System;
use super::backend::solve_conic;
use super::components::Component;
use super::load_factor::Motion;
use super::problem::{Accuracy, Cone, ConicProblem, FrictionModel, SolverStatus, Var};
use crate::interfaces::Interface;
use crate::model::Assembly;
use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Settings of the kinematic check; each default written once, in `Default` (with why).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct KinematicSettings {
    /// Rounds of the fixed point c = μ f_n allowed before the answer is "undecided".
    pub max_rounds: u32,
    /// A block is at rest when no vertex accelerates faster than this fraction of g.
    pub still: f64,
    /// The capacities have settled when no vertex's changed by more than this fraction of the
    /// largest.
    pub settle: f64,
    /// Interior-point feasibility and gap tolerance of each round.
    pub solver_tolerance: f64,
    /// Interior-point iterations allowed per round.
    pub max_iterations: u32,
}

impl Default for KinematicSettings {
    fn default() -> Self {
        Self {
            // Above the rounds of every design that settles: it only bounds the ones that cycle.
            max_rounds: 40,
            // Far above the accelerations a round solved to 1e-10 leaves on designs at rest.
            still: 1e-6,
            // The capacities converge linearly; 1e-4 of the largest is far inside what changes
            // a verdict and saves the tail of rounds.
            settle: 1e-4,
            solver_tolerance: 1e-10,
            max_iterations: 200,
        }
    }
}

impl KinematicSettings {
    /// The settings that cannot give an answer, by name.
    pub fn validate(&self) -> Result<(), String> {
        for (name, v) in [("still", self.still), ("settle", self.settle), ("solver_tolerance", self.solver_tolerance)] {
            if !(v > 0.0 && v < 1.0) {
                return Err(format!("kinematic setting {name} = {v} must be in (0, 1)"));
            }
        }
        if self.max_rounds == 0 || self.max_iterations == 0 {
            return Err("kinematic settings max_rounds and max_iterations must be at least 1".into());
        }
        Ok(())
    }
}

/// Where the fixed point ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RateState {
    /// At rest, held by the friction the release produced.
    AtRest,
    /// Moving, with settled friction capacities.
    Moving,
    /// The capacities did not settle within the round limit.
    Unsettled,
    /// A round's solve failed (`status`).
    SolverFailed,
}

/// The rate problem's answer for one component.
#[derive(Clone, Debug)]
pub struct RateOutcome {
    /// At rest, moving, unsettled or solver trouble.
    pub state: RateState,
    /// The last round's solver status.
    pub status: SolverStatus,
    /// Per block of the component, in its order: m/s², then rad/s².
    pub accelerations: Vec<Motion>,
    /// The largest vertex acceleration, as a fraction of g.
    pub peak: f64,
    /// Fixed-point rounds of the friction capacities.
    pub rounds: u32,
    /// Interior-point iterations, summed over rounds.
    pub iterations: u32,
    /// ‖M a − w − A f‖_∞ of the last round, N.
    pub residual: f64,
    /// Seconds inside the solver.
    pub solver_seconds: f64,
}

/// A capacity below this fraction of the largest is none: its friction columns are left out
/// (a second-order cone or pyramid of radius ~0 leaves the interior-point method no interior).
const CAPACITY_FLOOR: f64 = 1e-9;

/// A normal force (relative to the component's weight) below this multiple of the solver
/// tolerance is the interior point's round-off, not a contact force.
const NOISE: f64 = 1e2;

/// Solves the rate problem of `comp` (module docs).
pub fn rate_problem(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    model: FrictionModel,
    settings: &KinematicSettings,
) -> RateOutcome {
    let t = Instant::now();
    let sys = System::new(assembly, interfaces, comp, mu, model, false);
    let inertia = principal_inertia(assembly, comp, sys.force_scale);
    let acc = Accuracy::uniform(settings.solver_tolerance);
    let mut caps = vec![0.0; sys.points.len()];
    let mut iterations = 0;
    let mut last = None;
    for round in 1..=settings.max_rounds {
        let (mut problem, cols) = round_problem(&sys, &inertia, &caps);
        let gauss = solve_conic(&problem, acc, settings.max_iterations);
        iterations += gauss.iterations;
        let motion = read_motion(assembly, comp, &inertia, &cols, &gauss.x);
        let solved = SolverStatus::solved;
        // At rest the round's forces are not needed (no next round): the second QP only runs
        // for a component that moves.
        let at_rest = solved(gauss.status) && motion.peak <= settings.still;
        let out = if solved(gauss.status) && !at_rest {
            pin_accelerations(&mut problem, &cols, sys.eq_rhs.len(), &gauss.x);
            let forces = solve_conic(&problem, acc, settings.max_iterations);
            iterations += forces.iterations;
            forces
        } else {
            gauss
        };
        let step = read_forces(&sys, &problem, &cols, &out.x, motion);
        let done = |state| RateOutcome {
            state,
            status: out.status,
            accelerations: step.accelerations.clone(),
            peak: step.peak,
            rounds: round,
            iterations,
            residual: step.residual,
            solver_seconds: t.elapsed().as_secs_f64(),
        };
        if at_rest {
            return done(RateState::AtRest);
        }
        if !solved(out.status) {
            return done(RateState::SolverFailed);
        }
        // A normal force within the solver's noise is none. The second QP resolves Σ f² to its
        // relative tolerance, so a force with f² below tol × Σ f² is invisible to it, and the
        // barrier keeps such forces on contacts that stay closed with nothing to carry. Changes
        // are measured against the mean capacity per point at the least, so that capacities of
        // ~0 that merely wobble count as settled.
        let sum_sq: f64 = step.normal.iter().map(|f| f * f).sum();
        let noise = (NOISE * settings.solver_tolerance).max((settings.solver_tolerance * sum_sq).sqrt());
        let next: Vec<f64> = step.normal.iter().map(|&f| if f > noise { mu * f } else { 0.0 }).collect();
        let mean = mu / caps.len().max(1) as f64;
        let largest = next.iter().chain(&caps).fold(mean.max(f64::MIN_POSITIVE), |m, c| m.max(*c));
        let change = next.iter().zip(&caps).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / largest;
        if change <= settings.settle {
            return done(RateState::Moving);
        }
        caps = next;
        last = Some(done(RateState::Unsettled));
    }
    last.expect("at least one round")
}

/// A block's mass and principal inertia, non-dimensional (module docs), and its principal
/// axes (columns).
struct BlockInertia {
    mass: f64,
    moments: [f64; 3],
    axes: Matrix3<f64>,
}

impl BlockInertia {
    /// The residual columns' scale: r' = s ρ makes Gauss's weight on ρ the identity.
    fn column_scale(&self) -> [f64; 6] {
        let m = self.mass.sqrt();
        [m, m, m, self.moments[0].sqrt(), self.moments[1].sqrt(), self.moments[2].sqrt()]
    }
}

fn principal_inertia(assembly: &Assembly, comp: &Component, force_scale: f64) -> Vec<BlockInertia> {
    let g = assembly.gravity.norm().max(f64::MIN_POSITIVE);
    let l = assembly.scale;
    comp.blocks
        .iter()
        .map(|&b| {
            let block = assembly.block(b);
            let eig = SymmetricEigen::new(block.mass.inertia * block.density);
            BlockInertia {
                mass: block.mass() * g / force_scale,
                moments: [0, 1, 2].map(|k| eig.eigenvalues[k].max(f64::MIN_POSITIVE) * g / (force_scale * l * l)),
                axes: eig.eigenvectors,
            }
        })
        .collect()
}

/// Where a round's variables sit: each vertex's normal force, its friction pair when it has
/// a capacity, and the first of the 6-per-block residual columns.
struct Columns {
    normal: Vec<usize>,
    friction: Vec<Option<(usize, usize)>>,
    residual: usize,
}

/// One round's QP: minimise ½ Σ ρᵀρ (= ½ Σ r'ᵀ M̃'⁻¹ r' with r' = s ρ, s the column scale)
/// subject to A f − R r' = −w, f_n ≥ 0 and f_t within the capacities `caps`.
fn round_problem(sys: &System, inertia: &[BlockInertia], caps: &[f64]) -> (ConicProblem, Columns) {
    let floor = caps.iter().fold(0.0f64, |m, c| m.max(*c)) * CAPACITY_FLOOR;
    let mut n = 0;
    let mut normal = Vec::with_capacity(caps.len());
    let mut friction = Vec::with_capacity(caps.len());
    for &c in caps {
        normal.push(n);
        n += 1;
        if sys.layout.friction && c > floor && c > 0.0 {
            friction.push(Some((n, n + 1)));
            n += 2;
        } else {
            friction.push(None);
        }
    }
    let cols = Columns { normal, friction, residual: n };
    let blocks = inertia.len();
    let mut p_diag = vec![0.0; n];
    p_diag.extend(std::iter::repeat_n(1.0, 6 * blocks));
    let mut a = equilibrium_rows(sys, &cols);
    for (i, bi) in inertia.iter().enumerate() {
        let r = cols.residual + 6 * i;
        let s = bi.column_scale();
        a.extend((0..3).map(|k| (6 * i + k, r + k, -s[k])));
        for k in 0..3 {
            a.extend(
                (0..3)
                    .filter(|&j| bi.axes[(k, j)] != 0.0)
                    .map(|j| (6 * i + 3 + k, r + 3 + j, -bi.axes[(k, j)] * s[3 + j])),
            );
        }
    }
    let mut b = sys.eq_rhs.clone();
    let mut cones = vec![Cone::Zero(6 * blocks)];
    let start = b.len();
    for (p, &c) in caps.iter().enumerate() {
        a.push((b.len(), cols.normal[p], -1.0));
        b.push(0.0);
        let Some((u, v)) = cols.friction[p] else { continue };
        for &(du, dv, s) in sys.model.facets() {
            let row = b.len();
            a.extend([(row, u, du), (row, v, dv)].into_iter().filter(|e| e.2 != 0.0));
            b.push(s * c);
        }
    }
    cones.push(Cone::Nonnegative(b.len() - start));
    if sys.model == FrictionModel::Cone {
        for (p, &c) in caps.iter().enumerate() {
            let Some((u, v)) = cols.friction[p] else { continue };
            // s = b − A x = (c, f_u, f_v) in the second-order cone.
            let row = b.len();
            a.extend([(row + 1, u, -1.0), (row + 2, v, -1.0)]);
            b.extend([c, 0.0, 0.0]);
            cones.push(Cone::SecondOrder(3));
        }
    }
    let n = p_diag.len();
    (ConicProblem { n, p_diag, q: vec![0.0; n], a, b, cones }, cols)
}

/// The statics' equilibrium triplets with their columns moved to the round's.
fn equilibrium_rows(sys: &System, cols: &Columns) -> Vec<(usize, usize, f64)> {
    let per = sys.layout.per_point;
    let (u, v) = (sys.layout.offset(Var::Cu), sys.layout.offset(Var::Cv));
    sys.eq_triplets()
        .into_iter()
        .filter_map(|(row, col, value)| {
            let (p, off) = (col / per, Some(col % per));
            let to = if off == Some(0) {
                Some(cols.normal[p])
            } else if off == u {
                cols.friction[p].map(|f| f.0)
            } else if off == v {
                cols.friction[p].map(|f| f.1)
            } else {
                None
            };
            to.map(|c| (row, c, value))
        })
        .collect()
}

/// The second QP of a round (module docs): the forces' weight Σ f², and the accelerations
/// pinned at the first QP's by (1/η) ½ δᵀ M̃⁻¹ δ, η = [`PIN`], in the residual's deviation
/// δ = r' − r'* (so that the objective stays of the forces' size and the solver's relative
/// tolerance resolves them): the block rows' right-hand side takes in R r'*.
fn pin_accelerations(problem: &mut ConicProblem, cols: &Columns, block_rows: usize, gauss: &[f64]) {
    for &(row, col, v) in problem.a.iter().filter(|e| e.0 < block_rows && e.1 >= cols.residual) {
        problem.b[row] -= v * gauss[col];
    }
    for j in 0..problem.n {
        problem.p_diag[j] = if j < cols.residual { 1.0 } else { problem.p_diag[j] / PIN };
    }
}

/// The stiffness η of the second QP's pin: the accelerations it gives differ from the first
/// QP's by ~η × the forces (relative to g), far below `still`.
pub const PIN: f64 = 1e-8;

/// A round's accelerations (from the first QP): per block (m/s², rad/s²), and the largest
/// vertex acceleration as a fraction of g.
struct RoundMotion {
    accelerations: Vec<Motion>,
    peak: f64,
}

fn read_motion(
    assembly: &Assembly,
    comp: &Component,
    inertia: &[BlockInertia],
    cols: &Columns,
    x: &[f64],
) -> RoundMotion {
    let g = assembly.gravity.norm();
    let l = assembly.scale;
    let mut peak = 0.0f64;
    let accelerations = inertia
        .iter()
        .enumerate()
        .map(|(i, bi)| {
            let s = bi.column_scale();
            let r: Vec<f64> = (0..6).map(|k| x[cols.residual + 6 * i + k] * s[k]).collect();
            let linear = Vector3::new(r[0], r[1], r[2]) / bi.mass;
            let angular = bi.axes * Vector3::new(r[3] / bi.moments[0], r[4] / bi.moments[1], r[5] / bi.moments[2]);
            let block = assembly.block(comp.blocks[i]);
            for p in &block.mesh.vertices {
                peak = peak.max((linear + angular.cross(&((p - block.mass.centroid) / l))).norm());
            }
            let (a, w) = (linear * g, angular * g / l);
            [a.x, a.y, a.z, w.x, w.y, w.z]
        })
        .collect();
    RoundMotion { accelerations, peak }
}

/// What one round gives: per vertex its normal force (non-dimensional, from the second QP), its motion, and the second QP's residual ‖M a − w − A f‖_∞ (N).
struct Round {
    normal: Vec<f64>,
    accelerations: Vec<Motion>,
    peak: f64,
    residual: f64,
}

fn read_forces(sys: &System, problem: &ConicProblem, cols: &Columns, x: &[f64], motion: RoundMotion) -> Round {
    let normal = cols.normal.iter().map(|&c| x[c]).collect();
    let block_rows = sys.eq_rhs.len();
    let mut rows = vec![0.0; block_rows];
    for &(row, col, v) in problem.a.iter().filter(|e| e.0 < block_rows) {
        rows[row] += v * x[col];
    }
    let residual = rows.iter().zip(&problem.b).fold(0.0f64, |m, (r, b)| m.max((r - b).abs())) * sys.force_scale;
    Round { normal, accelerations: motion.accelerations, peak: motion.peak, residual }
}
