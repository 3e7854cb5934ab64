//! What the diagrams show, without a window: the seed paper's colour mappings (pure functions),
//! the per-vertex colours of an interface, and the glTF export. The offscreen pictures
//! ([`crate::viz::plot::diagram`]) and the bevy viewer (feature `viewer`) use the same colours.

pub mod colors;
pub mod gltf;
pub mod plot;

pub use gltf::glb;

use crate::pipeline::Analysis;
use crate::statics::{FrictionModel, InterfaceResult};
use colors::Rgb;

/// Which diagram colours the interfaces (default: compression–tension).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum DiagramMode {
    /// Blue compression, red tension, grey nothing, normalised per face.
    #[default]
    Compression,
    /// Grey / yellow up to `threshold` of the capacity / orange / red beyond μ.
    Friction { threshold: f64 },
    /// Force arrows (resultants, relative magnitude) over the compression colours.
    Vectors,
}

impl DiagramMode {
    /// The friction diagram's "low friction" limit unless one is given (`--threshold`, the
    /// viewer's key 2): half of μ · compression.
    pub const DEFAULT_THRESHOLD: f64 = 0.5;
}

/// The colour of every force point of `r` (in `r.vertices` order) in `mode`; `mu` and `model`
/// are the friction coefficient and model the statics used.
///
/// Friction is measured as the model bounds it, so that red means beyond what the model allows
/// (the 8-sided pyramid allows up to 8.2 % more than the cone on its diagonals): the cone
/// |f_t|, the box max(|f_u|, |f_v|), the pyramid max(|f_u|, |f_v|, (|f_u| + |f_v|)/√2), each
/// against μ·compression. Friction below 1e-6 of the face's largest friction or capacity is
/// solver noise and shows grey.
pub fn vertex_colors(r: &InterfaceResult, mu: f64, model: FrictionModel, mode: DiagramMode) -> Vec<Rgb> {
    match mode {
        DiagramMode::Compression | DiagramMode::Vectors => {
            let net: Vec<f64> = r.vertices.iter().map(|v| v.compression - v.tension).collect();
            let face_max = net.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            net.iter().map(|&n| colors::compression_tension(n, face_max)).collect()
        }
        DiagramMode::Friction { threshold } => {
            let measured: Vec<(f64, f64)> = r
                .vertices
                .iter()
                .map(|v| (model_friction(model, v.friction_u, v.friction_v), mu * v.compression))
                .collect();
            let scale = measured.iter().fold(0.0f64, |m, &(f, c)| m.max(f).max(c));
            measured
                .iter()
                .map(
                    |&(f, c)| {
                        if f <= colors::ZERO_SHARE * scale { colors::GREY } else { colors::friction(f, c, threshold) }
                    },
                )
                .collect()
        }
    }
}

/// The friction of a force point as `model` bounds it (≤ μ·compression when within the model).
pub fn model_friction(model: FrictionModel, fu: f64, fv: f64) -> f64 {
    let (u, v) = (fu.abs(), fv.abs());
    match model {
        FrictionModel::Cone => u.hypot(v),
        FrictionModel::Box4 => u.max(v),
        FrictionModel::Pyramid8 => u.max(v).max((u + v) / std::f64::consts::SQRT_2),
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
        .map(|r| {
            (
                format!("{} | {}", r.a, r.b),
                triangles(r, &vertex_colors(r, s.friction_coefficient, s.friction_model, mode)),
            )
        })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::VertexForce;

    fn face(points: &[(f64, f64, f64)]) -> InterfaceResult {
        let vertices = points
            .iter()
            .enumerate()
            .map(|(k, &(compression, friction_u, friction_v))| VertexForce {
                position: [k as f64, (k * k) as f64, 0.0],
                compression,
                tension: 0.0,
                friction_u,
                friction_v,
                friction_excess: 0.0,
            })
            .collect();
        InterfaceResult {
            index: 0,
            a: "a".into(),
            b: "b".into(),
            area: 1.0,
            normal: [0.0, 0.0, 1.0],
            u: [1.0, 0.0, 0.0],
            v: [0.0, 1.0, 0.0],
            vertices,
            normal_force: 0.0,
            compression: 0.0,
            tension: 0.0,
            friction: 0.0,
            friction_excess: 0.0,
            friction_utilization: 0.0,
            resultant: [0.0; 3],
            resultant_point: None,
        }
    }

    #[test]
    fn friction_is_red_only_beyond_what_the_model_allows() {
        // 1.08 μc at 22.5°: inside the 8-sided pyramid (its corner is at 1/cos 22.5° = 1.0824)
        // and inside the box (max(|f_u|, |f_v|) = 0.998 μc), beyond the cone.
        let (mu, m, a) = (0.5, 1.08, 22.5f64.to_radians());
        let r = face(&[(1.0, mu * m * a.cos(), mu * m * a.sin()), (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]);
        let mode = DiagramMode::Friction { threshold: 0.5 };
        let colour = |model| vertex_colors(&r, mu, model, mode)[0];
        assert_eq!(colour(FrictionModel::Cone), colors::RED);
        assert_ne!(colour(FrictionModel::Pyramid8), colors::RED);
        assert_ne!(colour(FrictionModel::Box4), colors::RED);
        assert!((model_friction(FrictionModel::Pyramid8, m * a.cos(), m * a.sin()) - 0.99779).abs() < 1e-5);
        // On the diagonal the pyramid is the cone: 1.01 μc is beyond both.
        let d = 1.01 * mu / 2f64.sqrt();
        let r = face(&[(1.0, d, d), (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]);
        assert_eq!(vertex_colors(&r, mu, FrictionModel::Pyramid8, mode)[0], colors::RED);
    }

    #[test]
    fn solver_noise_is_no_friction() {
        // A force point without compression whose friction is 1e-9 of the face's capacity:
        // noise, grey — not "friction without compression" red.
        let r = face(&[(0.0, 1e-9, 0.0), (2.0, 0.1, 0.0), (2.0, 0.0, 0.0)]);
        let colours = vertex_colors(&r, 0.5, FrictionModel::Pyramid8, DiagramMode::Friction { threshold: 0.5 });
        assert_eq!(colours[0], colors::GREY);
        assert_eq!(colours[1], colors::YELLOW, "0.1 of a 1.0 capacity is low friction");
        assert_eq!(colours[2], colors::GREY);
        // Real friction without compression stays red.
        let r = face(&[(0.0, 0.3, 0.0), (2.0, 0.1, 0.0), (2.0, 0.0, 0.0)]);
        let colours = vertex_colors(&r, 0.5, FrictionModel::Pyramid8, DiagramMode::Friction { threshold: 0.5 });
        assert_eq!(colours[0], colors::RED);
    }
}
