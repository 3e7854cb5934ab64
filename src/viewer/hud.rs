//! The side panel: verdict first (coloured), the graded numbers, timings and counts, the drop
//! test beside the statics, the sequence step, the edit state; the colour legend of the mode;
//! buttons for everything the keys do; the keys. Optional force labels over the interfaces.

use super::PANEL_WIDTH;
use super::actions::{Overlay, ViewerAction, ViewerState};
use super::camera::MainCamera;
use crate::ecs::{
    DropStatus, InterfaceForces, KinematicStatus, PipelineState, RobustnessStatus, SceneStatus, SequenceStatus,
};
use crate::statics::Verdict;
use crate::viz::{DiagramMode, colors};
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;

pub struct HudPlugin;

impl Plugin for HudPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, spawn_panel)
            .add_systems(Update, press_buttons.before(super::actions::ActionSystems))
            .add_systems(Update, (write_texts, legend, labels));
    }
}

/// A button that sends its action when pressed.
#[derive(Component, Clone)]
pub struct HudButton(pub ViewerAction);

#[derive(Component, Clone, Copy, PartialEq, Eq)]
enum Line {
    Title,
    Verdict,
    Numbers,
    Dynamics,
    Robustness,
    Kinematic,
    Sequence,
    Edit,
}

#[derive(Component)]
struct Legend;

#[derive(Component)]
struct Label;

const KEYS: &str = "mouse: left click select · right drag orbit · shift+right / middle drag pan · wheel zoom\n\
1/2/3 compression/friction/vectors · T translucent · M mass centres · V vertex arrows · L labels · F frame\n\
C cut selected · PgUp/PgDn move cut · arrows turn cut · Backspace drop cut · O repair (selected block's cuts)\n\
G support · X remove · R restore · Ctrl+Z/Y undo/redo · Ctrl+S save\n\
D drop test · Esc leave drop / sequence · Q sequence · ,/. step · K collapse mechanism · J kinematic check";

fn font(size: f32) -> TextFont {
    TextFont { font_size: FontSize::Px(size), ..default() }
}

fn button(label: &str, action: ViewerAction) -> impl Bundle {
    (
        Button,
        HudButton(action),
        Node { padding: UiRect::axes(px(6), px(3)), margin: UiRect::all(px(2)), ..default() },
        BackgroundColor(Color::srgb(0.22, 0.22, 0.24)),
        children![(Text::new(label), font(12.0), TextColor(Color::srgb(0.92, 0.92, 0.92)))],
    )
}

fn row() -> Node {
    Node { flex_direction: FlexDirection::Row, flex_wrap: FlexWrap::Wrap, ..default() }
}

fn spawn_panel(mut commands: Commands) {
    let text = |line: Line, size: f32| (Text::new(""), font(size), TextColor(Color::srgb(0.9, 0.9, 0.9)), line);
    let friction = DiagramMode::Friction { threshold: DiagramMode::DEFAULT_THRESHOLD };
    commands
        .spawn((
            Node {
                width: px(PANEL_WIDTH),
                height: percent(100),
                flex_direction: FlexDirection::Column,
                padding: UiRect::all(px(10)),
                row_gap: px(6),
                overflow: Overflow::clip(),
                ..default()
            },
            BackgroundColor(Color::srgb(0.07, 0.07, 0.08)),
        ))
        .with_children(|p| {
            p.spawn(text(Line::Title, 15.0));
            p.spawn(text(Line::Verdict, 22.0));
            p.spawn(text(Line::Numbers, 12.0));
            p.spawn(text(Line::Dynamics, 12.0));
            p.spawn(text(Line::Robustness, 12.0));
            p.spawn(text(Line::Kinematic, 12.0));
            p.spawn(text(Line::Sequence, 12.0));
            p.spawn((
                row(),
                children![
                    button("1 Compression", ViewerAction::SetMode(DiagramMode::Compression)),
                    button("2 Friction", ViewerAction::SetMode(friction)),
                    button("3 Vectors", ViewerAction::SetMode(DiagramMode::Vectors)),
                ],
            ));
            p.spawn((Node { flex_direction: FlexDirection::Column, row_gap: px(2), ..default() }, Legend));
            p.spawn((
                row(),
                children![
                    button("T Translucent", ViewerAction::ToggleTranslucent),
                    button("M Centres", ViewerAction::ToggleMassCentres),
                    button("L Labels", ViewerAction::ToggleLabels),
                    button("K Mechanism", ViewerAction::ToggleMechanism),
                    button("J Kinematic", ViewerAction::ToggleKinematic),
                ],
            ));
            p.spawn((
                row(),
                children![
                    button("C Cut", ViewerAction::AddCut),
                    button("O Repair", ViewerAction::Repair),
                    button("G Support", ViewerAction::ToggleSupport),
                    button("X Remove", ViewerAction::RemoveBlock),
                    button("R Restore", ViewerAction::RestoreBlock),
                ],
            ));
            p.spawn((
                row(),
                children![
                    button("Undo", ViewerAction::Undo),
                    button("Redo", ViewerAction::Redo),
                    button("Save", ViewerAction::Save),
                ],
            ));
            p.spawn((
                row(),
                children![
                    button("D Drop test", ViewerAction::DropTest),
                    button("Q Sequence", ViewerAction::StartSequence),
                    button("<", ViewerAction::Step(-1)),
                    button(">", ViewerAction::Step(1)),
                    button("Esc", ViewerAction::ResetDrop),
                ],
            ));
            p.spawn(text(Line::Edit, 12.0));
            p.spawn((Text::new(KEYS), font(10.0), TextColor(Color::srgb(0.6, 0.6, 0.6))));
        });
}

fn press_buttons(
    buttons: Query<(&Interaction, &HudButton), Changed<Interaction>>,
    mut actions: MessageWriter<ViewerAction>,
) {
    for (interaction, button) in &buttons {
        if *interaction == Interaction::Pressed {
            // Esc leaves whichever special view is open.
            if button.0 == ViewerAction::ResetDrop {
                actions.write(ViewerAction::ExitSequence);
            }
            actions.write(button.0.clone());
        }
    }
}

/// The verdict in words and its colour.
pub fn verdict_text(v: Option<Verdict>) -> (&'static str, Color) {
    let text = match v {
        Some(Verdict::Stands) => "STANDS",
        Some(Verdict::NeedsTension) => "NEEDS TENSION",
        Some(Verdict::NeedsFriction) => "FRICTION EXCEEDED",
        Some(Verdict::NeedsTensionAndFriction) => "TENSION + FRICTION",
        Some(Verdict::Unsupported) => "UNSUPPORTED",
        Some(Verdict::Unresolved) => "SOLVER TROUBLE",
        None => "—",
    };
    let [r, g, b] = colors::verdict(v);
    (text, Color::srgb(r, g, b))
}

/// What the viewer shows: its own state and the ECS's results.
#[derive(SystemParam)]
pub(super) struct Shown<'w> {
    pub state: Res<'w, ViewerState>,
    pub status: Res<'w, SceneStatus>,
    pub pipeline: Res<'w, PipelineState>,
    pub drop: Res<'w, DropStatus>,
    pub sequence: Res<'w, SequenceStatus>,
    pub robustness: Res<'w, RobustnessStatus>,
    pub kinematic: Res<'w, KinematicStatus>,
}

fn write_texts(shown: Shown, mut texts: Query<(&Line, &mut Text, &mut TextColor)>) {
    for (line, mut text, mut colour) in &mut texts {
        if *line == Line::Verdict {
            let c = verdict_text(shown.status.verdict).1;
            if colour.0 != c {
                colour.0 = c;
            }
        }
        let value = shown.text(*line);
        if text.0 != value {
            text.0 = value;
        }
    }
}

impl Shown<'_> {
    fn text(&self, line: Line) -> String {
        match line {
            Line::Title => {
                let a = self.pipeline.analysis.as_ref();
                let (b, i) = a.map_or((0, 0), |a| (a.assembly.blocks.len(), a.interfaces.len()));
                format!("{}\n{b} blocks · {i} interfaces", self.state.design.name)
            }
            Line::Verdict => verdict_text(self.status.verdict).0.to_string(),
            Line::Numbers => self.numbers_text(),
            Line::Dynamics => self.drop_text(),
            Line::Robustness => robustness_text(&self.state, &self.robustness),
            Line::Kinematic => kinematic_text(&self.state, &self.kinematic),
            Line::Sequence => self.sequence_text(),
            Line::Edit => edit_text(&self.state),
        }
    }

    /// The graded numbers and the solve's timings, or the error that stopped the analysis.
    fn numbers_text(&self) -> String {
        let status = &self.status;
        if let Some(e) = &status.error {
            return format!("error: {e}");
        }
        let t = &status.timings;
        // Utilisation is measured as a circle; the polyhedral models allow more.
        let model = self.pipeline.analysis.as_ref().map(|a| a.statics.friction_model);
        let bound = model
            .filter(|m| *m != crate::statics::FrictionModel::Cone)
            .map_or(String::new(), |m| format!(" (≤ {:.2} in {m})", m.max_utilization()));
        format!(
            "tension {:.2e} W · friction excess {:.2e} W\nmax friction utilisation {:.2} μ{bound}\nsolve {:.1} ms (detect {:.1}, assemble {:.1}, interior point {:.1}; total {:.1})",
            status.tension_ratio,
            status.friction_excess_ratio,
            status.max_friction_utilization,
            1e3 * (t.assemble + t.solve),
            1e3 * t.detect,
            1e3 * t.assemble,
            1e3 * t.solve,
            1e3 * t.total
        )
    }

    /// The drop test: its progress, its outcome beside the statics', or why it did not run.
    fn drop_text(&self) -> String {
        let drop = &self.drop;
        match (&drop.running, &drop.result) {
            (Some(run), _) => format!(
                "drop test: {:.2} / {:.2} s simulated",
                run.steps_done() as f64 * run.dt(),
                run.total_steps() as f64 * run.dt()
            ),
            (None, Some(r)) => format!(
                "drop test: {} (drift {:.1e}, rotation {:.1e}) — {}",
                if r.stands { "stands" } else { "falls" },
                r.max_drift,
                r.max_rotation,
                match drop.agree {
                    Some(true) => "agrees with the statics",
                    Some(false) => "DISAGREES with the statics",
                    None => "",
                }
            ),
            _ => drop.error.clone().unwrap_or_else(|| "drop test: not run (D)".into()),
        }
    }

    /// The sequence step shown: the block placed, its verdicts and what fails.
    fn sequence_text(&self) -> String {
        let sequence = &self.sequence;
        let (Some(r), Some(step)) = (&sequence.report, sequence.step()) else {
            return sequence.error.clone().map_or(String::new(), |e| format!("sequence: {e}"));
        };
        let dynamic = step
            .dynamic
            .as_ref()
            .map_or(String::new(), |d| format!(" · drop: {}", if d.stands { "stands" } else { "falls" }));
        let mut s = format!(
            "sequence step {}/{}: + {}\nstatics: {}{dynamic}",
            sequence.current + 1,
            r.steps.len(),
            step.placed,
            verdict_text(Some(step.verdict)).0.to_lowercase()
        );
        if !step.offending.is_empty() {
            s += &format!("\noffending: {}", step.offending.join(", "));
        }
        s
    }
}

/// The edit state: the selection, the cut being edited, the history, the last note.
fn edit_text(state: &ViewerState) -> String {
    let mut s = format!("selected: {}", state.selected.as_deref().unwrap_or("—"));
    if let Some(c) = &state.active_cut {
        s += &format!(
            "\ncut #{} of {}: point ({:.3}, {:.3}, {:.3}) normal ({:.2}, {:.2}, {:.2})",
            c.index, c.target, c.point.x, c.point.y, c.point.z, c.normal.x, c.normal.y, c.normal.z
        );
    }
    s += &format!("\nundo {} · redo {}", state.undo.len(), state.redo.len());
    if let Some(m) = &state.message {
        s += &format!("\n{m}");
    }
    s
}

/// The load factor line: λ* (and the worst direction) while the mechanism view is on.
fn robustness_text(state: &ViewerState, r: &RobustnessStatus) -> String {
    use crate::stability::Safety;
    if state.overlay != Overlay::Mechanism {
        return "load factor: not computed (K)".into();
    }
    if let Some(e) = &r.error {
        return format!("load factor: {e}");
    }
    let Some(result) = &r.result else { return "load factor: …".into() };
    let mut s = match result.safety {
        Safety::Collapses { load_factor } => format!("load factor λ* = {load_factor:.4}"),
        Safety::Unlimited => "load factor λ* = ∞".into(),
        Safety::DoesNotStand { .. } => "does not stand: failure mechanism".into(),
        Safety::SolverFailed { status, .. } => format!("load factor: solver {status:?}"),
    };
    if let Some(az) = r.worst_azimuth {
        s += &format!(" · worst direction {az:.1}°");
    }
    s
}

/// The kinematic line: both verdicts and whether they agree, while the check is on.
fn kinematic_text(state: &ViewerState, k: &KinematicStatus) -> String {
    use crate::stability::kinematic::KinematicVerdict;
    if state.overlay != Overlay::Kinematic {
        return "kinematic check: not run (J)".into();
    }
    if let Some(e) = &k.error {
        return format!("kinematic check: {e}");
    }
    let Some(r) = &k.result else { return "kinematic check: …".into() };
    let verdict = match r.verdict {
        KinematicVerdict::Stands => "stands",
        KinematicVerdict::Fails if r.mechanism.is_some() => "falls (mechanism shown)",
        KinematicVerdict::Fails => "falls",
        KinematicVerdict::Undecided => "undecided",
    };
    let agreement = match (r.verdict, r.agrees) {
        (KinematicVerdict::Undecided, _) => "",
        (_, true) => " — agrees with the statics",
        (_, false) => " — DISAGREES with the statics",
    };
    format!("kinematic check: {verdict}{agreement} ({} rounds, {:.0} ms)", r.rounds, 1e3 * r.solver_seconds)
}

fn legend(
    mut commands: Commands,
    state: Res<ViewerState>,
    panel: Query<Entity, With<Legend>>,
    mut shown: Local<Option<DiagramMode>>,
) {
    if *shown == Some(state.mode) {
        return;
    }
    let Ok(panel) = panel.single() else { return };
    *shown = Some(state.mode);
    commands.entity(panel).despawn_children();
    let mut rows: Vec<(Color, &str)> =
        crate::viz::legend(state.mode).into_iter().map(|(c, l)| (Color::linear_rgb(c[0], c[1], c[2]), l)).collect();
    if state.mode == DiagramMode::Vectors {
        rows.push((Color::srgb(0.1, 0.8, 0.25), "resultant force (length ∝ |F|)"));
    }
    commands.entity(panel).with_children(|p| {
        for (c, label) in rows {
            p.spawn((
                Node { column_gap: px(6), ..row() },
                children![
                    (Node { width: px(18), height: px(12), ..default() }, BackgroundColor(c)),
                    (Text::new(label), font(11.0), TextColor(Color::srgb(0.85, 0.85, 0.85))),
                ],
            ));
        }
    });
}

/// Force labels (kN or N) at the resultant points of the largest interface forces.
fn labels(
    mut commands: Commands,
    state: Res<ViewerState>,
    forces: Query<&InterfaceForces>,
    camera: Query<(&Camera, &GlobalTransform), With<MainCamera>>,
    shown: Query<Entity, With<Label>>,
) {
    shown.iter().for_each(|e| commands.entity(e).despawn());
    if !state.labels || state.sequence_view {
        return;
    }
    let Ok((camera, at)) = camera.single() else { return };
    let mut list: Vec<&crate::statics::InterfaceResult> = forces.iter().map(|f| &f.0).collect();
    list.sort_by(|a, b| b.normal_force.abs().total_cmp(&a.normal_force.abs()));
    for r in list.into_iter().take(40) {
        let Some(p) = r.resultant_point else { continue };
        let Ok(xy) = camera.world_to_viewport(at, Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32)) else { continue };
        let n = r.normal_force;
        let text = if n.abs() >= 1e3 { format!("{:.1} kN", n / 1e3) } else { format!("{n:.1} N") };
        commands.spawn((
            Text::new(text),
            font(11.0),
            TextColor(Color::WHITE),
            Node { position_type: PositionType::Absolute, left: px(xy.x), top: px(xy.y), ..default() },
            Label,
        ));
    }
}
