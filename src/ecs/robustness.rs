//! The robustness plugin: while [`RobustnessRequest`] asks for it, every analysis is followed by
//! the load factor of the design's live loads (or of a horizontal 1 g along a direction, or the
//! worst direction); [`RobustnessStatus`] holds λ* and the worst direction, each moving block
//! entity gets its [`MechanismMotion`] and each interface entity of the moving components its
//! [`JointMotion`]. For live loads and one direction the component load factors are kept by
//! content ([`crate::stability::FactorCache`]): after an edit only the components it touched
//! are solved again. All the work is [`crate::stability`].

use super::{BlockIndex, InterfaceIndex, PipelineState, Settings, VoussoirSet};
use crate::stability::{self, DirectionSettings, FactorCache, JointState, Robustness, Safety, directions};
use bevy::app::{App, Plugin, Update};
use bevy::ecs::prelude::*;

/// Computes load factors after each analysis when asked.
pub struct RobustnessPlugin;

impl Plugin for RobustnessPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<RobustnessRequest>()
            .init_resource::<RobustnessStatus>()
            .init_resource::<RobustnessState>()
            .add_systems(Update, (update_robustness, write_mechanism).chain().after(VoussoirSet::Write));
    }
}

/// What to compute after each analysis.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub enum RobustnessRequest {
    /// Nothing (the default: a load factor costs a solve per loaded component).
    #[default]
    Off,
    /// λ* of the design's live loads.
    LiveLoads,
    /// λ* of a horizontal 1 g along this azimuth (degrees).
    Direction(f64),
    /// The worst horizontal direction over this many azimuths.
    Worst(usize),
}

/// The last load factor, or why there is none.
#[derive(Resource, Clone, Debug, Default)]
pub struct RobustnessStatus {
    /// The last load factor and mechanism.
    pub result: Option<Robustness>,
    /// The worst direction (degrees), when a sweep ran.
    pub worst_azimuth: Option<f64>,
    /// Component load factors solved and reused by the last run.
    pub solved: usize,
    /// Component load factors the last run took from the cache.
    pub reused: usize,
    /// Why the load factor could not be computed, when it could not.
    pub error: Option<String>,
}

impl RobustnessStatus {
    /// λ* (NaN when there is none).
    pub fn load_factor(&self) -> f64 {
        match self.result.as_ref().map(|r| r.safety) {
            Some(Safety::Collapses { load_factor }) => load_factor,
            Some(Safety::Unlimited) => f64::INFINITY,
            _ => f64::NAN,
        }
    }
}

/// A moving block's virtual motion in the mechanism: translation (m) and rotation (rad).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct MechanismMotion {
    /// Virtual translation, m.
    pub translation: [f64; 3],
    /// Virtual rotation about the centroid, rad (a rotation vector).
    pub rotation: [f64; 3],
}

/// What an interface does in the mechanism.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct JointMotion(pub JointState);

#[derive(Resource, Default)]
struct RobustnessState {
    cache: FactorCache,
    /// The pipeline generation and request last computed.
    done: Option<(u64, RobustnessRequest)>,
}

/// Recomputes the load factor when the analysis or the request changed.
fn update_robustness(
    request: Res<RobustnessRequest>,
    settings: Res<Settings>,
    pipeline: Res<PipelineState>,
    mut state: ResMut<RobustnessState>,
    mut status: ResMut<RobustnessStatus>,
) {
    let now = (pipeline.generation, request.clone());
    if state.done.as_ref() == Some(&now) {
        return;
    }
    state.done = Some(now);
    let (Some(a), false) = (&pipeline.analysis, *request == RobustnessRequest::Off) else {
        *status = RobustnessStatus::default();
        return;
    };
    let statics = &settings.0.statics;
    let keys = crate::interfaces::block_keys(&a.assembly);
    let mut worst_azimuth = None;
    let state = &mut *state;
    let result = match (&*request, a.statics.stands) {
        (RobustnessRequest::LiveLoads, stands) => {
            stability::assess_cached(&a.assembly, &a.interfaces, stands, statics, Some((&keys, &mut state.cache)))
        }
        (RobustnessRequest::Direction(d), true) => {
            let field = directions::with_horizontal_field(&a.assembly, *d);
            stability::assess_cached(&field, &a.interfaces, true, statics, Some((&keys, &mut state.cache)))
        }
        (RobustnessRequest::Worst(n), true) => {
            let s = DirectionSettings { directions: *n, ..Default::default() };
            stability::worst_direction(&a.assembly, &a.interfaces, statics, &s, &|_, _| {}).map(|s| {
                worst_azimuth = Some(s.worst_azimuth);
                s.worst
            })
        }
        (_, false) => stability::assess(a, statics),
        (RobustnessRequest::Off, _) => unreachable!("handled above"),
    };
    *status = match result {
        Ok(r) => RobustnessStatus {
            result: Some(r),
            worst_azimuth,
            solved: state.cache.solved,
            reused: state.cache.reused,
            error: None,
        },
        Err(e) => RobustnessStatus { error: Some(e.to_string()), ..Default::default() },
    };
}

/// Writes the mechanism on the block and interface entities when the status changed.
fn write_mechanism(
    mut commands: Commands,
    status: Res<RobustnessStatus>,
    index: Res<BlockIndex>,
    moving: Query<Entity, With<MechanismMotion>>,
    joints: Query<(Entity, &InterfaceIndex)>,
) {
    if !status.is_changed() {
        return;
    }
    moving.iter().for_each(|e| {
        commands.entity(e).remove::<MechanismMotion>();
    });
    let mechanism = status.result.as_ref().and_then(|r| r.mechanism.as_ref());
    for b in mechanism.iter().flat_map(|m| &m.blocks) {
        if let Some(&e) = index.0.get(&b.block) {
            commands.entity(e).insert(MechanismMotion { translation: b.translation, rotation: b.rotation });
        }
    }
    let states: std::collections::HashMap<usize, JointState> =
        mechanism.map(|m| m.interfaces.iter().map(|i| (i.index, i.state)).collect()).unwrap_or_default();
    for (e, InterfaceIndex(k)) in &joints {
        match states.get(k) {
            Some(&s) => commands.entity(e).insert(JointMotion(s)),
            None => commands.entity(e).remove::<JointMotion>(),
        };
    }
}
