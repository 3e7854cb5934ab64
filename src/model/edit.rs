//! Edits of a design, as data: what the ECS layer's requests and the CLI carry. Applying one is
//! a pure function of the scene; names are checked when the design is next resolved.

use super::FrictionModel;
use super::{Block, Cut, Load, Material, Scene};
use thiserror::Error;

/// One edit of a design.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Replace the whole design.
    Load(Box<Scene>),
    /// Append a cut to the history.
    AddCut(Cut),
    /// Replace cut `index` of the history.
    MoveCut {
        /// The cut's position in the history, from 0.
        index: usize,
        /// The cut that replaces it.
        cut: Cut,
    },
    /// Drop cut `index` of the history.
    RemoveCut(usize),
    /// Make a block or piece a support, or free it again.
    ToggleSupport(String),
    /// Leave a block or piece out of the design.
    RemoveBlock(String),
    /// Put a removed block or piece back.
    RestoreBlock(String),
    /// Add a source block.
    AddBlock(Block),
    /// Set the friction coefficient μ of the material.
    SetFriction(f64),
    /// Add a load (checked when the design is resolved, like names).
    AddLoad(Load),
    /// Drop load `index`.
    RemoveLoad(usize),
}

/// Settings-level edits (they do not change the design itself).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SettingsEdit {
    /// Analyse with this friction model (pyramid8, cone, box4).
    SetFrictionModel(FrictionModel),
}

/// Why an edit cannot be applied.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EditError {
    /// No cut at that position of the history.
    #[error("there is no cut {index} (the history has {len})")]
    NoCut {
        /// The position asked for.
        index: usize,
        /// How many cuts the history has.
        len: usize,
    },
    /// The block or piece to restore is not among the removed ones.
    #[error("'{0}' is not removed")]
    NotRemoved(String),
    /// A block to add has the name of one the design has.
    #[error("a block called '{0}' already exists")]
    Duplicate(String),
    /// μ is negative, infinite or NaN.
    #[error("friction coefficient {0} must be a finite number ≥ 0")]
    BadFriction(f64),
    /// No load at that position of the list.
    #[error("there is no load {index} (the design has {len})")]
    NoLoad {
        /// The position asked for.
        index: usize,
        /// How many loads the design has.
        len: usize,
    },
}

/// Applies `edit` to `scene`. Names of pieces are checked when the design is resolved.
pub fn apply(scene: &mut Scene, edit: &Edit) -> Result<(), EditError> {
    let len = scene.cuts.len();
    let no_cut = |index: usize| EditError::NoCut { index, len };
    match edit {
        Edit::Load(s) => *scene = (**s).clone(),
        Edit::AddCut(cut) => scene.cuts.push(cut.clone()),
        Edit::MoveCut { index, cut } => *scene.cuts.get_mut(*index).ok_or_else(|| no_cut(*index))? = cut.clone(),
        Edit::RemoveCut(index) => {
            if *index >= len {
                return Err(no_cut(*index));
            }
            scene.cuts.remove(*index);
        }
        Edit::ToggleSupport(name) => {
            // Without a history the blocks are the pieces: flip the flag itself.
            if let Some(b) = scene.blocks.iter_mut().find(|b| &b.name == name && len == 0) {
                b.support = !b.support;
            } else if let Some(i) = scene.supports.iter().position(|s| s == name) {
                scene.supports.remove(i);
            } else {
                scene.supports.push(name.clone());
            }
        }
        Edit::RemoveBlock(name) => scene.removed.push(name.clone()),
        Edit::RestoreBlock(name) => {
            let i = scene.removed.iter().position(|s| s == name).ok_or_else(|| EditError::NotRemoved(name.clone()))?;
            scene.removed.remove(i);
        }
        Edit::AddBlock(block) => {
            if scene.blocks.iter().any(|b| b.name == block.name) {
                return Err(EditError::Duplicate(block.name.clone()));
            }
            scene.blocks.push(block.clone());
        }
        Edit::SetFriction(mu) => {
            if !Material::valid_friction(*mu) {
                return Err(EditError::BadFriction(*mu));
            }
            scene.material.friction = *mu;
        }
        Edit::AddLoad(load) => scene.loads.push(load.clone()),
        Edit::RemoveLoad(index) => {
            if *index >= scene.loads.len() {
                return Err(EditError::NoLoad { index: *index, len: scene.loads.len() });
            }
            scene.loads.remove(*index);
        }
    }
    Ok(())
}
