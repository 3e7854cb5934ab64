//! Invariant: interface detection finds exactly the face contacts with positive overlap area,
//! with the exact overlap polygon and area, the a→b normal, and is independent of units.

use crate::common::*;
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::interfaces::{Body, detect};
use voussoir::model::{Block, BlockId, Scene};

fn two(a: Block, b: Block) -> Scene {
    Scene::new("t", vec![a, b])
}

#[test]
fn stacked_unit_cubes_one_interface_of_area_one() {
    let s = two(cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [0.0, 0.0, 1.0], 1.0));
    let asm = assembly(&s);
    let ifs = detect(&asm);
    assert_eq!(ifs.len(), 1);
    let i = &ifs[0];
    assert_close(i.area, 1.0, 1e-12, "area");
    assert_eq!((i.a, i.b), (Body::Block(BlockId(0)), Body::Block(BlockId(1))));
    assert!((i.frame.n - Vector3::z()).norm() < 1e-12, "normal from a (below) into b: {}", i.frame.n);
    assert!((i.centroid() - Point3::new(0.5, 0.5, 1.0)).norm() < 1e-12);
    assert_eq!(i.polygon.len(), 4);
    // CCW about n.
    let area = voussoir::geometry::polygon::area_vector(&i.polygon);
    assert!(area.dot(&i.frame.n) > 0.0);
}

#[test]
fn offset_cubes_partial_overlap_exact_area() {
    // b shifted by (0.3, 0.6): overlap 0.7 × 0.4.
    let s = two(cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [0.3, 0.6, 1.0], 1.0));
    let ifs = detect(&assembly(&s));
    assert_eq!(ifs.len(), 1);
    assert_close(ifs[0].area, 0.28, 1e-12, "area");
    assert!((ifs[0].centroid() - Point3::new(0.65, 0.8, 1.0)).norm() < 1e-12);
}

#[test]
fn non_convex_faces_give_non_convex_overlap() {
    // Two L prisms, the upper one mirrored: the overlap of the L footprints is itself an L
    // with area 2 (the 2×1 bar of one L plus the square of the other, sharing one cell).
    let l = [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]];
    let l_mirror: Vec<[f64; 2]> = [[2., 2.], [0., 2.], [0., 1.], [1., 1.], [1., 0.], [2., 0.]].to_vec();
    // l_mirror is the L rotated by 180° about (1, 1): cells (1,1)x... intersection = cells
    // {(0,1) , (1,0) , (1,1)?}: compute by cells: L covers (0,0),(1,0),(0,1); mirror covers
    // (1,1),(0,1),(1,0). Shared cells: (1,0) and (0,1), which touch only at a corner: two
    // disjoint pieces of area 1 each.
    let a = Block::new("a", Mesh::extrude_z(&l, 0.0, 1.0));
    let b = Block::new("b", Mesh::extrude_z(&l_mirror, 1.0, 2.0));
    let ifs = detect(&assembly(&two(a, b)));
    assert_eq!(ifs.len(), 2, "two disjoint overlap pieces");
    for i in &ifs {
        assert_close(i.area, 1.0, 1e-12, "piece area");
    }
    // Same L on an L shifted by (0.5, 0.5): overlap is a genuinely non-convex hexagon.
    let shifted: Vec<[f64; 2]> = l.iter().map(|p| [p[0] + 0.5, p[1] + 0.5]).collect();
    let a = Block::new("a", Mesh::extrude_z(&l, 0.0, 1.0));
    let b = Block::new("b", Mesh::extrude_z(&shifted, 1.0, 2.0));
    let ifs = detect(&assembly(&two(a, b)));
    assert_eq!(ifs.len(), 1);
    // Cells of size 0.5: L = 12 cells; shifted L ∩ L: rows y∈[.5,1): x∈[.5,2) 3 cells; y∈[1,1.5):
    // L has x∈[0,1), shifted has x∈[.5,1.5): x∈[.5,1) 1 cell; y∈[1.5,2): L x∈[0,1), shifted
    // x∈[.5,1.5): 1 cell → 5 cells of 0.25 = 1.25.
    assert_close(ifs[0].area, 1.25, 1e-12, "L ∩ shifted L");
    assert_eq!(ifs[0].polygon.len(), 6, "non-convex hexagon: {:?}", ifs[0].polygon);
}

#[test]
fn u_face_under_a_slab_gives_the_u() {
    // A U-shaped prism under a wide slab: the overlap is the (non-convex) U itself.
    let u = [[0., 0.], [3., 0.], [3., 3.], [2., 3.], [2., 1.], [1., 1.], [1., 3.], [0., 3.]];
    let a = Block::new("a", Mesh::extrude_z(&u, 0.0, 1.0));
    let b = cuboid("b", [-1.0, -1.0, 1.0], [4.0, 4.0, 2.0]);
    let ifs = detect(&assembly(&two(a, b)));
    assert_eq!(ifs.len(), 1);
    assert_close(ifs[0].area, 9.0 - 2.0, 1e-12, "U area");
    assert_eq!(ifs[0].polygon.len(), 8);
}

#[test]
fn edge_or_point_contact_is_no_interface() {
    // Touching along an edge (b on top, shifted by exactly 1 in x) and at a corner.
    let edge = two(cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [1.0, 0.0, 1.0], 1.0));
    assert!(detect(&assembly(&edge)).is_empty());
    let corner = two(cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [1.0, 1.0, 1.0], 1.0));
    assert!(detect(&assembly(&corner)).is_empty());
    // Side by side sharing a face is an interface (vertical normal along x).
    let side = two(cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [1.0, 0.0, 0.0], 1.0));
    let ifs = detect(&assembly(&side));
    assert_eq!(ifs.len(), 1);
    assert!((ifs[0].frame.n - Vector3::x()).norm() < 1e-12);
}

#[test]
fn gap_threshold_follows_the_relative_tolerance() {
    let tol = voussoir::geometry::Tolerances::default();
    // Model size: bounding-box diagonal of the two cubes plus the gap.
    let scene_with_gap = |gap: f64| two(cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [0.0, 0.0, 1.0 + gap], 1.0));
    let diag = |gap: f64| (2.0f64 + (2.0 + gap) * (2.0 + gap)).sqrt();
    let limit = tol.coplanar * diag(0.0);
    assert_eq!(detect(&assembly(&scene_with_gap(0.9 * limit))).len(), 1, "gap below tolerance");
    assert_eq!(detect(&assembly(&scene_with_gap(1.1 * limit))).len(), 0, "gap just above tolerance");
}

#[test]
fn tilt_beyond_angle_tolerance_is_no_interface() {
    let tol = voussoir::geometry::Tolerances::default();
    // A narrow post and a narrow plate on it tilted about the post's centre line (x = 0.5):
    // 1 cm wide, so the faces stay within the coplanar distance and only the angle decides.
    let tilted = |deg: f64| {
        let t = deg.to_radians();
        let plate = Mesh::cuboid(Point3::new(0.49, 0.0, 1.0), Point3::new(0.51, 1.0, 1.01)).map_points(|p| {
            let (x, z) = (p.x - 0.5, p.z - 1.0);
            Point3::new(0.5 + x * t.cos() - z * t.sin(), p.y, 1.0 + x * t.sin() + z * t.cos())
        });
        two(cuboid("a", [0.49, 0.0, 0.0], [0.51, 1.0, 1.0]), Block::new("b", plate))
    };
    assert_eq!(detect(&assembly(&tilted(0.8 * tol.angle_deg))).len(), 1);
    assert_eq!(detect(&assembly(&tilted(1.2 * tol.angle_deg))).len(), 0);
}

#[test]
fn millimetres_and_metres_give_the_same_interfaces() {
    let build = |s: f64| {
        let blocks = vec![
            cuboid("base", [0.0, 0.0, 0.0], [3.0 * s, 1.0 * s, 0.5 * s]),
            cuboid("left", [0.2 * s, 0.0, 0.5 * s], [1.4 * s, 1.0 * s, 1.0 * s]),
            cuboid("right", [1.4 * s, 0.2 * s, 0.5 * s], [2.9 * s, 0.9 * s, 1.0 * s]),
            cuboid("top", [0.7 * s, 0.1 * s, 1.0 * s], [2.1 * s, 0.8 * s, 1.3 * s]),
        ];
        Scene::new("units", blocks)
    };
    let m = detect(&assembly(&build(1.0)));
    let mm = detect(&assembly(&build(1000.0)));
    assert_eq!(m.len(), mm.len());
    assert_eq!(m.len(), 5);
    for (a, b) in m.iter().zip(&mm) {
        assert_eq!((a.a, a.b), (b.a, b.b));
        assert_close(b.area / 1e6, a.area, 1e-12 * a.area, "area scales by 1e6");
        assert!((b.frame.n - a.frame.n).norm() < 1e-12);
    }
}

#[test]
fn ground_plane_supports_faces_on_it() {
    let mut s = Scene::new("g", vec![cube("a", [0.0, 0.0, 0.0], 1.0), cube("b", [2.0, 0.0, 0.5], 1.0)]);
    s.ground = true;
    let ifs = detect(&assembly(&s));
    assert_eq!(ifs.len(), 1, "only the cube on z = 0");
    assert_eq!((ifs[0].a, ifs[0].b), (Body::Ground, Body::Block(BlockId(0))));
    assert!((ifs[0].frame.n - Vector3::z()).norm() < 1e-12);
    assert_close(ifs[0].area, 1.0, 1e-12, "area");
}

#[test]
fn support_to_support_contacts_are_skipped() {
    let s = two(cube("a", [0.0, 0.0, 0.0], 1.0).support(true), cube("b", [0.0, 0.0, 1.0], 1.0).support(true));
    assert!(detect(&assembly(&s)).is_empty());
}
