//! Pattern generation (`synthesis::pattern`, `decompose --strategy pattern`): a running bond on
//! the outer surface extruded to an apex.
//!
//! Invariants: every joint between two generated pieces lies in a plane through the apex (to
//! 1e-9 of the model size); the pieces fill the shape (volume conserved to 1e-9); the Fig 9
//! box generated this way stands, as the seed's hand-drawn `assets/cases/fig9a_box.json` does;
//! a dome shell is cut into a staggered bond whose head joints do not run through two courses;
//! an apex inside the shape is one clear error.

use crate::common::*;
use voussoir::geometry::{MassProperties, Mesh, Point3};
use voussoir::interfaces::Body;
use voussoir::model::{Block, Scene};
use voussoir::pipeline::{Analysis, AnalysisSettings};
use voussoir::statics::Verdict;
use voussoir::synthesis::{BlockSize, Generated, pattern};

/// The Fig 9 box as a source shape (its cut history dropped).
fn fig9_box() -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases/fig9a_box.json");
    let mut scene = voussoir::io::load_scene(&path).unwrap();
    scene.cuts.clear();
    scene
}

/// The largest distance of the apex from the plane of a joint between two free pieces,
/// relative to the model size.
fn apex_offset(a: &Analysis, apex: [f64; 3]) -> f64 {
    let free = |b: Body| b.block().is_some_and(|id| !a.assembly.block(id).support);
    a.interfaces
        .iter()
        .filter(|i| free(i.a) && free(i.b))
        .map(|i| (Point3::from(apex) - i.frame.origin).dot(&i.frame.n).abs() / a.assembly.scale)
        .fold(0.0, f64::max)
}

fn volume(blocks: &[Block]) -> f64 {
    blocks.iter().filter(|b| !b.support).map(|b| MassProperties::of_mesh(&b.mesh).volume).sum()
}

fn generated_volume(g: &Generated) -> f64 {
    let (resolved, _) = voussoir::history::resolve(&g.design, &Default::default(), &mut Default::default()).unwrap();
    volume(&resolved.blocks)
}

#[test]
fn the_fig9_box_generated_by_pattern_stands_with_every_joint_through_the_apex() {
    let apex = [0.0, 0.0, -1.0];
    let shape = fig9_box();
    let g = pattern(&shape, apex, &BlockSize::Max(0.5), true).expect("a pattern");
    assert_eq!(g.design.cuts.len(), 1, "one pattern cut in the history");
    assert!(g.pieces >= 8, "{} pieces", g.pieces);
    assert_close(generated_volume(&g), volume(&shape.blocks), 1e-9 * volume(&shape.blocks), "volume");
    let a = run(&g.design, &AnalysisSettings::default());
    let joints = a.interfaces.iter().filter(|i| i.a.block().is_some() && i.b.block().is_some()).count();
    assert!(joints >= g.pieces - 1, "{joints} joints between {} pieces", g.pieces);
    assert!(apex_offset(&a, apex) <= 1e-9, "joint off the apex by {}", apex_offset(&a, apex));
    assert_eq!(a.statics.verdict, Verdict::Stands, "as fig9a_box does");
}

/// A spherical shell (radius `r` to the outer surface, thickness `t`) from an oculus of
/// half-angle `oculus` (degrees from the top) down to the springing at z = 0, meshed with planar
/// trapezoids: `lat` rings, `lon` segments.
fn dome_shell(r: f64, t: f64, oculus: f64, lat: usize, lon: usize) -> Mesh {
    let ring = |k: usize| oculus.to_radians() + (90.0 - oculus).to_radians() * k as f64 / lat as f64;
    let at = |radius: f64, k: usize, j: usize| {
        let (psi, phi) = (ring(k), std::f64::consts::TAU * j as f64 / lon as f64);
        Point3::new(radius * psi.sin() * phi.cos(), radius * psi.sin() * phi.sin(), radius * psi.cos())
    };
    let mut vertices = Vec::new();
    for radius in [r, r - t] {
        for k in 0..=lat {
            for j in 0..lon {
                vertices.push(at(radius, k, j));
            }
        }
    }
    let id = |inner: bool, k: usize, j: usize| inner as usize * (lat + 1) * lon + k * lon + j % lon;
    let mut faces = Vec::new();
    for k in 0..lat {
        for j in 0..lon {
            faces.push(vec![id(false, k, j), id(false, k + 1, j), id(false, k + 1, j + 1), id(false, k, j + 1)]);
            faces.push(vec![id(true, k, j), id(true, k, j + 1), id(true, k + 1, j + 1), id(true, k + 1, j)]);
        }
    }
    for j in 0..lon {
        faces.push(vec![id(false, 0, j), id(false, 0, j + 1), id(true, 0, j + 1), id(true, 0, j)]);
        faces.push(vec![id(false, lat, j), id(true, lat, j), id(true, lat, j + 1), id(false, lat, j + 1)]);
    }
    Mesh::new(vertices, faces)
}

/// The test dome: R 1, t 0.12, a 20° oculus, springing on the ground.
fn dome() -> Scene {
    let mut shape = Scene::new("dome", vec![Block::new("dome", dome_shell(1.0, 0.12, 20.0, 6, 32))]);
    shape.ground = true;
    shape
}

#[test]
fn a_dome_is_cut_into_a_bond_converging_on_its_apex() {
    let shape = dome();
    let apex = [0.0, 0.0, -0.6];
    let g = pattern(&shape, apex, &BlockSize::Count(40), true).expect("a pattern");
    assert!((25..=80).contains(&g.pieces), "{} pieces for about 40", g.pieces);
    assert_close(generated_volume(&g), volume(&shape.blocks), 1e-9 * volume(&shape.blocks), "volume");
    let a = run(&g.design, &AnalysisSettings::default());
    assert!(apex_offset(&a, apex) <= 1e-9, "joint off the apex by {}", apex_offset(&a, apex));
    assert_ne!(a.statics.verdict, Verdict::Unresolved);
}

/// Invariant: with the apex just below the sphere's centre (1 % of the radius: the apex must lie
/// outside the shape, which springs from z = 0) every generated joint is nearly radial (the
/// masonry dome's own beds and heads), and the dome — t/R 0.12, from a 20° oculus to the
/// springing on the ground, well above the least thickness of a hemispherical dome (~0.042 R)
/// — stands by compression and friction.
#[test]
fn a_dome_cut_towards_its_centre_stands() {
    let shape = dome();
    let apex = [0.0, 0.0, -0.01];
    let g = pattern(&shape, apex, &BlockSize::Count(40), true).expect("a pattern");
    let a = run(&g.design, &AnalysisSettings::default());
    assert!(apex_offset(&a, apex) <= 1e-9, "joint off the apex by {}", apex_offset(&a, apex));
    assert_eq!(a.statics.verdict, Verdict::Stands, "{} pieces", g.pieces);
}

#[test]
fn an_apex_inside_the_shape_is_an_error() {
    let e = pattern(&fig9_box(), [0.0, 0.0, 0.4], &BlockSize::Max(0.5), true).unwrap_err().to_string();
    assert!(e.contains("behind the apex") || e.contains("centre"), "{e}");
}
