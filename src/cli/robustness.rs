//! `voussoir robustness`: how safely a design stands — the load factor λ* of its live loads
//! (the scene's and `--load`/`--accel`), of a horizontal 1 g along `--direction`, or the worst
//! horizontal direction over `--directions` azimuths (the default when no live load is given);
//! the collapse mechanism; a JSON report, a polar plot and a mechanism picture on request.
//! Exit codes as `analyze`: 0 it stands under its dead load, 1 it does not (or a solver could
//! not tell), 2 bad input.

use super::options::{LoadOptions, SolverOptions};
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::pipeline::analyze;
use crate::report::{stability as robustness_report, text as text_report};
use crate::stability::{self, Answer, Question, Safety};
use crate::viz::plot::{MechanismPicture, PolarPlot, write_mechanism, write_polar};
use clap::Args;
use std::path::PathBuf;

/// The options of `voussoir robustness`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct RobustnessArgs {
    /// Scene file (.json voussoir or compas Assembly, .obj, .stl) or `builtin:NAME?k=v&...`.
    /// Default: the embedded default scene.
    pub scene: Option<String>,
    /// The solver options the design is analysed with.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// Point loads and acceleration fields added to the scene's.
    #[command(flatten)]
    pub loads: LoadOptions,
    /// The live load is a horizontal 1 g acceleration along this azimuth (degrees from +x
    /// towards +y), in place of the scene's live loads.
    #[arg(long, conflicts_with = "directions")]
    pub direction: Option<f64>,
    /// Find the worst horizontal direction over this many azimuths, refined around the
    /// smallest (what runs when no live load is given, with the default count).
    #[arg(long, value_name = "N")]
    pub directions: Option<usize>,
    /// Write the JSON report here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Polar plot of λ* over the directions (.png or .svg; with a direction sweep).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Picture of the collapse mechanism (.png or .svg).
    #[arg(long)]
    pub mechanism: Option<PathBuf>,
    /// A fabrication tolerance: every joint shrunk by this much (model units) from its edges
    /// before the load factor — λ* of the design as it may be built (`analyze --tolerance`
    /// gives the largest shrink it survives).
    #[arg(long, value_name = "LENGTH")]
    pub chip: Option<f64>,
}

/// Runs `robustness`: prints λ* and the mechanism; exit code 0 when it stands under its dead load.
pub fn run(args: &RobustnessArgs) -> Result<i32, BadInput> {
    for out in [&args.json, &args.plot, &args.mechanism].into_iter().flatten() {
        refuse_overwrite(args.scene.as_deref(), out, "output")?;
    }
    let name = scene_name(args.scene.as_deref()).to_string();
    let mut scene = load(args.scene.as_deref())?;
    scene.loads.extend(args.loads.loads()?);
    let settings = args.solver.settings();
    let mut analysis = analyze(&scene, &settings).map_err(|e| BadInput(format!("{name}: {e}")))?;
    if let Some(delta) = args.chip {
        analysis = crate::stability::tolerance::chipped(&analysis, delta, &settings.statics)
            .map_err(|e| BadInput(format!("{name}: --chip: {e}")))?;
        println!("every joint shrunk by {delta} from its edges (--chip): {}", analysis.statics.verdict.words());
    }
    let question = Question::choose(&analysis, args.direction, args.directions);
    if args.plot.is_some() && !matches!(question, Question::Worst(_)) {
        return Err(BadInput("--plot draws a direction sweep: give --directions N (or no live load)".into()));
    }
    let directions = match &question {
        Question::Worst(s) => s.directions,
        _ => 0,
    };
    let Answer { result, sweep: swept, load } =
        with_progress(directions, |progress| stability::answer(&analysis, &settings.statics, &question, progress))
            .map_err(|e| BadInput(format!("{name}: {e}")))?;
    print!("{}", text_report::robustness(&analysis, &result, swept.as_ref(), &load));
    if let Some(out) = &args.json {
        let json = robustness_report::to_json(&analysis, &result, swept.as_ref(), &load);
        write_output(out, json.as_bytes())?;
        println!("report written to {}", out.display());
    }
    if let (Some(out), Some(s)) = (&args.plot, &swept) {
        let plot = PolarPlot { title: analysis.assembly.name.clone(), sweep: s, size: (900, 900) };
        write_polar(&plot, out).map_err(|e| BadInput(e.to_string()))?;
        println!("polar plot written to {}", out.display());
    }
    if let Some(out) = &args.mechanism {
        write_mechanism(&MechanismPicture::new(&analysis, &result, load.clone()), out)
            .map_err(|e| BadInput(e.to_string()))?;
        println!("mechanism picture written to {}", out.display());
    }
    Ok(match result.safety {
        Safety::Collapses { .. } | Safety::Unlimited => 0,
        Safety::DoesNotStand { .. } | Safety::SolverFailed { .. } => 1,
    })
}

/// Runs `f` with a progress callback: a bar over `total` steps ([`super::LateBar`]).
fn with_progress<T>(total: usize, f: impl FnOnce(&(dyn Fn(usize, usize) + Sync)) -> T) -> T {
    let bar = super::LateBar::new(None);
    bar.update(0, total, None);
    f(&|done: usize, _total: usize| bar.update(done, total, None))
}
