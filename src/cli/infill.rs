//! `voussoir infill DESIGN -o OUT.json`: per-block densities within bounds that make the design
//! stand — the lightest ([`InfillObjective::Stand`]) or those carrying the largest horizontal
//! load (`--objective robust`) — written into the design by piece name
//! ([`synthesis::infill`](mod@crate::synthesis::infill)). When no density within the bounds holds it, says so and
//! prints the mechanism every admissible mass drives. Exit codes: 0 the infilled design
//! stands, 1 no density holds it (or a solver failed), 2 bad input.

use super::options::SolverOptions;
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::io::scene_json;
use crate::statics::Verdict;
use crate::synthesis::{self, InfillObjective, InfillOutcome, InfillReport, InfillSettings};
use crate::viz::DiagramMode;
use crate::viz::plot::diagram::{DiagramPicture, write_diagram};
use clap::Args;
use std::path::PathBuf;

/// The options of `voussoir infill`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct InfillArgs {
    /// The design: a scene file (with or without a cut history), or `builtin:…`.
    pub scene: String,
    /// The solver options the design is analysed with.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// Every free block's density bounds, kg/m³ (e.g. `150,600`); default: from a quarter of
    /// each block's density to its density.
    #[arg(long, value_name = "LO,HI", value_parser = density_range)]
    pub density_range: Option<(f64, f64)>,
    /// `stand`: the lightest densities that stand; `robust`: those that carry the largest
    /// horizontal load (the scene's live loads when it has some).
    #[arg(long, value_enum, default_value = "stand")]
    pub objective: Objective,
    /// Cells per axis of each block's box, each with its own density (2: octants, which move
    /// the block's centroid); 1: one density per block.
    #[arg(long, default_value_t = InfillSettings::default().cells)]
    pub cells: usize,
    /// Robust: the one horizontal direction to carry, degrees from +x towards +y; default:
    /// every one of `--directions` evenly spaced azimuths.
    #[arg(long)]
    pub azimuth: Option<f64>,
    /// Robust: evenly spaced horizontal azimuths the design must carry together.
    #[arg(long, default_value_t = InfillSettings::default().directions)]
    pub directions: usize,
    /// The infilled design (scene JSON with `densities`, written atomically).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write the JSON report here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Picture of the infilled design (.png or .svg): blocks coloured by density (when they
    /// differ), interfaces by compression.
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// What `--objective` asks for.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Objective {
    /// The lightest densities that stand.
    Stand,
    /// The densities that carry the largest horizontal load.
    Robust,
}

/// Runs `infill`: writes the infilled design; exit code 0 when it stands, 1 when impossible.
pub fn run(args: &InfillArgs) -> Result<i32, BadInput> {
    for out in std::iter::once(&args.output).chain(&args.json).chain(&args.plot) {
        refuse_overwrite(Some(&args.scene), out, "output")?;
    }
    let name = scene_name(Some(&args.scene)).to_string();
    let scene = load(Some(&args.scene))?;
    let settings = InfillSettings {
        range: args.density_range,
        objective: match args.objective {
            Objective::Stand => InfillObjective::Stand,
            Objective::Robust => InfillObjective::Robust,
        },
        cells: args.cells,
        azimuth: args.azimuth,
        directions: args.directions,
        ..Default::default()
    };
    let report =
        synthesis::infill(&scene, &args.solver.settings(), &settings).map_err(|e| BadInput(format!("{name}: {e}")))?;
    print!("{}", text(&report));
    if let Some(design) = &report.design {
        write_output(&args.output, scene_json::scene_to_string(design).as_bytes())?;
        println!("design written to {}", args.output.display());
    }
    if let (Some(out), Some(after)) = (&args.plot, &report.analysis) {
        let picture = DiagramPicture::new(after, DiagramMode::Compression);
        write_diagram(&picture, out).map_err(|e| BadInput(format!("{}: {e}", out.display())))?;
        println!("picture written to {}", out.display());
    }
    if let Some(out) = &args.json {
        let json = serde_json::to_string_pretty(&report).expect("a report serialises");
        write_output(out, json.as_bytes())?;
        println!("report written to {}", out.display());
    }
    let stands = report.outcome == InfillOutcome::Stands && report.verdict_after == Some(Verdict::Stands);
    Ok(if stands { 0 } else { 1 })
}

/// Blocks listed in the text (all of them in the JSON report and the design).
const SHOWN: usize = 12;

/// The headline, the densities that changed and the mass.
pub fn text(r: &InfillReport) -> String {
    let mut s = match &r.outcome {
        InfillOutcome::Stands => {
            format!("INFILLED: {} with these densities\n", r.verdict_after.map_or("not analysed", |v| v.words()))
        }
        InfillOutcome::Impossible => "IMPOSSIBLE: no density within the bounds makes it stand\n".to_string(),
        InfillOutcome::SolverFailed { status, residual } => {
            format!("UNRESOLVED: the solver stopped ({status:?}, residual {residual:.3e} N)\n")
        }
    };
    s += &format!("  verdict before: {}\n", r.verdict_before.words());
    if let Some(l) = r.load_factor {
        s += &format!("  carries λ = {l:.4} g horizontally (in each direction asked)\n");
    }
    s += &format!("  mass of the free blocks: {:.4} kg → {:.4} kg\n", r.mass_before, r.mass_after);
    let changed: Vec<_> = r.blocks.iter().filter(|b| (b.after - b.before).abs() > 1e-9 * b.before).collect();
    for b in changed.iter().take(SHOWN) {
        s += &format!("  {:<24} {:>10.2} → {:>10.2} kg/m³  [{:.0}, {:.0}]", b.block, b.before, b.after, b.lo, b.hi);
        if !b.cells.is_empty() {
            let cells: Vec<String> = b.cells.iter().map(|c| format!("{c:.0}")).collect();
            s += &format!("  cells {}", cells.join(" "));
        }
        s += "\n";
    }
    if changed.len() > SHOWN {
        s += &format!("  … {} more changed (all in the JSON report)\n", changed.len() - SHOWN);
    }
    if let Some(m) = &r.mechanism {
        s +=
            &format!("  the mechanism every admissible mass drives (least work {:.3e} of the weight):\n", r.least_work);
        for b in m.blocks.iter().take(SHOWN) {
            let t = b.translation;
            let w = b.rotation;
            s += &format!(
                "    {:<22} moves ({:+.3e}, {:+.3e}, {:+.3e}) m, turns ({:+.3e}, {:+.3e}, {:+.3e}) rad\n",
                b.block, t[0], t[1], t[2], w[0], w[1], w[2]
            );
        }
    }
    s += &format!("  {} density problems in {:.2} s\n", r.solves, r.seconds);
    s
}

/// `LO,HI` as two numbers (their bounds are checked with the other settings).
fn density_range(text: &str) -> Result<(f64, f64), String> {
    text.split_once(',')
        .and_then(|(lo, hi)| Some((lo.trim().parse::<f64>().ok()?, hi.trim().parse::<f64>().ok()?)))
        .ok_or_else(|| format!("expected LO,HI in kg/m³, e.g. 150,600 (got {text:?})"))
}
