//! compas_dem's files: a `BlockModel` (a compas_model `Model`) and plain lists of compas meshes.
//!
//! - `BlockModel`: `data.elements[guid]` with `dtype` `compas_dem.elements/Block`,
//!   `data.geometry.data.{vertex, face}` (a compas mesh) and `data.is_support`; the graph's
//!   `data.graph.node[key].element` names each node's element. Blocks are named by their graph
//!   node key (elements outside the graph by their guid). The contacts stored on the graph's
//!   edges are not read: voussoir detects its own.
//! - A list of meshes (`[{dtype: "compas.datastructures/Mesh", data: {vertex, face}}, …]`; in
//!   `pavillionvault/blocks.json` each item is itself a list holding one mesh): free blocks
//!   named by their index, or with [`supports_from_value`] the supports of another file
//!   (`--supports-file`).
//!
//! Neither carries units or densities the scene could use: the default material.

use super::IoError;
use super::compas::{key_order, mesh_from_value, sorted_keys, with_slab_supports};
use crate::model::{Block, Scene};
use serde_json::Value;
use std::collections::HashMap;
use std::path::Path;

const BLOCK_MODEL: &str = "compas_dem.models/BlockModel";
const MESH: &str = "compas.datastructures/Mesh";

/// True when the JSON value is a compas_dem `BlockModel`.
pub fn is_block_model(value: &Value) -> bool {
    value.get("dtype").and_then(Value::as_str) == Some(BLOCK_MODEL)
}

/// True when the bytes are a compas_dem `BlockModel` file (its top-level `dtype`; the rest is
/// skipped, not built).
pub fn is_block_model_bytes(bytes: &[u8]) -> bool {
    #[derive(serde::Deserialize)]
    struct Top {
        dtype: Option<String>,
    }
    serde_json::from_slice::<Top>(bytes).is_ok_and(|t| t.dtype.as_deref() == Some(BLOCK_MODEL))
}

/// True when the JSON value is a non-empty list whose first item is a compas mesh (or a list
/// holding one).
pub fn is_mesh_list(value: &Value) -> bool {
    value.as_array().and_then(|a| a.first()).is_some_and(|item| one_mesh(item).is_ok())
}

/// The mesh an item of a mesh list is: the mesh itself or a list holding exactly one.
fn one_mesh(item: &Value) -> Result<&Value, String> {
    let mesh = match item.as_array().map(Vec::as_slice) {
        Some([one]) => one,
        Some(many) => return Err(format!("holds {} meshes (one block is one mesh)", many.len())),
        None => item,
    };
    match mesh.get("dtype").and_then(Value::as_str) {
        Some(MESH) => mesh.get("data").ok_or_else(|| "is a mesh without data".to_string()),
        _ => Err(format!("is not a compas mesh (dtype {MESH})")),
    }
}

/// Reads the blocks and supports of a `BlockModel`.
pub fn block_model_from_value(path: &Path, value: &Value) -> Result<Scene, IoError> {
    let elements = value
        .pointer("/data/elements")
        .and_then(Value::as_object)
        .ok_or_else(|| IoError::format(path, "BlockModel: 'data.elements' is not an object"))?;
    // Node key by element guid: the names users see in compas.
    let mut names: HashMap<&str, &String> = HashMap::new();
    if let Some(nodes) = value.pointer("/data/graph/node").and_then(Value::as_object) {
        for key in sorted_keys(nodes) {
            if let Some(guid) = nodes[key].get("element").and_then(Value::as_str) {
                names.insert(guid, key);
            }
        }
    }
    let mut blocks = Vec::with_capacity(elements.len());
    for guid in sorted_keys(elements) {
        let element = &elements[guid];
        let name = names.get(guid.as_str()).map_or_else(|| guid.clone(), |k| (*k).clone());
        let data = element
            .get("data")
            .ok_or_else(|| IoError::format(path, format!("BlockModel: element '{name}' has no data")))?;
        let mesh = data
            .pointer("/geometry/data")
            .ok_or_else(|| IoError::format(path, format!("BlockModel: element '{name}' has no geometry mesh")))
            .and_then(|m| mesh_from_value(path, &name, m))?;
        let support = data.get("is_support").and_then(Value::as_bool).unwrap_or(false);
        blocks.push(Block { name, mesh, support, density: None });
    }
    // Graph order (numeric keys), the elements outside the graph after them.
    blocks.sort_by(|a, b| key_order(&a.name, &b.name));
    Ok(Scene::new(super::stem(path), with_slab_supports(path, blocks)?))
}

/// Reads a list of compas meshes as free blocks named by their index.
pub fn mesh_list_from_value(path: &Path, value: &Value) -> Result<Scene, IoError> {
    Ok(Scene::new(super::stem(path), list(path, value, "", false)?))
}

/// Reads a list of compas meshes as supports named `support <index>`.
pub fn supports_from_value(path: &Path, value: &Value) -> Result<Vec<Block>, IoError> {
    list(path, value, "support ", true)
}

fn list(path: &Path, value: &Value, prefix: &str, support: bool) -> Result<Vec<Block>, IoError> {
    let items = value.as_array().ok_or_else(|| IoError::format(path, "expected a list of compas meshes"))?;
    let blocks = items
        .iter()
        .enumerate()
        .map(|(i, item)| {
            let name = format!("{prefix}{i}");
            let data = one_mesh(item).map_err(|e| IoError::format(path, format!("item {i} {e}")))?;
            Ok(Block { mesh: mesh_from_value(path, &name, data)?, name, support, density: None })
        })
        .collect::<Result<Vec<_>, _>>()?;
    with_slab_supports(path, blocks)
}
