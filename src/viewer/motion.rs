//! The motion pane, right of the design while a drop test, the load factor's collapse
//! mechanism (K) or the kinematic check's mechanism (J) is shown: the blocks at rest as faint
//! ghosts, the moved blocks in violet (a colour no diagram legend uses), supports dark, the
//! joints of a mechanism coloured by what they do (hinging, opening, sliding, as in the PNG
//! export), the load as an arrow, and a caption saying what is shown and how much it is
//! exaggerated. A mechanism is seen square to its plane (the plane its blocks turn in).

use super::Overlay;
use super::camera::{COMPARED_LAYER, PHYSICS_LAYER, PaneView};
use super::draw::{Palette, coloured_mesh};
use super::hud::Shown;
use crate::ecs::{BlockName, BlockPose, ComparedPose, DropLane, MassCentre, SettlePose, ShakePose};
use crate::ecs::{Support, VoussoirSet};
use crate::model::{Load, LoadKind};
use crate::report::words;
use crate::stability::{BlockMotion, JointState, Mechanism};
use crate::studies::settlement::Outcome;
use crate::viz::colors;
use bevy::camera::visibility::RenderLayers;
use bevy::prelude::*;
use std::collections::{HashMap, HashSet};

pub struct MotionPlugin;

impl Plugin for MotionPlugin {
    fn build(&self, app: &mut App) {
        app.init_gizmo_group::<MotionGizmos>()
            .init_resource::<PaneView>()
            .add_systems(Startup, (configure_gizmos, spawn_caption, spawn_thrust_plot))
            .add_systems(
                Update,
                (copies, rest_ghosts, joints, caption, thrust_plot, gizmo_marks, pane_view)
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

/// A block's copy in a motion pane (lane 0 the pane, lane 1 the compared engine's), moved.
#[derive(Component)]
struct Moved {
    block: Entity,
    lane: usize,
}

/// A block's copy in a motion pane, at rest (shown while its moved copy is elsewhere).
#[derive(Component)]
struct AtRest {
    block: Entity,
    lane: usize,
}

/// The render layer of a lane's pane.
fn lane_layer(lane: usize) -> RenderLayers {
    RenderLayers::layer(if lane == 0 { PHYSICS_LAYER } else { COMPARED_LAYER })
}

/// A mechanism's moving joint, drawn on its moved face.
#[derive(Component)]
struct JointMark;

/// The caption over a motion pane (the lane's).
#[derive(Component)]
pub(super) struct Caption(usize);

/// What the motion pane shows.
pub(super) enum Pane<'a> {
    Hidden,
    Drop,
    /// The supports moving: the settlement's quasi-static motion.
    Settle,
    /// The ground shaking: the first engine's run.
    Shake,
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
        if self.state.drop_view && !self.drop.lanes.is_empty() {
            return Pane::Drop;
        }
        if self.state.settle_view {
            return Pane::Settle;
        }
        if self.state.shake_view {
            return Pane::Shake;
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
        self.lane_caption(0)
    }

    /// The caption of a lane's pane (lane 1: the compared engine's; empty when not shown).
    pub(super) fn lane_caption(&self, lane: usize) -> String {
        if lane > 0 {
            return match (self.pane(), self.drop.lanes.get(lane)) {
                (Pane::Drop, Some(l)) => drop_caption(l),
                _ => String::new(),
            };
        }
        match self.pane() {
            Pane::Hidden => self.nothing_moves().into(),
            Pane::Drop => self.drop.lead().map_or(String::new(), drop_caption),
            Pane::Settle => self.settle_caption(),
            Pane::Shake => self.shake_caption(),
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
                let unique = mechanism.uniqueness.label().map_or(String::new(), |l| format!("\n{l}"));
                format!(
                    "{head}\nviolet: moved, largest motion drawn\n  as {:.0} % of the size · ghost: at rest\n{}{unique}",
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

    /// The settlement pane's caption: where along the path the motion is, and how it ends.
    fn settle_caption(&self) -> String {
        let s = &self.settle;
        let (Some(r), Some((_, fraction))) = (&s.result, s.frame()) else {
            return s.error.clone().unwrap_or_else(|| "supports move: following the path…".into());
        };
        let end = match r.quasi_static.outcome {
            Outcome::Collapses { fraction, movement, .. } => {
                format!("collapses at {:.1} % of the path ({})", 100.0 * fraction, words::length(movement))
            }
            Outcome::Stands => "stands to the end of the path".into(),
            Outcome::Unresolved { fraction, .. } => format!("solver trouble at {:.1} % of the path", 100.0 * fraction),
        };
        format!(
            "supports move (quasi-static), true scale\n{:.1} % of the path · {}\n{end}\nviolet: the blocks now · ghost: at the start",
            100.0 * fraction,
            words::length(fraction * r.path_movement),
        )
    }

    /// The shake pane's caption: the clock, the ground's acceleration then, λ*, how it ends.
    fn shake_caption(&self) -> String {
        let s = &self.shake;
        let (Some(r), Some((_, t))) = (&s.result, s.frame()) else {
            return s.error.clone().unwrap_or_else(|| "shake: running the exact engine…".into());
        };
        let Some(run) = r.runs.first() else { return String::new() };
        let end = match run.collapse_time_s {
            Some(c) => format!("collapses at {c:.2} s"),
            None => "survives".into(),
        };
        format!(
            "shake ({}), true scale, relative to the ground\nt = {t:.2} s · ground {:+.3} g · λ* = {:.4} g\n{end}\nviolet: the blocks now · ghost: at the start",
            run.result.engine.name(),
            s.ground_now().unwrap_or(0.0),
            r.static_load_factor,
        )
    }

    /// The live load the load factor scales, in words.
    fn load_words(&self) -> String {
        match self.robustness.worst_azimuth {
            Some(az) => format!("load: horizontal × λ*, worst at {az:.0}° (arrow)"),
            None => "load: the design's live loads × λ* (arrows)".into(),
        }
    }
}

/// A drop-test lane's caption: engine, clock and verdict.
fn drop_caption(lane: &DropLane) -> String {
    let (t, total) = lane.clock();
    let verdict = lane.result.as_ref().map_or("", |r| if r.stands { ": stands" } else { ": falls" });
    format!(
        "drop test ({}), true scale\nt = {t:.2} of {total:.2} s{verdict}\nviolet: the blocks now · ghost: at the start",
        lane.engine()
    )
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
    ghosts: Query<'w, 's, (&'static AtRest, &'static Visibility)>,
    joints: Query<'w, 's, (), With<JointMark>>,
}

impl PaneCounts<'_, '_> {
    /// Copies in the pane, those moved off their rest place, rest ghosts shown, joints marked;
    /// and the copies of the compared engine's pane moved off their rest place.
    pub(super) fn describe(&self) -> serde_json::Value {
        let moved =
            |lane: usize| self.moved.iter().filter(|(m, t)| m.lane == lane && **t != Transform::IDENTITY).count();
        serde_json::json!({
            "copies": self.moved.iter().filter(|(m, _)| m.lane == 0).count(),
            "moved": moved(0),
            "ghosts": self.ghosts.iter().filter(|(g, v)| g.lane == 0 && **v != Visibility::Hidden).count(),
            "joints": self.joints.iter().count(),
            "compared_copies": self.moved.iter().filter(|(m, _)| m.lane == 1).count(),
            "compared_moved": moved(1),
        })
    }
}

/// A block as its copies need it.
type Source<'a> = (
    Entity,
    &'a Mesh3d,
    &'a MassCentre,
    Option<&'a BlockPose>,
    Option<&'a ComparedPose>,
    Option<&'a SettlePose>,
    Option<&'a ShakePose>,
    &'a BlockName,
    Has<Support>,
);

/// The moved copies: every block in each pane shown, moved by its drop-test pose (the lane's)
/// or along the mechanism; a mechanism's still blocks in stone, its moving ones violet.
fn copies(
    mut commands: Commands,
    shown: Shown,
    palette: Res<Palette>,
    blocks: Query<Source, Without<Moved>>,
    mut moved: Query<(Entity, &Moved, &mut Transform, &mut MeshMaterial3d<StandardMaterial>)>,
) {
    let pane = shown.pane();
    let lanes = match pane {
        Pane::Hidden => 0,
        Pane::Drop if shown.drop.compared() => 2,
        Pane::Settle if shown.settle.result.is_none() => 0,
        Pane::Shake if shown.shake.result.is_none() => 0,
        _ => 1,
    };
    let (mechanism, scale) = match pane {
        Pane::Mechanism { mechanism, scale, .. } => (Some(mechanism), scale),
        _ => (None, 0.0),
    };
    let motions_by_name: HashMap<&str, &BlockMotion> =
        mechanism.iter().flat_map(|m| &m.blocks).map(|b| (b.block.as_str(), b)).collect();
    let mut have = HashSet::new();
    for (e, copy, mut transform, mut material) in &mut moved {
        let Some((_, _, mass, pose, compared, settled, shaken, name, support)) =
            blocks.get(copy.block).ok().filter(|_| copy.lane < lanes)
        else {
            commands.entity(e).despawn();
            continue;
        };
        have.insert((copy.block, copy.lane));
        let motion = motions_by_name.get(name.0.as_str());
        let pose = match (mechanism, copy.lane) {
            (Some(_), _) => motion.map(|m| mechanism_pose(mass, m, scale)),
            (None, _) if matches!(pane, Pane::Settle) => settled.map(|s| s.0),
            (None, _) if matches!(pane, Pane::Shake) => shaken.map(|s| s.0),
            (None, 0) => pose.copied(),
            (None, _) => compared.map(|c| c.0),
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
    for lane in 0..lanes {
        for (e, mesh, ..) in blocks.iter().filter(|b| !have.contains(&(b.0, lane))) {
            commands.spawn((
                Mesh3d(mesh.0.clone()),
                MeshMaterial3d(palette.still.clone()),
                Transform::IDENTITY,
                lane_layer(lane),
                Moved { block: e, lane },
            ));
        }
    }
}

/// The rest-state ghosts: a faint copy of every free block at rest, shown where its moved
/// copy (in the same pane) has left.
fn rest_ghosts(
    mut commands: Commands,
    palette: Res<Palette>,
    moved: Query<(&Moved, &Transform, &Mesh3d)>,
    blocks: Query<Has<Support>>,
    mut ghosts: Query<(Entity, &AtRest, &mut Visibility)>,
) {
    let away: HashMap<(Entity, usize), (bool, &Mesh3d)> =
        moved.iter().map(|(m, t, mesh)| ((m.block, m.lane), (*t != Transform::IDENTITY, mesh))).collect();
    let mut have = HashSet::new();
    for (e, ghost, mut visibility) in &mut ghosts {
        let Some(&(away, _)) = away.get(&(ghost.block, ghost.lane)) else {
            commands.entity(e).despawn();
            continue;
        };
        have.insert((ghost.block, ghost.lane));
        let v = if away { Visibility::Visible } else { Visibility::Hidden };
        if *visibility != v {
            *visibility = v;
        }
    }
    for (&(block, lane), &(_, mesh)) in &away {
        if !have.contains(&(block, lane)) && !blocks.get(block).unwrap_or(true) {
            commands.spawn((
                Mesh3d(mesh.0.clone()),
                MeshMaterial3d(palette.rest.clone()),
                Transform::IDENTITY,
                Visibility::Hidden,
                lane_layer(lane),
                AtRest { block, lane },
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
    for lane in 0..2 {
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
            Caption(lane),
        ));
    }
}

/// Each caption at its pane's top-left corner.
fn caption(
    shown: Shown,
    pane: Query<&Camera, With<super::camera::PhysicsCamera>>,
    compared: Query<&Camera, With<super::camera::ComparedCamera>>,
    window: Query<&Window, With<bevy::window::PrimaryWindow>>,
    mut text: Query<(&mut Text, &mut Node, &Caption)>,
) {
    let scale = window.single().map_or(1.0, |w| w.scale_factor());
    for (mut text, mut node, lane) in &mut text {
        let words = shown.lane_caption(lane.0);
        let camera = if lane.0 == 0 { pane.single() } else { compared.single() };
        let at = camera.ok().filter(|c| c.is_active).and_then(|c| c.physical_viewport_rect());
        let (display, left, width) = match at {
            Some(r) if !words.is_empty() => {
                (Display::Flex, r.min.x as f32 / scale + 6.0, r.width() as f32 / scale - 12.0)
            }
            _ => (Display::None, 0.0, 0.0),
        };
        if node.display != display {
            node.display = display;
        }
        // Within the pane: three panes side by side are narrow.
        if node.max_width != px(width) {
            node.max_width = px(width);
        }
        if node.left != px(left) {
            node.left = px(left);
            node.top = px(6.0);
        }
        if text.0 != words {
            text.0 = words;
        }
    }
}

/// Which plot the pane's plot node shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PanePlot {
    /// The settlement's thrust against the movement.
    Thrust,
    /// The shake's ground acceleration with ±λ*, and the response.
    Shake,
}

/// The settlement's thrust curve or the shake's trace, at the bottom of the motion pane.
#[derive(Component)]
pub(super) struct ThrustPlotNode;

/// The thrust curve's size, pixels (drawn at this size, shown at half of it per logical pixel).
const THRUST_PLOT: (u32, u32) = (640, 400);

fn spawn_thrust_plot(mut commands: Commands) {
    commands.spawn((
        ImageNode::default(),
        Node {
            position_type: PositionType::Absolute,
            width: px(THRUST_PLOT.0 / 2),
            height: px(THRUST_PLOT.1 / 2),
            display: Display::None,
            ..default()
        },
        ThrustPlotNode,
    ));
}

/// Draws the thrust curve when a settlement's result arrives (the shake's trace when a
/// shake's does), and keeps it at the bottom-left corner of the pane while it is shown.
fn thrust_plot(
    shown: Shown,
    pane: Query<&Camera, With<super::camera::PhysicsCamera>>,
    window: Query<&Window, With<bevy::window::PrimaryWindow>>,
    mut images: ResMut<Assets<Image>>,
    mut node: Query<(&mut ImageNode, &mut Node), With<ThrustPlotNode>>,
    mut drawn: Local<Option<PanePlot>>,
) {
    let Ok((mut image, mut node)) = node.single_mut() else { return };
    let want = match shown.pane() {
        Pane::Settle => shown.settle.result.as_ref().map(|_| PanePlot::Thrust),
        Pane::Shake => shown.shake.result.as_ref().map(|_| PanePlot::Shake),
        _ => None,
    };
    if want.is_none() || *drawn != want {
        *drawn = None;
    }
    if let (Some(what), None) = (want, *drawn) {
        *drawn = want;
        let rgb = match what {
            PanePlot::Thrust => shown.settle.result.as_ref().map(|settlement| {
                crate::viz::plot::render_rgb(
                    &crate::viz::plot::ThrustPlot { title: "thrust against movement".into(), settlement },
                    THRUST_PLOT,
                )
            }),
            PanePlot::Shake => shown.shake.result.as_ref().map(|study| {
                crate::viz::plot::render_rgb(
                    &crate::viz::plot::ShakePlot { title: "ground acceleration, λ*, response".into(), study },
                    THRUST_PLOT,
                )
            }),
        };
        if let Some(Ok(rgb)) = rgb {
            image.image = images.add(rgba_image(&rgb, THRUST_PLOT));
        }
    }
    let scale = window.single().map_or(1.0, |w| w.scale_factor());
    let at = pane.single().ok().filter(|c| c.is_active).and_then(|c| c.physical_viewport_rect());
    let (display, left, top) = match at {
        Some(r) if drawn.is_some() => {
            (Display::Flex, r.min.x as f32 / scale + 6.0, r.max.y as f32 / scale - THRUST_PLOT.1 as f32 / 2.0 - 6.0)
        }
        _ => (Display::None, 0.0, 0.0),
    };
    if node.display != display {
        node.display = display;
    }
    if node.left != px(left) || node.top != px(top) {
        node.left = px(left);
        node.top = px(top);
    }
}

/// An 8-bit RGB picture as a texture.
fn rgba_image(rgb: &[u8], (w, h): (u32, u32)) -> Image {
    let data = rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    Image::new(
        bevy::render::render_resource::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        bevy::render::render_resource::TextureDimension::D2,
        data,
        bevy::render::render_resource::TextureFormat::Rgba8UnormSrgb,
        bevy::asset::RenderAssetUsages::default(),
    )
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
