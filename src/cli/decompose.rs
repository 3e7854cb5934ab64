//! `voussoir decompose SHAPE (--blocks N | --max-size L) [--strategy courses|thrust] -o OUT.json`:
//! a cut history for a source shape by courses ([`crate::synthesis::generate`]) — horizontal
//! beds, or beds through an axis with `--center`/`--axis` (arches, vaults) — with staggered
//! head joints, the beds turned normal to the thrust with `--strategy thrust`
//! ([`crate::synthesis::thrust`]); prints the design's verdict and with `--optimize` repairs it
//! ([`crate::synthesis::repair`]). Writes the
//! design atomically, never over the input. Exit codes: 0 it stands, 1 it does not, 2 bad input.

use super::choice::Choice;
use super::options::SolverOptions;
use super::{BadInput, load, numbers, refuse_overwrite, scene_name, write_output};
use crate::io::scene_json;
use crate::pipeline::analyze;
use crate::statics::Verdict;
use crate::synthesis::{self, BlockSize, Field, RepairSettings, ThrustSettings};
use clap::Args;
use clap::ValueEnum;
use std::path::PathBuf;

#[derive(Args, Debug, Clone, PartialEq)]
pub struct DecomposeArgs {
    /// The source shape (any scene or mesh file the readers accept, without a cut history).
    pub scene: String,
    #[command(flatten)]
    pub solver: SolverOptions,
    /// About this many blocks (along the arc for `--center`).
    #[arg(long, required_unless_present = "max_size", conflicts_with = "max_size")]
    pub blocks: Option<usize>,
    /// Largest block dimension along the cut directions, m.
    #[arg(long)]
    pub max_size: Option<f64>,
    /// Courses through an axis (arches, barrel vaults): a point `x,y,z` on it.
    #[arg(long, allow_hyphen_values = true)]
    pub center: Option<String>,
    /// The axis' direction `x,y,z` (with `--center`).
    #[arg(long, allow_hyphen_values = true, default_value = "0,1,0", requires = "center")]
    pub axis: String,
    /// How the beds are placed: `courses` across the field, or `thrust`: turned normal to the
    /// force an analysis finds crossing them (arches, vaults, buttresses).
    #[arg(long, value_enum, value_parser = Choice::<Strategy>::new(), default_value_t = Strategy::Courses)]
    pub strategy: Strategy,
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

/// A generation strategy ([`crate::synthesis::generate`], [`crate::synthesis::thrust`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Strategy {
    Courses,
    Thrust,
}

pub fn run(args: &DecomposeArgs) -> Result<i32, BadInput> {
    refuse_overwrite(Some(&args.scene), &args.output, "-o")?;
    let name = scene_name(Some(&args.scene)).to_string();
    let shape = load(Some(&args.scene))?;
    let field = match &args.center {
        None => Field::Vertical,
        Some(c) => Field::Radial {
            center: numbers::<3>("--center", c, "x,y,z")?,
            axis: numbers::<3>("--axis", &args.axis, "x,y,z")?,
        },
    };
    let size = match (args.blocks, args.max_size) {
        (Some(n), _) => BlockSize::Count(n),
        (None, Some(l)) => BlockSize::Max(l),
        (None, None) => return Err(BadInput("give --blocks N or --max-size L".into())),
    };
    let bad = |e: synthesis::DesignError| BadInput(format!("{name}: {e}"));
    let settings = args.solver.settings();
    let generated = match args.strategy {
        Strategy::Courses => synthesis::courses(&shape, &field, &size, !args.no_stagger),
        Strategy::Thrust => {
            synthesis::thrust(&shape, &field, &size, !args.no_stagger, &ThrustSettings::default(), &settings)
        }
    }
    .map_err(bad)?;
    println!(
        "{} courses, {} pieces (block size {:.4} m), {} cuts",
        generated.courses,
        generated.pieces,
        generated.max_size,
        generated.design.cuts.len()
    );
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
