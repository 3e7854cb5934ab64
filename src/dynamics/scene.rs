//! What both engines are given beside the assembly and the settings: the paths of moved
//! supports and the floor the blocks land on. Units SI, z up.

use super::settings::DropSettings;
use crate::model::Assembly;

/// A support moved along a prescribed path: its whole translation (m) and rotation vector
/// (rad, about its centroid), covered in the fractions each step is given
/// (`exact::World::step_supports`, `Simulation::step_supports`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SupportPath {
    /// Index of the support in the assembly.
    pub block: usize,
    /// Its whole translation, m.
    pub translation: crate::geometry::Vector3,
    /// Its whole rotation vector about its centroid, rad.
    pub rotation: crate::geometry::Vector3,
}

/// The height (m) of the plane z = const the blocks land on: the design's own ground (z = 0),
/// or with [`DropSettings::floor`] and supports, one median block size below the lowest point
/// of the design — under the supports, so that nothing touches it at the start (a free block
/// standing on nothing beside a support must still fall), and close enough that a collapse
/// lands at about the foundations' level; none without supports.
pub fn floor_level(assembly: &Assembly, settings: &DropSettings) -> Option<f64> {
    if assembly.ground {
        return Some(0.0);
    }
    if !settings.floor || !assembly.blocks.iter().any(|b| b.support) {
        return None;
    }
    let lowest = assembly.blocks.iter().map(|b| b.aabb.min.z).fold(f64::INFINITY, f64::min);
    let size = assembly.median_block_size().unwrap_or(0.0);
    Some(lowest - size).filter(|z| z.is_finite())
}
