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
//! Which joints get the rows ([`binding`]): closed ones (every vertex an active contact, none
//! open, the resultant not at an edge) whose forces in the step's round need more than half the strength — found round by
//! round like the friction capacities. A stone far stronger than its stresses adds no rows (the
//! rigid answer, bit for bit), and an open joint — a hinge, whose contact is its edge — is not
//! bounded: the crushed zone that would carry a hinge's thrust a little inside its edge is not
//! modelled (its width, N / (σ w), is what the statics' stress block measures).
//!
//! Non-dimensional (lengths by the model size L, forces by the free weight F, σ by F / L²).

use super::contacts::{Contact, Origin};
use crate::interfaces::Interface;
use crate::statics::{ConicProblem, StrengthColumn, StressBlock, stress_block, stress_block_cones};
use std::collections::{BTreeMap, BTreeSet};

/// A joint whose round forces need more than this fraction of the strength gets its rows.
const NEAR: f64 = 0.5;

/// A resultant within this fraction of the joint's extent of its edge is a hinge's (left
/// unbounded: its rigid contact is the edge itself).
const HINGE: f64 = 1e-3;

/// The crushing of a step: every interface's bearing, the strength (non-dimensional), and the
/// interfaces bounded this round.
pub(super) struct Crush<'a> {
    pub bearings: &'a [Bearing],
    pub sigma: f64,
    pub bound: &'a BTreeSet<usize>,
}

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

/// Appends the crushing cones (and their auxiliary columns) of every bounded interface with an
/// active vertex contact (`normals`: each active contact's index and the column of its normal
/// force).
pub(super) fn rows(
    crush: &Crush,
    contacts: &[Contact],
    normals: impl Iterator<Item = (usize, usize)>,
    p: &mut ConicProblem,
) {
    let mut by_interface: BTreeMap<usize, Vec<(usize, f64, [f64; 2])>> = BTreeMap::new();
    for (contact, column) in normals {
        if let Origin::Interface { interface, vertex } = contacts[contact].origin
            && crush.bound.contains(&interface)
        {
            by_interface.entry(interface).or_default().push((column, 1.0, crush.bearings[interface].along[vertex]));
        }
    }
    for (interface, terms) in by_interface {
        stress_block_cones(&crush.bearings[interface].block, &terms, StrengthColumn::Fixed(crush.sigma), p);
    }
}

/// A joint's active vertex contacts in a round: how many, whether any is open, and each
/// vertex's normal force.
type Joint = (usize, bool, Vec<(usize, f64)>);

/// Adds to `bound` every closed joint whose normal forces `normal` (per active contact: its
/// index, gap in m, force non-dimensional) need more than [`NEAR`] of the strength; whether any
/// was added. Open by more than `open` m is open.
pub(super) fn binding(
    bearings: &[Bearing],
    sigma: f64,
    contacts: &[Contact],
    normal: impl Iterator<Item = (usize, f64, f64)>,
    open: f64,
    bound: &mut BTreeSet<usize>,
) -> bool {
    let mut by_interface: BTreeMap<usize, Joint> = BTreeMap::new();
    for (contact, gap, f) in normal {
        if let Origin::Interface { interface, vertex } = contacts[contact].origin {
            let entry = by_interface.entry(interface).or_insert((0, false, Vec::new()));
            entry.0 += 1;
            entry.1 |= gap > open;
            entry.2.push((vertex, f));
        }
    }
    let mut grew = false;
    for (interface, (count, opened, forces)) in by_interface {
        let bearing = &bearings[interface];
        if opened || count < bearing.along.len() || bound.contains(&interface) {
            continue;
        }
        if !bearing.hinged(&forces) && bearing.demand(&forces) > NEAR * sigma {
            grew |= bound.insert(interface);
        }
    }
    grew
}

impl Bearing {
    fn forces<'a>(&'a self, forces: &'a [(usize, f64)]) -> impl Iterator<Item = ([f64; 2], f64)> + Clone + 'a {
        forces.iter().map(|&(v, f)| (self.along[v], f))
    }

    /// Whether the resultant sits at an edge ([`HINGE`]): a hinge, or nothing to carry.
    fn hinged(&self, forces: &[(usize, f64)]) -> bool {
        let b = &self.block;
        self.block.reach(self.forces(forces)).is_none_or(|r| (0..2).any(|k| r[k] <= HINGE * (b.hi[k] - b.lo[k])))
    }

    /// The strength the normal forces (vertex, force) need under the biaxial stress block.
    fn demand(&self, forces: &[(usize, f64)]) -> f64 {
        self.block.need(self.forces(forces))
    }
}
