//! What is drawn in the design's view: block meshes (world coordinates, flat shaded;
//! translucent or opaque, supports dark — translucent too, so that what they carry shows — the
//! selection highlighted), the ground, interface polygons coloured per force point (unlit, so
//! the colours of [`crate::viz::colors`] reach the screen unchanged), and the gizmos: force
//! arrows, mass centres, the cut being edited. The motion pane is [`super::motion`]'s.

use super::ViewerState;
use super::camera::{COMPARED_LAYER, PHYSICS_LAYER};
use crate::ecs::{BlockMesh, BlockName, InterfaceColors, InterfaceForces, MassCentre, PipelineState};
use crate::ecs::{Placed, SequenceStatus, Support, VoussoirSet};
use crate::statics::InterfaceResult;
use crate::viz::{ColouredTriangle, DiagramMode, colors};
use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::RenderLayers;
use bevy::mesh::PrimitiveTopology;
use bevy::prelude::*;

pub struct DrawPlugin;

impl Plugin for DrawPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, setup).add_systems(
            Update,
            (mesh_blocks, style_blocks, mesh_interfaces, show_interfaces, step_interfaces, ground, gizmos)
                .chain()
                .after(VoussoirSet::Write)
                .after(crate::ecs::diagram::DiagramSystems),
        );
    }
}

/// The materials every block and interface uses (compared by handle, so restyling is cheap).
#[derive(Resource)]
pub struct Palette {
    block: Handle<StandardMaterial>,
    block_translucent: Handle<StandardMaterial>,
    pub(super) support: Handle<StandardMaterial>,
    pub(super) support_translucent: Handle<StandardMaterial>,
    selected: Handle<StandardMaterial>,
    /// The motion pane's moved blocks: violet, a colour no diagram legend uses.
    pub(super) moved: Handle<StandardMaterial>,
    /// The motion pane's blocks that do not move.
    pub(super) still: Handle<StandardMaterial>,
    /// The motion pane's rest-state ghosts.
    pub(super) rest: Handle<StandardMaterial>,
    pub(super) interface: Handle<StandardMaterial>,
    /// Blocks by density, lightest to densest ([`DENSITY_LEVELS`] steps of the ramp).
    pub(super) density: Vec<Handle<StandardMaterial>>,
}

/// Steps of the density colours: finer than the eye tells apart on a block face.
const DENSITY_LEVELS: usize = 16;

#[derive(Component)]
struct Ground;

/// An interface polygon of the sequence step shown.
#[derive(Component)]
pub struct StepInterface;

fn setup(mut commands: Commands, mut materials: ResMut<Assets<StandardMaterial>>) {
    let lit = |c: Color| StandardMaterial { base_color: c, perceptual_roughness: 0.9, ..default() };
    let translucent = |c: Color| StandardMaterial { alpha_mode: AlphaMode::Blend, ..lit(c) };
    commands.insert_resource(Palette {
        block: materials.add(lit(Color::srgb(0.80, 0.78, 0.74))),
        block_translucent: materials.add(translucent(Color::srgba(0.88, 0.87, 0.85, 0.2))),
        support: materials.add(lit(Color::srgb(0.28, 0.28, 0.30))),
        support_translucent: materials.add(translucent(Color::srgba(0.30, 0.30, 0.34, 0.4))),
        selected: materials.add(translucent(Color::srgba(0.25, 0.85, 0.85, 0.5))),
        moved: materials.add(lit(Color::srgb(colors::MOVED[0], colors::MOVED[1], colors::MOVED[2]))),
        still: materials.add(lit(Color::srgb(0.72, 0.70, 0.66))),
        rest: materials.add(StandardMaterial { unlit: true, ..translucent(Color::srgba(0.9, 0.9, 0.9, 0.14)) }),
        // Vertex colours times white, unlit, both sides; pulled towards the camera so that it
        // wins over the block faces it lies on.
        interface: materials.add(StandardMaterial {
            base_color: Color::WHITE,
            unlit: true,
            cull_mode: None,
            double_sided: true,
            depth_bias: 1000.0,
            ..default()
        }),
        density: (0..DENSITY_LEVELS)
            .map(|k| {
                let c = colors::density(k as f64, 0.0, (DENSITY_LEVELS - 1) as f64);
                materials.add(lit(Color::linear_rgb(c[0], c[1], c[2])))
            })
            .collect(),
    });
    let both = RenderLayers::from_layers(&[0, PHYSICS_LAYER, COMPARED_LAYER]);
    commands.spawn((
        DirectionalLight { illuminance: 9000.0, ..default() },
        Transform::from_xyz(0.4, -0.7, 1.0).looking_at(Vec3::ZERO, Vec3::Z),
        both.clone(),
    ));
    commands.insert_resource(GlobalAmbientLight { brightness: 600.0, ..default() });
}

fn v3(p: [f64; 3]) -> [f32; 3] {
    p.map(|x| x as f32)
}

fn vec(p: [f64; 3]) -> Vec3 {
    Vec3::from_array(v3(p))
}

/// A flat-shaded triangle mesh of a block (world coordinates; kept in the main world for picking).
fn block_mesh(m: &crate::geometry::Mesh) -> Mesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for (t, _) in m.triangles() {
        let p = t.map(|k| Vec3::from_array(v3(m.vertices[k].coords.into())));
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        positions.extend(p.map(|p| p.to_array()));
        normals.extend([n.to_array(); 3]);
    }
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default())
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
}

/// Unlit triangles with a colour per corner (linear RGB).
pub(super) fn coloured_mesh(triangles: &[ColouredTriangle], normal: [f64; 3]) -> Mesh {
    let positions: Vec<[f32; 3]> = triangles.iter().flat_map(|t| t.map(|(p, _)| v3(p))).collect();
    let colours: Vec<[f32; 4]> = triangles.iter().flat_map(|t| t.map(|(_, c)| [c[0], c[1], c[2], 1.0])).collect();
    let normals = vec![v3(normal); positions.len()];
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default())
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
        .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, colours)
}

fn mesh_blocks(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    palette: Res<Palette>,
    changed: Query<(Entity, &BlockMesh), Changed<BlockMesh>>,
) {
    for (e, m) in &changed {
        commands.entity(e).insert((
            Mesh3d(meshes.add(block_mesh(&m.0))),
            MeshMaterial3d(palette.block_translucent.clone()),
            Transform::IDENTITY,
            Visibility::Visible,
        ));
    }
}

/// What a block's style is computed from, and what it sets.
type BlockStyle<'a> = (
    &'a BlockName,
    Option<&'a MassCentre>,
    Has<Support>,
    Has<Placed>,
    &'a mut MeshMaterial3d<StandardMaterial>,
    &'a mut Visibility,
);

/// Material and visibility of every block from the state (set only where they differ).
fn style_blocks(state: Res<ViewerState>, palette: Res<Palette>, mut blocks: Query<BlockStyle>) {
    // The density scale: the free blocks' lightest to densest.
    let (lo, hi) = blocks
        .iter()
        .filter(|b| !b.2)
        .filter_map(|b| b.1.map(|m| m.density))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| (lo.min(d), hi.max(d)));
    let level = |d: f64| {
        let t = if hi > lo { (d - lo) / (hi - lo) } else { 0.5 };
        ((t * (DENSITY_LEVELS - 1) as f64).round() as usize).min(DENSITY_LEVELS - 1)
    };
    for (name, mass, support, placed, mut material, mut visibility) in &mut blocks {
        let want = if state.selected.as_deref() == Some(name.0.as_str()) {
            &palette.selected
        } else if let (true, false, Some(m)) = (state.density, support, mass) {
            &palette.density[level(m.density)]
        } else if support && state.translucent {
            &palette.support_translucent
        } else if support {
            &palette.support
        } else if state.translucent {
            &palette.block_translucent
        } else {
            &palette.block
        };
        if material.0 != *want {
            material.0 = want.clone();
        }
        let shown = support || !state.sequence_view || placed;
        let v = if shown { Visibility::Visible } else { Visibility::Hidden };
        if *visibility != v {
            *visibility = v;
        }
    }
}

fn mesh_interfaces(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    palette: Res<Palette>,
    changed: Query<(Entity, &InterfaceForces, &InterfaceColors), Changed<InterfaceColors>>,
) {
    for (e, forces, colours) in &changed {
        let tris = crate::viz::triangles(&forces.0, &colours.0);
        commands.entity(e).insert((
            Mesh3d(meshes.add(coloured_mesh(&tris, forces.0.normal))),
            MeshMaterial3d(palette.interface.clone()),
            Transform::IDENTITY,
        ));
    }
}

/// The design's interfaces are hidden while a sequence step shows its own.
fn show_interfaces(state: Res<ViewerState>, mut interfaces: Query<&mut Visibility, With<InterfaceForces>>) {
    let v = if state.sequence_view { Visibility::Hidden } else { Visibility::Visible };
    for mut visibility in &mut interfaces {
        if *visibility != v {
            *visibility = v;
        }
    }
}

/// The interfaces of the sequence step shown, from its own analysis.
fn step_interfaces(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    palette: Res<Palette>,
    state: Res<ViewerState>,
    sequence: Res<SequenceStatus>,
    shown: Query<Entity, With<StepInterface>>,
) {
    if !sequence.is_changed() && !state.is_changed() {
        return;
    }
    shown.iter().for_each(|e| commands.entity(e).despawn());
    let (true, Some(a)) = (state.sequence_view, &sequence.analysis) else { return };
    let (mu, model) = (a.statics.friction_coefficient, a.statics.friction_model);
    for r in &a.statics.interfaces {
        let tris = crate::viz::triangles(r, &crate::viz::vertex_colors(r, mu, model, state.mode));
        commands.spawn((
            Mesh3d(meshes.add(coloured_mesh(&tris, r.normal))),
            MeshMaterial3d(palette.interface.clone()),
            StepInterface,
        ));
    }
}

/// A ground plane under the design (just below its lowest point), in both views.
fn ground(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    pipeline: Res<PipelineState>,
    existing: Query<Entity, With<Ground>>,
    mut generation: Local<u64>,
) {
    if *generation == pipeline.generation {
        return;
    }
    *generation = pipeline.generation;
    let Some(a) = &pipeline.analysis else { return };
    let bb = a.assembly.aabb();
    if bb.is_empty() {
        return;
    }
    existing.iter().for_each(|e| commands.entity(e).despawn());
    let d = bb.diagonal() as f32;
    let c = bb.center();
    let z = bb.min.z as f32 - 2e-3 * d;
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::new(Vec3::Z, Vec2::splat(2.0 * d)).mesh())),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.09, 0.09, 0.09),
            perceptual_roughness: 1.0,
            ..default()
        })),
        Transform::from_xyz(c.x as f32, c.y as f32, z),
        RenderLayers::from_layers(&[0, PHYSICS_LAYER, COMPARED_LAYER]),
        Ground,
    ));
}

/// The resultant force on b at its point of application, and every force point's force.
fn vertex_force(r: &InterfaceResult, k: usize) -> Vec3 {
    let v = &r.vertices[k];
    (v.compression - v.tension) as f32 * vec(r.normal) + v.friction_u as f32 * vec(r.u) + v.friction_v as f32 * vec(r.v)
}

fn gizmos(
    mut gizmos: Gizmos,
    state: Res<ViewerState>,
    pipeline: Res<PipelineState>,
    sequence: Res<SequenceStatus>,
    forces: Query<&InterfaceForces>,
    masses: Query<(&MassCentre, &BlockMesh, &Visibility)>,
) {
    let Some(a) = &pipeline.analysis else { return };
    let size = a.assembly.aabb().diagonal() as f32;
    let step = sequence.analysis.as_ref().filter(|_| state.sequence_view);
    let interfaces: Vec<&InterfaceResult> = match step {
        Some(s) => s.statics.interfaces.iter().collect(),
        None => forces.iter().map(|f| &f.0).collect(),
    };
    if state.mode == DiagramMode::Vectors || state.vertex_arrows {
        let biggest = interfaces.iter().map(|r| vec(r.resultant).length()).fold(0.0f32, f32::max);
        let scale = if biggest > 0.0 { 0.25 * size / biggest } else { 0.0 };
        for r in &interfaces {
            if state.mode == DiagramMode::Vectors
                && let Some(p) = r.resultant_point
            {
                let p = vec(p);
                gizmos.arrow(p, p + vec(r.resultant) * scale, Color::srgb(0.1, 0.8, 0.25));
            }
            if state.vertex_arrows {
                for k in 0..r.vertices.len() {
                    let p = vec(r.vertices[k].position);
                    gizmos.arrow(p, p + vertex_force(r, k) * scale, Color::srgb(0.55, 0.95, 0.6));
                }
            }
        }
    }
    if state.mass_centres {
        // A small three-axis cross, sized by the block (a vault of 400 stones would drown in
        // scene-sized markers).
        for (m, mesh, visibility) in &masses {
            if *visibility != Visibility::Hidden {
                let p = vec(m.centroid.coords.into());
                let r = (0.05 * mesh.0.aabb().diagonal() as f32).min(0.012 * size);
                gizmos.cross(Isometry3d::from_translation(p), r, Color::srgb(1.0, 1.0, 1.0));
            }
        }
    }
    if let Some(cut) = &state.active_cut {
        let n = Vec3::new(cut.normal.x as f32, cut.normal.y as f32, cut.normal.z as f32);
        let p = Vec3::new(cut.point.x as f32, cut.point.y as f32, cut.point.z as f32);
        let rotation = Quat::from_rotation_arc(Vec3::Z, n.normalize_or_zero());
        let s = cut.size as f32 * 1.2;
        gizmos.rect(Isometry3d::new(p, rotation), Vec2::splat(s), Color::srgb(0.2, 0.9, 0.9));
        gizmos.arrow(p, p + n * 0.3 * s, Color::srgb(0.2, 0.9, 0.9));
    }
}
