//! What the viewer can be asked to do ([`ViewerAction`], from keys, buttons or a script) and
//! the one system that does it. Design edits go to the ECS as [`EditDesign`] messages; the
//! viewer keeps a mirror of the design it sent so that undo/redo are whole snapshots and
//! several actions in one frame build on each other.

use super::ViewerOptions;
use crate::dynamics::{DropSettings, Engine};
use crate::ecs::{
    CompareDropTests, Design, DropStatus, EditDesign, KinematicRequest, PipelineState, RepairStatus, RobustnessRequest,
    RunDropTest, RunRepair, RunSettlement, RunShake, SequenceStatus, SetDiagram, SettleStatus, ShakeStatus,
    StartSequence, StepSequence, VoussoirSet,
};
use crate::model::Scene;
use crate::model::cut::{Cut, CutShape};
use crate::model::edit::{Edit, apply};
use crate::studies::sequence::OrderSpec;
use crate::studies::settlement::SettleSettings;
use crate::viz::DiagramMode;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use nalgebra::{Rotation3, Unit, Vector3};
use std::path::PathBuf;

pub struct ActionsPlugin;

impl Plugin for ActionsPlugin {
    fn build(&self, app: &mut App) {
        app.add_message::<ViewerAction>()
            .add_systems(Update, apply_actions.in_set(ActionSystems).before(VoussoirSet::Edit))
            .add_systems(Update, follow_repair.after(VoussoirSet::Edit));
    }
}

/// The system that applies [`ViewerAction`]s (whatever sends them runs before it).
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ActionSystems;

/// Something the user (or a script) asks of the viewer.
#[derive(Message, Clone, Debug, PartialEq)]
pub enum ViewerAction {
    SetMode(DiagramMode),
    ToggleTranslucent,
    ToggleMassCentres,
    /// Colour the blocks by density (an infill design's), or back to stone.
    ToggleDensity,
    ToggleVertexArrows,
    ToggleLabels,
    /// Show or hide the list of keys in the panel.
    ToggleKeys,
    /// Show the collapse mechanism beside the design (the load factor of the live loads, or of
    /// the worst horizontal direction when there are none), or hide it.
    ToggleMechanism,
    /// Run the kinematic check after every analysis (and show its mechanism when the design
    /// fails it), or stop.
    ToggleKinematic,
    /// Select a block by name (`None`: clear).
    Select(Option<String>),
    /// Click where this world point (m) appears in the view: selects the block the ray from
    /// the camera meets first (what a left click does; scripts use it).
    ClickToward([f32; 3]),
    /// Cut the selected block with a plane through its centroid, across its longest extent.
    AddCut,
    /// Move the cut being edited along its normal by this fraction of its block's size.
    ShiftCut(f64),
    /// Turn the cut being edited: `yaw` about z, `tilt` about the horizontal line in the plane
    /// (degrees).
    TurnCut {
        yaw: f64,
        tilt: f64,
    },
    /// Drop the cut being edited from the history.
    DeleteCut,
    /// Move and turn the cuts that made the selected block (every cut when none is selected)
    /// until the design stands most safely; the cuts glide into place when the search ends.
    Repair,
    ToggleSupport,
    RemoveBlock,
    /// Put the most recently removed block back.
    RestoreBlock,
    Undo,
    Redo,
    Save,
    /// Drop-test the design on an engine (D rapier, E exact contacts).
    DropTest(Engine),
    /// Drop-test the design on both engines side by side (B).
    CompareEngines,
    /// Move the design's supports along its `movements` and play the quasi-static motion (P).
    Settle,
    /// Shake the design by its `ground_motion` (else the first 15 s of El Centro 1940) on the
    /// exact engine and play it, the ground's trace and λ* under it (W).
    Shake,
    /// Leave the drop-test view (the static diagram alone again).
    ResetDrop,
    /// Check the design's order (its `order`, else bottom-up) and show its first step.
    StartSequence,
    Step(i64),
    ExitSequence,
    /// Fit the camera to the design.
    Frame,
}

/// The cut being edited: its place in the history and its plane.
#[derive(Clone, Debug, PartialEq)]
pub struct ActiveCut {
    pub index: usize,
    pub target: String,
    pub point: Vector3<f64>,
    pub normal: Vector3<f64>,
    /// The target block's bounding-box diagonal (m): the unit of shifts and the gizmo's size.
    pub size: f64,
}

impl ActiveCut {
    fn cut(&self) -> Cut {
        let shape = CutShape::Plane { point: self.point.into(), normal: self.normal.into() };
        Cut { shape, target: Some(self.target.clone()) }
    }
}

/// The mechanism drawn beside the design: one at a time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Overlay {
    #[default]
    None,
    /// The collapse mechanism of the load factor (live loads, else the worst direction).
    Mechanism,
    /// The kinematic check runs after every analysis; its mechanism when the design fails it.
    Kinematic,
}

/// What the viewer shows and remembers.
#[derive(Resource, Debug)]
pub struct ViewerState {
    pub mode: DiagramMode,
    pub translucent: bool,
    pub mass_centres: bool,
    /// Blocks coloured by density.
    pub density: bool,
    pub vertex_arrows: bool,
    pub labels: bool,
    /// The panel lists the keys.
    pub keys: bool,
    pub selected: Option<String>,
    pub active_cut: Option<ActiveCut>,
    /// The design as the viewer last sent it.
    pub design: Scene,
    pub undo: Vec<Scene>,
    pub redo: Vec<Scene>,
    pub save_path: PathBuf,
    input: Option<PathBuf>,
    save_over_input: bool,
    /// The last note for the user (saved, nothing selected, …).
    pub message: Option<String>,
    pub drop_view: bool,
    /// The engine of the drop test shown; `None` while both are compared.
    pub drop_engine: Option<Engine>,
    pub sequence_view: bool,
    /// The settlement's motion is shown (P).
    pub settle_view: bool,
    /// The shake's motion is shown (W).
    pub shake_view: bool,
    /// The mechanism drawn beside the design, if any.
    pub overlay: Overlay,
    /// Set when the camera should fit the design at the next analysis.
    pub frame_pending: bool,
}

impl ViewerState {
    pub fn new(o: &ViewerOptions) -> Self {
        Self {
            mode: o.mode,
            translucent: o.translucent,
            mass_centres: true,
            density: false,
            vertex_arrows: false,
            labels: false,
            keys: false,
            selected: None,
            active_cut: None,
            design: o.scene.clone(),
            undo: Vec::new(),
            redo: Vec::new(),
            save_path: o.save_path(),
            input: o.input.clone(),
            save_over_input: o.save_over_input,
            message: None,
            drop_view: false,
            drop_engine: Some(Engine::default()),
            sequence_view: false,
            settle_view: false,
            shake_view: false,
            overlay: Overlay::None,
            frame_pending: true,
        }
    }

    /// Applies `edit` to the mirror (with an undo snapshot) and returns it to send, or notes
    /// why it cannot be applied.
    fn edit(&mut self, edit: Edit) -> Option<EditDesign> {
        let before = self.design.clone();
        match apply(&mut self.design, &edit) {
            Ok(()) => {
                self.undo.push(before);
                self.redo.clear();
                Some(EditDesign(edit))
            }
            Err(e) => {
                self.message = Some(e.to_string());
                None
            }
        }
    }

    fn save(&mut self) {
        if self.input.as_ref().is_some_and(|i| crate::io::same_file(i, &self.save_path)) && !self.save_over_input {
            self.message =
                Some(format!("not saved: {} is the input (--save-over-input allows it)", self.save_path.display()));
            return;
        }
        let text = crate::io::scene_json::scene_to_string(&self.design);
        self.message = Some(match crate::io::write_atomic(&self.save_path, text.as_bytes()) {
            Ok(()) => format!("saved {}", self.save_path.display()),
            Err(e) => format!("not saved: {e}"),
        });
    }
}

/// The plane of a new cut through `name`: through its centroid, normal along its longest
/// bounding-box extent (so that it halves the block).
fn new_cut(state: &PipelineState, name: &str, index: usize) -> Option<ActiveCut> {
    let a = state.analysis.as_ref()?;
    let b = a.assembly.blocks.iter().find(|b| b.name == name)?;
    let bb = b.mesh.aabb();
    let extent = bb.max - bb.min;
    let axis = extent.iamax();
    let normal = Vector3::ith(axis, 1.0);
    Some(ActiveCut { index, target: name.to_string(), point: b.mass.centroid.coords, normal, size: bb.diagonal() })
}

fn turned(normal: Vector3<f64>, yaw: f64, tilt: f64) -> Vector3<f64> {
    let n = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw.to_radians()) * normal;
    let side = n.cross(&Vector3::z());
    let axis = if side.norm() < 1e-9 { Vector3::x_axis() } else { Unit::new_normalize(side) };
    (Rotation3::from_axis_angle(&axis, tilt.to_radians()) * n).normalize()
}

/// Everything the actions read and change besides the actions themselves.
#[derive(SystemParam)]
struct Effects<'w> {
    studies: Studies<'w>,
    state: ResMut<'w, ViewerState>,
    pipeline: Res<'w, PipelineState>,
    // What runs after each analysis for the overlay.
    robustness: ResMut<'w, RobustnessRequest>,
    kinematic: ResMut<'w, KinematicRequest>,
    edits: MessageWriter<'w, EditDesign>,
    repairs: MessageWriter<'w, RunRepair>,
    diagram: MessageWriter<'w, SetDiagram>,
}

/// The drop test and the assembly sequence: what starts them and what they show.
#[derive(SystemParam)]
struct Studies<'w> {
    drop: ResMut<'w, DropStatus>,
    drops: MessageWriter<'w, RunDropTest>,
    comparisons: MessageWriter<'w, CompareDropTests>,
    settle: ResMut<'w, SettleStatus>,
    settlements: MessageWriter<'w, RunSettlement>,
    shake: ResMut<'w, ShakeStatus>,
    shakes: MessageWriter<'w, RunShake>,
    sequence: ResMut<'w, SequenceStatus>,
    starts: MessageWriter<'w, StartSequence>,
    steps: MessageWriter<'w, StepSequence>,
}

fn apply_actions(mut actions: MessageReader<ViewerAction>, mut effects: Effects) {
    for action in actions.read() {
        effects.apply(action);
    }
}

impl Effects<'_> {
    fn apply(&mut self, action: &ViewerAction) {
        use ViewerAction as A;
        let s = &mut *self.state;
        match action {
            A::SetMode(m) => {
                s.mode = *m;
                self.diagram.write(SetDiagram(*m));
            }
            A::ToggleTranslucent => s.translucent = !s.translucent,
            A::ToggleMassCentres => s.mass_centres = !s.mass_centres,
            A::ToggleDensity => s.density = !s.density,
            A::ToggleVertexArrows => s.vertex_arrows = !s.vertex_arrows,
            A::ToggleLabels => s.labels = !s.labels,
            A::ToggleKeys => s.keys = !s.keys,
            A::ToggleMechanism => self.toggle_overlay(Overlay::Mechanism),
            A::ToggleKinematic => self.toggle_overlay(Overlay::Kinematic),
            A::Select(name) => s.selected = name.clone(),
            // Done by the picking system (it has the ray caster).
            A::ClickToward(_) => {}
            A::AddCut => self.add_cut(),
            A::ShiftCut(_) | A::TurnCut { .. } => self.move_cut(action),
            A::DeleteCut => self.delete_cut(),
            A::Repair => self.repair(),
            A::ToggleSupport | A::RemoveBlock => self.edit_selected(action == &A::RemoveBlock),
            A::RestoreBlock => self.restore_block(),
            A::Undo => self.travel(true),
            A::Redo => self.travel(false),
            A::Save => s.save(),
            A::DropTest(engine) => {
                s.drop_view = true;
                (s.settle_view, s.shake_view) = (false, false);
                s.drop_engine = Some(*engine);
                self.studies.drops.write(RunDropTest(DropSettings { engine: *engine, ..Default::default() }));
            }
            A::CompareEngines => {
                s.drop_view = true;
                (s.settle_view, s.shake_view) = (false, false);
                s.drop_engine = None;
                self.studies.comparisons.write(CompareDropTests(DropSettings::default()));
            }
            A::Settle => {
                (s.drop_view, s.shake_view) = (false, false);
                s.settle_view = true;
                let settings = SettleSettings { engines: false, ..Default::default() };
                self.studies.settlements.write(RunSettlement(settings));
            }
            A::Shake => self.shake(),
            A::ResetDrop => self.reset_drop(),
            A::StartSequence => self.start_sequence(),
            A::Step(k) => self.step_sequence(*k),
            A::ExitSequence => {
                s.sequence_view = false;
                *self.studies.sequence = SequenceStatus::default();
            }
            A::Frame => s.frame_pending = true,
        }
    }

    /// Shows `overlay` (hiding the other) or hides it, and asks for what it draws.
    fn toggle_overlay(&mut self, overlay: Overlay) {
        let s = &mut *self.state;
        s.overlay = if s.overlay == overlay { Overlay::None } else { overlay };
        let live = s.design.loads.iter().any(|l| l.kind() == crate::model::LoadKind::Live);
        let robustness = match (s.overlay, live) {
            (Overlay::Mechanism, true) => RobustnessRequest::LiveLoads,
            (Overlay::Mechanism, false) => {
                RobustnessRequest::Worst(crate::stability::DirectionSettings::default().directions)
            }
            _ => RobustnessRequest::Off,
        };
        let kinematic = match s.overlay {
            Overlay::Kinematic => KinematicRequest::On(Default::default()),
            _ => KinematicRequest::Off,
        };
        self.robustness.set_if_neq(robustness);
        self.kinematic.set_if_neq(kinematic);
    }

    /// Applies `edit` to the mirror and sends it; false (with a note) when it cannot apply.
    fn send_edit(&mut self, edit: Edit) -> bool {
        let Some(e) = self.state.edit(edit) else { return false };
        self.edits.write(e);
        true
    }

    fn add_cut(&mut self) {
        let Some(name) = self.state.selected.clone() else {
            self.state.message = Some("select a block to cut (click it)".into());
            return;
        };
        let Some(cut) = new_cut(&self.pipeline, &name, self.state.design.cuts.len()) else { return };
        if self.send_edit(Edit::AddCut(cut.cut())) {
            self.state.active_cut = Some(cut);
            self.state.selected = None;
        }
    }

    fn move_cut(&mut self, action: &ViewerAction) {
        let Some(mut cut) = self.state.active_cut.clone() else {
            self.state.message = Some("no cut being edited (C cuts the selected block)".into());
            return;
        };
        match action {
            ViewerAction::ShiftCut(f) => cut.point += cut.normal * (f * cut.size),
            ViewerAction::TurnCut { yaw, tilt } => cut.normal = turned(cut.normal, *yaw, *tilt),
            _ => return,
        }
        if self.send_edit(Edit::MoveCut { index: cut.index, cut: cut.cut() }) {
            self.state.active_cut = Some(cut);
        }
    }

    fn delete_cut(&mut self) {
        if let Some(cut) = self.state.active_cut.take() {
            self.send_edit(Edit::RemoveCut(cut.index));
        }
    }

    /// Sends a repair of the selected block's cuts (every cut when none is selected).
    fn repair(&mut self) {
        let s = &mut *self.state;
        let cuts = s
            .selected
            .as_ref()
            .map(|name| (0..s.design.cuts.len()).filter(|&i| crate::history::made_by(name, i)).collect::<Vec<_>>());
        if cuts.as_ref().is_some_and(Vec::is_empty) || s.design.cuts.is_empty() {
            s.message = Some("no cut made this design or block: nothing to move (C cuts the selected block)".into());
            return;
        }
        s.message = Some(match &cuts {
            Some(c) => format!("repairing cuts {c:?} of {}…", s.selected.as_deref().unwrap_or_default()),
            None => format!("repairing all {} cuts…", s.design.cuts.len()),
        });
        s.active_cut = None;
        self.repairs.write(RunRepair(crate::synthesis::RepairSettings { cuts, ..Default::default() }));
    }

    /// Removes the selected block (`remove`) or toggles its support.
    fn edit_selected(&mut self, remove: bool) {
        let Some(name) = self.state.selected.clone() else {
            self.state.message = Some("select a block first (click it)".into());
            return;
        };
        let edit = if remove {
            self.state.selected = None;
            Edit::RemoveBlock(name)
        } else {
            Edit::ToggleSupport(name)
        };
        self.send_edit(edit);
    }

    fn restore_block(&mut self) {
        match self.state.design.removed.last().cloned() {
            Some(name) => {
                self.send_edit(Edit::RestoreBlock(name));
            }
            None => self.state.message = Some("no removed block to restore".into()),
        }
    }

    /// Undo (`back`) or redo: swaps in a whole snapshot of the design.
    fn travel(&mut self, back: bool) {
        let s = &mut *self.state;
        let (from, to) = if back { (&mut s.undo, &mut s.redo) } else { (&mut s.redo, &mut s.undo) };
        let Some(scene) = from.pop() else {
            s.message = Some("nothing to undo or redo".into());
            return;
        };
        to.push(std::mem::replace(&mut s.design, scene.clone()));
        // A snapshot may predate the cut being edited: stop editing it.
        s.active_cut = None;
        self.edits.write(EditDesign(Edit::Load(Box::new(scene))));
    }

    fn reset_drop(&mut self) {
        self.state.drop_view = false;
        self.studies.drop.clear();
        self.state.settle_view = false;
        self.studies.settle.clear();
        self.state.shake_view = false;
        self.studies.shake.clear();
    }

    /// Shakes the design on the exact engine by its own ground motion, else by El Centro's
    /// first 15 s (the strong part), and shows it.
    fn shake(&mut self) {
        use crate::io::accelerogram::{NamedMotion, named_motion};
        let s = &mut *self.state;
        let scene_file = s.input.clone().unwrap_or_default();
        let own = s.design.ground_motion.is_some();
        let named = NamedMotion {
            pulse: None,
            sine: None,
            record: (!own).then_some("builtin:elcentro"),
            scale: 1.0,
            direction: 0.0,
            supports: &[],
        };
        let duration = (!own).then_some(15.0);
        match named_motion(&named, &s.design, &scene_file, "") {
            Ok((motion, _)) => {
                (s.drop_view, s.settle_view, s.shake_view) = (false, false, true);
                let settings = crate::studies::shake::ShakeSettings { duration, ..Default::default() };
                let engines = vec![crate::dynamics::Engine::Exact];
                self.studies.shakes.write(RunShake { motion, settings, engines });
            }
            Err(e) => s.message = Some(format!("shake: {e}")),
        }
    }

    /// Checks the design's order (its `order`, else bottom-up).
    fn start_sequence(&mut self) {
        let s = &mut *self.state;
        let spec =
            if s.design.order.is_empty() { OrderSpec::BottomUp } else { OrderSpec::Given(s.design.order.clone()) };
        s.sequence_view = true;
        self.studies.starts.write(StartSequence(spec));
    }

    fn step_sequence(&mut self, k: i64) {
        if !self.state.sequence_view {
            self.state.message = Some("no sequence shown (Q checks the assembly order)".into());
            return;
        }
        self.studies.steps.write(StepSequence(k));
    }
}

/// Adopts a repaired design once its cuts are in place (one undo step back to the design as it
/// was), and says how the repair went.
fn follow_repair(
    repair: Res<RepairStatus>,
    design: Res<Design>,
    mut state: ResMut<ViewerState>,
    mut seen: Local<(u64, Option<String>)>,
) {
    if repair.error != seen.1 {
        seen.1 = repair.error.clone();
        if let Some(e) = &repair.error {
            state.message = Some(format!("repair: {e}"));
        }
    }
    if repair.finished == seen.0 {
        return;
    }
    seen.0 = repair.finished;
    let (Some(report), Some(after)) = (&repair.report, &design.0) else { return };
    if !report.changed.is_empty() {
        let before = std::mem::replace(&mut state.design, after.clone());
        state.undo.push(before);
        state.redo.clear();
    }
    state.message = Some(repair_summary(report));
}

/// Three short lines: the outcome; the verdicts and load factors before and after; the cuts
/// moved and the search's cost.
fn repair_summary(r: &crate::synthesis::RepairReport) -> String {
    use crate::synthesis::RepairOutcome;
    let verdict = |s: &crate::synthesis::Score| s.verdict.map_or("cannot be cut", crate::statics::Verdict::words);
    let lambda = |l: Option<f64>| l.map_or("—".into(), |l| format!("{l:.3}"));
    let outcome = match &r.outcome {
        RepairOutcome::Repaired => "repaired: it stands now",
        RepairOutcome::AlreadyStood { improved: true } => "it stood; now more safely",
        RepairOutcome::AlreadyStood { improved: false } => "it stood; no safer placement found",
        RepairOutcome::NotRepaired => "NOT repaired: no placement of\nthese cuts makes it stand",
        RepairOutcome::NothingToMove => "nothing to move",
    };
    let moved = match r.changed.len() {
        1 => "1 cut moved".to_string(),
        n => format!("{n} cuts moved"),
    };
    format!(
        "{outcome}\n  {} → {}\n  λ* {} → {}\n  {moved} · {} evaluations, {:.1} s",
        verdict(&r.before),
        verdict(&r.after),
        lambda(r.load_factor_before),
        lambda(r.load_factor_after),
        r.evaluations,
        r.seconds
    )
}

#[cfg(test)]
mod tests {
    use super::turned;
    use nalgebra::Vector3;

    #[test]
    fn turning_keeps_the_normal_unit_and_turns_by_the_angle() {
        let n = turned(Vector3::x(), 90.0, 0.0);
        assert!((n - Vector3::y()).norm() < 1e-12);
        let n = turned(Vector3::x(), 0.0, 30.0);
        assert!((n.norm() - 1.0).abs() < 1e-12);
        assert!((n.dot(&Vector3::x()) - 30f64.to_radians().cos()).abs() < 1e-12);
        // A horizontal plane (vertical normal) tilts about x.
        let n = turned(Vector3::z(), 0.0, 10.0);
        assert!((n.dot(&Vector3::z()) - 10f64.to_radians().cos()).abs() < 1e-12);
    }
}
