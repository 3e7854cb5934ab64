//! The run both engines share: a drop test stepped on either engine ([`Stepper`]), each free
//! block's motion tracked against the fall criteria (drift relative to the block's size,
//! rotation), the verdict ([`DropResult`]) and the motion sampled for playback
//! ([`Trajectory`]). Units SI, z up.

use super::exact::{self, ExactStats};
use super::ground_motion::GroundMotion;
use super::rapier::Simulation;
use super::scene::SupportPath;
use super::settings::{DropError, DropSettings, Engine};
use crate::model::Assembly;
use serde::Serialize;
use std::time::Instant;

/// Motion of one free block over the run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BlockMotion {
    /// The block's name.
    pub name: String,
    /// Largest centroid displacement from the start, m.
    pub max_drift: f64,
    /// `max_drift` / the block's size.
    pub max_drift_ratio: f64,
    /// Largest rotation from the start, rad.
    pub max_rotation: f64,
    /// Kinetic energy at the end, J.
    pub final_kinetic_energy: f64,
    /// When the block first moved more than a tenth of the tolerances, s.
    pub first_motion: Option<f64>,
    /// Its centroid's displacement at the end, m (a shake's residual displacement).
    pub final_drift: f64,
    /// Its rotation at the end, rad.
    pub final_rotation: f64,
    /// The largest fall of its centroid below its start, m.
    pub max_drop: f64,
    /// When it fell — turned by more than [`DropSettings::fall_rotation`] or dropped by more
    /// than [`DropSettings::fall_drop`] of its size, beyond any recovery — s.
    pub fell: Option<f64>,
}

/// The drop test's outcome.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DropResult {
    /// The engine that ran it.
    pub engine: Engine,
    /// Every free block stayed within the drift and rotation tolerances, and every solve
    /// answered.
    pub stands: bool,
    /// Largest drift over the free blocks, a fraction of the block's size.
    pub max_drift: f64,
    /// Largest rotation over the free blocks, rad.
    pub max_rotation: f64,
    /// The block that moved most (relative to the tolerances), if any block is free.
    pub worst_block: Option<String>,
    /// When the first block fell (see [`BlockMotion::fell`]), s: a shake's collapse.
    pub fell: Option<f64>,
    /// Simulated time, s.
    pub simulated_s: f64,
    /// Wall time of the run, s.
    pub wall_s: f64,
    /// Steps of dt taken.
    pub steps: usize,
    /// Largest relative volume error of a collider: a nearly convex block's hull or a
    /// non-convex block's convex decomposition (0 when all blocks are convex).
    pub max_volume_error: f64,
    /// The deepest overlap between two blocks' colliders at the start (the input blocks
    /// overlap there; rapier pushes them apart first), as a fraction of the smaller block's
    /// size; 0 when none exceeds 1e-3 of the median block size.
    pub max_initial_overlap: f64,
    /// The two blocks of that overlap.
    pub initial_overlap_blocks: Option<[String; 2]>,
    /// At rest at the end: the free blocks' kinetic energy is at most 1e-6 of their weight
    /// times the median block size. A block beyond the tolerances that has come to rest
    /// settled (soft contacts, overlapping input); one still moving is falling.
    pub at_rest: bool,
    /// Every free block's motion.
    pub blocks: Vec<BlockMotion>,
    /// The exact engine's account (solves, status, overlap, energy balance).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exact: Option<ExactStats>,
}

/// The engine a drop test (or a settlement's engine run) runs on.
pub enum Stepper {
    /// rapier3d's soft contacts.
    Rapier(Box<Simulation>),
    /// The exact-contact engine.
    Exact(Box<exact::World>),
}

impl Stepper {
    /// The engine `settings` name, with the supports `paths` name moving along them
    /// ([`Self::step_supports`]).
    pub fn with_paths(assembly: &Assembly, settings: &DropSettings, paths: &[SupportPath]) -> Self {
        match settings.engine {
            Engine::Rapier => Self::Rapier(Box::new(Simulation::with_paths(assembly, settings, paths))),
            Engine::Exact => Self::Exact(Box::new(exact::World::with_paths(assembly, settings, paths))),
        }
    }

    fn step(&mut self) {
        match self {
            Self::Rapier(s) => s.step(),
            Self::Exact(w) => w.step(),
        }
    }

    /// The base's acceleration for the next steps (m/s²): the engines step in its frame
    /// ([`super::ground_motion`]).
    pub fn set_base_acceleration(&mut self, a: crate::geometry::Vector3) {
        match self {
            Self::Rapier(s) => s.set_base_acceleration(a),
            Self::Exact(w) => w.set_base_acceleration(a),
        }
    }

    /// One step in which every moved support translates by `displacement` (m).
    pub fn step_supports_by(&mut self, displacement: crate::geometry::Vector3) {
        match self {
            Self::Rapier(s) => s.step_supports_by(displacement),
            Self::Exact(w) => w.step_supports_by(displacement),
        }
    }

    /// One step in which every moved support covers `fraction` of its path.
    pub fn step_supports(&mut self, fraction: f64) {
        match self {
            Self::Rapier(s) => s.step_supports(fraction),
            Self::Exact(w) => w.step_supports(fraction),
        }
    }

    /// The fastest block, m/s: the exact engine's fastest vertex; in rapier, the centroid's speed
    /// plus the angular speed × half the block's box diagonal.
    pub fn fastest(&self, assembly: &Assembly) -> f64 {
        match self {
            Self::Exact(w) => w.fastest_vertex(),
            Self::Rapier(s) => (0..assembly.blocks.len())
                .filter(|&i| !assembly.blocks[i].support)
                .map(|i| {
                    let (v, w) = s.speeds(i);
                    v + w * 0.5 * assembly.blocks[i].aabb.diagonal()
                })
                .fold(0.0, f64::max),
        }
    }

    fn displacement(&self, i: usize) -> (f64, f64) {
        match self {
            Self::Rapier(s) => s.displacement(i),
            Self::Exact(w) => w.displacement(i),
        }
    }

    fn kinetic_energy(&self, i: usize) -> f64 {
        match self {
            Self::Rapier(s) => s.kinetic_energy(i),
            Self::Exact(w) => w.kinetic_energy(i),
        }
    }
}

/// Runs the drop test of `assembly` (see the module docs).
pub fn drop_test(assembly: &Assembly, settings: &DropSettings) -> Result<DropResult, DropError> {
    let mut run = DropRun::new(assembly, settings)?;
    run.advance(run.total_steps());
    Ok(run.result())
}

/// A drop test's motion sampled for playback: the times (s) and, per frame, every block's
/// centroid (m) and rotation since the start ([w, x, y, z]).
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// The engine that moved them.
    pub engine: Engine,
    /// The frames' times, s.
    pub times: Vec<f64>,
    /// Per frame, per block: its centroid (m) and its rotation since the start ([w, x, y, z]).
    pub poses: Vec<Vec<(crate::geometry::Point3, [f64; 4])>>,
}

/// Runs the drop test of `assembly`, recording every block's pose about `fps` times per
/// simulated second (the start and the end included): the motion behind the verdict, for
/// [`crate::viz::gltf::animation_glb`].
pub fn record(assembly: &Assembly, settings: &DropSettings, fps: f64) -> Result<(DropResult, Trajectory), DropError> {
    if !(fps > 0.0 && fps.is_finite()) {
        return Err(DropError::NotPositive { name: "frames per second", value: fps });
    }
    record_run(DropRun::new(assembly, settings)?, assembly, fps)
}

/// Runs `run` to its end, recording every block's pose about `fps` times per simulated
/// second (see [`record`]).
pub fn record_run(mut run: DropRun, assembly: &Assembly, fps: f64) -> Result<(DropResult, Trajectory), DropError> {
    if !(fps > 0.0 && fps.is_finite()) {
        return Err(DropError::NotPositive { name: "frames per second", value: fps });
    }
    let dt = run.dt();
    let every = ((1.0 / (fps * dt)).round() as usize).max(1);
    let frame = |run: &DropRun| (0..assembly.blocks.len()).map(|i| run.pose(i)).collect();
    let mut motion = Trajectory { engine: run.engine(), times: vec![0.0], poses: vec![frame(&run)] };
    while !run.finished() {
        run.advance(every);
        motion.times.push(run.steps_done() as f64 * dt);
        motion.poses.push(frame(&run));
    }
    Ok((run.result(), motion))
}

/// A drop test that can be advanced step by step (the ECS plugin steps it in FixedUpdate).
pub struct DropRun {
    sim: Stepper,
    /// Every block's centroid at the start (a support's pose in the exact engine).
    start: Vec<crate::geometry::Point3>,
    settings: DropSettings,
    /// Indices of the free blocks and their sizes (m).
    free: Vec<usize>,
    size: Vec<f64>,
    /// Free weight (N) times the median free block size (m): the scale of `at_rest`.
    energy_scale: f64,
    motions: Vec<BlockMotion>,
    /// The ground motion that shakes the base (or only its named supports: `shaken`), if any.
    ground: Option<GroundMotion>,
    shaken: bool,
    steps: usize,
    total: usize,
    wall: f64,
}

impl DropRun {
    /// A drop test of `assembly` at its start (the settings checked first).
    pub fn new(assembly: &Assembly, settings: &DropSettings) -> Result<Self, DropError> {
        Self::with_paths(assembly, settings, &[])
    }

    /// A drop test whose supports `paths` name are kinematic bodies (their motion given by the
    /// caller's steps).
    fn with_paths(assembly: &Assembly, settings: &DropSettings, paths: &[SupportPath]) -> Result<Self, DropError> {
        settings.validate()?;
        let start = Instant::now();
        let sim = Stepper::with_paths(assembly, settings, paths);
        let origins = assembly.blocks.iter().map(|b| b.mass.centroid).collect();
        let free: Vec<usize> = (0..assembly.blocks.len()).filter(|&i| !assembly.blocks[i].support).collect();
        let size: Vec<f64> = free.iter().map(|&i| assembly.blocks[i].aabb.diagonal()).collect();
        let mut sorted = size.clone();
        sorted.sort_by(f64::total_cmp);
        let weight: f64 = free.iter().map(|&i| assembly.blocks[i].mass() * assembly.gravity.norm()).sum();
        let energy_scale = weight * sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        let motions = free
            .iter()
            .map(|&i| BlockMotion {
                name: assembly.blocks[i].name.clone(),
                max_drift: 0.0,
                max_drift_ratio: 0.0,
                max_rotation: 0.0,
                final_kinetic_energy: 0.0,
                first_motion: None,
                final_drift: 0.0,
                final_rotation: 0.0,
                max_drop: 0.0,
                fell: None,
            })
            .collect();
        let total = (settings.duration / settings.dt).ceil() as usize;
        let wall = start.elapsed().as_secs_f64();
        Ok(Self {
            sim,
            start: origins,
            settings: settings.clone(),
            free,
            size,
            energy_scale,
            motions,
            ground: None,
            shaken: false,
            steps: 0,
            total,
            wall,
        })
    }

    /// A drop test of `assembly` whose base moves by `motion` (checked first): the run of a
    /// shake ([`super::ground_motion`]). A fall stops it when the settings say so.
    pub fn shaken(assembly: &Assembly, settings: &DropSettings, motion: GroundMotion) -> Result<Self, DropError> {
        let motion = motion.validated()?;
        let paths = motion.shaken_supports(assembly)?;
        let mut run = Self::with_paths(assembly, settings, &paths)?;
        run.shaken = !paths.is_empty();
        run.ground = Some(motion);
        Ok(run)
    }

    /// Ends the run by `t` s (no later than its duration): a shake that has collapsed needs only
    /// the time for its debris to land.
    pub fn end_by(&mut self, t: f64) {
        let steps = (t / self.settings.dt).ceil().max(0.0) as usize;
        self.total = self.total.min(steps.max(self.steps));
    }

    /// The steps the whole duration takes (fewer once it stops at a fall).
    pub fn total_steps(&self) -> usize {
        self.total
    }

    /// The engine it runs on.
    pub fn engine(&self) -> Engine {
        self.settings.engine
    }

    /// The time step, s.
    pub fn dt(&self) -> f64 {
        self.settings.dt
    }

    /// The steps taken so far.
    pub fn steps_done(&self) -> usize {
        self.steps
    }

    /// Whether it has run its duration (or stopped at a fall).
    pub fn finished(&self) -> bool {
        self.steps >= self.total
    }

    /// Advances by up to `n` steps (not past the duration), tracking every block's motion.
    pub fn advance(&mut self, n: usize) {
        let start = Instant::now();
        let dt = self.settings.dt;
        for _ in 0..n.min(self.total - self.steps) {
            let t = self.steps as f64 * dt;
            match &self.ground {
                Some(ground) if self.shaken => self.sim.step_supports_by(ground.displacement(t, t + dt)),
                Some(ground) => {
                    self.sim.set_base_acceleration(ground.mean_acceleration(t, t + dt));
                    self.sim.step();
                }
                None => self.sim.step(),
            }
            self.steps += 1;
            self.track();
            let s = &self.settings;
            // A shake's blocks rock beyond the tolerances and come back: it stops at a fall.
            let stop = if self.ground.is_some() {
                self.motions.iter().any(|m| m.fell.is_some())
            } else {
                self.motions
                    .iter()
                    .any(|m| m.max_drift_ratio > s.drift_tolerance || m.max_rotation > s.rotation_tolerance)
            };
            if s.stop_when_falls && stop {
                self.total = self.steps;
                break;
            }
        }
        self.wall += start.elapsed().as_secs_f64();
    }

    /// Every free block's motion after a step.
    fn track(&mut self) {
        let s = &self.settings;
        let t = self.steps as f64 * s.dt;
        for (k, &i) in self.free.iter().enumerate() {
            let (drift, rotation) = self.sim.displacement(i);
            let drop = self.start[i].z - self.pose(i).0.z;
            let m = &mut self.motions[k];
            m.max_drift = m.max_drift.max(drift);
            m.max_drift_ratio = m.max_drift / self.size[k];
            m.max_rotation = m.max_rotation.max(rotation);
            (m.final_drift, m.final_rotation) = (drift, rotation);
            m.max_drop = m.max_drop.max(drop);
            if m.first_motion.is_none()
                && (drift > 0.1 * s.drift_tolerance * self.size[k] || rotation > 0.1 * s.rotation_tolerance)
            {
                m.first_motion = Some(t);
            }
            if m.fell.is_none() && (rotation > s.fall_rotation || drop > s.fall_drop * self.size[k]) {
                m.fell = Some(t);
            }
        }
    }

    /// When the first block fell so far, s.
    pub fn fell(&self) -> Option<f64> {
        self.motions.iter().filter_map(|m| m.fell).min_by(f64::total_cmp)
    }

    /// The largest drift (a fraction of the block's size) and rotation (rad) of a free block
    /// now.
    pub fn largest_now(&self) -> (f64, f64) {
        self.motions
            .iter()
            .zip(&self.size)
            .fold((0.0, 0.0), |(d, r), (m, size)| (f64::max(d, m.final_drift / size), f64::max(r, m.final_rotation)))
    }

    /// Block `i`'s centroid (m) and rotation since the start (unit quaternion [w, x, y, z]).
    pub fn pose(&self, i: usize) -> (crate::geometry::Point3, [f64; 4]) {
        match &self.sim {
            Stepper::Rapier(s) => s.pose(i),
            Stepper::Exact(w) => w.pose(i, self.start[i]),
        }
    }

    /// The outcome so far (the verdict covers the steps run).
    pub fn result(&self) -> DropResult {
        let s = &self.settings;
        let mut motions = self.motions.clone();
        for (m, &i) in motions.iter_mut().zip(&self.free) {
            m.final_kinetic_energy = self.sim.kinetic_energy(i);
        }
        let badness =
            |m: &BlockMotion| (m.max_drift_ratio / s.drift_tolerance).max(m.max_rotation / s.rotation_tolerance);
        let worst = motions.iter().max_by(|a, b| badness(a).total_cmp(&badness(b)));
        let (max_volume_error, initial_overlap, exact) = match &self.sim {
            Stepper::Rapier(s) => (s.max_volume_error, s.initial_overlap.clone(), None),
            Stepper::Exact(w) => (0.0, None, Some(w.stats())),
        };
        // A failed solve leaves its step undone: no verdict of standing rests on it.
        let solved = exact.as_ref().is_none_or(|e| e.status <= crate::statics::SolverStatus::AlmostSolved);
        DropResult {
            engine: s.engine,
            stands: solved && motions.iter().all(|m| badness(m) <= 1.0),
            max_drift: motions.iter().map(|m| m.max_drift_ratio).fold(0.0, f64::max),
            max_rotation: motions.iter().map(|m| m.max_rotation).fold(0.0, f64::max),
            worst_block: worst.map(|m| m.name.clone()),
            fell: self.fell(),
            simulated_s: self.steps as f64 * s.dt,
            wall_s: self.wall,
            steps: self.steps,
            max_volume_error,
            max_initial_overlap: initial_overlap.as_ref().map_or(0.0, |o| o.0),
            initial_overlap_blocks: initial_overlap.map(|o| o.1),
            at_rest: motions.iter().map(|m| m.final_kinetic_energy).sum::<f64>() <= 1e-6 * self.energy_scale,
            blocks: motions,
            exact,
        }
    }
}
