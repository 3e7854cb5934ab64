//! Command line: `voussoir [analyze] [SCENE] [options]`. Exit codes: 0 the assembly stands,
//! 1 it does not (or the solver could not tell), 2 bad input.
//!
//! One file per command ([`analyze`], [`cut`], [`decompose`], [`export`], [`infill`], [`repair`], [`report`], [`robustness`], [`sequence`], [`settle`], [`shake`], [`sweep`],
//! [`view`]);
//! the options several commands share are flattened structs in [`options`] that turn into the
//! library's settings in one place. Every default is the library's (`default_value_t` reads its
//! `Default` or constant), so `--help` prints it and it is written once.

// `print!`/`println!` panic when stdout is a closed pipe (`voussoir analyze … | head`); the
// report is what matters then: write what can be written, still write the JSON and exit with
// the verdict's code. Defined before the command modules so that they use these.
macro_rules! print {
    ($($t:tt)*) => { $crate::cli::write_stdout(format_args!($($t)*)) };
}
macro_rules! println {
    ($($t:tt)*) => { $crate::cli::write_stdout(format_args!("{}\n", format_args!($($t)*))) };
}

pub mod analyze;
mod choice;
pub mod cut;
pub mod decompose;
pub mod export;
pub mod infill;
pub mod options;
pub mod repair;
pub mod report;
pub mod robustness;
pub mod sequence;
pub mod settle;
pub mod shake;
pub mod sweep;
pub mod view;

pub use analyze::AnalyzeArgs;
pub use cut::CutArgs;
pub use decompose::DecomposeArgs;
pub use export::ExportArgs;
pub use infill::InfillArgs;
pub use options::{Diagram, DiagramOptions, DropOptions, LoadOptions, SolverOptions};
pub use repair::RepairArgs;
pub use report::ReportArgs;
pub use robustness::RobustnessArgs;
pub use sequence::SequenceArgs;
pub use settle::SettleArgs;
pub use shake::ShakeArgs;
pub use sweep::{FamilyName, SweepArgs};
pub use view::ViewArgs;

use crate::io;
use crate::model::{Scene, builtin};
use clap::{Parser, Subcommand};
use std::path::Path;

fn write_stdout(args: std::fmt::Arguments) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_fmt(args);
}

/// The default scene of `voussoir` without arguments (embedded, so it runs from anywhere).
pub const DEFAULT_SCENE: &str = include_str!("../../assets/default.json");

/// One example per command, as `voussoir <command> --help` shows it (and `voussoir --help` all
/// of them): each runs from the repository's root (tests/it/cli.rs runs them, but `view`).
pub const EXAMPLES: [(&str, &str); 14] = [
    ("analyze", r#"voussoir analyze "builtin:arch?n=15&t=0.15" --json report.json"#),
    ("drop", r#"voussoir drop "builtin:arch?n=15&t=0.15" --engine exact --duration 1"#),
    ("robustness", r#"voussoir robustness "builtin:arch?n=15&t=0.15" --plot polar.png --mechanism mechanism.png"#),
    (
        "settle",
        r#"voussoir settle "builtin:arch?n=15&t=0.15" --move springer_left:-0.15,0,0 --move springer_right:0.15,0,0 --quasi-static"#,
    ),
    ("shake", r#"voussoir shake "builtin:arch?n=15&t=0.15" --pulse rect:0.5,0.2 --engine both --plot shake.png"#),
    ("sequence", "voussoir sequence assets/cases/fig6_dmsc_sequence.json --search"),
    ("sweep", "voussoir sweep slope --iterations 6"),
    ("cut", r#"voussoir cut "builtin:stack?n=2" --plane 0,0,1.5,0,0,1 -o cut.json"#),
    ("decompose", "voussoir decompose assets/shapes/solid_arch.json --blocks 11 -o arch.json"),
    ("repair", "voussoir repair assets/cases/fig4a_m_cut.json -o repaired.json"),
    ("infill", r#"voussoir infill "builtin:arch?n=15&t=0.07" -o light.json"#),
    ("report", r#"voussoir report "builtin:arch?n=15&t=0.15" --robustness -o arch.html"#),
    ("export", "voussoir export assets/cases/fig6_dmsc.json --mode friction --png fig6.png --gltf fig6.glb"),
    ("view", "voussoir view assets/cases/fig6_dmsc.json --mode friction"),
];

/// The `Example:` section of one command's help.
fn example(command: &str) -> String {
    let (_, line) = EXAMPLES.iter().find(|(c, _)| *c == command).expect("every command has an example");
    format!("Example:\n  {line}")
}

/// The `Examples:` section of `voussoir --help`: one line per command.
fn examples() -> String {
    let lines: Vec<String> = EXAMPLES.iter().map(|(_, line)| format!("  {line}")).collect();
    format!("Examples (from the repository's root; each command's --help shows its own):\n{}", lines.join("\n"))
}

#[derive(Parser, Debug)]
#[command(
    name = "voussoir",
    version,
    about = "Do these blocks stand by compression and friction alone?",
    after_long_help = examples()
)]
/// The command line: a command, or none (the default scene's analysis).
pub struct Cli {
    /// The command to run; without one, `analyze` of the embedded default scene.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Detect interfaces, solve the equilibrium, print the verdict (and write a JSON report).
    #[command(after_help = example("analyze"))]
    Analyze(AnalyzeArgs),
    /// Statics and the rapier drop test side by side (= `analyze --dynamic`).
    #[command(after_help = example("drop"))]
    Drop(AnalyzeArgs),
    /// How safely it stands: the load factor of the live loads (or of a horizontal
    /// acceleration, or its worst direction) and the collapse mechanism.
    #[command(after_help = example("robustness"))]
    Robustness(RobustnessArgs),
    /// The design on supports that move (`--move`): followed until it collapses,
    /// quasi-statically and in both engines; the movement at collapse, hinges, thrust.
    #[command(after_help = example("settle"))]
    Settle(SettleArgs),
    /// The design on a shaking ground (a pulse, a harmonic or a record) in both engines, the
    /// static load factor beside it; `--spectrum` the least collapsing pulse per duration.
    #[command(after_help = example("shake"))]
    Shake(ShakeArgs),
    /// Check every step of an assembly order (static, and with --dynamic the drop test).
    #[command(after_help = example("sequence"))]
    Sequence(SequenceArgs),
    /// Static and drop-test thresholds of a parametric family, by bisection.
    #[command(after_help = example("sweep"))]
    Sweep(SweepArgs),
    /// Add a plane or pattern cut to the scene's cut history and write the design (never over
    /// the input).
    #[command(after_help = example("cut"))]
    Cut(CutArgs),
    /// Cut a source shape into courses (horizontal, or through an axis for arches) with
    /// staggered head joints; `--optimize` then repairs it. Writes the design.
    #[command(after_help = example("decompose"))]
    Decompose(DecomposeArgs),
    /// Move and turn the design's cuts until it stands, then stands most safely; write the
    /// repaired design (or say why no placement helps, and which support would).
    #[command(after_help = example("repair"))]
    Repair(RepairArgs),
    /// Choose per-block densities within bounds (a print's infill) that make the design stand:
    /// the lightest, or the most robust; write the design (or the mechanism no mass can stop).
    #[command(after_help = example("infill"))]
    Infill(InfillArgs),
    /// Export the analysed design without a window: glTF binary with the blocks and the
    /// interface polygons coloured by a diagram mode.
    #[command(after_help = example("export"))]
    Export(ExportArgs),
    /// One self-contained HTML report to send: the design's diagrams in 3D, the verdict and
    /// its numbers, and the collapse mechanism, drop test or settlement played beside it.
    #[command(after_help = example("report"))]
    Report(ReportArgs),
    /// The interactive 3D viewer (built with `--features viewer`): diagrams, live cut editing,
    /// drop test and sequence stepper side by side.
    #[command(after_help = example("view"))]
    View(ViewArgs),
}

/// A failure that is the input's fault: exit code 2.
#[derive(Debug)]
pub struct BadInput(pub String);

/// Runs the CLI; returns the process exit code.
pub fn run(cli: Cli) -> i32 {
    let result = match cli.command {
        None => analyze::run(&AnalyzeArgs::defaults()),
        Some(Command::Analyze(args)) => analyze::run(&args),
        Some(Command::Drop(args)) => analyze::run(&AnalyzeArgs { dynamic: true, ..args }),
        Some(Command::Cut(args)) => cut::run(&args),
        Some(Command::Sweep(args)) => sweep::run(&args),
        Some(Command::Sequence(args)) => sequence::run(&args),
        Some(Command::Robustness(args)) => robustness::run(&args),
        Some(Command::Settle(args)) => settle::run(&args),
        Some(Command::Shake(args)) => shake::run(&args),
        Some(Command::Repair(args)) => repair::run(&args),
        Some(Command::Decompose(args)) => decompose::run(&args),
        Some(Command::Infill(args)) => infill::run(&args),
        Some(Command::Export(args)) => export::run(&args),
        Some(Command::Report(args)) => report::run(&args),
        Some(Command::View(args)) => view::run(&args),
    };
    match result {
        Ok(code) => code,
        Err(BadInput(msg)) => {
            eprintln!("error: {msg}");
            2
        }
    }
}

/// A progress bar on stderr that appears only once a run has taken half a second (quick runs
/// print nothing); `template` is indicatif's, `{msg}` filled by [`LateBar::update`].
struct LateBar {
    bar: indicatif::ProgressBar,
    start: std::time::Instant,
    shown: std::sync::Once,
}

impl LateBar {
    fn new(template: Option<&str>) -> Self {
        let bar = indicatif::ProgressBar::hidden();
        if let Some(t) = template {
            bar.set_style(indicatif::ProgressStyle::with_template(t).expect("a valid template"));
        }
        Self { bar, start: std::time::Instant::now(), shown: std::sync::Once::new() }
    }

    fn update(&self, done: usize, total: usize, message: Option<String>) {
        if self.start.elapsed() > std::time::Duration::from_millis(500) {
            self.shown.call_once(|| self.bar.set_draw_target(indicatif::ProgressDrawTarget::stderr()));
        }
        self.bar.set_length(total as u64);
        self.bar.set_position(done as u64);
        if let Some(m) = message {
            self.bar.set_message(m);
        }
    }
}

impl Drop for LateBar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// Loads the scene named on the command line.
pub fn load(spec: Option<&str>) -> Result<Scene, BadInput> {
    match spec {
        None => io::scene_json::scene_from_str(Path::new("assets/default.json"), DEFAULT_SCENE)
            .map_err(|e| BadInput(e.to_string())),
        Some(s) if s.starts_with("builtin:") => builtin(&s["builtin:".len()..]).map_err(|e| BadInput(e.to_string())),
        Some(path) => io::load_scene(Path::new(path)).map_err(|e| BadInput(e.to_string())),
    }
}

/// How messages name the scene given on the command line (or the default one).
fn scene_name(spec: Option<&str>) -> &str {
    spec.unwrap_or("default scene")
}

/// Refuses to write `out` when it is the input scene file (by canonical path, so `./a.json`
/// and `a.json` match); `option` names the flag in the message. Inputs are never overwritten.
fn refuse_overwrite(input: Option<&str>, out: &Path, option: &str) -> Result<(), BadInput> {
    let Some(input) = input else { return Ok(()) };
    if io::same_file(Path::new(input), out) {
        return Err(BadInput(format!("{option} {} would overwrite the input; write elsewhere", out.display())));
    }
    Ok(())
}

/// Writes `bytes` to `out` atomically; a failure is the output path's fault.
fn write_output(out: &Path, bytes: &[u8]) -> Result<(), BadInput> {
    io::write_atomic(out, bytes).map_err(|e| BadInput(e.to_string()))
}

/// `N` comma-separated numbers from option `option`.
fn numbers<const N: usize>(option: &str, text: &str, form: &str) -> Result<[f64; N], BadInput> {
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| BadInput(format!("{option} '{text}': expected {N} numbers {form}")))?;
    v.try_into().map_err(|v: Vec<f64>| BadInput(format!("{option} '{text}': expected {N} numbers, got {}", v.len())))
}
