//! The kinematic plugin: while [`KinematicRequest`] asks for it, every analysis is followed by
//! the kinematic check (does the equilibrium the statics found arise when the blocks are
//! released from rest?). [`KinematicStatus`] holds both verdicts and, when the design fails,
//! the mechanism (the moving blocks' initial accelerations, the load factor's representation:
//! the viewer draws it the same way). All the work is [`crate::stability::kinematic`].

use super::{PipelineState, Settings, VoussoirSet};
use crate::stability::kinematic::{self, Kinematic};
use crate::statics::KinematicSettings;
use bevy::app::{App, Plugin, Update};
use bevy::ecs::prelude::*;

/// Runs the kinematic check after each analysis when asked.
pub struct KinematicPlugin;

impl Plugin for KinematicPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<KinematicRequest>()
            .init_resource::<KinematicStatus>()
            .add_systems(Update, update_kinematic.after(VoussoirSet::Write));
    }
}

/// Whether to run the kinematic check, with which settings.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub enum KinematicRequest {
    /// Not run (the default: a check costs two QPs per round on every supported component).
    #[default]
    Off,
    /// Run after every analysis, with these settings.
    On(KinematicSettings),
}

/// The last kinematic check, or why there is none.
#[derive(Resource, Clone, Debug, Default)]
pub struct KinematicStatus {
    /// The last check's answer.
    pub result: Option<Kinematic>,
    /// Why it could not run, when it could not.
    pub error: Option<String>,
}

/// Checks again when the analysis or the request changed.
fn update_kinematic(
    request: Res<KinematicRequest>,
    settings: Res<Settings>,
    pipeline: Res<PipelineState>,
    mut done: Local<Option<(u64, KinematicRequest)>>,
    mut status: ResMut<KinematicStatus>,
) {
    let now = (pipeline.generation, request.clone());
    if done.as_ref() == Some(&now) {
        return;
    }
    *done = Some(now);
    let (Some(a), KinematicRequest::On(k)) = (&pipeline.analysis, &*request) else {
        *status = KinematicStatus::default();
        return;
    };
    *status = match kinematic::check(a, &settings.0.statics, k) {
        Ok(r) => KinematicStatus { result: Some(r), error: None },
        Err(e) => KinematicStatus { result: None, error: Some(e.to_string()) },
    };
}
