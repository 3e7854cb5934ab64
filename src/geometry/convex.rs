//! Exact convex decomposition of a closed polygon mesh by splitting along its own face planes:
//! while some face plane has vertices of the piece clearly on its outer side, split the piece
//! by the plane that is most violated. Every split is exact ([`super::cut::split`]), so the
//! parts' volumes sum to the mesh's. For the slightly bent voussoirs of real vaults this gives
//! two or three parts (a general-purpose decomposition like V-HACD approximates them with
//! volume errors of 25 %).

use super::cut::{SplitResult, split};
use super::polygon::{Plane, area_vector};
use super::{Mesh, Point3};

/// The most violated face plane of `mesh` (vertices beyond it by more than `tol`), if any.
fn worst_plane(mesh: &Mesh, tol: f64) -> Option<Plane> {
    let mut best: Option<(f64, Plane)> = None;
    for face in &mesh.faces {
        let pts: Vec<Point3> = face.iter().map(|&i| mesh.vertices[i]).collect();
        let n = area_vector(&pts);
        if n.norm() == 0.0 {
            continue;
        }
        let plane = Plane::from_point_normal(&pts[0], &n);
        let beyond = mesh.vertices.iter().map(|p| plane.distance(p)).fold(0.0, f64::max);
        if beyond > tol && best.as_ref().is_none_or(|(b, _)| beyond > *b) {
            best = Some((beyond, plane));
        }
    }
    best.map(|(_, p)| p)
}

/// Convex parts of `mesh` (closed, outward, planar faces): convex up to `tol` (m), at most
/// `max_parts` of them; `None` when more would be needed.
pub fn convex_parts(mesh: &Mesh, tol: f64, max_parts: usize) -> Option<Vec<Mesh>> {
    let mut done = Vec::new();
    let mut todo = vec![mesh.clone()];
    while let Some(piece) = todo.pop() {
        let Some(plane) = worst_plane(&piece, tol) else {
            done.push(piece);
            continue;
        };
        match split(&piece, &plane, 0.1 * tol) {
            SplitResult::Pair { negative, positive } => todo.extend(negative.into_iter().chain(positive)),
            // The violation is below the split's snapping: treat the piece as convex.
            SplitResult::Negative | SplitResult::Positive => done.push(piece),
        }
        if done.len() + todo.len() > max_parts {
            return None;
        }
    }
    Some(done)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::MassProperties;

    #[test]
    fn l_prism_splits_into_two_exact_boxes() {
        let l = Mesh::extrude_z(&[[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]], 0.0, 1.0);
        let parts = convex_parts(&l, 1e-9, 8).unwrap();
        assert_eq!(parts.len(), 2);
        let v: f64 = parts.iter().map(|p| MassProperties::of_mesh(p).volume).sum();
        assert!((v - 3.0).abs() < 1e-12, "{v}");
        for p in &parts {
            assert!(worst_plane(p, 1e-9).is_none(), "each part is convex");
        }
    }

    #[test]
    fn convex_mesh_is_one_part_and_limits_are_kept() {
        let cube = Mesh::cuboid(Point3::origin(), Point3::new(1., 1., 1.));
        assert_eq!(convex_parts(&cube, 1e-9, 1).unwrap().len(), 1);
        let u =
            Mesh::extrude_z(&[[0., 0.], [3., 0.], [3., 2.], [2., 2.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]], 0., 1.);
        assert!(convex_parts(&u, 1e-9, 2).is_none(), "a U needs three parts");
        assert_eq!(convex_parts(&u, 1e-9, 8).unwrap().len(), 3);
    }
}
