//! `voussoir sweep`: the static and drop-test thresholds of a parametric family, by
//! bisection, optionally plotted against the parameter.

use super::choice::Choice;
use super::options::DropOptions;
use super::{BadInput, load, refuse_overwrite, write_output};
use crate::dynamics::Engine;
use crate::model::{FrictionModel, Material};
use crate::studies::threshold::{Family, compare_engines, scan};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// Voussoirs of the swept arch unless `--n` says otherwise.
pub const ARCH_VOUSSOIRS: usize = 15;
/// Blocks of the swept harmonic stack unless `--n` says otherwise.
pub const HARMONIC_BLOCKS: usize = 6;

/// The options of `voussoir sweep`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct SweepArgs {
    /// arch (t/R), slope (degrees), harmonic (overhang fraction) or tilt (ground tilt in
    /// degrees of `--scene`).
    #[arg(value_enum, value_parser = Choice::<FamilyName>::new())]
    pub family: FamilyName,
    /// Lower end of the parameter range (default per family).
    #[arg(long, allow_hyphen_values = true)]
    pub lo: Option<f64>,
    /// Upper end of the parameter range (default per family).
    #[arg(long, allow_hyphen_values = true)]
    pub hi: Option<f64>,
    /// Bisection steps per threshold (each halves the bracket).
    #[arg(long, default_value_t = 10)]
    pub iterations: usize,
    /// Voussoirs (arch) or blocks (harmonic).
    #[arg(long, help = format!("Voussoirs (arch) or blocks (harmonic), default {ARCH_VOUSSOIRS} / {HARMONIC_BLOCKS}"))]
    pub n: Option<usize>,
    // The slope's default μ is the default material's, printed from it.
    #[arg(long, help = format!(
        "Friction coefficient of the slope family (default {:.4}, the default material's)",
        Material::default().friction
    ))]
    /// The slope family's friction coefficient.
    pub mu: Option<f64>,
    /// The scene the tilt family tilts (file or builtin:…).
    #[arg(long)]
    pub scene: Option<String>,
    /// The drop test's engine, duration and time step.
    #[command(flatten)]
    pub drop: DropOptions,
    /// Find the drop-test threshold with both engines (rapier and exact; the statics' once),
    /// side by side. The plot's scan stays with `--engine`.
    #[arg(long)]
    pub both_engines: bool,
    /// Write the result as JSON here (atomically): one study, or with `--both-engines` one per
    /// engine (an array).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Also plot both verdicts and margins against the parameter (.png or .svg), from a scan
    /// of `--points` evenly spaced parameters.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Parameters scanned for the plot.
    #[arg(long, default_value_t = 25)]
    pub points: usize,
}

/// The families by name; what the command line adds to [`Family`]: the designs' sizes, the
/// range swept unless `--lo`/`--hi` say otherwise, the plot's axis label.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FamilyName {
    /// Semicircular arch; parameter t/R.
    Arch,
    /// A block on a slope; parameter the angle, degrees.
    Slope,
    /// Harmonic stack; parameter the overhang fraction.
    Harmonic,
    /// `--scene` on a tilting base; parameter the tilt, degrees.
    Tilt,
}

impl FamilyName {
    /// The family with `--n`, `--mu` and `--scene` (or their defaults).
    fn family(self, args: &SweepArgs) -> Result<Family, BadInput> {
        Ok(match self {
            Self::Arch => Family::Arch { n: args.n.unwrap_or(ARCH_VOUSSOIRS) },
            Self::Slope => Family::Slope { mu: args.mu.unwrap_or(Material::default().friction) },
            Self::Harmonic => Family::Harmonic { n: args.n.unwrap_or(HARMONIC_BLOCKS) },
            Self::Tilt => {
                let scene = args.scene.as_deref().ok_or_else(|| BadInput("tilt needs --scene".into()))?;
                Family::Tilt { scene: Box::new(load(Some(scene))?) }
            }
        })
    }

    /// The range that brackets both thresholds of the default designs.
    fn default_range(self) -> (f64, f64) {
        match self {
            Self::Arch => (0.02, 0.4),
            Self::Slope => (0.0, 80.0),
            Self::Harmonic => (0.5, 1.5),
            Self::Tilt => (0.0, 60.0),
        }
    }

    fn parameter(self) -> &'static str {
        match self {
            Self::Arch => "thickness t/R",
            Self::Slope => "slope angle (degrees)",
            Self::Harmonic => "overhang / critical overhang",
            Self::Tilt => "ground tilt (degrees)",
        }
    }
}

impl std::fmt::Display for FamilyName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&super::choice::name(self))
    }
}

/// Runs `sweep`: prints both thresholds; exit code 0.
pub fn run(args: &SweepArgs) -> Result<i32, BadInput> {
    for (out, option) in [(&args.json, "--json"), (&args.plot, "--plot")] {
        if let Some(out) = out {
            refuse_overwrite(args.scene.as_deref(), out, option)?;
        }
    }
    let name = args.family;
    let family = name.family(args)?;
    let (lo, hi) = name.default_range();
    let range = (args.lo.unwrap_or(lo), args.hi.unwrap_or(hi));
    if range.0.partial_cmp(&range.1) != Some(std::cmp::Ordering::Less) {
        return Err(BadInput(format!("--lo {} must be below --hi {}", range.0, range.1)));
    }
    let drop = args.drop.settings(None, FrictionModel::default(), Default::default());
    let engines = if args.both_engines { vec![Engine::Rapier, Engine::Exact] } else { vec![drop.engine] };
    let bar = indicatif::ProgressBar::new((1 + engines.len() as u64) * (args.iterations as u64 + 2));
    bar.set_message(format!("sweeping {name}"));
    let result = compare_engines(&family, range, args.iterations, &drop, &engines, &mut || bar.inc(1));
    bar.finish_and_clear();
    let studies = result.map_err(|e| BadInput(e.to_string()))?;
    let t = &studies[0].statics;
    println!("{name}: statics threshold {:.5} (stands at {:.5}, falls at {:.5})", t.mid(), t.stands_at, t.fails_at);
    for r in &studies {
        let t = &r.dynamic;
        println!(
            "{name}: drop-test threshold ({}) {:.5} (stands at {:.5}, falls at {:.5}); gap (drop test − statics) {:+.5}, {} evaluations",
            r.engine,
            t.mid(),
            t.stands_at,
            t.fails_at,
            r.gap,
            r.evaluations
        );
    }
    if let Some(out) = &args.json {
        let json = match studies.as_slice() {
            [one] => serde_json::to_string_pretty(one),
            all => serde_json::to_string_pretty(all),
        };
        write_output(out, json.unwrap_or_default().as_bytes())?;
    }
    let r = studies.iter().find(|r| r.engine == drop.engine).unwrap_or(&studies[0]);
    if let Some(out) = &args.plot {
        let bar = indicatif::ProgressBar::new(args.points as u64);
        bar.set_message("scanning for the plot");
        let scan = scan(&family, range, args.points, &drop, &mut || bar.inc(1));
        bar.finish_and_clear();
        let scan = scan.map_err(|e| BadInput(e.to_string()))?;
        let plot = crate::viz::plot::ThresholdPlot {
            title: format!("{name} sweep: statics vs drop test"),
            parameter: name.parameter().into(),
            scan: &scan,
            result: Some(r),
        };
        crate::viz::plot::write_thresholds(&plot, out).map_err(|e| BadInput(e.to_string()))?;
        println!("plot written to {}", out.display());
    }
    Ok(0)
}
