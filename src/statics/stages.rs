//! The stages of one component's solve (module docs of [`crate::statics`]): the strict QP,
//! and when it has no solution the exact minimum-tension and minimum-excess LPs and the
//! distribution QP; and the solve of all components, on two threads when it pays.

use super::assemble::{Stage, System, Var, contact_problem, tension_budget};
use super::components::Component;
use super::result::{SolverStatus, stand_threshold};
use super::settings::{FirstStage, StaticsSettings};
use super::solve::{Accuracy, run};
use crate::interfaces::Interface;
use crate::model::Assembly;
use std::time::Instant;

/// Interior-point tolerance of the minimum-tension and minimum-excess LPs.
pub const LP_TOLERANCE: f64 = 1e-10;

/// First weight M of Σ c_n⁻ in the exact-penalty friction-excess LP `M Σ c_n⁻ + Σ s`, and the
/// largest tried (×100 each time the tension comes back above its minimum T*).
///
/// Why a penalty and not the budget Σ c_n⁻ ≤ T*: in the dual (a mechanism), M bounds how fast
/// a joint may open; with the budget (or with c_n⁻ pinned at 0) the openings are unbounded,
/// the dual optimal face with them, and the interior-point method drifts towards it — 40–190
/// iterations on the Armadillo's partial shells, often ending at reduced accuracy with a
/// wrong optimum (2.3e7 W where the optimum is 4.9 W). The penalty form takes 22–50. Its
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
    pub points: Vec<super::assemble::ForcePoint>,
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
    /// Seconds building the problems (layout, rows, matrices) and inside clarabel.
    pub assemble_seconds: f64,
    pub solver_seconds: f64,
}

/// A component without a solution. `residual` (N) is the equilibrium residual of the last
/// iterate, or the unbalanced weight when nothing could hold the blocks.
fn failed(
    status: SolverStatus,
    message: String,
    (weight, lightest): (f64, f64),
    residual: f64,
    iterations: u32,
    times: (f64, f64, bool),
) -> ComponentOutcome {
    ComponentOutcome {
        status,
        message: Some(message),
        forces: Vec::new(),
        points: Vec::new(),
        min_tension: f64::NAN,
        min_excess: f64::NAN,
        residual,
        iterations,
        used_clarabel: times.2,
        weight,
        lightest,
        assemble_seconds: times.0,
        solver_seconds: times.1,
    }
}

/// Solves one component: the strict QP, and if it has no solution the relaxed stages.
pub fn solve_component(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    mu: f64,
    settings: &StaticsSettings,
) -> ComponentOutcome {
    let names = |limit: usize| -> String {
        let mut s: Vec<&str> = comp.blocks.iter().take(limit).map(|&b| assembly.block(b).name.as_str()).collect();
        if comp.blocks.len() > limit {
            s.push("…");
        }
        s.join("', '")
    };
    let block_weight = |b: &crate::model::BlockId| assembly.block(*b).mass() * assembly.gravity.norm();
    let weight: f64 = comp.blocks.iter().map(block_weight).sum();
    let lightest = comp.blocks.iter().map(block_weight).fold(f64::INFINITY, f64::min);
    let weights = (weight, lightest);
    if comp.interfaces.is_empty() {
        return failed(
            SolverStatus::Unsupported,
            format!(
                "block '{}' touches nothing: no interface holds it (check its position or the tolerances)",
                names(5)
            ),
            weights,
            weight,
            0,
            (0.0, 0.0, false),
        );
    }
    if !comp.is_supported(assembly, interfaces) {
        return failed(
            SolverStatus::Unsupported,
            format!("blocks '{}' touch no support or ground: the group has nothing to stand on", names(5)),
            weights,
            weight,
            0,
            (0.0, 0.0, false),
        );
    }
    let ok = |s: SolverStatus| matches!(s, SolverStatus::Solved | SolverStatus::AlmostSolved);
    // Iterations, assembly seconds and solver seconds over all stages.
    let mut tally = (0u32, 0.0f64, 0.0f64, false);
    let stage = |sys: &System, st: Stage, tally: &mut (u32, f64, f64, bool)| {
        let t = Instant::now();
        let cp = contact_problem(sys, st, settings);
        let built = t.elapsed().as_secs_f64();
        // The LPs decide the verdict: solve them to 1e-10 (absolute) so that their optimum
        // resolves a tension or friction excess of 1e-8 W near zero (see
        // `StaticsSettings::stand_tolerance`); a large optimum (a design far from standing)
        // needs only the solver tolerance relative to itself.
        let acc = match st {
            Stage::Tension | Stage::FrictionExcess { .. } => {
                let tol = settings.solver_tolerance.min(LP_TOLERANCE);
                Accuracy { feas: tol, gap_abs: tol, gap_rel: settings.solver_tolerance, pure_relative: true }
            }
            _ => Accuracy::uniform(settings.solver_tolerance),
        };
        let mut out = run(&cp, settings, acc);
        out.x = sys.stage_values(&cp, &out.x);
        tally.0 += out.iterations;
        tally.1 += built + out.convert_seconds;
        tally.2 += out.solver_seconds;
        tally.3 |= out.backend == super::settings::Backend::Clarabel;
        out
    };
    let system = |relaxed: bool, tally: &mut (u32, f64, f64, bool)| {
        let t = Instant::now();
        let sys = System::new(assembly, interfaces, comp, mu, settings.friction_model, relaxed);
        tally.1 += t.elapsed().as_secs_f64();
        sys
    };
    // Most designs being checked stand: try the strict problem (compression only, friction
    // within μ) first. Solved ⇒ minimum tension and excess are exactly 0, and this is the
    // distribution. Otherwise (infeasible, or trouble) take the relaxed stages — straight away
    // when the caller expects the design not to stand.
    let first = match settings.first_stage {
        FirstStage::Strict => {
            let strict = system(false, &mut tally);
            let first = stage(&strict, Stage::Strict, &mut tally);
            // Solved to its tolerance, the QP's forces may still exceed friction by a little
            // at many points: it stands only if that excess (an upper bound of the minimum)
            // is within the stand tolerance, so that both ways in give the same verdict.
            let within =
                strict.friction_violation(&first.x) * strict.force_scale <= stand_threshold(settings, lightest, weight);
            (ok(first.status) && within).then_some((strict, first))
        }
        FirstStage::Relaxed => None,
    };
    let (sys, c, tension, excess) = if let Some((strict, first)) = first {
        (strict, first, 0.0, 0.0)
    } else {
        let sys = system(true, &mut tally);
        let sum = |x: &[f64], var: Var| (0..sys.points.len()).map(|i| sys.value(x, i, var)).sum::<f64>();
        // The exact-penalty friction-excess LP first: when its optimum needs no tension, it is
        // the whole answer (T* = 0 below the LPs' resolution, F* its Σ s). Otherwise the
        // minimum-tension LP gives T*, and the penalty LP's answer stands if its tension is
        // T*; if not, M was too small: ×100, and past its largest the budget form.
        let mut penalty = EXCESS_PENALTY.0;
        let mut tension: Option<f64> = None;
        let best = loop {
            let out = stage(&sys, Stage::FrictionExcess { tension: tension.unwrap_or(0.0), penalty }, &mut tally);
            if !ok(out.status) {
                let msg = match out.status {
                    SolverStatus::Infeasible => "no equilibrium exists even with tension and unlimited friction \
                                                 (some block cannot be held in some direction)"
                        .to_string(),
                    s => format!("the friction-excess LP ended with status {s:?}"),
                };
                let residual = sys.residual(&out.x) * sys.force_scale;
                return failed(out.status, msg, weights, residual, tally.0, (tally.1, tally.2, tally.3));
            }
            let used = sum(&out.x, Var::CnNeg);
            if tension.is_none() && used <= tension_budget(0.0) {
                tension = Some(0.0);
                break out;
            }
            let t = match tension {
                Some(t) => t,
                None => {
                    let b1 = stage(&sys, Stage::Tension, &mut tally);
                    if !ok(b1.status) {
                        let msg = format!("the minimum-tension LP ended with status {:?}", b1.status);
                        let residual = sys.residual(&b1.x) * sys.force_scale;
                        return failed(b1.status, msg, weights, residual, tally.0, (tally.1, tally.2, tally.3));
                    }
                    *tension.insert(b1.objective.max(0.0))
                }
            };
            if penalty == 0.0 {
                break out;
            }
            if used <= tension_budget(t) {
                // Its Σ s is resolved to ~1e-9 of the whole objective M T* + Σ s: when that
                // cannot tell a small excess from none, the budget form decides (it is well
                // behaved when the excess is small; its trouble was large ones).
                if sum(&out.x, Var::Slack) >= 1e-6 * (penalty * t).max(1.0) {
                    break out;
                }
                penalty = 0.0;
                continue;
            }
            // M was too small: the optimum traded friction for tension.
            penalty = if penalty < EXCESS_PENALTY.1 { penalty * 100.0 } else { 0.0 };
        };
        let tension = tension.unwrap_or(0.0);
        let excess = sum(&best.x, Var::Slack).max(0.0);
        // The distribution QP only refines the forces: if it fails (or is not asked for), the
        // last LP's solution is an equilibrium with the same minimum tension and excess.
        let c = if settings.distribution {
            let c = stage(&sys, Stage::Distribution { tension, excess }, &mut tally);
            if ok(c.status) { c } else { best }
        } else {
            best
        };
        (sys, c, tension, excess)
    };
    let mut c = c;
    sys.polish(&mut c.x);
    let residual = sys.residual(&c.x) * sys.force_scale;
    let status = c.status;
    let fs = sys.force_scale;
    let forces = (0..sys.points.len())
        .map(|i| [Var::CnPos, Var::CnNeg, Var::Cu, Var::Cv, Var::Slack].map(|v| sys.value(&c.x, i, v) * fs))
        .collect();
    ComponentOutcome {
        status,
        message: (!ok(status)).then(|| format!("the force-distribution QP ended with status {status:?}")),
        forces,
        points: sys.points,
        min_tension: tension * fs,
        min_excess: excess * fs,
        residual,
        iterations: tally.0,
        used_clarabel: tally.3,
        weight,
        lightest,
        assemble_seconds: tally.1,
        solver_seconds: tally.2,
    }
}

/// Solves every component; on two threads when there are several and the work is large.
pub fn solve_components(
    assembly: &Assembly,
    interfaces: &[Interface],
    comps: &[Component],
    mu: f64,
    settings: &StaticsSettings,
) -> Vec<ComponentOutcome> {
    let work = |c: &Component| c.interfaces.iter().map(|&k| interfaces[k].polygon.len()).sum::<usize>();
    let total: usize = comps.iter().map(work).sum();
    let solve = |c: &Component| solve_component(assembly, interfaces, c, mu, settings);
    // Below ~500 force points a solve takes a few ms: a thread would cost more than it saves.
    if !settings.parallel || comps.len() < 2 || total < 500 {
        return comps.iter().map(solve).collect();
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
    let mut out: Vec<Option<ComponentOutcome>> = vec![None; comps.len()];
    let right_results = std::thread::scope(|s| {
        let handle = s.spawn(|| right.iter().map(|&i| (i, solve(&comps[i]))).collect::<Vec<_>>());
        for &i in &left {
            out[i] = Some(solve(&comps[i]));
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
                out[i] = Some(solve(&comps[i]));
            }
        }
    }
    out.into_iter().map(|o| o.expect("every component was solved")).collect()
}
