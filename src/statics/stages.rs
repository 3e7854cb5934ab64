//! The stages of one component's solve (module docs of [`crate::statics`]): the strict QP,
//! and when it has no solution the exact minimum-tension and minimum-excess LPs and the
//! distribution QP; the solve of all components, on two threads when it pays; and the verdict
//! rule over their outcomes.

use super::assemble::{ForcePoint, Stage, System, contact_problem, tension_budget};
use super::backend::{Backend, QpOutcome, Warm, WarmStart, run_warm};
use super::components::Component;
use super::problem::{Accuracy, SolverStatus, Var};
use super::settings::{FirstStage, StaticsSettings};
use crate::interfaces::Interface;
use crate::model::{Assembly, BlockId};
use serde::Serialize;
use std::time::Instant;
/// A relaxed-first answer that misses standing by at most this fraction of the component's
/// weight is confirmed by the strict QP ([`ComponentSolve::to_confirm`]), and a strict QP whose
/// forces miss friction by at most this is solved again to a tighter feasibility
/// ([`ComponentSolve::strict`]).
const CONFIRM_BELOW: f64 = 1e-6;

/// Interior-point tolerance of the minimum-tension and minimum-excess LPs.
pub const LP_TOLERANCE: f64 = 1e-10;

/// First weight M of Σ c_n⁻ in the exact-penalty friction-excess LP `M Σ c_n⁻ + Σ s`, and the
/// largest tried (×100 each time the tension comes back above its minimum T*).
///
/// Why a penalty and not the budget Σ c_n⁻ ≤ T*: in the dual (a mechanism), M bounds how fast
/// a joint may open; with the budget (or with c_n⁻ pinned at 0) the openings are unbounded,
/// the dual optimal face with them, and the interior-point method drifts towards it. Its
/// answer is the budget form's whenever Σ c_n⁻ comes back at T*: then it is feasible for the
/// budget form, and no point of the budget form does better (M T* + F ≥ M Σc_n⁻ + Σ s).
const EXCESS_PENALTY: (f64, f64) = (1e3, 1e7);

/// Outcome of one component, in physical units.
#[derive(Clone, Debug)]
pub struct ComponentOutcome {
    pub status: SolverStatus,
    pub message: Option<String>,
    /// Per force point `[c_n⁺, c_n⁻, c_u, c_v, s]` in N (zeros where a model has no such
    /// variable); empty when not solved.
    pub forces: Vec<[f64; 5]>,
    pub points: Vec<ForcePoint>,
    /// Minimum total tension and friction excess, N.
    pub min_tension: f64,
    pub min_excess: f64,
    /// ‖equilibrium residual‖_∞, N.
    pub residual: f64,
    pub iterations: u32,
    /// Whether any stage ran on clarabel (the clarabel backend, or a problem the structured
    /// solver does not take).
    pub used_clarabel: bool,
    /// Free weight of the component and of its lightest block, N.
    pub weight: f64,
    pub lightest: f64,
    /// With a compressive strength, on a component that stands by compression and friction:
    /// the least strength its equilibria need (Pa) and the interface that needs it (its place
    /// in the component's interfaces, so that a cached outcome stays valid); `None` otherwise.
    pub crushing: Option<(f64, usize)>,
    /// Seconds building the problems (layout, rows; on the clarabel backend also its matrices)
    /// and inside the interior-point solver that ran (the structured backend by default).
    pub assemble_seconds: f64,
    pub solver_seconds: f64,
}

/// What a component's stages have spent so far.
#[derive(Clone, Copy, Default)]
struct Tally {
    iterations: u32,
    assemble_seconds: f64,
    solver_seconds: f64,
    used_clarabel: bool,
}

/// A solved component before it is turned into forces: the system the forces live in, the
/// last solve's outcome (in the system's layout), and the minimum tension and friction excess
/// (non-dimensional).
struct Solution {
    sys: System,
    out: QpOutcome,
    tension: f64,
    excess: f64,
}

/// One component's solve, step by step ([`solve_component`]).
struct ComponentSolve<'a> {
    assembly: &'a Assembly,
    interfaces: &'a [Interface],
    comp: &'a Component,
    mu: f64,
    settings: &'a StaticsSettings,
    /// Free weight of the component and of its lightest block, N.
    weights: (f64, f64),
    tally: Tally,
    /// The strict QP's iterate the previous solve of this component kept, and the one this
    /// solve keeps (`StaticsSettings::warm_start`).
    warm_in: Option<&'a WarmStart>,
    warm_out: Option<WarmStart>,
}

/// Solves one component: the strict QP, and if it has no solution the relaxed stages. With
/// `settings.warm_start`, the strict QP starts from `warm` (the iterate the previous solve of
/// a component of this layout kept, when it fits), and the iterate this solve keeps comes back
/// beside the outcome. Only the strict QP: on the relaxed stages' LPs (degenerate, near a
/// mechanism) a warm start saves no iterations.
pub fn solve_component(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
    warm: Option<&WarmStart>,
) -> (ComponentOutcome, Option<WarmStart>) {
    let mut solve = ComponentSolve::new(assembly, interfaces, comp, mu, settings);
    solve.warm_in = warm;
    if let Some(unheld) = solve.unsupported() {
        return (unheld, None);
    }
    let solution = match solve.strict_first() {
        Some(solution) => solution,
        None => match solve.relaxed() {
            Ok(solution) if solve.to_confirm(&solution) => solve.strict().unwrap_or(solution),
            Ok(solution) => solution,
            Err(failed) => return (*failed, solve.warm_out),
        },
    };
    let kept = std::mem::take(&mut solve.warm_out);
    let mut solution = solution;
    let crushing = solve.crushing(&mut solution);
    (ComponentOutcome { crushing, ..solve.finish(solution) }, kept)
}

/// The accuracy a stage is solved to. The LPs decide the verdict: they are solved to 1e-10
/// (absolute) so that their optimum resolves a tension or friction excess of 1e-8 W near zero
/// (see `StaticsSettings::stand_tolerance`); a large optimum (a design far from standing) needs
/// only the solver tolerance relative to itself.
fn stage_accuracy(stage: Stage, settings: &StaticsSettings) -> Accuracy {
    match stage {
        Stage::Tension | Stage::FrictionExcess { .. } => {
            let tol = settings.solver_tolerance.min(LP_TOLERANCE);
            Accuracy { feas: tol, gap_abs: tol, gap_rel: settings.solver_tolerance, pure_relative: true }
        }
        _ => Accuracy::uniform(settings.solver_tolerance),
    }
}

impl<'a> ComponentSolve<'a> {
    fn new(
        assembly: &'a Assembly,
        interfaces: &'a [Interface],
        comp: &'a Component,
        mu: f64,
        settings: &'a StaticsSettings,
    ) -> Self {
        let block_weight = |b: &BlockId| assembly.block(*b).mass() * assembly.gravity.norm();
        let weight: f64 = comp.blocks.iter().map(block_weight).sum();
        let lightest = comp.blocks.iter().map(block_weight).fold(f64::INFINITY, f64::min);
        Self {
            assembly,
            interfaces,
            comp,
            mu,
            settings,
            weights: (weight, lightest),
            tally: Tally::default(),
            warm_in: None,
            warm_out: None,
        }
    }

    /// The first few block names of the component, for messages.
    fn names(&self, limit: usize) -> String {
        let blocks = &self.comp.blocks;
        let mut s: Vec<&str> = blocks.iter().take(limit).map(|&b| self.assembly.block(b).name.as_str()).collect();
        if blocks.len() > limit {
            s.push("…");
        }
        s.join("', '")
    }

    /// A component without a solution. `residual` (N) is the equilibrium residual of the last
    /// iterate, or the unbalanced weight when nothing could hold the blocks.
    fn failed(&self, status: SolverStatus, message: String, residual: f64) -> ComponentOutcome {
        self.outcome(status, Some(message), residual)
    }

    /// The component's outcome with what its stages spent and no forces (no minima either:
    /// NaN); a solved component's forces and minima are set over it.
    fn outcome(&self, status: SolverStatus, message: Option<String>, residual: f64) -> ComponentOutcome {
        let t = &self.tally;
        ComponentOutcome {
            status,
            message,
            forces: Vec::new(),
            points: Vec::new(),
            min_tension: f64::NAN,
            min_excess: f64::NAN,
            residual,
            iterations: t.iterations,
            used_clarabel: t.used_clarabel,
            weight: self.weights.0,
            lightest: self.weights.1,
            crushing: None,
            assemble_seconds: t.assemble_seconds,
            solver_seconds: t.solver_seconds,
        }
    }

    /// The outcome of a component nothing can hold (no solve runs), if it is one.
    fn unsupported(&self) -> Option<ComponentOutcome> {
        let message = if self.comp.interfaces.is_empty() {
            format!(
                "block '{}' touches nothing: no interface holds it (check its position or the tolerances)",
                self.names(5)
            )
        } else if !self.comp.is_supported(self.assembly, self.interfaces) {
            format!("blocks '{}' touch no support or ground: the group has nothing to stand on", self.names(5))
        } else {
            return None;
        };
        Some(self.failed(SolverStatus::Unsupported, message, self.weights.0))
    }

    /// The component's system, strict or relaxed (its build time counted as assembly).
    fn system(&mut self, relaxed: bool) -> System {
        let t = Instant::now();
        let sys =
            System::new(self.assembly, self.interfaces, self.comp, self.mu, self.settings.friction_model, relaxed);
        self.tally.assemble_seconds += t.elapsed().as_secs_f64();
        sys
    }

    /// Builds and solves one stage of `sys`; the outcome's x in the system's layout.
    fn stage(&mut self, sys: &System, stage: Stage) -> QpOutcome {
        self.stage_to(sys, stage, stage_accuracy(stage, self.settings))
    }

    /// [`Self::stage`] to the accuracy `acc`.
    fn stage_to(&mut self, sys: &System, stage: Stage, acc: Accuracy) -> QpOutcome {
        let t = Instant::now();
        let cp = contact_problem(sys, stage, self.settings);
        let built = t.elapsed().as_secs_f64();
        let s = self.settings;
        let warm = match self.warm_in {
            _ if !s.warm_start || stage != Stage::Strict => Warm::Off,
            Some(from) => Warm::From(from),
            None => Warm::Keep,
        };
        let (mut out, kept) = run_warm(&cp, s.backend, acc, s.max_iterations, warm);
        if kept.is_some() {
            self.warm_out = kept;
        }
        out.x = sys.stage_values(&cp, &out.x);
        self.tally.iterations += out.iterations;
        self.tally.assemble_seconds += built + out.convert_seconds;
        self.tally.solver_seconds += out.solver_seconds;
        self.tally.used_clarabel |= out.backend == Backend::Clarabel;
        out
    }

    /// Most designs being checked stand: the strict problem (compression only, friction within
    /// μ) first. Solved ⇒ minimum tension and excess are exactly 0, and this is the
    /// distribution. `None` (infeasible, or trouble) sends the component to the relaxed stages —
    /// straight away when the caller expects the design not to stand.
    fn strict_first(&mut self) -> Option<Solution> {
        if self.settings.first_stage == FirstStage::Relaxed {
            return None;
        }
        self.strict()
    }

    /// Whether a relaxed-first answer needs the strict QP to confirm it: it misses standing by
    /// less than [`CONFIRM_BELOW`] of the weight. The LPs' minima are read at feasible states
    /// ([`System::make_feasible`]), upper bounds whose rows an interior point met only to its
    /// tolerance: over thousands of points such a bound can pass the floor where the true
    /// minimum is 0. The strict QP decides such a case exactly as the strict-first path does,
    /// so both paths give one verdict.
    fn to_confirm(&self, s: &Solution) -> bool {
        let (weight, lightest) = self.weights;
        let threshold = stand_threshold(self.settings, lightest, weight) / s.sys.force_scale;
        self.settings.first_stage == FirstStage::Relaxed
            && s.tension.max(s.excess) > threshold
            && s.tension.max(s.excess) <= CONFIRM_BELOW
    }

    /// The strict problem; `Some` when it stands by it (see [`Self::strict_first`]).
    ///
    /// Solved to its tolerance, the QP's forces may still exceed friction by a little at many
    /// points: it stands only if that excess (an upper bound of the minimum) is within the stand
    /// tolerance, so that both ways in give the same verdict. Each friction row may miss by up
    /// to the feasibility tolerance, and over thousands of points that sum can pass the
    /// threshold of a design that stands. Such a near miss (below [`CONFIRM_BELOW`] of the
    /// weight) is solved again to the LPs' feasibility, 1e-10.
    fn strict(&mut self) -> Option<Solution> {
        let sys = self.system(false);
        let (weight, lightest) = self.weights;
        let threshold = stand_threshold(self.settings, lightest, weight);
        let violation = |out: &QpOutcome| sys.friction_violation(&out.x) * sys.force_scale;
        let mut out = self.stage(&sys, Stage::Strict);
        let missed = violation(&out);
        if out.status.solved() && missed > threshold && missed <= CONFIRM_BELOW * weight {
            let tol = self.settings.solver_tolerance;
            let tighter = Accuracy { feas: tol.min(LP_TOLERANCE), ..Accuracy::uniform(tol) };
            out = self.stage_to(&sys, Stage::Strict, tighter);
        }
        let within = violation(&out) <= threshold;
        (out.status.solved() && within).then_some(Solution { sys, out, tension: 0.0, excess: 0.0 })
    }

    /// The relaxed stages: the exact minimum friction excess (and minimum tension when it is
    /// needed), then the distribution QP. `Err` is the outcome of a component whose LPs failed.
    fn relaxed(&mut self) -> Result<Solution, Box<ComponentOutcome>> {
        let sys = self.system(true);
        let (best, tension, excess) = self.minimum_excess(&sys)?;
        // The distribution QP only refines the forces: if it fails (or is not asked for), the
        // last LP's solution is an equilibrium with the same minimum tension and excess.
        let out = if self.settings.distribution {
            let c = self.stage(&sys, Stage::Distribution { tension, excess });
            if c.status.solved() { c } else { best }
        } else {
            best
        };
        Ok(Solution { sys, out, tension, excess })
    }

    /// The exact-penalty friction-excess LP first: when its optimum needs no tension, it is the
    /// whole answer (T* = 0 below the LPs' resolution, F* its Σ s). Otherwise the
    /// minimum-tension LP gives T*, and the penalty LP's answer stands if its tension is T*; if
    /// not, M was too small: ×100, and past its largest the budget form. Returns the chosen
    /// LP's outcome (made feasible: [`System::make_feasible`]), T* and F*.
    fn minimum_excess(&mut self, sys: &System) -> Result<(QpOutcome, f64, f64), Box<ComponentOutcome>> {
        let mut penalty = EXCESS_PENALTY.0;
        let mut tension: Option<f64> = None;
        // A penalty LP's answer within T*'s budget whose Σ s was too small to tell from none:
        // a feasible state, so an upper bound the budget form must beat.
        let mut within: Option<(QpOutcome, f64)> = None;
        let (best, excess) = loop {
            let mut out = self.stage(sys, Stage::FrictionExcess { tension: tension.unwrap_or(0.0), penalty });
            if !out.status.solved() {
                if let Some(found) = within.take() {
                    break found;
                }
                let msg = match out.status {
                    SolverStatus::Infeasible => "no equilibrium exists even with tension and unlimited friction \
                                                 (some block cannot be held in some direction)"
                        .to_string(),
                    s => format!("the friction-excess LP ended with status {s:?}"),
                };
                return Err(Box::new(self.failed(out.status, msg, sys.residual(&out.x) * sys.force_scale)));
            }
            let (used, slack) = sys.make_feasible(&mut out.x);
            if tension.is_none() && used <= tension_budget(0.0) {
                tension = Some(0.0);
                break (out, slack);
            }
            let t = match tension {
                Some(t) => t,
                None => *tension.insert(self.minimum_tension(sys)?),
            };
            if penalty == 0.0 {
                // Both are feasible states within the budget: the smaller excess is nearer F*.
                break match within {
                    Some((w, ws)) if ws <= slack => (w, ws),
                    _ => (out, slack),
                };
            }
            if used <= tension_budget(t) {
                // Its Σ s is resolved to ~1e-9 of the whole objective M T* + Σ s: when that
                // cannot tell a small excess from none, the budget form decides (it is well
                // behaved when the excess is small; its trouble was large ones).
                if slack >= 1e-6 * (penalty * t).max(1.0) {
                    break (out, slack);
                }
                within = Some((out, slack));
                penalty = 0.0;
                continue;
            }
            // M was too small: the optimum traded friction for tension.
            penalty = if penalty < EXCESS_PENALTY.1 { penalty * 100.0 } else { 0.0 };
        };
        Ok((best, tension.unwrap_or(0.0), excess))
    }

    /// T*: the minimum-tension LP's optimum (non-dimensional), at its solution made feasible
    /// ([`System::make_feasible`]).
    fn minimum_tension(&mut self, sys: &System) -> Result<f64, Box<ComponentOutcome>> {
        let mut out = self.stage(sys, Stage::Tension);
        if !out.status.solved() {
            let msg = format!("the minimum-tension LP ended with status {:?}", out.status);
            return Err(Box::new(self.failed(out.status, msg, sys.residual(&out.x) * sys.force_scale)));
        }
        Ok(sys.make_feasible(&mut out.x).0)
    }

    /// With a compressive strength σ_c, on a component that stands by compression and
    /// friction: the least strength σ* its equilibria need (the `Strength` stage, on
    /// clarabel) and its governing interface. When σ* ≤ σ_c but the forces found ask more of
    /// some interface than σ_c, `solution` becomes the distribution over the equilibria the
    /// stone carries (the `Capped` stage; the least-strength equilibrium itself when that solve
    /// fails), so the forces drawn are ones it can carry.
    fn crushing(&mut self, solution: &mut Solution) -> Option<(f64, usize)> {
        let sigma = self.settings.strength?;
        let (weight, lightest) = self.weights;
        let threshold = stand_threshold(self.settings, lightest, weight) / solution.sys.force_scale;
        if solution.tension.max(solution.excess) > threshold {
            return None;
        }
        // The stress blocks are the geometry's, shared by the solution's system and the strict one.
        let blocks = solution.sys.geometry.stress_blocks();
        let own = solution.sys.stress_demands(&blocks, &solution.out.x).into_iter().fold(0.0, f64::max);
        let mut sys = self.system(false);
        sys.stress = blocks;
        let unit = sys.strength_scale(self.assembly.scale);
        let least = self.stage(&sys, Stage::Strength);
        if !least.status.solved() {
            return None;
        }
        let demands = sys.stress_demands(&sys.stress, &least.x);
        let (governing, needed) =
            demands.iter().enumerate().fold((0, 0.0), |best, (k, &d)| if d > best.1 { (k, d) } else { best });
        if needed <= sigma * unit && own > sigma * unit {
            let capped = self.stage(&sys, Stage::Capped { strength: sigma * unit });
            // Should that solve fail, the least-strength equilibrium is one the stone carries.
            let carried = if capped.status.solved() { capped } else { least };
            *solution = Solution { sys, out: carried, tension: 0.0, excess: 0.0 };
        }
        Some((needed / unit, governing))
    }

    /// Polishes the equilibrium residual and scales the solution back to N.
    fn finish(self, solution: Solution) -> ComponentOutcome {
        let Solution { sys, mut out, tension, excess } = solution;
        sys.polish(&mut out.x);
        let fs = sys.force_scale;
        let residual = sys.residual(&out.x) * fs;
        let status = out.status;
        let forces = (0..sys.points.len())
            .map(|i| [Var::CnPos, Var::CnNeg, Var::Cu, Var::Cv, Var::Slack].map(|v| sys.value(&out.x, i, v) * fs))
            .collect();
        let message = (!status.solved()).then(|| format!("the force-distribution QP ended with status {status:?}"));
        ComponentOutcome {
            forces,
            points: sys.points,
            min_tension: tension * fs,
            min_excess: excess * fs,
            ..self.outcome(status, message, residual)
        }
    }
}

/// Solves every component; on two threads when there are several and the work is large.
pub fn solve_components(
    assembly: &Assembly,
    interfaces: &[Interface],
    comps: &[Component],
    mu: f64,
    settings: &StaticsSettings,
    warm: &[Option<&WarmStart>],
) -> Vec<(ComponentOutcome, Option<WarmStart>)> {
    let work = |c: &Component| c.interfaces.iter().map(|&k| interfaces[k].polygon.len()).sum::<usize>();
    let total: usize = comps.iter().map(work).sum();
    let solve = |i: usize| solve_component(assembly, interfaces, &comps[i], mu, settings, warm[i]);
    // Below ~500 force points a solve takes a few ms: a thread would cost more than it saves.
    if !settings.parallel || comps.len() < 2 || total < 500 {
        return (0..comps.len()).map(solve).collect();
    }
    // Greedy split of the components into two halves of about equal work; each component's
    // solve is independent of the thread it runs on, so the result is deterministic.
    let mut order: Vec<usize> = (0..comps.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(work(&comps[i])));
    let (mut left, mut right, mut lw, mut rw) = (Vec::new(), Vec::new(), 0, 0);
    for i in order {
        if lw <= rw {
            lw += work(&comps[i]);
            left.push(i);
        } else {
            rw += work(&comps[i]);
            right.push(i);
        }
    }
    // Each thread solves serially: the two already use both cores.
    let serial = StaticsSettings { parallel: false, ..settings.clone() };
    let solve = |i: usize| solve_component(assembly, interfaces, &comps[i], mu, &serial, warm[i]);
    let mut out: Vec<Option<(ComponentOutcome, Option<WarmStart>)>> = vec![None; comps.len()];
    let right_results = std::thread::scope(|s| {
        let handle = s.spawn(|| right.iter().map(|&i| (i, solve(i))).collect::<Vec<_>>());
        for &i in &left {
            out[i] = Some(solve(i));
        }
        handle.join()
    });
    match right_results {
        Ok(results) => {
            for (i, r) in results {
                out[i] = Some(r);
            }
        }
        Err(_) => {
            // A panic inside the solver thread: solve those components again here, serially.
            for &i in &right {
                out[i] = Some(solve(i));
            }
        }
    }
    out.into_iter().map(|o| o.expect("every component was solved")).collect()
}

/// The graded answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Compression and friction within the limits suffice.
    Stands,
    /// Needs tension somewhere (no compression-only equilibrium, even with unlimited friction).
    NeedsTension,
    /// Compression-only equilibrium exists, but only with more friction than μ allows.
    NeedsFriction,
    /// Both.
    NeedsTensionAndFriction,
    /// Compression and friction within the limits suffice, but some interface needs more
    /// compressive strength than the material has.
    Crushes,
    /// Some block cannot be held at all (it touches nothing, or its group has no support).
    Unsupported,
    /// The solver did not converge: no verdict.
    Unresolved,
}

impl Verdict {
    /// The verdict in words, lower case ("stands", "needs tension", …).
    pub fn words(self) -> &'static str {
        match self {
            Verdict::Stands => "stands",
            Verdict::NeedsTension => "needs tension",
            Verdict::NeedsFriction => "needs more friction",
            Verdict::NeedsTensionAndFriction => "needs tension and friction",
            Verdict::Crushes => "crushes",
            Verdict::Unsupported => "unsupported",
            Verdict::Unresolved => "solver trouble",
        }
    }
}

/// A needed strength counts as above the material's beyond this fraction of it: the strength
/// SOCP is solved to the solver tolerance (1e-8), so a design exactly at its strength is not
/// called crushed by round-off.
pub const CRUSH_TOLERANCE: f64 = 1e-6;

/// Below this fraction of a component's weight a minimum tension or excess is not resolved
/// by the LPs (solved to 1e-10): it counts as zero.
pub const STAND_FLOOR: f64 = 1e-8;

/// The minimum tension or friction excess (N) up to which a component of `weight` whose
/// lightest block weighs `lightest` (N) counts as standing (see `stand_tolerance`).
pub fn stand_threshold(settings: &StaticsSettings, lightest: f64, weight: f64) -> f64 {
    (settings.stand_tolerance * lightest).max(STAND_FLOOR * weight)
}

/// The verdict rule: the worst status of any component and, when every component solved, what
/// the design needs — tension where some component's minimum tension is above its
/// [`stand_threshold`], more friction where its minimum friction excess is.
pub fn verdict(outcomes: &[ComponentOutcome], settings: &StaticsSettings) -> (SolverStatus, Verdict) {
    let mut status = SolverStatus::Solved;
    let (mut needs_tension, mut needs_friction, mut crushes) = (false, false, false);
    for out in outcomes {
        status = status.max(out.status);
        let threshold = stand_threshold(settings, out.lightest, out.weight);
        needs_tension |= out.min_tension > threshold;
        needs_friction |= out.min_excess > threshold;
        if let (Some(strength), Some((needed, _))) = (settings.strength, out.crushing) {
            crushes |= needed > strength * (1.0 + CRUSH_TOLERANCE);
        }
    }
    let verdict = match status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => match (needs_tension, needs_friction) {
            (false, false) if crushes => Verdict::Crushes,
            (false, false) => Verdict::Stands,
            (true, false) => Verdict::NeedsTension,
            (false, true) => Verdict::NeedsFriction,
            (true, true) => Verdict::NeedsTensionAndFriction,
        },
        SolverStatus::Unsupported => Verdict::Unsupported,
        _ => Verdict::Unresolved,
    };
    (status, verdict)
}
