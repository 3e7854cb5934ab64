//! Crushing at the interfaces: with a compressive strength σ (Pa), each interface's normal
//! forces are bounded by the statics' rectangular stress block ([`StressBlock`]: along each of
//! two in-plane axes, N ≤ 2 σ w min(e − lo, hi − e), e the resultant's position, w the
//! interface's width across the axis) — the same rotated second-order cones as the statics'
//! crushing rows, over the interface's active vertex contacts. The block is fixed in block a's
//! face (the polygon, its axes and extents as detected), so a hinge's stress block shrinks
//! towards its edge as the joint opens. A bound that binds lets the contact yield: the step's
//! complementarity then allows the faces to close into each other (the stone crushes
//! plastically), and the overlap is reported as penetration. Ground contacts (vertex by
//! vertex) and touches have no area: they do not crush.
//!
//! Lengths in m (non-dimensional in the rows: by the model size), σ in Pa.

use super::contacts::{Contact, Origin};
use crate::interfaces::Interface;
use crate::statics::{Cone, ConicProblem, StressBlock, stress_block};
use std::collections::BTreeMap;

/// An interface's stress block in its own frame (m, about its area centroid) and each polygon
/// vertex's coordinate along the block's two axes (m).
#[derive(Clone, Debug)]
pub(super) struct Bearing {
    block: StressBlock,
    along: Vec<[f64; 2]>,
}

/// The bearing of every interface, in detection order.
pub(super) fn bearings(interfaces: &[Interface]) -> Vec<Bearing> {
    interfaces
        .iter()
        .map(|itf| {
            let f = &itf.frame;
            let pts: Vec<[f64; 2]> =
                itf.polygon.iter().map(|p| [(p - f.origin).dot(&f.u), (p - f.origin).dot(&f.v)]).collect();
            let block = stress_block(0..pts.len(), &pts);
            let along = pts.iter().map(|p| block.axes.map(|a| p[0] * a[0] + p[1] * a[1])).collect();
            Bearing { block, along }
        })
        .collect()
}

/// Appends the crushing cones of every interface with an active vertex contact (`normals`:
/// each active contact's index and the column of its normal force), at the non-dimensional
/// strength `sigma` (σ L² / F), lengths by `length` (m).
pub(super) fn rows(
    sigma: f64,
    length: f64,
    bearings: &[Bearing],
    contacts: &[Contact],
    normals: impl Iterator<Item = (usize, usize)>,
    p: &mut ConicProblem,
) {
    let mut by_interface: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new();
    for (contact, column) in normals {
        if let Origin::Interface { interface, vertex } = contacts[contact].origin {
            by_interface.entry(interface).or_default().push((column, vertex));
        }
    }
    let r = std::f64::consts::FRAC_1_SQRT_2;
    for (interface, members) in by_interface {
        let bearing = &bearings[interface];
        let block = &bearing.block;
        for k in 0..2 {
            let x = sigma * block.width[k] / length;
            for (sign, edge) in [(1.0, block.lo[k]), (-1.0, block.hi[k])] {
                // Cone 2 x y ≥ z², y = sign (M − edge N), z = N, as ((x + y)/√2, z, (x − y)/√2);
                // its slack is b − A f, so each row holds minus y's and z's coefficients.
                let row = p.b.len();
                for &(col, vertex) in &members {
                    let y = sign * (bearing.along[vertex][k] - edge) / length;
                    p.a.extend(
                        [(row, col, -r * y), (row + 1, col, -1.0), (row + 2, col, r * y)]
                            .into_iter()
                            .filter(|e| e.2 != 0.0),
                    );
                }
                p.b.extend([r * x, 0.0, r * x]);
                p.cones.push(Cone::SecondOrder(3));
            }
        }
    }
}
