//! The worst horizontal direction: λ* of a horizontal acceleration field (1 g, live, on every
//! free block) over evenly spaced azimuths, then refined between the smallest one's neighbours.
//! The scene's dead loads and self-weight stay; its live loads are replaced by the field.
//! Directions run on two threads when there are several.
//!
//! The refinement reads each solve's dual. The horizontal accelerations a = (a_x, a_y) that the
//! design carries form a convex set K (forces are linear in the load), λ*(θ) is K's radial
//! function, and the mechanism at θ is a supporting line of K at λ*(θ)·(cos θ, sin θ): its
//! normal n = (work of a unit x field, work of a unit y field). With φ = ∠n − θ,
//! dλ*/dθ = −λ* tan φ, so the worst direction between two neighbours is the root of φ — found
//! by Brent's root finder (argmin) from the bracket the grid already solved, a few solves where
//! minimising λ* itself took a dozen.
//!
//! Azimuths in degrees from +x towards +y.

use super::{Robustness, RobustnessError, Safety, assess_parts};
use crate::interfaces::Interface;
use crate::model::Assembly;
use crate::statics::StaticsSettings;
use serde::Serialize;
use std::sync::Mutex;

/// How the directions are swept.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DirectionSettings {
    /// Evenly spaced azimuths over the full circle.
    pub directions: usize,
    /// Largest number of root-finder solves refining the worst direction between its
    /// neighbours (0: none).
    pub refine: u64,
}

impl Default for DirectionSettings {
    fn default() -> Self {
        // Every 10°.
        Self { directions: 36, refine: 12 }
    }
}

impl DirectionSettings {
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
        let per_kg = if b.support { [0.0; 3] } else { [c * g, s * g, 0.0] };
        load.live = [per_kg[0] * b.mass(), per_kg[1] * b.mass(), 0.0, 0.0, 0.0, 0.0];
        load.live_per_kg = per_kg;
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

/// φ = ∠n − θ (degrees, in (−180°, 180°]) of a collapse at `azimuth`: n is the work of a unit
/// x and a unit y field in its mechanism (see the module docs; the blocks' masses are the same
/// whichever field the assembly carries). `None` where there is no mechanism to read
/// (unlimited, failed).
fn normal_offset(assembly: &Assembly, r: &Robustness, azimuth: f64) -> Option<f64> {
    let mechanism = r.mechanism.as_ref().filter(|_| r.load_factor.is_finite())?;
    let g = assembly.gravity.norm();
    let mut n = [0.0; 2];
    for (b, m) in assembly.blocks.iter().zip(&mechanism.motion) {
        if !b.support {
            n[0] += g * b.mass() * m[0];
            n[1] += g * b.mass() * m[1];
        }
    }
    let phi = n[1].atan2(n[0]).to_degrees() - azimuth;
    Some(180.0 - (180.0 - phi).rem_euclid(360.0))
}

/// The root finder's function: φ along an azimuth, every solve kept (the bracket's ends are
/// the grid's, given beforehand, so that they are not solved again).
struct Offset<'a> {
    assembly: &'a Assembly,
    interfaces: &'a [Interface],
    settings: &'a StaticsSettings,
    solved: &'a Mutex<Vec<(f64, Robustness)>>,
}

impl Offset<'_> {
    fn at(&self, azimuth: f64) -> Result<f64, String> {
        let known = self.solved.lock().expect("not poisoned").iter().find(|(a, _)| *a == azimuth).map(|k| k.1.clone());
        let r = match known {
            Some(r) => r,
            None => {
                let r = factor_at(self.assembly, self.interfaces, self.settings, azimuth).map_err(|e| e.to_string())?;
                self.solved.lock().expect("not poisoned").push((azimuth, r.clone()));
                r
            }
        };
        normal_offset(self.assembly, &r, azimuth).ok_or_else(|| format!("no mechanism at {azimuth}°"))
    }
}

/// The worst horizontal direction of a design that stands under its dead load. `progress` is
/// called with (done, total) after each grid direction.
pub fn worst_direction(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
    sweep: &DirectionSettings,
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
    let (worst_azimuth, worst, refined) = if sweep.refine > 0 && load_factors[k].is_finite() {
        refine(assembly, interfaces, settings, sweep, &azimuths, &results, k)
    } else {
        (azimuths[k], results[k].clone(), 0)
    };
    Ok(DirectionSweep {
        azimuths,
        worst_load_factor: worst.load_factor,
        load_factors,
        worst_azimuth,
        worst,
        solves: n + refined,
    })
}

/// The root of φ next to the grid's worst direction `k`, from the grid's own solves at its
/// bracket: the lowest λ* solved (the grid's when the root finder cannot run, e.g. when φ
/// does not change sign or a neighbour is unlimited), its analysis, and the solves it took.
fn refine(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
    sweep: &DirectionSettings,
    azimuths: &[f64],
    results: &[Robustness],
    k: usize,
) -> (f64, Robustness, usize) {
    let n = azimuths.len();
    let step = 360.0 / n as f64;
    // Grid neighbour i of k: its unwrapped azimuth and its solve.
    let at = |i: isize| (azimuths[k] + step * (i - k as isize) as f64, &results[i.rem_euclid(n as isize) as usize]);
    let phi = |(az, r): (f64, &Robustness)| normal_offset(assembly, r, az);
    let ki = k as isize;
    let (lo, hi) = match phi(at(ki)) {
        Some(p) if p > 0.0 => (at(ki), at(ki + 1)),
        Some(p) if p < 0.0 => (at(ki - 1), at(ki)),
        _ => return (azimuths[k], results[k].clone(), 0),
    };
    if !matches!((phi(lo), phi(hi)), (Some(a), Some(b)) if a >= 0.0 && b <= 0.0) {
        return (azimuths[k], results[k].clone(), 0);
    }
    let bracket = vec![(lo.0, lo.1.clone()), (hi.0, hi.1.clone())];
    let solved = Mutex::new(bracket);
    let offset = Offset { assembly, interfaces, settings, solved: &solved };
    // A failed solve ends the search; what was solved so far still counts.
    let _ = crate::optimise::brent_root(&|az| offset.at(az), lo.0, hi.0, 1e-4, sweep.refine);
    let solved = solved.into_inner().expect("not poisoned");
    // Everything after the bracket's two ends was solved here.
    let solves = solved.len() - 2;
    let best = solved
        .into_iter()
        .filter(|(_, r)| r.load_factor.is_finite())
        .min_by(|a, b| a.1.load_factor.total_cmp(&b.1.load_factor));
    match best {
        Some((az, r)) if r.load_factor < results[k].load_factor => (az.rem_euclid(360.0), r, solves),
        _ => (azimuths[k], results[k].clone(), solves),
    }
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
