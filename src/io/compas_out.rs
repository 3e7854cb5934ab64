//! Writes an analysed design as a compas 2 `Assembly` (compas_assembly's JSON, the format
//! compas_cra reads): what `analyze --compas-out` writes, for compas' viewers and solvers.
//!
//! - Nodes `0..n` in block order: `block` a `compas_assembly.datastructures/Block` mesh (m),
//!   `is_support`, and `name` (voussoir's block name: compas node keys are integers).
//! - Edge u → v for every block–block interface (u = the interface's `a`): `interfaces` with
//!   one `compas_assembly.datastructures/Interface` holding the force points (`points`), the
//!   area (`size`), the frame (origin at the centroid; xaxis, yaxis = voussoir's u, v, so the
//!   normal xaxis × yaxis points from u into v), the polygon as a one-face mesh, and `forces`
//!   per point: `c_np` compression, `c_nn` tension (both ≥ 0, along the normal), `c_u`, `c_v`
//!   friction along xaxis, yaxis — the force on v (u receives the opposite), in N. compas_cra
//!   writes its own solves in density × volume units (kg with density 1): compare ratios.
//! - Interfaces with the ground plane have no node to attach to and are left out (the file's
//!   `attributes.ground_interfaces` counts them).

use crate::analysis::Analysis;
use crate::geometry::{Mesh, Point3};
use crate::interfaces::Body;
use serde_json::{Map, Value, json};

/// The compas 2 Assembly JSON of `a`.
pub fn assembly_json(a: &Analysis) -> String {
    let blocks = &a.assembly.blocks;
    let mut nodes = Map::new();
    let mut edges: Map<String, Value> = (0..blocks.len()).map(|i| (i.to_string(), json!({}))).collect();
    for (i, b) in blocks.iter().enumerate() {
        let block = json!({ "dtype": "compas_assembly.datastructures/Block", "data": mesh_data(&b.mesh) });
        nodes.insert(i.to_string(), json!({ "block": block, "is_support": b.support, "name": b.name }));
    }
    let mut ground = 0;
    for r in &a.statics.interfaces {
        let Some(i) = a.interfaces.get(r.index) else { continue };
        let (Body::Block(u), Body::Block(v)) = (i.a, i.b) else {
            ground += 1;
            continue;
        };
        let points: Vec<[f64; 3]> = r.vertices.iter().map(|p| p.position).collect();
        let forces: Vec<Value> = r
            .vertices
            .iter()
            .map(|p| json!({ "c_np": p.compression, "c_nn": p.tension, "c_u": p.friction_u, "c_v": p.friction_v }))
            .collect();
        let polygon = Mesh::new(points.iter().map(|p| Point3::from(*p)).collect(), vec![(0..points.len()).collect()]);
        let o = i.frame.origin;
        let interface = json!({
            "dtype": "compas_assembly.datastructures/Interface",
            "data": {
                "points": points.iter().map(|p| json!({ "dtype": "compas.geometry/Point", "data": p })).collect::<Vec<_>>(),
                "size": i.area,
                "frame": {
                    "dtype": "compas.geometry/Frame",
                    "data": { "point": [o.x, o.y, o.z], "xaxis": r.u, "yaxis": r.v },
                },
                "forces": forces,
                "mesh": { "dtype": "compas.datastructures/Mesh", "data": mesh_data(&polygon) },
            },
        });
        let from = edges.entry(u.0.to_string()).or_insert_with(|| json!({}));
        let list = from
            .as_object_mut()
            .expect("edge rows are objects")
            .entry(v.0.to_string())
            .or_insert_with(|| json!({ "interfaces": [] }));
        list["interfaces"].as_array_mut().expect("a list").push(interface);
    }
    let graph = json!({
        "dtype": "compas.datastructures/Graph",
        "data": {
            "attributes": {},
            "default_node_attributes": {
                "x": 0.0, "y": 0.0, "z": 0.0, "block": null, "is_support": false,
                "section": null, "mesh_size": null, "displacement": [0, 0, 0, 0, 0, 0],
            },
            "default_edge_attributes": { "interfaces": null },
            "node": nodes,
            "edge": edges,
            "max_node": blocks.len() as i64 - 1,
        },
    });
    let attributes = json!({ "name": a.assembly.name, "ground_interfaces": ground, "force_unit": "N" });
    let file = json!({
        "dtype": "compas_assembly.datastructures/Assembly",
        "data": { "attributes": attributes, "graph": graph },
    });
    serde_json::to_string(&file).unwrap_or_default()
}

/// A compas 2 mesh's data: `vertex[k] = {x, y, z}`, `face[f] = [vertex keys]`.
fn mesh_data(mesh: &Mesh) -> Value {
    let vertex: Map<String, Value> = mesh
        .vertices
        .iter()
        .enumerate()
        .map(|(k, p)| (k.to_string(), json!({ "x": p.x, "y": p.y, "z": p.z })))
        .collect();
    let face: Map<String, Value> = mesh.faces.iter().enumerate().map(|(f, vs)| (f.to_string(), json!(vs))).collect();
    let facedata: Map<String, Value> = (0..mesh.faces.len()).map(|f| (f.to_string(), json!({}))).collect();
    json!({
        "attributes": {},
        "default_vertex_attributes": { "x": 0.0, "y": 0.0, "z": 0.0 },
        "default_edge_attributes": {},
        "default_face_attributes": {},
        "vertex": vertex,
        "face": face,
        "facedata": facedata,
        "edgedata": {},
        "max_vertex": mesh.vertices.len() as i64 - 1,
        "max_face": mesh.faces.len() as i64 - 1,
    })
}
