//! `voussoir.Scene`: a design (blocks, supports, material, cut history) read from a file, from
//! a compas object (a graph of blocks through its blocks' own vertex and face tables, anything
//! else through its JSON data: no compas code is copied), or built from arrays.
//! Immutable: the edits (`with_cut`, `with_supports`) return a new scene.

use crate::errors;
use crate::settings::Supports;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use std::path::{Path, PathBuf};
use voussoir::geometry::{Mesh, Point3};
use voussoir::io;
use voussoir::model::{self, Block, Cut};

/// One block as Python gives it: vertices (m) and faces (vertex indices).
type BlockArrays = (Vec<[f64; 3]>, Vec<Vec<usize>>);

#[pyclass(module = "voussoir", frozen)]
pub struct Scene {
    pub(crate) scene: model::Scene,
    /// How errors name the scene: the file it came from, or what built it.
    pub(crate) source: String,
}

impl Scene {
    fn new(scene: model::Scene, source: impl Into<String>) -> Self {
        Self { scene, source: source.into() }
    }

    pub(crate) fn edited(&self, scene: model::Scene) -> Self {
        Self { scene, source: self.source.clone() }
    }
}

#[pymethods]
impl Scene {
    /// Reads a scene file: voussoir JSON, compas Assembly / CRA_Assembly / BlockModel JSON, a
    /// compas mesh list, legacy compas_rbe JSON, OBJ or STL (by extension, JSON by content).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let scene = io::load_scene(&path).map_err(errors::io)?;
        Ok(Self::new(scene, path.display().to_string()))
    }

    /// Parses JSON text in any JSON format `from_file` reads; `source` names it in errors.
    #[staticmethod]
    #[pyo3(signature = (text, source = "<json>"))]
    fn from_json(text: &str, source: &str) -> PyResult<Self> {
        let scene = io::scene_from_json(Path::new(source), text.as_bytes()).map_err(errors::io)?;
        Ok(Self::new(scene, source))
    }

    /// A compas object — compas_assembly `Assembly`, compas_cra `CRA_Assembly`, compas_dem
    /// `BlockModel`, or a list of compas `Mesh`es. An Assembly's blocks and supports are read
    /// from its blocks' own tables (`voussoir._compas.block_tables`), the same scene as its JSON
    /// data gives without writing and parsing the JSON; anything else through its data
    /// (`voussoir._compas.data_json`: `compas.json_dumps`). Blocks are named by the compas node
    /// keys (as strings).
    #[staticmethod]
    fn from_compas(obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        let py = obj.py();
        let kind = obj.get_type().name()?.to_string();
        if !obj.hasattr("__data__")? && !obj.is_instance_of::<PyList>() {
            return Err(PyTypeError::new_err(format!(
                "Scene.from_compas takes a compas Assembly, CRA_Assembly, BlockModel or a list of compas \
                 Meshes, not a {kind}"
            )));
        }
        let compas = py.import("voussoir._compas")?;
        let source = format!("<compas {kind}>");
        if let Some(nodes) = node_tables(&compas.call_method1("block_tables", (obj,))?) {
            let scene = io::compas::scene_from_nodes(Path::new(&source), nodes).map_err(errors::io)?;
            return Ok(Self::new(scene, source));
        }
        let text: String = compas.call_method1("data_json", (obj,))?.extract()?;
        Self::from_json(&text, &source)
    }

    /// A built-in scene by the command line's spec, e.g. `"arch?n=15&t=0.1"` (or
    /// `"builtin:arch?n=15"`).
    #[staticmethod]
    fn builtin(spec: &str) -> PyResult<Self> {
        let spec = spec.strip_prefix("builtin:").unwrap_or(spec);
        let scene = model::builtin(spec).map_err(|e| errors::input(&format!("builtin:{spec}"), e))?;
        Ok(Self::new(scene, format!("builtin:{spec}")))
    }

    /// Blocks from arrays: each block a pair (vertices (n, 3) in m, faces as lists of vertex
    /// indices, counter-clockwise seen from outside). `names` default to "0", "1", … (as compas
    /// node keys); `supports` are indices of fixed blocks; `density` in kg/m³ (default: the
    /// library's material).
    #[staticmethod]
    #[pyo3(signature = (blocks, *, names = None, supports = None, density = None, ground = false, name = "arrays"))]
    fn from_arrays(
        blocks: Vec<BlockArrays>,
        names: Option<Vec<String>>,
        supports: Option<Vec<usize>>,
        density: Option<f64>,
        ground: bool,
        name: &str,
    ) -> PyResult<Self> {
        let names = names.unwrap_or_else(|| (0..blocks.len()).map(|i| i.to_string()).collect());
        if names.len() != blocks.len() {
            return Err(errors::input(name, format!("{} names for {} blocks", names.len(), blocks.len())));
        }
        let supports = supports.unwrap_or_default();
        if let Some(bad) = supports.iter().find(|&&i| i >= blocks.len()) {
            return Err(errors::input(name, format!("support index {bad} but only {} blocks", blocks.len())));
        }
        let blocks = blocks
            .into_iter()
            .zip(names)
            .enumerate()
            .map(|(i, ((vertices, faces), block_name))| {
                let mesh = Mesh::new(vertices.into_iter().map(Point3::from).collect(), faces);
                Block::new(block_name, mesh).support(supports.contains(&i))
            })
            .collect();
        let mut scene = model::Scene::new(name, blocks);
        if let Some(d) = density {
            scene.material.density = d;
        }
        scene.ground = ground;
        Ok(Self::new(scene, name))
    }

    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// What errors call this scene (its file, or what built it).
    #[getter]
    fn source(&self) -> &str {
        &self.source
    }

    /// The blocks' names (the source shapes when the scene has a cut history).
    #[getter]
    fn block_names(&self) -> Vec<String> {
        self.scene.blocks.iter().map(|b| b.name.clone()).collect()
    }

    /// Names of the blocks marked as supports.
    #[getter]
    fn support_names(&self) -> Vec<String> {
        let marked = self.scene.blocks.iter().filter(|b| b.support).map(|b| b.name.clone());
        marked.chain(self.scene.supports.iter().cloned()).collect()
    }

    /// The plane z = 0 supports faces lying on it.
    #[getter]
    fn ground(&self) -> bool {
        self.scene.ground
    }

    /// Number of cuts in the history.
    #[getter]
    fn cuts(&self) -> usize {
        self.scene.cuts.len()
    }

    /// The names of the blocks an analysis sees: the cut history replayed.
    fn pieces(&self) -> PyResult<Vec<String>> {
        let (resolved, _) =
            voussoir::history::resolve(&self.scene, &Default::default(), &mut voussoir::history::CutCache::new())
                .map_err(|e| errors::input(&self.source, e))?;
        Ok(resolved.blocks.into_iter().map(|b| b.name).collect())
    }

    /// This scene with a plane cut appended to its history: through `point` with `normal` (the
    /// `-` pieces on the side the normal points away from); `target` cuts one piece only.
    #[pyo3(signature = (point, normal, target = None))]
    fn with_cut(&self, point: [f64; 3], normal: [f64; 3], target: Option<String>) -> PyResult<Self> {
        let mut scene = self.scene.clone();
        scene.cuts.push(Cut { target, ..Cut::plane(point, normal) });
        // Replayed now, so a bad cut is an error here rather than at the next analysis.
        voussoir::history::resolve(&scene, &Default::default(), &mut voussoir::history::CutCache::new())
            .map_err(|e| errors::input(&self.source, e))?;
        Ok(self.edited(scene))
    }

    /// This scene with a pattern cut appended to its history: each segment `[p, q]` (drawn on a
    /// face, in order) cuts with the plane through `apex`, `p` and `q`, but only the pieces the
    /// cone from the apex through the segment meets (brick bonds, voussoir courses); `target`
    /// restricts it to one piece and the pieces cut from it.
    #[pyo3(signature = (apex, segments, target = None))]
    fn with_pattern_cut(&self, apex: [f64; 3], segments: Vec<[[f64; 3]; 2]>, target: Option<String>) -> PyResult<Self> {
        let mut scene = self.scene.clone();
        scene.cuts.push(Cut { target, ..Cut::pattern(apex, segments) });
        voussoir::history::resolve(&scene, &Default::default(), &mut voussoir::history::CutCache::new())
            .map_err(|e| errors::input(&self.source, e))?;
        Ok(self.edited(scene))
    }

    /// This scene with other supports: `"lowest"` or a list of block names.
    fn with_supports(&self, supports: Supports) -> PyResult<Self> {
        let choice = supports.choice()?;
        let mut scene = self.scene.clone();
        scene
            .choose_supports(&choice, voussoir::geometry::Tolerances::default().coplanar)
            .map_err(|e| errors::input(&self.source, format!("supports: {e}")))?;
        Ok(self.edited(scene))
    }

    /// The scene as voussoir scene JSON (with its cut history: editable like any design).
    fn to_json(&self) -> String {
        io::scene_json::scene_to_string(&self.scene)
    }

    /// Writes `to_json()` to `path` atomically.
    fn write(&self, path: PathBuf) -> PyResult<()> {
        io::write_atomic(&path, self.to_json().as_bytes()).map_err(errors::io)
    }

    fn __len__(&self) -> usize {
        self.scene.blocks.len()
    }

    fn __repr__(&self) -> String {
        let supports = self.scene.blocks.iter().filter(|b| b.support).count();
        format!(
            "Scene({:?}: {} blocks, {} supports, {} cuts{})",
            self.scene.name,
            self.scene.blocks.len(),
            supports,
            self.scene.cuts.len(),
            if self.scene.ground { ", ground" } else { "" }
        )
    }
}

/// The blocks' tables as `voussoir._compas.block_tables` hands them over (the compas object's
/// own dicts), read as the JSON route would read them; `None` — the JSON route then, which
/// names what is wrong — for anything laid out otherwise: a key that is not an integer or a
/// string, a vertex without numeric x, y, z, a face that is not a list. (A coordinate that is
/// not finite is read, and the scene's reader names it.)
fn node_tables(tables: &Bound<'_, PyAny>) -> Option<Vec<io::compas::NodeTables>> {
    let list = tables.cast::<PyList>().ok()?;
    list.iter()
        .map(|item| {
            let (key, support, vertex, face): (String, bool, Bound<PyDict>, Bound<PyDict>) = item.extract().ok()?;
            let vertices =
                vertex.iter().map(|(k, attr)| Some((key_text(&k)?, point(&attr)?))).collect::<Option<_>>()?;
            let faces = face
                .iter()
                .map(|(k, keys)| {
                    let keys = keys.cast::<PyList>().ok()?.iter().map(|v| key_text(&v)).collect::<Option<_>>()?;
                    Some((key_text(&k)?, keys))
                })
                .collect::<Option<_>>()?;
            Some(io::compas::NodeTables { key, support, vertices, faces })
        })
        .collect()
}

/// A compas key as the JSON route writes it: an integer's digits, or the string itself.
fn key_text(key: &Bound<'_, PyAny>) -> Option<String> {
    if key.is_instance_of::<PyString>() {
        return key.extract::<String>().ok();
    }
    if key.is_instance_of::<PyBool>() {
        return None;
    }
    key.extract::<i64>().ok().map(|i| i.to_string())
}

/// A vertex's x, y, z from its attribute dict.
fn point(attr: &Bound<'_, PyAny>) -> Option<[f64; 3]> {
    let attr = attr.cast::<PyDict>().ok()?;
    let axis = |name: &str| attr.get_item(name).ok().flatten()?.extract::<f64>().ok();
    Some([axis("x")?, axis("y")?, axis("z")?])
}
