//! Invariant: every kind of bad input gives one clear error naming the file, block and face
//! (or vertex) — never a panic, never a silent wrong answer.

use crate::common::*;
use std::path::PathBuf;
use voussoir::geometry::{Mesh, Point3};
use voussoir::io::load_scene;
use voussoir::model::{Assembly, Block, ModelError, Scene};

fn write(name: &str, content: &[u8]) -> PathBuf {
    let p = crate::common::scratch("bad-input").join(name);
    std::fs::write(&p, content).unwrap();
    p
}

fn model_error(mesh: Mesh) -> String {
    let s = Scene::new("bad", vec![Block::new("culprit", mesh)]);
    let e = Assembly::new(&s, &Default::default()).expect_err("must be rejected");
    let msg = e.to_string();
    assert!(msg.contains("block 'culprit'"), "names the block: {msg}");
    msg
}

fn unit() -> Mesh {
    Mesh::cuboid(Point3::origin(), Point3::new(1.0, 1.0, 1.0))
}

#[test]
fn empty_mesh() {
    assert!(model_error(Mesh::default()).contains("empty"));
}

#[test]
fn non_finite_vertex() {
    let mut m = unit();
    m.vertices[3].y = f64::NAN;
    let msg = model_error(m);
    assert!(msg.contains("vertex 3") && msg.contains("non-finite"), "{msg}");
    let mut m = unit();
    m.vertices[5].z = f64::INFINITY;
    assert!(model_error(m).contains("vertex 5"));
}

#[test]
fn index_out_of_range_and_short_face() {
    let mut m = unit();
    m.faces[2][1] = 99;
    let msg = model_error(m);
    assert!(msg.contains("face 2") && msg.contains("99"), "{msg}");
    let mut m = unit();
    m.faces[4] = vec![0, 1];
    let msg = model_error(m);
    assert!(msg.contains("face 4") && msg.contains("at least 3"), "{msg}");
}

#[test]
fn open_mesh_names_the_face_and_edge() {
    let mut m = unit();
    m.faces.remove(1);
    let msg = model_error(m);
    assert!(msg.contains("not closed") && msg.contains("face"), "{msg}");
}

#[test]
fn non_manifold_edge() {
    // Two cubes sharing one edge through a third face pair: add a duplicate face.
    let mut m = unit();
    let extra = m.faces[0].clone();
    m.faces.push(extra.iter().rev().cloned().collect());
    m.faces.push(extra);
    let msg = model_error(m);
    assert!(msg.contains("not manifold"), "{msg}");
}

#[test]
fn zero_volume_is_rejected() {
    // A flat box (all z = 0): closed and manifold but no volume.
    let m = Mesh::cuboid(Point3::origin(), Point3::new(1.0, 1.0, 1.0)).map_points(|p| Point3::new(p.x, p.y, 0.0));
    let msg = model_error(m);
    assert!(msg.contains("volume") || msg.contains("collapsed") || msg.contains("closed"), "{msg}");
}

#[test]
fn inverted_orientation_is_repaired_with_a_warning() {
    let mut m = unit();
    m.faces.iter_mut().for_each(|f| f.reverse());
    let s = Scene::new("inv", vec![Block::new("flipped", m)]);
    let a = Assembly::new(&s, &Default::default()).unwrap();
    assert_close(a.blocks[0].mass.volume, 1.0, 1e-12, "volume after repair");
    assert_eq!(a.warnings.len(), 1);
    assert!(a.warnings[0].to_string().contains("flipped"), "{}", a.warnings[0]);
}

#[test]
fn one_inconsistent_face_is_flipped_with_a_warning() {
    let mut m = unit();
    m.faces[3].reverse();
    let s = Scene::new("one", vec![Block::new("b", m)]);
    let a = Assembly::new(&s, &Default::default()).unwrap();
    assert_close(a.blocks[0].mass.volume, 1.0, 1e-12, "volume after repair");
    assert!(a.warnings.iter().any(|w| w.to_string().contains("flipped 1 faces")), "{:?}", a.warnings);
}

#[test]
fn duplicate_vertices_are_welded() {
    // Every face gets its own copies of its corners (24 vertices for a cube).
    let u = unit();
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for f in &u.faces {
        let start = vertices.len();
        vertices.extend(f.iter().map(|&i| u.vertices[i]));
        faces.push((start..start + f.len()).collect());
    }
    let s = Scene::new("soup", vec![Block::new("soup", Mesh::new(vertices, faces))]);
    let a = Assembly::new(&s, &Default::default()).unwrap();
    assert_eq!(a.blocks[0].mesh.vertices.len(), 8);
    assert_close(a.blocks[0].mass.volume, 1.0, 1e-12, "volume");
}

#[test]
fn non_planar_face_is_triangulated_with_a_warning() {
    let mut m = unit();
    // Lift one top corner by 10 % of the size along z: the side faces through it stay planar,
    // the top face deviates by 0.033, above the default 1e-2 × model size ≈ 0.018.
    let top = m.faces[1][0];
    m.vertices[top].z += 0.1;
    let s = Scene::new("np", vec![Block::new("warped", m)]);
    let a = Assembly::new(&s, &Default::default()).unwrap();
    let triangulated = a.warnings.iter().filter(|w| w.to_string().contains("not planar")).count();
    assert_eq!(triangulated, 1, "{:?}", a.warnings);
    assert_eq!(a.blocks[0].mesh.faces.len(), 5 + 2, "the top quad became two triangles");
}

#[test]
fn duplicate_and_empty_names_bad_density() {
    let s = Scene::new("dup", vec![Block::new("x", unit()), Block::new("x", unit())]);
    assert_eq!(Assembly::new(&s, &Default::default()).unwrap_err(), ModelError::DuplicateName("x".into()));
    let s = Scene::new("empty", vec![Block::new("", unit())]);
    assert!(matches!(Assembly::new(&s, &Default::default()), Err(ModelError::EmptyName(0))));
    let mut b = Block::new("heavy", unit());
    b.density = Some((-1.0).into());
    let e = Assembly::new(&Scene::new("d", vec![b]), &Default::default()).unwrap_err();
    assert!(e.to_string().contains("'heavy'") && e.to_string().contains("density"), "{e}");
    assert!(matches!(Assembly::new(&Scene::new("none", vec![]), &Default::default()), Err(ModelError::NoBlocks)));
}

#[test]
fn file_errors_name_the_file() {
    let cases: Vec<(&str, &[u8], &str)> = vec![
        ("broken.json", b"{\"blocks\": [", "not valid JSON"),
        ("typo.json", b"{\"blocks\": [], \"frictoin\": 0.5}", "frictoin"),
        ("schema.json", b"{\"schema\": 99, \"blocks\": []}", "schema 99"),
        ("shape.json", b"{\"blocks\": [{\"name\": \"a\", \"vertices\": [[0,0]], \"faces\": []}]}", "not a voussoir scene"),
        ("compas.json", b"{\"data\": {\"graph\": {\"data\": {\"node\": {\"0\": {\"block\": {\"data\": {\"vertex\": {\"0\": {\"x\": 1}}, \"face\": {}}}}}}}}}", "vertex '0' has no numeric 'y'"),
        ("bad.obj", b"v 0 0 0\nv 1 0 0\nf 1 2 7\n", "bad.obj"),
        ("empty.stl", b"solid x\nendsolid x\n", "empty.stl"),
        ("garbage.stl", b"\x00\x01\x02", "garbage.stl"),
        ("scene.xyz", b"", "unknown file type"),
    ];
    for (name, content, expect) in cases {
        let p = write(name, content);
        let e = load_scene(&p).expect_err(name).to_string();
        assert!(e.contains(name), "{name}: error names the file: {e}");
        assert!(e.contains(expect), "{name}: expected '{expect}' in: {e}");
    }
    let missing = load_scene(std::path::Path::new("/nonexistent/scene.json")).unwrap_err().to_string();
    assert!(missing.contains("/nonexistent/scene.json") && missing.contains("cannot read"), "{missing}");
}

#[test]
fn mesh_errors_from_files_name_file_and_block() {
    // An OBJ with an open box: the error from the analysis names the block (the CLI adds the
    // file); the block name comes from the `o` line.
    let obj = b"o lid_missing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    let p = write("open.obj", obj);
    let scene = load_scene(&p).unwrap();
    let e = Assembly::new(&scene, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("block 'lid_missing'") && e.contains("not closed"), "{e}");
}

#[test]
fn a_reference_length_sets_the_model_size_and_a_bad_one_is_named() {
    let s = Scene::new("one", vec![Block::new("b", unit())]);
    let mut t = voussoir::geometry::Tolerances::default();
    assert_close(Assembly::new(&s, &t).unwrap().scale, 3f64.sqrt(), 1e-12, "the bounding-box diagonal");
    t.reference_length = Some(20.0);
    let a = Assembly::new(&s, &t).unwrap();
    assert_eq!((a.scale, a.tolerances.coplanar), (20.0, 20.0 * t.coplanar));
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        t.reference_length = Some(bad);
        let e = Assembly::new(&s, &t).expect_err("rejected");
        assert!(matches!(e, ModelError::BadReferenceLength(_)) && e.to_string().contains("reference length"), "{e}");
    }
}

/// Issue #44's reproducers (the fuzz targets `mesh` and `stl`): a model whose vertices all
/// coincide, far from the origin, once overflowed the weld grid's cell arithmetic (its size was
/// taken as 1 m, the weld tolerance 1e-7 m, the cell index past i64). Now it is one clear error
/// naming the block and the point, before any tolerance is derived.
#[test]
fn a_model_at_one_point_is_named_not_welded() {
    let p = Point3::new(-41255400907263.99, 5.96e-212, 5.96e-212);
    let point = Mesh::new(vec![p], vec![vec![0, 0, 0, 0, 0]]);
    let msg = model_error(point);
    assert!(msg.contains("vertices (1) all lie at one point"), "{msg}");

    let stl =
        std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/fuzz/regressions/stl/weld-overflow-one-point-triangle"))
            .expect("the kept reproducer");
    let path = write("one-point.stl", &stl);
    let scene = load_scene(&path).expect("a readable STL");
    let e = Assembly::new(&scene, &Default::default()).expect_err("a point is no block").to_string();
    assert!(e.contains("all lie at one point"), "{e}");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_voussoir"))
        .args(["analyze", path.to_str().expect("utf-8 path")])
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "bad input: {stderr}");
    assert!(
        stderr.contains("one-point.stl") && stderr.contains("one point") && stderr.lines().count() == 1,
        "{stderr}"
    );
}

/// Invariant: the weld grid cannot overflow whatever the coordinates (within the accepted
/// ±1e15) and the tolerance: a block far from the origin, and a valid block beside a
/// degenerate one at the limit, are welded or refused with a message, never a panic.
#[test]
fn the_weld_grid_holds_at_the_coordinate_limit() {
    let far = voussoir::geometry::Vector3::new(9.9e14, -9.9e14, 9.9e14);
    let mut cube = unit();
    cube.vertices.iter_mut().for_each(|p| *p += far);
    let s = Scene::new("far", vec![Block::new("far", cube)]);
    let a = Assembly::new(&s, &Default::default()).expect("a unit cube at 1e15 is still a cube");
    assert_eq!(a.blocks[0].mesh.vertices.len(), 8);
    let tol = voussoir::geometry::Tolerances::default().resolve(1e-15);
    let r = voussoir::geometry::repair(&unit(), &tol).expect("a cube welded with a tiny tolerance");
    assert_eq!(r.mesh.vertices.len(), 8, "no vertex merged");
}

/// Invariant: a tolerance that is not a finite number in its range is named, not used.
#[test]
fn bad_tolerances_are_named() {
    let s = Scene::new("one", vec![Block::new("b", unit())]);
    type Set = fn(&mut voussoir::geometry::Tolerances);
    let cases: [(&str, Set); 6] = [
        ("weld", |t| t.weld = 0.0),
        ("planarity", |t| t.planarity = f64::NAN),
        ("coplanar", |t| t.coplanar = -1e-3),
        ("min_area", |t| t.min_area = f64::INFINITY),
        ("angle_deg", |t| t.angle_deg = 0.0),
        ("angle_deg", |t| t.angle_deg = 120.0),
    ];
    for (name, set) in cases {
        let mut t = voussoir::geometry::Tolerances::default();
        set(&mut t);
        let e = Assembly::new(&s, &t).expect_err(name).to_string();
        assert!(e.contains(&format!("tolerance '{name}'")), "{name}: {e}");
    }
}
