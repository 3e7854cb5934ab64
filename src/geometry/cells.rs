//! A block's grid cells: its bounding box divided into k × k × k equal boxes, each clipped to
//! the block ([`super::cut::split`] by the grid's planes), with the mass properties of what
//! lies in each — the cells whose densities an infill design sets.
//!
//! Order: x fastest, then y, then z (cell (i, j, l) is `i + k j + k² l`). A cell the block does
//! not reach has volume 0. Units: m, m³; per unit density.

use super::cut::{SplitResult, split};
use super::mass::MassProperties;
use super::polygon::Plane;
use super::{Mesh, Point3, Vector3};

/// The k³ cells of `mesh` (closed, outward, planar faces); `eps` is the distance under which a
/// vertex lies on a grid plane.
pub fn grid(mesh: &Mesh, k: usize, eps: f64) -> Vec<MassProperties> {
    let empty = MassProperties { volume: 0.0, centroid: Point3::origin(), inertia: Default::default() };
    let aabb = mesh.aabb();
    let (lo, size) = (aabb.min, aabb.max - aabb.min);
    let mut pieces = vec![mesh.clone()];
    for axis in 0..3 {
        for i in 1..k {
            let mut n = Vector3::zeros();
            n[axis] = 1.0;
            let plane = Plane { normal: n, offset: lo[axis] + size[axis] * i as f64 / k as f64 };
            pieces = pieces.into_iter().flat_map(|p| halves(p, &plane, eps)).collect();
        }
    }
    let mut parts: Vec<Vec<(f64, MassProperties)>> = vec![Vec::new(); k * k * k];
    for p in &pieces {
        let m = MassProperties::of_mesh(p);
        let index = |axis: usize| {
            let t = (m.centroid[axis] - lo[axis]) / size[axis].max(f64::MIN_POSITIVE);
            ((t * k as f64).floor().max(0.0) as usize).min(k - 1)
        };
        parts[index(0) + k * index(1) + k * k * index(2)].push((1.0, m));
    }
    parts.iter().map(|p| MassProperties::combined(p).unwrap_or(empty)).collect()
}

/// The pieces of `mesh` on both sides of `plane` (the mesh itself when the plane misses it).
fn halves(mesh: Mesh, plane: &Plane, eps: f64) -> Vec<Mesh> {
    match split(&mesh, plane, eps) {
        SplitResult::Pair { mut negative, positive } => {
            negative.extend(positive);
            negative
        }
        SplitResult::Negative | SplitResult::Positive => vec![mesh],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: a box's octants are its eight half-boxes — an eighth of the volume each,
    /// centroids at the quarter points — and together give back the box's mass properties.
    #[test]
    fn a_box_has_eight_equal_octants() {
        let mesh = Mesh::cuboid(Point3::new(0.0, 0.0, 0.0), Point3::new(2.0, 1.0, 4.0));
        let cells = grid(&mesh, 2, 1e-9);
        assert_eq!(cells.len(), 8);
        for (c, m) in cells.iter().enumerate() {
            assert!((m.volume - 1.0).abs() < 1e-12, "{c}: {}", m.volume);
            let want =
                Point3::new(0.5 + (c & 1) as f64, 0.25 + 0.5 * ((c >> 1) & 1) as f64, 1.0 + 2.0 * (c >> 2) as f64);
            assert!((m.centroid - want).norm() < 1e-12, "{c}: {:?}", m.centroid);
        }
        let whole = MassProperties::combined(&cells.iter().map(|m| (1.0, *m)).collect::<Vec<_>>()).unwrap();
        let direct = MassProperties::of_mesh(&mesh);
        assert!((whole.centroid - direct.centroid).norm() < 1e-12);
        assert!((whole.inertia - direct.inertia).norm() < 1e-9 * direct.inertia.norm());
    }
}
