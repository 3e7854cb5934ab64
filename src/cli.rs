//! Command line: `voussoir [analyze] [SCENE] [options]`. Exit codes: 0 the assembly stands,
//! 1 it does not (or the solver could not tell), 2 bad input.

use crate::analysis::{Analysis, AnalysisSettings, analyze};
use crate::io;
use crate::model::{Scene, builtin};
use crate::statics::{Backend, FrictionModel, Verdict};
use clap::{Args, Parser, Subcommand};
use std::path::{Path, PathBuf};

// `print!`/`println!` panic when stdout is a closed pipe (`voussoir analyze … | head`); the
// report is what matters then: write what can be written, still write the JSON and exit with
// the verdict's code.
macro_rules! print {
    ($($t:tt)*) => { write_stdout(format_args!($($t)*)) };
}
macro_rules! println {
    ($($t:tt)*) => { write_stdout(format_args!("{}\n", format_args!($($t)*))) };
}

fn write_stdout(args: std::fmt::Arguments) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_fmt(args);
}

/// The default scene of `voussoir` without arguments (embedded, so it runs from anywhere).
pub const DEFAULT_SCENE: &str = include_str!("../assets/default.json");

#[derive(Parser, Debug)]
#[command(name = "voussoir", version, about = "Do these blocks stand by compression and friction alone?")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Detect interfaces, solve the equilibrium, print the verdict (and write a JSON report).
    Analyze(AnalyzeArgs),
    /// Statics and the rapier drop test side by side (= `analyze --dynamic`).
    Drop(AnalyzeArgs),
    /// Check every step of an assembly order (static, and with --dynamic the drop test).
    Sequence(SequenceArgs),
    /// Static and drop-test thresholds of a parametric family, by bisection.
    Sweep(SweepArgs),
    /// Add a plane or pattern cut to the scene's cut history and write the design (never over
    /// the input).
    Cut(CutArgs),
    /// Export the analysed design without a window: glTF binary with the blocks and the
    /// interface polygons coloured by a diagram mode.
    Export(ExportArgs),
    /// The interactive 3D viewer (built with `--features viewer`): diagrams, live cut editing,
    /// drop test and sequence stepper side by side.
    View(ViewArgs),
}

#[derive(Args, Debug)]
pub struct ViewArgs {
    /// Scene file or `builtin:…` (default: the embedded default scene).
    pub scene: Option<String>,
    /// Diagram at start: compression, friction or vectors (keys 1/2/3 switch).
    #[arg(long, default_value = "compression")]
    pub mode: String,
    /// Friction mode: the "low friction" limit as a fraction of μ · compression (default 0.5).
    #[arg(long, default_value_t = 0.5)]
    pub threshold: f64,
    /// Friction model: pyramid8 (default), cone or box4.
    #[arg(long, default_value = "pyramid8")]
    pub friction_model: FrictionModel,
    /// Friction coefficient μ (default: the scene's).
    #[arg(long)]
    pub mu: Option<f64>,
    /// Draw the blocks opaque (default translucent, so that the interfaces show).
    #[arg(long)]
    pub opaque: bool,
    /// Where Ctrl+S saves the design (default `<input>.edited.json` beside the input).
    #[arg(long)]
    pub save: Option<PathBuf>,
    /// Allow Ctrl+S to write over the input file.
    #[arg(long)]
    pub save_over_input: bool,
    /// Window size, `WIDTHxHEIGHT` logical pixels.
    #[arg(long, default_value = "1280x800")]
    pub size: String,
    /// No interaction: render, save a screenshot of the window here (PNG), exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Scene file or `builtin:…`.
    pub scene: String,
    /// Write a glTF binary (.glb) here (atomically; never over the input).
    #[arg(long, required_unless_present = "png")]
    pub gltf: Option<PathBuf>,
    /// Render the diagram offscreen to a picture here (.png or .svg; atomically).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Diagram colouring the interfaces: compression (blue compression, red tension, grey
    /// nothing), friction (grey, yellow up to --threshold of μ, orange up to μ, red beyond) or
    /// vectors (force arrows over the compression colours).
    #[arg(long, default_value = "compression")]
    pub mode: String,
    /// Friction mode: the "low friction" limit as a fraction of μ · compression (default 0.5).
    #[arg(long, default_value_t = 0.5)]
    pub threshold: f64,
    /// Friction model: pyramid8 (default), cone or box4.
    #[arg(long, default_value = "pyramid8")]
    pub friction_model: FrictionModel,
    /// Friction coefficient μ (default: the scene's).
    #[arg(long)]
    pub mu: Option<f64>,
}

#[derive(Args, Debug)]
pub struct CutArgs {
    /// Scene file or `builtin:…` (its blocks become the source shapes when it has no history).
    pub scene: String,
    /// The plane: a point and a normal, `px,py,pz,nx,ny,nz`; the `-` pieces are on the side
    /// the normal points away from.
    #[arg(long, allow_hyphen_values = true, required_unless_present = "apex", conflicts_with = "apex")]
    pub plane: Option<String>,
    /// Pattern cut: the apex `x,y,z` the segments are extruded to (with one `--segment` per
    /// line of the pattern).
    #[arg(long, allow_hyphen_values = true, requires = "segment")]
    pub apex: Option<String>,
    /// A pattern segment `x0,y0,z0,x1,y1,z1` (repeat; applied in order, each cutting the pieces
    /// that the cone from the apex through it meets).
    #[arg(long, allow_hyphen_values = true, requires = "apex")]
    pub segment: Vec<String>,
    /// Cut only this piece (supports are cut only when named here).
    #[arg(long)]
    pub target: Option<String>,
    /// Output scene JSON (written atomically).
    #[arg(short, long)]
    pub output: PathBuf,
}

#[derive(Args, Debug)]
pub struct SequenceArgs {
    /// Scene file or `builtin:…`.
    pub scene: String,
    /// `bottom-up` (by height), `from-supports` (by graph distance from the supports) or
    /// block names in placing order, comma-separated (a source shape's name stands for all its
    /// pieces, bottom-up). Default: the scene file's `order`, else bottom-up.
    #[arg(long, conflicts_with = "search")]
    pub order: Option<String>,
    /// Search an order in which every step stands; when none exists, propose temporary
    /// supports (exit code 1).
    #[arg(long)]
    pub search: bool,
    /// Propose temporary supports (props) for the order wherever a step would not stand.
    #[arg(long)]
    pub props: bool,
    /// Static checks the search may run (default 20 per block + 200).
    #[arg(long)]
    pub max_checks: Option<usize>,
    /// Also drop-test every step.
    #[arg(long)]
    pub dynamic: bool,
    /// Friction coefficient μ (default: the scene's).
    #[arg(long)]
    pub mu: Option<f64>,
    /// Write the report as JSON here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct SweepArgs {
    /// arch (t/R), slope (degrees), harmonic (overhang fraction) or tilt (ground tilt in
    /// degrees of `--scene`).
    pub family: String,
    /// Lower end of the parameter range (default per family).
    #[arg(long, allow_hyphen_values = true)]
    pub lo: Option<f64>,
    /// Upper end of the parameter range (default per family).
    #[arg(long, allow_hyphen_values = true)]
    pub hi: Option<f64>,
    /// Bisection steps per threshold (default 10: the bracket shrinks 1024×).
    #[arg(long, default_value_t = 10)]
    pub iterations: usize,
    /// Voussoirs (arch) or blocks (harmonic), default 15 / 6.
    #[arg(long)]
    pub n: Option<usize>,
    /// Friction coefficient of the slope family (default tan 40°).
    #[arg(long)]
    pub mu: Option<f64>,
    /// The scene the tilt family tilts (file or builtin:…).
    #[arg(long)]
    pub scene: Option<String>,
    /// Drop test: simulated seconds per evaluation (default 2).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Write the result as JSON here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Also plot both verdicts and margins against the parameter (.png or .svg), from a scan
    /// of `--points` evenly spaced parameters.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Parameters scanned for the plot (default 25).
    #[arg(long, default_value_t = 25)]
    pub points: usize,
}

#[derive(Args, Debug, Default)]
pub struct AnalyzeArgs {
    /// Scene file (.json voussoir or compas Assembly, .obj, .stl) or `builtin:NAME?k=v&...`
    /// (stack, harmonic, arch, wall, slope, dome). Default: the embedded default scene.
    pub scene: Option<String>,
    /// Write the JSON report here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Friction model: pyramid8 (default), cone or box4.
    #[arg(long, default_value = "pyramid8")]
    pub friction_model: FrictionModel,
    /// Interior-point solver: structured (default; the Newton system reduced to the
    /// equilibrium rows) or clarabel (its general LDL), to cross-check.
    #[arg(long, default_value = "structured")]
    pub solver: Backend,
    /// Friction coefficient μ (default: the scene's).
    #[arg(long)]
    pub mu: Option<f64>,
    /// Density for every block, kg/m³ (default: the scene's).
    #[arg(long)]
    pub density: Option<f64>,
    /// Supports: `lowest` (blocks at the lowest level) or a comma-separated list of block
    /// names; replaces the supports given in the scene.
    #[arg(long)]
    pub supports: Option<String>,
    /// The ground plane z = 0 supports faces lying on it.
    #[arg(long)]
    pub ground: bool,
    /// Coplanarity tolerance relative to the model size (default 3e-3).
    #[arg(long)]
    pub coplanar: Option<f64>,
    /// Angle tolerance between opposite faces, degrees (default 6).
    #[arg(long)]
    pub angle: Option<f64>,
    /// How many of the worst interfaces to list (default 5).
    #[arg(long, default_value_t = 5)]
    pub worst: usize,
    /// Also run the rapier drop test and compare the verdicts.
    #[arg(long)]
    pub dynamic: bool,
    /// Drop test: simulated seconds (default 2).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Drop test: time step, s (default 1/240).
    #[arg(long)]
    pub dt: Option<f64>,
}

/// A failure that is the input's fault: exit code 2.
#[derive(Debug)]
pub struct BadInput(pub String);

/// Runs the CLI; returns the process exit code.
pub fn run(cli: Cli) -> i32 {
    let result = match cli.command {
        None => run_analyze(&AnalyzeArgs { friction_model: FrictionModel::Pyramid8, worst: 5, ..Default::default() }),
        Some(Command::Analyze(args)) => run_analyze(&args),
        Some(Command::Drop(args)) => run_analyze(&AnalyzeArgs { dynamic: true, ..args }),
        Some(Command::Cut(args)) => run_cut(&args),
        Some(Command::Sweep(args)) => run_sweep(&args),
        Some(Command::Sequence(args)) => run_sequence(&args),
        Some(Command::Export(args)) => run_export(&args),
        Some(Command::View(args)) => run_view(&args),
    };
    match result {
        Ok(code) => code,
        Err(BadInput(msg)) => {
            eprintln!("error: {msg}");
            2
        }
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

fn apply_options(scene: &mut Scene, args: &AnalyzeArgs, settings: &AnalysisSettings) -> Result<(), BadInput> {
    if let Some(d) = args.density {
        scene.material.density = d;
        scene.blocks.iter_mut().for_each(|b| b.density = None);
    }
    if args.ground {
        scene.ground = true;
    }
    match args.supports.as_deref() {
        None => {}
        Some("lowest") => {
            scene.blocks.iter_mut().for_each(|b| b.support = false);
            // "The lowest level" within the coplanarity tolerance: the Armadillo's 33 supports
            // sit within 2.5 cm (1.2e-3 of its size) of each other.
            scene.mark_lowest_as_supports(settings.tolerances.coplanar);
        }
        Some(list) => {
            let names: Vec<&str> = list.split(',').map(str::trim).filter(|s| !s.is_empty()).collect();
            if let Some(missing) = names.iter().find(|n| scene.find(n).is_none()) {
                return Err(BadInput(format!("--supports: the scene has no block named '{missing}'")));
            }
            for b in &mut scene.blocks {
                b.support = names.contains(&b.name.as_str());
            }
        }
    }
    Ok(())
}

fn run_analyze(args: &AnalyzeArgs) -> Result<i32, BadInput> {
    if let Some(out) = &args.json {
        refuse_overwrite(args.scene.as_deref(), out, "--json")?;
    }
    let mut scene = load(args.scene.as_deref())?;
    let mut settings = AnalysisSettings::default();
    settings.statics.friction_model = args.friction_model;
    settings.statics.backend = args.solver;
    settings.statics.friction = args.mu;
    if let Some(c) = args.coplanar {
        settings.tolerances.coplanar = c;
    }
    if let Some(a) = args.angle {
        settings.tolerances.angle_deg = a;
    }
    apply_options(&mut scene, args, &settings)?;
    let analysis = analyze(&scene, &settings).map_err(|e| BadInput(format!("{}: {e}", source_name(args))))?;
    print!("{}", summary(&analysis, args.worst));
    let dynamic = if args.dynamic {
        let mut ds = crate::dynamics::DropSettings { friction: args.mu, ..Default::default() };
        ds.duration = args.duration.unwrap_or(ds.duration);
        ds.dt = args.dt.unwrap_or(ds.dt);
        let d = crate::dynamics::drop_test(&analysis.assembly, &ds).map_err(|e| BadInput(e.to_string()))?;
        print!("{}", side_by_side(&analysis, &d));
        Some(d)
    } else {
        None
    };
    if let Some(out) = &args.json {
        let json = io::report::to_json_with(&analysis, dynamic.as_ref());
        io::write_atomic(out, json.as_bytes()).map_err(|e| BadInput(e.to_string()))?;
        println!("report written to {}", out.display());
    }
    // Exit 0 only when it stands by every test that ran.
    let stands = analysis.statics.stands && dynamic.as_ref().is_none_or(|d| d.stands);
    Ok(if stands { 0 } else { 1 })
}

fn run_cut(args: &CutArgs) -> Result<i32, BadInput> {
    let mut scene = load(Some(&args.scene))?;
    let cut = match (&args.plane, &args.apex) {
        (Some(plane), _) => {
            let [px, py, pz, nx, ny, nz] = numbers::<6>("--plane", plane, "px,py,pz,nx,ny,nz")?;
            crate::model::Cut::plane([px, py, pz], [nx, ny, nz])
        }
        (None, Some(apex)) => {
            let apex = numbers::<3>("--apex", apex, "x,y,z")?;
            let segments = args
                .segment
                .iter()
                .map(|s| {
                    numbers::<6>("--segment", s, "x0,y0,z0,x1,y1,z1").map(|v| [[v[0], v[1], v[2]], [v[3], v[4], v[5]]])
                })
                .collect::<Result<Vec<_>, _>>()?;
            crate::model::Cut::pattern(apex, segments)
        }
        (None, None) => return Err(BadInput("give --plane or --apex with --segment".into())),
    };
    let before = crate::decompose::resolve(&scene, &Default::default(), &mut Default::default())
        .map_err(|e| BadInput(format!("{}: {e}", args.scene)))?
        .0;
    scene.cuts.push(crate::model::Cut { target: args.target.clone(), ..cut });
    let (after, _) = crate::decompose::resolve(&scene, &Default::default(), &mut Default::default())
        .map_err(|e| BadInput(format!("{}: {e}", args.scene)))?;
    let old: std::collections::HashSet<&str> = before.blocks.iter().map(|b| b.name.as_str()).collect();
    let new: Vec<&str> = after.blocks.iter().map(|b| b.name.as_str()).filter(|n| !old.contains(n)).collect();
    if new.is_empty() {
        println!("the cut misses every piece it may cut: the design is unchanged (the cut is recorded)");
    } else {
        println!("cut {}: {} new pieces: {}", scene.cuts.len() - 1, new.len(), new.join(", "));
    }
    refuse_overwrite(Some(&args.scene), &args.output, "-o")?;
    io::write_atomic(&args.output, io::scene_json::scene_to_string(&scene).as_bytes())
        .map_err(|e| BadInput(e.to_string()))?;
    println!(
        "design written to {} ({} blocks after {} cuts)",
        args.output.display(),
        after.blocks.len(),
        scene.cuts.len()
    );
    Ok(0)
}

/// Refuses to write `out` when it is the input scene file (by canonical path, so `./a.json`
/// and `a.json` match); `option` names the flag in the message. Inputs are never overwritten.
fn refuse_overwrite(input: Option<&str>, out: &Path, option: &str) -> Result<(), BadInput> {
    let Some(input) = input else { return Ok(()) };
    let same = match (std::fs::canonicalize(input), std::fs::canonicalize(out)) {
        (Ok(a), Ok(b)) => a == b,
        _ => Path::new(input) == out,
    };
    if same {
        return Err(BadInput(format!("{option} {} would overwrite the input; write elsewhere", out.display())));
    }
    Ok(())
}

fn diagram_mode(mode: &str, threshold: f64) -> Result<crate::viz::DiagramMode, BadInput> {
    use crate::viz::DiagramMode;
    Ok(match mode {
        "compression" => DiagramMode::Compression,
        "vectors" => DiagramMode::Vectors,
        "friction" if (0.0..=1.0).contains(&threshold) => DiagramMode::Friction { threshold },
        "friction" => return Err(BadInput(format!("--threshold {threshold} must be within [0, 1]"))),
        m => return Err(BadInput(format!("--mode {m}: expected compression, friction or vectors"))),
    })
}

#[cfg(not(feature = "viewer"))]
fn run_view(_: &ViewArgs) -> Result<i32, BadInput> {
    Err(BadInput(
        "this voussoir was built without the viewer: cargo run --release --features viewer -- view SCENE".into(),
    ))
}

#[cfg(feature = "viewer")]
fn run_view(args: &ViewArgs) -> Result<i32, BadInput> {
    use crate::viewer::{Script, ScriptStep, ViewerOptions};
    let mode = diagram_mode(&args.mode, args.threshold)?;
    let size = args
        .size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| (200..=10_000).contains(&w) && (150..=10_000).contains(&h))
        .ok_or_else(|| BadInput(format!("--size {}: expected WIDTHxHEIGHT, e.g. 1280x800", args.size)))?;
    let scene = load(args.scene.as_deref())?;
    if let Some(out) = &args.screenshot {
        refuse_overwrite(args.scene.as_deref(), out, "--screenshot")?;
    }
    let mut settings = AnalysisSettings::default();
    settings.statics.friction_model = args.friction_model;
    settings.statics.friction = args.mu;
    // A design that cannot be analysed is reported here, not as an empty window.
    crate::analysis::analyze(&scene, &settings)
        .map_err(|e| BadInput(format!("{}: {e}", args.scene.as_deref().unwrap_or("default scene"))))?;
    let mut options = ViewerOptions::new(scene);
    options.input = args.scene.as_ref().filter(|s| !s.starts_with("builtin:")).map(PathBuf::from);
    options.save_to = args.save.clone();
    options.save_over_input = args.save_over_input;
    options.mode = mode;
    options.translucent = !args.opaque;
    options.size = size;
    options.settings = settings;
    options.script = args
        .screenshot
        .as_ref()
        .map(|out| Script { steps: vec![ScriptStep::Settle(5), ScriptStep::Shot(out.clone())], report: None });
    let exit = crate::viewer::run(options);
    if let Some(out) = &args.screenshot {
        println!("screenshot written to {}", out.display());
    }
    Ok(if exit.is_success() { 0 } else { 1 })
}

fn run_export(args: &ExportArgs) -> Result<i32, BadInput> {
    let mode = diagram_mode(&args.mode, args.threshold)?;
    let scene = load(Some(&args.scene))?;
    for (out, option) in [(&args.gltf, "--gltf"), (&args.png, "--png")] {
        if let Some(out) = out {
            refuse_overwrite(Some(&args.scene), out, option)?;
        }
    }
    let mut settings = AnalysisSettings::default();
    settings.statics.friction_model = args.friction_model;
    settings.statics.friction = args.mu;
    let a = crate::analysis::analyze(&scene, &settings).map_err(|e| BadInput(format!("{}: {e}", args.scene)))?;
    let verdict = if a.statics.stands { "stands" } else { "does not stand" };
    if let Some(out) = &args.gltf {
        let bytes = crate::viz::glb(&a, mode);
        io::write_atomic(out, &bytes).map_err(|e| BadInput(e.to_string()))?;
        println!(
            "{}: {} blocks and {} interfaces written to {} ({} KB; the design {verdict})",
            args.scene,
            a.assembly.blocks.len(),
            a.statics.interfaces.len(),
            out.display(),
            bytes.len() / 1024
        );
    }
    if let Some(out) = &args.png {
        let picture = crate::plot::DiagramPicture::new(&a, mode);
        crate::plot::write_diagram(&picture, out).map_err(|e| BadInput(e.to_string()))?;
        println!("{}: {} diagram rendered to {} (the design {verdict})", args.scene, args.mode, out.display());
    }
    Ok(0)
}

fn run_sequence(args: &SequenceArgs) -> Result<i32, BadInput> {
    use crate::sequence::{OrderSpec, SearchSettings, check, check_with_props, search};
    if let Some(out) = &args.json {
        refuse_overwrite(Some(&args.scene), out, "--json")?;
    }
    let scene = load(Some(&args.scene))?;
    let spec = match args.order.as_deref() {
        Some("bottom-up") => OrderSpec::BottomUp,
        Some("from-supports") => OrderSpec::FromSupports,
        Some(list) => {
            OrderSpec::Given(list.split(',').map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect())
        }
        None if !scene.order.is_empty() => OrderSpec::Given(scene.order.clone()),
        None => OrderSpec::BottomUp,
    };
    let mut settings = AnalysisSettings::default();
    settings.statics.friction = args.mu;
    let drop = crate::dynamics::DropSettings { friction: args.mu, ..Default::default() };
    let dynamic = args.dynamic.then_some(&drop);
    let search_settings = SearchSettings { max_checks: args.max_checks, ..Default::default() };
    // The number of steps is known only after the cut history is replayed: a counting spinner.
    let bar = indicatif::ProgressBar::new_spinner();
    bar.set_style(
        indicatif::ProgressStyle::with_template("{spinner} {pos} {msg} ({elapsed})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    bar.set_message(if args.search { "static checks (searching an order)" } else { "steps checked" });
    let tick = || bar.inc(1);
    let report = if args.search {
        search(&scene, &settings, &search_settings, dynamic, &tick)
    } else if args.props {
        check_with_props(&scene, &spec, &settings, &search_settings, dynamic, &tick)
    } else {
        check(&scene, &spec, &settings, dynamic, &tick)
    };
    bar.finish_and_clear();
    let r = report.map_err(|e| BadInput(format!("{}: {e}", args.scene)))?;
    if let Some(info) = &r.search {
        let what = match (info.found, info.exhaustive) {
            (true, _) => "found an order in which every step stands".to_string(),
            (false, true) => "no order stands at every step (the search was exhaustive)".to_string(),
            (false, false) => format!("no standing order found within {} checks", info.checks),
        };
        println!("search: {what}; {} static checks, longest standing prefix {}", info.checks, info.deepest);
    }
    println!(
        "step  placed                 statics  tension      friction excess{}  props",
        if args.dynamic { "  drop test" } else { "" }
    );
    for (i, s) in r.steps.iter().enumerate() {
        let d = s.dynamic.as_ref().map(|d| if d.stands { "  stands" } else { "  falls " }).unwrap_or("");
        let word = if s.stands { "stands" } else { "FAILS " };
        println!(
            "{i:>4}  {:<22} {word}   {:.3e} W  {:.3e} W{d}  {}",
            s.placed,
            s.tension_ratio,
            s.friction_excess_ratio,
            s.props.join(", ")
        );
    }
    for p in &r.temporary_supports {
        println!("prop '{}' from step {} until step {}", p.block, p.from, p.until);
    }
    match r.first_failure {
        None if r.temporary_supports.is_empty() => println!("every step stands"),
        None => println!("every step stands with {} temporary support(s)", r.temporary_supports.len()),
        Some(k) => {
            let s = &r.steps[k];
            println!("first failure at step {k} ({}): {:?} {}", s.placed, s.verdict, s.offending.join(", "))
        }
    }
    if let Some(out) = &args.json {
        let json = serde_json::to_string_pretty(&r).unwrap_or_default();
        io::write_atomic(out, json.as_bytes()).map_err(|e| BadInput(e.to_string()))?;
    }
    let dyn_ok = r.steps.iter().all(|s| s.dynamic.as_ref().is_none_or(|d| d.stands));
    Ok(if r.stands_unpropped() && dyn_ok { 0 } else { 1 })
}

fn run_sweep(args: &SweepArgs) -> Result<i32, BadInput> {
    use crate::sweep::{Family, sweep};
    for (out, option) in [(&args.json, "--json"), (&args.plot, "--plot")] {
        if let Some(out) = out {
            refuse_overwrite(args.scene.as_deref(), out, option)?;
        }
    }
    let (family, lo, hi) = match args.family.as_str() {
        "arch" => (Family::Arch { n: args.n.unwrap_or(15) }, 0.02, 0.4),
        "slope" => (Family::Slope { mu: args.mu.unwrap_or(40f64.to_radians().tan()) }, 0.0, 80.0),
        "harmonic" => (Family::Harmonic { n: args.n.unwrap_or(6) }, 0.5, 1.5),
        "tilt" => {
            let scene = load(Some(args.scene.as_deref().ok_or_else(|| BadInput("tilt needs --scene".into()))?))?;
            (Family::Tilt { scene: Box::new(scene) }, 0.0, 60.0)
        }
        other => return Err(BadInput(format!("unknown family '{other}': arch, slope, harmonic or tilt"))),
    };
    let range = (args.lo.unwrap_or(lo), args.hi.unwrap_or(hi));
    if range.0.partial_cmp(&range.1) != Some(std::cmp::Ordering::Less) {
        return Err(BadInput(format!("--lo {} must be below --hi {}", range.0, range.1)));
    }
    let mut drop = crate::dynamics::DropSettings::default();
    drop.duration = args.duration.unwrap_or(drop.duration);
    let bar = indicatif::ProgressBar::new(2 * (args.iterations as u64 + 2));
    bar.set_message(format!("sweeping {}", args.family));
    let result = sweep(&family, range, args.iterations, &drop, &mut || bar.inc(1));
    bar.finish_and_clear();
    let r = result.map_err(|e| BadInput(e.to_string()))?;
    println!(
        "{}: statics threshold {:.5} (stands at {:.5}, falls at {:.5})",
        args.family,
        r.statics.mid(),
        r.statics.stands_at,
        r.statics.fails_at
    );
    println!(
        "{}: drop-test threshold {:.5} (stands at {:.5}, falls at {:.5})",
        args.family,
        r.dynamic.mid(),
        r.dynamic.stands_at,
        r.dynamic.fails_at
    );
    println!("gap (drop test − statics): {:+.5}, {} evaluations", r.gap, r.evaluations);
    if let Some(out) = &args.json {
        let json = serde_json::to_string_pretty(&r).unwrap_or_default();
        io::write_atomic(out, json.as_bytes()).map_err(|e| BadInput(e.to_string()))?;
    }
    if let Some(out) = &args.plot {
        let bar = indicatif::ProgressBar::new(args.points as u64);
        bar.set_message("scanning for the plot");
        let scan = crate::sweep::scan(&family, range, args.points, &drop, &mut || bar.inc(1));
        bar.finish_and_clear();
        let scan = scan.map_err(|e| BadInput(e.to_string()))?;
        let parameter = match args.family.as_str() {
            "arch" => "thickness t/R",
            "slope" => "slope angle (degrees)",
            "harmonic" => "overhang / critical overhang",
            _ => "ground tilt (degrees)",
        };
        let plot = crate::plot::SweepPlot {
            title: format!("{} sweep: statics vs drop test", args.family),
            parameter: parameter.into(),
            scan: &scan,
            result: Some(&r),
        };
        crate::plot::write_sweep(&plot, out).map_err(|e| BadInput(e.to_string()))?;
        println!("plot written to {}", out.display());
    }
    Ok(0)
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

/// The drop test beside the statics, with the disagreement flagged.
fn side_by_side(analysis: &Analysis, d: &crate::dynamics::DropResult) -> String {
    let s = &analysis.statics;
    let word = |b: bool| if b { "stands" } else { "falls" };
    let mut o = format!(
        "drop test (rapier, {:.2} s simulated in {:.2} s, {} steps): {}\n  largest drift {:.3e} of the block size, \
         largest rotation {:.3e} rad{}\n",
        d.simulated_s,
        d.wall_s,
        d.steps,
        word(d.stands),
        d.max_drift,
        d.max_rotation,
        d.worst_block.as_ref().map(|b| format!(" (worst: {b})")).unwrap_or_default()
    );
    if d.max_volume_error > 0.0 {
        o += &format!(
            "  colliders differ from the blocks by up to {:.2} % of a block's volume (hulls of curved or notched blocks, decompositions)\n",
            100.0 * d.max_volume_error
        );
    }
    if let Some([a, b]) = &d.initial_overlap_blocks {
        o += &format!(
            "  blocks {a} and {b} start overlapping by {:.2} % of a block's size (the input blocks overlap; rapier pushes them apart first, which counts as drift)\n",
            100.0 * d.max_initial_overlap
        );
    }
    o += &format!(
        "statics {} (tension {:.3e} W, friction excess {:.3e} W, utilisation {:.3}) | drop test {}: {}\n",
        word(s.stands),
        s.tension_ratio,
        s.friction_excess_ratio,
        s.max_friction_utilization,
        word(d.stands),
        disagreement(s.stands, d)
    );
    o
}

/// AGREE, or DISAGREE with what the drop test's motion suggests.
fn disagreement(statics_stand: bool, d: &crate::dynamics::DropResult) -> &'static str {
    match (statics_stand == d.stands, statics_stand, d.at_rest) {
        (true, _, _) => "AGREE",
        (false, false, _) => {
            "DISAGREE (the drop test held what the statics cannot: a margin within rapier's tolerances, or too short a run)"
        }
        (false, true, true) => {
            "DISAGREE (the blocks moved past the tolerance, then came to rest: rapier's soft contacts settling, or overlapping input — compare the margins)"
        }
        (false, true, false) => {
            "DISAGREE (still moving at the end: a failure the statics miss, or rapier near a limit — compare the margins)"
        }
    }
}

fn source_name(args: &AnalyzeArgs) -> String {
    args.scene.clone().unwrap_or_else(|| "default scene".into())
}

/// Human-readable summary: verdict first, then the graded numbers, then the worst interfaces.
pub fn summary(analysis: &Analysis, worst: usize) -> String {
    use std::fmt::Write;
    let a = &analysis.assembly;
    let s = &analysis.statics;
    let mut o = String::new();
    let verdict = match s.verdict {
        Verdict::Stands => "STANDS: compression and friction suffice".to_string(),
        Verdict::NeedsTension => "DOES NOT STAND: needs tension".to_string(),
        Verdict::NeedsFriction => "DOES NOT STAND: needs more friction".to_string(),
        Verdict::NeedsTensionAndFriction => "DOES NOT STAND: needs tension and more friction".to_string(),
        Verdict::Unsupported => "DOES NOT STAND: something touches no support".to_string(),
        Verdict::Unresolved => "UNRESOLVED: the solver did not converge".to_string(),
    };
    let supports = a.blocks.iter().filter(|b| b.support).count();
    let _ = writeln!(o, "{verdict}");
    let _ = writeln!(
        o,
        "  scene '{}': {} blocks ({} supports{}), {} interfaces, {} component(s)",
        a.name,
        a.blocks.len(),
        supports,
        if a.ground { ", ground plane" } else { "" },
        analysis.interfaces.len(),
        s.components
    );
    let _ = writeln!(
        o,
        "  free weight W = {:.6e} N, μ = {:.4} ({})",
        s.free_weight, s.friction_coefficient, s.friction_model
    );
    let _ = writeln!(o, "  minimum tension         {:.3e} W", s.tension_ratio);
    let _ = writeln!(o, "  minimum friction excess {:.3e} W", s.friction_excess_ratio);
    let _ = write!(o, "  max friction use        {:.1} % of μ·compression", 100.0 * s.max_friction_utilization);
    let _ = match s.friction_model {
        FrictionModel::Cone => writeln!(o),
        m => writeln!(o, " (|f_t| as a circle; {m} allows up to {:.1} %)", 100.0 * m.max_utilization()),
    };
    let _ = writeln!(
        o,
        "  solver: {} — {:?}, {} iterations, residual {:.2e} W",
        s.solver.backend,
        s.solver.status,
        s.solver.iterations,
        s.solver.residual / s.free_weight
    );
    for m in &s.solver.messages {
        let _ = writeln!(o, "  ! {m}");
    }
    let t = &analysis.timings;
    let _ = writeln!(
        o,
        "  time: validate {:.1} ms, detect {:.1} ms, assemble {:.1} ms, solve {:.1} ms (total {:.1} ms)",
        1e3 * t.validate,
        1e3 * t.detect,
        1e3 * t.assemble,
        1e3 * t.solve,
        1e3 * t.total
    );
    if !a.warnings.is_empty() {
        let _ = writeln!(o, "  {} repair warning(s), first: {}", a.warnings.len(), a.warnings[0]);
    }
    let mut ranked: Vec<_> = s.interfaces.iter().collect();
    ranked.sort_by(|x, y| {
        (y.tension, y.friction_excess, y.friction_utilization)
            .partial_cmp(&(x.tension, x.friction_excess, x.friction_utilization))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    if worst > 0 && !ranked.is_empty() {
        let _ = writeln!(o, "  worst interfaces (a → b: net normal, tension, friction use):");
        for r in ranked.iter().take(worst) {
            let _ = writeln!(
                o,
                "    {} → {}: {:.4e} N, tension {:.3e} N, friction {:.1} %",
                r.a,
                r.b,
                r.normal_force,
                r.tension,
                100.0 * r.friction_utilization
            );
        }
    }
    o
}
