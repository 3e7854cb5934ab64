//! The repair plugin: a [`RunRepair`] request runs [`crate::synthesis::repair()`] on the current
//! design off the main thread (bevy's async compute pool, so the app keeps drawing); when it
//! ends, [`RepairStatus`] holds the report and the cuts the repair changed move from where
//! they were to where it put them over [`ANIMATION_FRAMES`] updates — one `MoveCut` edit per
//! changed cut per update, so every frame of the motion is analysed and drawn. All the search
//! is the core's.

use super::{Design, EditDesign, Settings, VoussoirSet};
use crate::model::edit::Edit;
use crate::synthesis::{self, CutChange, DesignError, RepairReport, RepairSettings};
use bevy::app::{App, Plugin, Update};
use bevy::ecs::prelude::*;
use bevy::tasks::{AsyncComputeTaskPool, Task, futures::check_ready};

/// Updates over which a repaired cut moves into place.
pub const ANIMATION_FRAMES: u32 = 30;

/// Runs repairs and animates their cuts.
pub struct RepairPlugin;

impl Plugin for RepairPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<RunRepair>()
            .init_resource::<RepairStatus>()
            .add_systems(Update, (start_repair, finish_repair, animate_repair).chain().before(VoussoirSet::Edit));
    }
}

/// A request to repair the current design (the settings choose the cuts that may move).
#[derive(Message, Clone, Debug, Default)]
pub struct RunRepair(pub RepairSettings);

/// The running repair, the last report and the cuts moving into place.
#[derive(Resource, Default)]
pub struct RepairStatus {
    running: Option<Task<Result<RepairReport, DesignError>>>,
    /// The design the running repair started from.
    started_from: Option<crate::model::Scene>,
    /// The last finished repair's report.
    pub report: Option<RepairReport>,
    animation: Option<Animation>,
    /// Why the last repair could not run, when it could not.
    pub error: Option<String>,
    /// Repairs finished, their cuts in place (a viewer adopts the design when this grows).
    pub finished: u64,
}

impl RepairStatus {
    /// Whether a repair is searching (off the main thread).
    pub fn running(&self) -> bool {
        self.running.is_some()
    }

    /// Whether the repaired cuts are gliding into place.
    pub fn animating(&self) -> bool {
        self.animation.is_some()
    }
}

struct Animation {
    changes: Vec<CutChange>,
    frame: u32,
}

fn start_repair(
    mut requests: MessageReader<RunRepair>,
    design: Res<Design>,
    settings: Res<Settings>,
    mut status: ResMut<RepairStatus>,
) {
    let Some(RunRepair(repair)) = requests.read().last().cloned() else { return };
    if status.running() || status.animating() {
        status.error = Some("a repair is already running".into());
        return;
    }
    let Some(scene) = design.0.clone() else {
        status.error = Some("repair: there is no design".into());
        return;
    };
    let analysis = settings.0.clone();
    let from = scene.clone();
    let task =
        AsyncComputeTaskPool::get().spawn(async move { synthesis::repair(&scene, &analysis, &repair, &|_, _, _| {}) });
    *status =
        RepairStatus { running: Some(task), started_from: Some(from), finished: status.finished, ..Default::default() };
}

/// Takes the report when the search is done; starts the cuts moving unless the design was
/// edited meanwhile (then the report stands, but nothing moves).
fn finish_repair(design: Res<Design>, mut status: ResMut<RepairStatus>) {
    let status = &mut *status;
    let Some(task) = &mut status.running else { return };
    let Some(result) = check_ready(task) else { return };
    status.running = None;
    let from = status.started_from.take();
    match result {
        Ok(report) if report.changed.is_empty() => {
            status.report = Some(report);
            status.finished += 1;
        }
        Ok(report) if design.0 != from => {
            status.error = Some("the design changed while the repair ran: its cuts were not moved".into());
            status.report = Some(report);
        }
        Ok(report) => {
            status.animation = Some(Animation { changes: report.changed.clone(), frame: 0 });
            status.report = Some(report);
        }
        Err(e) => status.error = Some(e.to_string()),
    }
}

/// Moves the changed cuts one frame further (eased in and out); the last frame puts them
/// exactly where the repair did.
fn animate_repair(mut status: ResMut<RepairStatus>, mut edits: MessageWriter<EditDesign>) {
    let status = &mut *status;
    let Some(animation) = &mut status.animation else { return };
    animation.frame += 1;
    let last = animation.frame >= ANIMATION_FRAMES;
    let s = f64::from(animation.frame) / f64::from(ANIMATION_FRAMES);
    let eased = s * s * (3.0 - 2.0 * s);
    for c in &animation.changes {
        let cut =
            if last { c.after.clone() } else { c.before.toward(&c.after, eased).unwrap_or_else(|| c.after.clone()) };
        edits.write(EditDesign(Edit::MoveCut { index: c.index, cut }));
    }
    if last {
        status.animation = None;
        status.finished += 1;
    }
}
