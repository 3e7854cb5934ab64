//! Keys and mouse → [`ViewerAction`]s and camera moves. Nothing here changes the design itself.

use super::PANEL_WIDTH;
use super::actions::{ViewerAction, ViewerState};
use super::camera::{MainCamera, OrbitCamera};
use crate::dynamics::Engine;
use crate::ecs::BlockName;
use crate::viz::DiagramMode;
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll, MouseScrollUnit};
use bevy::picking::mesh_picking::ray_cast::{MeshRayCast, MeshRayCastSettings};
use bevy::prelude::*;
use bevy::window::PrimaryWindow;

pub struct InputPlugin;

impl Plugin for InputPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Update, (keys, mouse, pick).before(super::actions::ActionSystems));
    }
}

fn keys(keys: Res<ButtonInput<KeyCode>>, mut actions: MessageWriter<ViewerAction>) {
    let ctrl = keys.any_pressed([KeyCode::ControlLeft, KeyCode::ControlRight]);
    let shift = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
    let step = if shift { 0.1 } else { 0.02 };
    let turn = if shift { 15.0 } else { 5.0 };
    let mut send = |a: ViewerAction| {
        actions.write(a);
    };
    for key in keys.get_just_pressed() {
        match (key, ctrl) {
            (KeyCode::KeyZ, true) => send(ViewerAction::Undo),
            (KeyCode::KeyY, true) => send(ViewerAction::Redo),
            (KeyCode::KeyS, true) => send(ViewerAction::Save),
            (_, true) => {}
            (KeyCode::Digit1, _) => send(ViewerAction::SetMode(DiagramMode::Compression)),
            (KeyCode::Digit2, _) => {
                send(ViewerAction::SetMode(DiagramMode::Friction { threshold: DiagramMode::DEFAULT_THRESHOLD }))
            }
            (KeyCode::Digit3, _) => send(ViewerAction::SetMode(DiagramMode::Vectors)),
            (KeyCode::KeyT, _) => send(ViewerAction::ToggleTranslucent),
            (KeyCode::KeyM, _) => send(ViewerAction::ToggleMassCentres),
            (KeyCode::KeyI, _) => send(ViewerAction::ToggleDensity),
            (KeyCode::KeyV, _) => send(ViewerAction::ToggleVertexArrows),
            (KeyCode::KeyL, _) => send(ViewerAction::ToggleLabels),
            (KeyCode::KeyH, _) => send(ViewerAction::ToggleKeys),
            (KeyCode::KeyK, _) => send(ViewerAction::ToggleMechanism),
            (KeyCode::KeyJ, _) => send(ViewerAction::ToggleKinematic),
            (KeyCode::KeyF, _) => send(ViewerAction::Frame),
            (KeyCode::KeyC, _) => send(ViewerAction::AddCut),
            (KeyCode::PageUp, _) => send(ViewerAction::ShiftCut(step)),
            (KeyCode::PageDown, _) => send(ViewerAction::ShiftCut(-step)),
            (KeyCode::ArrowLeft, _) => send(ViewerAction::TurnCut { yaw: turn, tilt: 0.0 }),
            (KeyCode::ArrowRight, _) => send(ViewerAction::TurnCut { yaw: -turn, tilt: 0.0 }),
            (KeyCode::ArrowUp, _) => send(ViewerAction::TurnCut { yaw: 0.0, tilt: turn }),
            (KeyCode::ArrowDown, _) => send(ViewerAction::TurnCut { yaw: 0.0, tilt: -turn }),
            (KeyCode::Backspace, _) => send(ViewerAction::DeleteCut),
            (KeyCode::KeyO, _) => send(ViewerAction::Repair),
            (KeyCode::KeyG, _) => send(ViewerAction::ToggleSupport),
            (KeyCode::KeyX | KeyCode::Delete, _) => send(ViewerAction::RemoveBlock),
            (KeyCode::KeyR, _) => send(ViewerAction::RestoreBlock),
            (KeyCode::KeyD, _) => send(ViewerAction::DropTest(Engine::Rapier)),
            (KeyCode::KeyE, _) => send(ViewerAction::DropTest(Engine::Exact)),
            (KeyCode::KeyB, _) => send(ViewerAction::CompareEngines),
            (KeyCode::KeyP, _) => send(ViewerAction::Settle),
            (KeyCode::KeyW, _) => send(ViewerAction::Shake),
            (KeyCode::KeyQ, _) => send(ViewerAction::StartSequence),
            (KeyCode::Comma, _) => send(ViewerAction::Step(-1)),
            (KeyCode::Period, _) => send(ViewerAction::Step(1)),
            (KeyCode::Escape, _) => {
                send(ViewerAction::ResetDrop);
                send(ViewerAction::ExitSequence);
            }
            _ => {}
        }
    }
}

/// Whether the cursor is over the 3D view (not the panel).
fn in_view(window: &Window) -> Option<Vec2> {
    window.cursor_position().filter(|p| p.x > PANEL_WIDTH)
}

fn mouse(
    buttons: Res<ButtonInput<MouseButton>>,
    keys: Res<ButtonInput<KeyCode>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    window: Query<&Window, With<PrimaryWindow>>,
    mut orbit: Query<&mut OrbitCamera, With<MainCamera>>,
    mut dragging: Local<bool>,
) {
    let (Ok(window), Ok(mut orbit)) = (window.single(), orbit.single_mut()) else { return };
    let any = [MouseButton::Right, MouseButton::Middle];
    if buttons.any_just_pressed(any) {
        *dragging = in_view(window).is_some();
    }
    if !buttons.any_pressed(any) {
        *dragging = false;
    }
    let shift = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
    if *dragging && motion.delta != Vec2::ZERO {
        if buttons.pressed(MouseButton::Middle) || shift {
            orbit.pan(motion.delta, window.height());
        } else {
            orbit.orbit(motion.delta);
        }
    }
    if scroll.delta.y != 0.0 && in_view(window).is_some() {
        let steps = match scroll.unit {
            MouseScrollUnit::Line => scroll.delta.y,
            MouseScrollUnit::Pixel => scroll.delta.y / 40.0,
        };
        orbit.zoom(steps);
    }
}

/// A left click (without a drag) in the view selects the block under the cursor, or clears;
/// so does a scripted [`ViewerAction::ClickToward`]. (It sets the selection itself: a system
/// cannot both read and send the actions.)
#[allow(clippy::too_many_arguments)]
fn pick(
    buttons: Res<ButtonInput<MouseButton>>,
    window: Query<&Window, With<PrimaryWindow>>,
    camera: Query<(&Camera, &GlobalTransform), With<MainCamera>>,
    blocks: Query<&BlockName>,
    mut ray_cast: MeshRayCast,
    mut pressed_at: Local<Option<Vec2>>,
    mut requests: MessageReader<ViewerAction>,
    mut state: ResMut<ViewerState>,
) {
    let (Ok(window), Ok((camera, at))) = (window.single(), camera.single()) else { return };
    let mut clicks: Vec<Vec2> = requests
        .read()
        .filter_map(|a| match a {
            ViewerAction::ClickToward(p) => camera.world_to_viewport(at, Vec3::from_array(*p)).ok(),
            _ => None,
        })
        .collect();
    if buttons.just_pressed(MouseButton::Left) {
        *pressed_at = in_view(window);
    }
    if buttons.just_released(MouseButton::Left)
        && let (Some(start), Some(end)) = (pressed_at.take(), in_view(window))
        && start.distance(end) <= 4.0
    {
        clicks.push(end);
    }
    for xy in clicks {
        let Ok(ray) = camera.viewport_to_world(at, xy) else { continue };
        let filter = |e: Entity| blocks.contains(e);
        let settings = MeshRayCastSettings::default().with_filter(&filter);
        let hit = ray_cast.cast_ray(ray, &settings).first().map(|(e, _)| *e);
        let name = hit.and_then(|e| blocks.get(e).ok()).map(|n| n.0.clone());
        state.selected = name;
    }
}
