//! The text report of an analysis, as `voussoir analyze` prints it (the JSON report is
//! [`super::json`]): the verdict first, then the graded numbers, the solver and timings, the
//! worst interfaces; with a drop test, its verdict beside the statics' and whether they agree.

use crate::dynamics::DropResult;
use crate::model::Warning;
use crate::pipeline::Analysis;
use crate::statics::{FrictionModel, InterfaceResult, Verdict};

/// Warnings printed in full; the JSON report lists them all.
const SHOWN_WARNINGS: usize = 5;

/// The verdict as the first line of a report says it.
pub fn headline(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Stands => "STANDS: compression and friction suffice",
        Verdict::NeedsTension => "DOES NOT STAND: needs tension",
        Verdict::NeedsFriction => "DOES NOT STAND: needs more friction",
        Verdict::NeedsTensionAndFriction => "DOES NOT STAND: needs tension and more friction",
        Verdict::Crushes => "DOES NOT STAND: the stone crushes",
        Verdict::Unsupported => "DOES NOT STAND: something touches no support",
        Verdict::Unresolved => "UNRESOLVED: the solver did not converge",
    }
}

/// Human-readable summary: verdict first, then the graded numbers, then the worst interfaces.
pub fn summary(analysis: &Analysis, worst: usize) -> String {
    use std::fmt::Write;
    let a = &analysis.assembly;
    let s = &analysis.statics;
    let mut o = String::new();
    let verdict = headline(s.verdict);
    let supports = a.blocks.iter().filter(|b| b.support).count();
    let _ = writeln!(o, "{verdict}");
    let _ = writeln!(
        o,
        "  scene '{}': {} blocks ({} supports{}), {} interfaces, {} component(s)",
        a.name,
        a.blocks.len(),
        supports,
        if a.ground { ", ground plane" } else { "" },
        analysis.interfaces.len(),
        s.components
    );
    let _ = writeln!(
        o,
        "  free weight W = {:.6e} N, μ = {:.4} ({})",
        s.free_weight, s.friction_coefficient, s.friction_model
    );
    let _ = writeln!(o, "  minimum tension         {:.3e} W", s.tension_ratio);
    let _ = writeln!(o, "  minimum friction excess {:.3e} W", s.friction_excess_ratio);
    let _ = write!(o, "  max friction use        {:.1} % of μ·compression", 100.0 * s.max_friction_utilization);
    let _ = match s.friction_model {
        FrictionModel::Cone => writeln!(o),
        m => writeln!(o, " (|f_t| as a circle; {m} allows up to {:.1} %)", 100.0 * m.max_utilization()),
    };
    if let Some(c) = &s.crushing {
        let _ = writeln!(
            o,
            "  crushing: needs {:.4e} Pa of σ_c = {:.4e} Pa ({:.1} %), at {} → {} (rectangular stress block)",
            c.needed,
            c.strength,
            100.0 * c.utilization,
            c.a,
            c.b
        );
    }
    solver_lines(&mut o, analysis);
    warning_lines(&mut o, &a.warnings);
    worst_lines(&mut o, &s.interfaces, worst);
    o
}

/// The solver's line, its messages and the pipeline's timings.
fn solver_lines(o: &mut String, analysis: &Analysis) {
    use std::fmt::Write;
    let s = &analysis.statics;
    let _ = writeln!(
        o,
        "  solver: {} — {:?}, {} iterations, residual {:.2e} W",
        s.solver.backend,
        s.solver.status,
        s.solver.iterations,
        s.solver.residual / s.free_weight
    );
    for m in &s.solver.messages {
        let _ = writeln!(o, "  ! {m}");
    }
    let t = &analysis.timings;
    let _ = writeln!(
        o,
        "  time: validate {:.1} ms, detect {:.1} ms, assemble {:.1} ms, solve {:.1} ms (total {:.1} ms)",
        1e3 * t.validate,
        1e3 * t.detect,
        1e3 * t.assemble,
        1e3 * t.solve,
        1e3 * t.total
    );
}

/// The assembly's first warnings and how many more the JSON report has.
fn warning_lines(o: &mut String, warnings: &[Warning]) {
    use std::fmt::Write;
    // Overlaps first (they can make the statics wrong), then unknown keys and repairs.
    for w in warnings.iter().take(SHOWN_WARNINGS) {
        let _ = writeln!(o, "  warning: {w}");
    }
    if warnings.len() > SHOWN_WARNINGS {
        let _ = writeln!(o, "  … {} more warning(s) in the JSON report", warnings.len() - SHOWN_WARNINGS);
    }
}

/// The `worst` interfaces, by tension, then friction excess, then friction use.
fn worst_lines(o: &mut String, interfaces: &[InterfaceResult], worst: usize) {
    use std::fmt::Write;
    let mut ranked: Vec<_> = interfaces.iter().collect();
    ranked.sort_by(|x, y| {
        (y.tension, y.friction_excess, y.friction_utilization)
            .partial_cmp(&(x.tension, x.friction_excess, x.friction_utilization))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    if worst > 0 && !ranked.is_empty() {
        let _ = writeln!(o, "  worst interfaces (a → b: net normal, tension, friction use):");
        for r in ranked.iter().take(worst) {
            let _ = writeln!(
                o,
                "    {} → {}: {:.4e} N, tension {:.3e} N, friction {:.1} %",
                r.a,
                r.b,
                r.normal_force,
                r.tension,
                100.0 * r.friction_utilization
            );
        }
    }
}

/// The drop test beside the statics, with the disagreement flagged.
pub fn side_by_side(analysis: &Analysis, d: &DropResult) -> String {
    let s = &analysis.statics;
    let word = |b: bool| if b { "stands" } else { "falls" };
    let mut o = format!(
        "drop test ({}, {:.2} s simulated in {:.2} s, {} steps): {}\n  largest drift {:.3e} of the block size, \
         largest rotation {:.3e} rad{}\n",
        d.engine,
        d.simulated_s,
        d.wall_s,
        d.steps,
        word(d.stands),
        d.max_drift,
        d.max_rotation,
        d.worst_block.as_ref().map(|b| format!(" (worst: {b})")).unwrap_or_default()
    );
    if let Some(e) = &d.exact {
        o += &exact_engine(e);
    }
    if d.max_volume_error > 0.0 {
        o += &format!(
            "  colliders differ from the blocks by up to {:.2} % of a block's volume (hulls of curved or notched blocks, decompositions)\n",
            100.0 * d.max_volume_error
        );
    }
    if let Some([a, b]) = &d.initial_overlap_blocks {
        o += &format!(
            "  blocks {a} and {b} start overlapping by {:.2} % of a block's size (the input blocks overlap; rapier pushes them apart first, which counts as drift)\n",
            100.0 * d.max_initial_overlap
        );
    }
    o += &format!(
        "statics {} (tension {:.3e} W, friction excess {:.3e} W, utilisation {:.3}) | drop test {}: {}\n",
        word(s.stands),
        s.tension_ratio,
        s.friction_excess_ratio,
        s.max_friction_utilization,
        word(d.stands),
        disagreement(s.stands, d)
    );
    o
}

/// The exact engine's account: its solves, their status, the deepest overlap and the energy
/// balance.
fn exact_engine(e: &crate::dynamics::ExactStats) -> String {
    let b = &e.energy;
    let mut o = format!(
        "  exact contacts ({} Coulomb, {}): {} steps by their contacts' states, {} solves ({} without clarabel), {} iterations, up to {} round(s) a step{}{}; {:?}, residual {:.1e} N\n",
        e.coulomb,
        e.friction_model,
        e.state_steps,
        e.solves,
        e.structured_solves,
        e.iterations,
        e.max_rounds,
        if e.unsettled_steps > 0 { format!(" ({} steps unsettled)", e.unsettled_steps) } else { String::new() },
        if e.failed_steps > 0 {
            format!(" ({} steps failed: the motion after them is not the dynamics')", e.failed_steps)
        } else {
            String::new()
        },
        e.status,
        e.residual
    );
    o += &format!(
        "  deepest overlap {:.2e} of the block size; energy: loads' work {:.4e} J = kinetic {:.4e} + contacts {:.4e} + impacts {:.4e} (error {:.1e})\n",
        e.max_penetration, b.load_work, b.kinetic, b.contact, b.impact, b.error
    );
    o
}

/// The kinematic check beside the statics: both verdicts, whether they agree, and when it
/// fails, how (the mechanism's moving blocks and what its joints do).
pub fn kinematic(analysis: &Analysis, k: &crate::stability::kinematic::Kinematic) -> String {
    use crate::stability::JointState;
    use crate::stability::kinematic::KinematicVerdict;
    use std::fmt::Write;
    let mut o = String::new();
    let word = match k.verdict {
        KinematicVerdict::Stands => "stands",
        KinematicVerdict::Fails => "falls",
        KinematicVerdict::Undecided => "undecided",
    };
    let _ = writeln!(
        o,
        "kinematic check (released from rest, no squeeze): {word}; {} round(s), {} iterations, {:.1} ms in the solver",
        k.rounds,
        k.iterations,
        1e3 * k.solver_seconds
    );
    if let Some(m) = &k.mechanism {
        let count = |state| m.interfaces.iter().filter(|i| i.state == state).count();
        let _ = writeln!(
            o,
            "  {} block(s) start to move (largest acceleration {:.3} g); interfaces {} hinging, {} opening, {} sliding",
            m.blocks.len(),
            k.peak_acceleration,
            count(JointState::Hinging),
            count(JointState::Opening),
            count(JointState::Sliding),
        );
        joint_lines(&mut o, m);
    }
    let statics = if analysis.statics.stands { "stands" } else { "falls" };
    let verdict = match (k.verdict, k.agrees) {
        (_, true) => "AGREE",
        (KinematicVerdict::Undecided, _) => "UNDECIDED (the friction capacities did not settle: trust neither blindly)",
        _ => {
            "DISAGREE (the statics' equilibrium needs a squeeze nothing applies: the kinematic verdict is the physical one)"
        }
    };
    let _ = writeln!(o, "statics (RBE) {statics} | kinematic {word}: {verdict}");
    o
}

/// AGREE, or DISAGREE with what the drop test's motion suggests.
fn disagreement(statics_stand: bool, d: &DropResult) -> &'static str {
    use crate::dynamics::Engine;
    match (statics_stand == d.stands, statics_stand, d.at_rest) {
        (true, _, _) => "AGREE",
        (false, _, _) if d.engine == Engine::Exact => {
            "DISAGREE (hard contacts: a squeeze the statics count on that nothing applies, a motion that arrests itself, or a solver status above)"
        }
        (false, false, _) => {
            "DISAGREE (the drop test held what the statics cannot: a margin within rapier's tolerances, or too short a run)"
        }
        (false, true, true) => {
            "DISAGREE (the blocks moved past the tolerance, then came to rest: rapier's soft contacts settling, or overlapping input — compare the margins)"
        }
        (false, true, false) => {
            "DISAGREE (still moving at the end: a failure the statics miss, or rapier near a limit — compare the margins)"
        }
    }
}

/// The text report of `voussoir robustness`: the load factor first, then the mechanism and,
/// for a direction sweep, the worst direction. `load` says what the live load was.
pub fn robustness(
    analysis: &Analysis,
    r: &crate::stability::Robustness,
    sweep: Option<&crate::stability::DirectionSweep>,
    load: &str,
) -> String {
    use crate::stability::{JointState, Safety};
    use std::fmt::Write;
    let mut o = String::new();
    let s = &analysis.statics;
    let _ = match r.safety {
        Safety::Collapses { load_factor } => {
            writeln!(o, "LOAD FACTOR λ* = {load_factor:.4}: collapses at {load_factor:.4} × {load}")
        }
        Safety::Unlimited => writeln!(o, "LOAD FACTOR λ* = ∞: no multiple of {load} makes it collapse"),
        Safety::DoesNotStand { load_factor } => writeln!(
            o,
            "DOES NOT STAND under its dead load: tension {:.3e} W, friction excess {:.3e} W; {}",
            s.tension_ratio,
            s.friction_excess_ratio,
            match load_factor {
                Some(l) => format!("it would stand with up to λ = {l:.4} × {load}"),
                None => format!("no multiple of {load} holds it"),
            }
        ),
        Safety::SolverFailed { status, residual } => {
            writeln!(o, "UNDECIDED: the load-factor solve ended with {status:?} (residual {residual:.2e} N)")
        }
    };
    let _ = writeln!(
        o,
        "  {} blocks, friction {} μ = {:.4}; {} iterations, {:.1} ms in the solver",
        analysis.assembly.blocks.len(),
        s.friction_model,
        s.friction_coefficient,
        r.iterations,
        1e3 * r.solver_seconds
    );
    if r.status == crate::statics::SolverStatus::AlmostSolved {
        let _ = writeln!(
            o,
            "  note: solved only to the reduced tolerances (λ* to ~1e-5 of itself; residual {:.2e} N)",
            r.residual
        );
    }
    if let Some(sw) = sweep {
        let _ = writeln!(
            o,
            "  worst direction {:.2}° (λ* = {:.4}); over {} directions λ* from {:.4} to {:.4} ({} solves)",
            sw.worst_azimuth,
            sw.worst_load_factor,
            sw.azimuths.len(),
            sw.load_factors.iter().copied().fold(f64::INFINITY, f64::min),
            sw.load_factors.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            sw.solves
        );
    }
    match &r.mechanism {
        None => {
            let _ = writeln!(o, "  no collapse mechanism");
        }
        Some(m) => {
            let count = |state| m.interfaces.iter().filter(|i| i.state == state).count();
            let _ = writeln!(
                o,
                "  mechanism: {} moving block(s); interfaces {} hinging, {} opening, {} sliding, {} closed",
                m.blocks.len(),
                count(JointState::Hinging),
                count(JointState::Opening),
                count(JointState::Sliding),
                count(JointState::Closed)
            );
            if let Some(line) = m.uniqueness.sentence() {
                let _ = writeln!(o, "    {line}");
            }
            joint_lines(&mut o, m);
        }
    }
    o
}

/// A mechanism's moving joints, the largest motion first, five of them and a count of the rest.
fn joint_lines(o: &mut String, m: &crate::statics::Mechanism) {
    use std::fmt::Write;
    const SHOWN: usize = 5;
    let joints = m.moving_joints();
    for i in joints.iter().take(SHOWN) {
        let _ = writeln!(o, "    {} → {}: {:?}", i.a, i.b, i.state);
    }
    if joints.len() > SHOWN {
        let _ = writeln!(o, "    … and {} more moving joint(s), each moving less", joints.len() - SHOWN);
    }
}

/// The fabrication tolerance margins, one line each with the joint that governs.
pub fn tolerance(m: &crate::stability::tolerance::Margins) -> String {
    let joint = |g: &Option<crate::stability::tolerance::Governing>| {
        g.as_ref().map_or(String::from("no joint limits it"), |g| format!("governed by {} → {}", g.a, g.b))
    };
    format!(
        "TOLERANCE: joints may bear short of their edges by {:.4e} m ({:.2} % of the block size {:.3e} m), {}\n  \
         joint planes may turn by {:.3}° ({:.1} % of the friction angle), {}; {} statics solves\n",
        m.shrink.value,
        100.0 * m.shrink.relative,
        m.block_size,
        joint(&m.shrink.governing),
        m.tilt.value,
        100.0 * m.tilt.relative,
        joint(&m.tilt.governing),
        m.solves
    )
}
