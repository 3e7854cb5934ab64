//! The analysis pipeline: scene → cut history replayed → validated assembly → interfaces →
//! statics, with timings; blocks that interpenetrate are a warning on the assembly, or with
//! [`AnalysisSettings::strict`] an error. [`Pipeline`] keeps its work between runs (repaired meshes, split pieces,
//! block-pair interfaces and component solutions, each by content), so re-running after an edit
//! recomputes only what the edit touched and reports how much in [`Work`]; [`analyze`] is one
//! run of a fresh pipeline. The CLI and the ECS layer both go through [`Pipeline::run`] (one
//! code path for results).

use crate::geometry::Tolerances;
use crate::history;
use crate::interfaces::{self, Interface};
use crate::model::{Assembly, ModelError, Scene, Warning};
use crate::statics::{self, StaticsError, StaticsResult, StaticsSettings};
use serde::Serialize;
use std::time::Instant;
use thiserror::Error;

/// Settings of [`analyze`]; defaults as documented on each part.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AnalysisSettings {
    /// Interface detection's tolerances (weld, coplanarity, angle, overlap), relative to the model size.
    pub tolerances: Tolerances,
    /// The statics' friction model, solver backend and its tolerances.
    pub statics: StaticsSettings,
    /// Blocks that interpenetrate beyond the coplanarity tolerance
    /// ([`crate::interfaces::penetration`]) are an error ([`ModelError::Overlap`], naming the
    /// deepest pair) instead of a warning on the assembly.
    pub strict: bool,
}

/// Why the pipeline could not run (bad input or settings, never solver trouble).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AnalysisError {
    /// The scene does not make a valid assembly (mesh, coordinates, overlapping blocks).
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The statics refused the settings or the assembly (not solver trouble, which is a status).
    #[error(transparent)]
    Statics(#[from] StaticsError),
    /// The cut history cannot be replayed on the scene's shapes.
    #[error(transparent)]
    Cut(#[from] crate::history::CutError),
}

/// Wall-clock seconds per stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Timings {
    /// Replaying the cut history.
    pub cut: f64,
    /// Validating the blocks and checking that they do not interpenetrate.
    pub validate: f64,
    /// Detecting the contact interfaces between blocks (and the ground).
    pub detect: f64,
    /// Building the equilibrium problems (summed over components).
    pub assemble: f64,
    /// Inside the interior-point solver that ran — the structured backend by default, clarabel
    /// with `Backend::Clarabel` (summed over components).
    pub solve: f64,
    /// Wall clock of the whole pipeline.
    pub total: f64,
}

/// What a run computed and what it took from the pipeline's memory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Work {
    /// Plane splits computed / reused while replaying the cut history.
    pub pieces_cut: usize,
    /// Plane splits taken from the cache instead of computed.
    pub pieces_reused: usize,
    /// Block pairs (and block–ground pairs) whose interfaces were detected / reused.
    pub pairs_detected: usize,
    /// Block pairs whose interfaces were taken from the cache.
    pub pairs_reused: usize,
    /// Connected components solved / whose solution was reused.
    pub components_solved: usize,
    /// Connected components whose statics was taken from the cache.
    pub components_reused: usize,
}

/// Everything the pipeline produced.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The validated blocks (meshes, mass properties, supports) the statics ran on.
    pub assembly: Assembly,
    /// The contact interfaces detected between them, in the order the statics' results use.
    pub interfaces: Vec<Interface>,
    /// The graded verdict, the forces per interface and the solver's report.
    pub statics: StaticsResult,
    /// Wall-clock seconds per stage.
    pub timings: Timings,
    /// What this run computed and what it reused from the pipeline's caches.
    pub work: Work,
}

/// The pipeline with memory between runs (see the module docs). Each cache keeps only what the
/// last run used, so memory follows the design, not the edit history.
#[derive(Debug, Default)]
pub struct Pipeline {
    cuts: history::CutCache,
    repairs: crate::geometry::RepairCache,
    pairs: interfaces::DetectCache,
    overlaps: interfaces::OverlapCache,
    components: statics::StaticsCache,
}

/// Replays `scene`'s cut history, validates the blocks, detects their interfaces and solves
/// their equilibrium (one run of a fresh [`Pipeline`]).
pub fn analyze(scene: &Scene, settings: &AnalysisSettings) -> Result<Analysis, AnalysisError> {
    Pipeline::default().run(scene, settings)
}

impl Pipeline {
    /// A pipeline with empty caches (the first run computes everything).
    pub fn new() -> Self {
        Self::default()
    }

    /// A pipeline whose statics also keeps the `keep` most recently used component outcomes of
    /// earlier runs ([`statics::StaticsCache::keeping`]).
    pub fn keeping_components(keep: usize) -> Self {
        Self { components: statics::StaticsCache::keeping(keep), ..Self::default() }
    }

    /// One run; the results are those of [`analyze`] whatever the pipeline ran before.
    pub fn run(&mut self, scene: &Scene, settings: &AnalysisSettings) -> Result<Analysis, AnalysisError> {
        let prepared = self.prepare(scene, settings)?;
        let solved = self.solve(&prepared, settings)?;
        Ok(prepared.into_analysis(solved))
    }

    /// The run up to the statics: the cut history replayed, the blocks validated, their
    /// interfaces detected. What needs the geometry but not the equilibrium (the infill's
    /// density problem) can run beside [`Self::solve`].
    pub(crate) fn prepare(&mut self, scene: &Scene, settings: &AnalysisSettings) -> Result<Prepared, AnalysisError> {
        let start = Instant::now();
        let (resolved, cut_stats) = history::resolve(scene, &settings.tolerances, &mut self.cuts)?;
        let t0 = Instant::now();
        let mut assembly = Assembly::new_cached(&resolved, &settings.tolerances, &mut self.repairs)?;
        let keys = interfaces::block_keys(&assembly);
        let overlaps = interfaces::overlaps_cached(&assembly, &keys, &mut self.overlaps);
        if settings.strict
            && let Some(deepest) = overlaps.iter().max_by(|a, b| a.relative().total_cmp(&b.relative()))
        {
            return Err(ModelError::Overlap { overlap: deepest.clone(), others: overlaps.len() - 1 }.into());
        }
        // Ahead of the load and repair warnings: the one that can make the statics wrong.
        assembly.warnings.splice(0..0, overlaps.into_iter().map(Warning::Overlap));
        let t1 = Instant::now();
        let (interfaces, detect_stats) = interfaces::detect_cached(&assembly, &keys, &mut self.pairs);
        let t2 = Instant::now();
        let timings = Timings {
            cut: (t0 - start).as_secs_f64(),
            validate: (t1 - t0).as_secs_f64(),
            detect: (t2 - t1).as_secs_f64(),
            ..Timings::default()
        };
        let work = Work {
            pieces_cut: cut_stats.splits,
            pieces_reused: cut_stats.cached,
            pairs_detected: detect_stats.detected,
            pairs_reused: detect_stats.reused,
            ..Work::default()
        };
        Ok(Prepared { assembly, interfaces, keys, start, timings, work })
    }

    /// The statics of a prepared run.
    pub(crate) fn solve(&mut self, prepared: &Prepared, settings: &AnalysisSettings) -> Result<Solved, AnalysisError> {
        let p = prepared;
        let (statics, stats) =
            statics::solve_cached(&p.assembly, &p.interfaces, &settings.statics, &p.keys, &mut self.components)?;
        Ok(Solved { statics, stats, end: Instant::now() })
    }
}

/// A run up to the statics ([`Pipeline::prepare`]).
pub(crate) struct Prepared {
    pub assembly: Assembly,
    pub interfaces: Vec<Interface>,
    keys: Vec<u64>,
    start: Instant,
    timings: Timings,
    work: Work,
}

/// The statics of a prepared run ([`Pipeline::solve`]).
pub(crate) struct Solved {
    statics: StaticsResult,
    stats: statics::SolveStats,
    /// When the statics ended: the run's total stops there, whatever ran beside it.
    end: Instant,
}

impl Prepared {
    /// The run's analysis, timed from its start to the end of its statics.
    pub(crate) fn into_analysis(self, solved: Solved) -> Analysis {
        let Solved { statics, stats, end } = solved;
        let timings = Timings {
            assemble: statics.assemble_seconds,
            solve: statics.solver_seconds,
            total: (end - self.start).as_secs_f64(),
            ..self.timings
        };
        let work = Work { components_solved: stats.solved, components_reused: stats.reused, ..self.work };
        Analysis { assembly: self.assembly, interfaces: self.interfaces, statics, timings, work }
    }
}
