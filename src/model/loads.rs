//! Loads beyond self-weight: point loads on blocks and a uniform acceleration field, each
//! *dead* (always applied, as self-weight is) or *live* (scaled by the load factor λ of
//! [`crate::stability`]).
//!
//! Units SI: a point load is a force in N applied at a point in m (the scene's coordinates); an
//! acceleration field is a vector in units of g (the scene's |gravity|) acting on every free
//! block's mass at its centroid — a horizontal 0.2 g is the pseudo-static seismic or
//! tilting-table load. Each load reaches the statics as a wrench per free block about its
//! centroid: force (N) and moment (N·m), world axes.

use super::{AssemblyBlock, ModelError, Warning, significant};
use crate::geometry::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// Whether a load is always applied or scaled by the load factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LoadKind {
    /// Fixed: applied in every analysis, like self-weight.
    Dead,
    /// Scaled by λ in a load-factor analysis; left out of `analyze`.
    #[default]
    Live,
}

/// One load as the user gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum Load {
    /// A force (N) at a point (m) of the block named `block`. A block cut by the scene's
    /// history stands for the piece containing the point.
    Point {
        /// The block's (or source shape's) name.
        block: String,
        /// Where the force acts, m.
        point: Point3,
        /// The force, N.
        force: Vector3,
        /// Dead (always on) or live (multiplied by the load factor).
        kind: LoadKind,
    },
    /// A uniform acceleration (units of g) on every free block's mass at its centroid.
    Acceleration {
        /// The acceleration in units of g (the magnitude of the scene's gravity).
        accel: Vector3,
        /// Dead or live.
        kind: LoadKind,
    },
}

impl Load {
    /// Whether the load is dead or live.
    pub fn kind(&self) -> LoadKind {
        match self {
            Load::Point { kind, .. } | Load::Acceleration { kind, .. } => *kind,
        }
    }

    /// A horizontal live acceleration of `magnitude` g along `azimuth` (radians from +x towards
    /// +y).
    pub fn horizontal(azimuth: f64, magnitude: f64) -> Self {
        Load::Acceleration { accel: Vector3::new(azimuth.cos(), azimuth.sin(), 0.0) * magnitude, kind: LoadKind::Live }
    }
}

/// A wrench about a block's centroid: force (N) then moment (N·m), world axes.
pub type Wrench = [f64; 6];

/// The loads of one block, resolved: the dead and the live wrench about its centroid, and of
/// each the part that scales with the block's mass (the acceleration fields: N per kg, at the
/// centroid), so that a design may change the mass ([`synthesis::infill`](mod@crate::synthesis::infill)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BlockLoads {
    /// The dead loads' wrench, acceleration fields included.
    pub dead: Wrench,
    /// The live loads' wrench, acceleration fields included.
    pub live: Wrench,
    /// The dead acceleration fields' force per kg of the block's mass, N/kg.
    pub dead_per_kg: [f64; 3],
    /// The live acceleration fields' force per kg of the block's mass, N/kg.
    pub live_per_kg: [f64; 3],
}

impl BlockLoads {
    fn add(&mut self, kind: LoadKind, w: Wrench) {
        let target = match kind {
            LoadKind::Dead => &mut self.dead,
            LoadKind::Live => &mut self.live,
        };
        target.iter_mut().zip(w).for_each(|(t, v)| *t += v);
    }

    /// An acceleration field of `per_kg` N/kg on a block of `mass` kg.
    fn add_field(&mut self, kind: LoadKind, per_kg: Vector3, mass: f64) {
        let f = per_kg * mass;
        self.add(kind, [f.x, f.y, f.z, 0.0, 0.0, 0.0]);
        let target = match kind {
            LoadKind::Dead => &mut self.dead_per_kg,
            LoadKind::Live => &mut self.live_per_kg,
        };
        target.iter_mut().zip(per_kg.iter()).for_each(|(t, v)| *t += v);
    }
}

/// The wrench about `centroid` of a force `force` applied at `point`.
pub fn wrench_about(centroid: &Point3, point: &Point3, force: &Vector3) -> Wrench {
    let m = (point - centroid).cross(force);
    [force.x, force.y, force.z, m.x, m.y, m.z]
}

/// Resolves `loads` onto `blocks` (validated, named): one [`BlockLoads`] per block, and a
/// warning per load on a support (ignored: a support takes any reaction). `g` is the gravity's
/// magnitude (m/s²), `reach` how far outside its block a point may lie (m: the coplanarity
/// tolerance). An error names the load (its index in the list) and what is wrong with it.
pub fn resolve(
    loads: &[Load],
    blocks: &[AssemblyBlock],
    g: f64,
    reach: f64,
) -> Result<(Vec<BlockLoads>, Vec<Warning>), ModelError> {
    let mut out = vec![BlockLoads::default(); blocks.len()];
    let mut warnings = Vec::new();
    for (index, load) in loads.iter().enumerate() {
        let bad = |message: String| ModelError::BadLoad { index, message };
        match load {
            Load::Point { block, point, force, kind } => {
                if !point.iter().chain(force.iter()).all(|c| c.is_finite()) {
                    return Err(bad(format!("point {point:?} or force {force:?} is not finite")));
                }
                let b = find_block(blocks, block, point, reach).map_err(bad)?;
                if blocks[b].support {
                    warnings.push(Warning::LoadOnSupport { index, block: blocks[b].name.clone() });
                    continue;
                }
                out[b].add(*kind, wrench_about(&blocks[b].mass.centroid, point, force));
            }
            Load::Acceleration { accel, kind } => {
                if !accel.iter().all(|c| c.is_finite()) {
                    return Err(bad(format!("acceleration {accel:?} is not finite")));
                }
                for (b, blk) in blocks.iter().enumerate().filter(|(_, b)| !b.support) {
                    out[b].add_field(*kind, accel * g, blk.mass());
                }
            }
        }
    }
    Ok((out, warnings))
}

/// The block a point load names: by name, or — for a source shape the cut history split — the
/// piece `name.…` whose box holds the point. The point must lie in (or within `reach` of) the
/// block's bounding box.
fn find_block(blocks: &[AssemblyBlock], name: &str, point: &Point3, reach: f64) -> Result<usize, String> {
    let outside = |b: &AssemblyBlock| {
        let (lo, hi) = (b.aabb.min, b.aabb.max);
        (0..3).map(|k| (lo[k] - point[k]).max(point[k] - hi[k]).max(0.0)).fold(0.0, f64::max)
    };
    if let Some(b) = blocks.iter().position(|b| b.name == name) {
        let d = outside(&blocks[b]);
        return if d <= reach {
            Ok(b)
        } else {
            Err(format!(
                "the point ({}, {}, {}) is {} m outside block '{name}' (its box is {:?}–{:?})",
                significant(point.x),
                significant(point.y),
                significant(point.z),
                significant(d),
                blocks[b].aabb.min.coords.as_slice(),
                blocks[b].aabb.max.coords.as_slice()
            ))
        };
    }
    let prefix = format!("{name}.");
    let piece = blocks
        .iter()
        .enumerate()
        .filter(|(_, b)| b.name.starts_with(&prefix))
        .map(|(i, b)| (i, outside(b)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    match piece {
        Some((i, d)) if d <= reach => Ok(i),
        Some(_) => Err(format!("no piece of block '{name}' holds the point {:?}", point.coords.as_slice())),
        None => Err(format!("the scene has no block named '{name}'")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: a force's wrench about a point is (F, r × F): a unit x-force 2 m above the
    /// centroid turns about +y by 2 N·m.
    #[test]
    fn wrench_is_force_and_moment() {
        let w = wrench_about(&Point3::origin(), &Point3::new(0.0, 0.0, 2.0), &Vector3::new(1.0, 0.0, 0.0));
        assert_eq!(w, [1.0, 0.0, 0.0, 0.0, 2.0, 0.0]);
    }
}
