//! The interactive 3D viewer (cargo feature `viewer`): bevy's render stack over the headless
//! [`crate::ecs::VoussoirPlugins`]. It only draws what the ECS holds and turns keys, clicks and
//! buttons into [`ViewerAction`]s; every answer comes from the core through the plugins.
//!
//! - [`camera`]: orbit / pan / zoom camera, z up (the model's axes, SI metres), split view
//!   while a motion pane is shown.
//! - [`draw`]: blocks (opaque or translucent; supports dark), the ground, interface polygons
//!   coloured per force point ([`crate::ecs::InterfaceColors`], the colours of
//!   [`crate::viz::colors`]), force arrows, mass centres, the cut being edited.
//! - [`motion`]: the motion pane beside the design — the drop test, the load factor's or the
//!   kinematic check's mechanism — with rest-state ghosts, joint states, the load and a caption.
//! - [`hud`]: the side panel: headline, graded numbers, the checks that ran, legend, buttons
//!   that show their state, the edit state, the keys.
//! - [`actions`]: the actions and what they do (edits with undo/redo, save, drop test,
//!   sequence stepper); [`input`] maps keys and mouse to them.
//! - [`capture`]: scripted runs (actions, then screenshots written atomically, then exit):
//!   `voussoir view --screenshot` and the rendering test.

pub mod actions;
pub mod camera;
pub mod capture;
pub mod draw;
pub mod hud;
pub mod input;
pub mod motion;

pub use actions::{Overlay, ViewerAction, ViewerState};
pub use capture::{Script, ScriptStep};

use crate::dynamics::DropSettings;
use crate::ecs::{EditDesign, SequenceSettings, Settings, VoussoirPlugins};
use crate::model::Scene;
use crate::model::edit::Edit;
use crate::pipeline::AnalysisSettings;
use crate::studies::sequence::StepChecks;
use crate::viz::DiagramMode;
use bevy::prelude::*;
use bevy::window::WindowResolution;
use std::path::PathBuf;

/// Width of the side panel, logical pixels (the 3D view is the rest of the window).
pub const PANEL_WIDTH: f32 = 300.0;

/// How the viewer starts.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    pub scene: Scene,
    /// Where the design came from (saving never writes over it unless `save_over_input`).
    pub input: Option<PathBuf>,
    /// Where Ctrl+S saves (default: `<input stem>.edited.json` beside the input, or
    /// `<scene name>.json` in the working directory).
    pub save_to: Option<PathBuf>,
    pub save_over_input: bool,
    /// Friction model, μ, tolerances (the ECS's `Settings`).
    pub settings: AnalysisSettings,
    pub mode: DiagramMode,
    pub translucent: bool,
    /// Window size, logical pixels.
    pub size: (u32, u32),
    /// A scripted run (screenshots, then exit); `None` for an interactive session.
    pub script: Option<Script>,
}

impl ViewerOptions {
    pub fn new(scene: Scene) -> Self {
        Self {
            scene,
            input: None,
            save_to: None,
            save_over_input: false,
            settings: AnalysisSettings::default(),
            mode: DiagramMode::default(),
            translucent: true,
            size: (1280, 800),
            script: None,
        }
    }

    /// Where a save goes.
    pub fn save_path(&self) -> PathBuf {
        if let Some(p) = &self.save_to {
            return p.clone();
        }
        match &self.input {
            Some(input) => {
                let stem = input.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                input.with_file_name(format!("{stem}.edited.json"))
            }
            None => PathBuf::from(format!("{}.json", sanitize(&self.scene.name))),
        }
    }
}

fn sanitize(name: &str) -> String {
    let s: String = name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' }).collect();
    if s.is_empty() { "design".into() } else { s }
}

/// The viewer's own plugin (added after bevy's `DefaultPlugins` and [`VoussoirPlugins`]).
pub struct ViewerPlugin(pub ViewerOptions);

impl Plugin for ViewerPlugin {
    fn build(&self, app: &mut App) {
        let o = &self.0;
        // The stepper shows each step's drop verdict beside its static one.
        let per_step = StepChecks { dynamic: Some(DropSettings::default()), ..Default::default() };
        app.insert_resource(SequenceSettings(per_step))
            .insert_resource(ViewerState::new(o))
            .insert_resource(Settings::editing(o.settings.clone()))
            .insert_resource(ClearColor(Color::srgb(0.11, 0.11, 0.11)))
            .add_plugins((camera::CameraPlugin, draw::DrawPlugin, hud::HudPlugin, actions::ActionsPlugin))
            .add_plugins(motion::MotionPlugin)
            .add_plugins((input::InputPlugin, capture::CapturePlugin(o.script.clone())));
        // The bundled font replaces bevy's default (a subset without μ, ·, —).
        let font = bevy::text::Font::from_bytes(crate::viz::plot::FONT.to_vec());
        let _ = app.world_mut().resource_mut::<Assets<bevy::text::Font>>().insert(AssetId::default(), font);
        app.world_mut().write_message(EditDesign(Edit::Load(Box::new(o.scene.clone()))));
        app.world_mut().write_message(crate::ecs::SetDiagram(o.mode));
    }
}

/// The app of a viewer session: window, render stack, voussoir's plugins, the viewer.
pub fn app(options: ViewerOptions) -> App {
    let mut app = App::new();
    let title = format!("voussoir — {}", options.scene.name);
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title,
            resolution: WindowResolution::new(options.size.0, options.size.1),
            ..default()
        }),
        ..default()
    }))
    .add_plugins(VoussoirPlugins)
    .add_plugins(ViewerPlugin(options));
    app
}

/// Runs a viewer session until the window closes (or the script ends).
pub fn run(options: ViewerOptions) -> AppExit {
    app(options).run()
}
