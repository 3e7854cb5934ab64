//! The legacy compas_rbe JSON (compas 0.x): `blocks[key]` is a mesh (`vertex[k] = {x, y, z}`,
//! `face[f] = [vertex keys]`) and `assembly.vertex[key].is_support` marks the fixed blocks. Block
//! names are the keys (as the assembly's). compas_rbe stores some supports as a single open
//! polygon (genevault's footings, simple_arch's ground) — the face the blocks stand on; such a
//! support becomes a slab below it (0.02 × the model size thick: `compas::with_slab_supports`).

use super::IoError;
use super::compas::{mesh_from_value, sorted_keys, with_slab_supports};
use crate::model::{Block, Scene};
use serde_json::Value;
use std::path::Path;

/// True when the JSON value looks like a legacy compas_rbe file.
pub fn is_rbe(value: &Value) -> bool {
    value.get("blocks").is_some_and(Value::is_object) && value.pointer("/assembly/vertex").is_some()
}

/// Reads the blocks and supports of a legacy compas_rbe file.
pub fn scene_from_value(path: &Path, value: &Value) -> Result<Scene, IoError> {
    let blocks = value
        .get("blocks")
        .and_then(Value::as_object)
        .ok_or_else(|| IoError::format(path, "compas_rbe: 'blocks' is not an object"))?;
    let nodes = value
        .pointer("/assembly/vertex")
        .and_then(Value::as_object)
        .ok_or_else(|| IoError::format(path, "compas_rbe: 'assembly.vertex' is not an object"))?;
    let mut out = Vec::with_capacity(blocks.len());
    for key in sorted_keys(blocks) {
        let mesh = mesh_from_value(path, key, &blocks[key])?;
        let support = nodes.get(key.as_str()).and_then(|n| n.get("is_support")).and_then(Value::as_bool);
        let support = support.ok_or_else(|| {
            IoError::format(path, format!("compas_rbe: block '{key}' is not a vertex of the assembly"))
        })?;
        out.push(Block { name: key.clone(), mesh, support, density: None });
    }
    Ok(Scene::new(super::stem(path), with_slab_supports(path, out)?))
}
