//! Invariant: the headless app (MinimalPlugins + VoussoirPlugins) gives the core's results,
//! applies edits as messages, recomputes only what an edit touches, and is deterministic.

use crate::common::*;
use bevy::prelude::*;
use voussoir::ecs::*;
use voussoir::model::edit::{Edit, SettingsEdit};
use voussoir::model::{Cut, Scene, builtin};
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::statics::FrictionModel;

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, VoussoirPlugins));
    app
}

fn send(app: &mut App, edit: Edit) {
    app.world_mut().write_message(EditDesign(edit));
    app.update();
}

fn status(app: &App) -> SceneStatus {
    app.world().resource::<SceneStatus>().clone()
}

fn counters(app: &App) -> Counters {
    *app.world().resource::<Counters>()
}

fn block_names(app: &mut App) -> Vec<String> {
    let mut q = app.world_mut().query::<&BlockName>();
    let mut v: Vec<String> = q.iter(app.world()).map(|n| n.0.clone()).collect();
    v.sort();
    v
}

fn forces(app: &mut App) -> Vec<voussoir::statics::InterfaceResult> {
    let mut q = app.world_mut().query::<&InterfaceForces>();
    let mut v: Vec<_> = q.iter(app.world()).map(|f| f.0.clone()).collect();
    v.sort_by_key(|r| r.index);
    v
}

#[test]
fn loaded_scene_has_the_cores_verdict_and_forces() {
    let scene = builtin("arch?n=9&t=0.15").unwrap();
    let core = analyze(&scene, &AnalysisSettings::default()).unwrap();
    let mut app = app();
    send(&mut app, Edit::Load(Box::new(scene)));
    let s = status(&app);
    assert_eq!(s.verdict, Some(core.statics.verdict));
    assert_eq!(s.tension_ratio, core.statics.tension_ratio);
    assert_eq!(block_names(&mut app).len(), core.assembly.blocks.len());
    assert_eq!(forces(&mut app), core.statics.interfaces, "bitwise the core's forces");
    // Supports carry the marker; interfaces link entities.
    let mut q = app.world_mut().query_filtered::<&BlockName, With<Support>>();
    assert_eq!(q.iter(app.world()).count(), core.assembly.blocks.iter().filter(|b| b.support).count());
    let mut q = app.world_mut().query::<&InterfaceOf>();
    assert_eq!(q.iter(app.world()).count(), core.interfaces.len());
}

/// Two separate beams on the ground: cutting one must not re-solve the other.
fn two_beams() -> Scene {
    let mut s = Scene::new(
        "beams",
        vec![cuboid("left", [0.0, 0.0, 0.0], [4.0, 1.0, 1.0]), cuboid("right", [10.0, 0.0, 0.0], [14.0, 1.0, 1.0])],
    );
    s.ground = true;
    s
}

#[test]
fn cut_edits_recompute_only_what_they_touch() {
    let mut app = app();
    send(&mut app, Edit::Load(Box::new(two_beams())));
    assert_eq!(counters(&app).components_resolved, 2);
    // Cut the left beam: two new pieces; only the left component is solved again.
    let cut = Cut::plane([2.0, 0.0, 0.0], [1.0, 0.0, 0.2]).on("left");
    send(&mut app, Edit::AddCut(cut));
    assert_eq!(block_names(&mut app), ["left.0+", "left.0-", "right"]);
    let w = status(&app).work;
    // The two left pieces touch: one component, solved; the right beam's reused, and its
    // ground pair too (3 new pairs: the pieces' joint and their two ground contacts).
    assert_eq!((w.pieces_cut, w.components_solved, w.components_reused), (1, 1, 1), "{w:?}");
    assert_eq!((w.pairs_detected, w.pairs_reused), (3, 1), "{w:?}");
    // Move the cut: one split again (the right beam is no target), the right beam reused.
    let moved = Cut::plane([2.5, 0.0, 0.0], [1.0, 0.0, 0.2]).on("left");
    send(&mut app, Edit::MoveCut { index: 0, cut: moved });
    let w = status(&app).work;
    assert_eq!((w.pieces_cut, w.components_solved, w.components_reused), (1, 1, 1), "{w:?}");
    // The results equal a fresh core analysis of the same design.
    let design = app.world().resource::<Design>().0.clone().unwrap();
    let core = analyze(&design, &AnalysisSettings::default()).unwrap();
    assert_eq!(forces(&mut app), core.statics.interfaces);
    // An update without requests does nothing.
    let before = counters(&app);
    app.update();
    assert_eq!(counters(&app), before);
}

#[test]
fn support_removal_and_friction_change_the_verdict() {
    // Slope of 30°: stands for μ = 0.7 > tan 30°, slides for μ = 0.5.
    let mut app = app();
    send(&mut app, Edit::Load(Box::new(builtin("slope?angle=30").unwrap())));
    send(&mut app, Edit::SetFriction(0.7));
    assert!(status(&app).stands);
    send(&mut app, Edit::SetFriction(0.5));
    let s = status(&app);
    assert!(!s.stands && s.friction_excess_ratio > 0.0, "{s:?}");
    // A bad μ is an error message, the design unchanged.
    send(&mut app, Edit::SetFriction(-1.0));
    assert!(status(&app).error.as_deref().is_some_and(|e| e.contains("-1")));

    // A stack: removing the bottom block leaves the top one hanging (unsupported); making the
    // top a support makes everything stand again.
    let mut app = self::app();
    send(&mut app, Edit::Load(Box::new(builtin("stack?n=3").unwrap())));
    assert!(status(&app).stands);
    let names = block_names(&mut app);
    send(&mut app, Edit::RemoveBlock(names[1].clone()));
    assert!(!status(&app).stands);
    assert_eq!(block_names(&mut app).len(), names.len() - 1);
    send(&mut app, Edit::RestoreBlock(names[1].clone()));
    assert!(status(&app).stands);
    send(&mut app, Edit::ToggleSupport(names[2].clone()));
    let mut q = app.world_mut().query_filtered::<&BlockName, With<Support>>();
    assert!(q.iter(app.world()).any(|n| n.0 == names[2]));
    // Friction model as a settings request.
    app.world_mut().write_message(EditSettings(SettingsEdit::SetFrictionModel(FrictionModel::Cone)));
    app.update();
    assert!(status(&app).stands);
}

#[test]
fn fixed_number_of_updates_is_deterministic() {
    let run = || {
        let mut app = app();
        send(&mut app, Edit::Load(Box::new(builtin("arch?n=7").unwrap())));
        send(&mut app, Edit::AddCut(Cut::plane([0.0, 0.0, 0.3], [0.0, 0.0, 1.0])));
        for _ in 0..5 {
            app.update();
        }
        (block_names(&mut app), forces(&mut app), status(&app).verdict)
    };
    assert_eq!(run(), run());
}

/// A stack of two boxes and a loose box 0.5 m above the ground, in an app ticking 1/64 s per
/// update.
fn loose_box_app() -> App {
    use std::time::Duration;
    let mut scene = Scene::new(
        "stack and a loose box",
        vec![
            cuboid("bottom", [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
            cuboid("top", [0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
            cuboid("loose", [3.0, 0.0, 1.5], [4.0, 1.0, 2.5]),
        ],
    );
    scene.ground = true;
    let mut app = app();
    // One fixed tick (1/64 s) per update, whatever the wall clock does.
    app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(1.0 / 64.0)));
    send(&mut app, Edit::Load(Box::new(scene)));
    assert!(!status(&app).stands, "statics: the loose box touches nothing");
    app
}

/// Updates until every lane of the drop test finished (at most `ticks`).
fn run_drop(app: &mut App, ticks: usize) {
    for _ in 0..ticks {
        app.update();
        if app.world().resource::<DropStatus>().done() {
            return;
        }
    }
    panic!("the drop test did not finish within {ticks} ticks of 1/64 s");
}

/// Invariant: the loose box falls 1.5 m onto the ground and rests with its centroid at half its
/// height (0.5 m); the stack stays where it was; the verdict (falls, at the loose box) agrees
/// with the statics'.
fn assert_landed(poses: &std::collections::HashMap<String, BlockPose>, tolerance: f64) {
    assert!((poses["loose"].centroid.z - 0.5).abs() < tolerance, "{:?}", poses["loose"]);
    assert!((poses["top"].centroid.z - 1.5).abs() < 0.005, "{:?}", poses["top"]);
    assert!((poses["bottom"].centroid - nalgebra::Point3::new(0.5, 0.5, 0.5)).norm() < 0.005);
}

#[test]
fn drop_test_plugin_moves_a_falling_block_and_leaves_a_stack() {
    use voussoir::dynamics::DropSettings;
    let mut app = loose_box_app();
    app.world_mut().write_message(RunDropTest(DropSettings { duration: 1.0, ..Default::default() }));
    run_drop(&mut app, 100);
    let drop = app.world().resource::<DropStatus>();
    assert_eq!(drop.lanes.len(), 1);
    let lane = drop.lead().unwrap();
    let result = lane.result.clone().unwrap();
    assert!(!result.stands && result.worst_block.as_deref() == Some("loose"));
    assert_eq!(lane.agree, Some(true));
    let mut q = app.world_mut().query::<(&BlockName, &BlockPose)>();
    let poses = q.iter(app.world()).map(|(n, p)| (n.0.clone(), *p)).collect();
    assert_landed(&poses, 0.02);
}

/// Invariant: both engines run side by side on the same design, rapier's lane first and the
/// exact engine's second, each writing its own poses: the loose box lands on the ground in
/// both (rapier within its soft contacts' 2 cm, the exact engine within 1 mm), and both
/// verdicts agree with the statics.
#[test]
fn drop_test_plugin_compares_the_engines_side_by_side() {
    use voussoir::dynamics::{DropSettings, Engine};
    use voussoir::ecs::{CompareDropTests, ComparedPose};
    let mut app = loose_box_app();
    app.world_mut().write_message(CompareDropTests(DropSettings { duration: 1.0, ..Default::default() }));
    run_drop(&mut app, 100);
    let drop = app.world().resource::<DropStatus>();
    assert!(drop.compared());
    let engines: Vec<Engine> = drop.lanes.iter().map(|l| l.engine()).collect();
    assert_eq!(engines, [Engine::Rapier, Engine::Exact]);
    for lane in &drop.lanes {
        let result = lane.result.as_ref().unwrap();
        assert!(!result.stands && result.worst_block.as_deref() == Some("loose"), "{result:?}");
        assert_eq!(lane.agree, Some(true));
    }
    let mut q = app.world_mut().query::<(&BlockName, &BlockPose, &ComparedPose)>();
    let both: Vec<(String, BlockPose, BlockPose)> =
        q.iter(app.world()).map(|(n, p, c)| (n.0.clone(), *p, c.0)).collect();
    assert_eq!(both.len(), 3, "every block has a pose in both lanes");
    assert_landed(&both.iter().map(|(n, p, _)| (n.clone(), *p)).collect(), 0.02);
    assert_landed(&both.iter().map(|(n, _, c)| (n.clone(), *c)).collect(), 1e-3);
}

#[test]
fn sequence_plugin_steps_through_an_order() {
    use voussoir::studies::sequence::OrderSpec;
    let mut app = app();
    send(&mut app, Edit::Load(Box::new(builtin("arch?n=5&t=0.15").unwrap())));
    app.world_mut().write_message(StartSequence(OrderSpec::BottomUp));
    app.update();
    let placed = |app: &mut App| {
        let mut q = app.world_mut().query_filtered::<&BlockName, With<Placed>>();
        q.iter(app.world()).count()
    };
    let status = app.world().resource::<SequenceStatus>();
    assert_eq!(status.current, 0);
    let first = status.step().unwrap().clone();
    assert!(!first.stands, "one voussoir on a springer tips");
    assert_eq!(placed(&mut app), 1);
    for _ in 0..10 {
        app.world_mut().write_message(StepSequence(1));
        app.update();
    }
    let status = app.world().resource::<SequenceStatus>();
    assert_eq!(status.current, 4, "clamped at the last step");
    assert!(status.step().unwrap().stands, "the closed arch stands");
    let a = status.analysis.as_ref().expect("the step's analysis");
    assert_eq!(a.assembly.blocks.len(), 7, "five voussoirs and two springers");
    assert!(a.statics.stands && a.statics.solver.residual < 1e-9 * a.statics.free_weight);
    assert_eq!(placed(&mut app), 5);
    app.world_mut().write_message(StepSequence(-2));
    app.update();
    assert_eq!(placed(&mut app), 3);
    // The step shown is analysed on its own: its blocks and its verdict, forces included.
    let status = app.world().resource::<SequenceStatus>();
    let a = status.analysis.as_ref().expect("the step's analysis");
    assert_eq!(a.assembly.blocks.len(), 3 + 2);
    assert_eq!(a.statics.stands, status.step().unwrap().stands);
    assert!(a.statics.interfaces.iter().any(|r| !r.vertices.is_empty()));
}

#[test]
fn sequence_settings_add_the_drop_test_of_every_step() {
    use voussoir::dynamics::DropSettings;
    use voussoir::ecs::SequenceSettings;
    use voussoir::studies::sequence::OrderSpec;
    let mut app = app();
    let dynamic = Some(DropSettings { duration: 0.5, ..Default::default() });
    app.insert_resource(SequenceSettings(voussoir::studies::sequence::StepChecks { dynamic, ..Default::default() }));
    send(&mut app, Edit::Load(Box::new(builtin("stack?n=3").unwrap())));
    app.world_mut().write_message(StartSequence(OrderSpec::BottomUp));
    app.update();
    let status = app.world().resource::<SequenceStatus>();
    let report = status.report.as_ref().unwrap();
    assert_eq!(report.steps.len(), 3);
    for step in &report.steps {
        let drop = step.dynamic.as_ref().expect("a drop test per step");
        assert!(step.stands && drop.stands, "a plain stack stands at every step: {step:?}");
    }
}

#[test]
fn interfaces_are_coloured_by_the_diagram_mode() {
    use voussoir::viz::{DiagramMode, colors};
    let mut app = app();
    send(&mut app, Edit::Load(Box::new(builtin("slope?angle=35&b=2&h=0.5").unwrap())));
    let colours = |app: &mut App| -> Vec<(voussoir::statics::InterfaceResult, Vec<[f32; 3]>)> {
        let mut q = app.world_mut().query::<(&InterfaceForces, &InterfaceColors)>();
        q.iter(app.world()).map(|(f, c)| (f.0.clone(), c.0.clone())).collect()
    };
    let before = colours(&mut app);
    assert_eq!(before.len(), 1);
    // Compression: every force point carries compression on a standing slope: blue.
    assert!(before[0].1.iter().all(|c| c[2] > c[0] + 0.2), "{:?}", before[0].1);
    app.world_mut().write_message(SetDiagram(DiagramMode::Friction { threshold: 0.5 }));
    app.update();
    let after = colours(&mut app);
    let mu = 40f64.to_radians().tan();
    // One colour per interface: its resultant's use tan 35° / tan 40° = 0.83, orange.
    for (r, cs) in &after {
        assert_eq!(cs.len(), r.vertices.len());
        let expected = 35f64.to_radians().tan() / mu;
        assert!((r.friction_utilization - expected).abs() < 1e-6, "{} vs {expected}", r.friction_utilization);
        assert!(cs.iter().all(|c| *c == colors::FrictionBand::High(r.friction_utilization).colour(0.5)), "{cs:?}");
    }
    assert_ne!(before[0].1, after[0].1, "the mode switch recoloured the interface");
}

/// Invariant: with a robustness request the app holds the core's load factor and writes the
/// mechanism on the block and interface entities; after an edit of one component only that
/// component's load factor is solved again.
#[test]
fn the_load_factor_follows_edits_component_by_component() {
    use voussoir::model::Load;
    // Two separate blocks b × b × h on their own bases, 3 m apart: two components.
    let pillar = |name: &str, x: f64, h: f64| {
        vec![
            cuboid(&format!("{name}-base"), [x - 1.0, -1.0, -1.0], [x + 1.5, 1.5, 0.0]).support(true),
            cuboid(name, [x, 0.0, 0.0], [x + 0.5, 0.5, h]),
        ]
    };
    let mut blocks = pillar("left", 0.0, 1.0);
    blocks.extend(pillar("right", 4.0, 2.0));
    let mut scene = Scene::new("pillars", blocks);
    scene.loads.push(Load::horizontal(0.0, 1.0));
    let mut app = app();
    app.insert_resource(RobustnessRequest::LiveLoads);
    send(&mut app, Edit::Load(Box::new(scene.clone())));
    let r = app.world().resource::<RobustnessStatus>().clone();
    // The taller pillar tips first: λ* = b/h = 0.25.
    assert_close(r.load_factor(), 0.25, 1e-6, "the ECS load factor");
    assert_eq!((r.solved, r.reused), (2, 0));
    let mut q = app.world_mut().query::<(&BlockName, &MechanismMotion)>();
    let moving: Vec<String> = q.iter(app.world()).map(|(n, _)| n.0.clone()).collect();
    assert_eq!(moving, vec!["right".to_string()]);
    let mut q = app.world_mut().query::<&JointMotion>();
    assert!(q.iter(app.world()).any(|j| j.0 == voussoir::stability::JointState::Hinging));

    // Shorten the left pillar's neighbour: a new block on the left base touches only the left
    // component's base (a support): the right component is reused.
    send(&mut app, Edit::AddBlock(cuboid("cap", [-0.9, 1.0, 0.0], [-0.4, 1.4, 0.3])));
    let r = app.world().resource::<RobustnessStatus>().clone();
    assert_close(r.load_factor(), 0.25, 1e-6, "unchanged");
    assert_eq!(r.reused, 2, "both old components reused; {} solved (the new block)", r.solved);
    assert_eq!(r.solved, 1);
}

/// Invariant: the kinematic plugin gives the core's check of the design on screen. The letter
/// H of compas_cra (a bar between two posts, held only by a squeeze nothing produces): RBE
/// stands, the kinematic check fails with the bar falling at g — the same verdicts and
/// mechanism as `kinematic::check`; a new design (a thick arch) is checked again, and both
/// stand; switched off, the status is empty.
#[test]
fn kinematic_plugin_reports_both_verdicts_and_the_mechanism() {
    use voussoir::stability::kinematic::{self, KinematicVerdict};
    let mut scene = voussoir::io::load_scene(&compas_data("compas_cra/H.json")).unwrap();
    assert_eq!(scene.mark_lowest_as_supports(1e-3), 2, "the two posts");
    scene.material.friction = 0.84;
    let settings = AnalysisSettings::default();
    let core = kinematic::check(&analyze(&scene, &settings).unwrap(), &settings.statics, &Default::default()).unwrap();

    let mut app = app();
    app.insert_resource(KinematicRequest::On(Default::default()));
    send(&mut app, Edit::Load(Box::new(scene)));
    let k = app.world().resource::<KinematicStatus>().result.clone().expect("checked after the analysis");
    assert_eq!((k.verdict, k.statics_stands, k.agrees), (KinematicVerdict::Fails, true, false));
    assert_eq!(k.verdict, core.verdict);
    let (m, c) = (k.mechanism.expect("a mechanism"), core.mechanism.expect("the core's mechanism"));
    assert_eq!(m.blocks.len(), 1, "only the bar moves");
    assert_eq!(m.blocks[0].block, c.blocks[0].block);
    assert_close(m.blocks[0].translation[2], -9.81, 1e-6 * 9.81, "the bar falls at g");

    send(&mut app, Edit::Load(Box::new(builtin("arch?n=9&t=0.15").unwrap())));
    let k = app.world().resource::<KinematicStatus>().result.clone().expect("checked again after the edit");
    assert_eq!((k.verdict, k.agrees), (KinematicVerdict::Stands, true), "a thick arch");
    assert!(k.mechanism.is_none());

    app.insert_resource(KinematicRequest::Off);
    app.update();
    assert!(app.world().resource::<KinematicStatus>().result.is_none());
}

/// Invariants (the repair plugin on the paper's Fig 4a, whose cut needs tension): the design
/// stays as it is while the search runs off the main thread; then the changed cut moves into
/// place over ANIMATION_FRAMES updates, each a run of the pipeline, its point moving
/// monotonically from the old place to the new one; at the end the design's cuts are the
/// report's and the app's verdict is the core's on that design: it stands.
#[test]
fn repair_plugin_moves_the_cut_into_place() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases/fig4a_m_cut.json");
    let scene = voussoir::io::load_scene(&path).unwrap();
    let mut app = app();
    send(&mut app, Edit::Load(Box::new(scene.clone())));
    assert!(!status(&app).stands);
    app.world_mut().write_message(RunRepair(Default::default()));
    let cut_point = |app: &App| match &app.world().resource::<Design>().0.as_ref().unwrap().cuts[0].shape {
        voussoir::model::CutShape::Plane { point, .. } => *point,
        voussoir::model::CutShape::Pattern { .. } => panic!("fig4a's cut is a plane"),
    };
    let mut updates = 0;
    let mut points = vec![cut_point(&app)];
    let generation = |app: &App| app.world().resource::<PipelineState>().generation;
    let runs_before = generation(&app);
    while app.world().resource::<RepairStatus>().finished == 0 {
        // A bound on updates, not a timing: the search runs on another thread meanwhile.
        updates += 1;
        assert!(updates < 30_000, "the repair did not finish");
        let searching = app.world().resource::<RepairStatus>().running();
        app.update();
        if searching {
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        let p = cut_point(&app);
        if p != *points.last().unwrap() {
            points.push(p);
        }
    }
    let repair_status = app.world().resource::<RepairStatus>();
    assert_eq!(repair_status.error, None);
    let report = repair_status.report.clone().unwrap();
    assert_eq!(report.changed.len(), 1);
    assert_eq!(points.len(), ANIMATION_FRAMES as usize + 1, "one position per frame: {points:?}");
    // Every frame is analysed (a frame whose plane would cut a sliver is reported, not drawn).
    assert_eq!(generation(&app) - runs_before, ANIMATION_FRAMES as u64, "one analysis per frame");
    for axis in 0..3 {
        let rising = points.last().unwrap()[axis] >= points[0][axis];
        assert!(
            points.windows(2).all(|w| if rising { w[1][axis] >= w[0][axis] } else { w[1][axis] <= w[0][axis] }),
            "axis {axis} not monotone: {points:?}"
        );
    }
    let design = app.world().resource::<Design>().0.clone().unwrap();
    assert_eq!(design.cuts, report.design.cuts);
    let core = analyze(&report.design, &AnalysisSettings::default()).unwrap();
    assert!(core.statics.stands && status(&app).stands);
}

/// The lintel on two piers ([`lintel`]), the right one settling 0.1 m.
fn settling_lintel() -> Scene {
    let mut scene = lintel();
    scene.movements =
        vec![voussoir::model::Movement { block: "right".into(), translation: [0.0, 0.0, -0.1], rotation: [0.0; 3] }];
    scene
}

/// Updates (real time passing for the analysis' thread) until the settlement has a result or
/// an error.
fn run_settlement(app: &mut App) {
    for _ in 0..6000 {
        app.update();
        let s = app.world().resource::<SettleStatus>();
        if s.result.is_some() || s.error.is_some() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    panic!("the settlement did not finish within a minute");
}

/// Invariant: the plugin's settlement is the library's on the same design and settings (same
/// input, same output: outcome and stages equal), and its playback ends on the run's last
/// frame: the settling pier 0.1 m down (1e-12), the lintel turned by the last stage's
/// rotation; a design that moves no support gets one clear error.
#[test]
fn settle_plugin_follows_the_design_s_movements_and_plays_them() {
    use voussoir::studies::settlement::{SettleSettings, settle};
    let settings = SettleSettings { engines: false, increments: 10, ..Default::default() };
    let mut app = app();
    // A quarter second per update: the 5 s playback in 20 updates.
    app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(std::time::Duration::from_secs_f64(0.25)));
    let scene = settling_lintel();
    send(&mut app, Edit::Load(Box::new(scene.clone())));
    app.world_mut().write_message(RunSettlement(settings.clone()));
    run_settlement(&mut app);
    let analysis = analyze(&scene, &Settings::default().0).unwrap();
    let direct = settle(&analysis, &scene.movements, &settings).unwrap();
    {
        let status = app.world().resource::<SettleStatus>();
        let got = status.result.as_ref().expect("a settlement");
        assert_eq!(got.quasi_static.outcome, direct.quasi_static.outcome);
        assert_eq!(got.quasi_static.stages, direct.quasi_static.stages);
    }
    for _ in 0..(PLAY_SECONDS / 0.25).ceil() as usize + 1 {
        app.update();
    }
    assert!(app.world().resource::<SettleStatus>().played());
    let mut q = app.world_mut().query::<(&BlockName, &SettlePose)>();
    let poses: std::collections::HashMap<String, BlockPose> =
        q.iter(app.world()).map(|(n, p)| (n.0.clone(), p.0)).collect();
    assert!((poses["right"].centroid - nalgebra::Point3::new(3.0, 0.5, -0.6)).norm() < 1e-12, "{:?}", poses["right"]);
    let turn = 2.0 * poses["lintel"].rotation[0].clamp(-1.0, 1.0).acos().to_degrees();
    let last = direct.quasi_static.stages.last().unwrap().rotation;
    assert!((turn - last).abs() < 1e-9, "{turn} vs {last}");

    let mut still = settling_lintel();
    still.movements.clear();
    send(&mut app, Edit::Load(Box::new(still)));
    app.world_mut().write_message(RunSettlement(settings));
    app.update();
    let error = app.world().resource::<SettleStatus>().error.clone().expect("an error");
    assert!(error.contains("moves no support"), "{error}");
}

/// Invariant: the plugin's shake is the library's on the same design, motion and settings (the
/// same input, the same output: λ* and each run's result bar the wall time), and its playback
/// ends on the run's last frame — the arch's voussoirs where the library's run left them — with
/// the ground's acceleration read from the trace at the clock; a request with no engine gets
/// one clear error.
#[test]
fn shake_plugin_shakes_the_design_and_plays_it() {
    use voussoir::dynamics::{Engine, Excitation, GroundMotion, PulseShape};
    use voussoir::studies::shake::{ShakeSettings, shake_study};
    let scene = builtin("arch?n=9&t=0.15").unwrap();
    let g = scene.gravity.norm();
    let motion = GroundMotion::horizontal(
        Excitation::Pulse { shape: PulseShape::Rectangular, amplitude: 0.6 * g, duration: 0.3 },
        0.0,
    );
    let settings = ShakeSettings { duration: Some(1.0), ..Default::default() };
    let mut app = app();
    app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(std::time::Duration::from_secs_f64(0.1)));
    send(&mut app, Edit::Load(Box::new(scene.clone())));
    let request = RunShake { motion: motion.clone(), settings: settings.clone(), engines: vec![Engine::Exact] };
    app.world_mut().write_message(request);
    for _ in 0..6000 {
        app.update();
        let s = app.world().resource::<ShakeStatus>();
        if s.result.is_some() || s.error.is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let analysis = analyze(&scene, &Settings::default().0).unwrap();
    let direct =
        shake_study(&analysis, &Settings::default().0.statics, &motion, &settings, &[Engine::Exact], None).unwrap();
    let last = {
        let status = app.world().resource::<ShakeStatus>();
        let got = status.result.as_ref().expect("a shake");
        assert_eq!(got.static_load_factor, direct.static_load_factor);
        let (mut a, mut b) = (got.runs[0].result.clone(), direct.runs[0].result.clone());
        (a.wall_s, b.wall_s) = (0.0, 0.0);
        assert_eq!(a, b);
        assert!(got.runs[0].collapsed, "0.6 g for 0.3 s brings the arch (λ* ≈ 0.15) down");
        got.runs[0].frames.as_ref().unwrap().poses.last().unwrap().clone()
    };
    for _ in 0..12 {
        app.update();
    }
    let status = app.world().resource::<ShakeStatus>();
    assert!(status.played());
    assert_eq!(status.ground_now(), Some(0.0), "the pulse is over at the end");
    let names: Vec<String> = analysis.assembly.blocks.iter().map(|b| b.name.clone()).collect();
    let mut q = app.world_mut().query::<(&BlockName, &ShakePose)>();
    let poses: std::collections::HashMap<String, BlockPose> =
        q.iter(app.world()).map(|(n, p)| (n.0.clone(), p.0)).collect();
    for (name, (centroid, _)) in names.iter().zip(&last) {
        if let Some(p) = poses.get(name) {
            assert_eq!(p.centroid, *centroid, "{name}");
        }
    }
    assert!(!poses.is_empty());
    app.world_mut().write_message(RunShake { motion, settings, engines: vec![] });
    app.update();
    let error = app.world().resource::<ShakeStatus>().error.clone().expect("an error");
    assert!(error.contains("no engine"), "{error}");
}
