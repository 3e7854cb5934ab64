//! The ECS sandbox on bevy (headless: no render stack). Blocks are entities with small
//! components, interfaces are entities linking two blocks (or a block and the ground), the
//! scene's verdict, timings and work counters are resources. Requests are [`EditDesign`]
//! messages. Every system is thin: it reads messages or resources, calls one core function
//! ([`crate::model::edit::apply`], [`crate::pipeline::Pipeline::run`]) and writes components.
//!
//! Order per update, one chained set: [`VoussoirSet::Edit`] (apply requests to the design) →
//! [`VoussoirSet::Analyze`] (cut, detect, solve: the pipeline, only when something changed,
//! recomputing only what the edit touched) → [`VoussoirSet::Write`] (block and interface
//! entities and their results).
//!
//! Units and signs as in the core: SI, z up; see [`crate::statics`].

pub mod diagram;
pub mod dynamics;
pub mod kinematic;
pub mod repair;
pub mod robustness;
pub mod sequence;
pub mod settle;
pub mod shake;
mod systems;

pub use diagram::{DiagramPlugin, DiagramSettings, InterfaceColors, SetDiagram};
pub use dynamics::{BlockPose, CompareDropTests, ComparedPose, DropLane, DropStatus, DynamicsPlugin, RunDropTest};
pub use kinematic::{KinematicPlugin, KinematicRequest, KinematicStatus};
pub use repair::{ANIMATION_FRAMES, RepairPlugin, RepairStatus, RunRepair};
pub use robustness::{JointMotion, MechanismMotion, RobustnessPlugin, RobustnessRequest, RobustnessStatus};
pub use sequence::{Placed, SequencePlugin, SequenceSettings, SequenceStatus, StartSequence, StepSequence};
pub use settle::{PLAY_SECONDS, RunSettlement, SettlePlugin, SettlePose, SettleStatus};
pub use shake::{RunShake, SHAKE_FPS, ShakePlugin, ShakePose, ShakeStatus};

use crate::geometry::{Mesh, Point3};
use crate::model::Scene;
use crate::model::edit::{Edit, SettingsEdit};
use crate::pipeline::{AnalysisSettings, Pipeline, Timings, Work};
use crate::statics::{InterfaceResult, Verdict};
use bevy::app::{App, Plugin, PluginGroup, PluginGroupBuilder, Update};
use bevy::ecs::prelude::*;
use std::collections::HashMap;

/// The plugin group: everything voussoir adds to an app.
pub struct VoussoirPlugins;

impl PluginGroup for VoussoirPlugins {
    fn build(self) -> PluginGroupBuilder {
        PluginGroupBuilder::start::<Self>()
            .add(DesignPlugin)
            .add(DiagramPlugin)
            .add(DynamicsPlugin)
            .add(SequencePlugin)
            .add(RobustnessPlugin)
            .add(KinematicPlugin)
            .add(RepairPlugin)
            .add(SettlePlugin)
            .add(ShakePlugin)
    }
}

/// The design, its analysis and the entities that show them.
pub struct DesignPlugin;

impl Plugin for DesignPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<EditDesign>()
            .add_message::<EditSettings>()
            .init_resource::<Design>()
            .init_resource::<Settings>()
            .init_resource::<PipelineState>()
            .init_resource::<SceneStatus>()
            .init_resource::<Counters>()
            .init_resource::<BlockIndex>()
            .configure_sets(Update, (VoussoirSet::Edit, VoussoirSet::Analyze, VoussoirSet::Write).chain())
            .add_systems(Update, systems::apply_edits.in_set(VoussoirSet::Edit))
            .add_systems(Update, systems::run_pipeline.in_set(VoussoirSet::Analyze))
            .add_systems(Update, systems::write_entities.in_set(VoussoirSet::Write));
    }
}

/// The stages of an update, run in this order.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VoussoirSet {
    /// Edits are applied (messages to the design).
    Edit,
    /// The pipeline runs on the edited design.
    Analyze,
    /// The results are written to the entities and the status resources.
    Write,
}

/// A request to change the design (applied in the order sent).
#[derive(Message, Clone, Debug)]
pub struct EditDesign(pub Edit);

/// A request to change the analysis settings.
#[derive(Message, Clone, Debug)]
pub struct EditSettings(pub SettingsEdit);

/// The design being edited (source shapes, cut history, removed pieces, material).
#[derive(Resource, Default, Clone, Debug)]
pub struct Design(pub Option<Scene>);

/// Analysis settings: the documented defaults, except that each solve starts from the
/// previous edit's iterates (`StaticsSettings::warm_start`: the app is an editor; answers
/// equal cold solves' to the solver's tolerance).
#[derive(Resource, Clone, Debug)]
pub struct Settings(pub AnalysisSettings);

impl Settings {
    /// `settings` for the editor: warm starts on.
    pub fn editing(mut settings: AnalysisSettings) -> Self {
        settings.statics.warm_start = true;
        Self(settings)
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self::editing(AnalysisSettings::default())
    }
}

/// The pipeline with its memory, and whether the design changed since it last ran.
#[derive(Resource, Default)]
pub struct PipelineState {
    /// The analysis pipeline with its caches (recuts and re-solves only what an edit touched).
    pub pipeline: Pipeline,
    /// Whether the design changed since the pipeline last ran.
    pub dirty: bool,
    /// The last run's results (`None` before the first or after an error).
    pub analysis: Option<crate::pipeline::Analysis>,
    /// Bumped on every run, so the writer knows when to write.
    pub generation: u64,
}

/// The scene's verdict and timings (after the last run), or why it could not run.
#[derive(Resource, Default, Clone, Debug, PartialEq)]
pub struct SceneStatus {
    /// The statics' verdict (`None` before the first run or after an error).
    pub verdict: Option<Verdict>,
    /// Whether it stands by compression and friction alone.
    pub stands: bool,
    /// Minimum tension, a fraction of the free weight.
    pub tension_ratio: f64,
    /// Minimum friction excess, a fraction of the free weight.
    pub friction_excess_ratio: f64,
    /// The largest friction use over the interfaces (> 1: exceeded).
    pub max_friction_utilization: f64,
    /// The last run's wall-clock seconds per stage.
    pub timings: Timings,
    /// The last run's work (what was recomputed and what reused).
    pub work: Work,
    /// The last edit or run that failed, with its message.
    pub error: Option<String>,
}

/// Work summed over every run since the app started.
#[derive(Resource, Default, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Counters {
    /// Pipeline runs.
    pub runs: usize,
    /// Plane splits computed (not taken from the cache).
    pub pieces_recut: usize,
    /// Block pairs whose interfaces were detected again.
    pub interfaces_redetected: usize,
    /// Components whose statics was solved again.
    pub components_resolved: usize,
    /// Components whose statics came from the cache.
    pub components_reused: usize,
}

/// Block entities by name.
#[derive(Resource, Default, Debug)]
pub struct BlockIndex(pub HashMap<String, Entity>);

/// A block's (piece's) name: its stable id.
#[derive(Component, Clone, Debug, PartialEq, Eq, Hash)]
pub struct BlockName(pub String);

/// A block's validated mesh (m).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct BlockMesh(pub Mesh);

/// Marks a support (fixed) block.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Support;

/// Mass (kg), mass centre (m) and mean density (kg/m³).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct MassCentre {
    /// Mass, kg.
    pub mass: f64,
    /// Mass centre, m.
    pub centroid: Point3,
    /// Mean density, kg/m³.
    pub density: f64,
}

/// An interface entity: the two bodies it links (`None` = the ground).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct InterfaceOf {
    /// The block entity on side a (the normal points from a into b).
    pub a: Option<Entity>,
    /// The block entity on side b.
    pub b: Option<Entity>,
}

/// An interface entity's index in the analysis's interface list.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct InterfaceIndex(pub usize);

/// An interface's forces and utilisation as the statics computed them.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct InterfaceForces(pub InterfaceResult);
