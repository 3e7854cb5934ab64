//! Wavefront OBJ through `tobj`: one block per object/group; names starting with "support"
//! (any case) mark supports.

use super::IoError;
use crate::geometry::{Mesh, Point3};
use crate::model::{Block, Scene};
use std::path::Path;

pub fn read(path: &Path) -> Result<Scene, IoError> {
    let options =
        tobj::LoadOptions { single_index: false, triangulate: false, ignore_points: true, ignore_lines: true };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| match e {
        tobj::LoadError::OpenFileFailed | tobj::LoadError::ReadError => {
            IoError::Read { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) }
        }
        other => IoError::format(path, format!("not a valid OBJ file: {other}")),
    })?;
    if models.is_empty() {
        return Err(IoError::format(path, "the OBJ file has no faces"));
    }
    let mut blocks = Vec::with_capacity(models.len());
    for (k, model) in models.iter().enumerate() {
        let m = &model.mesh;
        let vertices: Vec<Point3> =
            m.positions.chunks_exact(3).map(|p| Point3::new(p[0] as f64, p[1] as f64, p[2] as f64)).collect();
        let mut faces = Vec::new();
        let mut start = 0usize;
        let arities: Vec<usize> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.iter().map(|&a| a as usize).collect()
        };
        for a in arities {
            faces.push(m.indices[start..start + a].iter().map(|&i| i as usize).collect());
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
