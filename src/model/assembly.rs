//! Validated scene: repaired meshes, mass properties, model size, face planes.

use super::{Block, BlockId, BlockLoads, Density, Material, Scene};
use crate::geometry::format::significant;
use crate::geometry::polygon::{area_vector, centroid};
use crate::geometry::tolerances::AbsTolerances;
use crate::geometry::{Aabb3, MassProperties, Mesh, MeshError, MeshWarning, Point3, RepairCache, Tolerances, Vector3};
use std::collections::HashSet;
use std::path::PathBuf;
use thiserror::Error;

/// Why a scene cannot be analysed. Each variant names the block.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ModelError {
    /// The scene has no blocks.
    #[error("the scene has no blocks")]
    NoBlocks,
    /// A block's mesh is not a closed solid (or cannot be repaired into one).
    #[error("block '{block}': {source}")]
    Mesh {
        /// The block's name.
        block: String,
        /// What is wrong with its mesh.
        #[source]
        source: MeshError,
    },
    /// Two blocks share a name.
    #[error("two blocks are called '{0}'; block names must be unique")]
    DuplicateName(String),
    /// A block (its position in the scene, from 0) has an empty name.
    #[error("block #{0} has an empty name")]
    EmptyName(usize),
    /// A block's density is not usable.
    #[error("block '{block}': density {density} is not a positive finite number (kg/m³)")]
    BadDensity {
        /// The block's name.
        block: String,
        /// The density as given, kg/m³.
        density: f64,
    },
    /// A block's cell densities do not fit its grid (not k³ values, or one not usable).
    #[error("block '{block}': {count} cell densities: {why}")]
    BadCells {
        /// The block's name.
        block: String,
        /// How many values were given.
        count: usize,
        /// What is wrong, in words.
        why: &'static str,
    },
    /// μ is negative, infinite or NaN.
    #[error("friction coefficient {0} is not a finite number ≥ 0")]
    BadFriction(f64),
    /// σ_c is not a finite positive number (Pa).
    #[error("compressive strength {0} is not a finite number > 0 (Pa)")]
    BadStrength(f64),
    /// Gravity is not a finite vector (m/s²).
    #[error("gravity {0:?} is not a finite vector")]
    BadGravity([f64; 3]),
    /// A relative tolerance is out of range.
    #[error(transparent)]
    BadTolerance(#[from] crate::geometry::ToleranceError),
    /// The reference length the tolerances scale with is not a finite positive length (m).
    #[error("reference length {0} is not a positive finite number (m)")]
    BadReferenceLength(f64),
    /// The model is too small for floating point (its bounding-box diagonal, in its unit).
    #[error(
        "the model is only {0:.2e} across (its bounding-box diagonal; at least 1e-15 keeps its areas, \
         volumes and moments within floating-point range): give the coordinates in a smaller unit \
         (mm instead of m)"
    )]
    TooSmall(f64),
    /// Two blocks interpenetrate (an error only with `AnalysisSettings::strict`); the deepest
    /// pair relative to its size, and how many other pairs overlap.
    #[error("{overlap}{}", others_note(.others))]
    Overlap {
        /// The deepest pair, relative to the thinner block.
        overlap: Overlap,
        /// How many other pairs overlap.
        others: usize,
    },
    /// A load (`index` in the scene's list) that cannot be applied.
    #[error("load #{index}: {message}")]
    BadLoad {
        /// The load's position in the scene's list, from 0.
        index: usize,
        /// Why it cannot be applied.
        message: String,
    },
}

/// Something the analysis let pass but the user should know, naming the file, block or pair.
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// A repair of a block's mesh made while validating it.
    Repair {
        /// The block's name.
        block: String,
        /// What was repaired (weld, flipped faces, triangulated faces).
        warning: MeshWarning,
    },
    /// A key the scene file format does not know, ignored (metadata such as a `params` object,
    /// tool names or colours). `place` is where it was: `None` at the top level, else e.g.
    /// `block 'top'` or `cut 2`.
    UnknownKey {
        /// The scene file.
        file: PathBuf,
        /// Where the key was (`None` at the top level).
        place: Option<String>,
        /// The key as written.
        key: String,
    },
    /// Two blocks interpenetrate beyond the coplanarity tolerance: the statics see only their
    /// interfaces, not the overlap.
    Overlap(Overlap),
    /// A load (`index` in the scene's list) on a support block: ignored, a support takes any
    /// reaction.
    LoadOnSupport {
        /// The load's position in the scene's list, from 0.
        index: usize,
        /// The support's name.
        block: String,
    },
}

impl Warning {
    /// The block a repair warning concerns.
    pub fn block(&self) -> Option<&str> {
        match self {
            Warning::Repair { block, .. } => Some(block),
            _ => None,
        }
    }
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Warning::Repair { block, warning } => write!(f, "block '{block}': {warning}"),
            Warning::UnknownKey { file, place, key } => {
                write!(f, "{}: ", file.display())?;
                if let Some(place) = place {
                    write!(f, "{place}: ")?;
                }
                write!(f, "unknown key `{key}` ignored")
            }
            Warning::Overlap(o) => write!(f, "{o}"),
            Warning::LoadOnSupport { index, block } => {
                write!(f, "load #{index} on support block '{block}' ignored (a support takes any reaction)")
            }
        }
    }
}

/// Two blocks that interpenetrate: how deep (the shortest translation that would separate
/// them, m) and how that compares with the smaller block and the tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct Overlap {
    /// One block's name.
    pub a: String,
    /// The other block's name.
    pub b: String,
    /// Penetration depth, m.
    pub depth: f64,
    /// The thinner block's thickness (volume / largest face area: a cube's edge), m.
    pub size: f64,
    /// The pair's coplanarity tolerance, m: a joint open or closed by less is an interface.
    pub tolerance: f64,
}

impl Overlap {
    /// Depth relative to the thinner block's thickness.
    pub fn relative(&self) -> f64 {
        self.depth / self.size
    }
}

impl std::fmt::Display for Overlap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "blocks '{}' and '{}' interpenetrate {} m deep ({} of the thinner one's thickness {} m; the \
             coplanarity tolerance is {} m): the statics see their interfaces, not the overlap",
            self.a,
            self.b,
            significant(self.depth),
            significant(self.relative()),
            significant(self.size),
            significant(self.tolerance)
        )
    }
}

fn others_note(others: &usize) -> String {
    match others {
        0 => String::new(),
        n => format!("; {n} other pair(s) interpenetrate too"),
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
    /// The block's (or piece's) name, unique in the assembly.
    pub name: String,
    /// Its closed, consistently oriented mesh (welded and repaired), m.
    pub mesh: Mesh,
    /// A fixed body: no equilibrium rows, takes any reaction.
    pub support: bool,
    /// kg/m³ (the block's own or the scene's).
    pub density: f64,
    /// Volume, volume centroid and inertia per unit density.
    pub mass: MassProperties,
    /// Its planar faces with their planes, in the mesh's face order.
    pub faces: Vec<Face>,
    /// Its axis-aligned bounding box, m.
    pub aabb: Aabb3,
    /// Volume / largest face area: a plate's thickness, a cube's edge (m).
    pub thickness: f64,
}

/// A block's density, uniform or per cell, is finite and positive (cells: k³ of them, none
/// negative, not all zero).
fn check_density(b: &Block, default: f64) -> Result<(), ModelError> {
    let bad = |density: f64| ModelError::BadDensity { block: b.name.clone(), density };
    let cells = |count, why| ModelError::BadCells { block: b.name.clone(), count, why };
    match b.density.as_ref().unwrap_or(&Density::Uniform(default)) {
        Density::Uniform(d) if !(*d > 0.0 && d.is_finite()) => Err(bad(*d)),
        Density::Uniform(_) => Ok(()),
        Density::Cells(v) => {
            let k = (v.len() as f64).cbrt().round() as usize;
            if v.is_empty() || k * k * k != v.len() {
                return Err(cells(v.len(), "not k³ for any whole k (8 for octants)"));
            }
            if let Some(d) = v.iter().find(|d| !(**d >= 0.0 && d.is_finite())) {
                return Err(cells(v.len(), if d.is_finite() { "one is negative" } else { "one is not finite" }));
            }
            if v.iter().all(|d| *d == 0.0) {
                return Err(cells(v.len(), "all are zero: the block has no mass"));
            }
            Ok(())
        }
    }
}

/// A block's mean density and its mass properties per unit of it (`check_density` passed):
/// with cells, each cell of its grid weighted by its density ([`crate::geometry::cells`]).
fn block_mass(
    b: &Block,
    default: f64,
    mesh: &Mesh,
    geometric: MassProperties,
    eps: f64,
) -> Result<(f64, MassProperties), ModelError> {
    let Some(Density::Cells(v)) = &b.density else {
        let d = match b.density {
            Some(Density::Uniform(d)) => d,
            _ => default,
        };
        return Ok((d, geometric));
    };
    let k = (v.len() as f64).cbrt().round() as usize;
    let parts: Vec<(f64, MassProperties)> = v.iter().copied().zip(crate::geometry::cells::grid(mesh, k, eps)).collect();
    let Some(mass) = MassProperties::combined(&parts) else {
        let why = "the cells with density hold none of the block's volume";
        return Err(ModelError::BadCells { block: b.name.clone(), count: v.len(), why });
    };
    let total: f64 = parts.iter().map(|(d, c)| d * c.volume).sum();
    Ok((total / mass.volume, mass))
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
    /// The scene's name.
    pub name: String,
    /// The validated blocks; a [`BlockId`] indexes them.
    pub blocks: Vec<AssemblyBlock>,
    /// Density, μ and compressive strength of the material.
    pub material: Material,
    /// Gravity, m/s² (standard gravity along −z by default).
    pub gravity: Vector3,
    /// Whether the ground plane z = 0 supports faces lying on it.
    pub ground: bool,
    /// Bounding-box diagonal of all blocks: the length every tolerance is relative to.
    pub scale: f64,
    /// The interface tolerances in model units (the relative ones times [`Assembly::scale`]).
    pub tolerances: AbsTolerances,
    /// Loads besides self-weight, per block (zero on supports): [`super::loads`].
    pub loads: Vec<BlockLoads>,
    /// The scene's load warnings, then the repairs made here; a [`crate::pipeline::Pipeline`]
    /// run puts the interpenetrating pairs ahead of them.
    pub warnings: Vec<Warning>,
}

impl Assembly {
    /// Validates and repairs every block. Fails on the first block that cannot be repaired.
    pub fn new(scene: &Scene, tolerances: &Tolerances) -> Result<Self, ModelError> {
        Self::new_cached(scene, tolerances, &mut RepairCache::default())
    }

    /// [`Self::new`] with the repairs kept by mesh content between runs (a pipeline's).
    pub fn new_cached(scene: &Scene, tolerances: &Tolerances, repairs: &mut RepairCache) -> Result<Self, ModelError> {
        if scene.blocks.is_empty() {
            return Err(ModelError::NoBlocks);
        }
        if !Material::valid_friction(scene.material.friction) {
            return Err(ModelError::BadFriction(scene.material.friction));
        }
        if let Some(s) = scene.material.strength
            && !Material::valid_strength(s)
        {
            return Err(ModelError::BadStrength(s));
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
        // Before any tolerance is derived from the model size: a stray vertex is named, not
        // the block its tolerances would break.
        let scale = super::coordinates::model_size(&scene.blocks, tolerances)?;
        let tol = tolerances.resolve(scale);
        let mut blocks = Vec::with_capacity(scene.blocks.len());
        let mut warnings = scene.warnings.clone();
        repairs.begin();
        for b in &scene.blocks {
            check_density(b, scene.material.density)?;
            let r =
                repairs.repair(&b.mesh, &tol).map_err(|source| ModelError::Mesh { block: b.name.clone(), source })?;
            let (density, mass) = block_mass(b, scene.material.density, &r.mesh, r.mass, tol.weld)?;
            warnings.extend(r.warnings.into_iter().map(|w| Warning::Repair { block: b.name.clone(), warning: w }));
            let faces = face_data(&r.mesh);
            let largest = faces.iter().map(|f| f.area).fold(0.0, f64::max);
            blocks.push(AssemblyBlock {
                name: b.name.clone(),
                aabb: r.mesh.aabb(),
                mesh: r.mesh,
                support: b.support,
                density,
                thickness: r.mass.volume / largest,
                mass,
                faces,
            });
        }
        let (loads, load_warnings) = super::loads::resolve(&scene.loads, &blocks, scene.gravity.norm(), tol.coplanar)?;
        warnings.extend(load_warnings);
        Ok(Self {
            name: scene.name.clone(),
            loads,
            blocks,
            material: scene.material,
            gravity: scene.gravity,
            ground: scene.ground,
            scale,
            tolerances: tol,
            warnings,
        })
    }

    /// The block `id` names.
    pub fn block(&self, id: BlockId) -> &AssemblyBlock {
        &self.blocks[id.0]
    }

    /// The block called `name`, if any.
    pub fn find(&self, name: &str) -> Option<BlockId> {
        self.blocks.iter().position(|b| b.name == name).map(BlockId)
    }

    /// The median of the blocks' bounding-box diagonals, m (None without blocks): the length
    /// the engines and the overlap check measure depths and tolerances against.
    pub fn median_block_size(&self) -> Option<f64> {
        let mut sizes: Vec<f64> = self.blocks.iter().map(|b| b.aabb.diagonal()).collect();
        sizes.sort_by(f64::total_cmp);
        sizes.get(sizes.len() / 2).copied()
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

    /// Whether any free block carries a live load.
    pub fn has_live_loads(&self) -> bool {
        self.loads.iter().any(|l| l.live.iter().any(|&v| v != 0.0))
    }

    /// The support blocks, in block order.
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
