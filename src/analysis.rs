//! The analysis pipeline as one function: scene → validated assembly → interfaces → statics,
//! with timings. The CLI and the ECS layer both call this (one code path for results).

use crate::decompose;
use crate::geometry::Tolerances;
use crate::interfaces::{self, Interface};
use crate::model::{Assembly, ModelError, Scene};
use crate::statics::{self, StaticsError, StaticsResult, StaticsSettings};
use serde::Serialize;
use std::time::Instant;
use thiserror::Error;

/// Settings of [`analyze`]; defaults as documented on each part.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AnalysisSettings {
    pub tolerances: Tolerances,
    pub statics: StaticsSettings,
}

/// Why the pipeline could not run (bad input or settings, never solver trouble).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AnalysisError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Statics(#[from] StaticsError),
    #[error(transparent)]
    Cut(#[from] crate::decompose::CutError),
}

/// Wall-clock seconds per stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Timings {
    /// Replaying the cut history.
    pub cut: f64,
    pub validate: f64,
    pub detect: f64,
    /// Building the equilibrium problems (summed over components).
    pub assemble: f64,
    /// Inside clarabel (summed over components).
    pub solve: f64,
    /// Wall clock of the whole pipeline.
    pub total: f64,
}

/// Everything the pipeline produced.
#[derive(Clone, Debug)]
pub struct Analysis {
    pub assembly: Assembly,
    pub interfaces: Vec<Interface>,
    pub statics: StaticsResult,
    pub timings: Timings,
}

/// Replays `scene`'s cut history, validates the blocks, detects their interfaces and solves
/// their equilibrium.
pub fn analyze(scene: &Scene, settings: &AnalysisSettings) -> Result<Analysis, AnalysisError> {
    let tc = Instant::now();
    let (resolved, _) = decompose::resolve(scene, &settings.tolerances, &mut decompose::CutCache::new())?;
    let t0 = Instant::now();
    let assembly = Assembly::new(&resolved, &settings.tolerances)?;
    let t1 = Instant::now();
    let interfaces = interfaces::detect(&assembly);
    let t2 = Instant::now();
    let statics = statics::analyze(&assembly, &interfaces, &settings.statics)?;
    let t3 = Instant::now();
    let timings = Timings {
        cut: (t0 - tc).as_secs_f64(),
        validate: (t1 - t0).as_secs_f64(),
        detect: (t2 - t1).as_secs_f64(),
        assemble: statics.assemble_seconds,
        solve: statics.solver_seconds,
        total: (t3 - tc).as_secs_f64(),
    };
    Ok(Analysis { assembly, interfaces, statics, timings })
}
