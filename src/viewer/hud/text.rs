//! The panel's words: each section as short lines that fit the panel (nothing breaks
//! mid-phrase), numbers for people (0 W, 1.2e-3 W, units), words instead of enum names, and a
//! headline that says when the checks disagree.

use super::super::actions::{Overlay, ViewerState};
use super::Shown;
use crate::dynamics::Engine;
use crate::ecs::{DropLane, DropStatus, KinematicStatus, RobustnessStatus, SettleStatus, ShakeStatus};
use crate::report::words::{self, count, duration, force, share_of_weight};
use crate::stability::kinematic::KinematicVerdict;
use crate::statics::Verdict;
use crate::studies::settlement::Outcome;
use crate::viz::DiagramMode;
use crate::viz::colors::{self, Srgb};

/// The verdict in capitals (the headline) and its colour.
pub fn verdict_text(v: Option<Verdict>) -> (&'static str, Srgb) {
    let text = match v {
        Some(Verdict::Stands) => "STANDS",
        Some(Verdict::NeedsTension) => "NEEDS TENSION",
        Some(Verdict::NeedsFriction) => "FRICTION EXCEEDED",
        Some(Verdict::NeedsTensionAndFriction) => "TENSION + FRICTION",
        Some(Verdict::Crushes) => "CRUSHES",
        Some(Verdict::Unsupported) => "UNSUPPORTED",
        Some(Verdict::Unresolved) => "SOLVER TROUBLE",
        None => "—",
    };
    (text, colors::verdict(v))
}

/// The headline: the statics' verdict, and every check that disagrees with it on its own line.
#[derive(Clone, Debug, PartialEq)]
pub struct Headline {
    pub text: String,
    pub colour: Srgb,
    /// Whether another check contradicts the statics.
    pub disagrees: bool,
}

/// The verdicts of the checks that ran beside the statics: (check, stands).
fn other_verdicts(state: &ViewerState, drop: &DropStatus, kinematic: &KinematicStatus) -> Vec<(&'static str, bool)> {
    let mut out = Vec::new();
    if state.overlay == Overlay::Kinematic
        && let Some(k) = kinematic.result.as_ref().filter(|k| k.verdict != KinematicVerdict::Undecided)
    {
        out.push(("kinematic", k.verdict == KinematicVerdict::Stands));
    }
    for r in drop.lanes.iter().filter_map(|l| l.result.as_ref()) {
        let check = match (drop.compared(), r.engine) {
            (false, _) => "drop test",
            (true, Engine::Rapier) => "drop test, rapier",
            (true, Engine::Exact) => "drop test, exact",
        };
        out.push((check, r.stands));
    }
    out
}

impl Shown<'_> {
    pub(in crate::viewer) fn headline(&self) -> Headline {
        let (word, colour) = verdict_text(self.status.verdict);
        if self.status.error.is_some() {
            return Headline { text: "CANNOT ANALYSE".into(), colour: colors::FAILS, disagrees: false };
        }
        let decided =
            matches!(self.status.verdict, Some(v) if !matches!(v, Verdict::Unsupported | Verdict::Unresolved));
        let stands = self.status.stands;
        let against: Vec<(&str, bool)> = other_verdicts(&self.state, &self.drop, &self.kinematic)
            .into_iter()
            .filter(|&(_, s)| decided && s != stands)
            .collect();
        if against.is_empty() {
            return Headline { text: word.into(), colour, disagrees: false };
        }
        let mut text = format!("{word} (statics)");
        for (check, s) in &against {
            text += &format!("\n{} ({check})", if *s { "STANDS" } else { "FALLS" });
        }
        Headline { text, colour: colors::FAILS, disagrees: true }
    }

    /// The caption of the design's view: what it is and which diagram colours it.
    pub(in crate::viewer) fn view_caption(&self) -> String {
        let diagram = match self.state.mode {
            DiagramMode::Compression => "compression (blue) and tension (red)".to_string(),
            DiagramMode::Friction { threshold } => format!("friction use per interface (yellow ≤ {threshold:.2} μN)"),
            DiagramMode::Vectors => "resultant forces (green arrows)".to_string(),
        };
        let what = match (self.state.sequence_view, &self.sequence.report) {
            (true, Some(r)) => format!("sequence step {} of {}", self.sequence.current + 1, r.steps.len()),
            _ => "the design".to_string(),
        };
        format!("{what} · {diagram}")
    }

    /// The design's name (marked when edited) and its counts.
    pub(super) fn title(&self) -> String {
        let a = self.pipeline.analysis.as_ref();
        let (b, i) = a.map_or((0, 0), |a| (a.assembly.blocks.len(), a.interfaces.len()));
        let edited = if self.state.undo.is_empty() { "" } else { " (edited)" };
        format!("{}{edited}\n{} · {}", self.state.design.name, count(b, "block"), count(i, "interface"))
    }

    /// The graded numbers and the solve's time; what is unsupported; or the error.
    pub(super) fn numbers(&self) -> String {
        let status = &self.status;
        if let Some(e) = &status.error {
            return format!("cannot analyse: {e}");
        }
        let Some(a) = &self.pipeline.analysis else { return "analysing…".into() };
        let s = &a.statics;
        if s.verdict == Verdict::Unsupported {
            let what = s.solver.messages.join("\n");
            return format!(
                "nothing holds part of it:\n{what}\nselect a block and press G to\nmake it a support, or open with\n--supports lowest"
            );
        }
        let t = &status.timings;
        let worst = s.interfaces.iter().max_by(|x, y| x.friction_utilization.total_cmp(&y.friction_utilization));
        let friction = match worst.filter(|r| r.friction_utilization > 0.0) {
            Some(r) if r.friction_utilization.is_infinite() => {
                format!("friction without compression\n  at {} | {}", r.a, r.b)
            }
            Some(r) => format!("largest friction use {:.2} μN\n  at {} | {}", r.friction_utilization, r.a, r.b),
            None => "no friction acts".into(),
        };
        format!(
            "tension needed {}\nfriction beyond μ {}\n  W: the free blocks' weight, {}\n{friction}\nsolved in {} (detect {})",
            share_of_weight(status.tension_ratio),
            share_of_weight(status.friction_excess_ratio),
            force(s.free_weight),
            duration(t.assemble + t.solve),
            duration(t.detect),
        )
    }

    /// The checks that ran beside the statics (empty when none did).
    pub(super) fn checks(&self) -> String {
        let lines = [
            drop_text(&self.drop),
            settle_text(&self.state, &self.settle),
            shake_text(&self.state, &self.shake),
            robustness_text(&self.state, &self.robustness),
            kinematic_text(&self.state, &self.kinematic),
            self.sequence_text(),
        ];
        lines.into_iter().filter(|l| !l.is_empty()).collect::<Vec<_>>().join("\n")
    }

    /// The sequence step shown: the block placed, its verdicts and what fails.
    fn sequence_text(&self) -> String {
        let sequence = &self.sequence;
        if !self.state.sequence_view {
            return String::new();
        }
        let (Some(r), Some(step)) = (&sequence.report, sequence.step()) else {
            return sequence.error.clone().map_or("sequence: checking…".into(), |e| format!("sequence: {e}"));
        };
        let dynamic = step
            .dynamic
            .as_ref()
            .map_or(String::new(), |d| format!(" · drop: {}", if d.stands { "stands" } else { "falls" }));
        let mut s = format!(
            "sequence step {} of {}: + {}\n  statics: {}{dynamic}",
            sequence.current + 1,
            r.steps.len(),
            step.placed,
            step.verdict.words()
        );
        // The first offending interface and how many there are: a long list would not fit.
        match step.offending.as_slice() {
            [] => {}
            [one] => s += &format!("\n  fails at {one}"),
            [first, rest @ ..] => s += &format!("\n  fails at {first}\n  and {} more", count(rest.len(), "interface")),
        }
        s
    }
}

/// The drop tests: their progress, or their outcomes beside the statics'.
fn drop_text(drop: &DropStatus) -> String {
    if drop.lanes.is_empty() {
        return drop.error.clone().map_or(String::new(), |e| format!("drop test: {e}"));
    }
    drop.lanes.iter().map(lane_text).collect::<Vec<_>>().join("\n")
}

fn lane_text(lane: &DropLane) -> String {
    let (t, total) = lane.clock();
    let Some(r) = &lane.result else {
        return format!("drop test ({}): {t:.2} of {total:.2} s simulated", lane.engine());
    };
    format!(
        "drop test ({}): {}{}\n  drift {:.1e} of size · turn {:.2}°",
        r.engine,
        if r.stands { "stands" } else { "falls" },
        match lane.agree {
            Some(true) => ", agrees",
            Some(false) => " — disagrees",
            None => "",
        },
        r.max_drift,
        r.max_rotation.to_degrees(),
    )
}

/// The settlement while its pane is on: how far the supports went and how it ended, the
/// thrust at the start and at the end, the joints that opened.
fn settle_text(state: &ViewerState, s: &SettleStatus) -> String {
    if !state.settle_view {
        return String::new();
    }
    let Some(r) = &s.result else {
        return s.error.clone().unwrap_or_else(|| "supports move: following the path…".into());
    };
    let run = &r.quasi_static;
    let end = match run.outcome {
        Outcome::Collapses { fraction, movement, .. } => {
            format!("collapses\n  at {:.1} % of the path ({})", 100.0 * fraction, words::length(movement))
        }
        Outcome::Stands => format!("stands\n  to the path's end: {}", words::length(r.path_movement)),
        Outcome::Unresolved { fraction, .. } => format!("solver trouble\n  at {:.1} % of the path", 100.0 * fraction),
    };
    let thrust = |k: usize| run.stages.get(k).and_then(|st| st.reactions.first()).map(|f| f[0].hypot(f[1]));
    let thrusts = match (thrust(0), run.stages.len().checked_sub(1).and_then(thrust)) {
        (Some(a), Some(b)) => format!("\n  thrust {} → {}", force(a), force(b)),
        _ => String::new(),
    };
    // The collapse's mechanism, or the joints open at the last stage.
    let open =
        if run.mechanism.is_empty() { run.stages.last().map_or(0, |st| st.joints.len()) } else { run.mechanism.len() };
    format!("supports move (quasi-static): {end}{thrusts}\n  {} not closed", count(open, "joint"))
}

/// The shake while its pane is on: the static load factor beside each engine's answer.
fn shake_text(state: &ViewerState, s: &ShakeStatus) -> String {
    if !state.shake_view {
        return String::new();
    }
    let Some(r) = &s.result else {
        return s.error.clone().unwrap_or_else(|| "shake: running…".into());
    };
    let runs: Vec<String> = r
        .runs
        .iter()
        .map(|run| match run.collapse_time_s {
            Some(t) => format!("{}: collapses at {t:.2} s", run.result.engine.name()),
            None => {
                format!("{}: survives, {:.2}° at most", run.result.engine.name(), run.result.max_rotation.to_degrees())
            }
        })
        .collect();
    format!("shake: peak {:.3} g, λ* {:.4} g\n  {}", r.peak_g, r.static_load_factor, runs.join("\n  "))
}

/// The load factor while the mechanism pane is on: λ* and the direction it is for.
fn robustness_text(state: &ViewerState, r: &RobustnessStatus) -> String {
    use crate::stability::Safety;
    if state.overlay != Overlay::Mechanism {
        return String::new();
    }
    if let Some(e) = &r.error {
        return format!("load factor: {e}");
    }
    let Some(result) = &r.result else { return "load factor: computing…".into() };
    let head = match result.safety {
        Safety::Collapses { load_factor } => format!("load factor λ* = {load_factor:.4}"),
        Safety::Unlimited => "load factor λ* = ∞ (never collapses)".into(),
        Safety::DoesNotStand { .. } => return "load factor: none, it does not\n  stand under its own weight".into(),
        Safety::SolverFailed { status, .. } => format!("load factor: solver stopped ({status:?})"),
    };
    match r.worst_azimuth {
        Some(az) => format!("{head}\n  horizontal, worst direction {az:.0}°"),
        None => format!("{head}\n  for the design's live loads"),
    }
}

/// The kinematic check while it is on: its verdict and whether it agrees with the statics.
fn kinematic_text(state: &ViewerState, k: &KinematicStatus) -> String {
    if state.overlay != Overlay::Kinematic {
        return String::new();
    }
    if let Some(e) = &k.error {
        return format!("kinematic check: {e}");
    }
    let Some(r) = &k.result else { return "kinematic check: running…".into() };
    let verdict = match r.verdict {
        KinematicVerdict::Stands => "stands",
        KinematicVerdict::Fails => "falls",
        KinematicVerdict::Undecided => "undecided",
    };
    let agreement = match (r.verdict, r.agrees) {
        (KinematicVerdict::Undecided, _) => "",
        (_, true) => ", agrees",
        (_, false) => " — disagrees",
    };
    format!(
        "kinematic check: {verdict}{agreement}\n  {} · {}",
        count(r.rounds as usize, "round"),
        duration(r.solver_seconds)
    )
}

/// The edit state: the selection, the cut being edited, the history, the last note.
pub(super) fn edit_text(state: &ViewerState) -> String {
    let mut s = match &state.selected {
        Some(name) => format!("selected: {name}"),
        None => "click a block to select it".into(),
    };
    if let Some(c) = &state.active_cut {
        s += &format!(
            "\ncut {} of {}: through\n  ({:.3}, {:.3}, {:.3}) m\n  normal ({:.2}, {:.2}, {:.2})",
            c.index + 1,
            c.target,
            c.point.x,
            c.point.y,
            c.point.z,
            c.normal.x,
            c.normal.y,
            c.normal.z
        );
    }
    s += &format!("\nundo {} · redo {}", state.undo.len(), state.redo.len());
    if let Some(m) = &state.message {
        s += &format!("\n{m}");
    }
    s
}
