//! voussoir's scene JSON.
//!
//! ```json
//! {"schema": 1, "name": "two cubes",
//!  "blocks": [{"name": "base", "vertices": [[0,0,0], ...], "faces": [[0,3,2,1], ...],
//!              "support": true, "density": 2400}],
//!  "density": 600, "friction": 0.839, "gravity": [0, 0, -9.81], "ground": false}
//! ```
//! `schema` (default 1), `name`, `density` (600 kg/m³), `friction` (tan 40°), `gravity`
//! (0, 0, −9.81), `ground` (false), `cuts` (a cut history: `[{"point": [x,y,z], "normal":
//! [nx,ny,nz], "target": "name"?}` or `{"apex": [x,y,z], "segments": [[[x,y,z],[x,y,z]], …],
//! "target": "name"?}`, …], default none: then `blocks` are the source shapes), `removed`
//! (names of pieces left out after the history, default none), `supports` (names of pieces
//! made supports after the history, default none), and
//! per block `support` (false) and `density` are optional, so the neutral shape without
//! `schema` and `ground` loads as is. Unknown keys are errors (a
//! typo must not be ignored silently).

use super::IoError;
use crate::geometry::{Mesh, Point3, Vector3};
use crate::model::{Block, Cut, Material, Scene};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The newest scene schema version this build reads and writes.
pub const SCHEMA_VERSION: u32 = 1;

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    #[serde(default = "default_schema")]
    schema: u32,
    #[serde(default)]
    name: Option<String>,
    blocks: Vec<BlockFile>,
    #[serde(default)]
    density: Option<f64>,
    #[serde(default)]
    friction: Option<f64>,
    #[serde(default)]
    gravity: Option<[f64; 3]>,
    #[serde(default)]
    ground: bool,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    cuts: Vec<Cut>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    removed: Vec<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    supports: Vec<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    order: Vec<String>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BlockFile {
    name: String,
    vertices: Vec<[f64; 3]>,
    faces: Vec<Vec<usize>>,
    #[serde(default)]
    support: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    density: Option<f64>,
}

fn default_schema() -> u32 {
    1
}

/// Parses a scene from JSON text.
pub fn scene_from_str(path: &Path, text: &str) -> Result<Scene, IoError> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|source| IoError::Json { path: path.to_path_buf(), source })?;
    scene_from_value(path, value)
}

pub(crate) fn scene_from_value(path: &Path, value: serde_json::Value) -> Result<Scene, IoError> {
    let file: SceneFile =
        serde_json::from_value(value).map_err(|e| IoError::format(path, format!("not a voussoir scene: {e}")))?;
    if file.schema == 0 || file.schema > SCHEMA_VERSION {
        return Err(IoError::format(
            path,
            format!("scene schema {} is not supported (this build reads 1..={SCHEMA_VERSION})", file.schema),
        ));
    }
    let defaults = Material::default();
    let mut scene = Scene::new(file.name.unwrap_or_else(|| super::stem(path)), Vec::new());
    scene.material = Material {
        density: file.density.unwrap_or(defaults.density),
        friction: file.friction.unwrap_or(defaults.friction),
    };
    if let Some(g) = file.gravity {
        scene.gravity = Vector3::new(g[0], g[1], g[2]);
    }
    scene.ground = file.ground;
    scene.cuts = file.cuts;
    scene.removed = file.removed;
    scene.supports = file.supports;
    scene.order = file.order;
    scene.blocks = file
        .blocks
        .into_iter()
        .map(|b| Block {
            name: b.name,
            mesh: Mesh::new(b.vertices.iter().map(|v| Point3::new(v[0], v[1], v[2])).collect(), b.faces),
            support: b.support,
            density: b.density,
        })
        .collect();
    Ok(scene)
}

/// Serialises a scene (current schema).
pub fn scene_to_string(scene: &Scene) -> String {
    let file = SceneFile {
        schema: SCHEMA_VERSION,
        name: Some(scene.name.clone()),
        blocks: scene
            .blocks
            .iter()
            .map(|b| BlockFile {
                name: b.name.clone(),
                vertices: b.mesh.vertices.iter().map(|p| [p.x, p.y, p.z]).collect(),
                faces: b.mesh.faces.clone(),
                support: b.support,
                density: b.density,
            })
            .collect(),
        density: Some(scene.material.density),
        friction: Some(scene.material.friction),
        gravity: Some([scene.gravity.x, scene.gravity.y, scene.gravity.z]),
        ground: scene.ground,
        cuts: scene.cuts.clone(),
        removed: scene.removed.clone(),
        supports: scene.supports.clone(),
        order: scene.order.clone(),
    };
    serde_json::to_string_pretty(&file).expect("a scene always serialises")
}
