//! When the supports move: a design followed along prescribed support paths
//! ([`crate::model::Movement`]) until it collapses, three ways side by side.
//!
//! - **Quasi-static** (the answer): the path in increments; in each, the blocks start from
//!   rest and take the motion the contacts allow while the supports move by the increment
//!   (one step of the exact-contact engine, its first step from rest being the kinematic
//!   check's rate problem: hinges open, joints slide, as the rigid-block equilibrium
//!   allows), then the supports stop and the blocks are released from rest again: if they stay
//!   at rest an equilibrium exists in the moved geometry; if not, it has collapsed. The
//!   collapsing increment is halved `refine` times, so the movement at collapse is known to
//!   2^-refine of an increment. No inertia: no velocity is carried from one increment to the
//!   next. Where the forces are not unique (a hyperstatic vault), each step keeps the smallest
//!   that Coulomb's sets carry ([`crate::dynamics::Selection::Coulomb`]), as the statics'
//!   strict QP does.
//! - **Exact engine** and **rapier**: the supports moved slowly in real time (at `speed` ×
//!   √(g × block size); the exact engine's supports start from rest and reach it in
//!   √(block size / g), since rigid blocks cannot take a sudden start); collapse is the first
//!   block faster than `collapse_speed` × √(g × block size). In rapier, the collapse is dated
//!   back to where the blocks left the supports' pace. In the exact engine it is judged as the
//!   quasi-static run judges its increments: fast blocks that an equilibrium still holds where
//!   the engine has them are following the supports (a flat arch's halves turn ever faster as
//!   their crown nears the hinges' level) and the run goes on; a collapse is dated to the first
//!   step from which, stopped, they no longer stay at rest.
//!
//! Which mechanism a step takes where several are admissible: a component at rest stays at rest
//! when an equilibrium within Coulomb's sets holds it (the static theorem's pick; a flat arch
//! could also slide down its vertical joints with no force on them:
//! [`ExactSettings::rest_when_admissible`], on in all of the exact engine's runs here). A moving component takes
//! the exact engine's step: the velocities closest to its momentum (in the kinetic metric) that
//! the contacts admit, with the friction of the Tresca rounds' fixed point, started from the
//! equilibrium's forces.
//!
//! Each run records stages: the fraction of the path, the movement (m: the largest translation
//! of a support, and its fraction of the model size), the reaction on each moved support (N,
//! the force the blocks put on it: the thrust), and the joints that are not closed (hinging,
//! opening, sliding) from the contacts' gaps, and their slips since the last stage, beyond
//! [`JOINT_TOLERANCE`] of the block size. Units SI, z up; rotations of the paths in degrees (input) about the support's centroid.

use crate::dynamics::exact::World;
use crate::dynamics::{DropSettings, Engine, ExactSettings, Selection, Stepper, SupportPath, Trajectory};
use crate::geometry::Vector3;
use crate::interfaces::Interface;
use crate::model::{Assembly, Movement};
use crate::pipeline::Analysis;
use crate::statics::{Backend, JointState, SolverStatus};
use serde::Serialize;
use thiserror::Error;

/// The quasi-static run's [`Run::method`].
pub const QUASI_STATIC: &str = "quasi-static";

/// A joint counts as open (sliding) where a contact's gap (its slip since the last stage)
/// passes this fraction of the median block size.
pub const JOINT_TOLERANCE: f64 = 1e-4;

/// Settings of [`settle`]; each default written once, in `Default`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SettleSettings {
    /// Quasi-static increments over the whole path.
    pub increments: usize,
    /// Halvings of the increment in which it collapses.
    pub refine: usize,
    /// Friction coefficient; `None` takes the scene material's.
    pub friction: Option<f64>,
    /// Compressive strength, Pa; `None` takes the scene material's (none: the stone does not
    /// crush). The quasi-static run and the exact engine bound each interface's compression by
    /// its stress block; rapier's contacts do not crush.
    pub strength: Option<f64>,
    /// Also run the path in the exact-contact engine and in rapier.
    pub engines: bool,
    /// The engines' time step, s.
    pub dt: f64,
    /// The supports' speed in the engines' runs, a fraction of √(g × block size).
    pub speed: f64,
    /// A block faster than this fraction of √(g × block size) has collapsed (engines' runs).
    pub collapse_speed: f64,
    /// The interior-point solver of the exact engine's steps (the quasi-static run's too).
    pub backend: Backend,
}

impl Default for SettleSettings {
    fn default() -> Self {
        Self {
            // 1 % of the path per increment, refined to 1/6400 where it collapses.
            increments: 100,
            refine: 6,
            friction: None,
            strength: None,
            engines: true,
            dt: DropSettings::default().dt,
            // Slow against a block's fall (√(g size)) and its collapse threshold: quasi-static.
            speed: 0.01,
            collapse_speed: 0.2,
            backend: Backend::default(),
        }
    }
}

impl SettleSettings {
    /// Every setting checked: one clear error naming the first that is wrong.
    pub fn validate(&self) -> Result<(), SettleError> {
        let positive = |name: &'static str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(SettleError::Setting(format!("{name} = {v} must be > 0")))
            }
        };
        if self.increments == 0 || self.increments > MAX_INCREMENTS {
            return Err(SettleError::Setting(format!(
                "increments = {} must be between 1 and {MAX_INCREMENTS}",
                self.increments
            )));
        }
        if self.refine > 52 {
            return Err(SettleError::Setting(format!(
                "refine = {} halvings is beyond a double's 52 bits (at most 52)",
                self.refine
            )));
        }
        positive("dt", self.dt)?;
        if let Some(s) = self.strength {
            positive("strength", s)?;
        }
        positive("speed", self.speed)?;
        positive("collapse_speed", self.collapse_speed)?;
        if self.speed >= self.collapse_speed {
            return Err(SettleError::Setting("speed must be below collapse_speed".into()));
        }
        Ok(())
    }
}

/// Bad movement input; each names the movement and what is wrong.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SettleError {
    /// No movement was given.
    #[error("no support movement: give one (--move NAME:dx,dy,dz or the scene's `movements`)")]
    NoMovement,
    /// A movement names no block.
    #[error("movement of '{0}': no block of that name")]
    UnknownBlock(String),
    /// A movement names a free block.
    #[error("movement of '{0}': it is a free block; only supports are moved (the blocks follow)")]
    NotASupport(String),
    /// A movement's translation or rotation is not finite.
    #[error("movement of '{0}': a translation or rotation that is not a finite number")]
    NotFinite(String),
    /// A movement beyond the bounds a path may have.
    #[error("movement of '{block}': {what} {value:.4e} exceeds the limit {limit:.4e} ({why})")]
    TooFar {
        /// The moved support.
        block: String,
        /// What is too large (its translation, its rotation).
        what: &'static str,
        /// Its size (m or degrees).
        value: f64,
        /// The limit (m or degrees).
        limit: f64,
        /// Why the limit is there.
        why: &'static str,
    },
    /// The engines' run of the path would take too many steps.
    #[error("the engines' run would take {steps:.3e} steps of dt (limit {limit:.0e}): a larger --dt or a shorter path")]
    TooManySteps {
        /// The steps the path would take.
        steps: f64,
        /// The limit.
        limit: f64,
    },
    /// A support is moved twice.
    #[error("'{0}' is moved twice: give one path per support")]
    Twice(String),
    /// A path runs a support into another.
    #[error("movement of '{moved}': its path runs it into support '{other}' (two supports cannot pass each other)")]
    Closes {
        /// The moved support.
        moved: String,
        /// The support it runs into.
        other: String,
    },
    /// A setting out of its range.
    #[error("{0}")]
    Setting(String),
}

/// One non-closed joint of a stage.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Joint {
    /// The interface's index in the analysis.
    pub interface: usize,
    /// Its two blocks' names (a → b).
    pub a: String,
    /// The second block.
    pub b: String,
    /// How it moves: hinging, opening or sliding.
    pub state: JointState,
}

/// One stage of a run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stage {
    /// Fraction of the path covered.
    pub fraction: f64,
    /// The largest translation of a moved support, m.
    pub movement: f64,
    /// Per moved support (in the movements' order), the force the blocks put on it, N.
    pub reactions: Vec<[f64; 3]>,
    /// The joints that are not closed at this stage.
    pub joints: Vec<Joint>,
    /// The largest rotation of a free block since the start, degrees (engine runs: the exact
    /// engine's; none in rapier's stages).
    pub rotation: f64,
    /// The blocks did not stay in the last equilibrium but snapped over into this one (a
    /// hinge moved), moving with their inertia while the supports were still (quasi-static run).
    pub snapped: bool,
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Outcome {
    /// It collapsed at this fraction of the path, this movement (m) and fraction of the model
    /// size.
    Collapses {
        /// The fraction of the path.
        fraction: f64,
        /// The largest support translation then, m.
        movement: f64,
        /// That movement over the model's size.
        relative: f64,
    },
    /// It stood to the end of the path.
    Stands,
    /// A step's solve reached no answer at this fraction of the path (`status`, the worst):
    /// what the run would say beyond it is not known, and it stops there.
    Unresolved {
        /// The fraction of the path.
        fraction: f64,
        /// The worst solver status.
        status: SolverStatus,
    },
}

/// One way through the path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Run {
    /// "quasi-static", "exact" or "rapier".
    pub method: &'static str,
    /// How it ended.
    pub outcome: Outcome,
    /// Its stages along the path.
    pub stages: Vec<Stage>,
    /// The joints that are not closed just after the collapse (the mechanism); empty when it
    /// stands.
    pub mechanism: Vec<Joint>,
    /// Engine steps taken.
    pub steps: usize,
    /// With a compressive strength: how deep the joints crushed (the largest overlap at a
    /// contact over the run, m). Closed joints crush; an open one (a hinge, its contact its
    /// rigid edge) is left unbounded (README, "Is the stone strong enough?").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crushed: Option<f64>,
    /// The blocks' poses at the start, at every stage and just past a collapse, the times
    /// being fractions of the path (none in rapier's run).
    #[serde(skip)]
    pub motion: Trajectory,
}

impl Run {
    fn new(method: &'static str, engine: Engine) -> Self {
        let motion = Trajectory { engine, times: Vec::new(), poses: Vec::new() };
        Self {
            method,
            outcome: Outcome::Stands,
            stages: Vec::new(),
            mechanism: Vec::new(),
            steps: 0,
            crushed: None,
            motion,
        }
    }

    /// Records `world`'s poses at `fraction` of the path.
    fn frame(&mut self, world: &World, fraction: f64) {
        self.motion.times.push(fraction);
        self.motion.poses.push(world.all_poses());
    }
}

/// The analysis of a design on moving supports ([`settle`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Settlement {
    /// The moved supports, in order.
    pub supports: Vec<String>,
    /// The largest translation of a support over the whole path, m.
    pub path_movement: f64,
    /// The model size (bounding-box diagonal), m: the movement relative to it.
    pub model_size: f64,
    /// The compressive strength the quasi-static run and the exact engine honoured, Pa (none:
    /// the stone does not crush).
    pub strength: Option<f64>,
    /// The quasi-static run (the answer).
    pub quasi_static: Run,
    /// The exact engine's run, when the engines ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exact: Option<Run>,
    /// rapier's run, when the engines ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rapier: Option<Run>,
}

/// Follows `analysis`'s design along `movements` (module docs).
pub fn settle(
    analysis: &Analysis,
    movements: &[Movement],
    settings: &SettleSettings,
) -> Result<Settlement, SettleError> {
    settle_with_progress(analysis, movements, settings, &|_, _| {})
}

/// What a run tells of its progress: the fraction of the path it has followed.
type Heard<'a> = &'a dyn Fn(f64);

/// [`settle`], calling `progress(method, fraction)` as each run goes: the fraction of the path
/// it has followed, 0 as it starts and 1 as it ends (at the path's end or its collapse), never
/// decreasing within a run; the runs in the report's order.
pub fn settle_with_progress(
    analysis: &Analysis,
    movements: &[Movement],
    settings: &SettleSettings,
    progress: &dyn Fn(&'static str, f64),
) -> Result<Settlement, SettleError> {
    settings.validate()?;
    let assembly = &analysis.assembly;
    let paths = resolve(assembly, movements)?;
    let path = PathScale::new(assembly, &paths);
    if settings.engines {
        let steps = engine_steps(assembly, &path, settings) + ramp_steps(assembly, settings);
        if steps > MAX_ENGINE_STEPS {
            return Err(SettleError::TooManySteps { steps, limit: MAX_ENGINE_STEPS });
        }
    }
    let reported = |method: &'static str, run: &dyn Fn(Heard) -> Run| {
        progress(method, 0.0);
        let r = run(&|fraction| progress(method, fraction));
        progress(method, 1.0);
        r
    };
    let quasi_static = reported(QUASI_STATIC, &|p| quasi_static(analysis, &paths, &path, settings, p));
    let (exact, rapier) = if settings.engines {
        (
            Some(reported(Engine::Exact.name(), &|p| in_engine(analysis, &paths, &path, settings, Engine::Exact, p))),
            Some(reported(Engine::Rapier.name(), &|p| in_engine(analysis, &paths, &path, settings, Engine::Rapier, p))),
        )
    } else {
        (None, None)
    };
    Ok(Settlement {
        supports: paths.iter().map(|p| assembly.blocks[p.block].name.clone()).collect(),
        path_movement: path.movement,
        model_size: assembly.scale,
        strength: settings.strength.or(assembly.material.strength),
        quasi_static,
        exact,
        rapier,
    })
}

/// The movements as engine paths (radians), each checked.
pub fn resolve(assembly: &Assembly, movements: &[Movement]) -> Result<Vec<SupportPath>, SettleError> {
    if movements.is_empty() {
        return Err(SettleError::NoMovement);
    }
    let mut paths: Vec<SupportPath> = Vec::new();
    for m in movements {
        let block = assembly
            .blocks
            .iter()
            .position(|b| b.name == m.block)
            .ok_or_else(|| SettleError::UnknownBlock(m.block.clone()))?;
        if !assembly.blocks[block].support {
            return Err(SettleError::NotASupport(m.block.clone()));
        }
        if !m.finite() {
            return Err(SettleError::NotFinite(m.block.clone()));
        }
        if paths.iter().any(|p| p.block == block) {
            return Err(SettleError::Twice(m.block.clone()));
        }
        let v = |a: [f64; 3]| Vector3::new(a[0], a[1], a[2]);
        let path = SupportPath { block, translation: v(m.translation), rotation: v(m.rotation) * 1f64.to_radians() };
        check_bounds(assembly, &m.block, &path)?;
        paths.push(path);
    }
    check_clear(assembly, &paths)?;
    Ok(paths)
}

/// A support moves at most [`MAX_TRAVEL`] model sizes and turns at most half a turn: a path
/// beyond either has left the design behind long before its end.
fn check_bounds(assembly: &Assembly, name: &str, path: &SupportPath) -> Result<(), SettleError> {
    let too_far = |what, value: f64, limit: f64, why| {
        (value > limit).then(|| SettleError::TooFar { block: name.to_owned(), what, value, limit, why })
    };
    let size = assembly.scale.max(f64::MIN_POSITIVE);
    let translation = path.translation.norm();
    let limit = MAX_TRAVEL * size;
    let rotation = path.rotation.norm().to_degrees();
    match too_far("translation (m)", translation, limit, "10 model sizes")
        .or_else(|| too_far("rotation (°)", rotation, 180.0, "half a turn"))
    {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The most quasi-static increments of a path (each an equilibrium solve or more).
const MAX_INCREMENTS: usize = 1_000_000;

/// The farthest a support may move, in model sizes ([`check_bounds`]).
const MAX_TRAVEL: f64 = 10.0;

/// The most steps an engine's run may take (a drop test's bound).
const MAX_ENGINE_STEPS: f64 = 1e7;

/// Two supports must not be driven into each other: at the path's quarters, a moved support's
/// box (moved by its translation) may not overlap another support's box more than at the start.
fn check_clear(assembly: &Assembly, paths: &[SupportPath]) -> Result<(), SettleError> {
    let moved = |i: usize, f: f64| {
        let mut b = assembly.blocks[i].aabb;
        if let Some(p) = paths.iter().find(|p| p.block == i) {
            b.min += p.translation * f;
            b.max += p.translation * f;
        }
        b
    };
    let overlap = |a: &crate::geometry::Aabb3, b: &crate::geometry::Aabb3| {
        (0..3).map(|k| (a.max[k].min(b.max[k]) - a.min[k].max(b.min[k])).max(0.0)).product::<f64>()
    };
    let supports: Vec<usize> = (0..assembly.blocks.len()).filter(|&i| assembly.blocks[i].support).collect();
    let grain = 1e-9 * assembly.scale.powi(3);
    for p in paths {
        for &o in supports.iter().filter(|&&o| o != p.block) {
            let start = overlap(&moved(p.block, 0.0), &moved(o, 0.0));
            if [0.25, 0.5, 0.75, 1.0].iter().any(|&f| overlap(&moved(p.block, f), &moved(o, f)) > start + grain) {
                let name = |i: usize| assembly.blocks[i].name.clone();
                return Err(SettleError::Closes { moved: name(p.block), other: name(o) });
            }
        }
    }
    Ok(())
}

/// How far the supports go: the largest translation (m) and the largest distance any point of
/// a moved support travels (translation plus rotation × its reach, m).
struct PathScale {
    movement: f64,
    travel: f64,
}

impl PathScale {
    fn new(assembly: &Assembly, paths: &[SupportPath]) -> Self {
        let movement = paths.iter().map(|p| p.translation.norm()).fold(0.0, f64::max);
        let travel = paths
            .iter()
            .map(|p| p.translation.norm() + p.rotation.norm() * 0.5 * assembly.blocks[p.block].aabb.diagonal())
            .fold(0.0, f64::max);
        Self { movement, travel }
    }
}

fn engine_settings(settings: &SettleSettings, engine: Engine) -> DropSettings {
    DropSettings {
        engine,
        dt: settings.dt,
        friction: settings.friction,
        strength: settings.strength,
        perturbation: 0.0,
        // The rounds' pick where several answers are admissible (module docs).
        exact: ExactSettings {
            backend: settings.backend,
            rest_when_admissible: true,
            by_states: false,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The quasi-static run's solver tolerance. Its verdicts compare speeds with [`HELD`] × g h,
/// which a residual of 1e-8 moves by ~1e-8 g h; the engines' runs keep the kinematic check's
/// 1e-10 (their first step is that check).
const QUASI_STATIC_TOLERANCE: f64 = 1e-8;

/// The quasi-static run's stall (`ExactSettings::stall_rounds`): an increment's driving step
/// on a hyperstatic vault can reshuffle its capacities round after round without closing in,
/// and each step starts from rest and ends in hold steps that settle the blocks; a contracting
/// fixed point halves its change every round or two (Anderson's secant steps may overshoot
/// for a round or three).
const QUASI_STATIC_STALL: u32 = 8;

/// The quasi-static run (module docs); `progress` hears the fraction of the path held so far.
fn quasi_static(
    analysis: &Analysis,
    paths: &[SupportPath],
    scale: &PathScale,
    settings: &SettleSettings,
    progress: Heard,
) -> Run {
    let assembly = &analysis.assembly;
    let mut drop = engine_settings(settings, Engine::Exact);
    drop.exact.solver_tolerance = QUASI_STATIC_TOLERANCE;
    // A sequence of equilibria: the statics' least-norm rule, and a few rounds a step on
    // hyperstatic vaults (docs/benchmarks.md).
    drop.exact.selection = Selection::Coulomb;
    drop.exact.stall_rounds = Some(QUASI_STATIC_STALL);
    let mut world = World::with_paths(assembly, &drop, paths);
    let mut run = Run::new(QUASI_STATIC, Engine::Exact);
    let n = settings.increments;
    let mut done = 0.0;
    let g = assembly.gravity.norm().max(f64::MIN_POSITIVE);
    // One increment per step, long enough that a block falls ten times the supports' travel
    // in it: the blocks follow the supports under their weight instead of being left behind.
    let step = |fraction: f64| (10.0 * fraction * scale.travel / g).sqrt().max(settings.dt);
    world.set_step(step(1.0 / n as f64));
    run.frame(&world, 0.0);
    let held = increment(&mut world, 0.0, &mut run.steps);
    run.crushed = crush_depth(&world, settings, assembly);
    if let Some(status) = failure(&world) {
        return unresolved(run, 0.0, status);
    }
    if !held {
        return collapsed(run, analysis, world, 0.0, scale);
    }
    for k in 1..=n {
        let fraction = k as f64 / n as f64;
        let before = world.clone();
        let held = increment(&mut world, fraction - done, &mut run.steps);
        run.crushed = crush_depth(&world, settings, assembly);
        if let Some(status) = failure(&world) {
            return unresolved(run, fraction, status);
        }
        if held {
            done = fraction;
            run.stages.push(stage(assembly, &analysis.interfaces, &world, done, scale));
            world.mark_slips();
            run.frame(&world, done);
            progress(done);
            continue;
        }
        let h = step(1.0 / n as f64);
        let snapped = snap(world.clone(), g, settings.dt, h, &mut run.steps);
        if let Err(status) = snapped {
            return unresolved(run, fraction, status);
        }
        if let Ok(Some(snapped)) = snapped {
            world = snapped;
            done = fraction;
            let mut s = stage(assembly, &analysis.interfaces, &world, done, scale);
            s.snapped = true;
            run.stages.push(s);
            world.mark_slips();
            run.frame(&world, done);
            progress(done);
            continue;
        }
        let ctx = Bisection { analysis, settings, scale, step: &step, progress };
        return ctx.refine(run, (done, fraction), before, world);
    }
    run
}

/// What the bisection of a collapsing increment works with ([`Bisection::refine`]).
struct Bisection<'a> {
    analysis: &'a Analysis,
    settings: &'a SettleSettings,
    scale: &'a PathScale,
    /// The step length of an increment of the given fraction of the path.
    step: &'a dyn Fn(f64) -> f64,
    progress: Heard<'a>,
}

impl Bisection<'_> {
    /// The blocks held at `bracket.0` (`held`) and collapsed by `bracket.1` (`past`): the
    /// bracket halved `settings.refine` times from the held world, and the run ended collapsed
    /// at its top (or unresolved where a solve failed).
    fn refine(&self, mut run: Run, bracket: (f64, f64), mut held: World, mut past: World) -> Run {
        let (mut lo, mut hi) = bracket;
        for _ in 0..self.settings.refine {
            let mid = 0.5 * (lo + hi);
            let mut w = held.clone();
            w.set_step((self.step)(mid - lo));
            let stays = increment(&mut w, mid - lo, &mut run.steps);
            if let Some(status) = failure(&w) {
                return unresolved(run, mid, status);
            }
            if stays {
                (lo, held) = (mid, w);
                (self.progress)(lo);
            } else {
                (hi, past) = (mid, w);
            }
        }
        run.crushed = crush_depth(&past, self.settings, &self.analysis.assembly);
        collapsed(run, self.analysis, past, hi, self.scale)
    }
}

/// The worst solver status, when a step's solve failed (the world has left the dynamics).
fn failure(world: &World) -> Option<SolverStatus> {
    let stats = world.stats();
    (stats.failed_steps > 0).then_some(stats.status)
}

/// The run stops at `fraction`: a step's solve failed there ([`Outcome::Unresolved`]).
fn unresolved(mut run: Run, fraction: f64, status: SolverStatus) -> Run {
    run.outcome = Outcome::Unresolved { fraction, status };
    run
}

/// The deepest overlap of the run so far (m), when the stone crushes.
fn crush_depth(world: &World, settings: &SettleSettings, assembly: &Assembly) -> Option<f64> {
    settings.strength.or(assembly.material.strength).map(|_| world.deepest_overlap())
}

/// How long a snap may take (in √(block size / g)) and how far a block may move in it (in block
/// sizes) before it counts as a fall.
const SNAP_TIME: f64 = 20.0;
const SNAP_DROP: f64 = 0.25;

/// The snap's engine step, in `dt`: a snap lands and a fall falls alike on steps this much
/// longer (implicit steps only dissipate more: the spreading arch snaps at the same stage onto
/// the same hinges, its thrust there within 4e-6, and both it and the tilting block collapse
/// at the same fraction), at an eighth of the steps.
const SNAP_STEP: f64 = 8.0;

/// After an increment from which the blocks do not settle at rest: the blocks move under
/// their weight with the supports still and their inertia kept (engine steps of
/// [`SNAP_STEP`] × `dt`), as a hinge snaps over to another; `Some` with the world at rest in
/// the new equilibrium (held, as an increment, at the increment step `h`), `None` when a block
/// falls (moves more than [`SNAP_DROP`] of a block) or nothing settles within [`SNAP_TIME`];
/// the worst status when a step's solve failed.
fn snap(mut world: World, g: f64, dt: f64, h: f64, steps: &mut usize) -> Result<Option<World>, SolverStatus> {
    let dt = SNAP_STEP * dt;
    let size = world.block_size();
    let start = world.centroids();
    world.set_step(dt);
    let limit = (SNAP_TIME * (size / g).sqrt() / dt).ceil() as usize;
    let every = ((0.5 * (size / g).sqrt() / dt).ceil() as usize).max(1);
    for k in 1..=limit {
        world.step_supports(0.0);
        *steps += 1;
        if let Some(status) = failure(&world) {
            return Err(status);
        }
        let drift = world.centroids().iter().zip(&start).map(|(p, q)| (p - q).norm()).fold(0.0, f64::max);
        if drift > SNAP_DROP * size {
            return Ok(None);
        }
        // Every half √(size / g): stopped there, does an equilibrium hold them?
        if k % every == 0 || world.at_rest() {
            let mut held = world.clone();
            held.set_step(h);
            let stays = increment(&mut held, 0.0, steps);
            if let Some(status) = failure(&held) {
                return Err(status);
            }
            if stays {
                return Ok(Some(held));
            }
        }
    }
    Ok(None)
}

/// Hold steps that may settle what an increment left: one step moves the blocks along
/// straight lines at one velocity, so they end a little off the position the contacts hold,
/// and the first steps from rest settle them there, each by a fraction of the last (the
/// motion dies out); a collapse does not die out.
const HOLDS: usize = 8;

/// A hold step's motion that is not below this fraction of the previous one's is not dying
/// out: a collapse.
const DYING: f64 = 0.5;

/// Blocks that a hold step from rest leaves slower than this fraction of a free fall's speed
/// over the step (g h) are held: a collapse mechanism's acceleration is then below 1e-4 g,
/// which a tilt passes within 1e-4 rad of its limit, while a mechanism at its neutral point
/// (a hinge about to move over, at the round-off of the contact forces) is not called a
/// collapse.
const HELD: f64 = 1e-4;

/// One quasi-static increment: from rest, the supports move by `fraction` of their paths in
/// one step; then, from rest, held still: whether the blocks settle at rest (module docs).
fn increment(world: &mut World, fraction: f64, steps: &mut usize) -> bool {
    if fraction > 0.0 {
        world.stop();
        world.step_supports(fraction);
        *steps += 1;
    }
    let mut last = f64::INFINITY;
    for _ in 0..HOLDS {
        world.stop();
        world.step_held();
        *steps += 1;
        let now = world.fastest_vertex();
        if world.at_rest() || now <= HELD * world.free_fall_speed() {
            world.stop();
            return true;
        }
        if now > DYING * last {
            return false;
        }
        last = now;
    }
    false
}

/// The run ended by a collapse at `fraction`: the mechanism is how the joints move as the
/// blocks start to fall (the last hold step's velocities, as the kinematic check's).
fn collapsed(mut run: Run, analysis: &Analysis, world: World, fraction: f64, scale: &PathScale) -> Run {
    let assembly = &analysis.assembly;
    run.frame(&world, fraction);
    let fastest = world.fastest_vertex();
    run.mechanism = classify(assembly, &analysis.interfaces, world.joint_rates(), MECHANISM_TOLERANCE * fastest);
    let movement = fraction * scale.movement;
    run.outcome = Outcome::Collapses { fraction, movement, relative: movement / assembly.scale };
    run
}

fn stage(assembly: &Assembly, interfaces: &[Interface], world: &World, fraction: f64, scale: &PathScale) -> Stage {
    let reactions = (0..world.moved_supports()).map(|m| world.support_reaction(m)[0].into()).collect();
    Stage {
        fraction,
        movement: fraction * scale.movement,
        reactions,
        joints: joints(assembly, interfaces, world),
        rotation: world.largest_rotation().to_degrees(),
        snapped: false,
    }
}

/// A joint's contact counts as opening (sliding) in a collapse where its relative velocity
/// passes this fraction of the fastest block's.
pub const MECHANISM_TOLERANCE: f64 = 1e-3;

/// The joints whose contacts are not all closed and still, from their gaps and slips.
fn joints(assembly: &Assembly, interfaces: &[Interface], world: &World) -> Vec<Joint> {
    classify(assembly, interfaces, world.joint_gaps(), JOINT_TOLERANCE * world.block_size())
}

/// Per interface from its contacts' (interface, vertex, opening, slip) — distances or rates —
/// beyond `tol`: hinging (some open), opening (all open), sliding (a closed contact slips).
fn classify(
    assembly: &Assembly,
    interfaces: &[Interface],
    contacts: Vec<(usize, usize, f64, f64)>,
    tol: f64,
) -> Vec<Joint> {
    let mut per: Vec<(usize, usize, usize, bool)> = Vec::new(); // interface, open, total, slid
    for (interface, _, gap, slip) in contacts {
        if per.last().is_none_or(|p| p.0 != interface) {
            per.push((interface, 0, 0, false));
        }
        let p = per.last_mut().expect("just pushed");
        p.2 += 1;
        if gap > tol {
            p.1 += 1;
        } else if slip > tol {
            p.3 = true;
        }
    }
    per.into_iter()
        .filter_map(|(k, open, total, slid)| {
            let state = match (open, slid) {
                (o, _) if o == total => JointState::Opening,
                (_, true) => JointState::Sliding,
                (0, false) => return None,
                _ => JointState::Hinging,
            };
            let itf = &interfaces[k];
            Some(Joint {
                interface: k,
                a: itf.a.name(assembly).to_string(),
                b: itf.b.name(assembly).to_string(),
                state,
            })
        })
        .collect()
}

/// The path in real time in `engine` (module docs); `progress` hears the fraction of the path at
/// each stage.
fn in_engine(
    analysis: &Analysis,
    paths: &[SupportPath],
    scale: &PathScale,
    settings: &SettleSettings,
    engine: Engine,
    progress: Heard,
) -> Run {
    let assembly = &analysis.assembly;
    let drop = engine_settings(settings, engine);
    let unit = speed_unit(assembly);
    let ramp = if engine == Engine::Exact { ramp_steps(assembly, settings) } else { 0.0 };
    let pace = Pace::new(engine_steps(assembly, scale, settings), ramp);
    let steps = pace.steps();
    let every = (steps / settings.increments).max(1);
    let mut run = Run::new(engine.name(), engine);
    let mut stepper = Stepper::with_paths(assembly, &drop, paths);
    if let Stepper::Exact(w) = &stepper {
        run.frame(w, 0.0);
    }
    let mut speeds = Vec::with_capacity(steps);
    // The exact engine's last stage whose configuration an equilibrium holds, and its step.
    let mut holding = match &stepper {
        Stepper::Exact(w) => Some(((**w).clone(), 0)),
        Stepper::Rapier(_) => None,
    };
    for k in 1..=steps {
        stepper.step_supports(pace.covered(k) - pace.covered(k - 1));
        run.steps += 1;
        if let Stepper::Exact(w) = &stepper
            && let Some(status) = failure(w)
        {
            return unresolved(run, pace.covered(k), status);
        }
        speeds.push(stepper.fastest(assembly));
        // Fast blocks an equilibrium still holds where they are follow the supports' pace at a
        // turn of the geometry (a flat arch near its end); the exact engine runs on.
        let still_held = |stepper: &Stepper, steps: &mut usize| match stepper {
            Stepper::Exact(w) => increment(&mut (**w).clone(), 0.0, steps),
            Stepper::Rapier(_) => false,
        };
        if speeds[k - 1] > settings.collapse_speed * unit && !still_held(&stepper, &mut run.steps) {
            let left = match holding.take() {
                Some((held, from)) => first_unheld(held, (from, k), &pace, &mut run.steps),
                None => departure(&speeds),
            };
            let fraction = pace.covered(left);
            let movement = fraction * scale.movement;
            run.outcome = Outcome::Collapses { fraction, movement, relative: movement / assembly.scale };
            if let Stepper::Exact(w) = &stepper {
                run.mechanism = joints(assembly, &analysis.interfaces, w);
                run.frame(w, k as f64 / steps as f64);
            }
            return run;
        }
        if k % every == 0 {
            let fraction = pace.covered(k);
            progress(fraction);
            let s = match &mut stepper {
                Stepper::Exact(w) => {
                    let mut stopped = (**w).clone();
                    if increment(&mut stopped, 0.0, &mut run.steps) {
                        holding = Some(((**w).clone(), k));
                    }
                    run.frame(w, fraction);
                    let s = stage(assembly, &analysis.interfaces, w, fraction, scale);
                    w.mark_slips();
                    s
                }
                // rapier's joints are not classified: the stage has its movement and reactions
                // (read from its contact impulses, `Simulation::contact_force`).
                Stepper::Rapier(sim) => Stage {
                    fraction,
                    movement: fraction * scale.movement,
                    reactions: paths.iter().map(|p| sim.contact_force(p.block).into()).collect(),
                    joints: Vec::new(),
                    rotation: f64::NAN,
                    snapped: false,
                },
            };
            run.stages.push(s);
        }
    }
    run
}

/// The exact engine's collapse: the first step after `bracket.0` (whose configuration `held`,
/// an equilibrium holds) at which the blocks, stopped where the engine has them, no longer stay
/// at rest — found by bisection up to `bracket.1` (the step past the collapse speed, returned
/// when every step before it holds: a fall carried by the blocks' momentum). It is the
/// engine's own path judged as the quasi-static run judges its increments: where the pace of
/// the blocks grows with the geometry (a flat arch's halves turn ever faster as their crown
/// contact nears the hinges' level) no rule on speeds tells it from a fall.
fn first_unheld(mut held: World, bracket: (usize, usize), pace: &Pace, steps: &mut usize) -> usize {
    let (mut lo, mut hi) = bracket;
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        let mut w = held.clone();
        for j in lo + 1..=mid {
            w.step_supports(pace.covered(j) - pace.covered(j - 1));
            *steps += 1;
        }
        let mut stopped = w.clone();
        if increment(&mut stopped, 0.0, steps) {
            (lo, held) = (mid, w);
        } else {
            hi = mid;
        }
    }
    hi
}

/// Blocks faster than this multiple of their pace following the supports have left it.
const DEPARTURE: f64 = 1.25;

/// The step at which the blocks left the supports' pace, given every step's fastest block
/// speed up to the one past the collapse speed: the first of the last run of steps faster than
/// [`DEPARTURE`] × the median (the pace at which the blocks followed the supports).
/// √(g × the median block size), m/s: the engines' runs' speeds are fractions of it.
fn speed_unit(assembly: &Assembly) -> f64 {
    let g = assembly.gravity.norm().max(f64::MIN_POSITIVE);
    let size = assembly.median_block_size().unwrap_or(1.0).max(f64::MIN_POSITIVE);
    (g * size).sqrt()
}

/// The steps of dt an engine's run takes to cover the path at the settings' speed.
fn engine_steps(assembly: &Assembly, scale: &PathScale, settings: &SettleSettings) -> f64 {
    let duration = scale.travel / (settings.speed * speed_unit(assembly));
    (duration / settings.dt).ceil()
}

/// The exact engine's runs start the supports from rest, reaching their speed in this many
/// √(block size / g): a support that starts at full speed leaves rigid blocks behind in its
/// first step (no finite force gives them its speed at once), and a flat arch whose halves must
/// turn to follow it falls through the opened joints. rapier's soft contacts take such a start
/// in their compliance; its runs keep the even pace.
const RAMP: f64 = 1.0;

/// The steps of dt in which the supports reach their speed ([`RAMP`]).
fn ramp_steps(assembly: &Assembly, settings: &SettleSettings) -> f64 {
    let g = assembly.gravity.norm().max(f64::MIN_POSITIVE);
    let size = assembly.median_block_size().unwrap_or(1.0).max(f64::MIN_POSITIVE);
    (std::env::var("RAMPX").ok().and_then(|s| s.parse::<f64>().ok()).unwrap_or(RAMP) * (size / g).sqrt() / settings.dt)
        .ceil()
}

/// How the engines' runs cover the path: the speed rising linearly over `ramp` steps (none: 0)
/// to the speed that covers the path in `plain` steps, then held.
struct Pace {
    plain: f64,
    ramp: f64,
}

impl Pace {
    fn new(plain: f64, ramp: f64) -> Self {
        Self { plain: plain.max(1.0), ramp: ramp.max(0.0) }
    }

    /// Full-speed steps' worth of path covered after `k` steps.
    fn distance(&self, k: f64) -> f64 {
        if k < self.ramp { 0.5 * k * k / self.ramp } else { k - 0.5 * self.ramp }
    }

    /// The fraction of the path covered after `k` steps (the speed scaled a little so that the
    /// last step is a whole one: a short last step would brake the supports).
    fn covered(&self, k: usize) -> f64 {
        (self.distance(k as f64) / self.distance(self.steps() as f64)).min(1.0)
    }

    /// The steps that cover the whole path.
    fn steps(&self) -> usize {
        let k = if self.plain <= 0.5 * self.ramp {
            (2.0 * self.ramp * self.plain).sqrt()
        } else {
            self.plain + 0.5 * self.ramp
        };
        (k.ceil() as usize).max(1)
    }
}

fn departure(speeds: &[f64]) -> usize {
    let mut sorted = speeds.to_vec();
    sorted.sort_by(f64::total_cmp);
    let pace = sorted[sorted.len() / 2];
    let mut k = speeds.len();
    while k > 1 && speeds[k - 2] > DEPARTURE * pace {
        k -= 1;
    }
    k
}
