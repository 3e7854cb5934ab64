//! The shake plugin: a [`RunShake`] request shakes the current design by a ground motion with
//! [`crate::studies::shake::shake_study`] (the static load factor beside each engine's run), on
//! a thread of its own; [`ShakeStatus`] holds the outcome, then plays the first engine's motion
//! back in simulated time: every block entity gets its [`ShakePose`] at the play clock, and the
//! ground's acceleration then is [`ShakeStatus::ground_now`].

use super::{BlockIndex, BlockPose, PipelineState, Settings, VoussoirSet};
use crate::dynamics::{Engine, GroundMotion};
use crate::studies::shake::{ShakeSettings, ShakeStudy, shake_study};
use bevy::app::{App, Plugin, Update};
use bevy::ecs::prelude::*;
use bevy::time::Time;
use std::thread::JoinHandle;

/// Frames a simulated second kept for playback.
pub const SHAKE_FPS: f64 = 30.0;

/// Runs shakes and plays their motion on the block entities.
pub struct ShakePlugin;

impl Plugin for ShakePlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<RunShake>()
            .init_resource::<ShakeStatus>()
            .add_systems(Update, (start_shake, finish_shake, play_shake).chain().after(VoussoirSet::Write));
    }
}

/// A request to shake the current design.
#[derive(Message, Clone, Debug)]
pub struct RunShake {
    /// The ground motion (checked when the run starts).
    pub motion: GroundMotion,
    /// How each run goes (its engine replaced by each of `engines`').
    pub settings: ShakeSettings,
    /// The engines, the first one played back.
    pub engines: Vec<Engine>,
}

/// A block's pose in the shake's motion at the play clock.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ShakePose(pub BlockPose);

/// The shake under way or done, and its playback.
#[derive(Resource, Default)]
pub struct ShakeStatus {
    running: Option<JoinHandle<Result<ShakeStudy, String>>>,
    /// Block names in the order of the analysed assembly.
    names: Vec<String>,
    /// The finished shake: λ* and each engine's run.
    pub result: Option<ShakeStudy>,
    /// Why it could not run, when it could not.
    pub error: Option<String>,
    /// Playback clock, simulated s.
    pub clock: f64,
}

impl ShakeStatus {
    /// Whether a shake is running (on its own thread).
    pub fn running(&self) -> bool {
        self.running.is_some()
    }

    /// The played run's frame at the clock and its time, s.
    pub fn frame(&self) -> Option<(usize, f64)> {
        let motion = self.result.as_ref()?.runs.first()?.frames.as_ref()?;
        let k = motion.times.iter().rposition(|&t| t <= self.clock).unwrap_or(0);
        Some((k, motion.times[k]))
    }

    /// The ground's acceleration at the clock (the played run's trace), in the design's g.
    pub fn ground_now(&self) -> Option<f64> {
        let trace = &self.result.as_ref()?.runs.first()?.trace;
        let k = trace.times.iter().rposition(|&t| t <= self.clock)?;
        trace.ground_g.get(k).copied()
    }

    /// The playback reached the run's end.
    pub fn played(&self) -> bool {
        self.end().is_some_and(|end| self.clock >= end)
    }

    /// The played run's last time, s.
    fn end(&self) -> Option<f64> {
        self.result.as_ref()?.runs.first()?.trace.times.last().copied()
    }

    /// Forgets the run, its result and the playback (an edit makes them stale).
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

fn start_shake(
    mut requests: MessageReader<RunShake>,
    state: Res<PipelineState>,
    settings: Res<Settings>,
    mut status: ResMut<ShakeStatus>,
) {
    let Some(request) = requests.read().last().cloned() else { return };
    let Some(analysis) = &state.analysis else {
        *status = ShakeStatus { error: Some("shake: there is no analysed design".into()), ..Default::default() };
        return;
    };
    if !analysis.statics.stands || request.engines.is_empty() {
        let why = if request.engines.is_empty() { "no engine named" } else { "the design does not stand as drawn" };
        *status = ShakeStatus { error: Some(format!("shake: {why}")), ..Default::default() };
        return;
    }
    let (analysis, statics) = (analysis.clone(), settings.0.statics.clone());
    let names = analysis.assembly.blocks.iter().map(|b| b.name.clone()).collect();
    let handle = std::thread::spawn(move || {
        let r = &request;
        shake_study(&analysis, &statics, &r.motion, &r.settings, &r.engines, Some(SHAKE_FPS)).map_err(|e| e.to_string())
    });
    *status = ShakeStatus { running: Some(handle), names, ..Default::default() };
}

fn finish_shake(mut status: ResMut<ShakeStatus>) {
    if !status.running.as_ref().is_some_and(|h| h.is_finished()) {
        return;
    }
    let handle = status.running.take().expect("checked above");
    match handle.join() {
        Ok(Ok(s)) => status.result = Some(s),
        Ok(Err(e)) => status.error = Some(format!("shake: {e}")),
        Err(_) => status.error = Some("shake: the run stopped unexpectedly".into()),
    }
}

/// Advances the clock and writes the frame's poses (only when the frame changes).
fn play_shake(
    mut commands: Commands,
    time: Res<Time>,
    mut status: ResMut<ShakeStatus>,
    index: Res<BlockIndex>,
    mut shown: Local<Option<usize>>,
) {
    if status.result.is_none() {
        *shown = None;
        return;
    }
    if !status.played() {
        let end = status.end().unwrap_or(0.0);
        status.clock = (status.clock + time.delta_secs_f64()).min(end);
    }
    let Some((k, _)) = status.frame() else { return };
    if *shown == Some(k) {
        return;
    }
    *shown = Some(k);
    let run = status.result.as_ref().and_then(|r| r.runs.first()).expect("checked above");
    let poses = &run.frames.as_ref().expect("a frame").poses[k];
    for (name, &(centroid, rotation)) in status.names.iter().zip(poses) {
        if let Some(&e) = index.0.get(name) {
            commands.entity(e).insert(ShakePose(BlockPose { centroid, rotation }));
        }
    }
}
