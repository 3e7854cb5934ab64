//! compas 2 `Assembly` JSON (compas_assembly, compas_cra): blocks, supports and the stored
//! interfaces (and forces, where the file was saved after a solve).
//!
//! Layout: `data.graph.data.node[key].block.data.{vertex, face}` with `vertex[k] = {x, y, z}`
//! and `face[f] = [vertex keys]`; `node[key].is_support`; `data.graph.data.edge[u][v].interfaces`
//! with `points`, `frame` (`point`, `xaxis`, `yaxis`; normal = xaxis × yaxis, the outward normal
//! of u's face) and optional `forces` (`c_np`, `c_nn`, `c_u`, `c_v` per point). Block names are
//! the node keys. compas files carry no density or units: the scene gets the default material.

use super::IoError;
use crate::geometry::{LookupMap, Mesh, Point3, Vector3};
use crate::model::{Block, Scene};
use serde_json::Value;
use std::path::Path;

/// True when the JSON value looks like a compas Assembly.
pub fn is_compas(value: &Value) -> bool {
    value.pointer("/data/graph/data/node").is_some()
}

/// An interface as stored by compas, for comparison.
#[derive(Clone, Debug)]
pub struct StoredInterface {
    /// The graph node (block) key of the edge's first end.
    pub u: String,
    /// The graph node key of its second end.
    pub v: String,
    /// The contact polygon's points, m.
    pub points: Vec<Point3>,
    /// xaxis × yaxis of the stored frame.
    pub normal: Vector3,
    /// Per point `[c_np, c_nn, c_u, c_v]` along (n, n, xaxis, yaxis), when stored.
    pub forces: Option<Vec<[f64; 4]>>,
    /// The stored frame's first in-plane axis.
    pub xaxis: Vector3,
    /// The stored frame's second in-plane axis.
    pub yaxis: Vector3,
}

fn graph<'a>(path: &Path, value: &'a Value) -> Result<&'a Value, IoError> {
    value.pointer("/data/graph/data").ok_or_else(|| IoError::format(path, "not a compas Assembly: no data.graph.data"))
}

/// Node keys in a deterministic order: numeric keys by value, then the others by text.
pub(crate) fn sorted_keys(map: &serde_json::Map<String, Value>) -> Vec<&String> {
    sorted(map.keys())
}

fn sorted<'a>(keys: impl Iterator<Item = &'a String>) -> Vec<&'a String> {
    let mut keys: Vec<&String> = keys.collect();
    keys.sort_by(|a, b| key_order(a, b));
    keys
}

/// The order of [`sorted_keys`].
pub(crate) fn key_order(a: &str, b: &str) -> std::cmp::Ordering {
    match (a.parse::<i64>(), b.parse::<i64>()) {
        (Ok(x), Ok(y)) => x.cmp(&y),
        (Ok(_), Err(_)) => std::cmp::Ordering::Less,
        (Err(_), Ok(_)) => std::cmp::Ordering::Greater,
        _ => a.cmp(b),
    }
}

/// The thickness of the slab under a support given as one open polygon, as a fraction of the
/// model's size (any thickness gives the same statics: a support is fixed; it only has to be a
/// solid that stays clear of the blocks).
const SLAB: f64 = 0.02;

/// `blocks` with every support given as a single open polygon made a slab: the polygon is its
/// top face, the slab extends away from the free blocks' centroid by [`SLAB`] × the model size.
/// A free block given as one polygon is an error (it has no volume, so no weight).
pub(crate) fn with_slab_supports(path: &Path, mut blocks: Vec<Block>) -> Result<Vec<Block>, IoError> {
    let all: Vec<Point3> = blocks.iter().flat_map(|b| b.mesh.vertices.iter().copied()).collect();
    let size = crate::geometry::Aabb3::from_points(&all).diagonal();
    let free: Vec<Point3> =
        blocks.iter().filter(|b| !b.support).flat_map(|b| b.mesh.vertices.iter().copied()).collect();
    let towards =
        (!free.is_empty()).then(|| free.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / free.len() as f64);
    for b in blocks.iter_mut().filter(|b| b.mesh.faces.len() == 1) {
        if !b.support {
            return Err(IoError::format(path, format!("block '{}': a single open face has no volume", b.name)));
        }
        let polygon: Vec<Point3> = b.mesh.faces[0].iter().map(|&i| b.mesh.vertices[i]).collect();
        let normal = crate::geometry::polygon::area_vector(&polygon);
        if polygon.len() < 3 || normal.norm() == 0.0 {
            return Err(IoError::format(path, format!("support '{}': its one face is degenerate", b.name)));
        }
        let centre = crate::geometry::polygon::centroid(&polygon);
        let away = match towards {
            Some(c) if (c - centre.coords).dot(&normal) < 0.0 => normal.normalize(),
            _ => -normal.normalize(),
        };
        b.mesh = Mesh::prism(&polygon, away * SLAB * size);
    }
    Ok(blocks)
}

/// Reads the blocks and supports of a compas Assembly.
pub fn scene_from_value(path: &Path, value: &Value) -> Result<Scene, IoError> {
    let g = graph(path, value)?;
    let nodes = g
        .get("node")
        .and_then(Value::as_object)
        .ok_or_else(|| IoError::format(path, "data.graph.data.node is not an object"))?;
    let mut blocks = Vec::with_capacity(nodes.len());
    for key in sorted_keys(nodes) {
        let node = &nodes[key];
        let mesh = node
            .pointer("/block/data")
            .ok_or_else(|| IoError::format(path, format!("node '{key}' has no block mesh")))
            .and_then(|m| mesh_from_value(path, key, m))?;
        let support = node.get("is_support").and_then(Value::as_bool).unwrap_or(false);
        blocks.push(Block { name: key.clone(), mesh, support, density: None });
    }
    Ok(Scene::new(super::stem(path), blocks))
}

/// A compas mesh's `vertex` and `face` tables (compas 0.x and 2 alike) as a mesh; errors name
/// `key`'s block.
pub(crate) fn mesh_from_value(path: &Path, key: &str, m: &Value) -> Result<Mesh, IoError> {
    let bad = |what: String| IoError::format(path, format!("block '{key}': {what}"));
    let verts = m.get("vertex").and_then(Value::as_object).ok_or_else(|| bad("no vertex table".into()))?;
    let faces = m.get("face").and_then(Value::as_object).ok_or_else(|| bad("no face table".into()))?;
    let mut index = LookupMap::default();
    index.reserve(verts.len());
    let mut vertices = Vec::with_capacity(verts.len());
    for vk in sorted_keys(verts) {
        let v = &verts[vk];
        let c = |axis: &str| -> Result<f64, IoError> {
            v.get(axis).and_then(Value::as_f64).ok_or_else(|| bad(format!("vertex '{vk}' has no numeric '{axis}'")))
        };
        index.insert(vk.as_str(), vertices.len());
        vertices.push(Point3::new(c("x")?, c("y")?, c("z")?));
    }
    let mut out_faces = Vec::with_capacity(faces.len());
    for fk in sorted_keys(faces) {
        let list = faces[fk].as_array().ok_or_else(|| bad(format!("face '{fk}' is not a list")))?;
        let mut face = Vec::with_capacity(list.len());
        for item in list {
            let k = match item {
                Value::Number(n) => n.to_string(),
                Value::String(s) => s.clone(),
                _ => return Err(bad(format!("face '{fk}' has a non-key entry {item}"))),
            };
            face.push(vertex_index(&index, fk, &k).map_err(&bad)?);
        }
        out_faces.push(face);
    }
    Ok(Mesh::new(vertices, out_faces))
}

fn vertex_index(index: &LookupMap<&str, usize>, face: &str, key: &str) -> Result<usize, String> {
    index.get(key).copied().ok_or_else(|| format!("face '{face}' refers to missing vertex '{key}'"))
}

/// The part of a compas Assembly file a scene needs, typed; everything else (the stored
/// interfaces and forces, attributes) is skipped while lexing instead of being built into a
/// tree — on the Armadillo ~3× less time than through [`Value`]. Any deviation from the usual
/// layout fails this parse, and the caller falls back to [`scene_from_value`], which names
/// the problem.
mod typed {
    use crate::geometry::LookupMap;
    use serde::Deserialize;

    #[derive(Deserialize)]
    pub struct File {
        pub data: Data,
    }
    #[derive(Deserialize)]
    pub struct Data {
        pub graph: Graph,
    }
    #[derive(Deserialize)]
    pub struct Graph {
        pub data: GraphData,
    }
    #[derive(Deserialize)]
    pub struct GraphData {
        pub node: LookupMap<String, Node>,
    }
    #[derive(Deserialize)]
    pub struct Node {
        pub block: Block,
        pub is_support: Option<bool>,
    }
    #[derive(Deserialize)]
    pub struct Block {
        pub data: MeshData,
    }
    #[derive(Deserialize)]
    pub struct MeshData {
        pub vertex: LookupMap<String, Vertex>,
        pub face: LookupMap<String, Vec<Key>>,
    }
    #[derive(Deserialize)]
    pub struct Vertex {
        pub x: f64,
        pub y: f64,
        pub z: f64,
    }

    /// A vertex key in a face list: an integer or a string, as text (what [`super::Value`]'s
    /// path makes of them); anything else fails the typed parse.
    pub struct Key(pub String);

    impl<'de> Deserialize<'de> for Key {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            struct V;
            impl serde::de::Visitor<'_> for V {
                type Value = Key;
                fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                    f.write_str("a vertex key (integer or string)")
                }
                fn visit_u64<E>(self, v: u64) -> Result<Key, E> {
                    Ok(Key(v.to_string()))
                }
                fn visit_i64<E>(self, v: i64) -> Result<Key, E> {
                    Ok(Key(v.to_string()))
                }
                fn visit_str<E>(self, v: &str) -> Result<Key, E> {
                    Ok(Key(v.to_string()))
                }
            }
            d.deserialize_any(V)
        }
    }
}

/// One node of a compas Assembly's graph as read: its key, whether it is a support, and its
/// block's vertex table (key, x, y, z) and face table (key, vertex keys), keys as text (what
/// the JSON has). The typed parse reads these from the file; the Python package from the
/// compas object itself.
pub struct NodeTables {
    /// The graph node's key: the block's name.
    pub key: String,
    /// Whether the node is marked `is_support`.
    pub support: bool,
    /// The block mesh's vertices: key and coordinates (m).
    pub vertices: Vec<(String, [f64; 3])>,
    /// The block mesh's faces: key and vertex keys, counter-clockwise seen from outside.
    pub faces: Vec<(String, Vec<String>)>,
}

/// The scene of a compas Assembly from its nodes' tables: blocks in node-key order, each
/// block's vertices and faces in key order (`key_order`); `path` names the source in errors.
pub fn scene_from_nodes(path: &Path, mut nodes: Vec<NodeTables>) -> Result<Scene, IoError> {
    nodes.sort_by(|a, b| key_order(&a.key, &b.key));
    let mut blocks = Vec::with_capacity(nodes.len());
    for mut node in nodes {
        let bad = |what: String| IoError::format(path, format!("block '{}': {what}", node.key));
        node.vertices.sort_by(|a, b| key_order(&a.0, &b.0));
        node.faces.sort_by(|a, b| key_order(&a.0, &b.0));
        let mut index = LookupMap::default();
        index.reserve(node.vertices.len());
        for (i, (vk, p)) in node.vertices.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(bad(format!("vertex '{vk}' has a coordinate that is not a finite number: {p:?}")));
            }
            index.insert(vk.as_str(), i);
        }
        let mut faces = Vec::with_capacity(node.faces.len());
        for (fk, keys) in &node.faces {
            let face = keys.iter().map(|k| vertex_index(&index, fk, k)).collect::<Result<_, _>>();
            faces.push(face.map_err(bad)?);
        }
        let vertices = node.vertices.iter().map(|(_, p)| Point3::new(p[0], p[1], p[2])).collect();
        let mesh = Mesh::new(vertices, faces);
        blocks.push(Block { name: node.key, mesh, support: node.support, density: None });
    }
    Ok(Scene::new(super::stem(path), blocks))
}

/// The scene of a compas Assembly file through the typed parse; `None` when the bytes are not
/// laid out as usual (another format, or something [`scene_from_value`] should name).
pub(crate) fn scene_from_bytes(path: &Path, bytes: &[u8]) -> Option<Result<Scene, IoError>> {
    let file: typed::File = serde_json::from_slice(bytes).ok()?;
    let nodes = file
        .data
        .graph
        .data
        .node
        .into_iter()
        .map(|(key, node)| {
            let m = node.block.data;
            NodeTables {
                key,
                support: node.is_support.unwrap_or(false),
                vertices: m.vertex.into_iter().map(|(k, v)| (k, [v.x, v.y, v.z])).collect(),
                faces: m.face.into_iter().map(|(k, f)| (k, f.into_iter().map(|key| key.0).collect())).collect(),
            }
        })
        .collect();
    Some(scene_from_nodes(path, nodes))
}

fn point(v: &Value) -> Option<Point3> {
    // A plain [x, y, z] or a compas Point {"dtype": ..., "data": [x, y, z]}.
    let arr = v.as_array().or_else(|| v.get("data").and_then(Value::as_array))?;
    if arr.len() != 3 {
        return None;
    }
    Some(Point3::new(arr[0].as_f64()?, arr[1].as_f64()?, arr[2].as_f64()?))
}

/// Reads the interfaces stored in a compas Assembly file (empty when none are stored).
pub fn stored_interfaces(path: &Path, value: &Value) -> Result<Vec<StoredInterface>, IoError> {
    let g = graph(path, value)?;
    let Some(edges) = g.get("edge").and_then(Value::as_object) else { return Ok(Vec::new()) };
    let mut out = Vec::new();
    for u in sorted_keys(edges) {
        let Some(targets) = edges[u].as_object() else { continue };
        for v in sorted_keys(targets) {
            let Some(list) = targets[v].get("interfaces").and_then(Value::as_array) else { continue };
            for item in list {
                let d = item.get("data").unwrap_or(item);
                let bad = || IoError::format(path, format!("edge {u}->{v}: malformed interface"));
                let points: Vec<Point3> = d
                    .get("points")
                    .and_then(Value::as_array)
                    .ok_or_else(bad)?
                    .iter()
                    .map(point)
                    .collect::<Option<_>>()
                    .ok_or_else(bad)?;
                let frame = d.get("frame").map(|f| f.get("data").unwrap_or(f)).ok_or_else(bad)?;
                let axis = |k: &str| frame.get(k).and_then(point).map(|p| p.coords).ok_or_else(bad);
                let (xaxis, yaxis) = (axis("xaxis")?, axis("yaxis")?);
                let forces = d.get("forces").and_then(Value::as_array).map(|fs| {
                    fs.iter()
                        .map(|f| {
                            let c = |k: &str| f.get(k).and_then(Value::as_f64).unwrap_or(0.0);
                            [c("c_np"), c("c_nn"), c("c_u"), c("c_v")]
                        })
                        .collect()
                });
                out.push(StoredInterface {
                    u: u.clone(),
                    v: v.clone(),
                    points,
                    normal: xaxis.cross(&yaxis).normalize(),
                    forces,
                    xaxis,
                    yaxis,
                });
            }
        }
    }
    Ok(out)
}

/// Reads a compas Assembly file's stored interfaces.
pub fn load_stored_interfaces(path: &Path) -> Result<Vec<StoredInterface>, IoError> {
    let text = super::read_text(path)?;
    let value: Value =
        serde_json::from_str(&text).map_err(|source| IoError::Json { path: path.to_path_buf(), source })?;
    stored_interfaces(path, &value)
}
