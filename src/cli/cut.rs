//! `voussoir cut`: one plane or pattern cut appended to the scene's cut history, the design
//! written elsewhere (never over the input).

use super::{BadInput, load, numbers, refuse_overwrite, write_output};
use crate::io::scene_json;
use crate::model::{Cut, Scene};
use clap::Args;
use std::collections::HashSet;
use std::path::PathBuf;

/// The options of `voussoir cut`.
#[derive(Args, Debug, Clone, PartialEq)]
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

/// Runs `cut`: writes the design with the cut appended; exit code 0.
pub fn run(args: &CutArgs) -> Result<i32, BadInput> {
    let mut scene = load(Some(&args.scene))?;
    let cut = the_cut(args)?;
    let resolve = |scene: &Scene| {
        crate::history::resolve(scene, &Default::default(), &mut Default::default())
            .map(|(resolved, _)| resolved)
            .map_err(|e| BadInput(format!("{}: {e}", args.scene)))
    };
    let before = resolve(&scene)?;
    scene.cuts.push(Cut { target: args.target.clone(), ..cut });
    let after = resolve(&scene)?;
    let old: HashSet<&str> = before.blocks.iter().map(|b| b.name.as_str()).collect();
    let new: Vec<&str> = after.blocks.iter().map(|b| b.name.as_str()).filter(|n| !old.contains(n)).collect();
    if new.is_empty() {
        println!("the cut misses every piece it may cut: the design is unchanged (the cut is recorded)");
    } else {
        println!("cut {}: {} new pieces: {}", scene.cuts.len() - 1, new.len(), new.join(", "));
    }
    refuse_overwrite(Some(&args.scene), &args.output, "-o")?;
    write_output(&args.output, scene_json::scene_to_string(&scene).as_bytes())?;
    println!(
        "design written to {} ({} blocks after {} cuts)",
        args.output.display(),
        after.blocks.len(),
        scene.cuts.len()
    );
    Ok(0)
}

/// The cut `--plane`, or `--apex` with its `--segment`s, describe (without its target).
fn the_cut(args: &CutArgs) -> Result<Cut, BadInput> {
    match (&args.plane, &args.apex) {
        (Some(plane), _) => {
            let [px, py, pz, nx, ny, nz] = numbers::<6>("--plane", plane, "px,py,pz,nx,ny,nz")?;
            Ok(Cut::plane([px, py, pz], [nx, ny, nz]))
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
            Ok(Cut::pattern(apex, segments))
        }
        (None, None) => Err(BadInput("give --plane or --apex with --segment".into())),
    }
}
