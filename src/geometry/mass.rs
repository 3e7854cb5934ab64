//! Exact mass properties of closed polyhedra by the divergence theorem.
//!
//! Each face is fanned into triangles; each triangle with a reference point spans a signed
//! tetrahedron whose volume, first and second moments have closed forms (Tonon 2004). The fan
//! of a planar polygon is an exact signed decomposition, so non-convex faces and non-convex
//! solids are handled exactly. Values are per unit density: multiply by the density for mass
//! and inertia. Units: m³, m, m⁵.

use super::{Mesh, Point3, Vector3};
use nalgebra::Matrix3;

/// Volume, volume centroid and inertia tensor about the centroid (per unit density).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Volume, m³.
    pub volume: f64,
    /// Volume centroid, m.
    pub centroid: Point3,
    /// Inertia tensor about the centroid, world axes, for density 1 (kg·m² per kg/m³).
    pub inertia: Matrix3<f64>,
}

impl MassProperties {
    /// Mass properties of a closed, outward-oriented mesh. The volume is negative for an
    /// inward-oriented mesh; the centroid is the vertex mean when the volume vanishes.
    pub fn of_mesh(mesh: &Mesh) -> Self {
        // Reference point inside the bounding box keeps the cancellation small.
        let aabb = mesh.aabb();
        let o = if aabb.is_empty() { Point3::origin() } else { nalgebra::center(&aabb.min, &aabb.max) };
        let mut vol6 = 0.0; // 6 V
        let mut first24 = Vector3::zeros(); // 24 ∫x dV
        let mut second120 = Matrix3::zeros(); // 120 ∫x xᵀ dV
        for face in &mesh.faces {
            if face.len() < 3 {
                continue;
            }
            let a = mesh.vertices[face[0]] - o;
            for k in 1..face.len() - 1 {
                let b = mesh.vertices[face[k]] - o;
                let c = mesh.vertices[face[k + 1]] - o;
                let det = a.dot(&b.cross(&c));
                let s = a + b + c;
                vol6 += det;
                first24 += s * det;
                second120 += (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose()) * det;
            }
        }
        let volume = vol6 / 6.0;
        if volume == 0.0 {
            let mean: Vector3 =
                mesh.vertices.iter().map(|p| p.coords).sum::<Vector3>() / mesh.vertices.len().max(1) as f64;
            return Self { volume, centroid: Point3::from(mean), inertia: Matrix3::zeros() };
        }
        let c_rel = first24 / 24.0 / volume;
        // Second moment about the centroid: ∫(x−c)(x−c)ᵀ = ∫x xᵀ − V c cᵀ.
        let cov = second120 / 120.0 - c_rel * c_rel.transpose() * volume;
        let inertia = Matrix3::identity() * cov.trace() - cov;
        Self { volume, centroid: o + c_rel, inertia }
    }

    /// The mass properties of parts with densities `weights` (relative: the result is per unit
    /// of their volume-weighted mean), combined: weighted volume, centroid and inertia, each
    /// part's inertia moved to the common centroid (parallel axes). `None` when the weighted
    /// volume is not positive.
    pub fn combined(parts: &[(f64, MassProperties)]) -> Option<Self> {
        let mass: f64 = parts.iter().map(|(w, p)| w * p.volume).sum();
        let volume: f64 = parts.iter().map(|(_, p)| p.volume).sum();
        if !(mass > 0.0 && volume > 0.0) {
            return None;
        }
        let mean = mass / volume;
        let centroid = parts.iter().map(|(w, p)| p.centroid.coords * (w * p.volume)).sum::<Vector3>() / mass;
        let inertia = parts
            .iter()
            .map(|(w, p)| {
                let d = p.centroid.coords - centroid;
                (p.inertia + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * p.volume) * (w / mean)
            })
            .sum();
        Some(Self { volume, centroid: Point3::from(centroid), inertia })
    }
}
