//! The scene model: named blocks (closed polygon meshes), supports, material, gravity, the
//! optional ground plane and the cut history; and [`Assembly`], the validated form every analysis works on.
//!
//! Units SI (m, kg, N), z up, gravity (0, 0, −9.81) by default. Supports are fixed bodies: they
//! get no equilibrium rows. The ground plane z = 0, when enabled, supports faces lying on it.

mod assembly;
pub mod builtin;
pub mod coordinates;
pub mod cut;
pub mod edit;
mod friction;
pub mod loads;
pub mod movement;
pub mod shaking;

pub(crate) use crate::geometry::format::significant;
pub use assembly::{Assembly, AssemblyBlock, ModelError, Overlap, Warning};
pub use builtin::{BuiltinError, builtin};
pub use cut::{Cut, CutShape};
pub use friction::FrictionModel;
pub use loads::{BlockLoads, Load, LoadKind};
pub use movement::Movement;
pub use shaking::Shaking;

/// Which blocks are supports ([`Scene::choose_supports`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SupportChoice {
    /// The blocks at the lowest level.
    Lowest,
    /// These blocks (by name), and no others.
    Named(Vec<String>),
}

/// A block name the scene does not have.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the scene has no block named '{0}'")]
pub struct UnknownBlock(pub String);

use crate::geometry::{Mesh, Vector3};
use serde::{Deserialize, Serialize};

/// Index of a block in its [`Scene`] / [`Assembly`] (stable for a given scene; names are the
/// user-facing stable ids).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct BlockId(pub usize);

/// One rigid block as given by the user.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// The block's name, unique in the scene (cut pieces are named from it).
    pub name: String,
    /// Its closed surface mesh, m; it may be non-convex.
    pub mesh: Mesh,
    /// Fixed body: no equilibrium rows, takes any reaction.
    pub support: bool,
    /// Overrides the scene's density for this block (kg/m³).
    pub density: Option<Density>,
}

/// A block's density, kg/m³: one for the whole block, or one per cell of its bounding box's
/// k × k × k grid ([`crate::geometry::cells`]: x fastest, then y, then z; k³ values), which moves
/// its centroid — an infill design's ([`synthesis::infill`](mod@crate::synthesis::infill)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Density {
    /// One density for the whole block, kg/m³.
    Uniform(f64),
    /// k³ densities, one per cell of the k × k × k grid, kg/m³.
    Cells(Vec<f64>),
}

impl From<f64> for Density {
    fn from(d: f64) -> Self {
        Density::Uniform(d)
    }
}

impl Block {
    /// A free block of the scene's density.
    pub fn new(name: impl Into<String>, mesh: Mesh) -> Self {
        Self { name: name.into(), mesh, support: false, density: None }
    }

    /// The block made a support (`true`) or free.
    pub fn support(mut self, yes: bool) -> Self {
        self.support = yes;
        self
    }
}

/// Material shared by all blocks unless a block overrides its density.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// kg/m³.
    pub density: f64,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
    /// Compressive strength σ_c, Pa (README: typical values); `None`: the stone does not crush.
    pub strength: Option<f64>,
}

impl Default for Material {
    /// The seed paper's case studies: 600 kg/m³, μ = tan 40° ≈ 0.839.
    fn default() -> Self {
        Self { density: 600.0, friction: 40f64.to_radians().tan(), strength: None }
    }
}

impl Material {
    /// The one rule for a friction coefficient: a finite number ≥ 0. Each way μ enters — the
    /// scene's material (`Assembly::new`), an edit, a statics override — is checked by it once.
    pub fn valid_friction(mu: f64) -> bool {
        mu >= 0.0 && mu.is_finite()
    }

    /// The one rule for a compressive strength: a finite number > 0 (Pa).
    pub fn valid_strength(sigma: f64) -> bool {
        sigma > 0.0 && sigma.is_finite()
    }
}

/// Standard gravity (m/s², along −z).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// A design: blocks, material, gravity and supports.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The design's name, as reports show it.
    pub name: String,
    /// The source blocks (before the cut history).
    pub blocks: Vec<Block>,
    /// Density, μ and compressive strength of the material.
    pub material: Material,
    /// m/s² ([`Scene::new`]: [`STANDARD_GRAVITY`] along −z).
    pub gravity: Vector3,
    /// The plane z = 0 supports faces lying on it.
    pub ground: bool,
    /// Cut history: when not empty, `blocks` are the source shapes and the blocks to analyse
    /// are the pieces of replaying these cuts ([`crate::history::resolve`]).
    pub cuts: Vec<Cut>,
    /// Pieces left out after the cut history (by name): parts removed from a design.
    pub removed: Vec<String>,
    /// Pieces made supports after the cut history (by name), besides blocks marked `support`.
    pub supports: Vec<String>,
    /// Densities of pieces after the cut history (kg/m³, by name), overriding the source
    /// shape's and the material's: what an infill design sets ([`synthesis::infill`](mod@crate::synthesis::infill)).
    pub densities: std::collections::BTreeMap<String, Density>,
    /// Bounds of pieces' densities for an infill design (kg/m³, `[low, high]` by name), over
    /// the infill's own range.
    pub density_ranges: std::collections::BTreeMap<String, [f64; 2]>,
    /// An assembly order (piece names, or source-shape names standing for all their pieces
    /// bottom-up) for [`crate::studies::sequence`]; empty when none is given.
    pub order: Vec<String>,
    /// Point loads and acceleration fields besides self-weight ([`loads`]); dead ones are part
    /// of every analysis, live ones are what a load factor scales.
    pub loads: Vec<Load>,
    /// Prescribed support paths for a settlement analysis ([`movement`]); empty when none.
    pub movements: Vec<Movement>,
    /// The ground motion `voussoir shake` runs when none is named ([`shaking`]).
    pub ground_motion: Option<Shaking>,
    /// What reading the file let pass (unknown keys ignored); the [`Assembly`] carries them
    /// on, ahead of its repair warnings. Never written back to a file.
    pub warnings: Vec<Warning>,
}

impl Scene {
    /// A scene of `blocks` in the default material, standard gravity, no ground, no cuts.
    pub fn new(name: impl Into<String>, blocks: Vec<Block>) -> Self {
        Self {
            name: name.into(),
            blocks,
            material: Material::default(),
            gravity: Vector3::new(0.0, 0.0, -STANDARD_GRAVITY),
            ground: false,
            cuts: Vec::new(),
            removed: Vec::new(),
            supports: Vec::new(),
            densities: Default::default(),
            density_ranges: Default::default(),
            order: Vec::new(),
            loads: Vec::new(),
            movements: Vec::new(),
            ground_motion: None,
            warnings: Vec::new(),
        }
    }

    /// Marks as supports the blocks whose lowest point is within `rel_tol` × (model size) of
    /// the lowest point of the whole scene. Returns how many were marked.
    pub fn mark_lowest_as_supports(&mut self, rel_tol: f64) -> usize {
        let aabbs: Vec<_> = self.blocks.iter().map(|b| b.mesh.aabb()).collect();
        let mut all = crate::geometry::Aabb3::empty();
        aabbs.iter().for_each(|a| all.merge(a));
        if all.is_empty() {
            return 0;
        }
        let tol = rel_tol * all.diagonal();
        let mut count = 0;
        for (b, a) in self.blocks.iter_mut().zip(&aabbs) {
            if a.min.z <= all.min.z + tol {
                b.support = true;
                count += 1;
            }
        }
        count
    }

    /// The model size every tolerance is relative to: the bounding-box diagonal of all finite
    /// vertices (1 when there are none; an assembly refuses such a model,
    /// `coordinates::extent`).
    pub fn scale(&self) -> f64 {
        let extent = coordinates::extent(&self.blocks);
        if extent > 0.0 { extent } else { 1.0 }
    }

    /// One density for every block (kg/m³): the material's, with the blocks' and pieces' own
    /// overrides dropped (`analyze --density`, Python's `density=`).
    pub fn set_density(&mut self, density: f64) {
        self.material.density = density;
        self.blocks.iter_mut().for_each(|b| b.density = None);
        self.densities.clear();
    }

    /// Replaces the supports given in the scene by `choice` (`analyze --supports`, Python's
    /// `supports=`). "The lowest level" is within `rel_tol` × (model size): the Armadillo's 33
    /// supports sit within 2.5 cm (1.2e-3 of its size) of each other. Errors name the first
    /// name that is no block, and change nothing.
    pub fn choose_supports(&mut self, choice: &SupportChoice, rel_tol: f64) -> Result<(), UnknownBlock> {
        match choice {
            SupportChoice::Lowest => {
                self.blocks.iter_mut().for_each(|b| b.support = false);
                self.mark_lowest_as_supports(rel_tol);
            }
            SupportChoice::Named(names) => {
                if let Some(missing) = names.iter().find(|n| self.find(n).is_none()) {
                    return Err(UnknownBlock(missing.clone()));
                }
                for b in &mut self.blocks {
                    b.support = names.contains(&b.name);
                }
            }
        }
        Ok(())
    }

    /// Index of the block called `name`.
    pub fn find(&self, name: &str) -> Option<BlockId> {
        self.blocks.iter().position(|b| b.name == name).map(BlockId)
    }
}
