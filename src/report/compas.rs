//! Writes an analysed design as a compas 2 `Assembly` (compas_assembly's JSON, the format
//! compas_cra reads) or a compas_dem `BlockModel` ([`block_model_json`]): what
//! `analyze --compas-out` writes, for compas' viewers and solvers.
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

use crate::geometry::{Mesh, Point3};
use crate::interfaces::Body;
use crate::pipeline::Analysis;
use crate::statics::InterfaceResult;
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
        let Some((u, v, contact)) = contact(a, r) else {
            ground += 1;
            continue;
        };
        let polygon = Mesh::new(
            contact.points.iter().map(|p| Point3::from(*p)).collect(),
            vec![(0..contact.points.len()).collect()],
        );
        let interface = json!({
            "dtype": "compas_assembly.datastructures/Interface",
            "data": {
                "points": contact.points.iter().map(|p| json!({ "dtype": "compas.geometry/Point", "data": p })).collect::<Vec<_>>(),
                "size": contact.size,
                "frame": contact.frame,
                "forces": contact.forces,
                "mesh": { "dtype": "compas.datastructures/Mesh", "data": mesh_data(&polygon) },
            },
        });
        push_edge(&mut edges, u, v, "interfaces", interface);
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

/// The compas_dem `BlockModel` JSON of `a` (compas_dem 0.6 / compas_model 0.9's schema):
///
/// - `elements[guid]`: a `compas_dem.elements/Block` with voussoir's block `name`, its mesh
///   (`geometry`) and `is_support`; guids `00000000-0000-4000-8000-<index, 12 hex digits>`
///   (deterministic: the same design gives the same file), keyed and stored as the element's
///   own `guid` so that compas saves and reloads the model unchanged;
/// - the model tree lists the elements; graph node `i` (block order) holds element `i`;
/// - edge u → v for every block–block interface: `contacts`, one
///   `compas_dem.interactions/FrictionContact` per interface with `points`, `frame`, `size`
///   and `forces` as in the Assembly (the force on v, N), so that compas_dem's contact
///   properties (resultant, compression, friction forces) read them;
/// - interfaces with the ground plane are counted in `graph.attributes.ground_interfaces`.
pub fn block_model_json(a: &Analysis) -> String {
    let blocks = &a.assembly.blocks;
    let guid = |i: usize| format!("00000000-0000-4000-8000-{i:012x}");
    let mut elements = Map::new();
    let mut nodes = Map::new();
    let mut edges: Map<String, Value> = (0..blocks.len()).map(|i| (i.to_string(), json!({}))).collect();
    for (i, b) in blocks.iter().enumerate() {
        let element = json!({
            "dtype": "compas_dem.elements/Block",
            "guid": guid(i),
            "data": {
                "transformation": null,
                "features": [],
                "name": b.name,
                "material": null,
                "is_support": b.support,
                "geometry": { "dtype": "compas.datastructures/Mesh", "data": mesh_data(&b.mesh) },
            },
        });
        elements.insert(guid(i), element);
        nodes.insert(i.to_string(), json!({ "element": guid(i) }));
    }
    let mut ground = 0;
    for r in &a.statics.interfaces {
        let Some((u, v, c)) = contact(a, r) else {
            ground += 1;
            continue;
        };
        let friction_contact = json!({
            "dtype": "compas_dem.interactions/FrictionContact",
            "data": { "points": c.points, "frame": c.frame, "size": c.size, "forces": c.forces },
        });
        push_edge(&mut edges, u, v, "contacts", friction_contact);
    }
    let children: Vec<Value> =
        (0..blocks.len()).map(|i| json!({ "name": "ElementNode", "element": guid(i) })).collect();
    let graph = json!({
        "attributes": { "name": a.assembly.name, "ground_interfaces": ground, "force_unit": "N" },
        "default_node_attributes": { "element": null },
        "default_edge_attributes": { "modifiers": null, "contacts": null },
        "node": nodes,
        "edge": edges,
        "max_node": blocks.len() as i64 - 1,
    });
    let file = json!({
        "dtype": "compas_dem.models/BlockModel",
        "data": {
            "transformation": null,
            "materials": {},
            "elements": elements,
            "tree": { "attributes": {}, "root": { "name": "root", "children": children } },
            "graph": graph,
        },
    });
    serde_json::to_string(&file).unwrap_or_default()
}

/// One block–block interface as compas writes it: its force points, frame and area, and the
/// force on v at each point. `None` for an interface with the ground.
struct Contact {
    points: Vec<[f64; 3]>,
    frame: Value,
    size: f64,
    forces: Vec<Value>,
}

fn contact(a: &Analysis, r: &InterfaceResult) -> Option<(usize, usize, Contact)> {
    let i = a.interfaces.get(r.index)?;
    let (Body::Block(u), Body::Block(v)) = (i.a, i.b) else { return None };
    let points: Vec<[f64; 3]> = r.vertices.iter().map(|p| p.position).collect();
    let forces = r
        .vertices
        .iter()
        .map(|p| json!({ "c_np": p.compression, "c_nn": p.tension, "c_u": p.friction_u, "c_v": p.friction_v }))
        .collect();
    let o = i.frame.origin;
    let frame = json!({
        "dtype": "compas.geometry/Frame",
        "data": { "point": [o.x, o.y, o.z], "xaxis": r.u, "yaxis": r.v },
    });
    Some((u.0, v.0, Contact { points, frame, size: i.area, forces }))
}

/// Appends `item` to the list `key` of edge u → v.
fn push_edge(edges: &mut Map<String, Value>, u: usize, v: usize, key: &str, item: Value) {
    let from = edges.entry(u.to_string()).or_insert_with(|| json!({}));
    let Some(row) = from.as_object_mut() else { return };
    let entry = row.entry(v.to_string()).or_insert_with(|| json!({ key: [] }));
    if let Some(list) = entry[key].as_array_mut() {
        list.push(item);
    }
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
