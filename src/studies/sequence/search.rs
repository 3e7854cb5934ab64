//! Order search and temporary supports.
//!
//! Search: depth-first over *sets* of placed blocks — whether a set stands does not depend on
//! the order it was placed in, so a set from which no complete order exists is remembered and
//! never explored twice. At each set the candidates are the unplaced blocks touching a placed
//! block or a fixed body, tried in the from-supports order (graph distance, then height): the
//! first that stands is taken (greedy), the next on backtracking. With a budget of prefixes
//! checked; the search is exhaustive (a "no order" is a proof) when it ends within it.
//!
//! Temporary supports (props): along an order, when a step does not stand, the fewest placed
//! blocks are fixed so that it does — one prop is tried first (the new block, then the blocks
//! of the offending interfaces, then its neighbours), more are added greedily by the graded
//! answer; after each later step, props whose release still leaves the step standing are
//! released, latest first (all of them when a keystone closes an arch).
//!
//! Fixing a block only adds supports, so whatever stands with some props stands with more.
//! Two checks follow, each on a block's neighbourhood — it and the placed free blocks within
//! 1, then 2, 4 and 8 interfaces free (1 and 2 around a new block along an order with props),
//! the placed blocks touching them fixed ([`LocalCheck`]), a small problem: when the new
//! block's neighbourhood fails, the step fails with its props and with fewer — a prefix of the
//! search is then dead without its whole analysis, and along an order no release is tried and
//! the new block is propped straight away (the step then stands with no analysis when the last
//! one stood with the same props: a prop adds supports and no load); when a prop's
//! neighbourhood fails without it, its release cannot stand and is not analysed. A release a
//! whole step refused is tried again later first on the neighbourhood of the blocks where it
//! failed (it mostly fails again, there). The props and steps are those of the whole-step
//! analyses alone (tests below). On the Armadillo 4 of 5 releases end at the neighbourhoods
//! (docs/benchmarks.md).

use super::order::Adjacency;
use super::steps::{Stepper, offending, sorted};
use super::{SequenceError, Step, TemporarySupport};
use crate::model::Scene;
use crate::pipeline::Analysis;
use crate::statics::{FirstStage, stand_threshold};
use std::collections::{HashMap, HashSet};

/// Settings of the order search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchSettings {
    /// Prefixes the order search may check (each decided by its last block's neighbourhood or
    /// by a whole-step analysis); `None` (default) allows [`Self::CHECKS_PER_BLOCK`] per free
    /// block + [`Self::BASE_CHECKS`].
    pub max_checks: Option<usize>,
    /// Prop candidates tried one by one at a failing step before adding props greedily.
    pub prop_candidates: usize,
    /// Check a prefix of the search, a prop's release and a new block on the block's
    /// neighbourhood before the whole step (module docs): the same orders and props, a
    /// fraction of the solves. Off only to measure that.
    pub local_checks: bool,
}

impl Default for SearchSettings {
    fn default() -> Self {
        Self { max_checks: None, prop_candidates: 24, local_checks: true }
    }
}

impl SearchSettings {
    /// The default budget: this many static checks per free block…
    pub const CHECKS_PER_BLOCK: usize = 20;
    /// … and this many more.
    pub const BASE_CHECKS: usize = 200;

    /// The static checks allowed for a design of `free` free blocks.
    pub fn budget(&self, free: usize) -> usize {
        self.max_checks.unwrap_or(Self::CHECKS_PER_BLOCK * free + Self::BASE_CHECKS)
    }
}

/// What the search found.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SearchInfo {
    /// An order in which every step stands was found.
    pub found: bool,
    /// The search covered every order (so `found == false` proves there is none).
    pub exhaustive: bool,
    /// Static checks of whole steps run (search and props).
    pub checks: usize,
    /// Static checks of one block's neighbourhood run (module docs).
    pub local_checks: usize,
    /// The longest standing prefix reached.
    pub deepest: usize,
}

type Set = Vec<u64>;

struct Dfs<'s, 'a> {
    stepper: &'s mut Stepper<'a>,
    local: LocalCheck<'a>,
    names: Vec<&'a str>,
    adj: &'s Adjacency,
    rank: Vec<usize>,
    dead: HashSet<Set>,
    /// Prefixes decided, by a neighbourhood or the whole prefix, against the budget.
    decided: usize,
    budget: usize,
    out_of_budget: bool,
    best: Vec<usize>,
    tick: &'s (dyn Fn() + Sync),
}

fn has(set: &Set, k: usize) -> bool {
    set[k / 64] >> (k % 64) & 1 == 1
}

impl Dfs<'_, '_> {
    /// Whether the prefix `order` stands: not when the last block's neighbourhood fails. That
    /// is checked after a prefix that failed only: failures come in runs, and where prefixes
    /// stand the neighbourhoods would all be solved for nothing.
    fn stands(&mut self, order: &[usize]) -> Result<bool, SequenceError> {
        let placed: HashSet<&str> = order.iter().map(|&k| self.names[k]).collect();
        (self.tick)();
        self.decided += 1;
        let last = self.names[*order.last().expect("a block placed")];
        if self.stepper.last_failed() && self.local.fails(&placed, &HashSet::new(), last, LocalCheck::RINGS)? {
            return Ok(false);
        }
        Ok(self.stepper.analyse(&placed, &HashSet::new())?.statics.stands)
    }

    fn candidates(&self, set: &Set, free: &[usize]) -> Vec<usize> {
        let mut c: Vec<usize> = free
            .iter()
            .copied()
            .filter(|&k| !has(set, k))
            .filter(|&k| self.adj.grounded[k] || self.adj.neighbours[k].iter().any(|&m| has(set, m)))
            .collect();
        c.sort_by_key(|&k| self.rank[k]);
        c
    }

    /// Extends `order` (standing, with `set` its blocks) to all of `free`; false when no
    /// extension exists or the budget ran out.
    fn extend(&mut self, set: &mut Set, order: &mut Vec<usize>, free: &[usize]) -> Result<bool, SequenceError> {
        if order.len() == free.len() {
            return Ok(true);
        }
        for c in self.candidates(set, free) {
            if self.decided >= self.budget {
                self.out_of_budget = true;
                return Ok(false);
            }
            set[c / 64] |= 1 << (c % 64);
            order.push(c);
            let ok = !self.dead.contains(set) && self.stands(order)?;
            if ok {
                if order.len() > self.best.len() {
                    self.best = order.clone();
                }
                if self.extend(set, order, free)? {
                    return Ok(true);
                }
            }
            if !self.out_of_budget {
                self.dead.insert(set.clone());
            }
            order.pop();
            set[c / 64] &= !(1 << (c % 64));
            if self.out_of_budget {
                return Ok(false);
            }
        }
        Ok(false)
    }
}

/// Searches an order of the free blocks of `resolved` in which every prefix stands. Returns the
/// order found (or the longest standing prefix) and the search's account.
/// `ranked`: the free blocks in the from-supports order (the candidates' priority).
pub(crate) fn search_order<'a>(
    stepper: &mut Stepper<'a>,
    resolved: &'a Scene,
    adj: &'a Adjacency,
    ranked: &[String],
    search: &SearchSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<(Vec<String>, SearchInfo), SequenceError> {
    let index = &adj.index;
    let n = resolved.blocks.len();
    let mut rank = vec![usize::MAX; n];
    for (r, name) in ranked.iter().enumerate() {
        rank[index[name].0] = r;
    }
    let free: Vec<usize> = (0..n).filter(|&k| !resolved.blocks[k].support).collect();
    let budget = search.budget(free.len());
    let local = LocalCheck::new(stepper, resolved, adj, search.local_checks);
    let mut dfs = Dfs {
        stepper,
        local,
        names: resolved.blocks.iter().map(|b| b.name.as_str()).collect(),
        adj,
        rank,
        dead: HashSet::new(),
        decided: 0,
        budget,
        out_of_budget: false,
        best: Vec::new(),
        tick,
    };
    let mut set = vec![0u64; n.div_ceil(64)];
    let mut order = Vec::new();
    let found = dfs.extend(&mut set, &mut order, &free)?;
    let info = SearchInfo {
        found,
        exhaustive: found || !dfs.out_of_budget,
        checks: dfs.stepper.checks,
        local_checks: dfs.local.stepper.checks,
        deepest: if found { free.len() } else { dfs.best.len() },
    };
    let chosen = if found { order } else { dfs.best };
    Ok((chosen.into_iter().map(|k| resolved.blocks[k].name.clone()).collect(), info))
}

fn set_of<'x>(active: &[(&'x str, usize)]) -> HashSet<&'x str> {
    active.iter().map(|p| p.0).collect()
}

/// The placed blocks of the interfaces that need tension or friction beyond μ in `a`: where a
/// refused release failed (the props among them are left out where they are checked).
fn failing_blocks<'a>(a: &Analysis, placed: &HashSet<&'a str>) -> Vec<&'a str> {
    let mut blocks: Vec<&'a str> =
        offending(a).flat_map(|r| [r.a.as_str(), r.b.as_str()]).filter_map(|b| placed.get(b).copied()).collect();
    blocks.sort_unstable();
    blocks.dedup();
    blocks
}

/// The graded answer of an analysis: minimum tension plus friction excess, relative to W.
fn graded(a: &Analysis) -> f64 {
    a.statics.tension_ratio + a.statics.friction_excess_ratio
}

/// The steps of `order` with temporary supports where a step would not stand (module docs).
/// Every analysis of a step's final set (placed blocks, props) is the one the step reports:
/// no set is analysed twice. Also returns the neighbourhood checks run.
pub(crate) fn with_props<'a>(
    stepper: &mut Stepper<'a>,
    resolved: &'a Scene,
    adj: &'a Adjacency,
    order: &'a [String],
    search: &SearchSettings,
    per_step: &super::StepChecks,
    tick: &(dyn Fn() + Sync),
) -> Result<(Vec<Step>, Vec<TemporarySupport>, usize), SequenceError> {
    let mut local = LocalCheck::new(stepper, resolved, adj, search.local_checks);
    let mut props =
        Props { stepper, resolved, adj, search, active: Vec::new(), released: Vec::new(), refused: HashMap::new() };
    let mut placed: HashSet<&str> = HashSet::new();
    let mut steps = Vec::with_capacity(order.len());
    for (k, name) in order.iter().enumerate() {
        placed.insert(name);
        tick();
        // A step whose new block's neighbourhood fails cannot stand with its props, nor with
        // fewer: no release is tried. Checked once the order has needed a prop: until then the
        // steps stand and the neighbourhoods would be solved for nothing.
        let propped = !props.active.is_empty() || !props.released.is_empty();
        let doomed = propped && local.fails(&placed, &set_of(&props.active), name, LocalCheck::NEW_BLOCK_RINGS)?;
        // Propped at once on a step that stood with the same props, the step stands: a prop adds
        // supports and no load, so the last step's forces still balance every free block.
        if doomed && !per_step.any() && steps.last().is_some_and(|s: &Step| s.stands) {
            props.active.push((name, k));
            steps.push(Step::standing(name, sorted(&set_of(&props.active))));
            continue;
        }
        let released = if doomed { None } else { props.release(&mut local, &placed, k)? };
        let current = match released {
            Some(a) => a,
            None => props.prop_if_needed(&placed, order, k, doomed)?,
        };
        steps.push(props.stepper.step_from(name, &current, &set_of(&props.active), per_step)?);
    }
    let mut released = props.released;
    released.extend(props.active.drain(..).map(|(b, from)| TemporarySupport::new(b, from, order.len())));
    released.sort_by(|a, b| (a.from, &a.block).cmp(&(b.from, &b.block)));
    Ok((steps, released, local.stepper.checks))
}

/// The props along an order: those standing now and those released.
struct Props<'s, 'a> {
    stepper: &'s mut Stepper<'a>,
    resolved: &'a Scene,
    adj: &'s Adjacency,
    search: &'s SearchSettings,
    /// Active props: name → step from which it is propped.
    active: Vec<(&'a str, usize)>,
    released: Vec<TemporarySupport>,
    /// Active props whose release a whole-step analysis refused, each with the placed blocks of
    /// the interfaces that failed in that analysis.
    refused: HashMap<&'a str, Vec<&'a str>>,
}

impl<'a> Props<'_, 'a> {
    /// Releases, latest first, every prop the step `k` stands without; the analysis of the last
    /// release, if any was released. A release the prop's neighbourhood already fails is not
    /// analysed. Of the others, a prop's first whole-step try mostly stands and starts with the
    /// strict QP; a try after a refusal mostly fails again and starts with the LPs (the
    /// Armadillo: 108 of 112 and 33 of 37, docs/benchmarks.md). Either start gives the same
    /// verdict and graded numbers.
    fn release(
        &mut self,
        local: &mut LocalCheck<'_>,
        placed: &HashSet<&'a str>,
        k: usize,
    ) -> Result<Option<Analysis>, SequenceError> {
        let mut last = None;
        let mut i = self.active.len();
        while i > 0 {
            i -= 1;
            let mut without = self.active.clone();
            let (prop, _) = without.remove(i);
            let without = set_of(&without);
            if local.fails(placed, &without, prop, LocalCheck::RINGS)? {
                continue;
            }
            let failed_at = self.refused.get(prop);
            if let Some(at) = failed_at
                && local.fails_around(placed, &without, at, LocalCheck::REFUSED_RINGS)?
            {
                continue;
            }
            let first = if failed_at.is_some() { FirstStage::Relaxed } else { FirstStage::Strict };
            let a = self.stepper.analyse_from(placed, &without, first)?;
            if a.statics.stands {
                let (b, from) = self.active.remove(i);
                self.refused.remove(b);
                self.released.push(TemporarySupport::new(b, from, k));
                last = Some(a);
            } else {
                self.refused.insert(prop, failing_blocks(&a, placed));
            }
        }
        Ok(last)
    }

    /// The analysis of step `k` with the active props, and more props when it does not stand.
    /// When it cannot (`doomed`: the new block's neighbourhood fails), the new block, the first
    /// candidate, is tried as a prop straight away.
    fn prop_if_needed(
        &mut self,
        placed: &HashSet<&'a str>,
        order: &'a [String],
        k: usize,
        doomed: bool,
    ) -> Result<Analysis, SequenceError> {
        let name = order[k].as_str();
        let props = set_of(&self.active);
        let mut tried = None;
        if doomed {
            let mut with = props.clone();
            with.insert(name);
            let a = self.stepper.analyse_from(placed, &with, FirstStage::Strict)?;
            if a.statics.stands {
                self.active.push((name, k));
                return Ok(a);
            }
            tried = Some(a);
        }
        let current = self.stepper.analyse_from(placed, &props, FirstStage::Strict)?;
        if current.statics.stands {
            return Ok(current);
        }
        let cands = self.candidates(&current, placed, order, k);
        self.add_props(placed, &cands, k, current, tried)
    }

    /// Prop candidates at a failing step `k`: the new block, the blocks of the offending
    /// interfaces, its neighbours, then the other placed blocks from the top down.
    fn candidates(&self, current: &Analysis, placed: &HashSet<&'a str>, order: &'a [String], k: usize) -> Vec<&'a str> {
        let name = order[k].as_str();
        let mut cands: Vec<&str> = vec![name];
        for r in offending(current) {
            cands.extend([r.a.as_str(), r.b.as_str()]);
        }
        let me = self.adj.index[name].0;
        cands.extend(self.adj.neighbours[me].iter().map(|&m| self.resolved.blocks[m].name.as_str()));
        cands.extend(order[..k].iter().rev().map(String::as_str));
        let mut seen = HashSet::new();
        cands
            .into_iter()
            .filter(|c| placed.contains(c) && !self.active.iter().any(|p| p.0 == *c) && seen.insert(*c))
            .map(|c| *placed.get(c).expect("placed"))
            .collect()
    }

    /// Greedy rounds: each tries the candidates one at a time (so the first round finds a
    /// single prop when one suffices among them), takes the first with which the step stands,
    /// else the one that lowers the graded answer most, and goes again. `tried`: the first
    /// candidate's analysis, when already run. Returns the step's analysis. The candidates
    /// start with the strict QP: the first one mostly stands.
    fn add_props(
        &mut self,
        placed: &HashSet<&'a str>,
        cands: &[&'a str],
        k: usize,
        mut current: Analysis,
        mut tried: Option<Analysis>,
    ) -> Result<Analysis, SequenceError> {
        loop {
            let mut best: Option<(f64, &str, Analysis)> = None;
            let free = cands.iter().filter(|c| !self.active.iter().any(|p| p.0 == **c));
            for &c in free.take(self.search.prop_candidates) {
                let a = match tried.take() {
                    Some(a) => a,
                    None => {
                        let mut with = set_of(&self.active);
                        with.insert(c);
                        self.stepper.analyse_from(placed, &with, FirstStage::Strict)?
                    }
                };
                if a.statics.stands {
                    best = Some((-1.0, c, a));
                    break;
                }
                let g = graded(&a);
                if best.as_ref().is_none_or(|b| g < b.0) {
                    best = Some((g, c, a));
                }
            }
            // Every candidate is propped already: the step fails with the props it has.
            let Some((_, c, a)) = best else { return Ok(current) };
            self.active.push((c, k));
            current = a;
            if current.statics.stands {
                return Ok(current);
            }
        }
    }
}

/// A step checked on one block's neighbourhood alone (module docs), with its own pipeline so
/// the step's caches keep the step's blocks, and this one keeps the neighbourhoods' outcomes.
struct LocalCheck<'a> {
    stepper: Stepper<'a>,
    resolved: &'a Scene,
    adj: &'a Adjacency,
    enabled: bool,
}

impl<'a> LocalCheck<'a> {
    /// A friction excess beyond this many times the stand threshold, where the neighbourhood
    /// needs no tension, fails the step: the step's excess is minimised with its own minimum
    /// tension held, which may be above zero yet below the threshold and buy back a little
    /// excess — not this much.
    const EXCESS_MARGIN: f64 = 10.0;
    /// The neighbourhoods tried, in interfaces from the block: a small one first (most
    /// failures show there), a wider one for what it lets through.
    const RINGS: &'static [usize] = &[1, 2, 4, 8];
    /// The new block's neighbourhoods along an order with props: a block that cannot be placed
    /// fails within two interfaces; the wider rings around it never failed where the closer
    /// ones passed (the Armadillo, both domes, the arch, the DMSC ligature:
    /// docs/benchmarks.md), and cost more than the releases they would spare.
    const NEW_BLOCK_RINGS: &'static [usize] = &[1, 2];
    /// Around the blocks where a prop's release failed before, tried again when its own
    /// neighbourhoods pass: such a release mostly fails again, in the same place.
    const REFUSED_RINGS: &'static [usize] = &[1, 2];
    /// Neighbourhood outcomes kept from earlier checks: a prop's neighbourhood comes back
    /// unchanged at every step that places a block outside it.
    const KEEP: usize = 1024;

    fn new(step: &Stepper<'a>, resolved: &'a Scene, adj: &'a Adjacency, enabled: bool) -> Self {
        let stepper = step.twin(Self::KEEP);
        Self { stepper, resolved, adj, enabled }
    }

    /// Whether `placed` with the props `props` cannot stand because one of `block`'s
    /// neighbourhoods (within each of `rings` interfaces, in turn) fails with every other
    /// placed block fixed. Fixing blocks only adds supports; the step's component holding the
    /// neighbourhood has at least its minimum tension (and, when that is zero, its minimum
    /// friction excess), and a stand threshold at most the larger of the neighbourhood's
    /// weight's and the design's weight's.
    fn fails(
        &mut self,
        placed: &HashSet<&str>,
        props: &HashSet<&str>,
        block: &str,
        rings: &[usize],
    ) -> Result<bool, SequenceError> {
        self.fails_around(placed, props, &[block], rings)
    }

    /// [`Self::fails`] on the neighbourhoods of those of the blocks `seeds` that are placed and
    /// free, together (none: it does not).
    fn fails_around(
        &mut self,
        placed: &HashSet<&str>,
        props: &HashSet<&str>,
        seeds: &[&str],
        rings: &[usize],
    ) -> Result<bool, SequenceError> {
        let seeds: Vec<&str> = seeds.iter().copied().filter(|b| placed.contains(b) && !props.contains(b)).collect();
        if !self.enabled || seeds.is_empty() {
            return Ok(false);
        }
        for &within in rings {
            if self.fails_within(placed, props, &seeds, within)? {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// [`Self::fails`] on the blocks within `rings` interfaces of the `seeds` through placed
    /// free blocks.
    fn fails_within(
        &mut self,
        placed: &HashSet<&str>,
        props: &HashSet<&str>,
        seeds: &[&str],
        rings: usize,
    ) -> Result<bool, SequenceError> {
        let blocks = &self.resolved.blocks;
        let mut region: HashSet<&str> = seeds.iter().copied().collect();
        let mut front: Vec<usize> = seeds.iter().map(|b| self.adj.index[*b].0).collect();
        for _ in 0..rings {
            let mut next = Vec::new();
            for &at in &front {
                for &m in &self.adj.neighbours[at] {
                    let name = blocks[m].name.as_str();
                    if placed.contains(name) && !props.contains(name) && region.insert(name) {
                        next.push(m);
                    }
                }
            }
            front = next;
        }
        // Held: the placed blocks touching the region; the others touch none of its blocks.
        let held: HashSet<&str> = region
            .iter()
            .flat_map(|b| &self.adj.neighbours[self.adj.index[*b].0])
            .map(|&m| blocks[m].name.as_str())
            .filter(|m| placed.contains(m) && !region.contains(m))
            .collect();
        let scope: HashSet<&str> = region.union(&held).copied().collect();
        // One first stage, so that the outcomes kept match: most neighbourhoods checked fail.
        let a = self.stepper.analyse_from(&scope, &held, FirstStage::Relaxed)?;
        let s = &a.statics;
        let threshold = stand_threshold(&self.stepper.settings().statics, s.free_weight, self.adj.free_weight);
        let (tension, excess) = (s.tension_ratio * s.free_weight, s.friction_excess_ratio * s.free_weight);
        Ok(tension > threshold || (tension == 0.0 && excess > Self::EXCESS_MARGIN * threshold))
    }
}

/// Invariant: the neighbourhood checks are a shortcut, not an approximation — the same props
/// and the same steps with them as without, from fewer solves of whole steps.
#[cfg(test)]
mod local_checks_change_no_answer {
    use super::*;
    use crate::model::builtin;
    use crate::pipeline::AnalysisSettings;
    use crate::studies::sequence::{OrderSpec, order};

    struct Run {
        steps: Vec<Step>,
        props: Vec<TemporarySupport>,
        checks: usize,
        local: usize,
    }

    fn run(scene: &Scene, spec: &OrderSpec, local_checks: bool) -> Run {
        let settings = AnalysisSettings::default();
        let resolved = super::super::resolved(scene, &settings).unwrap();
        let order = order::order(&resolved, spec, &settings).unwrap();
        let adj = order::adjacency(&resolved, &settings).unwrap();
        let search = SearchSettings { local_checks, ..Default::default() };
        let mut stepper = Stepper::new(&resolved, &settings);
        let (steps, props, local) =
            with_props(&mut stepper, &resolved, &adj, &order, &search, &Default::default(), &|| {}).unwrap();
        Run { steps, props, checks: stepper.checks, local }
    }

    fn same_answer_fewer_solves(scene: &Scene, spec: &OrderSpec) {
        let (with, without) = (run(scene, spec, true), run(scene, spec, false));
        assert!(!without.props.is_empty(), "the order needs props");
        assert_eq!(with.props, without.props);
        assert_eq!(with.steps.len(), without.steps.len());
        for (k, (a, b)) in with.steps.iter().zip(&without.steps).enumerate() {
            assert_eq!((a.stands, a.verdict, &a.props), (b.stands, b.verdict, &b.props), "step {k}");
            assert!((a.tension_ratio - b.tension_ratio).abs() <= 1e-9, "step {k}");
            assert!((a.friction_excess_ratio - b.friction_excess_ratio).abs() <= 1e-9, "step {k}");
        }
        assert_eq!(without.local, 0);
        assert!(
            with.local > 0 && with.checks < without.checks,
            "{} + {} against {}",
            with.checks,
            with.local,
            without.checks
        );
    }

    #[test]
    fn arch_bottom_up() {
        same_answer_fewer_solves(&builtin("arch?n=15").unwrap(), &OrderSpec::BottomUp);
    }

    #[test]
    fn dome_bottom_up() {
        same_answer_fewer_solves(&builtin("dome?courses=5&blocks=10").unwrap(), &OrderSpec::BottomUp);
    }
}

/// Invariant: a release the whole step refused is checked again first where it failed — while
/// the failure is still there, that neighbourhood refuses it with no whole-step analysis, and
/// the prop stays, as the whole step analysed again says. The arch of 15: its right half placed
/// alone cannot stand; the left springer's voussoir, propped, stands by itself, so its own
/// neighbourhoods pass and only the whole step refuses its release.
#[cfg(test)]
mod refused_release {
    use super::*;
    use crate::model::builtin;
    use crate::pipeline::AnalysisSettings;
    use crate::studies::sequence::order;

    #[test]
    fn refused_again_where_it_failed() {
        let settings = AnalysisSettings::default();
        let resolved = super::super::resolved(&builtin("arch?n=15").unwrap(), &settings).unwrap();
        let adj = order::adjacency(&resolved, &settings).unwrap();
        let search = SearchSettings::default();
        let mut stepper = Stepper::new(&resolved, &settings);
        let mut local = LocalCheck::new(&stepper, &resolved, &adj, true);
        let placed: HashSet<&str> = ["v0", "v1", "v2", "v3", "v4", "v5", "v6", "v14"].into();
        let mut props = Props {
            stepper: &mut stepper,
            resolved: &resolved,
            adj: &adj,
            search: &search,
            active: vec![("v14", 7)],
            released: Vec::new(),
            refused: HashMap::new(),
        };
        assert!(props.release(&mut local, &placed, 8).unwrap().is_none());
        assert_eq!(props.stepper.checks, 1, "the first try is analysed whole");
        let at = props.refused.get("v14").expect("refused").clone();
        assert!(!at.is_empty() && at.iter().all(|b| b.starts_with('v') && *b != "v14"), "failed at {at:?}");
        let local_before = local.stepper.checks;
        assert!(props.release(&mut local, &placed, 9).unwrap().is_none());
        assert_eq!(props.stepper.checks, 1, "the second try ends where the first failed");
        assert!(local.stepper.checks > local_before);
        assert_eq!(props.active, vec![("v14", 7)]);
        let whole = props.stepper.analyse_from(&placed, &HashSet::new(), FirstStage::Relaxed).unwrap();
        assert!(!whole.statics.stands);
    }
}
