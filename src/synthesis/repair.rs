//! Repair: move and turn a design's cuts until it stands, then until it stands most safely.
//!
//! A particle swarm ([`crate::optimise`]: argmin's, seeded, evaluated in order: the same seed
//! gives the same design) searches the cut parameters of [`super::params`] for the lowest
//! [`super::objective`] score. The design as given is scored first and kept unless something
//! scores lower, so a repair never makes a design worse. When the best design still fails,
//! the answer names the interfaces that keep failing and, where one column under a failing
//! block holds it, that support ([`super::props`]).

use super::objective::{Evaluator, Score};
use super::params::{CutParameters, Freedom, holds};
use super::props::{SupportProposal, propose_support};
use super::{DesignError, RepairSettings};
use crate::model::{Cut, Scene};
use crate::pipeline::{Analysis, AnalysisSettings};
use crate::stability::{DirectionSettings, worst_direction};
use serde::Serialize;
use std::sync::Mutex;

/// How a repair ended.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RepairOutcome {
    /// It did not stand and now does.
    Repaired,
    /// It stood already; `improved` when the load factor grew.
    AlreadyStood {
        /// Whether the load factor grew.
        improved: bool,
    },
    /// No placement of the selected cuts found makes it stand.
    NotRepaired,
    /// The design has no cut to move (e.g. one solid piece).
    NothingToMove,
}

/// One interface of the best design that still needs tension or more friction.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FailingInterface {
    /// The name of the interface's side a.
    pub a: String,
    /// The name of its side b.
    pub b: String,
    /// Tension and friction excess at it, fractions of the free weight.
    pub tension: f64,
    /// Friction excess at it, a fraction of the free weight.
    pub friction_excess: f64,
}

/// A cut the repair moved.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CutChange {
    /// The cut's position in the history, from 0.
    pub index: usize,
    /// The cut as given.
    pub before: Cut,
    /// The cut as repaired (through the centre of the joints it makes).
    pub after: Cut,
}

/// Before and after, and how the search went.
#[derive(Clone, Debug, Serialize)]
pub struct RepairReport {
    /// Repaired, already stood, not repaired, or nothing to move.
    pub outcome: RepairOutcome,
    /// The design as given: verdict, graded numbers, pieces.
    pub before: Score,
    /// The repaired design's.
    pub after: Score,
    /// The worst-direction load factor of the design before and after (full sweep, when it
    /// stands).
    pub load_factor_before: Option<f64>,
    /// The repaired design's worst-direction load factor, when it stands.
    pub load_factor_after: Option<f64>,
    /// The cuts moved, each before and after.
    pub changed: Vec<CutChange>,
    /// The best search cost after each evaluation (the score less the closeness bonus of a
    /// standing design; non-increasing; the first is the design as given).
    pub history: Vec<f64>,
    /// Designs evaluated (analyses run, cached pieces reused).
    pub evaluations: usize,
    /// Wall-clock seconds of the search.
    pub seconds: f64,
    /// Where the best design still fails.
    pub failing: Vec<FailingInterface>,
    /// A support that makes the best design stand, when it does not and one column does.
    pub support: Option<SupportProposal>,
    /// The repaired design (the input with its cuts moved).
    #[serde(skip)]
    pub design: Scene,
}

/// Repairs `scene` (see the module docs). `progress` is called after each evaluation with
/// (evaluations done, evaluations planned, best score so far).
pub fn repair(
    scene: &Scene,
    analysis: &AnalysisSettings,
    settings: &RepairSettings,
    progress: &(dyn Fn(usize, usize, f64) + Sync),
) -> Result<RepairReport, DesignError> {
    settings.validate()?;
    let start = std::time::Instant::now();
    let freedom = Freedom { max_turn_degrees: settings.max_turn_degrees, apex_move: settings.apex_move };
    let base = crate::pipeline::analyze(scene, analysis)?;
    let params = CutParameters::around(scene, &base, settings.cuts.as_deref(), &freedom)?;
    let directions = settings.robust.then_some(settings.directions);
    let evaluator = Evaluator::new(analysis, directions, params.indices(), min_volume(&base, settings));
    let before = evaluator.judge(&base);
    let planned = if params.is_empty() { 0 } else { settings.particles * (settings.iterations as usize + 1) };
    let first = with_closeness(&before, 1.0);
    let search = Search {
        scene,
        params: &params,
        evaluator: &evaluator,
        log: Mutex::new(vec![first]),
        done_before: 0,
        planned,
        progress,
    };
    let (mut history, best) = if params.is_empty() { (vec![before.cost], None) } else { search.run(settings)? };
    let mut design = match &best {
        Some((x, cost)) if *cost < first => params.apply(scene, x),
        _ => scene.clone(),
    };
    focus(&mut design, &mut history, &params, &evaluator, &freedom, settings, progress)?;
    let changed = changes(scene, &design);
    let load_factor_before = full_load_factor(&base, analysis);
    // Unchanged: the design as given, already analysed and swept.
    let (after, after_analysis, load_factor_after) = if changed.is_empty() {
        (before.clone(), Some(base), load_factor_before)
    } else {
        let (score, a) = evaluator.score(&design);
        let lambda = a.as_ref().and_then(|a| full_load_factor(a, analysis));
        (score, a, lambda)
    };
    let failing = after_analysis.as_ref().map(failing_interfaces).unwrap_or_default();
    let support = match &after_analysis {
        Some(a) if !after.stands() => propose_support(&design, a, analysis),
        _ => None,
    };
    let outcome = match (before.stands(), after.stands()) {
        _ if params.is_empty() => RepairOutcome::NothingToMove,
        (true, _) => RepairOutcome::AlreadyStood { improved: after.cost < before.cost },
        (false, true) => RepairOutcome::Repaired,
        (false, false) => RepairOutcome::NotRepaired,
    };
    Ok(RepairReport {
        outcome,
        load_factor_before,
        load_factor_after,
        before,
        after,
        changed,
        evaluations: history.len(),
        history,
        seconds: start.elapsed().as_secs_f64(),
        failing,
        support,
        design,
    })
}

/// When the best design still fails, searches again over only the cuts in whose planes its
/// failing interfaces lie — or, when moving those alone does not help, also the cuts that
/// bound the blocks on either side (a swarm in a few dimensions finds what one over every cut
/// of a large design misses) — from the best design so far, up to `focus_rounds` times while
/// it fails and such cuts are fewer than the whole selection. Each round's log continues the
/// history (its running best never rises).
fn focus(
    design: &mut Scene,
    history: &mut Vec<f64>,
    params: &CutParameters,
    evaluator: &Evaluator,
    freedom: &Freedom,
    settings: &RepairSettings,
    progress: &(dyn Fn(usize, usize, f64) + Sync),
) -> Result<(), DesignError> {
    let selected = params.indices();
    let mut tried: Vec<Vec<usize>> = Vec::new();
    for round in 0..settings.focus_rounds {
        // A cost ≤ 0 is a standing design's: nothing to focus on (and no need to score it).
        if history.last().is_some_and(|&best| best <= 0.0) {
            break;
        }
        let (score, analysis) = evaluator.score(design);
        let Some(analysis) = analysis.filter(|_| !score.stands() && score.invalid.is_none()) else { break };
        // The cuts holding the failing joints, then also those bounding the blocks on either side.
        let holding = failing_cuts(design, &analysis, &selected);
        let mut bounding = holding.clone();
        bounding.extend(bounding_cuts(&analysis, &selected));
        bounding.sort_unstable();
        bounding.dedup();
        let Some(cuts) =
            [holding, bounding].into_iter().find(|c| !c.is_empty() && c.len() < selected.len() && !tried.contains(c))
        else {
            break;
        };
        let focused = CutParameters::around(design, &analysis, Some(&cuts), freedom)?;
        let current = history.last().copied().unwrap_or(score.cost).min(score.cost);
        let search = Search {
            scene: design,
            params: &focused,
            evaluator,
            log: Mutex::new(vec![current]),
            done_before: history.len() - 1,
            planned: history.len() - 1 + settings.particles * (settings.iterations as usize + 1),
            progress,
        };
        let round_settings = RepairSettings { seed: settings.seed.wrapping_add(1 + round as u64), ..settings.clone() };
        let (log, best) = search.run(&round_settings)?;
        history.extend(log.into_iter().skip(1));
        match best {
            Some((x, cost)) if cost < current => {
                *design = focused.apply(design, &x);
                tried.clear();
            }
            _ => tried.push(cuts),
        }
    }
    Ok(())
}

/// The selected cuts that made a block on either side of a failing interface (they bound it).
fn bounding_cuts(analysis: &Analysis, selected: &[usize]) -> Vec<usize> {
    let names: Vec<&str> = failing_results(analysis).flat_map(|r| [r.a.as_str(), r.b.as_str()]).collect();
    selected.iter().copied().filter(|&i| names.iter().any(|n| crate::history::made_by(n, i))).collect()
}

/// The selected cuts in whose plane a failing interface of `analysis` lies: a plane cut whose
/// plane holds the interface, a pattern cut whose apex lies in its plane.
fn failing_cuts(design: &Scene, analysis: &Analysis, selected: &[usize]) -> Vec<usize> {
    let tolerance = 1e-6 * design.scale();
    let failing: Vec<&crate::interfaces::Interface> =
        failing_results(analysis).map(|r| &analysis.interfaces[r.index]).collect();
    selected.iter().copied().filter(|&i| failing.iter().any(|itf| holds(&design.cuts[i], itf, tolerance))).collect()
}

/// The interface results of `analysis` that carry tension or friction excess (above 1e-9 W).
fn failing_results(analysis: &Analysis) -> impl Iterator<Item = &crate::statics::InterfaceResult> {
    let floor = 1e-9 * analysis.statics.free_weight;
    analysis.statics.interfaces.iter().filter(move |r| r.tension + r.friction_excess > floor)
}

/// The smallest volume a free piece may have: a fraction of the design's mean piece, but never
/// more than its own smallest piece (a piece as small as the designer's own is no sliver, and
/// the design as given passes its own rules).
fn min_volume(base: &Analysis, settings: &RepairSettings) -> f64 {
    let free: Vec<f64> = base.assembly.blocks.iter().filter(|b| !b.support).map(|b| b.mass.volume).collect();
    let mean = free.iter().sum::<f64>() / free.len().max(1) as f64;
    let smallest = free.iter().copied().fold(f64::INFINITY, f64::min);
    (settings.min_piece_fraction * mean).min(smallest)
}

/// The best parameters a search found and their cost.
type Best = (Vec<f64>, f64);

/// The particle swarm over the cut parameters, every evaluation logged.
struct Search<'a> {
    scene: &'a Scene,
    params: &'a CutParameters,
    evaluator: &'a Evaluator,
    log: Mutex<Vec<f64>>,
    /// Evaluations logged by earlier searches of the same repair (for the progress count).
    done_before: usize,
    planned: usize,
    progress: &'a (dyn Fn(usize, usize, f64) + Sync),
}

impl Search<'_> {
    /// The search cost of `x`, logged with the running best.
    fn cost(&self, x: &[f64]) -> f64 {
        let (score, _) = self.evaluator.score(&self.params.apply(self.scene, x));
        let cost = with_closeness(&score, self.params.closeness(x));
        let mut log = self.log.lock().expect("not poisoned");
        let best = log.last().copied().unwrap_or(f64::INFINITY).min(cost);
        log.push(best);
        (self.progress)(self.done_before + log.len() - 1, self.planned, best);
        cost
    }

    /// Runs the swarm; the log of best scores and the best parameters found with their score.
    fn run(self, settings: &RepairSettings) -> Result<(Vec<f64>, Option<Best>), DesignError> {
        let best = crate::optimise::particle_swarm(
            &|x| self.cost(x),
            self.params.bounds(),
            settings.particles,
            settings.iterations,
            settings.seed,
        )
        .map_err(DesignError::Optimiser)?;
        Ok((self.log.into_inner().expect("not poisoned"), best))
    }
}

/// Among standing designs, the search prefers the least change: a standing score gains up to
/// this much for being the design as given (less than any load-factor difference worth a
/// change, and never enough to lift it above zero, where failing designs are).
pub const CLOSENESS_WEIGHT: f64 = 1e-3;

/// The search's cost: the score, less [`CLOSENESS_WEIGHT`] × closeness for a standing design.
fn with_closeness(score: &Score, closeness: f64) -> f64 {
    if score.stands() { score.cost - CLOSENESS_WEIGHT * closeness } else { score.cost }
}

/// The cuts that differ between two versions of a design.
fn changes(before: &Scene, after: &Scene) -> Vec<CutChange> {
    before
        .cuts
        .iter()
        .zip(&after.cuts)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(index, (a, b))| CutChange { index, before: a.clone(), after: b.clone() })
        .collect()
}

/// The interfaces carrying most of the tension and friction excess (each above 1e-3 of the
/// largest), worst first.
fn failing_interfaces(analysis: &Analysis) -> Vec<FailingInterface> {
    let w = analysis.statics.free_weight.max(f64::MIN_POSITIVE);
    let mut bad: Vec<FailingInterface> = analysis
        .statics
        .interfaces
        .iter()
        .map(|i| FailingInterface {
            a: i.a.clone(),
            b: i.b.clone(),
            tension: i.tension / w,
            friction_excess: i.friction_excess / w,
        })
        .collect();
    let worst = bad.iter().map(|f| f.tension + f.friction_excess).fold(0.0, f64::max);
    bad.retain(|f| worst > 0.0 && f.tension + f.friction_excess > 1e-3 * worst);
    bad.sort_by(|x, y| (y.tension + y.friction_excess).total_cmp(&(x.tension + x.friction_excess)));
    bad
}

/// The worst-direction load factor (the robustness command's default sweep) of a design that
/// stands.
fn full_load_factor(analysis: &Analysis, settings: &AnalysisSettings) -> Option<f64> {
    if !analysis.statics.stands {
        return None;
    }
    worst_direction(
        &analysis.assembly,
        &analysis.interfaces,
        &settings.statics,
        &DirectionSettings::default(),
        &|_, _| {},
    )
    .ok()
    .map(|s| s.worst_load_factor)
}
