//! Crushing at the interfaces: with a compressive strength σ (Pa), each interface's normal
//! forces are bounded by the statics' biaxial rectangular stress block ([`StressBlock`]:
//! N ≤ σ κ a₀ a₁, a_k the resultant's distance to the nearer edge along each of two in-plane
//! axes) — the same rotated second-order cones as the statics' crushing rows
//! ([`stress_block_cones`]), over the interface's active vertex contacts. The block is fixed in
//! block a's face (the polygon, its axes and extents as detected), so a hinge's stress block
//! shrinks towards its edge as the joint opens. A bound that binds lets the contact yield: the
//! step's complementarity then allows the faces to close into each other (the stone crushes
//! plastically), and the overlap is reported as penetration. Ground contacts (vertex by
//! vertex) and touches have no area: they do not crush.
//!
//! Non-dimensional (lengths by the model size L, forces by the free weight F, σ by F / L²).

use super::contacts::{Contact, Origin};
use crate::interfaces::Interface;
use crate::statics::{ConicProblem, StrengthColumn, StressBlock, stress_block, stress_block_cones};
use std::collections::BTreeMap;

/// An interface's stress block in its own frame (about its area centroid) and each polygon
/// vertex's coordinate along the block's two axes, non-dimensional.
#[derive(Clone, Debug)]
pub(super) struct Bearing {
    block: StressBlock,
    along: Vec<[f64; 2]>,
}

/// The bearing of every interface, in detection order, lengths by `length` (m).
pub(super) fn bearings(interfaces: &[Interface], length: f64) -> Vec<Bearing> {
    interfaces
        .iter()
        .map(|itf| {
            let f = &itf.frame;
            let pts: Vec<[f64; 2]> = itf
                .polygon
                .iter()
                .map(|p| [(p - f.origin).dot(&f.u) / length, (p - f.origin).dot(&f.v) / length])
                .collect();
            let block = stress_block(0..pts.len(), &pts);
            let along = pts.iter().map(|p| block.axes.map(|a| p[0] * a[0] + p[1] * a[1])).collect();
            Bearing { block, along }
        })
        .collect()
}

/// Appends the crushing cones (and their auxiliary columns) of every interface with an active
/// vertex contact (`normals`: each active contact's index and the column of its normal force),
/// at the non-dimensional strength `sigma`.
pub(super) fn rows(
    sigma: f64,
    bearings: &[Bearing],
    contacts: &[Contact],
    normals: impl Iterator<Item = (usize, usize)>,
    p: &mut ConicProblem,
) {
    let mut by_interface: BTreeMap<usize, Vec<(usize, f64, [f64; 2])>> = BTreeMap::new();
    for (contact, column) in normals {
        if let Origin::Interface { interface, vertex } = contacts[contact].origin {
            by_interface.entry(interface).or_default().push((column, 1.0, bearings[interface].along[vertex]));
        }
    }
    for (interface, terms) in by_interface {
        stress_block_cones(&bearings[interface].block, &terms, StrengthColumn::Fixed(sigma), p);
    }
}
