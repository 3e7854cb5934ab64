//! Make it stand by mass: per-block densities within bounds — a 3D print's infill, a mix of
//! stones — or per cell of each block (`cells` per axis: its centroid moves), chosen so that the design stands, the lightest such ([`InfillObjective::Stand`]),
//! or so that it carries the largest horizontal load ([`InfillObjective::Robust`]).
//!
//! Each connected component of free blocks is its own problem ([`statics::component_densities`]:
//! the contact problem with the densities as variables; an LP, or an SOCP with the cone).
//! - Stand: the lightest densities that stand, one solve. The answer lies on the edge of what
//!   stands (a lighter block somewhere would tip it): the exact threshold, e.g. the lever rule's
//!   density ratio.
//! - Robust: the largest λ for which some densities stand under the dead load and under λ times
//!   each live case (the scene's live loads, else a horizontal 1 g field along each of
//!   `directions` azimuths, or along `azimuth`), by bisection on λ — a live field scales with
//!   the mass, so λ·ρ is bilinear, but for fixed densities the λ that stand form an interval
//!   holding 0, so "some densities carry λ" is monotone in λ. The densities of the largest λ
//!   found (within `precision` of λ*), the lightest of those.
//!
//! When no density within the bounds stands, the answer says so with the mechanism every
//! admissible mass drives (its least dead-load work over the bounds is positive).
//!
//! The design's own statics and the density problems share the geometry (one cut, validation
//! and detection) and nothing else, so they run side by side on two threads; the infilled
//! design's analysis follows, its solves started from the design's.
//!
//! Densities in kg/m³; the written design carries them by piece name (the scene's `densities`),
//! so `analyze` and the drop tests read the design as infilled.

use super::DesignError;
use crate::geometry::MassProperties;
use crate::model::{Assembly, BlockId, Density, Scene};
use crate::pipeline::{Analysis, AnalysisSettings, Pipeline};
use crate::statics::{
    self, Component, DensityCell, DensityGoal, DensityOutcome, LiveCase, Mechanism, SolverStatus, Verdict,
};
use serde::Serialize;

/// What the densities are chosen for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum InfillObjective {
    /// The lightest densities that stand.
    Stand,
    /// The densities that carry the largest horizontal (or the scene's live) load.
    Robust,
}

/// Settings of [`infill`]; each default written once, in `Default`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InfillSettings {
    /// Every free block's density bounds, kg/m³ (the scene's `density_ranges` first, per piece);
    /// `None`: each block from a quarter of its density to its density (a print from 25 %
    /// infill to solid).
    pub range: Option<(f64, f64)>,
    /// The lightest densities that stand, or the ones that carry the largest horizontal load.
    pub objective: InfillObjective,
    /// Cells per axis of each block's bounding box, each with its own density (1: one density
    /// per block; 2: octants, which move the block's centroid).
    pub cells: usize,
    /// Robust, on a scene without live loads: evenly spaced horizontal azimuths the design
    /// must carry together, or the one `azimuth` (degrees from +x towards +y).
    pub directions: usize,
    /// Robust: the one azimuth to carry (degrees from +x towards +y), instead of `directions`.
    pub azimuth: Option<f64>,
    /// Robust: λ to this fraction of itself.
    pub precision: f64,
}

impl Default for InfillSettings {
    fn default() -> Self {
        Self { range: None, objective: InfillObjective::Stand, cells: 1, directions: 8, azimuth: None, precision: 1e-4 }
    }
}

/// Above this load factor a design is taken to carry any horizontal load (a block's weight 16
/// times over, sideways).
const UNLIMITED: f64 = 16.0;

/// Cells per axis at most (a block of 6³ cells is 216 density variables).
const MAX_CELLS: usize = 6;

impl InfillSettings {
    /// Refuses bounds, cells, directions, an azimuth or a precision out of range.
    pub fn validate(&self) -> Result<(), DesignError> {
        let bad = |why: String| Err(DesignError::Settings(why));
        if let Some((lo, hi)) = self.range
            && !(lo > 0.0 && lo <= hi && hi.is_finite())
        {
            return bad(format!("density range {lo},{hi}: need 0 < low ≤ high, finite (kg/m³)"));
        }
        if !(1..=MAX_CELLS).contains(&self.cells) {
            return bad(format!("{} cells per axis: give 1 (a density per block) to {MAX_CELLS}", self.cells));
        }
        if self.directions == 0 {
            return bad("at least one direction is needed".into());
        }
        if let Some(a) = self.azimuth
            && !a.is_finite()
        {
            return bad(format!("azimuth {a} is not a finite angle (degrees)"));
        }
        if !(self.precision > 0.0 && self.precision < 1.0) {
            return bad(format!("precision {} must be a number in (0, 1)", self.precision));
        }
        Ok(())
    }
}

/// How an infill ended.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum InfillOutcome {
    /// Densities within the bounds make every component stand; the design carries them.
    Stands,
    /// No density within the bounds holds some component: `mechanism` is driven by every
    /// admissible mass.
    Impossible,
    /// A solver did not reach an answer.
    SolverFailed {
        /// How the solve ended.
        status: SolverStatus,
        /// ‖equilibrium residual‖_∞ where it stopped, N.
        residual: f64,
    },
}

/// One free block's (mean) density before and after and its bounds, kg/m³; with cells, each
/// cell's after (x fastest, then y, then z; [`crate::geometry::cells`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BlockDensity {
    /// The block's name.
    pub block: String,
    /// Its (mean) density before, kg/m³.
    pub before: f64,
    /// Its (mean) density after, kg/m³.
    pub after: f64,
    /// Its lowest density allowed, kg/m³.
    pub lo: f64,
    /// Its highest density allowed, kg/m³.
    pub hi: f64,
    /// With cells: each cell's density after, kg/m³ (empty otherwise).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub cells: Vec<f64>,
}

/// What [`infill`] found.
#[derive(Clone, Debug, Serialize)]
pub struct InfillReport {
    /// Stands, impossible, or solver trouble.
    pub outcome: InfillOutcome,
    /// What the densities were chosen for.
    pub objective: InfillObjective,
    /// The free blocks, in block order (after = before where no density was found).
    pub blocks: Vec<BlockDensity>,
    /// The free blocks' mass before and after, kg.
    pub mass_before: f64,
    /// The free blocks' mass after, kg.
    pub mass_after: f64,
    /// The design's verdict before the infill.
    pub verdict_before: Verdict,
    /// The verdict of the written design, analysed again (None when nothing was written).
    pub verdict_after: Option<Verdict>,
    /// Robust: the load factor the densities carry in every case, to `precision`.
    pub load_factor: Option<f64>,
    /// Impossible: the mechanism, normalised so that its least dead-load work over the bounds
    /// is 1 N·m; and that least work before normalisation, as a fraction of the weight.
    pub mechanism: Option<Mechanism>,
    /// Impossible: the mechanism's least dead-load work before normalisation, / the free weight.
    pub least_work: f64,
    /// Density problems solved.
    pub solves: usize,
    /// Wall-clock seconds of the whole infill.
    pub seconds: f64,
    /// The infilled design (the input with `densities` set), when one was found, and its
    /// analysis.
    #[serde(skip)]
    pub design: Option<Scene>,
    /// The infilled design's analysis, when one was written.
    #[serde(skip)]
    pub analysis: Option<Analysis>,
}

/// One component's answer.
struct Found {
    outcome: DensityOutcome,
    load_factor: Option<f64>,
}

/// Chooses densities for `scene` (see the module docs).
pub fn infill(
    scene: &Scene,
    analysis: &AnalysisSettings,
    settings: &InfillSettings,
) -> Result<InfillReport, DesignError> {
    let t = std::time::Instant::now();
    settings.validate()?;
    analysis.statics.validate().map_err(|e| DesignError::Settings(e.to_string()))?;
    // One pipeline for both analyses: the infilled design's differs only in its masses, so its
    // cut pieces, repairs and interfaces are reused, and its solves start from the design's
    // (the same layout, other loads: the answer a cold solve's to the solver's tolerance).
    let mut pipeline = Pipeline::new();
    let mut warm = analysis.clone();
    warm.statics.warm_start = true;
    // The design's statics and the density problems run side by side, one on each core.
    warm.statics.parallel = false;
    let analysis = &warm;
    let prepared = pipeline.prepare(scene, analysis)?;
    let (assembly, interfaces) = (&prepared.assembly, prepared.interfaces.as_slice());
    let statics_settings = analysis.statics.resolved(assembly);
    let mu = statics_settings.friction.unwrap_or(assembly.material.friction);
    let ranges = ranges(scene, assembly, settings)?;
    let cases = cases(assembly, settings);
    let comps = statics::components(assembly, interfaces);
    let grids = grids(assembly, settings.cells);
    // The design's own statics and the density problems need the same geometry and nothing of
    // each other: one on each core.
    let densities = || {
        let mut solves = 0;
        let found: Vec<Found> = comps
            .iter()
            .map(|c| {
                let cells = cells(c, &grids, &ranges);
                let mut solve = |goal: DensityGoal<'_>| {
                    solves += 1;
                    statics::component_densities(assembly, interfaces, c, mu, &statics_settings, &cells, goal)
                };
                component(&mut solve, settings, &cases)
            })
            .collect();
        (found, solves)
    };
    let (solved, (found, solves)) = std::thread::scope(|s| {
        let beside = s.spawn(densities);
        let solved = pipeline.solve(&prepared, analysis);
        (solved, beside.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)))
    });
    let before = prepared.into_analysis(solved?);
    let mut report = summary(&before, &comps, &found, &grids, &ranges, settings.objective);
    report.solves = solves;
    if report.outcome == InfillOutcome::Stands {
        let design = designed(scene, &report);
        let after = pipeline.run(&design, analysis)?;
        report.verdict_after = Some(after.statics.verdict);
        report.design = Some(design);
        report.analysis = Some(after);
    }
    report.seconds = t.elapsed().as_secs_f64();
    Ok(report)
}

/// Each block's bounds, kg/m³ (supports too: never used): the scene's own for the pieces it
/// names, else the settings' range, else from a quarter of the block's density to it.
fn ranges(scene: &Scene, assembly: &Assembly, settings: &InfillSettings) -> Result<Vec<(f64, f64)>, DesignError> {
    let blocks = &assembly.blocks;
    if let Some(name) = scene.density_ranges.keys().find(|n| !blocks.iter().any(|b| &b.name == *n)) {
        return Err(DesignError::Settings(format!("density range of '{name}': no piece of the design has that name")));
    }
    let own = |b: &crate::model::AssemblyBlock| (0.25 * b.density, b.density);
    blocks
        .iter()
        .map(|b| {
            let range = match scene.density_ranges.get(&b.name) {
                Some(&[lo, hi]) => (lo, hi),
                None => settings.range.unwrap_or_else(|| own(b)),
            };
            match range {
                (lo, hi) if lo > 0.0 && lo <= hi && hi.is_finite() => Ok(range),
                (lo, hi) => Err(DesignError::Settings(format!(
                    "density range {lo},{hi} of '{}': need 0 < low ≤ high, finite (kg/m³)",
                    b.name
                ))),
            }
        })
        .collect()
}

/// Each block's cells (k per axis; one, the block itself, for k = 1), supports left empty.
fn grids(assembly: &Assembly, k: usize) -> Vec<Vec<MassProperties>> {
    let eps = assembly.tolerances.weld;
    let cells = |b: &crate::model::AssemblyBlock| match k {
        1 => vec![MassProperties::of_mesh(&b.mesh)],
        _ => crate::geometry::cells::grid(&b.mesh, k, eps),
    };
    assembly.blocks.iter().map(|b| if b.support { Vec::new() } else { cells(b) }).collect()
}

/// The density variables of `comp`: every cell with volume of each of its blocks.
fn cells(comp: &Component, grids: &[Vec<MassProperties>], ranges: &[(f64, f64)]) -> Vec<DensityCell> {
    comp.blocks
        .iter()
        .enumerate()
        .flat_map(|(i, b)| {
            let (lo, hi) = ranges[b.0];
            grids[b.0].iter().filter(|c| c.volume > 0.0).map(move |c| DensityCell {
                block: i,
                volume: c.volume,
                centroid: c.centroid,
                lo,
                hi,
            })
        })
        .collect()
}

/// The live cases a robust design must carry.
fn cases(assembly: &Assembly, settings: &InfillSettings) -> Vec<LiveCase> {
    if settings.objective == InfillObjective::Stand {
        return Vec::new();
    }
    if assembly.has_live_loads() {
        return vec![LiveCase::of(assembly)];
    }
    match settings.azimuth {
        Some(a) => vec![LiveCase::horizontal(assembly, a)],
        None => (0..settings.directions)
            .map(|k| LiveCase::horizontal(assembly, 360.0 * k as f64 / settings.directions as f64))
            .collect(),
    }
}

/// One component: the lightest densities that stand, then (robust) the largest λ carried.
fn component(
    solve: &mut impl FnMut(DensityGoal) -> DensityOutcome,
    settings: &InfillSettings,
    cases: &[LiveCase],
) -> Found {
    let light = solve(DensityGoal::Lightest);
    if light.densities.is_empty() || settings.objective == InfillObjective::Stand {
        return Found { outcome: light, load_factor: None };
    }
    let mut carries = |lambda: f64| {
        let out = solve(DensityGoal::Carries { lambda, cases });
        (!out.densities.is_empty()).then_some(out)
    };
    let (mut lo, mut best, mut hi) = (0.0, light, 1.0);
    // Bracket: double λ until the densities cannot carry it.
    loop {
        match carries(hi) {
            Some(out) if hi < UNLIMITED => (lo, best, hi) = (hi, out, 2.0 * hi),
            Some(out) => return Found { outcome: out, load_factor: Some(hi) },
            None => break,
        }
    }
    while hi - lo > settings.precision * hi {
        let mid = 0.5 * (lo + hi);
        match carries(mid) {
            Some(out) => (lo, best) = (mid, out),
            None => hi = mid,
        }
    }
    Found { outcome: best, load_factor: Some(lo) }
}

/// The report from every component's answer (nothing analysed again yet).
fn summary(
    before: &Analysis,
    comps: &[Component],
    found: &[Found],
    grids: &[Vec<MassProperties>],
    ranges: &[(f64, f64)],
    objective: InfillObjective,
) -> InfillReport {
    let (assembly, interfaces) = (&before.assembly, before.interfaces.as_slice());
    let mut after: Vec<Vec<f64>> = Vec::new();
    after.resize(assembly.blocks.len(), Vec::new());
    for (c, f) in comps.iter().zip(found) {
        let mut densities = f.outcome.densities.iter();
        for b in c.blocks.iter().filter(|_| !f.outcome.densities.is_empty()) {
            let (lo, _) = ranges[b.0];
            // A cell the block does not reach keeps the lower bound (it weighs nothing).
            after[b.0] = grids[b.0]
                .iter()
                .map(|cell| if cell.volume > 0.0 { *densities.next().expect("one per cell") } else { lo })
                .collect();
        }
    }
    let mean = |b: BlockId| {
        let cells = &after[b.0];
        if cells.is_empty() {
            return assembly.block(b).density;
        }
        let mass: f64 = cells.iter().zip(&grids[b.0]).map(|(d, c)| d * c.volume).sum();
        mass / grids[b.0].iter().map(|c| c.volume).sum::<f64>()
    };
    let failed = found.iter().find(|f| f.outcome.densities.is_empty() && f.outcome.motions.is_empty());
    let impossible: Vec<(&Component, &[statics::Motion])> = comps
        .iter()
        .zip(found)
        .filter(|(_, f)| !f.outcome.motions.is_empty())
        .map(|(c, f)| (c, f.outcome.motions.as_slice()))
        .collect();
    let outcome = match (failed, impossible.is_empty()) {
        (_, false) => InfillOutcome::Impossible,
        (Some(f), true) => InfillOutcome::SolverFailed { status: f.outcome.status, residual: f.outcome.residual },
        (None, true) => InfillOutcome::Stands,
    };
    let free: Vec<BlockId> = (0..assembly.blocks.len()).map(BlockId).filter(|b| !assembly.block(*b).support).collect();
    let volume = |b: &BlockId| assembly.block(*b).mass.volume;
    InfillReport {
        blocks: free
            .iter()
            .map(|&b| BlockDensity {
                block: assembly.block(b).name.clone(),
                before: assembly.block(b).density,
                after: mean(b),
                lo: ranges[b.0].0,
                hi: ranges[b.0].1,
                cells: if after[b.0].len() > 1 { after[b.0].clone() } else { Vec::new() },
            })
            .collect(),
        mass_before: free.iter().map(|b| assembly.block(*b).mass()).sum(),
        mass_after: free.iter().map(|&b| mean(b) * volume(&b)).sum(),
        verdict_before: before.statics.verdict,
        verdict_after: None,
        load_factor: found.iter().filter_map(|f| f.load_factor).reduce(f64::min),
        mechanism: (!impossible.is_empty()).then(|| Mechanism::new(assembly, interfaces, &impossible)),
        least_work: found.iter().map(|f| f.outcome.excess).fold(0.0, f64::max),
        outcome,
        objective,
        solves: 0,
        seconds: 0.0,
        design: None,
        analysis: None,
    }
}

/// `scene` with the report's densities on its pieces.
fn designed(scene: &Scene, report: &InfillReport) -> Scene {
    let mut design = scene.clone();
    design.densities.extend(report.blocks.iter().map(|b| {
        let density = if b.cells.is_empty() { Density::Uniform(b.after) } else { Density::Cells(b.cells.clone()) };
        (b.block.clone(), density)
    }));
    design
}
