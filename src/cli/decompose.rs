//! `voussoir decompose SHAPE (--blocks N | --max-size L) [--strategy courses|thrust|pattern
//! --apex x,y,z] -o OUT.json`: a running bond extruded to an apex with `pattern`
//! ([`synthesis::pattern`](mod@crate::synthesis::pattern)), or
//! a cut history for a source shape by courses ([`crate::synthesis::generate`]) — horizontal
//! beds, or beds through an axis with `--center`/`--axis` (arches, vaults) — with staggered
//! head joints, the beds turned normal to the thrust with `--strategy thrust`
//! ([`synthesis::thrust`](mod@crate::synthesis::thrust)); prints the design's verdict and with `--optimize` repairs it
//! ([`synthesis::repair`](mod@crate::synthesis::repair)). Writes the
//! design atomically, never over the input. Exit codes: 0 it stands, 1 it does not, 2 bad input.

use super::choice::Choice;
use super::options::SolverOptions;
use super::{BadInput, load, numbers, refuse_overwrite, scene_name, write_output};
use crate::io::scene_json;
use crate::model::Scene;
use crate::pipeline::AnalysisSettings;
use crate::pipeline::analyze;
use crate::statics::Verdict;
use crate::synthesis::{self, BlockSize, DesignError, Field, Generated, RepairSettings, ThrustSettings};
use clap::Args;
use clap::ValueEnum;
use std::path::PathBuf;

/// The options of `voussoir decompose`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct DecomposeArgs {
    /// The source shape (any scene or mesh file the readers accept, without a cut history).
    pub scene: String,
    /// The solver options the coursed design is analysed with.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// About this many blocks (along the arc for `--center`).
    #[arg(long, required_unless_present = "max_size", conflicts_with = "max_size")]
    pub blocks: Option<usize>,
    /// Largest block dimension along the cut directions, m.
    #[arg(long)]
    pub max_size: Option<f64>,
    /// Courses through an axis (arches, barrel vaults): a point `x,y,z` on it. Without it the
    /// load path is found: horizontal beds, or when those do not stand, radial beds about the
    /// axis the shape's curved faces turn about (an arch's centre).
    #[arg(long, allow_hyphen_values = true)]
    pub center: Option<String>,
    /// The axis' direction `x,y,z` (with `--center`).
    #[arg(long, allow_hyphen_values = true, default_value = "0,1,0", requires = "center")]
    pub axis: String,
    /// How the beds are placed: `courses` across the field, or `thrust`: turned normal to the
    /// force an analysis finds crossing them (arches, vaults, buttresses); or `pattern`: a
    /// running bond on the outer surface extruded to `--apex` (shells, the seed's Fig 9).
    #[arg(long, value_enum, value_parser = Choice::<Strategy>::new(), default_value_t = Strategy::Courses)]
    pub strategy: Strategy,
    /// The apex every joint of `--strategy pattern` passes through, `x,y,z` (outside the shape,
    /// on the side away from the surface the pattern is drawn on).
    #[arg(long, allow_hyphen_values = true, required_if_eq("strategy", "pattern"))]
    pub apex: Option<String>,
    /// Head joints in line between courses (stack bond) instead of staggered.
    #[arg(long)]
    pub no_stagger: bool,
    /// Then move and turn the cuts until it stands most safely (`voussoir repair`).
    #[arg(long)]
    pub optimize: bool,
    /// Seed of the optimiser.
    #[arg(long, default_value_t = RepairSettings::default().seed)]
    pub seed: u64,
    /// The design (scene JSON with its cut history, written atomically).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// A generation strategy ([`crate::synthesis::generate`], [`synthesis::thrust`](mod@crate::synthesis::thrust)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Strategy {
    /// Bed joints across the load path, head joints staggered.
    Courses,
    /// The courses' beds turned normal to the thrust crossing them.
    Thrust,
    /// A running bond on the surface, every joint a plane through `--apex`.
    Pattern,
}

/// Runs `decompose`: writes the coursed design; exit code 0 when it stands, 1 when not.
pub fn run(args: &DecomposeArgs) -> Result<i32, BadInput> {
    refuse_overwrite(Some(&args.scene), &args.output, "-o")?;
    let name = scene_name(Some(&args.scene)).to_string();
    let shape = load(Some(&args.scene))?;
    let size = match (args.blocks, args.max_size) {
        (Some(n), _) => BlockSize::Count(n),
        (None, Some(l)) => BlockSize::Max(l),
        (None, None) => return Err(BadInput("give --blocks N or --max-size L".into())),
    };
    let bad = |e: synthesis::DesignError| BadInput(format!("{name}: {e}"));
    let settings = args.solver.settings();
    let (generated, found_field) = generate(args, &shape, &size, &settings)?.map_err(bad)?;
    println!(
        "{} courses, {} pieces (block size {:.4} m), {} cuts",
        generated.courses,
        generated.pieces,
        generated.max_size,
        generated.design.cuts.len()
    );
    if let Some(found) = &found_field {
        println!("load path: {}", describe(found));
    }
    if let Some(r) = &generated.rounds {
        println!(
            "beds normal to the thrust after {} analyses ({}; last turn {:.3}°), at most {:.2}° from the field's{}",
            r.rounds,
            if r.settled { "settled" } else { "NOT settled" },
            r.last_turn_degrees,
            r.largest_turn_degrees,
            if r.held > 0 { format!(", {} held at the largest turn", r.held) } else { String::new() }
        );
    }
    let (design, verdict, tension, excess) = if args.optimize {
        let repair = RepairSettings { seed: args.seed, ..Default::default() };
        let report = synthesis::repair(&generated.design, &settings, &repair, &|_, _, _| {}).map_err(bad)?;
        print!("{}", super::repair::text(&report));
        let after = &report.after;
        (report.design.clone(), after.verdict, after.tension_ratio, after.friction_excess_ratio)
    } else {
        let a = analyze(&generated.design, &settings).map_err(|e| BadInput(format!("{name}: {e}")))?;
        let s = &a.statics;
        (generated.design, Some(s.verdict), s.tension_ratio, s.friction_excess_ratio)
    };
    let stands = verdict == Some(Verdict::Stands);
    println!(
        "{} (minimum tension {tension:.3e} W, friction excess {excess:.3e} W)",
        verdict.map_or("DOES NOT STAND: the design cannot be cut as asked", crate::report::text::headline)
    );
    write_output(&args.output, scene_json::scene_to_string(&design).as_bytes())?;
    println!("design written to {}", args.output.display());
    Ok(if stands { 0 } else { 1 })
}

/// The design by the chosen strategy, and the load path found when `--center` was not given
/// (courses, thrust); the outer error is bad options, the inner the strategy's.
fn generate(
    args: &DecomposeArgs,
    shape: &Scene,
    size: &BlockSize,
    settings: &AnalysisSettings,
) -> Result<Result<(Generated, Option<Field>), DesignError>, BadInput> {
    let given = match &args.center {
        None => None,
        Some(c) => Some(Field::Radial {
            center: numbers::<3>("--center", c, "x,y,z")?,
            axis: numbers::<3>("--axis", &args.axis, "x,y,z")?,
        }),
    };
    let stagger = !args.no_stagger;
    let found = || synthesis::found_courses(shape, size, stagger, settings);
    Ok(match (args.strategy, given) {
        (Strategy::Courses, None) => found().map(|(g, f)| (g, Some(f))),
        (Strategy::Courses, Some(f)) => synthesis::courses(shape, &f, size, stagger).map(|g| (g, None)),
        (Strategy::Thrust, given) => {
            let (field, found) = match given {
                Some(f) => (f, None),
                None => match found() {
                    Ok((_, f)) => (f, Some(f)),
                    Err(e) => return Ok(Err(e)),
                },
            };
            synthesis::thrust(shape, &field, size, stagger, &ThrustSettings::default(), settings).map(|g| (g, found))
        }
        (Strategy::Pattern, _) => {
            let apex = numbers::<3>("--apex", args.apex.as_deref().unwrap_or_default(), "x,y,z")?;
            synthesis::pattern(shape, apex, size, stagger).map(|g| (g, None))
        }
    })
}

/// A field in words, for the line saying which load path was found.
fn describe(field: &Field) -> String {
    match field {
        Field::Vertical => "vertical (horizontal beds)".into(),
        Field::Radial { center, axis } => format!(
            "round the axis through ({:.4}, {:.4}, {:.4}) along ({:.3}, {:.3}, {:.3}), fitted to the curved faces (radial beds)",
            shown(center[0], 4),
            shown(center[1], 4),
            shown(center[2], 4),
            shown(axis[0], 3),
            shown(axis[1], 3),
            shown(axis[2], 3)
        ),
    }
}

/// `v` as printed with `places` decimals, without a sign on a value that rounds to zero.
fn shown(v: f64, places: i32) -> f64 {
    if v.abs() < 0.5 * 10f64.powi(-places) { 0.0 } else { v }
}
