//! `voussoir analyze` (also `drop`, and `voussoir` without a command): the statics of one
//! design, its text report and JSON report, and on request the drop test beside it.

use super::options::{DropOptions, LoadOptions, SceneOptions, SolverOptions};
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::dynamics::DropResult;
use crate::io;
use crate::model::LoadKind;
use crate::pipeline::{Analysis, analyze};
use crate::report::{self, text as text_report};
use clap::{Args, FromArgMatches};
use std::path::PathBuf;

/// The options of `voussoir analyze` (and `drop`, which turns the drop test on).
#[derive(Args, Debug, Clone, PartialEq)]
pub struct AnalyzeArgs {
    /// Scene file (.json voussoir or compas Assembly, .obj, .stl) or `builtin:NAME?k=v&...`
    /// (stack, harmonic, arch, wall, slope, dome). Default: the embedded default scene.
    pub scene: Option<String>,
    /// Write the JSON report here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the design with its interfaces and forces as compas JSON here (atomically): a
    /// compas_dem BlockModel for a BlockModel input, else a compas 2 Assembly (compas' viewers
    /// draw it, compas_cra reads it); `--compas-format` chooses.
    #[arg(long)]
    pub compas_out: Option<PathBuf>,
    /// The format of `--compas-out`: `assembly` or `block-model` (default: that of the input
    /// when it is a BlockModel, else an Assembly).
    #[arg(long, value_enum, value_parser = super::choice::Choice::<CompasFormat>::new(), requires = "compas_out")]
    pub compas_format: Option<CompasFormat>,
    /// The solver's friction model, μ, backend and interface tolerances.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// Point loads and acceleration fields added to the scene's.
    #[command(flatten)]
    pub loads: LoadOptions,
    /// Supports, ground and density given on the command line.
    #[command(flatten)]
    pub scene_options: SceneOptions,
    /// How many of the worst interfaces to list.
    #[arg(long, default_value_t = 5)]
    pub worst: usize,
    /// Also run the drop test (`--engine`) and compare the verdicts.
    #[arg(long)]
    pub dynamic: bool,
    /// With the drop test: write its motion as a glTF animation (.glb, 30 frames per simulated
    /// second; any glTF viewer plays it) — a collapse seen in motion.
    #[arg(long, value_name = "OUT.glb")]
    pub frames: Option<PathBuf>,
    /// With the drop test: draw its motion as a strip of six key frames, evenly spaced in time
    /// (.png or .svg).
    #[arg(long, value_name = "OUT.png")]
    pub strip: Option<PathBuf>,
    /// Also run the kinematic check (released from rest with no squeeze: do the forces RBE
    /// found actually arise?) and compare the verdicts.
    #[arg(long)]
    pub kinematic: bool,
    /// Also find how precisely it must be cut: the largest shrink of every joint (chipped
    /// arrises) and tilt of every joint plane for which it still stands, each with the joint
    /// that governs (bisection on the statics).
    #[arg(long)]
    pub tolerance: bool,
    /// The drop test's engine, duration and time step.
    #[command(flatten)]
    pub drop: DropOptions,
}

/// Which compas JSON `--compas-out` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CompasFormat {
    /// A compas_assembly `Assembly` (compas_cra reads it too).
    Assembly,
    /// A compas_dem `BlockModel`.
    BlockModel,
}

impl CompasFormat {
    /// A BlockModel for a BlockModel input file, else an Assembly.
    fn of_input(scene: Option<&str>) -> Self {
        let block_model =
            scene.and_then(|path| std::fs::read(path).ok()).is_some_and(|b| io::compas_dem::is_block_model_bytes(&b));
        if block_model { Self::BlockModel } else { Self::Assembly }
    }
}

impl AnalyzeArgs {
    /// `analyze` with every option at its default, as the parser gives it: what `voussoir`
    /// without a command runs (so the defaults are not written a second time).
    pub fn defaults() -> Self {
        let command = <Self as Args>::augment_args(clap::Command::new("analyze"));
        Self::from_arg_matches(&command.get_matches_from(["analyze"])).expect("every option is optional")
    }
}

/// Writes the recorded motion as `--frames`' animation and `--strip`'s key frames.
fn write_motion(
    args: &AnalyzeArgs,
    assembly: &crate::model::Assembly,
    motion: &crate::dynamics::Trajectory,
) -> Result<(), BadInput> {
    if let Some(out) = &args.frames {
        write_output(out, &crate::viz::gltf::animation_glb(assembly, motion))?;
        println!("motion written to {} ({} frames)", out.display(), motion.times.len());
    }
    if let Some(out) = &args.strip {
        let strip = crate::viz::plot::FrameStrip::new(assembly, motion);
        crate::viz::plot::write_strip(&strip, out).map_err(|e| BadInput(e.to_string()))?;
        println!(
            "key frames written to {} (t = {})",
            out.display(),
            strip.key_frames().iter().map(|&f| format!("{:.2}", motion.times[f])).collect::<Vec<_>>().join(", ")
        );
    }
    Ok(())
}

/// Runs `analyze`: prints the report and returns the exit code (0 stands, 1 does not).
pub fn run(args: &AnalyzeArgs) -> Result<i32, BadInput> {
    check_outputs(args)?;
    let mut scene = load(args.scene.as_deref())?;
    let settings = args.solver.settings();
    args.scene_options.apply(&mut scene, &settings)?;
    scene.loads.extend(args.loads.loads()?);
    let live = scene.loads.iter().filter(|l| l.kind() == LoadKind::Live).count();
    let analysis =
        analyze(&scene, &settings).map_err(|e| BadInput(format!("{}: {e}", scene_name(args.scene.as_deref()))))?;
    print!("{}", text_report::summary(&analysis, args.worst));
    if live > 0 {
        println!("  {live} live load(s) not applied: `voussoir robustness` gives their load factor");
    }
    let dynamic = if args.dynamic { Some(drop_test(args, &analysis)?) } else { None };
    let kinematic = if args.kinematic {
        let k = crate::stability::kinematic::check(&analysis, &settings.statics, &Default::default())
            .map_err(|e| BadInput(e.to_string()))?;
        print!("{}", text_report::kinematic(&analysis, &k));
        Some(k)
    } else {
        None
    };
    let tolerance = if args.tolerance {
        let t = crate::stability::tolerance::margins(&analysis, &settings.statics, &Default::default())
            .map_err(|e| BadInput(format!("--tolerance: {e}")))?;
        print!("{}", text_report::tolerance(&t));
        Some(t)
    } else {
        None
    };
    if let Some(out) = &args.compas_out {
        write_compas(args, &analysis, out)?;
    }
    if let Some(out) = &args.json {
        let extras = report::json::Extras {
            dynamic: dynamic.as_ref(),
            kinematic: kinematic.as_ref(),
            tolerance: tolerance.as_ref(),
        };
        write_output(out, report::json::to_json_with(&analysis, &extras).as_bytes())?;
        println!("report written to {}", out.display());
    }
    // Exit 0 only when it stands by every test that ran.
    let stands = analysis.statics.stands
        && dynamic.as_ref().is_none_or(|d| d.stands)
        && kinematic.as_ref().is_none_or(|k| k.verdict == crate::stability::kinematic::KinematicVerdict::Stands);
    Ok(if stands { 0 } else { 1 })
}

/// The outputs asked for, before any work: none overwrites the input, and the motion's files
/// come with the drop test.
fn check_outputs(args: &AnalyzeArgs) -> Result<(), BadInput> {
    if let Some(out) = &args.compas_out {
        refuse_overwrite(args.scene.as_deref(), out, "--compas-out")?;
    }
    for (out, option) in [(&args.frames, "--frames"), (&args.strip, "--strip")] {
        if let Some(out) = out {
            refuse_overwrite(args.scene.as_deref(), out, option)?;
            if !args.dynamic {
                return Err(BadInput(format!(
                    "{option}: the motion is the drop test's (use `drop` or `analyze --dynamic`)"
                )));
            }
        }
    }
    if let Some(out) = &args.json {
        refuse_overwrite(args.scene.as_deref(), out, "--json")?;
    }
    Ok(())
}

/// The drop test beside the statics (`--dynamic`), printed, with its motion written when
/// `--frames` or `--strip` asks for it.
fn drop_test(args: &AnalyzeArgs, analysis: &Analysis) -> Result<DropResult, BadInput> {
    let settings = args.drop.settings(args.solver.mu, args.solver.friction_model, args.solver.solver);
    let d = if args.frames.is_some() || args.strip.is_some() {
        let (d, motion) = crate::dynamics::record(&analysis.assembly, &settings, crate::viz::gltf::FRAMES_PER_SECOND)
            .map_err(|e| BadInput(e.to_string()))?;
        write_motion(args, &analysis.assembly, &motion)?;
        d
    } else {
        crate::dynamics::drop_test(&analysis.assembly, &settings).map_err(|e| BadInput(e.to_string()))?
    };
    print!("{}", text_report::side_by_side(analysis, &d));
    Ok(d)
}

/// The design in COMPAS's form (`--compas-out`): the input's own format unless
/// `--compas-format` names one.
fn write_compas(args: &AnalyzeArgs, analysis: &Analysis, out: &std::path::Path) -> Result<(), BadInput> {
    let format = args.compas_format.unwrap_or_else(|| CompasFormat::of_input(args.scene.as_deref()));
    let text = match format {
        CompasFormat::Assembly => report::compas::assembly_json(analysis),
        CompasFormat::BlockModel => report::compas::block_model_json(analysis),
    };
    write_output(out, text.as_bytes())
}
