//! The stages of one component's solve (module docs of [`crate::statics`]): the strict QP,
//! and when it has no solution the exact minimum-tension and minimum-excess LPs and the
//! distribution QP; and the solve of all components, on two threads when it pays.

use super::assemble::{Stage, System, Var, contact_problem};
use super::components::Component;
use super::result::SolverStatus;
use super::settings::StaticsSettings;
use super::solve::run;
use crate::interfaces::Interface;
use crate::model::Assembly;
use std::time::Instant;

/// Interior-point tolerance of the minimum-tension and minimum-excess LPs.
pub const LP_TOLERANCE: f64 = 1e-10;

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
        // The LPs decide the verdict: solve them to 1e-10 so that their optimum resolves a
        // tension or friction excess of 1e-8 W (see `StaticsSettings::stand_tolerance`).
        let tol = match st {
            Stage::Tension | Stage::FrictionExcess { .. } => settings.solver_tolerance.min(LP_TOLERANCE),
            _ => settings.solver_tolerance,
        };
        let mut out = run(&cp, settings, tol);
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
    // distribution. Otherwise (infeasible, or trouble) take the relaxed stages.
    let strict = system(false, &mut tally);
    let first = stage(&strict, Stage::Strict, &mut tally);
    let (sys, c, tension, excess) = if ok(first.status) {
        (strict, first, 0.0, 0.0)
    } else {
        let sys = system(true, &mut tally);
        let b1 = stage(&sys, Stage::Tension, &mut tally);
        if !ok(b1.status) {
            let msg = format!("the minimum-tension LP ended with status {:?}", b1.status);
            let residual = sys.residual(&b1.x) * sys.force_scale;
            return failed(b1.status, msg, weights, residual, tally.0, (tally.1, tally.2, tally.3));
        }
        let tension = b1.objective.max(0.0);
        let mut excess = 0.0;
        let mut best = b1;
        if sys.layout.friction {
            let b2 = stage(&sys, Stage::FrictionExcess { tension }, &mut tally);
            if !ok(b2.status) {
                let msg = format!("the friction-excess LP ended with status {:?}", b2.status);
                let residual = sys.residual(&b2.x) * sys.force_scale;
                return failed(b2.status, msg, weights, residual, tally.0, (tally.1, tally.2, tally.3));
            }
            excess = b2.objective.max(0.0);
            best = b2;
        }
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
