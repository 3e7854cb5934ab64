//! The sequence plugin: [`StartSequence`] checks every step of an order on the current design
//! ([`crate::studies::sequence::check`]); [`StepSequence`] moves through the steps, marking the blocks
//! placed so far with [`Placed`] (what a viewer shows) and exposing the step's result — and its
//! full analysis, forces included — in [`SequenceStatus`]. [`SequenceSettings`] asks for the
//! drop test and the kinematic check of every step beside the statics.

use super::{BlockIndex, Design, Settings, VoussoirSet};
use crate::pipeline::Analysis;
use crate::studies::sequence::{OrderSpec, SequenceReport, Step, StepChecks, check, step_analysis};
use bevy::app::{App, Plugin, Update};
use bevy::ecs::prelude::*;

/// Assembly sequences in the app: [`StartSequence`] checks an order, [`StepSequence`] steps through it.
pub struct SequencePlugin;

impl Plugin for SequencePlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<StartSequence>()
            .add_message::<StepSequence>()
            .init_resource::<SequenceStatus>()
            .init_resource::<SequenceSettings>()
            .add_systems(Update, (start_sequence, step_sequence).chain().after(VoussoirSet::Write));
    }
}

/// Check this order of the current design and show its first step.
#[derive(Message, Clone, Debug)]
pub struct StartSequence(pub OrderSpec);

/// Move to another step: +1 forward, −1 back (clamped to the order).
#[derive(Message, Clone, Copy, Debug)]
pub struct StepSequence(pub i64);

/// What is checked at every step besides the statics (default: nothing).
#[derive(Resource, Clone, Debug, Default)]
pub struct SequenceSettings(pub StepChecks);

/// Marks a block placed at the current step.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placed;

/// The checked order and the step shown.
#[derive(Resource, Default, Debug)]
pub struct SequenceStatus {
    /// The checked order's steps.
    pub report: Option<SequenceReport>,
    /// The step shown, from 0.
    pub current: usize,
    /// The full analysis of the step shown (blocks placed so far, forces included).
    pub analysis: Option<Analysis>,
    /// Why the order could not be checked, when it could not.
    pub error: Option<String>,
}

impl SequenceStatus {
    /// The result of the step shown.
    pub fn step(&self) -> Option<&Step> {
        self.report.as_ref().and_then(|r| r.steps.get(self.current))
    }
}

fn start_sequence(
    mut requests: MessageReader<StartSequence>,
    design: Res<Design>,
    settings: Res<Settings>,
    sequence: Res<SequenceSettings>,
    mut status: ResMut<SequenceStatus>,
) {
    let Some(StartSequence(spec)) = requests.read().last() else { return };
    let Some(scene) = &design.0 else { return };
    *status = match check(scene, spec, &settings.0, &sequence.0, &|| {}) {
        Ok(r) => SequenceStatus { report: Some(r), ..Default::default() },
        Err(e) => SequenceStatus { error: Some(e.to_string()), ..Default::default() },
    };
}

fn step_sequence(
    mut commands: Commands,
    mut requests: MessageReader<StepSequence>,
    mut status: ResMut<SequenceStatus>,
    index: Res<BlockIndex>,
    design: Res<Design>,
    settings: Res<Settings>,
) {
    let moves: i64 = requests.read().map(|s| s.0).sum();
    if !status.is_changed() && moves == 0 {
        return;
    }
    let Some(n) = status.report.as_ref().map(|r| r.steps.len()) else { return };
    let current = (status.current as i64 + moves).clamp(0, n as i64 - 1) as usize;
    let moved = current != status.current || status.analysis.is_none();
    status.current = current;
    let report = status.report.as_ref().expect("checked above");
    if moved && let Some(scene) = &design.0 {
        match step_analysis(scene, report, current, &settings.0) {
            Ok(a) => status.analysis = Some(a),
            Err(e) => {
                status.analysis = None;
                status.error = Some(e.to_string());
            }
        }
    }
    let report = status.report.as_ref().expect("checked above");
    for (k, name) in report.order.iter().enumerate() {
        if let Some(&e) = index.0.get(name) {
            if k <= current {
                commands.entity(e).insert(Placed);
            } else {
                commands.entity(e).remove::<Placed>();
            }
        }
    }
}
