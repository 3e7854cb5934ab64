//! Scripted runs: a list of [`ScriptStep`]s (actions, waits, loads, screenshots) played in
//! order, then a JSON report of what was on screen at every shot, then exit. The screenshots
//! are the real window's pixels (bevy's screenshot of the primary window), written as PNG
//! atomically. `voussoir view --screenshot` and the rendering test run through here.

use super::actions::{ViewerAction, ViewerState};
use super::camera::{ComparedCamera, MainCamera, PhysicsCamera};
use super::hud::{PanelLayout, Shown};
use super::motion::PaneCounts;
use crate::ecs::{DropStatus, EditDesign, InterfaceColors, PipelineState, RepairStatus, SequenceStatus, SettleStatus};
use crate::model::Scene;
use crate::model::edit::Edit;
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::{Render, RenderApp};
use serde_json::{Value, json};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// One step of a script.
#[derive(Clone, Debug)]
pub enum ScriptStep {
    Act(ViewerAction),
    /// Replace the design (the viewer's undo history starts again).
    Load(Box<Scene>),
    /// Wait until the analysis, the colours, a running drop test or repair and a requested
    /// sequence are done, then this many frames more (for the renderer to catch up).
    Settle(u32),
    /// Screenshot of the window to this PNG path.
    Shot(PathBuf),
}

/// A scripted run and where its report goes.
#[derive(Clone, Debug, Default)]
pub struct Script {
    pub steps: Vec<ScriptStep>,
    /// JSON report: one entry per shot (path, verdict, mode, counts, viewports, …).
    pub report: Option<PathBuf>,
}

pub struct CapturePlugin(pub Option<Script>);

impl Plugin for CapturePlugin {
    fn build(&self, app: &mut App) {
        if let Some(script) = &self.0 {
            let ready = PipelinesReady::default();
            app.insert_resource(Runner { script: script.clone(), ..default() })
                .insert_resource(ready.clone())
                .add_systems(Update, run_script.before(super::actions::ActionSystems));
            if let Some(render) = app.get_sub_app_mut(RenderApp) {
                render.insert_resource(ready).add_systems(Render, report_pipelines);
            }
        }
    }
}

/// Whether the renderer has compiled every pipeline it was asked for (shaders compile in the
/// background: until then new meshes are not drawn). Written in the render world.
#[derive(Resource, Clone, Default)]
struct PipelinesReady(Arc<AtomicBool>);

fn report_pipelines(cache: Res<PipelineCache>, ready: Res<PipelinesReady>) {
    ready.0.store(cache.waiting_pipelines().next().is_none(), Ordering::Relaxed);
}

/// Frames after which a script gives up (a stuck settle or screenshot).
const MAX_FRAMES: u64 = 20_000;

#[derive(Resource, Default)]
struct Runner {
    script: Script,
    next: usize,
    /// Frames still to wait, and the count to restart from when the renderer is busy.
    wait: u32,
    settle: u32,
    settling: bool,
    in_flight: bool,
    frames: u64,
    shots: Vec<Value>,
    failed: Option<String>,
}

fn run_script(
    mut commands: Commands,
    mut runner: ResMut<Runner>,
    mut state: ResMut<ViewerState>,
    busy: Busy,
    mut actions: MessageWriter<ViewerAction>,
    mut edits: MessageWriter<EditDesign>,
    mut exit: MessageWriter<AppExit>,
) {
    runner.frames += 1;
    if runner.frames > MAX_FRAMES {
        runner.failed = Some(format!("script stuck at step {}", runner.next));
    }
    if let Some(why) = runner.failed.take() {
        error!("{why}");
        exit.write(AppExit::error());
        return;
    }
    if runner.in_flight {
        return;
    }
    if runner.settling && !settled(&mut runner, busy.any(&state), busy.compiled()) {
        return;
    }
    if next_steps(&mut runner, &mut commands, &mut state, &mut actions, &mut edits) {
        finish(&runner, &mut exit);
    }
}

/// What a `Settle` step waits for: the pipeline and every job at rest, what they spawned
/// drawn, and every render pipeline compiled.
#[derive(bevy::ecs::system::SystemParam)]
struct Busy<'w, 's> {
    ready: Res<'w, PipelinesReady>,
    pipeline: Res<'w, PipelineState>,
    drop: Res<'w, DropStatus>,
    settle: Res<'w, SettleStatus>,
    shake: Res<'w, crate::ecs::ShakeStatus>,
    sequence: Res<'w, SequenceStatus>,
    repair: Res<'w, RepairStatus>,
    coloured: Query<'w, 's, (), With<InterfaceColors>>,
}

impl Busy<'_, '_> {
    fn compiled(&self) -> bool {
        self.ready.0.load(Ordering::Relaxed)
    }

    fn any(&self, state: &ViewerState) -> bool {
        let (pipeline, settle, sequence) = (&self.pipeline, &self.settle, &self.sequence);
        pipeline.dirty
            || self.drop.running()
            || settle.running()
            || (state.settle_view && settle.result.is_some() && !settle.played())
            || self.shake.running()
            || (state.shake_view && self.shake.result.is_some() && !self.shake.played())
            || self.repair.running()
            || self.repair.animating()
            || (state.sequence_view && sequence.error.is_none() && sequence.analysis.is_none())
            || (pipeline.analysis.as_ref().is_some_and(|a| !a.statics.interfaces.is_empty())
                && self.coloured.is_empty())
    }
}

/// Whether a `Settle` step is over: its frames counted with nothing busy, again from the start
/// while a pipeline still compiles (consecutive frames with every pipeline compiled: what was
/// spawned is on screen).
fn settled(runner: &mut Runner, busy: bool, compiled: bool) -> bool {
    if busy {
        return false;
    }
    if !compiled {
        runner.wait = runner.settle;
        return false;
    }
    if runner.wait > 0 {
        runner.wait -= 1;
        return false;
    }
    runner.settling = false;
    true
}

/// Sends the script's steps up to the next one that waits (a settle or a shot); true when the
/// script has ended.
fn next_steps(
    runner: &mut Runner,
    commands: &mut Commands,
    state: &mut ViewerState,
    actions: &mut MessageWriter<ViewerAction>,
    edits: &mut MessageWriter<EditDesign>,
) -> bool {
    while let Some(step) = runner.script.steps.get(runner.next).cloned() {
        runner.next += 1;
        match step {
            ScriptStep::Act(a) => {
                actions.write(a);
            }
            ScriptStep::Load(scene) => {
                let scene = *scene;
                state.design = scene.clone();
                state.undo.clear();
                state.redo.clear();
                state.frame_pending = true;
                edits.write(EditDesign(Edit::Load(Box::new(scene))));
            }
            ScriptStep::Settle(frames) => {
                runner.settling = true;
                // The requests just sent are applied later this frame: look from the next one.
                runner.wait = frames;
                runner.settle = frames;
                return false;
            }
            ScriptStep::Shot(path) => {
                runner.in_flight = true;
                commands.spawn(Screenshot::primary_window()).observe(
                    move |shot: On<ScreenshotCaptured>, mut runner: ResMut<Runner>, info: ShotInfo| {
                        runner.in_flight = false;
                        match write_png(&path, &shot.image) {
                            Ok(size) => runner.shots.push(info.describe(&path, size)),
                            Err(e) => runner.failed = Some(format!("screenshot {}: {e}", path.display())),
                        }
                    },
                );
                return false;
            }
        }
    }
    true
}

/// The script has ended: its report written (when it asks for one), and the app's exit.
fn finish(runner: &Runner, exit: &mut MessageWriter<AppExit>) {
    if let Some(report) = &runner.script.report {
        let text = serde_json::to_string_pretty(&json!({ "shots": runner.shots })).expect("plain JSON");
        if let Err(e) = crate::io::write_atomic(report, text.as_bytes()) {
            error!("report {}: {e}", report.display());
            exit.write(AppExit::error());
            return;
        }
    }
    exit.write(AppExit::Success);
}

/// What was on screen when a shot was taken.
#[derive(bevy::ecs::system::SystemParam)]
struct ShotInfo<'w, 's> {
    shown: Shown<'w>,
    panel: PanelLayout<'w, 's>,
    pane: PaneCounts<'w, 's>,
    main: Query<'w, 's, &'static Camera, With<MainCamera>>,
    physics: Query<'w, 's, &'static Camera, With<PhysicsCamera>>,
    compared: Query<'w, 's, &'static Camera, With<ComparedCamera>>,
    thrust_plot: Query<'w, 's, &'static Node, With<super::motion::ThrustPlotNode>>,
}

impl ShotInfo<'_, '_> {
    fn describe(&self, path: &std::path::Path, size: (u32, u32)) -> Value {
        let Shown { state, status, pipeline, drop, settle, shake, sequence, robustness, kinematic } = &self.shown;
        let rect = |c: &Camera| {
            c.physical_viewport_rect().filter(|_| c.is_active).map(|r| [r.min.x, r.min.y, r.max.x, r.max.y])
        };
        let a = pipeline.analysis.as_ref();
        let threshold = match state.mode {
            crate::viz::DiagramMode::Friction { threshold } => threshold,
            _ => crate::viz::DiagramMode::DEFAULT_THRESHOLD,
        };
        // Each interface's friction band, as the friction diagram colours it.
        let bands: Vec<Value> = a.map_or(Vec::new(), |a| {
            let s = &a.statics;
            s.interfaces
                .iter()
                .map(|r| {
                    let band = crate::viz::friction_band(r, s.friction_coefficient, s.friction_model, threshold);
                    json!({ "interface": format!("{} | {}", r.a, r.b), "use": r.friction_utilization,
                            "band": band.name(), "colour": band.colour(threshold) })
                })
                .collect()
        });
        let headline = self.shown.headline();
        json!({
            "headline": headline.text,
            "disagrees": headline.disagrees,
            "panel": self.panel.describe(&self.shown),
            "caption": self.shown.caption(),
            "view_caption": self.shown.view_caption(),
            "pane": self.pane.describe(),
            "friction_bands": bands,
            "max_friction_use": a.map(|a| a.statics.max_friction_utilization),
            "path": path.display().to_string(),
            "size": [size.0, size.1],
            "mode": format!("{:?}", state.mode),
            "verdict": status.verdict.map(|v| format!("{v:?}")),
            "stands": status.stands,
            "error": status.error,
            "blocks": a.map_or(0, |a| a.assembly.blocks.len()),
            "interfaces": a.map_or(0, |a| a.interfaces.len()),
            "cuts": state.design.cuts.len(),
            "removed": state.design.removed.clone(),
            "undo": state.undo.len(),
            "redo": state.redo.len(),
            "message": state.message,
            "translucent": state.translucent,
            "drop_stands": drop.lead().and_then(|l| l.result.as_ref()).map(|r| r.stands),
            "drop_agrees": drop.lead().and_then(|l| l.agree),
            "settle": settle.result.as_ref().map(|r| json!({
                "outcome": r.quasi_static.outcome,
                "played": settle.played(),
                "fraction": settle.frame().map(|f| f.1),
            })),
            "settle_error": settle.error,
            "shake": shake.result.as_ref().map(|r| json!({
                "static_load_factor": r.static_load_factor,
                "collapsed": r.runs.first().map(|run| run.collapsed),
                "played": shake.played(),
                "ground_g": shake.ground_now(),
            })),
            "shake_error": shake.error,
            "thrust_plot_shown": self.thrust_plot.single().is_ok_and(|n| n.display != Display::None),
            "drop_lanes": drop.lanes.iter().filter_map(|l| l.result.as_ref().map(|r| json!({
                "engine": r.engine,
                "stands": r.stands,
                "agrees": l.agree,
            }))).collect::<Vec<_>>(),
            "sequence_step": sequence.step().filter(|_| state.sequence_view).map(|s| json!({
                "index": sequence.current,
                "placed": s.placed,
                "stands": s.stands,
                "drop_stands": s.dynamic.as_ref().map(|d| d.stands),
            })),
            "load_factor": Some(robustness.load_factor()).filter(|l| !l.is_nan()),
            "worst_azimuth": robustness.worst_azimuth,
            "kinematic": kinematic.result.as_ref().map(|k| k.verdict),
            "kinematic_agrees": kinematic.result.as_ref().map(|k| k.agrees),
            "kinematic_moving": kinematic.result.as_ref().and_then(|k| k.mechanism.as_ref()).map(|m| m.blocks.len()),
            "main_viewport": self.main.single().ok().and_then(rect),
            "physics_viewport": self.physics.single().ok().and_then(rect),
            "compared_viewport": self.compared.single().ok().and_then(rect),
            "compared_caption": self.shown.lane_caption(1),
        })
    }
}

/// The screenshot as an RGB PNG, written atomically; returns its size.
fn write_png(path: &std::path::Path, image: &Image) -> Result<(u32, u32), String> {
    let rgb = image.clone().try_into_dynamic().map_err(|e| e.to_string())?.to_rgb8();
    let mut bytes = Vec::new();
    rgb.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).map_err(|e| e.to_string())?;
    crate::io::write_atomic(path, &bytes).map_err(|e| e.to_string())?;
    Ok(rgb.dimensions())
}
