//! `voussoir view`: the interactive viewer (cargo feature `viewer`); without the feature the
//! command says how to build it.

use super::BadInput;
use super::options::{DiagramOptions, SceneOptions, SolverOptions};
use clap::Args;
use std::path::PathBuf;

/// The options of `voussoir view`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct ViewArgs {
    /// Scene file or `builtin:…` (default: the embedded default scene).
    pub scene: Option<String>,
    /// The diagram mode and its threshold.
    #[command(flatten)]
    pub diagram: DiagramOptions,
    /// The solver options the design is analysed with.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// Supports, ground and density given on the command line.
    #[command(flatten)]
    pub scene_options: SceneOptions,
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
    #[arg(long, default_value = "1280x800", value_parser = window_size)]
    pub size: (u32, u32),
    /// No interaction: render, save a screenshot of the window here (PNG), exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
}

/// `WIDTHxHEIGHT`, each within what a window can be.
fn window_size(text: &str) -> Result<(u32, u32), String> {
    text.split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| (200..=10_000).contains(&w) && (150..=10_000).contains(&h))
        .ok_or_else(|| "expected WIDTHxHEIGHT, e.g. 1280x800, at least 200x150".to_string())
}

/// Without the viewer feature: says how to build it; exit code 2.
#[cfg(not(feature = "viewer"))]
pub fn run(_: &ViewArgs) -> Result<i32, BadInput> {
    Err(BadInput(
        "this voussoir was built without the viewer: cargo run --release --features viewer -- view SCENE".into(),
    ))
}

/// Why no window can open here, if none can: on Linux and the BSDs the viewer needs an X11
/// or Wayland display (bevy's window would panic without one).
pub fn missing_display(var: impl Fn(&str) -> Option<std::ffi::OsString>) -> Option<String> {
    let unix_desktop = cfg!(all(unix, not(target_os = "macos"), not(target_os = "ios"), not(target_os = "android")));
    let set = |name: &str| var(name).is_some_and(|v| !v.is_empty());
    (unix_desktop && !set("DISPLAY") && !set("WAYLAND_DISPLAY")).then(|| {
        "no display: the viewer needs a window, and neither DISPLAY nor WAYLAND_DISPLAY is set \
         (run it under xvfb-run, e.g. `xvfb-run -a voussoir view ...`)"
            .to_string()
    })
}

/// Runs `view`: opens the window (or writes `--screenshot`); exit code 0, 2 without a display.
#[cfg(feature = "viewer")]
pub fn run(args: &ViewArgs) -> Result<i32, BadInput> {
    use super::{load, refuse_overwrite, scene_name};
    use crate::viewer::{Script, ScriptStep, ViewerOptions};
    let mode = args.diagram.mode()?;
    let mut scene = load(args.scene.as_deref())?;
    if let Some(out) = &args.screenshot {
        refuse_overwrite(args.scene.as_deref(), out, "--screenshot")?;
    }
    let settings = args.solver.settings();
    args.scene_options.apply(&mut scene, &settings)?;
    // A design that cannot be analysed is reported here, not as an empty window.
    crate::pipeline::analyze(&scene, &settings)
        .map_err(|e| BadInput(format!("{}: {e}", scene_name(args.scene.as_deref()))))?;
    if let Some(why) = missing_display(|name| std::env::var_os(name)) {
        return Err(BadInput(why));
    }
    let mut options = ViewerOptions::new(scene);
    options.input = args.scene.as_ref().filter(|s| !s.starts_with("builtin:")).map(PathBuf::from);
    options.save_to = args.save.clone();
    options.save_over_input = args.save_over_input;
    options.mode = mode;
    options.translucent = !args.opaque;
    options.size = args.size;
    options.settings = settings;
    options.script = args
        .screenshot
        .as_ref()
        .map(|out| Script { steps: vec![ScriptStep::Settle(5), ScriptStep::Shot(out.clone())], report: None });
    let exit = crate::viewer::run(options);
    match (&args.screenshot, exit.is_success()) {
        (Some(out), true) => println!("screenshot written to {}", out.display()),
        (Some(out), false) => {
            eprintln!("error: the viewer stopped before the screenshot: {} not written", out.display())
        }
        (None, _) => {}
    }
    Ok(if exit.is_success() { 0 } else { 1 })
}
