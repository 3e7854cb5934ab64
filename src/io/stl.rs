//! STL (ascii or binary) through `stl_io`: one shape, one block named after the file.

use super::IoError;
use crate::geometry::{Mesh, Point3};
use crate::model::{Block, Scene};
use std::path::Path;

/// Parses STL bytes; `path` only names the source in errors, the scene and the block.
pub fn from_bytes(path: &Path, bytes: &[u8]) -> Result<Scene, IoError> {
    let mut cursor = std::io::Cursor::new(bytes);
    let stl = stl_io::read_stl(&mut cursor).map_err(|e| IoError::format(path, format!("not a valid STL file: {e}")))?;
    if stl.faces.is_empty() {
        return Err(IoError::format(path, "the STL file has no triangles"));
    }
    let vertices = stl.vertices.iter().map(|v| Point3::new(v[0] as f64, v[1] as f64, v[2] as f64)).collect();
    let faces = stl.faces.iter().map(|f| f.vertices.to_vec()).collect();
    let name = super::stem(path);
    Ok(Scene::new(name.clone(), vec![Block::new(name, Mesh::new(vertices, faces))]))
}
