//! The side panel: the design's name, the headline (the statics' verdict and any check that
//! disagrees), the graded numbers, the checks that ran (drop test, load factor, kinematic
//! check, sequence step), the colour legend of the mode, buttons that show their state, the edit
//! state, and the keys on request. Sections with nothing to say take no room, so the panel fits
//! a 1024×640 window. Optional force labels over the interfaces.

mod text;

pub use text::{Headline, verdict_text};

use super::PANEL_WIDTH;
use super::actions::{Overlay, ViewerAction, ViewerState};
use super::camera::MainCamera;
use crate::dynamics::Engine;
use crate::ecs::SequenceStatus;
use crate::ecs::{
    DropStatus, InterfaceForces, KinematicStatus, PipelineState, RobustnessStatus, SceneStatus, SettleStatus,
    ShakeStatus,
};
use crate::viz::DiagramMode;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::text::TextLayoutInfo;
use bevy::ui::UiGlobalTransform;
use serde_json::{Value, json};

pub struct HudPlugin;

impl Plugin for HudPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, spawn_panel)
            .add_systems(Update, press_buttons.before(super::actions::ActionSystems))
            .add_systems(Update, (write_texts, style_buttons, legend, labels, view_caption));
    }
}

/// A button that sends its action when pressed.
#[derive(Component, Clone)]
pub struct HudButton(pub ViewerAction);

/// A section of the panel's text.
#[derive(Component, Clone, Copy, PartialEq, Eq, Debug)]
enum Line {
    Title,
    Headline,
    Numbers,
    Checks,
    Edit,
    Keys,
}

impl Line {
    /// Whether the section is free text that may wrap (the design's name, an error, a note);
    /// the others are written as lines that fit the panel.
    fn may_wrap(self, shown: &Shown) -> bool {
        match self {
            Line::Title => true,
            Line::Edit => shown.state.message.is_some(),
            Line::Numbers => {
                shown.status.error.is_some() || shown.status.verdict == Some(crate::statics::Verdict::Unsupported)
            }
            _ => false,
        }
    }
}

#[derive(Component)]
struct Legend;

/// The caption over the design's view: what it shows.
#[derive(Component)]
struct ViewCaption;

#[derive(Component)]
struct Label;

const KEYS: &str = "left click select · right drag orbit\n\
shift+right / middle drag pan · wheel zoom\n\
1 2 3 diagram · T translucent · M centres\n\
I blocks by density (infill)\n\
V point forces · L labels · F frame\n\
C cut selected · PgUp/PgDn move cut\n\
arrows turn cut · Backspace drop cut\n\
O repair · G support · X remove · R restore\n\
Ctrl+Z/Y undo/redo · Ctrl+S save\n\
D/E drop · B both · P settle · W shake\n\
Q sequence · , . step\n\
K mechanism · J kinematic · Esc close";

const TEXT: Color = Color::srgb(0.9, 0.9, 0.9);
const BUTTON: Color = Color::srgb(0.22, 0.22, 0.24);
const BUTTON_ON: Color = Color::srgb(0.16, 0.42, 0.62);

/// The buttons under the legend, a row each: views, checks, edits.
const ACTION_ROWS: [&[(&str, ViewerAction)]; 3] = [
    &[
        ("T Translucent", ViewerAction::ToggleTranslucent),
        ("M Centres", ViewerAction::ToggleMassCentres),
        ("I Density", ViewerAction::ToggleDensity),
        ("V Points", ViewerAction::ToggleVertexArrows),
        ("L Labels", ViewerAction::ToggleLabels),
    ],
    &[
        ("D Drop (rapier)", ViewerAction::DropTest(Engine::Rapier)),
        ("E Drop (exact)", ViewerAction::DropTest(Engine::Exact)),
        ("B Both", ViewerAction::CompareEngines),
        ("P Settle", ViewerAction::Settle),
        ("K Mechanism", ViewerAction::ToggleMechanism),
        ("J Kinematic", ViewerAction::ToggleKinematic),
        ("Q Sequence", ViewerAction::StartSequence),
        ("<", ViewerAction::Step(-1)),
        (">", ViewerAction::Step(1)),
        ("Esc", ViewerAction::ResetDrop),
    ],
    &[
        ("C Cut", ViewerAction::AddCut),
        ("O Repair", ViewerAction::Repair),
        ("G Support", ViewerAction::ToggleSupport),
        ("X Remove", ViewerAction::RemoveBlock),
        ("R Restore", ViewerAction::RestoreBlock),
        ("Undo", ViewerAction::Undo),
        ("Redo", ViewerAction::Redo),
        ("Save", ViewerAction::Save),
        ("H Keys", ViewerAction::ToggleKeys),
    ],
];

fn font(size: f32) -> TextFont {
    TextFont { font_size: FontSize::Px(size), ..default() }
}

fn button(label: &str, action: ViewerAction) -> impl Bundle {
    (
        Button,
        HudButton(action),
        Node { padding: UiRect::axes(px(5), px(2)), margin: UiRect::all(px(1)), ..default() },
        BackgroundColor(BUTTON),
        children![(Text::new(label), font(11.0), TextColor(TEXT))],
    )
}

fn row() -> Node {
    Node { flex_direction: FlexDirection::Row, flex_wrap: FlexWrap::Wrap, ..default() }
}

fn spawn_panel(mut commands: Commands) {
    commands.spawn((
        Text::new(""),
        font(11.0),
        TextColor(Color::srgb(0.92, 0.92, 0.92)),
        BackgroundColor(Color::srgba(0.0, 0.0, 0.0, 0.55)),
        Node {
            position_type: PositionType::Absolute,
            left: px(PANEL_WIDTH + 6.0),
            top: px(6),
            padding: UiRect::all(px(4)),
            ..default()
        },
        ViewCaption,
    ));
    let text = |line: Line, size: f32, colour: Color| (Text::new(""), font(size), TextColor(colour), line);
    let friction = DiagramMode::Friction { threshold: DiagramMode::DEFAULT_THRESHOLD };
    commands
        .spawn((
            Node {
                width: px(PANEL_WIDTH),
                height: percent(100),
                flex_direction: FlexDirection::Column,
                padding: UiRect::all(px(8)),
                row_gap: px(4),
                overflow: Overflow::clip(),
                ..default()
            },
            BackgroundColor(Color::srgb(0.07, 0.07, 0.08)),
        ))
        .with_children(|p| {
            p.spawn(text(Line::Title, 13.0, TEXT));
            p.spawn(text(Line::Headline, 22.0, TEXT));
            p.spawn(text(Line::Numbers, 12.0, TEXT));
            p.spawn(text(Line::Checks, 12.0, TEXT));
            p.spawn((
                row(),
                children![
                    button("1 Compression", ViewerAction::SetMode(DiagramMode::Compression)),
                    button("2 Friction", ViewerAction::SetMode(friction)),
                    button("3 Vectors", ViewerAction::SetMode(DiagramMode::Vectors)),
                ],
            ));
            p.spawn((Node { flex_direction: FlexDirection::Column, row_gap: px(1), ..default() }, Legend));
            for buttons in ACTION_ROWS {
                p.spawn(row()).with_children(|r| {
                    for (label, action) in buttons {
                        r.spawn(button(label, action.clone()));
                    }
                });
            }
            p.spawn(text(Line::Edit, 12.0, TEXT));
            p.spawn(text(Line::Keys, 10.0, Color::srgb(0.65, 0.65, 0.65)));
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

/// Whether the toggle or mode a button stands for is on.
fn is_on(action: &ViewerAction, state: &ViewerState) -> bool {
    use ViewerAction as A;
    match action {
        A::SetMode(m) => std::mem::discriminant(m) == std::mem::discriminant(&state.mode),
        A::ToggleTranslucent => state.translucent,
        A::ToggleMassCentres => state.mass_centres,
        A::ToggleDensity => state.density,
        A::ToggleVertexArrows => state.vertex_arrows,
        A::ToggleLabels => state.labels,
        A::ToggleMechanism => state.overlay == Overlay::Mechanism,
        A::ToggleKinematic => state.overlay == Overlay::Kinematic,
        A::DropTest(engine) => state.drop_view && state.drop_engine == Some(*engine),
        A::CompareEngines => state.drop_view && state.drop_engine.is_none(),
        A::Settle => state.settle_view,
        A::Shake => state.shake_view,
        A::StartSequence => state.sequence_view,
        A::ToggleKeys => state.keys,
        _ => false,
    }
}

/// Buttons of toggles and modes that are on are drawn highlighted.
fn style_buttons(state: Res<ViewerState>, mut buttons: Query<(&HudButton, &mut BackgroundColor)>) {
    for (button, mut background) in &mut buttons {
        let want = if is_on(&button.0, &state) { BUTTON_ON } else { BUTTON };
        if background.0 != want {
            background.0 = want;
        }
    }
}

/// What the viewer shows: its own state and the ECS's results.
#[derive(SystemParam)]
pub(super) struct Shown<'w> {
    pub state: Res<'w, ViewerState>,
    pub status: Res<'w, SceneStatus>,
    pub pipeline: Res<'w, PipelineState>,
    pub drop: Res<'w, DropStatus>,
    pub settle: Res<'w, SettleStatus>,
    pub shake: Res<'w, ShakeStatus>,
    pub sequence: Res<'w, SequenceStatus>,
    pub robustness: Res<'w, RobustnessStatus>,
    pub kinematic: Res<'w, KinematicStatus>,
}

impl Shown<'_> {
    fn text(&self, line: Line) -> String {
        match line {
            Line::Title => self.title(),
            Line::Headline => self.headline().text,
            Line::Numbers => self.numbers(),
            Line::Checks => self.checks(),
            Line::Edit => text::edit_text(&self.state),
            Line::Keys if self.state.keys => KEYS.into(),
            Line::Keys => String::new(),
        }
    }
}

type PanelText<'a> = (&'a Line, &'a mut Text, &'a mut TextColor, &'a mut TextFont, &'a mut Node);

fn write_texts(shown: Shown, mut texts: Query<PanelText>) {
    for (line, mut text, mut colour, mut font, mut node) in &mut texts {
        let value = shown.text(*line);
        if *line == Line::Headline {
            let h = shown.headline();
            let c = Color::srgb(h.colour[0], h.colour[1], h.colour[2]);
            // Two or three verdicts in a smaller size, so that each stays on one line.
            let size = FontSize::Px(if h.disagrees { 16.0 } else { 22.0 });
            if colour.0 != c {
                colour.0 = c;
            }
            if font.font_size != size {
                font.font_size = size;
            }
        }
        // An empty section takes no room.
        let display = if value.is_empty() { Display::None } else { Display::Flex };
        if node.display != display {
            node.display = display;
        }
        if text.0 != value {
            text.0 = value;
        }
    }
}

/// Where every section of the panel's text is on screen (physical pixels) and whether a line
/// that should fit was wrapped: what the scripted report records.
#[derive(SystemParam)]
pub(super) struct PanelLayout<'w, 's> {
    texts: Query<
        'w,
        's,
        (&'static Line, &'static Text, &'static ComputedNode, &'static UiGlobalTransform, &'static TextLayoutInfo),
    >,
}

impl PanelLayout<'_, '_> {
    /// One entry per shown section: its text, its rectangle, its visual and logical line
    /// counts, whether it may wrap.
    pub fn describe(&self, shown: &Shown) -> Vec<Value> {
        let mut out: Vec<(Line, Value)> = self
            .texts
            .iter()
            .filter(|(_, text, ..)| !text.0.is_empty())
            .map(|(line, text, node, at, layout)| {
                let (c, half) = (at.translation, node.size / 2.0);
                let visual = layout.glyphs.iter().map(|g| g.line_index + 1).max().unwrap_or(0);
                let section = json!({
                    "section": format!("{line:?}"),
                    "text": text.0,
                    "rect": [c.x - half.x, c.y - half.y, c.x + half.x, c.y + half.y],
                    "lines": text.0.lines().count(),
                    "visual_lines": visual,
                    "may_wrap": line.may_wrap(shown),
                });
                (*line, section)
            })
            .collect();
        out.sort_by_key(|(line, _)| *line as u8);
        out.into_iter().map(|(_, v)| v).collect()
    }
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
    let mut rows: Vec<(Color, String)> =
        crate::viz::legend(state.mode).into_iter().map(|(c, l)| (Color::linear_rgb(c[0], c[1], c[2]), l)).collect();
    if state.mode == DiagramMode::Vectors {
        rows.push((Color::srgb(0.1, 0.8, 0.25), "resultant force (length ∝ |F|)".into()));
    }
    commands.entity(panel).with_children(|p| {
        for (c, label) in rows {
            p.spawn((
                Node { column_gap: px(6), align_items: AlignItems::Center, ..row() },
                children![
                    (Node { width: px(18), height: px(11), ..default() }, BackgroundColor(c)),
                    (Text::new(label), font(11.0), TextColor(Color::srgb(0.85, 0.85, 0.85))),
                ],
            ));
        }
    });
}

/// What the design's view shows: the diagram (and the sequence step, when one is shown),
/// wrapped within the view.
fn view_caption(
    shown: Shown,
    view: Query<&Camera, With<MainCamera>>,
    window: Query<&Window, With<bevy::window::PrimaryWindow>>,
    mut caption: Query<(&mut Text, &mut Node), With<ViewCaption>>,
) {
    let Ok((mut text, mut node)) = caption.single_mut() else { return };
    let words = shown.view_caption();
    if text.0 != words {
        text.0 = words;
    }
    let scale = window.single().map_or(1.0, |w| w.scale_factor());
    if let Some(r) = view.single().ok().and_then(|c| c.physical_viewport_rect()) {
        let width = px(r.width() as f32 / scale - 12.0);
        if node.max_width != width {
            node.max_width = width;
        }
    }
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
        commands.spawn((
            Text::new(crate::report::words::force(r.normal_force)),
            font(11.0),
            TextColor(Color::WHITE),
            Node { position_type: PositionType::Absolute, left: px(xy.x), top: px(xy.y), ..default() },
            Label,
        ));
    }
}
