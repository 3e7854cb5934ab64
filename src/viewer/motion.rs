//! The motion pane, right of the design while a drop test, the load factor's collapse
//! mechanism (K) or the kinematic check's mechanism (J) is shown: the blocks at rest as faint
//! ghosts, the moved blocks in violet (a colour no diagram legend uses), supports dark, the
//! joints of a mechanism coloured by what they do (hinging, opening, sliding, as in the PNG
//! export), the load as an arrow, and a caption saying what is shown and how much it is
//! exaggerated. A mechanism is seen square to its plane (the plane its blocks turn in).

use super::Overlay;
use super::camera::{PHYSICS_LAYER, PaneView};
use super::draw::{Palette, coloured_mesh};
use super::hud::Shown;
use crate::ecs::{BlockName, BlockPose, MassCentre};
use crate::ecs::{Support, VoussoirSet};
use crate::model::{Load, LoadKind};
use crate::stability::{BlockMotion, JointState, Mechanism};
use crate::viz::colors;
use bevy::camera::visibility::RenderLayers;
use bevy::prelude::*;
use std::collections::{HashMap, HashSet};

pub struct MotionPlugin;

impl Plugin for MotionPlugin {
    fn build(&self, app: &mut App) {
        app.init_gizmo_group::<MotionGizmos>()
            .init_resource::<PaneView>()
            .add_systems(Startup, (configure_gizmos, spawn_caption))
            .add_systems(
                Update,
                (copies, rest_ghosts, joints, caption, gizmo_marks, pane_view)
                    .chain()
                    .after(VoussoirSet::Write)
                    .after(crate::ecs::diagram::DiagramSystems),
            );
    }
}

/// Gizmos drawn in the motion pane only (the load arrow).
#[derive(Default, Reflect, GizmoConfigGroup)]
pub struct MotionGizmos;

fn configure_gizmos(mut store: ResMut<GizmoConfigStore>) {
    let (config, _) = store.config_mut::<MotionGizmos>();
    config.render_layers = RenderLayers::layer(PHYSICS_LAYER);
    config.line.width = 3.0;
}

/// A block's copy in the motion pane, moved.
#[derive(Component)]
struct Moved(Entity);

/// A block's copy in the motion pane, at rest (shown while its moved copy is elsewhere).
#[derive(Component)]
struct AtRest(Entity);

/// A mechanism's moving joint, drawn on its moved face.
#[derive(Component)]
struct JointMark;

/// The caption over the motion pane.
#[derive(Component)]
pub(super) struct Caption;

/// What the motion pane shows.
pub(super) enum Pane<'a> {
    Hidden,
    Drop,
    /// A mechanism, drawn `scale` × its motion.
    Mechanism {
        mechanism: &'a Mechanism,
        scale: f64,
        kinematic: bool,
    },
}

// The pane reads what the panel shows ([`Shown`]).
impl Shown<'_> {
    pub(super) fn pane(&self) -> Pane<'_> {
        if self.state.drop_view && (self.drop.running.is_some() || self.drop.result.is_some()) {
            return Pane::Drop;
        }
        let mechanism = match self.state.overlay {
            Overlay::None => None,
            Overlay::Mechanism => self.robustness.result.as_ref().and_then(|r| r.mechanism.as_ref()),
            Overlay::Kinematic => self.kinematic.result.as_ref().and_then(|k| k.mechanism.as_ref()),
        };
        let scale = mechanism
            .zip(self.pipeline.analysis.as_ref())
            .and_then(|(m, a)| crate::viz::mechanism_scale(m, &a.assembly).map(|s| (m, s)));
        match scale {
            Some((mechanism, scale)) => {
                Pane::Mechanism { mechanism, scale, kinematic: self.state.overlay == Overlay::Kinematic }
            }
            None => Pane::Hidden,
        }
    }

    /// The caption: what is shown, how much it is exaggerated, what the colours mean.
    pub(super) fn caption(&self) -> String {
        match self.pane() {
            Pane::Hidden => self.nothing_moves().into(),
            Pane::Drop => {
                let (t, total) = match (&self.drop.running, &self.drop.result) {
                    (Some(run), _) => (run.steps_done() as f64 * run.dt(), run.total_steps() as f64 * run.dt()),
                    (None, Some(r)) => (r.simulated_s, r.simulated_s),
                    _ => (0.0, 0.0),
                };
                let verdict = self.drop.result.as_ref().map_or("", |r| if r.stands { ": stands" } else { ": falls" });
                let engine = match (&self.drop.running, &self.drop.result) {
                    (Some(run), _) => run.engine(),
                    (None, Some(r)) => r.engine,
                    _ => Default::default(),
                };
                format!(
                    "drop test ({engine}), true scale\nt = {t:.2} of {total:.2} s{verdict}\nviolet: the blocks now · ghost: at the start"
                )
            }
            Pane::Mechanism { mechanism, kinematic, .. } => {
                let head = if kinematic {
                    "kinematic check: the first motion\nreleased from rest under gravity (arrow)".to_string()
                } else {
                    format!("collapse mechanism at λ* = {:.4}\n{}", self.robustness.load_factor(), self.load_words())
                };
                let states: Vec<String> = [JointState::Hinging, JointState::Opening, JointState::Sliding]
                    .into_iter()
                    .filter_map(|s| {
                        let n = mechanism.interfaces.iter().filter(|i| i.state == s).count();
                        (n > 0).then(|| format!("{n} {}", joint_words(s)))
                    })
                    .collect();
                format!(
                    "{head}\nviolet: moved, largest motion drawn\n  as {:.0} % of the size · ghost: at rest\n{}",
                    100.0 * crate::viz::EXAGGERATION,
                    if states.is_empty() { "no joint opens".into() } else { states.join(" · ") }
                )
            }
        }
    }

    /// Why a mechanism pane that is open shows nothing moving (empty when none is open).
    fn nothing_moves(&self) -> &'static str {
        use crate::stability::kinematic::KinematicVerdict;
        match self.state.overlay {
            Overlay::None => "",
            Overlay::Mechanism => match self.robustness.result.as_ref().map(|r| r.safety) {
                None => "collapse mechanism: computing…",
                Some(crate::stability::Safety::DoesNotStand { .. }) => {
                    "no collapse mechanism:\nit does not stand under its own weight"
                }
                Some(_) => "no collapse mechanism to show",
            },
            Overlay::Kinematic => match self.kinematic.result.as_ref().map(|k| k.verdict) {
                None => "kinematic check: running…",
                Some(KinematicVerdict::Stands) => "kinematic check: it stands,\nnothing moves",
                Some(_) => "kinematic check: no motion to show",
            },
        }
    }

    /// The live load the load factor scales, in words.
    fn load_words(&self) -> String {
        match self.robustness.worst_azimuth {
            Some(az) => format!("load: horizontal × λ*, worst at {az:.0}° (arrow)"),
            None => "load: the design's live loads × λ* (arrows)".into(),
        }
    }
}

fn joint_words(state: JointState) -> &'static str {
    match state {
        JointState::Closed => "closed",
        JointState::Hinging => "hinging (orange)",
        JointState::Opening => "opening (red)",
        JointState::Sliding => "sliding (blue)",
    }
}

/// How many of the pane's things are drawn (the scripted report's account of the pane).
#[derive(bevy::ecs::system::SystemParam)]
pub(super) struct PaneCounts<'w, 's> {
    moved: Query<'w, 's, (&'static Moved, &'static Transform)>,
    ghosts: Query<'w, 's, &'static Visibility, With<AtRest>>,
    joints: Query<'w, 's, (), With<JointMark>>,
}

impl PaneCounts<'_, '_> {
    /// Copies in the pane, those moved off their rest place, rest ghosts shown, joints marked.
    pub(super) fn describe(&self) -> serde_json::Value {
        serde_json::json!({
            "copies": self.moved.iter().count(),
            "moved": self.moved.iter().filter(|(_, t)| **t != Transform::IDENTITY).count(),
            "ghosts": self.ghosts.iter().filter(|v| **v != Visibility::Hidden).count(),
            "joints": self.joints.iter().count(),
        })
    }
}

/// A block as its copies need it.
type Source<'a> = (Entity, &'a Mesh3d, &'a MassCentre, Option<&'a BlockPose>, &'a BlockName, Has<Support>);

/// The moved copies: every block in the pane, moved by its drop-test pose or along the
/// mechanism; a mechanism's still blocks in stone, its moving ones violet.
fn copies(
    mut commands: Commands,
    shown: Shown,
    palette: Res<Palette>,
    blocks: Query<Source, Without<Moved>>,
    mut moved: Query<(Entity, &Moved, &mut Transform, &mut MeshMaterial3d<StandardMaterial>)>,
) {
    let pane = shown.pane();
    if matches!(pane, Pane::Hidden) {
        moved.iter().for_each(|(e, ..)| commands.entity(e).despawn());
        return;
    }
    let (mechanism, scale) = match pane {
        Pane::Mechanism { mechanism, scale, .. } => (Some(mechanism), scale),
        _ => (None, 0.0),
    };
    let motions_by_name: HashMap<&str, &BlockMotion> =
        mechanism.iter().flat_map(|m| &m.blocks).map(|b| (b.block.as_str(), b)).collect();
    let mut have = HashSet::new();
    for (e, copy, mut transform, mut material) in &mut moved {
        let Ok((_, _, mass, pose, name, support)) = blocks.get(copy.0) else {
            commands.entity(e).despawn();
            continue;
        };
        have.insert(copy.0);
        let motion = motions_by_name.get(name.0.as_str());
        let pose = match mechanism {
            Some(_) => motion.map(|m| mechanism_pose(mass, m, scale)),
            None => pose.copied(),
        };
        let t = pose.map_or(Transform::IDENTITY, |p| pose_transform(mass.centroid.coords.into(), &p));
        if *transform != t {
            *transform = t;
        }
        // Supports see-through, so that nothing moving hides behind them.
        let want = if support {
            &palette.support_translucent
        } else if mechanism.is_some() && motion.is_none() {
            &palette.still
        } else {
            &palette.moved
        };
        if material.0 != *want {
            material.0 = want.clone();
        }
    }
    for (e, mesh, ..) in &blocks {
        if !have.contains(&e) {
            commands.spawn((
                Mesh3d(mesh.0.clone()),
                MeshMaterial3d(palette.still.clone()),
                Transform::IDENTITY,
                RenderLayers::layer(PHYSICS_LAYER),
                Moved(e),
            ));
        }
    }
}

/// The rest-state ghosts: a faint copy of every free block at rest, shown where its moved
/// copy has left.
fn rest_ghosts(
    mut commands: Commands,
    palette: Res<Palette>,
    moved: Query<(&Moved, &Transform, &Mesh3d)>,
    blocks: Query<Has<Support>>,
    mut ghosts: Query<(Entity, &AtRest, &mut Visibility)>,
) {
    let away: HashMap<Entity, (bool, &Mesh3d)> =
        moved.iter().map(|(m, t, mesh)| (m.0, (*t != Transform::IDENTITY, mesh))).collect();
    let mut have = HashSet::new();
    for (e, ghost, mut visibility) in &mut ghosts {
        let Some(&(away, _)) = away.get(&ghost.0) else {
            commands.entity(e).despawn();
            continue;
        };
        have.insert(ghost.0);
        let v = if away { Visibility::Visible } else { Visibility::Hidden };
        if *visibility != v {
            *visibility = v;
        }
    }
    for (&block, &(_, mesh)) in &away {
        if !have.contains(&block) && !blocks.get(block).unwrap_or(true) {
            commands.spawn((
                Mesh3d(mesh.0.clone()),
                MeshMaterial3d(palette.rest.clone()),
                Transform::IDENTITY,
                Visibility::Hidden,
                RenderLayers::layer(PHYSICS_LAYER),
                AtRest(block),
            ));
        }
    }
}

/// The mechanism's moving joints, on side b's moved face, coloured by what they do.
fn joints(
    mut commands: Commands,
    shown: Shown,
    palette: Res<Palette>,
    mut meshes: ResMut<Assets<Mesh>>,
    marks: Query<Entity, With<JointMark>>,
    mut drawn: Local<bool>,
) {
    let (Pane::Mechanism { mechanism, scale, .. }, Some(a)) = (shown.pane(), &shown.pipeline.analysis) else {
        marks.iter().for_each(|e| commands.entity(e).despawn());
        *drawn = false;
        return;
    };
    // Redrawn when what the mechanism comes from (or which one is shown) changed.
    let changed = shown.pipeline.is_changed()
        || shown.robustness.is_changed()
        || shown.kinematic.is_changed()
        || shown.state.is_changed();
    if *drawn && !changed {
        return;
    }
    *drawn = true;
    marks.iter().for_each(|e| commands.entity(e).despawn());
    for im in mechanism.interfaces.iter().filter(|im| im.state != JointState::Closed) {
        let Some(itf) = a.interfaces.get(im.index) else { continue };
        let moved: Vec<[f64; 3]> =
            itf.polygon.iter().map(|p| (p + mechanism.point_motion(&a.assembly, itf.b, p) * scale).into()).collect();
        let flat: Vec<[f64; 2]> = itf.polygon.iter().map(|p| itf.frame.to_2d(p)).collect();
        let colour = colors::joint_state(im.state);
        let triangles: Vec<crate::viz::ColouredTriangle> = crate::geometry::polygon::triangulate_2d(&flat, &[])
            .into_iter()
            .map(|t| t.map(|k| (moved[k], colour)))
            .collect();
        commands.spawn((
            Mesh3d(meshes.add(coloured_mesh(&triangles, itf.frame.n.into()))),
            MeshMaterial3d(palette.interface.clone()),
            RenderLayers::layer(PHYSICS_LAYER),
            JointMark,
        ));
    }
}

fn spawn_caption(mut commands: Commands) {
    commands.spawn((
        Text::new(""),
        TextFont { font_size: bevy::text::FontSize::Px(11.0), ..default() },
        TextColor(Color::srgb(0.92, 0.92, 0.92)),
        BackgroundColor(Color::srgba(0.0, 0.0, 0.0, 0.55)),
        Node {
            position_type: PositionType::Absolute,
            padding: UiRect::all(px(4)),
            display: Display::None,
            ..default()
        },
        Caption,
    ));
}

/// The caption at the pane's top-left corner.
fn caption(
    shown: Shown,
    pane: Query<&Camera, With<super::camera::PhysicsCamera>>,
    window: Query<&Window, With<bevy::window::PrimaryWindow>>,
    mut text: Query<(&mut Text, &mut Node), With<Caption>>,
) {
    let Ok((mut text, mut node)) = text.single_mut() else { return };
    let words = shown.caption();
    let at = pane.single().ok().filter(|c| c.is_active).and_then(|c| c.physical_viewport_rect());
    let scale = window.single().map_or(1.0, |w| w.scale_factor());
    let (display, left) = match at {
        Some(r) if !words.is_empty() => (Display::Flex, r.min.x as f32 / scale + 6.0),
        _ => (Display::None, 0.0),
    };
    if node.display != display {
        node.display = display;
    }
    if node.left != px(left) {
        node.left = px(left);
        node.top = px(6.0);
    }
    if text.0 != words {
        text.0 = words;
    }
}

/// The load as arrows (the load factor's live load, or gravity for the kinematic check), and
/// a ring at every moving joint's contact — a hinge where its contact stays closed — in the
/// joint's colour, facing the pane's camera (a joint seen edge-on shows as a ring).
fn gizmo_marks(
    shown: Shown,
    camera: Query<&GlobalTransform, With<super::camera::PhysicsCamera>>,
    mut gizmos: Gizmos<MotionGizmos>,
) {
    let (Pane::Mechanism { mechanism, scale, kinematic }, Some(a)) = (shown.pane(), &shown.pipeline.analysis) else {
        return;
    };
    let bb = a.assembly.aabb();
    let size = bb.diagonal() as f32;
    let facing = camera.single().map_or(Quat::IDENTITY, |t| Quat::from_rotation_arc(Vec3::Z, -t.forward().as_vec3()));
    for (point, state) in joint_contacts(mechanism, a, scale) {
        let [r, g, b] = colors::joint_state(state);
        let at = Isometry3d::new(Vec3::from_array(point.map(|x| x as f32)), facing);
        gizmos.circle(at, 0.018 * size, Color::linear_rgb(r, g, b));
        gizmos.circle(at, 0.009 * size, Color::linear_rgb(r, g, b));
    }
    let top = Vec3::new(bb.center().x as f32, bb.center().y as f32, bb.max.z as f32 + 0.08 * size);
    let colour = Color::srgb(0.95, 0.95, 0.95);
    let length = 0.22 * size;
    if kinematic {
        gizmos.arrow(top + Vec3::Z * length, top, colour);
        return;
    }
    for d in load_directions(&shown.state.design.loads, shown.robustness.worst_azimuth) {
        let start = top - d * (0.5 * length);
        gizmos.arrow(start, start + d * length, colour);
    }
}

/// Where each moving joint of `m` is marked, moved with side b: the centre of its vertices
/// that stay closed (a hinge's line, a sliding joint's contact), or of all its vertices when
/// every one opens.
fn joint_contacts(m: &Mechanism, a: &crate::pipeline::Analysis, scale: f64) -> Vec<([f64; 3], JointState)> {
    let asm = &a.assembly;
    let largest = m.largest_motion(asm);
    let mut out = Vec::new();
    for im in m.interfaces.iter().filter(|im| im.state != JointState::Closed) {
        let Some(itf) = a.interfaces.get(im.index) else { continue };
        let opening = |p: &crate::geometry::Point3| {
            (m.point_motion(asm, itf.b, p) - m.point_motion(asm, itf.a, p)).dot(&itf.frame.n)
        };
        let closed: Vec<&crate::geometry::Point3> =
            itf.polygon.iter().filter(|p| opening(p) <= crate::statics::mechanism::STILL * largest).collect();
        let points = if closed.is_empty() { itf.polygon.iter().collect() } else { closed };
        let centre = points.iter().map(|p| p.coords).sum::<crate::geometry::Vector3>() / points.len().max(1) as f64;
        let centre = crate::geometry::Point3::from(centre);
        out.push(((centre + m.point_motion(asm, itf.b, &centre) * scale).into(), im.state));
    }
    out
}

/// The directions of the live loads (unit, world axes), or the worst horizontal direction.
fn load_directions(loads: &[Load], worst_azimuth: Option<f64>) -> Vec<Vec3> {
    if let Some(az) = worst_azimuth {
        let az = az.to_radians() as f32;
        return vec![Vec3::new(az.cos(), az.sin(), 0.0)];
    }
    loads
        .iter()
        .filter(|l| l.kind() == LoadKind::Live)
        .map(|l| match l {
            Load::Point { force, .. } => Vec3::new(force.x as f32, force.y as f32, force.z as f32),
            Load::Acceleration { accel, .. } => Vec3::new(accel.x as f32, accel.y as f32, accel.z as f32),
        })
        .filter_map(|v| v.try_normalize())
        .collect()
}

/// Sets the pane's own view square to a mechanism's plane (none: the design's view).
fn pane_view(shown: Shown, mut view: ResMut<PaneView>) {
    let want = match (shown.pane(), &shown.pipeline.analysis) {
        (Pane::Mechanism { mechanism, .. }, Some(a)) => crate::viz::mechanism_plane(mechanism, &a.assembly).map(|n| {
            let yaw = n.y.atan2(n.x) as f32;
            PaneView::Square { yaw }
        }),
        _ => None,
    }
    .unwrap_or(PaneView::Follow);
    view.set_if_neq(want);
}

/// A block's pose `scale` × along its mechanism motion: centroid moved by the translation,
/// turned by the rotation vector.
fn mechanism_pose(mass: &MassCentre, m: &BlockMotion, scale: f64) -> BlockPose {
    let t = crate::geometry::Vector3::from(m.translation) * scale;
    let q = Quat::from_scaled_axis(Vec3::from_array(m.rotation.map(|x| x as f32)) * scale as f32);
    BlockPose { centroid: mass.centroid + t, rotation: [q.w, q.x, q.y, q.z].map(f64::from) }
}

/// x ↦ c + R (x − c₀): the mesh is in world coordinates at rest.
fn pose_transform(c0: [f64; 3], pose: &BlockPose) -> Transform {
    let [w, x, y, z] = pose.rotation.map(|v| v as f32);
    let r = Quat::from_xyzw(x, y, z, w).normalize();
    let c = Vec3::from_array(<[f64; 3]>::from(pose.centroid.coords).map(|v| v as f32));
    Transform { translation: c - r * Vec3::from_array(c0.map(|v| v as f32)), rotation: r, scale: Vec3::ONE }
}
