//! Order search and temporary supports.
//!
//! Search: depth-first over *sets* of placed blocks — whether a set stands does not depend on
//! the order it was placed in, so a set from which no complete order exists is remembered and
//! never explored twice. At each set the candidates are the unplaced blocks touching a placed
//! block or a fixed body, tried in the from-supports order (graph distance, then height): the
//! first that stands is taken (greedy), the next on backtracking. With a budget of static
//! checks; the search is exhaustive (a "no order" is a proof) when it ends within it.
//!
//! Temporary supports (props): along an order, when a step does not stand, the fewest placed
//! blocks are fixed so that it does — one prop is tried first (the new block, then the blocks
//! of the offending interfaces, then its neighbours), more are added greedily by the graded
//! answer; after each later step, props whose release still leaves the step standing are
//! released (all at once when possible, as when a keystone closes an arch).

use super::order::Adjacency;
use super::steps::Stepper;
use super::{SequenceError, Step, TemporarySupport};
use crate::model::Scene;
use crate::pipeline::Analysis;
use std::collections::HashSet;

/// Settings of the order search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchSettings {
    /// Static checks allowed; `None` (default) allows [`Self::CHECKS_PER_BLOCK`] per free
    /// block + [`Self::BASE_CHECKS`].
    pub max_checks: Option<usize>,
    /// Prop candidates tried one by one at a failing step before adding props greedily.
    pub prop_candidates: usize,
}

impl Default for SearchSettings {
    fn default() -> Self {
        Self { max_checks: None, prop_candidates: 24 }
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
    /// Static checks run (search and props).
    pub checks: usize,
    /// The longest standing prefix reached.
    pub deepest: usize,
}

type Set = Vec<u64>;

struct Dfs<'s, 'a> {
    stepper: &'s mut Stepper<'a>,
    names: Vec<&'a str>,
    adj: &'s Adjacency,
    rank: Vec<usize>,
    dead: HashSet<Set>,
    budget: usize,
    out_of_budget: bool,
    best: Vec<usize>,
    tick: &'s (dyn Fn() + Sync),
}

fn has(set: &Set, k: usize) -> bool {
    set[k / 64] >> (k % 64) & 1 == 1
}

impl Dfs<'_, '_> {
    fn stands(&mut self, order: &[usize]) -> Result<bool, SequenceError> {
        let placed: HashSet<&str> = order.iter().map(|&k| self.names[k]).collect();
        (self.tick)();
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
            if self.stepper.checks >= self.budget {
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
    adj: &Adjacency,
    ranked: &[String],
    search: &SearchSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<(Vec<String>, SearchInfo), SequenceError> {
    let index = super::order::index(resolved);
    let n = resolved.blocks.len();
    let mut rank = vec![usize::MAX; n];
    for (r, name) in ranked.iter().enumerate() {
        rank[index[name].0] = r;
    }
    let free: Vec<usize> = (0..n).filter(|&k| !resolved.blocks[k].support).collect();
    let budget = stepper.checks + search.budget(free.len());
    let mut dfs = Dfs {
        stepper,
        names: resolved.blocks.iter().map(|b| b.name.as_str()).collect(),
        adj,
        rank,
        dead: HashSet::new(),
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
        deepest: if found { free.len() } else { dfs.best.len() },
    };
    let chosen = if found { order } else { dfs.best };
    Ok((chosen.into_iter().map(|k| resolved.blocks[k].name.clone()).collect(), info))
}

fn set_of<'x>(active: &[(&'x str, usize)]) -> HashSet<&'x str> {
    active.iter().map(|p| p.0).collect()
}

/// The graded answer of an analysis: minimum tension plus friction excess, relative to W.
fn graded(a: &Analysis) -> f64 {
    a.statics.tension_ratio + a.statics.friction_excess_ratio
}

/// The steps of `order` with temporary supports where a step would not stand (module docs).
/// Every analysis of a step's final set (placed blocks, props) is the one the step reports:
/// no set is analysed twice.
pub(crate) fn with_props(
    stepper: &mut Stepper<'_>,
    resolved: &Scene,
    adj: &Adjacency,
    order: &[String],
    search: &SearchSettings,
    per_step: &super::StepChecks,
    tick: &(dyn Fn() + Sync),
) -> Result<(Vec<Step>, Vec<TemporarySupport>), SequenceError> {
    let index = super::order::index(resolved);
    let mut placed: HashSet<&str> = HashSet::new();
    // Active props: name → step from which it is propped.
    let mut active: Vec<(&str, usize)> = Vec::new();
    let mut props_out = Vec::new();
    let mut steps = Vec::with_capacity(order.len());
    for (k, name) in order.iter().enumerate() {
        placed.insert(name);
        tick();
        // Release what is no longer needed: everything at once, else one by one (latest first).
        // `current` is the analysis of (placed, active) once one has been run.
        let mut current: Option<Analysis> = None;
        if !active.is_empty() {
            let bare = stepper.analyse(&placed, &HashSet::new())?;
            if bare.statics.stands {
                props_out.extend(active.drain(..).map(|(b, from)| TemporarySupport::new(b, from, k)));
                current = Some(bare);
            } else {
                let mut i = active.len();
                while i > 0 && active.len() > 1 {
                    i -= 1;
                    let mut without = active.clone();
                    without.remove(i);
                    let a = stepper.analyse(&placed, &set_of(&without))?;
                    if a.statics.stands {
                        let (b, from) = active.remove(i);
                        props_out.push(TemporarySupport::new(b, from, k));
                        current = Some(a);
                    }
                }
            }
        }
        let mut current = match current {
            Some(a) => a,
            None => stepper.analyse(&placed, &set_of(&active))?,
        };
        if !current.statics.stands {
            // Candidates: the new block, the blocks of the offending interfaces, its neighbours,
            // then the other placed blocks from the top down.
            let s = &current.statics;
            let mut cands: Vec<&str> = vec![name.as_str()];
            for r in s
                .interfaces
                .iter()
                .filter(|r| r.tension > 1e-6 * s.free_weight || r.friction_excess > 1e-6 * s.free_weight)
            {
                cands.extend([r.a.as_str(), r.b.as_str()]);
            }
            let me = index[name.as_str()].0;
            cands.extend(adj.neighbours[me].iter().map(|&m| resolved.blocks[m].name.as_str()));
            cands.extend(order[..k].iter().rev().map(String::as_str));
            let mut seen = HashSet::new();
            let cands: Vec<&str> = cands
                .into_iter()
                .filter(|c| placed.contains(c) && !active.iter().any(|p| p.0 == *c) && seen.insert(*c))
                .map(|c| *placed.get(c).expect("placed"))
                .collect();
            // Greedy rounds: each tries the candidates one at a time (so the first round finds a
            // single prop when one suffices among them), takes the first with which the step
            // stands, else the one that lowers the graded answer most, and goes again.
            loop {
                let mut best: Option<(f64, &str, Analysis)> = None;
                for &c in cands.iter().filter(|c| !active.iter().any(|p| p.0 == **c)).take(search.prop_candidates) {
                    let mut with = set_of(&active);
                    with.insert(c);
                    let a = stepper.analyse(&placed, &with)?;
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
                let Some((_, c, a)) = best else { break };
                active.push((c, k));
                current = a;
                if current.statics.stands {
                    break;
                }
            }
        }
        steps.push(stepper.step_from(name, &current, &set_of(&active), per_step)?);
    }
    props_out.extend(active.drain(..).map(|(b, from)| TemporarySupport::new(b, from, order.len())));
    props_out.sort_by(|a, b| (a.from, &a.block).cmp(&(b.from, &b.block)));
    Ok((steps, props_out))
}
