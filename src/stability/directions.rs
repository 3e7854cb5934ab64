//! The worst horizontal direction: λ* of a horizontal acceleration field (1 g, live, on every
//! free block) over evenly spaced azimuths, then refined between the smallest one's neighbours.
//! The scene's dead loads and self-weight stay; its live loads are replaced by the field.
//! Directions run on two threads; the refinement beside the rest of the grid (`Schedule`).
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
use std::sync::atomic::{AtomicUsize, Ordering};

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
    /// Refuses fewer than 3 directions (no worst one can be bracketed).
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
    /// λ* at each azimuth, in the same order (+∞ where unlimited).
    pub load_factors: Vec<f64>,
    /// The refined worst direction (degrees) and its λ*.
    pub worst_azimuth: f64,
    /// λ* at the refined worst direction.
    pub worst_load_factor: f64,
    /// The analysis at the worst direction (its mechanism).
    pub worst: Robustness,
    /// Load-factor problems solved: the grid and its refinement (two refinements when the
    /// overlapped schedule refined next to a lowest the rest of the grid then undercut).
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
    // The grid takes both cores, a direction on each: each solve keeps to its own.
    let settings = &StaticsSettings { parallel: false, ..settings.clone() };
    let grid = Grid { assembly, interfaces, settings, sweep, azimuths: &azimuths, progress, done: AtomicUsize::new(0) };
    let schedule = if sweep.refine > 0 { Schedule::Overlapped } else { Schedule::Serial };
    let (results, (worst_azimuth, worst, refined)) = grid.run(schedule)?;
    let load_factors: Vec<f64> = results.iter().map(|r| r.load_factor).collect();
    Ok(DirectionSweep {
        azimuths,
        worst_load_factor: worst.load_factor,
        load_factors,
        worst_azimuth,
        worst,
        solves: n + refined,
    })
}

/// In which order the grid and the refinement run; both give the same azimuths, load factors
/// and worst direction (the same solves, read the same way).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Schedule {
    /// The whole grid on two threads, then the refinement (one solve at a time).
    Serial,
    /// Every other azimuth first, then the two beside the lowest, then the refinement next to
    /// the lowest so far on one thread while the other solves the rest of the grid (and the
    /// first joins it when done): the refinement's solves come one at a time, and would
    /// otherwise leave a core idle. When the whole grid's lowest is elsewhere, the refinement
    /// runs again there (its solves count).
    Overlapped,
}

/// A refined worst direction: its azimuth (degrees), its analysis, and the solves it took.
type Refined = (f64, Robustness, usize);

/// One sweep's grid: the solves of its azimuths and their refinement.
struct Grid<'a> {
    assembly: &'a Assembly,
    interfaces: &'a [Interface],
    settings: &'a StaticsSettings,
    sweep: &'a DirectionSettings,
    azimuths: &'a [f64],
    progress: &'a (dyn Fn(usize, usize) + Sync),
    done: AtomicUsize,
}

impl Grid<'_> {
    /// Every azimuth's analysis and the refined worst direction.
    fn run(&self, schedule: Schedule) -> Result<(Vec<Robustness>, Refined), RobustnessError> {
        let n = self.azimuths.len();
        let mut results: Vec<Option<Robustness>> = vec![None; n];
        let mut early = None;
        if schedule == Schedule::Overlapped {
            place(&mut results, self.solve_many(&(0..n).step_by(2).collect::<Vec<_>>())?);
            let c = lowest(&results);
            let near: Vec<usize> =
                [(c + n - 1) % n, (c + 1) % n].into_iter().filter(|&i| results[i].is_none()).collect();
            place(&mut results, self.solve_many(&near)?);
            let guess = lowest(&results);
            let rest: Vec<usize> = (0..n).filter(|&i| results[i].is_none()).collect();
            let queue = Queue::new(&rest);
            let (refined, mine, other) = std::thread::scope(|s| {
                let other = s.spawn(|| self.drain(&queue));
                let refined = self.refine_if_finite(&results, guess);
                (refined, self.drain(&queue), other.join().expect("a direction's thread does not panic"))
            });
            place(&mut results, mine?);
            place(&mut results, other?);
            early = Some((guess, refined));
        } else {
            place(&mut results, self.solve_many(&(0..n).collect::<Vec<_>>())?);
        }
        if let Some(bad) = results.iter().flatten().find(|r| matches!(r.safety, Safety::SolverFailed { .. })) {
            return Err(RobustnessError::Settings(format!("a direction's load factor failed: {:?}", bad.safety)));
        }
        let k = lowest(&results);
        let refined = match early {
            Some((guess, refined)) if guess == k => refined,
            Some((_, (_, _, wasted))) => {
                let (az, r, solves) = self.refine_if_finite(&results, k);
                (az, r, solves + wasted)
            }
            None => self.refine_if_finite(&results, k),
        };
        Ok((results.into_iter().map(|r| r.expect("every azimuth solved")).collect(), refined))
    }

    /// λ* along azimuth `i`, with the progress reported.
    fn solve(&self, i: usize) -> Result<Robustness, RobustnessError> {
        let r = factor_at(self.assembly, self.interfaces, self.settings, self.azimuths[i]);
        (self.progress)(self.done.fetch_add(1, Ordering::Relaxed) + 1, self.azimuths.len());
        r
    }

    /// The azimuths `indices` on two threads, each taking the next one left.
    fn solve_many(&self, indices: &[usize]) -> Result<Vec<(usize, Robustness)>, RobustnessError> {
        let queue = Queue::new(indices);
        let (a, b) = std::thread::scope(|s| {
            let other = s.spawn(|| self.drain(&queue));
            (self.drain(&queue), other.join().expect("a direction's thread does not panic"))
        });
        Ok(a?.into_iter().chain(b?).collect())
    }

    /// Solves the azimuths `queue` has left until it is empty (or a solve fails).
    fn drain(&self, queue: &Queue) -> Result<Vec<(usize, Robustness)>, RobustnessError> {
        let mut out = Vec::new();
        while let Some(i) = queue.next() {
            out.push((i, self.solve(i)?));
        }
        Ok(out)
    }

    /// [`refine`] next to `k` when its λ* is finite and refining is asked for; else `k` as is.
    fn refine_if_finite(&self, results: &[Option<Robustness>], k: usize) -> Refined {
        let at_k = results[k].as_ref().expect("the lowest is solved");
        if self.sweep.refine == 0 || !at_k.load_factor.is_finite() {
            return (self.azimuths[k], at_k.clone(), 0);
        }
        refine(self.assembly, self.interfaces, self.settings, self.sweep, self.azimuths, results, k)
    }
}

/// Puts each solved azimuth's analysis in its place.
fn place(results: &mut [Option<Robustness>], solved: Vec<(usize, Robustness)>) {
    for (i, r) in solved {
        results[i] = Some(r);
    }
}

/// Azimuth indices handed out one at a time to the threads that solve them: which thread
/// solves which does not change any solve.
struct Queue<'a> {
    indices: &'a [usize],
    next: AtomicUsize,
}

impl<'a> Queue<'a> {
    fn new(indices: &'a [usize]) -> Self {
        Self { indices, next: AtomicUsize::new(0) }
    }

    fn next(&self) -> Option<usize> {
        self.indices.get(self.next.fetch_add(1, Ordering::Relaxed)).copied()
    }
}

/// The solved azimuth with the lowest λ* (the first of equals, in azimuth order).
fn lowest(results: &[Option<Robustness>]) -> usize {
    (0..results.len())
        .filter_map(|i| results[i].as_ref().map(|r| (i, r.load_factor)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("some azimuth is solved")
        .0
}

/// The root of φ next to the grid's worst direction `k`, from the grid's own solves at its
/// bracket: the lowest λ* solved (the grid's when the root finder cannot run, e.g. when φ
/// does not change sign or a neighbour is unlimited), its analysis, and the solves it took.
/// Reads only `k` and its two neighbours of `results`.
fn refine(
    assembly: &Assembly,
    interfaces: &[Interface],
    settings: &StaticsSettings,
    sweep: &DirectionSettings,
    azimuths: &[f64],
    results: &[Option<Robustness>],
    k: usize,
) -> Refined {
    let n = azimuths.len();
    let step = 360.0 / n as f64;
    let at_k = results[k].as_ref().expect("the lowest is solved");
    // Grid neighbour i of k: its unwrapped azimuth and its solve.
    let at = |i: isize| {
        let r = results[i.rem_euclid(n as isize) as usize].as_ref()?;
        Some((azimuths[k] + step * (i - k as isize) as f64, r))
    };
    let phi = |p: Option<(f64, &Robustness)>| p.and_then(|(az, r)| normal_offset(assembly, r, az));
    let ki = k as isize;
    let (lo, hi) = match phi(at(ki)) {
        Some(p) if p > 0.0 => (at(ki), at(ki + 1)),
        Some(p) if p < 0.0 => (at(ki - 1), at(ki)),
        _ => return (azimuths[k], at_k.clone(), 0),
    };
    let (Some(lo), Some(hi)) = (lo, hi) else { return (azimuths[k], at_k.clone(), 0) };
    if !matches!((phi(Some(lo)), phi(Some(hi))), (Some(a), Some(b)) if a >= 0.0 && b <= 0.0) {
        return (azimuths[k], at_k.clone(), 0);
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
        Some((az, r)) if r.load_factor < at_k.load_factor => (az.rem_euclid(360.0), r, solves),
        _ => (azimuths[k], at_k.clone(), solves),
    }
}

/// Invariant: the overlapped schedule is a change of order only — the same load factor at
/// every azimuth, the same worst direction and λ* as the serial one, bit for bit — here where
/// the whole grid's lowest is not beside the lowest of every other azimuth, so the refinement
/// runs twice. Against the closed form: two blocks 1 high on a base, sliding at μ = 0.8
/// (cone); A 0.5 × 2 turned by 10°, tipping at λ_A(θ) = min(0.5 / |cos(θ − 10°)|,
/// 2 / |sin(θ − 10°)|); B 2 × 0.45 along the axes, at λ_B(θ) = min(2 / |cos θ|,
/// 0.45 / |sin θ|). Every 60° A is the lowest (0.5077 at 0°); every 30° B (0.45 at 90°).
#[cfg(test)]
mod schedules_agree {
    use super::*;
    use crate::geometry::mesh::Mesh;
    use crate::model::{Block, Scene};
    use crate::pipeline::{AnalysisSettings, analyze};
    use crate::statics::FrictionModel;

    fn two_blocks() -> Scene {
        let turn = 10f64.to_radians();
        let a: Vec<[f64; 2]> = [[-0.25, -1.0], [0.25, -1.0], [0.25, 1.0], [-0.25, 1.0]]
            .iter()
            .map(|[x, y]| [x * turn.cos() - y * turn.sin(), x * turn.sin() + y * turn.cos()])
            .collect();
        let mut scene = Scene::new(
            "two blocks",
            vec![
                Block::new("base", Mesh::cuboid([-2.0, -2.0, -1.0].into(), [6.0, 3.0, 0.0].into())).support(true),
                Block::new("A", Mesh::extrude_z(&a, 0.0, 1.0)),
                Block::new("B", Mesh::cuboid([3.0, 0.0, 0.0].into(), [5.0, 0.45, 1.0].into())),
            ],
        );
        scene.material.friction = 0.8;
        scene
    }

    #[test]
    fn overlapped_gives_the_serial_answer() {
        let mut settings = AnalysisSettings::default();
        settings.statics.friction_model = FrictionModel::Cone;
        let a = analyze(&two_blocks(), &settings).unwrap();
        let sweep = DirectionSettings { directions: 12, ..Default::default() };
        let azimuths: Vec<f64> = (0..12).map(|k| 30.0 * k as f64).collect();
        let run = |schedule| {
            let grid = Grid {
                assembly: &a.assembly,
                interfaces: &a.interfaces,
                settings: &settings.statics,
                sweep: &sweep,
                azimuths: &azimuths,
                progress: &|_, _| {},
                done: AtomicUsize::new(0),
            };
            grid.run(schedule).unwrap()
        };
        let (serial, (s_az, s_worst, s_solves)) = run(Schedule::Serial);
        let (overlapped, (o_az, o_worst, o_solves)) = run(Schedule::Overlapped);
        for (k, (s, o)) in serial.iter().zip(&overlapped).enumerate() {
            assert_eq!(s.load_factor.to_bits(), o.load_factor.to_bits(), "azimuth {}", azimuths[k]);
            let (ta, tb) = ((azimuths[k] - 10.0).to_radians(), azimuths[k].to_radians());
            let lambda_a = (0.5 / ta.cos().abs()).min(2.0 / ta.sin().abs());
            let lambda_b = (2.0 / tb.cos().abs()).min(0.45 / tb.sin().abs());
            let closed = lambda_a.min(lambda_b).min(0.8);
            assert!(
                (s.load_factor - closed).abs() <= 1e-6 * closed,
                "λ* at {}°: {} against {closed}",
                azimuths[k],
                s.load_factor
            );
        }
        assert_eq!((s_az.to_bits(), s_worst.load_factor.to_bits()), (o_az.to_bits(), o_worst.load_factor.to_bits()));
        assert!((s_worst.load_factor - 0.45).abs() <= 1e-6 * 0.45, "the worst: {}", s_worst.load_factor);
        let off = (s_az - 90.0).rem_euclid(180.0);
        assert!(off.min(180.0 - off) < 1e-3, "across B's narrow side: {s_az}");
        // The refinement next to A's lowest ran first, and its solves count.
        assert!(o_solves > s_solves, "{o_solves} against {s_solves}");
    }
}
