//! Cameras: the main view (the static diagram) right of the side panel, a second view of the
//! drop test beside it while one is shown (render layer 1, same pose), a third beside that while
//! the two engines are compared (render layer 2: the exact-contact engine's), and a UI camera
//! over the whole window. Orbit about a focus point with z up; the main camera has no tone mapping so
//! that the diagram colours reach the screen as computed.

use super::{Overlay, PANEL_WIDTH, ViewerState};
use crate::ecs::PipelineState;
use bevy::camera::visibility::RenderLayers;
use bevy::camera::{ClearColorConfig, Viewport};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::window::PrimaryWindow;

/// Render layer of the motion pane (drop test, mechanisms).
pub const PHYSICS_LAYER: usize = 1;

/// Render layer of the compared engine's pane.
pub const COMPARED_LAYER: usize = 2;

/// How the motion pane looks at the design.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub enum PaneView {
    /// As the main view (the drop test).
    #[default]
    Follow,
    /// Level, square to a vertical plane whose normal has azimuth `yaw` (a mechanism's plane),
    /// from the side nearer the main view.
    Square { yaw: f32 },
}

pub struct CameraPlugin;

impl Plugin for CameraPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, spawn_cameras).add_systems(
            PostUpdate,
            (frame_design, place_cameras, set_viewports).chain().before(TransformSystems::Propagate),
        );
    }
}

/// Orbit parameters of the main camera (the drop-test view copies them).
#[derive(Component, Clone, Copy, Debug)]
pub struct OrbitCamera {
    pub focus: Vec3,
    pub distance: f32,
    /// Azimuth about z and elevation above the horizon, radians.
    pub yaw: f32,
    pub pitch: f32,
}

impl OrbitCamera {
    pub fn transform(&self) -> Transform {
        let dir = Vec3::new(self.pitch.cos() * self.yaw.cos(), self.pitch.cos() * self.yaw.sin(), self.pitch.sin());
        Transform::from_translation(self.focus + self.distance * dir).looking_at(self.focus, Vec3::Z)
    }

    /// Turns by a mouse drag of `delta` logical pixels.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw -= delta.x * 0.008;
        self.pitch = (self.pitch + delta.y * 0.008).clamp(-1.5, 1.5);
    }

    /// Moves the focus by a drag of `delta` logical pixels in a view `height` pixels tall.
    pub fn pan(&mut self, delta: Vec2, height: f32) {
        let t = self.transform();
        let scale = self.distance / height.max(1.0);
        self.focus += (-delta.x * t.right().as_vec3() + delta.y * t.up().as_vec3()) * scale;
    }

    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * (1.0 - 0.1 * steps).clamp(0.5, 1.5)).max(1e-4);
    }
}

#[derive(Component)]
pub struct MainCamera;

#[derive(Component)]
pub struct PhysicsCamera;

/// The compared engine's pane (the exact-contact engine's while both engines run).
#[derive(Component)]
pub struct ComparedCamera;

fn spawn_cameras(mut commands: Commands) {
    let orbit = OrbitCamera { focus: Vec3::ZERO, distance: 10.0, yaw: -1.1, pitch: 0.45 };
    commands.spawn((
        Camera3d::default(),
        Camera { order: 0, ..default() },
        Tonemapping::None,
        orbit,
        orbit.transform(),
        MainCamera,
    ));
    commands.spawn((
        Camera3d::default(),
        // Cameras on one window share its textures: only the first clears them.
        Camera { order: 1, is_active: false, clear_color: ClearColorConfig::None, ..default() },
        Tonemapping::None,
        RenderLayers::layer(PHYSICS_LAYER),
        orbit.transform(),
        PhysicsCamera,
    ));
    commands.spawn((
        Camera3d::default(),
        Camera { order: 2, is_active: false, clear_color: ClearColorConfig::None, ..default() },
        Tonemapping::None,
        RenderLayers::layer(COMPARED_LAYER),
        orbit.transform(),
        ComparedCamera,
    ));
    // The UI over the whole window; it clears nothing, the 3D views are beneath it. No render
    // layer: gizmos (layer 0) would otherwise be drawn again through its 2-D projection, as
    // specks at the window's centre.
    commands.spawn((
        Camera2d,
        Camera { order: 3, clear_color: ClearColorConfig::None, ..default() },
        RenderLayers::none(),
        IsDefaultUiCamera,
    ));
}

/// Fits the view to the design at the first analysis (and on request).
fn frame_design(mut state: ResMut<ViewerState>, pipeline: Res<PipelineState>, mut cams: Query<&mut OrbitCamera>) {
    if !state.frame_pending {
        return;
    }
    let Some(a) = &pipeline.analysis else { return };
    let bb = a.assembly.aabb();
    if bb.is_empty() {
        return;
    }
    state.frame_pending = false;
    let c = bb.center();
    for mut cam in &mut cams {
        cam.focus = Vec3::new(c.x as f32, c.y as f32, c.z as f32);
        // The bounding sphere (radius d/2) in a 45° vertical field of view: 0.5 d / sin 22.5°.
        cam.distance = (bb.diagonal() as f32 * 1.3).max(1e-3);
    }
}

/// The 3D views.
type Views = Or<(With<MainCamera>, With<PhysicsCamera>, With<ComparedCamera>)>;

/// Both views from the orbit; a view narrower than it is tall steps back so that what fits a
/// wide view still fits (the field of view is vertical). The motion pane may look square to a
/// mechanism's plane instead.
fn place_cameras(
    main: Query<&OrbitCamera, With<MainCamera>>,
    pane: Res<PaneView>,
    mut cams: Query<(&Camera, &mut Transform, Has<MainCamera>), Views>,
) {
    let Ok(orbit) = main.single() else { return };
    for (camera, mut transform, is_main) in &mut cams {
        let is_pane = !is_main;
        let aspect =
            camera.viewport.as_ref().map_or(1.0, |v| v.physical_size.x as f32 / v.physical_size.y.max(1) as f32);
        let mut view = OrbitCamera { distance: orbit.distance / aspect.clamp(0.2, 1.0), ..*orbit };
        if let (true, PaneView::Square { yaw }) = (is_pane, *pane) {
            // Of the plane's two sides, the one nearer the main view's azimuth.
            let turn = |y: f32| (y - orbit.yaw + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU);
            let flipped = yaw + std::f32::consts::PI;
            let nearer = |y: f32| (turn(y) - std::f32::consts::PI).abs();
            view.yaw = if nearer(yaw) <= nearer(flipped) { yaw } else { flipped };
            view.pitch = 0.12;
        }
        let t = view.transform();
        if *transform != t {
            *transform = t;
        }
    }
}

/// The 3D views fill the window right of the panel: one; two side by side while a drop test,
/// a settlement or a mechanism is shown; three while the engines are compared.
fn set_viewports(
    window: Query<&Window, With<PrimaryWindow>>,
    state: Res<ViewerState>,
    mut cams: Query<(&mut Camera, Has<PhysicsCamera>, Has<ComparedCamera>), Views>,
) {
    let Ok(window) = window.single() else { return };
    let size = window.physical_size();
    let panel = ((PANEL_WIDTH * window.scale_factor()) as u32).min(size.x.saturating_sub(2));
    let width = size.x - panel;
    let compared = state.drop_view && state.drop_engine.is_none();
    let views = if compared {
        3
    } else if state.drop_view || state.settle_view || state.shake_view || state.overlay != Overlay::None {
        2
    } else {
        1
    };
    let column = width / views;
    let view = |k: u32| {
        let w = if k + 1 == views { width - k * column } else { column };
        Viewport {
            physical_position: UVec2::new(panel + k * column, 0),
            physical_size: UVec2::new(w.max(1), size.y.max(1)),
            ..default()
        }
    };
    // Viewport has no PartialEq: compare what is set, so that cameras change only on resize.
    let same = |a: &Option<Viewport>, b: &Viewport| {
        a.as_ref().is_some_and(|a| a.physical_position == b.physical_position && a.physical_size == b.physical_size)
    };
    for (mut cam, is_pane, is_compared) in &mut cams {
        let k = u32::from(is_pane) + 2 * u32::from(is_compared);
        let active = k < views;
        if cam.is_active != active {
            cam.is_active = active;
        }
        let v = view(k);
        if active && !same(&cam.viewport, &v) {
            cam.viewport = Some(v);
        }
    }
}
