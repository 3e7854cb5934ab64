//! The settlement plugin: a [`RunSettlement`] request follows the current design along its
//! support movements (the scene's `movements`) with [`crate::studies::settlement::settle`], on a
//! thread of its own (the analysis takes seconds; the app keeps drawing); [`SettleStatus`] holds
//! the outcome, and then plays the quasi-static run's motion back: every block entity gets its
//! [`SettlePose`] at the play clock, the whole path (to the collapse) in [`PLAY_SECONDS`].

use super::{BlockIndex, BlockPose, Design, PipelineState, VoussoirSet};
use crate::studies::settlement::{SettleSettings, Settlement, settle};
use bevy::app::{App, Plugin, Update};
use bevy::ecs::prelude::*;
use bevy::time::Time;
use std::thread::JoinHandle;

/// Seconds of playback for the run's motion, start to end.
pub const PLAY_SECONDS: f64 = 5.0;

/// Runs settlement analyses and plays their motion on the block entities.
pub struct SettlePlugin;

impl Plugin for SettlePlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<RunSettlement>().init_resource::<SettleStatus>().add_systems(
            Update,
            (start_settlement, finish_settlement, play_settlement).chain().after(VoussoirSet::Write),
        );
    }
}

/// A request to follow the current design along its support movements.
#[derive(Message, Clone, Debug, Default)]
pub struct RunSettlement(pub SettleSettings);

/// A block's pose in the settlement's motion (the quasi-static run's) at the play clock.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SettlePose(pub BlockPose);

/// The settlement under way or done, and its playback.
#[derive(Resource, Default)]
pub struct SettleStatus {
    running: Option<JoinHandle<Result<Settlement, String>>>,
    /// Block names in the order of the analysed assembly.
    names: Vec<String>,
    /// The finished settlement's runs.
    pub result: Option<Settlement>,
    /// Why it could not run, when it could not.
    pub error: Option<String>,
    /// Playback clock, s (0 … [`PLAY_SECONDS`]).
    pub clock: f64,
}

impl SettleStatus {
    /// Whether a settlement is running (on its own thread).
    pub fn running(&self) -> bool {
        self.running.is_some()
    }

    /// The frame of the quasi-static run's motion shown at the clock, and its fraction of the
    /// path.
    pub fn frame(&self) -> Option<(usize, f64)> {
        let motion = &self.result.as_ref()?.quasi_static.motion;
        let end = *motion.times.last()?;
        let at = end * (self.clock / PLAY_SECONDS).min(1.0);
        let k = motion.times.iter().rposition(|&t| t <= at).unwrap_or(0);
        Some((k, motion.times[k]))
    }

    /// The playback reached its last frame.
    pub fn played(&self) -> bool {
        self.result.is_some() && self.clock >= PLAY_SECONDS
    }

    /// Forgets the run, its result and the playback (an edit makes them stale).
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

fn start_settlement(
    mut requests: MessageReader<RunSettlement>,
    design: Res<Design>,
    state: Res<PipelineState>,
    mut status: ResMut<SettleStatus>,
) {
    let Some(RunSettlement(settings)) = requests.read().last() else { return };
    let (Some(analysis), Some(scene)) = (&state.analysis, &design.0) else {
        status.error = Some("settlement: there is no analysed design".into());
        return;
    };
    if scene.movements.is_empty() {
        *status = SettleStatus {
            error: Some("settlement: the design moves no support (give it `movements`)".into()),
            ..Default::default()
        };
        return;
    }
    let (analysis, movements, settings) = (analysis.clone(), scene.movements.clone(), settings.clone());
    let names = analysis.assembly.blocks.iter().map(|b| b.name.clone()).collect();
    let handle = std::thread::spawn(move || settle(&analysis, &movements, &settings).map_err(|e| e.to_string()));
    *status = SettleStatus { running: Some(handle), names, ..Default::default() };
}

fn finish_settlement(mut status: ResMut<SettleStatus>) {
    if !status.running.as_ref().is_some_and(|h| h.is_finished()) {
        return;
    }
    let handle = status.running.take().expect("checked above");
    match handle.join() {
        Ok(Ok(s)) => status.result = Some(s),
        Ok(Err(e)) => status.error = Some(format!("settlement: {e}")),
        Err(_) => status.error = Some("settlement: the analysis stopped unexpectedly".into()),
    }
}

/// Advances the clock and writes the frame's poses (only when the frame changes).
fn play_settlement(
    mut commands: Commands,
    time: Res<Time>,
    mut status: ResMut<SettleStatus>,
    index: Res<BlockIndex>,
    mut shown: Local<Option<usize>>,
) {
    if status.result.is_none() {
        *shown = None;
        return;
    }
    if !status.played() {
        status.clock = (status.clock + time.delta_secs_f64()).min(PLAY_SECONDS);
    }
    let Some((k, _)) = status.frame() else { return };
    if *shown == Some(k) {
        return;
    }
    *shown = Some(k);
    let poses = &status.result.as_ref().expect("checked above").quasi_static.motion.poses[k];
    for (name, &(centroid, rotation)) in status.names.iter().zip(poses) {
        if let Some(&e) = index.0.get(name) {
            commands.entity(e).insert(SettlePose(BlockPose { centroid, rotation }));
        }
    }
}
