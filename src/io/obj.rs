//! Wavefront OBJ through `tobj`: one block per object/group; names starting with "support"
//! (any case) mark supports. Materials are ignored.

use super::IoError;
use crate::geometry::{Mesh, Point3};
use crate::model::{Block, Scene};
use std::path::Path;

/// Parses OBJ text; `path` only names the source in errors and the scene.
pub fn from_bytes(path: &Path, bytes: &[u8]) -> Result<Scene, IoError> {
    let options =
        tobj::LoadOptions { single_index: false, triangulate: false, ignore_points: true, ignore_lines: true };
    let mut reader = std::io::BufReader::new(bytes);
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| IoError::format(path, format!("not a valid OBJ file: {e}")))?;
    if models.is_empty() {
        return Err(IoError::format(path, "the OBJ file has no faces"));
    }
    let mut blocks = Vec::with_capacity(models.len());
    for (k, model) in models.iter().enumerate() {
        let m = &model.mesh;
        let vertices: Vec<Point3> =
            m.positions.chunks_exact(3).map(|p| Point3::new(p[0] as f64, p[1] as f64, p[2] as f64)).collect();
        let arities: Vec<usize> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.iter().map(|&a| a as usize).collect()
        };
        let mut faces = Vec::with_capacity(arities.len());
        let mut start = 0usize;
        for a in arities {
            let Some(idx) = m.indices.get(start..start + a) else {
                return Err(IoError::format(
                    path,
                    format!("object '{}': face {} is truncated", model.name, faces.len()),
                ));
            };
            faces.push(idx.iter().map(|&i| i as usize).collect());
            start += a;
        }
        let name = if model.name.is_empty() || model.name == "unnamed_object" {
            format!("block{k}")
        } else {
            model.name.clone()
        };
        let support = name.to_ascii_lowercase().starts_with("support");
        blocks.push(Block { name, mesh: Mesh::new(vertices, faces), support, density: None });
    }
    Ok(Scene::new(super::stem(path), blocks))
}
