//! Statics that remembers: each component's outcome is kept by the component's content — its
//! blocks (geometry, support flag, density, name, dead loads), its interfaces (which of its blocks, or a
//! fixed body, on each side; the polygon), gravity, μ and the settings — so after an edit only
//! the components whose blocks or interfaces changed are solved again. With
//! `StaticsSettings::warm_start`, the strict QP's iterate each solve kept is also kept, by the
//! component's layout (its blocks' count, and which blocks each interface joins with how many
//! vertices): a component an edit changed but did not re-shape starts from them.

use super::backend::WarmStart;
use super::components::{Component, components, merged};
use super::error::StaticsError;
use super::result::{self, StaticsResult};
use super::settings::StaticsSettings;
use super::stages::{ComponentOutcome, solve_components};
use crate::interfaces::{Body, Interface};
use crate::model::Assembly;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};

/// Outcomes by component key, with force points' interface indices local to the component,
/// and the run that last used each.
#[derive(Debug, Default)]
pub struct StaticsCache {
    map: HashMap<u64, (ComponentOutcome, u64)>,
    /// The last run's kept iterates by component layout ([`layout_key`]).
    warm: HashMap<u64, WarmStart>,
    /// Outcomes of earlier runs kept beside the last run's, the most recently used first.
    keep: usize,
    runs: u64,
}

impl StaticsCache {
    /// A cache that also keeps the `keep` most recently used outcomes of earlier runs: for a
    /// caller that comes back to the same components (a sequence's neighbourhood checks).
    pub fn keeping(keep: usize) -> Self {
        Self { keep, ..Self::default() }
    }

    /// Stores this run's outcomes and drops what neither it nor the `keep` most recent earlier
    /// ones used.
    fn store(&mut self, used: HashMap<u64, ComponentOutcome>) {
        let run = self.runs;
        self.map.extend(used.into_iter().map(|(k, out)| (k, (out, run))));
        let earlier = self.map.len().saturating_sub(self.map.values().filter(|e| e.1 == run).count());
        if earlier > self.keep {
            let mut ages: Vec<u64> = self.map.values().map(|e| e.1).filter(|&r| r != run).collect();
            ages.sort_unstable_by(|a, b| b.cmp(a));
            let oldest_kept = if self.keep == 0 { run } else { ages[self.keep - 1] };
            // Ties at the boundary are kept: a run's outcomes stay or go together.
            self.map.retain(|_, e| e.1 >= oldest_kept);
        }
    }
}

/// Components solved and reused by a cached analysis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolveStats {
    /// Components whose statics was solved in this run.
    pub solved: usize,
    /// Components whose outcome was taken from the cache.
    pub reused: usize,
}

pub(crate) fn component_key(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    block_keys: &[u64],
    common: u64,
) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    common.hash(&mut h);
    for &b in &comp.blocks {
        let blk = assembly.block(b);
        (block_keys[b.0], blk.density.to_bits(), &blk.name).hash(&mut h);
        assembly.loads[b.0].dead.iter().for_each(|c| c.to_bits().hash(&mut h));
    }
    let side = |body: Body| match body {
        Body::Block(b) if !assembly.block(b).support => comp.blocks.binary_search(&b).map_or(u64::MAX, |i| i as u64),
        _ => u64::MAX - 1, // a fixed body: which one does not change the problem
    };
    for &k in &comp.interfaces {
        let i = &interfaces[k];
        (side(i.a), side(i.b)).hash(&mut h);
        for p in &i.polygon {
            p.iter().for_each(|c| c.to_bits().hash(&mut h));
        }
        i.frame.n.iter().for_each(|c| c.to_bits().hash(&mut h));
    }
    h.finish()
}

/// What every component's key shares: the settings, μ and gravity.
fn common_key(settings: &StaticsSettings, mu: f64, gravity: &crate::geometry::Vector3) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!("{settings:?}").hash(&mut h);
    mu.to_bits().hash(&mut h);
    gravity.iter().for_each(|g| g.to_bits().hash(&mut h));
    h.finish()
}

/// A component's layout: what fixes the rows and columns of its problems (not their numbers).
fn layout_key(interfaces: &[Interface], comp: &Component, common: u64) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    (common, comp.blocks.len()).hash(&mut h);
    let side = |body: Body| match body {
        Body::Block(b) => comp.blocks.binary_search(&b).map_or(u64::MAX, |i| i as u64),
        Body::Ground => u64::MAX - 1,
    };
    for &k in &comp.interfaces {
        let i = &interfaces[k];
        (side(i.a), side(i.b), i.polygon.len()).hash(&mut h);
    }
    h.finish()
}

/// [`super::solve`] with a cache of component outcomes (`block_keys` from
/// [`crate::interfaces::block_keys`]). The cache keeps only this assembly's components
/// afterwards (and those [`StaticsCache::keeping`] asks for).
pub fn solve_cached(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
    block_keys: &[u64],
    cache: &mut StaticsCache,
) -> Result<(StaticsResult, SolveStats), StaticsError> {
    settings.validate()?;
    // Both sources of μ are validated where they enter: the override in `validate`, the
    // scene's material in `Assembly::new`.
    let mu = settings.friction.unwrap_or(assembly.material.friction);
    // The strength, like μ, from the override or the material, once: the stages, the verdict
    // and the cache key read it from the settings.
    let resolved = settings.resolved(assembly);
    let settings = &resolved;
    let mut comps = components(assembly, interfaces);
    if !settings.split_components && comps.len() > 1 {
        comps = vec![merged(comps)];
    }
    let common = common_key(settings, mu, &assembly.gravity);
    let keys: Vec<u64> = comps.iter().map(|c| component_key(assembly, interfaces, c, block_keys, common)).collect();
    let layouts: Vec<u64> = comps.iter().map(|c| layout_key(interfaces, c, common)).collect();
    cache.runs += 1;
    let cached: Vec<Option<ComponentOutcome>> = keys.iter().map(|k| cache.map.get(k).map(|e| e.0.clone())).collect();
    let missing: Vec<usize> = (0..comps.len()).filter(|&i| cached[i].is_none()).collect();
    let stats = SolveStats { solved: missing.len(), reused: comps.len() - missing.len() };
    let to_solve: Vec<Component> = missing.iter().map(|&i| comps[i].clone()).collect();
    let warm: Vec<Option<&WarmStart>> = missing.iter().map(|&i| cache.warm.get(&layouts[i])).collect();
    let (solved, kept): (Vec<_>, Vec<_>) =
        solve_components(assembly, interfaces, &to_solve, mu, settings, &warm).into_iter().unzip();
    cache.warm = next_warm_starts(std::mem::take(&mut cache.warm), &layouts, &missing, kept);
    let (outcomes, used) = merge_outcomes(&comps, &keys, cached, solved);
    cache.store(used);
    Ok((result::collect(assembly, interfaces, &comps, outcomes, mu, settings), stats))
}

/// The iterates to keep for the next run, by layout: those this run's solves kept, and a
/// reused component's own from the last run.
fn next_warm_starts(
    mut last: HashMap<u64, WarmStart>,
    layouts: &[u64],
    missing: &[usize],
    kept: Vec<Option<WarmStart>>,
) -> HashMap<u64, WarmStart> {
    let mut next = HashMap::new();
    for (&i, kept) in missing.iter().zip(kept) {
        if let Some(kept) = kept {
            next.insert(layouts[i], kept);
        }
    }
    let mut reused = vec![true; layouts.len()];
    missing.iter().for_each(|&i| reused[i] = false);
    for (i, layout) in layouts.iter().enumerate() {
        if reused[i]
            && let Some(w) = last.remove(layout)
        {
            next.entry(*layout).or_insert(w);
        }
    }
    next
}

/// Every component's outcome in this run's interface indices, and the entries to store by key
/// (the force points' interfaces local to their component).
fn merge_outcomes(
    comps: &[Component],
    keys: &[u64],
    cached: Vec<Option<ComponentOutcome>>,
    solved: Vec<ComponentOutcome>,
) -> (Vec<ComponentOutcome>, HashMap<u64, ComponentOutcome>) {
    let mut solved = solved.into_iter();
    let mut used = HashMap::new();
    let outcomes = cached
        .into_iter()
        .enumerate()
        .map(|(i, slot)| {
            let local = &comps[i].interfaces;
            match slot {
                Some(mut out) => {
                    // Reused: no work this run; points back to this run's interface indices.
                    used.insert(keys[i], out.clone());
                    out.points.iter_mut().for_each(|p| p.interface = local[p.interface]);
                    (out.assemble_seconds, out.solver_seconds, out.iterations) = (0.0, 0.0, 0);
                    out
                }
                None => {
                    let out = solved.next().expect("one outcome per solved component");
                    let mut stored = out.clone();
                    for p in &mut stored.points {
                        p.interface = local.binary_search(&p.interface).expect("a point of the component");
                    }
                    used.insert(keys[i], stored);
                    out
                }
            }
        })
        .collect();
    (outcomes, used)
}
