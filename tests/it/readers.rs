//! Invariant: each reader turns its format into the same blocks (names, supports, geometry),
//! and the neutral scene shape loads exactly as given.

use crate::common::*;
use voussoir::io::{load_scene, scene_json};
use voussoir::model::Assembly;

fn tmp(name: &str, content: &[u8]) -> std::path::PathBuf {
    let p = crate::common::scratch("readers").join(name);
    std::fs::write(&p, content).unwrap();
    p
}

const CUBE_V: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";

#[test]
fn neutral_shape_loads_as_is() {
    let text = r#"{"name": "pair", "blocks": [
        {"name": "base", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],
         "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]], "support": true},
        {"name": "top", "vertices": [[0,0,1],[1,0,1],[1,1,1],[0,1,1],[0,0,2],[1,0,2],[1,1,2],[0,1,2]],
         "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]], "support": false}],
        "density": 2000, "friction": 0.6, "gravity": [0, 0, -9.81]}"#;
    let p = tmp("neutral.json", text.as_bytes());
    let s = load_scene(&p).unwrap();
    assert_eq!(s.name, "pair");
    assert_eq!(s.blocks.len(), 2);
    assert!(s.blocks[0].support && !s.blocks[1].support);
    assert_eq!((s.material.density, s.material.friction), (2000.0, 0.6));
    let a = Assembly::new(&s, &Default::default()).unwrap();
    assert_close(a.free_weight(), 2000.0 * 9.81, 1e-9, "W");
    // Round trip through the writer gives the same scene.
    let again = scene_json::scene_from_str(&p, &scene_json::scene_to_string(&s)).unwrap();
    assert_eq!(again, s);
}

#[test]
fn obj_one_block_per_object_and_support_names() {
    // Each object: its vertices, then its quad faces with global 1-based OBJ indices.
    let mut text = String::new();
    for (k, (name, dz)) in [("support_floor", 0.0), ("brick", 1.0)].into_iter().enumerate() {
        text.push_str(&format!("o {name}\n"));
        for line in CUBE_V.lines() {
            let v: Vec<f64> = line[2..].split(' ').map(|x| x.parse().unwrap()).collect();
            text.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2] + dz));
        }
        let base = 8 * k;
        for f in [[1, 4, 3, 2], [5, 6, 7, 8], [1, 2, 6, 5], [2, 3, 7, 6], [3, 4, 8, 7], [4, 1, 5, 8]] {
            text.push_str(&format!("f {} {} {} {}\n", f[0] + base, f[1] + base, f[2] + base, f[3] + base));
        }
    }
    let p = tmp("two.obj", text.as_bytes());
    let s = load_scene(&p).unwrap();
    let names: Vec<&str> = s.blocks.iter().map(|b| b.name.as_str()).collect();
    assert!(names.contains(&"support_floor") && names.contains(&"brick"), "{names:?}");
    for b in &s.blocks {
        assert_eq!(b.support, b.name == "support_floor");
    }
    let a = Assembly::new(&s, &Default::default()).unwrap();
    assert_close(a.blocks[1].mass.centroid.z, 1.5, 1e-12, "brick centroid");
    assert_eq!(voussoir::interfaces::detect(&a).len(), 1);
}

#[test]
fn stl_ascii_and_binary_give_the_same_unit_cube() {
    let m = voussoir::geometry::Mesh::cuboid(
        voussoir::geometry::Point3::origin(),
        voussoir::geometry::Point3::new(1.0, 2.0, 3.0),
    );
    let mut tris = Vec::new();
    for f in &m.faces {
        for k in 1..f.len() - 1 {
            let p = |i: usize| {
                let v = m.vertices[f[i]];
                stl_io::Vertex::new([v.x as f32, v.y as f32, v.z as f32])
            };
            tris.push(stl_io::Triangle {
                normal: stl_io::Normal::new([0.0, 0.0, 0.0]),
                vertices: [p(0), p(k), p(k + 1)],
            });
        }
    }
    let mut bin = Vec::new();
    stl_io::write_stl(&mut bin, tris.iter()).unwrap();
    let mut ascii = String::from("solid cube\n");
    for t in &tris {
        ascii.push_str("facet normal 0 0 0\nouter loop\n");
        for v in &t.vertices {
            ascii.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        ascii.push_str("endloop\nendfacet\n");
    }
    ascii.push_str("endsolid cube\n");
    for (name, bytes) in [("bin.stl", bin), ("ascii.stl", ascii.into_bytes())] {
        let s = load_scene(&tmp(name, &bytes)).unwrap();
        assert_eq!(s.blocks.len(), 1);
        let a = Assembly::new(&s, &Default::default()).unwrap();
        assert_close(a.blocks[0].mass.volume, 6.0, 1e-9, name);
    }
}

#[test]
fn compas_blocks_and_supports() {
    let s = load_scene(&compas_data("compas_assembly/arch_assembly.json")).unwrap();
    assert_eq!(s.blocks.len(), 30);
    assert_eq!(s.blocks.iter().filter(|b| b.support).count(), 2);
    let names: Vec<&str> = s.blocks.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names[..3], ["0", "1", "2"], "numeric node order");
}

#[test]
fn compas_typed_parse_equals_the_tree_walk_and_odd_files_fall_back() {
    // load_scene reads compas files through a typed parse; the tree walk over serde_json::Value
    // (scene_from_value) is the independent reference: the same scene for every file.
    for rel in assembly_files() {
        let path = compas_data(&rel);
        let value: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        let reference = voussoir::io::compas::scene_from_value(&path, &value).unwrap();
        assert_eq!(load_scene(&path).unwrap(), reference, "{rel}");
    }
    // Off the usual layout (string support flag, float vertex key, a missing block mesh): the
    // typed parse declines and the tree walk answers or names the problem.
    let cube = |support: &str, key: &str| {
        format!(
            r#"{{"data": {{"graph": {{"data": {{"node": {{"0": {{"is_support": {support}, "block": {{"data": {{
            "vertex": {{"0": {{"x": 0, "y": 0, "z": 0}}, "1": {{"x": 1, "y": 0, "z": 0}}, "2": {{"x": 1, "y": 1, "z": 0}},
                        "3": {{"x": 0, "y": 1, "z": 0}}, "4": {{"x": 0, "y": 0, "z": 1}}, "5": {{"x": 1, "y": 0, "z": 1}},
                        "6": {{"x": 1, "y": 1, "z": 1}}, "7": {{"x": 0, "y": 1, "z": 1}}}},
            "face": {{"0": [0, 3, 2, 1], "1": [4, 5, 6, 7], "2": [0, 1, 5, 4], "3": [1, 2, 6, 5], "4": [2, 3, 7, 6],
                      "5": [3, 0, 4, {key}]}}}}}}}}}}}}}}}}}}"#
        )
    };
    let typed = load_scene(&tmp("typed.json", cube("true", "7").as_bytes())).unwrap();
    assert!(typed.blocks[0].support && typed.blocks[0].mesh.faces.len() == 6);
    let odd = load_scene(&tmp("odd.json", cube("\"yes\"", "\"7\"").as_bytes())).unwrap();
    assert!(!odd.blocks[0].support, "a non-bool flag reads as not a support, as before");
    assert_eq!(odd.blocks[0].mesh, typed.blocks[0].mesh);
    let e = load_scene(&tmp("float.json", cube("true", "7.0").as_bytes())).unwrap_err().to_string();
    assert!(e.contains("block '0'") && e.contains("missing vertex '7.0'"), "{e}");
}
