//! `voussoir export`: the analysed design without a window, as a glTF binary and/or a
//! picture of the diagram.

use super::options::{DiagramOptions, SolverOptions};
use super::{BadInput, load, refuse_overwrite, write_output};
use clap::Args;
use std::path::PathBuf;

/// The options of `voussoir export`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct ExportArgs {
    /// Scene file or `builtin:…`.
    pub scene: String,
    /// Write a glTF binary (.glb) here (atomically; never over the input).
    #[arg(long, required_unless_present = "png")]
    pub gltf: Option<PathBuf>,
    /// Render the diagram offscreen to a picture here (.png or .svg; atomically).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// The diagram mode and its threshold.
    #[command(flatten)]
    pub diagram: DiagramOptions,
    /// The solver options the design is analysed with.
    #[command(flatten)]
    pub solver: SolverOptions,
}

/// Runs `export`: writes the glTF and the picture asked for; exit code 0.
pub fn run(args: &ExportArgs) -> Result<i32, BadInput> {
    let mode = args.diagram.mode()?;
    let scene = load(Some(&args.scene))?;
    for (out, option) in [(&args.gltf, "--gltf"), (&args.png, "--png")] {
        if let Some(out) = out {
            refuse_overwrite(Some(&args.scene), out, option)?;
        }
    }
    let a = crate::pipeline::analyze(&scene, &args.solver.settings())
        .map_err(|e| BadInput(format!("{}: {e}", args.scene)))?;
    let verdict = if a.statics.stands { "stands" } else { "does not stand" };
    if let Some(out) = &args.gltf {
        let bytes = crate::viz::glb(&a, mode);
        write_output(out, &bytes)?;
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
        let picture = crate::viz::plot::DiagramPicture::new(&a, mode);
        crate::viz::plot::write_diagram(&picture, out).map_err(|e| BadInput(e.to_string()))?;
        println!("{}: {} diagram rendered to {} (the design {verdict})", args.scene, args.diagram.mode, out.display());
    }
    Ok(0)
}
