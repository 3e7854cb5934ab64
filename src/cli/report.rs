//! `voussoir report`: one self-contained HTML file ([`crate::viz::html`]) of the analysed
//! design — its diagrams in 3D, the verdict and the graded numbers — with, on request, the load
//! factor's collapse mechanism (`--robustness`), the drop test (`--dynamic`) and the settlement
//! on moving supports (`--settle`) played beside it. Exit codes as `analyze`: 0 it stands by
//! every check that ran, 1 it does not, 2 bad input.

use super::options::{DiagramOptions, DropOptions, LoadOptions, SceneOptions, SolverOptions};
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::model::Movement;
use crate::pipeline::analyze;
use crate::stability::{self, Question};
use crate::studies::settlement::{Outcome, SettleSettings, settle};
use crate::viz::html::HtmlReport;
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
    /// quasi-static run played in the motion pane, the thrust plot under it (`settle` runs the
    /// engines beside it).
    #[arg(long)]
    pub settle: bool,
    /// With `--settle`: a support's whole path, `NAME:dx,dy,dz[:rx,ry,rz]` (as `settle --move`).
    #[arg(long = "move", value_name = "NAME:DX,DY,DZ[:RX,RY,RZ]", requires = "settle")]
    pub moves: Vec<String>,
}

/// Runs `report`: analyses, runs what was asked, writes the page; prints one line.
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
        let question = Question::choose(&analysis, args.direction, args.directions);
        let answer = stability::answer(&analysis, &settings.statics, &question, &|_, _| {})
            .map_err(|e| BadInput(format!("{name}: --robustness: {e}")))?;
        page.add_mechanism(&answer).map_err(|e| BadInput(format!("{name}: --robustness: {e}")))?;
    }
    if args.dynamic {
        let drop = args.drop.settings(args.solver.mu, args.solver.friction_model, args.solver.solver);
        let (d, motion) = crate::dynamics::record(&analysis.assembly, &drop, crate::viz::gltf::FRAMES_PER_SECOND)
            .map_err(|e| BadInput(format!("{name}: --dynamic: {e}")))?;
        stands &= d.stands;
        page.add_drop(&d, &motion, &drop);
    }
    if args.settle {
        let result = settle(&analysis, &scene.movements, &settle_settings(args))
            .map_err(|e| BadInput(format!("{name}: --settle: {e}")))?;
        stands &= matches!(result.quasi_static.outcome, Outcome::Stands);
        page.add_settlement(&result).map_err(|e| BadInput(format!("{name}: --settle: {e}")))?;
    }
    let html = page.html();
    write_output(&args.out, html.as_bytes())?;
    let parts: Vec<&str> = page.motions.iter().map(|m| m.title.as_str()).collect();
    println!(
        "{name}: report written to {} ({} KB; {}{})",
        args.out.display(),
        html.len() / 1024,
        analysis.statics.verdict.words(),
        if parts.is_empty() { String::new() } else { format!("; {}", parts.join(", ")) }
    );
    for m in &page.motions {
        println!("  {}", m.caption);
    }
    Ok(if stands { 0 } else { 1 })
}

/// The settlement's settings: the quasi-static run only (the engines' runs are `settle`'s).
fn settle_settings(args: &ReportArgs) -> SettleSettings {
    SettleSettings {
        friction: args.solver.mu,
        strength: args.solver.strength,
        engines: false,
        backend: args.solver.solver,
        ..Default::default()
    }
}
