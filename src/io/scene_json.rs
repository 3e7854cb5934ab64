//! voussoir's scene JSON.
//!
//! ```json
//! {"schema": 1, "name": "two cubes",
//!  "blocks": [{"name": "base", "vertices": [[0,0,0], ...], "faces": [[0,3,2,1], ...],
//!              "support": true, "density": 2400}],
//!  "density": 600, "friction": 0.839, "gravity": [0, 0, -9.81], "ground": false}
//! ```
//! `schema` (default 1), `name`, `density` and `friction` (default [`Material::default`]),
//! `strength` (the compressive strength in Pa, default none: the stone does not crush),
//! `gravity` (default [`Scene::new`]'s), `ground` (false), `cuts` (a cut history: `[{"point": [x,y,z], "normal":
//! [nx,ny,nz], "target": "name"?}` or `{"apex": [x,y,z], "segments": [[[x,y,z],[x,y,z]], …],
//! "target": "name"?}`, …], default none: then `blocks` are the source shapes), `removed`
//! (names of pieces left out after the history, default none), `supports` (names of pieces
//! made supports after the history, default none), `densities` (`{"piece": kg/m³, …}`: densities
//! of pieces after the history, an infill design's, default none), `density_ranges` (`{"piece":
//! [low, high], …}`: bounds of an infill's densities per piece, kg/m³), `loads` (default none: `[{"block": "top",
//! "point": [x,y,z], "force": [fx,fy,fz], "kind": "dead"}, {"acceleration": [ax,ay,az]}, …]`,
//! forces in N, accelerations in g, `kind` dead or live — the default; [`crate::model::loads`]),
//! `movements` (default none: `[{"block": "left", "translation": [dx,dy,dz], "rotation":
//! [rx,ry,rz]}, …]`, a support's whole path in model units and degrees about its centroid;
//! [`crate::model::movement`]), `ground_motion` (default none: `{"components": [{"pulse":
//! {"shape": "rect", "amplitude": 0.3, "duration": 0.5}, "azimuth": 0}, …], "scale": 1}`, a
//! component `pulse`, `harmonic` (`{"amplitude", "period", "cycles"}`) or `record` (a path
//! relative to the scene file, or `builtin:elcentro`), amplitudes in g; checked on reading,
//! records read; [`crate::model::shaking`]),
//! and per block `support` (false) and `density` (a number, or k³ numbers: one per cell of the
//! block's box, [`crate::model::Density`]) are optional, so the neutral shape without
//! `schema` and `ground` loads as is.
//!
//! Unknown keys, at every level (the scene, a block, a cut, a load): a key within a typo of a known
//! one — edit distance at most 2, at most 1 when either is four letters or shorter (`note` is
//! not `name`) — is an error suggesting the known key (`frction`: "did you mean
//! `friction`?"), since a misspelt setting must not be dropped silently; any other is
//! metadata (a `params` object, a tool's name, colours): ignored, with a warning naming it
//! ([`Scene::warnings`]).

use super::IoError;
use crate::geometry::{Mesh, Point3, Vector3};
use crate::model::{Block, Cut, Density, Load, LoadKind, Material, Movement, Scene, Warning};
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
    #[serde(default, skip_serializing_if = "Option::is_none")]
    strength: Option<f64>,
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
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    densities: std::collections::BTreeMap<String, Density>,
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    density_ranges: std::collections::BTreeMap<String, [f64; 2]>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    order: Vec<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    loads: Vec<LoadFile>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    movements: Vec<Movement>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    ground_motion: Option<crate::model::Shaking>,
}

/// A load: `block`, `point` and `force` (a point load) or `acceleration` (a field, in g);
/// `kind` `dead` or `live` (default).
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LoadFile {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    block: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    point: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    force: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    acceleration: Option<[f64; 3]>,
    #[serde(default)]
    kind: LoadKind,
}

impl LoadFile {
    fn to_load(&self, path: &Path, index: usize) -> Result<Load, IoError> {
        let v = |a: [f64; 3]| Vector3::new(a[0], a[1], a[2]);
        match (&self.block, self.point, self.force, self.acceleration) {
            (Some(block), Some(p), Some(f), None) => Ok(Load::Point {
                block: block.clone(),
                point: Point3::new(p[0], p[1], p[2]),
                force: v(f),
                kind: self.kind,
            }),
            (None, None, None, Some(a)) => Ok(Load::Acceleration { accel: v(a), kind: self.kind }),
            _ => Err(IoError::format(
                path,
                format!(
                    "load #{index}: give either `block`, `point` and `force` (a point load) or \
                     `acceleration` (a field in g), not a mix"
                ),
            )),
        }
    }

    fn from_load(load: &Load) -> Self {
        let a = |v: &Vector3| Some([v.x, v.y, v.z]);
        match load {
            Load::Point { block, point, force, kind } => LoadFile {
                block: Some(block.clone()),
                point: Some([point.x, point.y, point.z]),
                force: a(force),
                kind: *kind,
                ..Default::default()
            },
            Load::Acceleration { accel, kind } => {
                LoadFile { acceleration: a(accel), kind: *kind, ..Default::default() }
            }
        }
    }
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
    density: Option<Density>,
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

/// Keys of the format at each level.
const SCENE_KEYS: &[&str] = &[
    "schema",
    "name",
    "blocks",
    "density",
    "friction",
    "strength",
    "gravity",
    "ground",
    "cuts",
    "removed",
    "supports",
    "densities",
    "density_ranges",
    "order",
    "loads",
    "movements",
    "ground_motion",
];
const BLOCK_KEYS: &[&str] = &["name", "vertices", "faces", "support", "density"];
const CUT_KEYS: &[&str] = &["point", "normal", "apex", "segments", "target"];
const LOAD_KEYS: &[&str] = &["block", "point", "force", "acceleration", "kind"];
const MOVEMENT_KEYS: &[&str] = &["block", "translation", "rotation"];

/// Levenshtein distance (insertions, deletions, substitutions of characters).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// The known key `key` is a typo of, if any: the closest within 2 edits, or within 1 when either
/// of the two has at most four characters (two edits make `name` of `note` or `date`).
fn typo_of(key: &str, known: &'static [&'static str]) -> Option<&'static str> {
    known
        .iter()
        .map(|&k| (edit_distance(key, k), k))
        .filter(|&(d, k)| d <= if key.chars().count().min(k.len()) <= 4 { 1 } else { 2 })
        .min_by_key(|&(d, _)| d)
        .map(|(_, k)| k)
}

/// Removes from `object` the keys not in `known`, each with a warning; a typo of a known key is
/// an error instead. `place` names the object in messages (`None`: the top level).
fn screen(
    path: &Path,
    object: &mut serde_json::Map<String, serde_json::Value>,
    known: &'static [&'static str],
    place: Option<String>,
    warnings: &mut Vec<Warning>,
) -> Result<(), IoError> {
    let unknown: Vec<String> = object.keys().filter(|k| !known.contains(&k.as_str())).cloned().collect();
    for key in unknown {
        if let Some(meant) = typo_of(&key, known) {
            let at = place.as_ref().map(|p| format!("{p}: ")).unwrap_or_default();
            return Err(IoError::format(path, format!("{at}unknown key `{key}`: did you mean `{meant}`?")));
        }
        object.remove(&key);
        warnings.push(Warning::UnknownKey { file: path.to_path_buf(), place: place.clone(), key });
    }
    Ok(())
}

/// Screens the keys of the scene, of each block and of each cut (see the module docs); the
/// shapes themselves are left to the typed parse, which names what is wrong with them.
fn screen_keys(path: &Path, value: &mut serde_json::Value) -> Result<Vec<Warning>, IoError> {
    let mut warnings = Vec::new();
    let Some(scene) = value.as_object_mut() else { return Ok(warnings) };
    screen(path, scene, SCENE_KEYS, None, &mut warnings)?;
    if let Some(blocks) = scene.get_mut("blocks").and_then(|b| b.as_array_mut()) {
        for (i, block) in blocks.iter_mut().enumerate() {
            let Some(block) = block.as_object_mut() else { continue };
            let place = match block.get("name").and_then(|n| n.as_str()) {
                Some(name) => format!("block '{name}'"),
                None => format!("block #{i}"),
            };
            screen(path, block, BLOCK_KEYS, Some(place), &mut warnings)?;
        }
    }
    if let Some(cuts) = scene.get_mut("cuts").and_then(|c| c.as_array_mut()) {
        for (i, cut) in cuts.iter_mut().enumerate() {
            if let Some(cut) = cut.as_object_mut() {
                screen(path, cut, CUT_KEYS, Some(format!("cut {i}")), &mut warnings)?;
            }
        }
    }
    if let Some(loads) = scene.get_mut("loads").and_then(|c| c.as_array_mut()) {
        for (i, load) in loads.iter_mut().enumerate() {
            if let Some(load) = load.as_object_mut() {
                screen(path, load, LOAD_KEYS, Some(format!("load #{i}")), &mut warnings)?;
            }
        }
    }
    if let Some(moves) = scene.get_mut("movements").and_then(|c| c.as_array_mut()) {
        for (i, m) in moves.iter_mut().enumerate() {
            if let Some(m) = m.as_object_mut() {
                screen(path, m, MOVEMENT_KEYS, Some(format!("movement #{i}")), &mut warnings)?;
            }
        }
    }
    Ok(warnings)
}

pub(crate) fn scene_from_value(path: &Path, mut value: serde_json::Value) -> Result<Scene, IoError> {
    let warnings = screen_keys(path, &mut value)?;
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
        strength: file.strength,
    };
    if let Some(g) = file.gravity {
        scene.gravity = Vector3::new(g[0], g[1], g[2]);
    }
    scene.ground = file.ground;
    scene.cuts = file.cuts;
    scene.removed = file.removed;
    scene.supports = file.supports;
    scene.densities = file.densities;
    scene.density_ranges = file.density_ranges;
    scene.order = file.order;
    scene.loads = file.loads.iter().enumerate().map(|(i, l)| l.to_load(path, i)).collect::<Result<_, _>>()?;
    scene.movements = file.movements;
    if let Some(shaking) = &file.ground_motion {
        super::accelerogram::ground_motion(shaking, path, scene.gravity.norm())
            .map_err(|e| IoError::format(path, format!("ground_motion: {e}")))?;
    }
    scene.ground_motion = file.ground_motion;
    scene.warnings = warnings;
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
                density: b.density.clone(),
            })
            .collect(),
        density: Some(scene.material.density),
        friction: Some(scene.material.friction),
        strength: scene.material.strength,
        gravity: Some([scene.gravity.x, scene.gravity.y, scene.gravity.z]),
        ground: scene.ground,
        cuts: scene.cuts.clone(),
        removed: scene.removed.clone(),
        supports: scene.supports.clone(),
        densities: scene.densities.clone(),
        density_ranges: scene.density_ranges.clone(),
        order: scene.order.clone(),
        loads: scene.loads.iter().map(LoadFile::from_load).collect(),
        movements: scene.movements.clone(),
        ground_motion: scene.ground_motion.clone(),
    };
    serde_json::to_string_pretty(&file).expect("a scene always serialises")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distances() {
        assert_eq!(edit_distance("frction", "friction"), 1);
        assert_eq!(edit_distance("firction", "friction"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("note", "name"), 2);
    }

    #[test]
    fn typos_and_metadata() {
        assert_eq!(typo_of("frction", SCENE_KEYS), Some("friction"));
        assert_eq!(typo_of("Friction", SCENE_KEYS), Some("friction"));
        assert_eq!(typo_of("support", SCENE_KEYS), Some("supports"));
        assert_eq!(typo_of("supports", BLOCK_KEYS), Some("support"));
        assert_eq!(typo_of("nme", BLOCK_KEYS), Some("name"));
        for metadata in ["params", "note", "date", "color", "colour", "tool", "tags", "units", "mu", "id", "meta"] {
            assert_eq!(typo_of(metadata, SCENE_KEYS), None, "{metadata}");
            assert_eq!(typo_of(metadata, BLOCK_KEYS), None, "{metadata}");
        }
    }
}
