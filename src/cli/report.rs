//! `voussoir report`: one self-contained HTML file ([`crate::report::html`]) of the analysed
//! design — its diagrams in 3D, the verdict and the graded numbers — with, on request, the load
//! factor's collapse mechanism (`--robustness`), the drop test (`--dynamic`) and the settlement
//! on moving supports (`--settle`) played beside it. Exit codes as `analyze`: 0 it stands by
//! every check that ran, 1 it does not, 2 bad input.

use super::options::{DiagramOptions, DropOptions, LoadOptions, SceneOptions, SolverOptions};
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::model::{Movement, Scene};
use crate::pipeline::{Analysis, analyze};
use crate::report::html::{HtmlReport, MotionPane, Plot};
use crate::report::{self, text as text_report};
use crate::stability::{self, Question};
use crate::studies::settlement::{Outcome, SettleSettings, settle};
use crate::viz::plot::{ThrustPlot, svg_string};
use clap::Args;
use std::path::PathBuf;

/// The options of `voussoir report`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct ReportArgs {
    /// Scene file or `builtin:NAME?k=v&...`. Default: the embedded default scene.
    pub scene: Option<String>,
    /// Write the report here (.html, atomically; never over the input).
    #[arg(short = 'o', long = "out", value_name = "REPORT.html")]
    pub out: PathBuf,
    /// The diagram shown first (the page switches between all three).
    #[command(flatten)]
    pub diagram: DiagramOptions,
    /// The solver's friction model, μ, backend and interface tolerances.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// Point loads and acceleration fields added to the scene's.
    #[command(flatten)]
    pub loads: LoadOptions,
    /// Supports, ground and density given on the command line.
    #[command(flatten)]
    pub scene_options: SceneOptions,
    /// Add the load factor λ* and its collapse mechanism, played in the motion pane (the
    /// question `robustness` asks: the live loads, `--direction`, or the worst direction).
    #[arg(long)]
    pub robustness: bool,
    /// With `--robustness`: a horizontal 1 g along this azimuth (degrees from +x towards +y).
    #[arg(long, requires = "robustness", conflicts_with = "directions")]
    pub direction: Option<f64>,
    /// With `--robustness`: the worst horizontal direction over this many azimuths.
    #[arg(long, value_name = "N", requires = "robustness")]
    pub directions: Option<usize>,
    /// Add the drop test (`--engine`), played in the motion pane.
    #[arg(long)]
    pub dynamic: bool,
    /// The drop test's engine, duration and time step.
    #[command(flatten)]
    pub drop: DropOptions,
    /// Add the settlement on the supports' movements (`--move`, else the scene's): the
    /// quasi-static run played in the motion pane, the thrust plot under it.
    #[arg(long)]
    pub settle: bool,
    /// With `--settle`: a support's whole path, NAME:dx,dy,dz[:rx,ry,rz] (as `settle --move`).
    #[arg(long = "move", value_name = "NAME:DX,DY,DZ[:RX,RY,RZ]", requires = "settle")]
    pub moves: Vec<String>,
}

/// Seconds a mechanism plays in, and the settlement's whole path (as `settle --frames`).
const MECHANISM_SECONDS: f64 = 3.0;
const PATH_SECONDS: f64 = 5.0;
/// The drop test's frames per simulated second (as `analyze --frames`).
const FRAMES_PER_SECOND: f64 = 30.0;

/// Runs `report`: analyses, runs what was asked, writes the page; prints one line per part.
pub fn run(args: &ReportArgs) -> Result<i32, BadInput> {
    refuse_overwrite(args.scene.as_deref(), &args.out, "--out")?;
    let mode = args.diagram.mode()?;
    let name = scene_name(args.scene.as_deref()).to_string();
    let mut scene = load(args.scene.as_deref())?;
    let settings = args.solver.settings();
    args.scene_options.apply(&mut scene, &settings)?;
    scene.loads.extend(args.loads.loads()?);
    if !args.moves.is_empty() {
        scene.movements = args.moves.iter().map(|m| Movement::parse(m)).collect::<Result<_, _>>().map_err(BadInput)?;
    }
    let analysis = analyze(&scene, &settings).map_err(|e| BadInput(format!("{name}: {e}")))?;
    let mut page = HtmlReport::new(&analysis, mode);
    let mut stands = analysis.statics.stands;
    if args.robustness {
        add_mechanism(args, &analysis, &mut page)?;
    }
    let dynamic = if args.dynamic { Some(add_drop(args, &analysis, &mut page)?) } else { None };
    if let Some(d) = &dynamic {
        stands &= d.stands;
        let extras = report::json::Extras { dynamic: Some(d), ..Default::default() };
        page.json = report::json::to_json_with(&analysis, &extras);
    }
    if args.settle {
        stands &= add_settlement(args, &scene, &analysis, &mut page)?;
    }
    let html = page.html();
    write_output(&args.out, html.as_bytes())?;
    println!(
        "{name}: report written to {} ({} KB; {}{})",
        args.out.display(),
        html.len() / 1024,
        analysis.statics.verdict.words(),
        if page.motions.is_empty() {
            String::new()
        } else {
            format!("; {}", page.motions.iter().map(|m| m.title.as_str()).collect::<Vec<_>>().join(", "))
        }
    );
    Ok(if stands { 0 } else { 1 })
}

/// The load factor and its mechanism: the panel's robustness text, the mechanism's motion.
fn add_mechanism(args: &ReportArgs, analysis: &Analysis, page: &mut HtmlReport) -> Result<(), BadInput> {
    let statics = args.solver.settings().statics;
    let question = Question::choose(analysis, args.direction, args.directions);
    let answer = stability::answer(analysis, &statics, &question, &|_, _| {})
        .map_err(|e| BadInput(format!("--robustness: {e}")))?;
    page.text.push('\n');
    page.text.push_str(&text_report::robustness(analysis, &answer.result, answer.sweep.as_ref(), &answer.load));
    let Some(mechanism) = &answer.result.mechanism else { return Ok(()) };
    let Some(glb) = crate::viz::gltf::mechanism_glb(&analysis.assembly, mechanism, MECHANISM_SECONDS) else {
        return Ok(());
    };
    let moved = (0..analysis.assembly.blocks.len()).filter(|&b| mechanism.motion[b] != [0.0; 6]).collect::<Vec<_>>();
    let caption = format!(
        "collapse mechanism under {}: λ* = {:.4}; {} moving block(s), drawn with the largest motion {:.0} % of the model size",
        answer.load,
        answer.result.load_factor,
        moved.len(),
        100.0 * crate::viz::EXAGGERATION
    );
    page.motions.push(MotionPane { title: "mechanism".into(), caption, glb, moved });
    Ok(())
}

/// The drop test: its side-by-side text and its recorded motion.
fn add_drop(
    args: &ReportArgs,
    analysis: &Analysis,
    page: &mut HtmlReport,
) -> Result<crate::dynamics::DropResult, BadInput> {
    let settings = args.drop.settings(args.solver.mu, args.solver.friction_model, args.solver.solver);
    let (d, motion) = crate::dynamics::record(&analysis.assembly, &settings, FRAMES_PER_SECOND)
        .map_err(|e| BadInput(e.to_string()))?;
    page.text.push('\n');
    page.text.push_str(&text_report::side_by_side(analysis, &d));
    let caption = format!(
        "drop test ({}): {} s at dt {} s — {}",
        motion.engine,
        settings.duration,
        settings.dt,
        if d.stands { "it stands" } else { "it falls" }
    );
    let moved = moved_blocks(analysis, &motion);
    page.motions.push(MotionPane {
        title: "drop test".into(),
        caption,
        glb: crate::viz::gltf::animation_glb(&analysis.assembly, &motion),
        moved,
    });
    Ok(d)
}

/// The settlement's quasi-static run (the engines beside it in the panel's lines when they
/// ran), its thrust plot; whether it stands to the end of the path.
fn add_settlement(args: &ReportArgs, scene: &Scene, analysis: &Analysis, page: &mut HtmlReport) -> Result<bool, BadInput> {
    let settings = SettleSettings {
        friction: args.solver.mu,
        strength: args.solver.strength,
        engines: false,
        backend: args.solver.solver,
        ..Default::default()
    };
    let result = settle(analysis, &scene.movements, &settings).map_err(|e| BadInput(format!("--settle: {e}")))?;
    let run = &result.quasi_static;
    page.text.push_str(&format!("\nSETTLE: {} moved ({:.4e} m at the end of the path)\n", result.supports.join(", "), result.path_movement));
    page.text.push_str(&super::settle::line(run, 0.0, 0.0));
    page.text.push('\n');
    let mut motion = run.motion.clone();
    motion.times.iter_mut().for_each(|t| *t *= PATH_SECONDS);
    let caption = match run.outcome {
        Outcome::Collapses { fraction, movement, .. } => {
            format!("settlement (quasi-static): collapses at {:.2} % of the path ({movement:.4e} m); the path plays in {PATH_SECONDS} s", 100.0 * fraction)
        }
        Outcome::Stands => format!("settlement (quasi-static): stands to the end of the path; the path plays in {PATH_SECONDS} s"),
        Outcome::Unresolved { fraction, .. } => format!("settlement (quasi-static): solver trouble at {:.2} % of the path", 100.0 * fraction),
    };
    page.motions.push(MotionPane {
        title: "settlement".into(),
        caption,
        glb: crate::viz::gltf::animation_glb(&analysis.assembly, &motion),
        moved: moved_blocks(analysis, &motion),
    });
    let plot = ThrustPlot { title: format!("{}: reaction against support movement", analysis.assembly.name), settlement: &result };
    let svg = svg_string(&plot, ThrustPlot::SIZE).map_err(|e| BadInput(format!("--settle: the thrust plot: {e}")))?;
    page.plots.push(Plot { title: "the horizontal reaction on the first moved support against its movement".into(), svg });
    Ok(matches!(run.outcome, Outcome::Stands))
}

/// The free blocks whose centroid moves in `motion` by more than a thousandth of the model size.
fn moved_blocks(analysis: &Analysis, motion: &crate::dynamics::Trajectory) -> Vec<usize> {
    let Some(first) = motion.poses.first() else { return Vec::new() };
    let still = 1e-3 * analysis.assembly.scale;
    let moves = |b: usize| motion.poses.iter().any(|f| (f[b].0 - first[b].0).norm() > still);
    (0..analysis.assembly.blocks.len()).filter(|&b| !analysis.assembly.blocks[b].support && moves(b)).collect()
}
