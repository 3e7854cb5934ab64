//! What the diagrams show, without a window: the seed paper's colour mappings (pure functions),
//! the per-vertex colours of an interface, the glTF export, and the self-contained HTML report
//! ([`html`]). The offscreen pictures ([`crate::viz::plot::diagram`]) and the bevy viewer
//! (feature `viewer`) use the same colours.

pub mod colors;
pub mod gltf;
pub mod html;
pub mod plot;

pub use gltf::glb;

use crate::pipeline::Analysis;
use crate::statics::{FrictionModel, InterfaceResult};
use colors::Rgb;

/// The largest motion of a drawn mechanism, as a fraction of the model size (the PNG export
/// and the viewer's motion pane exaggerate every mechanism to it).
pub const EXAGGERATION: f64 = 0.08;

/// The factor that draws `mechanism` at [`EXAGGERATION`] (`None` when nothing moves).
pub fn mechanism_scale(mechanism: &crate::statics::Mechanism, assembly: &crate::model::Assembly) -> Option<f64> {
    let largest = mechanism.largest_motion(assembly);
    (largest > 0.0).then(|| EXAGGERATION * assembly.scale / largest)
}

/// The normal of the plane a mechanism moves in, horizontal (`None` when it does not move in
/// one vertical plane): the common axis of its blocks' rotations, else the horizontal normal of
/// its translations.
pub fn mechanism_plane(
    m: &crate::statics::Mechanism,
    assembly: &crate::model::Assembly,
) -> Option<nalgebra::Vector3<f64>> {
    use nalgebra::{Matrix3, SymmetricEigen, Vector3};
    let outer = |vs: &mut dyn Iterator<Item = Vector3<f64>>| vs.fold(Matrix3::zeros(), |s, v| s + v * v.transpose());
    let size = assembly.scale.max(f64::MIN_POSITIVE);
    let rotations = outer(&mut m.blocks.iter().map(|b| Vector3::from(b.rotation) * size));
    let translations = outer(&mut m.blocks.iter().map(|b| Vector3::from(b.translation)));
    // Planar: one dominant direction (of the rotation axes, or of the translations' normal).
    let dominant = |s: Matrix3<f64>| -> Option<Vector3<f64>> {
        let e = SymmetricEigen::new(s);
        let k = e.eigenvalues.imax();
        let total: f64 = e.eigenvalues.iter().map(|x| x.abs()).sum();
        (total > 0.0 && e.eigenvalues[k] >= 0.9 * total).then(|| e.eigenvectors.column(k).into_owned())
    };
    let normal = if rotations.trace() >= 1e-3 * translations.trace() {
        dominant(rotations)?
    } else {
        // A vertical translation (a block dropping) lies in every vertical plane: none chosen.
        let along = dominant(translations).filter(|d| d.z.abs() < 0.9)?;
        along.cross(&Vector3::z())
    };
    let horizontal = Vector3::new(normal.x, normal.y, 0.0);
    (horizontal.norm() > 0.9 * normal.norm() && normal.norm() > 0.0).then(|| horizontal.normalize())
}

/// Which diagram colours the interfaces (default: compression–tension).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum DiagramMode {
    /// Blue compression, red tension, grey nothing, normalised per face.
    #[default]
    Compression,
    /// Grey / yellow up to `threshold` of the capacity / orange / red beyond μ.
    Friction {
        /// The share of the friction capacity μN up to which a joint is yellow (0.5 by default).
        threshold: f64,
    },
    /// Force arrows (resultants, relative magnitude) over the compression colours.
    Vectors,
}

impl DiagramMode {
    /// The friction diagram's "low friction" limit unless one is given (`--threshold`, the
    /// viewer's key 2): half of μ · compression.
    pub const DEFAULT_THRESHOLD: f64 = 0.5;
}

/// The colour of every force point of `r` (in `r.vertices` order) in `mode`; `mu` and `model`
/// are the friction coefficient and model the statics used. The friction diagram gives every
/// point of an interface its interface's colour ([`friction_band`]).
pub fn vertex_colors(r: &InterfaceResult, mu: f64, model: FrictionModel, mode: DiagramMode) -> Vec<Rgb> {
    match mode {
        DiagramMode::Compression | DiagramMode::Vectors => {
            let net: Vec<f64> = r.vertices.iter().map(|v| v.compression - v.tension).collect();
            let face_max = net.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            net.iter().map(|&n| colors::compression_tension(n, face_max)).collect()
        }
        DiagramMode::Friction { threshold } => {
            vec![friction_band(r, mu, model, threshold).colour(threshold); r.vertices.len()]
        }
    }
}

/// The friction band of interface `r` (the seed paper's one colour per interface): its
/// resultant's use u = |F_t| / (μ · compression) ([`InterfaceResult::friction_utilization`], the
/// number the reports print) against `threshold`; exceeded where the friction model is (some
/// point's friction beyond its capacity by more than 1e-6 of the interface's capacity, or the
/// resultant beyond μN as the model measures it) or friction acts without compression.
pub fn friction_band(r: &InterfaceResult, mu: f64, model: FrictionModel, threshold: f64) -> colors::FrictionBand {
    let capacity = mu * r.compression;
    let (fu, fv) = r.vertices.iter().fold((0.0, 0.0), |(u, v), p| (u + p.friction_u, v + p.friction_v));
    let noise = colors::ZERO_SHARE * capacity.max(r.friction);
    let exceeded = r.friction_excess > noise || model_friction(model, fu, fv) > capacity + noise;
    colors::FrictionBand::of(r.friction_utilization, exceeded, threshold)
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
pub fn legend(mode: DiagramMode) -> Vec<(Rgb, String)> {
    use colors::FrictionBand;
    match mode {
        DiagramMode::Friction { threshold } => vec![
            (colors::GREY, "no friction".into()),
            (colors::YELLOW, format!("friction ≤ {threshold:.2} μN")),
            (
                FrictionBand::High(0.5 * (1.0 + threshold)).colour(threshold),
                format!("{threshold:.2}–1 μN, deeper near μ"),
            ),
            (colors::RED, "beyond μN: slides".into()),
        ],
        _ => vec![
            (colors::compression_tension(1.0, 1.0), "compression (max of face)".into()),
            (colors::compression_tension(0.2, 1.0), "compression (20 %)".into()),
            (colors::GREY, "no compression".into()),
            (colors::compression_tension(-1.0, 1.0), "tension".into()),
        ],
    }
}

/// A triangle of force points: world position (m, z up) and colour.
pub type ColouredTriangle = [([f64; 3], Rgb); 3];

/// Every loaded interface of `analysis` with its index in `statics.interfaces` and its `a | b`
/// label, triangulated over its force points and coloured by `mode`: what both exports draw.
pub fn interface_triangles(analysis: &Analysis, mode: DiagramMode) -> Vec<(usize, String, Vec<ColouredTriangle>)> {
    let s = &analysis.statics;
    s.interfaces
        .iter()
        .enumerate()
        .filter(|(_, r)| r.vertices.len() >= 3)
        .map(|(k, r)| {
            (
                k,
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
    use colors::FrictionBand;

    /// An interface of force points (compression, f_u, f_v, excess), its sums as the statics
    /// collect them.
    fn face(points: &[(f64, f64, f64, f64)], mu: f64) -> InterfaceResult {
        let vertices: Vec<VertexForce> = points
            .iter()
            .enumerate()
            .map(|(k, &(compression, friction_u, friction_v, friction_excess))| VertexForce {
                position: [k as f64, (k * k) as f64, 0.0],
                compression,
                tension: 0.0,
                friction_u,
                friction_v,
                friction_excess,
            })
            .collect();
        let compression: f64 = vertices.iter().map(|v| v.compression).sum();
        let (fu, fv) = vertices.iter().fold((0.0, 0.0), |(u, v), p| (u + p.friction_u, v + p.friction_v));
        let friction = fu.hypot(fv);
        let friction_utilization = if friction == 0.0 {
            0.0
        } else if compression == 0.0 {
            f64::INFINITY
        } else {
            friction / (mu * compression)
        };
        InterfaceResult {
            index: 0,
            a: "a".into(),
            b: "b".into(),
            area: 1.0,
            normal: [0.0, 0.0, 1.0],
            u: [1.0, 0.0, 0.0],
            v: [0.0, 1.0, 0.0],
            vertices,
            normal_force: compression,
            compression,
            tension: 0.0,
            friction,
            friction_excess: points.iter().map(|p| p.3).sum(),
            friction_utilization,
            resultant: [fu, fv, compression],
            resultant_point: None,
        }
    }

    const FRICTION: DiagramMode = DiagramMode::Friction { threshold: 0.5 };

    /// Invariant: the friction diagram gives an interface one colour, its resultant's band —
    /// the paper's rule — whatever its points do one by one.
    #[test]
    fn one_colour_per_interface_from_its_resultant() {
        let mu = 0.6;
        let model = FrictionModel::Pyramid8;
        // u = 0.3 overall though one point carries 0.9 of its own capacity: yellow everywhere.
        let r = face(&[(1.0, 0.54, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0)], mu);
        assert!((r.friction_utilization - 0.3).abs() < 1e-12);
        assert_eq!(vertex_colors(&r, mu, model, FRICTION), vec![colors::YELLOW; 3]);
        // u = 0.7: one orange, between the light and the deep end.
        let r = face(&[(1.0, 0.42, 0.0, 0.0), (1.0, 0.42, 0.0, 0.0)], mu);
        let colours = vertex_colors(&r, mu, model, FRICTION);
        assert_eq!(colours[0], colours[1]);
        assert_eq!(friction_band(&r, mu, model, 0.5), FrictionBand::High(r.friction_utilization));
        assert_eq!(colours[0], FrictionBand::High(0.7).colour(0.5));
        // No friction: grey; friction without compression: red.
        assert_eq!(vertex_colors(&face(&[(1.0, 0.0, 0.0, 0.0); 3], mu), mu, model, FRICTION), vec![colors::GREY; 3]);
        let r = face(&[(0.0, 0.3, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0)], mu);
        assert_eq!(vertex_colors(&r, mu, model, FRICTION), vec![colors::RED; 2]);
    }

    /// Invariant: red exactly where the friction model is exceeded — by a point's excess beyond
    /// solver noise, or by the resultant as the model measures it.
    #[test]
    fn friction_is_red_only_beyond_what_the_model_allows() {
        let mu = 0.5;
        // A point beyond its capacity (the solver's excess) turns the interface red even when
        // its resultant is low; an excess at round-off (1e-12 of the capacity) does not.
        let r = face(&[(1.0, 0.6, 0.0, 0.1), (1.0, 0.0, 0.0, 0.0)], mu);
        assert_eq!(friction_band(&r, mu, FrictionModel::Pyramid8, 0.5), FrictionBand::Exceeded);
        let r = face(&[(1.0, 0.2, 0.0, 1e-12), (1.0, 0.0, 0.0, 0.0)], mu);
        assert_eq!(friction_band(&r, mu, FrictionModel::Pyramid8, 0.5), FrictionBand::Low(0.2));
        // 1.05 μN at 22.5°: inside the 8-sided pyramid (its corner is at 1/cos 22.5° = 1.0824
        // μN) and the box (max(|F_u|, |F_v|) = 0.970 μN): deep orange; beyond the cone: red.
        let (m, a) = (1.05, 22.5f64.to_radians());
        let r = face(&[(1.0, mu * m * a.cos(), mu * m * a.sin(), 0.0)], mu);
        assert_eq!(friction_band(&r, mu, FrictionModel::Cone, 0.5), FrictionBand::Exceeded);
        for model in [FrictionModel::Pyramid8, FrictionModel::Box4] {
            assert_eq!(friction_band(&r, mu, model, 0.5).colour(0.5), FrictionBand::High(1.0).colour(0.5), "{model}");
        }
        assert!((model_friction(FrictionModel::Pyramid8, m * a.cos(), m * a.sin()) - 0.970074).abs() < 1e-6);
    }
}

#[cfg(test)]
mod plane_tests {
    use super::mechanism_plane;
    use crate::statics::{BlockMotion, Mechanism};

    fn mechanism(blocks: Vec<([f64; 3], [f64; 3])>) -> Mechanism {
        Mechanism {
            blocks: blocks
                .into_iter()
                .enumerate()
                .map(|(k, (translation, rotation))| BlockMotion { block: format!("b{k}"), translation, rotation })
                .collect(),
            interfaces: Vec::new(),
            uniqueness: Default::default(),
            moving: Vec::new(),
            motion: Vec::new(),
        }
    }

    /// Invariant: an arch's blocks turning about axes parallel to y move in the x–z plane: the
    /// pane looks along ±y; a block sliding along x alone, too; a torsion about z has no
    /// vertical plane.
    #[test]
    fn the_pane_looks_square_to_the_mechanisms_plane() {
        let arch = crate::model::builtin("arch?n=5").unwrap();
        let a = crate::pipeline::analyze(&arch, &Default::default()).unwrap().assembly;
        let n =
            mechanism_plane(&mechanism(vec![([0.1, 0.0, 0.02], [0.0, 0.3, 0.0]), ([0.0; 3], [0.0, -0.2, 0.0])]), &a)
                .unwrap();
        assert!((n.y.abs() - 1.0).abs() < 1e-9, "{n:?}");
        let n = mechanism_plane(&mechanism(vec![([0.1, 0.0, 0.0], [0.0; 3])]), &a).unwrap();
        assert!((n.y.abs() - 1.0).abs() < 1e-9, "{n:?}");
        assert!(mechanism_plane(&mechanism(vec![([0.0; 3], [0.0, 0.0, 0.5])]), &a).is_none());
        assert!(mechanism_plane(&mechanism(vec![([0.01, 0.0, -1.0], [0.0; 3])]), &a).is_none(), "a block dropping");
    }
}
