//! Readers and writers. Every error names the file; scene readers never panic on bad input.
//!
//! Formats: voussoir scene JSON (`.json` with a `blocks` list), compas 2 Assembly JSON (`.json`
//! with `data.graph`), compas_dem `BlockModel` JSON and lists of compas meshes, legacy
//! compas_rbe JSON (`blocks` + `assembly`), Wavefront OBJ (one block per `o`/`g`; names starting with `support` are
//! supports), STL ascii/binary (one block); ground-motion records (`accelerogram`: PEER NGA
//! `.AT2`, two-column CSV). Writes are atomic (temporary file + rename).

pub mod accelerogram;
pub mod compas;
pub mod compas_dem;
pub mod compas_rbe;
mod obj;
pub mod scene_json;
mod stl;

use crate::model::Scene;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a file could not be read or written.
#[derive(Debug, Error)]
pub enum IoError {
    /// The file cannot be read (missing, no permission).
    #[error("{path}: cannot read: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// The file cannot be written (its folder missing, no permission, disk full).
    #[error("{path}: cannot write: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// The file is not JSON.
    #[error("{path}: not valid JSON: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// Where and why the JSON parser stopped.
        #[source]
        source: serde_json::Error,
    },
    /// The file parses but does not describe a scene: the message names the place and the key.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where in the file.
        message: String,
    },
    /// The file's extension is none of the formats read.
    #[error("{path}: unknown file type (expected .json, .obj or .stl)")]
    UnknownType {
        /// The file.
        path: PathBuf,
    },
}

impl IoError {
    pub(crate) fn format(path: &Path, message: impl Into<String>) -> Self {
        IoError::Format { path: path.to_path_buf(), message: message.into() }
    }
}

/// Reads a scene from any supported file type, chosen by extension (and for JSON by content).
pub fn load_scene(path: &Path) -> Result<Scene, IoError> {
    let kind = kind_of(path)?;
    let bytes = std::fs::read(path).map_err(|source| IoError::Read { path: path.to_path_buf(), source })?;
    parse(kind, path, &bytes)
}

/// Parses a scene from bytes, the format chosen by `path`'s extension (which also names the
/// source in errors). Never panics, whatever the bytes.
pub fn scene_from_bytes(path: &Path, bytes: &[u8]) -> Result<Scene, IoError> {
    parse(kind_of(path)?, path, bytes)
}

/// Parses a scene from JSON text in any of the JSON formats [`load_scene`] reads (voussoir,
/// compas Assembly, BlockModel, mesh list, compas_rbe); `source` names it in errors.
pub fn scene_from_json(source: &Path, bytes: &[u8]) -> Result<Scene, IoError> {
    parse(Kind::Json, source, bytes)
}

#[derive(Clone, Copy)]
enum Kind {
    Json,
    Obj,
    Stl,
}

fn kind_of(path: &Path) -> Result<Kind, IoError> {
    match path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).as_deref() {
        Some("json") => Ok(Kind::Json),
        Some("obj") => Ok(Kind::Obj),
        Some("stl") => Ok(Kind::Stl),
        _ => Err(IoError::UnknownType { path: path.to_path_buf() }),
    }
}

fn parse(kind: Kind, path: &Path, bytes: &[u8]) -> Result<Scene, IoError> {
    match kind {
        Kind::Json => {
            if let Some(scene) = compas::scene_from_bytes(path, bytes) {
                return scene;
            }
            let value: serde_json::Value =
                serde_json::from_slice(bytes).map_err(|source| IoError::Json { path: path.to_path_buf(), source })?;
            if compas::is_compas(&value) {
                compas::scene_from_value(path, &value)
            } else if compas_dem::is_block_model(&value) {
                compas_dem::block_model_from_value(path, &value)
            } else if compas_dem::is_mesh_list(&value) {
                compas_dem::mesh_list_from_value(path, &value)
            } else if compas_rbe::is_rbe(&value) {
                compas_rbe::scene_from_value(path, &value)
            } else {
                scene_json::scene_from_value(path, value)
            }
        }
        Kind::Obj => obj::from_bytes(path, bytes),
        Kind::Stl => stl::from_bytes(path, bytes),
    }
}

/// Reads a JSON list of compas meshes as support blocks (`--supports-file`, as compas_dem's
/// `pavillionvault/supports.json`), named `support <index>`.
pub fn load_supports(path: &Path) -> Result<Vec<crate::model::Block>, IoError> {
    let bytes = std::fs::read(path).map_err(|source| IoError::Read { path: path.to_path_buf(), source })?;
    let value: serde_json::Value =
        serde_json::from_slice(&bytes).map_err(|source| IoError::Json { path: path.to_path_buf(), source })?;
    compas_dem::supports_from_value(path, &value)
}

pub(crate) fn read_text(path: &Path) -> Result<String, IoError> {
    std::fs::read_to_string(path).map_err(|source| IoError::Read { path: path.to_path_buf(), source })
}

/// File name stem, used as a default block or scene name.
pub(crate) fn stem(path: &Path) -> String {
    path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene").to_string()
}

/// Whether `a` and `b` name the same file (through links and `..` when both exist; else as
/// written): an output must never be written over its input.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, then a rename, so
/// a reader never sees a half-written file and a failed write leaves the old file intact.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let err = |source| IoError::Write { path: path.to_path_buf(), source };
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(err)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        err(e)
    })
}
