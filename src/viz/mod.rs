//! What the diagrams show, without a window: the seed paper's colour mappings (pure functions),
//! the per-vertex colours of an interface, and the glTF export. The offscreen pictures
//! ([`crate::plot::diagram`]) and the bevy viewer (feature `viewer`) use the same colours.

pub mod colors;
pub mod gltf;

pub use gltf::glb;

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
