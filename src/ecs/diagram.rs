//! The diagram the interfaces show: a [`DiagramSettings`] resource (mode and friction threshold,
//! changed by [`SetDiagram`] messages) and an [`InterfaceColors`] component on every loaded
//! interface entity (the colour of each force point, from [`crate::viz::vertex_colors`]). The
//! viewer only draws these; headless apps and tests read them.

use super::{InterfaceForces, PipelineState, VoussoirSet};
use crate::viz::DiagramMode;
use crate::viz::colors::Rgb;
use bevy::app::{App, Plugin, Update};
use bevy::ecs::prelude::*;

/// Colours interface entities by the diagram mode.
pub struct DiagramPlugin;

impl Plugin for DiagramPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<SetDiagram>().init_resource::<DiagramSettings>().add_systems(
            Update,
            (set_diagram, colour_interfaces).chain().in_set(DiagramSystems).after(VoussoirSet::Write),
        );
    }
}

/// The systems that colour interfaces (a viewer draws after them).
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DiagramSystems;

/// The diagram mode (default: [`DiagramMode`]'s, compression–tension).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Default)]
pub struct DiagramSettings(pub DiagramMode);

/// A request to switch the diagram.
#[derive(Message, Clone, Copy, Debug)]
pub struct SetDiagram(pub DiagramMode);

/// The colour of each force point of an interface (in [`InterfaceForces`]' vertex order).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct InterfaceColors(pub Vec<Rgb>);

fn set_diagram(mut requests: MessageReader<SetDiagram>, mut settings: ResMut<DiagramSettings>) {
    if let Some(last) = requests.read().last()
        && settings.0 != last.0
    {
        settings.0 = last.0;
    }
}

/// Colours new interface entities, and all of them when the mode changed.
fn colour_interfaces(
    mut commands: Commands,
    settings: Res<DiagramSettings>,
    state: Res<PipelineState>,
    interfaces: Query<(Entity, &InterfaceForces, Has<InterfaceColors>)>,
) {
    let Some(a) = &state.analysis else { return };
    let (mu, model) = (a.statics.friction_coefficient, a.statics.friction_model);
    for (entity, forces, coloured) in &interfaces {
        if !coloured || settings.is_changed() {
            let colours = crate::viz::vertex_colors(&forces.0, mu, model, settings.0);
            commands.entity(entity).insert(InterfaceColors(colours));
        }
    }
}
