//! What the diagrams show, without a window: the seed paper's colour mappings (pure functions),
//! the per-vertex colours of an interface, and the glTF export. The offscreen pictures
//! ([`crate::plot::diagram`]) and the bevy viewer (feature `viewer`) use the same colours.

pub mod colors;
pub mod gltf;

pub use gltf::glb;

use crate::analysis::Analysis;
use crate::statics::InterfaceResult;
use colors::Rgb;

/// Which diagram colours the interfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DiagramMode {
    /// Blue compression, red tension, grey nothing, normalised per face.
    Compression,
    /// Grey / yellow up to `threshold` of the capacity / orange / red beyond μ.
    Friction { threshold: f64 },
    /// Force arrows (resultants, relative magnitude) over the compression colours.
    Vectors,
}

/// The colour of every force point of `r` (in `r.vertices` order) in `mode`; `mu` is the
/// friction coefficient the statics used.
pub fn vertex_colors(r: &InterfaceResult, mu: f64, mode: DiagramMode) -> Vec<Rgb> {
    match mode {
        DiagramMode::Compression | DiagramMode::Vectors => {
            let net: Vec<f64> = r.vertices.iter().map(|v| v.compression - v.tension).collect();
            let face_max = net.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            net.iter().map(|&n| colors::compression_tension(n, face_max)).collect()
        }
        DiagramMode::Friction { threshold } => r
            .vertices
            .iter()
            .map(|v| colors::friction(v.friction_u.hypot(v.friction_v), mu * v.compression, threshold))
            .collect(),
    }
}

/// The colour legend of `mode`: what each colour means, in the order drawn.
pub fn legend(mode: DiagramMode) -> Vec<(Rgb, &'static str)> {
    match mode {
        DiagramMode::Friction { .. } => vec![
            (colors::GREY, "no friction"),
            (colors::YELLOW, "below the threshold"),
            (colors::friction(0.99, 1.0, 0.0), "up to μ (orange)"),
            (colors::RED, "exceeds μ"),
        ],
        _ => vec![
            (colors::compression_tension(1.0, 1.0), "compression (max of face)"),
            (colors::compression_tension(0.2, 1.0), "compression (20 %)"),
            (colors::GREY, "no compression"),
            (colors::compression_tension(-1.0, 1.0), "tension"),
        ],
    }
}

/// A triangle of force points: world position (m, z up) and colour.
pub type ColouredTriangle = [([f64; 3], Rgb); 3];

/// Every loaded interface of `analysis` with its `a | b` label, triangulated over its force
/// points and coloured by `mode`: what both exports draw.
pub fn interface_triangles(analysis: &Analysis, mode: DiagramMode) -> Vec<(String, Vec<ColouredTriangle>)> {
    let s = &analysis.statics;
    s.interfaces
        .iter()
        .filter(|r| r.vertices.len() >= 3)
        .map(|r| (format!("{} | {}", r.a, r.b), triangles(r, &vertex_colors(r, s.friction_coefficient, mode))))
        .collect()
}

/// The force points of `r` triangulated in the interface plane (its `u`, `v` axes), each
/// corner with its colour from `colours` (in `r.vertices` order): what the exports and the
/// viewer draw. Empty when the interface has fewer than three force points.
pub fn triangles(r: &InterfaceResult, colours: &[Rgb]) -> Vec<ColouredTriangle> {
    if r.vertices.len() < 3 {
        return Vec::new();
    }
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let p2: Vec<[f64; 2]> = r.vertices.iter().map(|v| [dot(v.position, r.u), dot(v.position, r.v)]).collect();
    crate::geometry::polygon::triangulate_2d(&p2, &[])
        .into_iter()
        .map(|t| t.map(|k| (r.vertices[k].position, colours[k])))
        .collect()
}
