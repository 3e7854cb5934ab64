//! The drop-test plugin: a [`RunDropTest`] request starts the rapier drop test of the current
//! analysis; FixedUpdate advances it by the steps that fit in one fixed tick and writes each
//! block entity's [`BlockPose`]; when the simulated duration is reached, [`DropStatus`] holds
//! the outcome beside the statics' verdict. All physics is [`crate::dynamics::DropRun`].

use super::{BlockIndex, PipelineState, VoussoirSet};
use crate::dynamics::{DropResult, DropRun, DropSettings};
use crate::geometry::Point3;
use bevy::app::{App, FixedUpdate, Plugin, Update};
use bevy::ecs::prelude::*;
use bevy::time::{Fixed, Time};

/// Steps the drop test on the block entities.
pub struct DynamicsPlugin;

impl Plugin for DynamicsPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<RunDropTest>()
            .init_resource::<DropStatus>()
            .add_systems(Update, start_drop_test.after(VoussoirSet::Write))
            .add_systems(FixedUpdate, step_drop_test);
    }
}

/// A request to drop-test the current design.
#[derive(Message, Clone, Debug, Default)]
pub struct RunDropTest(pub DropSettings);

/// A block's pose in the drop test: its centroid (m) and its rotation since the start (unit
/// quaternion [w, x, y, z]).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct BlockPose {
    pub centroid: Point3,
    pub rotation: [f64; 4],
}

/// The running drop test and the last outcome.
#[derive(Resource, Default)]
pub struct DropStatus {
    pub running: Option<DropRun>,
    /// Block names in the order of the run's assembly.
    names: Vec<String>,
    pub result: Option<DropResult>,
    /// Whether the drop test's verdict equals the statics' (when both exist).
    pub agree: Option<bool>,
    pub error: Option<String>,
}

fn start_drop_test(
    mut requests: MessageReader<RunDropTest>,
    state: Res<PipelineState>,
    mut status: ResMut<DropStatus>,
) {
    let Some(RunDropTest(settings)) = requests.read().last() else { return };
    let Some(analysis) = &state.analysis else {
        status.error = Some("drop test: there is no analysed design".into());
        return;
    };
    match DropRun::new(&analysis.assembly, settings) {
        Ok(run) => {
            *status = DropStatus {
                running: Some(run),
                names: analysis.assembly.blocks.iter().map(|b| b.name.clone()).collect(),
                ..Default::default()
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
    let Some(run) = &mut status.running else { return };
    // The simulated time keeps pace with the fixed clock.
    let per_tick = (time.timestep().as_secs_f64() / run.dt()).round().max(1.0) as usize;
    run.advance(per_tick);
    for (i, name) in status.names.iter().enumerate() {
        if let Some(&e) = index.0.get(name) {
            let (centroid, rotation) = run.pose(i);
            commands.entity(e).insert(BlockPose { centroid, rotation });
        }
    }
    if run.finished() {
        let result = run.result();
        status.agree = state.analysis.as_ref().map(|a| a.statics.stands == result.stands);
        status.result = Some(result);
        status.running = None;
    }
}
