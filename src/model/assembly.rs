//! Validated scene: repaired meshes, mass properties, model size, face planes.

use super::{BlockId, Material, Scene};
use crate::geometry::polygon::{area_vector, centroid};
use crate::geometry::tolerances::AbsTolerances;
use crate::geometry::{Aabb3, MassProperties, Mesh, MeshError, MeshWarning, Point3, Tolerances, Vector3, repair};
use std::collections::HashSet;
use thiserror::Error;

/// Why a scene cannot be analysed. Each variant names the block.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ModelError {
    #[error("the scene has no blocks")]
    NoBlocks,
    #[error("block '{block}': {source}")]
    Mesh {
        block: String,
        #[source]
        source: MeshError,
    },
    #[error("two blocks are called '{0}'; block names must be unique")]
    DuplicateName(String),
    #[error("block #{0} has an empty name")]
    EmptyName(usize),
    #[error("block '{block}': density {density} is not a positive finite number (kg/m³)")]
    BadDensity { block: String, density: f64 },
    #[error("friction coefficient {0} is not a finite number ≥ 0")]
    BadFriction(f64),
    #[error("gravity {0:?} is not a finite vector")]
    BadGravity([f64; 3]),
    #[error("reference length {0} is not a positive finite number (m)")]
    BadReferenceLength(f64),
}

/// A repair made while loading, with the block it concerns.
#[derive(Debug, Clone, PartialEq)]
pub struct Warning {
    pub block: String,
    pub warning: MeshWarning,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "block '{}': {}", self.block, self.warning)
    }
}

/// One face of a validated block, with its plane data precomputed for interface detection.
#[derive(Clone, Debug)]
pub struct Face {
    /// Unit outward normal (zero for a degenerate, zero-area face).
    pub normal: Vector3,
    pub area: f64,
    pub centroid: Point3,
    pub aabb: Aabb3,
}

/// A validated block.
#[derive(Clone, Debug)]
pub struct AssemblyBlock {
    pub name: String,
    pub mesh: Mesh,
    pub support: bool,
    /// kg/m³ (the block's own or the scene's).
    pub density: f64,
    /// Volume, volume centroid and inertia per unit density.
    pub mass: MassProperties,
    pub faces: Vec<Face>,
    pub aabb: Aabb3,
    /// Volume / largest face area: a plate's thickness, a cube's edge (m).
    pub thickness: f64,
}

impl AssemblyBlock {
    /// kg.
    pub fn mass(&self) -> f64 {
        self.density * self.mass.volume
    }
}

/// A validated scene: what interface detection, statics and dynamics take.
#[derive(Clone, Debug)]
pub struct Assembly {
    pub name: String,
    pub blocks: Vec<AssemblyBlock>,
    pub material: Material,
    pub gravity: Vector3,
    pub ground: bool,
    /// Bounding-box diagonal of all blocks: the length every tolerance is relative to.
    pub scale: f64,
    pub tolerances: AbsTolerances,
    pub warnings: Vec<Warning>,
}

impl Assembly {
    /// Validates and repairs every block. Fails on the first block that cannot be repaired.
    pub fn new(scene: &Scene, tolerances: &Tolerances) -> Result<Self, ModelError> {
        if scene.blocks.is_empty() {
            return Err(ModelError::NoBlocks);
        }
        if !Material::valid_friction(scene.material.friction) {
            return Err(ModelError::BadFriction(scene.material.friction));
        }
        if !scene.gravity.iter().all(|g| g.is_finite()) {
            let g = scene.gravity;
            return Err(ModelError::BadGravity([g.x, g.y, g.z]));
        }
        let mut names = HashSet::new();
        for (i, b) in scene.blocks.iter().enumerate() {
            if b.name.is_empty() {
                return Err(ModelError::EmptyName(i));
            }
            if !names.insert(b.name.as_str()) {
                return Err(ModelError::DuplicateName(b.name.clone()));
            }
        }
        if let Some(l) = tolerances.reference_length.filter(|l| !(*l > 0.0 && l.is_finite())) {
            return Err(ModelError::BadReferenceLength(l));
        }
        let scale = tolerances.scale(scene.scale());
        let tol = tolerances.resolve(scale);
        let mut blocks = Vec::with_capacity(scene.blocks.len());
        let mut warnings = Vec::new();
        for b in &scene.blocks {
            let density = b.density.unwrap_or(scene.material.density);
            if !(density > 0.0 && density.is_finite()) {
                return Err(ModelError::BadDensity { block: b.name.clone(), density });
            }
            let r = repair(&b.mesh, &tol).map_err(|source| ModelError::Mesh { block: b.name.clone(), source })?;
            warnings.extend(r.warnings.into_iter().map(|w| Warning { block: b.name.clone(), warning: w }));
            let faces = face_data(&r.mesh);
            let largest = faces.iter().map(|f| f.area).fold(0.0, f64::max);
            blocks.push(AssemblyBlock {
                name: b.name.clone(),
                aabb: r.mesh.aabb(),
                mesh: r.mesh,
                support: b.support,
                density,
                thickness: r.mass.volume / largest,
                mass: r.mass,
                faces,
            });
        }
        Ok(Self {
            name: scene.name.clone(),
            blocks,
            material: scene.material,
            gravity: scene.gravity,
            ground: scene.ground,
            scale,
            tolerances: tol,
            warnings,
        })
    }

    pub fn block(&self, id: BlockId) -> &AssemblyBlock {
        &self.blocks[id.0]
    }

    pub fn find(&self, name: &str) -> Option<BlockId> {
        self.blocks.iter().position(|b| b.name == name).map(BlockId)
    }

    /// Total weight of the free (non-support) blocks, N.
    pub fn free_weight(&self) -> f64 {
        let g = self.gravity.norm();
        self.blocks.iter().filter(|b| !b.support).map(|b| b.mass() * g).sum()
    }

    /// The bounding box of every block (empty without blocks).
    pub fn aabb(&self) -> Aabb3 {
        let mut bb = Aabb3::empty();
        self.blocks.iter().for_each(|b| bb.merge(&b.mesh.aabb()));
        bb
    }

    pub fn supports(&self) -> impl Iterator<Item = BlockId> + '_ {
        self.blocks.iter().enumerate().filter(|(_, b)| b.support).map(|(i, _)| BlockId(i))
    }
}

fn face_data(mesh: &Mesh) -> Vec<Face> {
    (0..mesh.faces.len())
        .map(|f| {
            let pts: Vec<Point3> = mesh.face_points(f).collect();
            let a = area_vector(&pts);
            let area = a.norm();
            Face {
                normal: if area > 0.0 { a / area } else { Vector3::zeros() },
                area,
                centroid: centroid(&pts),
                aabb: Aabb3::from_points(&pts),
            }
        })
        .collect()
}
