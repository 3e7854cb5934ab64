//! The drop-test plugin: a [`RunDropTest`] request starts the drop test of the current analysis
//! on its engine, a [`CompareDropTests`] request on both engines at once (rapier first, then the
//! exact-contact engine, each a [`DropLane`]); FixedUpdate advances every running lane by the
//! steps that fit in one fixed tick and writes each block entity's poses ([`BlockPose`] the first
//! lane's, [`ComparedPose`] the second's); when a lane's simulated duration is reached, it holds
//! its outcome beside the statics' verdict. All physics is [`crate::dynamics::DropRun`].

use super::{BlockIndex, PipelineState, VoussoirSet};
use crate::dynamics::{DropResult, DropRun, DropSettings, Engine};
use crate::geometry::Point3;
use bevy::app::{App, FixedUpdate, Plugin, Update};
use bevy::ecs::prelude::*;
use bevy::time::{Fixed, Time};

/// Steps the drop test on the block entities.
pub struct DynamicsPlugin;

impl Plugin for DynamicsPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<RunDropTest>()
            .add_message::<CompareDropTests>()
            .init_resource::<DropStatus>()
            .add_systems(Update, start_drop_test.after(VoussoirSet::Write))
            .add_systems(FixedUpdate, step_drop_test);
    }
}

/// A request to drop-test the current design on `settings.engine`.
#[derive(Message, Clone, Debug, Default)]
pub struct RunDropTest(pub DropSettings);

/// A request to drop-test the current design on both engines side by side, with the same
/// settings (their `engine` aside): rapier's lane first, the exact-contact engine's second.
#[derive(Message, Clone, Debug, Default)]
pub struct CompareDropTests(pub DropSettings);

/// A block's pose in the drop test: its centroid (m) and its rotation since the start (unit
/// quaternion [w, x, y, z]).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct BlockPose {
    /// Its mass centre, m.
    pub centroid: Point3,
    /// Its rotation since the start, a unit quaternion [w, x, y, z].
    pub rotation: [f64; 4],
}

/// A block's pose in the second lane of a comparison (the exact-contact engine's).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ComparedPose(pub BlockPose);

/// One engine's drop test: running, or its outcome.
#[derive(Default)]
pub struct DropLane {
    /// The run under way (stepped a little every frame), until it finishes.
    pub running: Option<DropRun>,
    /// The finished run's verdict and motion.
    pub result: Option<DropResult>,
    /// Whether this lane's verdict equals the statics' (when both exist).
    pub agree: Option<bool>,
}

impl DropLane {
    /// The lane's engine (rapier or exact).
    pub fn engine(&self) -> Engine {
        match (&self.running, &self.result) {
            (Some(run), _) => run.engine(),
            (None, Some(r)) => r.engine,
            _ => Engine::default(),
        }
    }

    /// Simulated time so far and in all, s.
    pub fn clock(&self) -> (f64, f64) {
        match (&self.running, &self.result) {
            (Some(run), _) => (run.steps_done() as f64 * run.dt(), run.total_steps() as f64 * run.dt()),
            (None, Some(r)) => (r.simulated_s, r.simulated_s),
            _ => (0.0, 0.0),
        }
    }
}

/// The drop tests under way or done: one lane, or two when the engines are compared.
#[derive(Resource, Default)]
pub struct DropStatus {
    /// One lane per engine tested.
    pub lanes: Vec<DropLane>,
    /// Block names in the order of the runs' assembly.
    names: Vec<String>,
    /// Why the drop test could not start, when it could not.
    pub error: Option<String>,
}

impl DropStatus {
    /// The first lane (the only one unless the engines are compared).
    pub fn lead(&self) -> Option<&DropLane> {
        self.lanes.first()
    }

    /// Whether any lane is still running.
    pub fn running(&self) -> bool {
        self.lanes.iter().any(|l| l.running.is_some())
    }

    /// Whether the engines are compared (two lanes).
    pub fn compared(&self) -> bool {
        self.lanes.len() > 1
    }

    /// Every lane finished.
    pub fn done(&self) -> bool {
        !self.lanes.is_empty() && self.lanes.iter().all(|l| l.result.is_some())
    }

    /// Drops every lane and error (an edit makes them stale).
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

fn start_drop_test(
    mut single: MessageReader<RunDropTest>,
    mut compare: MessageReader<CompareDropTests>,
    state: Res<PipelineState>,
    mut status: ResMut<DropStatus>,
) {
    let single = single.read().last().map(|r| vec![r.0.clone()]);
    let compared = compare
        .read()
        .last()
        .map(|r| [Engine::Rapier, Engine::Exact].map(|engine| DropSettings { engine, ..r.0.clone() }).to_vec());
    let Some(lanes) = compared.or(single) else { return };
    let Some(analysis) = &state.analysis else {
        status.error = Some("drop test: there is no analysed design".into());
        return;
    };
    let runs: Result<Vec<DropRun>, _> = lanes.iter().map(|s| DropRun::new(&analysis.assembly, s)).collect();
    match runs {
        Ok(runs) => {
            *status = DropStatus {
                lanes: runs.into_iter().map(|run| DropLane { running: Some(run), ..Default::default() }).collect(),
                names: analysis.assembly.blocks.iter().map(|b| b.name.clone()).collect(),
                error: None,
            };
        }
        Err(e) => status.error = Some(e.to_string()),
    }
}

fn step_drop_test(
    mut commands: Commands,
    time: Res<Time<Fixed>>,
    mut status: ResMut<DropStatus>,
    state: Res<PipelineState>,
    index: Res<BlockIndex>,
) {
    let status = &mut *status;
    for (lane_index, lane) in status.lanes.iter_mut().enumerate() {
        let Some(run) = &mut lane.running else { continue };
        // The simulated time keeps pace with the fixed clock.
        let per_tick = (time.timestep().as_secs_f64() / run.dt()).round().max(1.0) as usize;
        run.advance(per_tick);
        for (i, name) in status.names.iter().enumerate() {
            if let Some(&e) = index.0.get(name) {
                let (centroid, rotation) = run.pose(i);
                let pose = BlockPose { centroid, rotation };
                match lane_index {
                    0 => commands.entity(e).insert(pose),
                    _ => commands.entity(e).insert(ComparedPose(pose)),
                };
            }
        }
        if run.finished() {
            let result = run.result();
            lane.agree = state.analysis.as_ref().map(|a| a.statics.stands == result.stands);
            lane.result = Some(result);
            lane.running = None;
        }
    }
}
