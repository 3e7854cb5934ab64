//! The worst horizontal direction: λ* of a horizontal acceleration field (1 g, live, on every
//! free block) over evenly spaced azimuths, then refined around the smallest by Brent's method
//! (argmin) between its two neighbours. The scene's dead loads and self-weight stay; its live
//! loads are replaced by the field. Directions run on two threads when there are several.
//!
//! Azimuths in degrees from +x towards +y.

use super::{Robustness, RobustnessError, Safety, assess_parts};
use crate::interfaces::Interface;
use crate::model::Assembly;
use crate::statics::StaticsSettings;
use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::brent::BrentOpt;
use serde::Serialize;

/// How the directions are swept.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepSettings {
    /// Evenly spaced azimuths over the full circle.
    pub directions: usize,
    /// Brent iterations refining the worst direction between its neighbours (0: none).
    pub refine: u64,
}

impl Default for SweepSettings {
    fn default() -> Self {
        // Every 10°.
        Self { directions: 36, refine: 12 }
    }
}

impl SweepSettings {
    pub fn validate(&self) -> Result<(), RobustnessError> {
        if self.directions < 3 {
            return Err(RobustnessError::Settings(format!(
                "{} directions: at least 3 are needed to find a worst one",
                self.directions
            )));
        }
        Ok(())
    }
}

/// λ* per azimuth and the worst direction.
#[derive(Clone, Debug, Serialize)]
pub struct DirectionSweep {
    /// The evenly spaced azimuths (degrees) and their λ* (+∞ where unlimited).
    pub azimuths: Vec<f64>,
    pub load_factors: Vec<f64>,
    /// The refined worst direction (degrees) and its λ*.
    pub worst_azimuth: f64,
    pub worst_load_factor: f64,
    /// The analysis at the worst direction (its mechanism).
    pub worst: Robustness,
    /// Load-factor problems solved (the grid and the refinement).
    pub solves: usize,
}

/// `assembly` with its live loads replaced by a horizontal 1 g field along `azimuth` (deg).
pub fn with_horizontal_field(assembly: &Assembly, azimuth: f64) -> Assembly {
    let mut a = assembly.clone();
    let (s, c) = azimuth.to_radians().sin_cos();
    let g = a.gravity.norm();
    for (load, b) in a.loads.iter_mut().zip(&assembly.blocks) {
        load.live = if b.support { [0.0; 6] } else { [c * g * b.mass(), s * g * b.mass(), 0.0, 0.0, 0.0, 0.0] };
    }
    a
}

/// λ* along `azimuth` (deg); NaN when it cannot be read (a failed solve).
fn factor_at(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
    azimuth: f64,
) -> Result<Robustness, RobustnessError> {
    assess_parts(&with_horizontal_field(assembly, azimuth), interfaces, true, settings)
}

struct Along<'a> {
    assembly: &'a Assembly,
    interfaces: &'a [Interface],
    settings: &'a StaticsSettings,
    solves: &'a std::sync::atomic::AtomicUsize,
}

impl CostFunction for Along<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, azimuth: &f64) -> Result<f64, ArgminError> {
        self.solves.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let r = factor_at(self.assembly, self.interfaces, self.settings, *azimuth)?;
        // An unlimited direction is never the worst; a failed solve neither.
        Ok(if r.load_factor.is_finite() { r.load_factor } else { f64::MAX })
    }
}

/// The worst horizontal direction of a design that stands under its dead load. `progress` is
/// called with (done, total) after each grid direction.
pub fn worst_direction(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
    sweep: &SweepSettings,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<DirectionSweep, RobustnessError> {
    sweep.validate()?;
    settings.validate()?;
    let n = sweep.directions;
    let azimuths: Vec<f64> = (0..n).map(|k| 360.0 * k as f64 / n as f64).collect();
    let results = grid(assembly, interfaces, settings, &azimuths, progress)?;
    if let Some(bad) = results.iter().find(|r| matches!(r.safety, Safety::SolverFailed { .. })) {
        return Err(RobustnessError::Settings(format!("a direction's load factor failed: {:?}", bad.safety)));
    }
    let load_factors: Vec<f64> = results.iter().map(|r| r.load_factor).collect();
    let k = (0..n).min_by(|&a, &b| load_factors[a].total_cmp(&load_factors[b])).expect("at least 3 directions");
    let mut worst_azimuth = azimuths[k];
    let refined = std::sync::atomic::AtomicUsize::new(0);
    if sweep.refine > 0 && load_factors[k].is_finite() {
        let step = 360.0 / n as f64;
        let cost = Along { assembly, interfaces, settings, solves: &refined };
        let solver = BrentOpt::new(azimuths[k] - step, azimuths[k] + step).set_tolerance(1e-8, 1e-3);
        let found = Executor::new(cost, solver).configure(|s| s.max_iters(sweep.refine)).run();
        if let Ok(res) = found {
            let state = res.state();
            if let Some(&best) = state.best_param.as_ref()
                && state.best_cost < load_factors[k]
            {
                worst_azimuth = best.rem_euclid(360.0);
            }
        }
    }
    // The grid's own result when the refinement found nothing lower: no second solve.
    let resolved = worst_azimuth != azimuths[k];
    let worst = if resolved { factor_at(assembly, interfaces, settings, worst_azimuth)? } else { results[k].clone() };
    Ok(DirectionSweep {
        azimuths,
        worst_load_factor: worst.load_factor,
        load_factors,
        worst_azimuth,
        worst,
        solves: n + refined.into_inner() + resolved as usize,
    })
}

/// λ* at each azimuth, on two threads when there is more than one direction.
fn grid(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
    azimuths: &[f64],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Robustness>, RobustnessError> {
    let done = std::sync::atomic::AtomicUsize::new(0);
    let run = |az: &f64| {
        let r = factor_at(assembly, interfaces, settings, *az);
        progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1, azimuths.len());
        r
    };
    let half = azimuths.len().div_ceil(2);
    let (first, second) = azimuths.split_at(half);
    let (a, b) = std::thread::scope(|s| {
        let other = s.spawn(|| second.iter().map(run).collect::<Vec<_>>());
        let mine: Vec<_> = first.iter().map(run).collect();
        (mine, other.join().expect("a direction's thread does not panic"))
    });
    a.into_iter().chain(b).collect()
}
