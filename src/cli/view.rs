//! `voussoir view`: the interactive viewer (cargo feature `viewer`); without the feature the
//! command says how to build it.

use super::BadInput;
use super::options::{DiagramOptions, SolverOptions};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug, Clone, PartialEq)]
pub struct ViewArgs {
    /// Scene file or `builtin:…` (default: the embedded default scene).
    pub scene: Option<String>,
    #[command(flatten)]
    pub diagram: DiagramOptions,
    #[command(flatten)]
    pub solver: SolverOptions,
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

#[cfg(not(feature = "viewer"))]
pub fn run(_: &ViewArgs) -> Result<i32, BadInput> {
    Err(BadInput(
        "this voussoir was built without the viewer: cargo run --release --features viewer -- view SCENE".into(),
    ))
}

#[cfg(feature = "viewer")]
pub fn run(args: &ViewArgs) -> Result<i32, BadInput> {
    use super::{load, refuse_overwrite, scene_name};
    use crate::viewer::{Script, ScriptStep, ViewerOptions};
    let mode = args.diagram.mode()?;
    let scene = load(args.scene.as_deref())?;
    if let Some(out) = &args.screenshot {
        refuse_overwrite(args.scene.as_deref(), out, "--screenshot")?;
    }
    let settings = args.solver.settings();
    // A design that cannot be analysed is reported here, not as an empty window.
    crate::pipeline::analyze(&scene, &settings)
        .map_err(|e| BadInput(format!("{}: {e}", scene_name(args.scene.as_deref()))))?;
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
    if let Some(out) = &args.screenshot {
        println!("screenshot written to {}", out.display());
    }
    Ok(if exit.is_success() { 0 } else { 1 })
}
