//! Repairs kept by mesh content: a pipeline validates and repairs every block after each edit,
//! and an edit changes a few. [`repair`] is a function of the mesh and the tolerances it uses,
//! so a kept result is the one it would compute.

use super::mesh::Mesh;
use super::tolerances::AbsTolerances;
use super::validate::{MeshError, Repaired, repair};
use std::collections::HashMap;

/// The mesh's content and the tolerances [`repair`] reads (weld, planarity, minimum volume).
type Key = (u64, [u64; 3]);

/// Repaired meshes of the current run and of the one before; a run keeps what it used
/// ([`Self::begin`]), so memory follows the design, not the edit history. Errors are not kept.
#[derive(Debug, Default)]
pub struct RepairCache {
    current: HashMap<Key, Repaired>,
    previous: HashMap<Key, Repaired>,
}

impl RepairCache {
    /// Starts a run: what the last run used stays available to it, the rest is dropped.
    pub fn begin(&mut self) {
        self.previous = std::mem::take(&mut self.current);
    }

    /// [`repair`]`(mesh, tol)`, computed once per content.
    pub fn repair(&mut self, mesh: &Mesh, tol: &AbsTolerances) -> Result<Repaired, MeshError> {
        let key = (mesh.content_key(), [tol.weld.to_bits(), tol.planarity.to_bits(), tol.min_volume_rel.to_bits()]);
        if let Some(r) = self.current.get(&key) {
            return Ok(r.clone());
        }
        let r = match self.previous.remove(&key) {
            Some(r) => r,
            None => repair(mesh, tol)?,
        };
        self.current.insert(key, r.clone());
        Ok(r)
    }

    /// Meshes kept for the current run.
    pub fn len(&self) -> usize {
        self.current.len()
    }

    /// Whether no mesh is kept.
    pub fn is_empty(&self) -> bool {
        self.current.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Tolerances;

    /// A unit cube at x = `offset` with its bottom face turned inward (repair turns it back and
    /// warns).
    fn cube(offset: f64) -> Mesh {
        let p = crate::geometry::Point3::new;
        let mut mesh = Mesh::cuboid(p(offset, 0.0, 0.0), p(offset + 1.0, 1.0, 1.0));
        mesh.faces[0].reverse();
        mesh
    }

    /// Invariant: a kept repair is the one `repair` computes (mesh, mass, warnings); a run keeps
    /// only what it used; a different tolerance or mesh is computed anew; errors are returned,
    /// not kept.
    #[test]
    fn kept_repairs_are_repairs() {
        let tol = Tolerances::default().resolve(1.0);
        let mut cache = RepairCache::default();
        let (a, b) = (cube(0.0), cube(2.0));
        cache.begin();
        let first = cache.repair(&a, &tol).unwrap();
        let direct = repair(&a, &tol).unwrap();
        assert_eq!(first.mesh, direct.mesh);
        assert_eq!(format!("{:?}", first.warnings), format!("{:?}", direct.warnings));
        assert_eq!(first.mass.volume, direct.mass.volume);
        cache.repair(&b, &tol).unwrap();
        assert_eq!(cache.len(), 2);
        // The next run uses a only: b is dropped.
        cache.begin();
        let again = cache.repair(&a, &tol).unwrap();
        assert_eq!(again.mesh, direct.mesh);
        assert_eq!(cache.len(), 1);
        cache.begin();
        assert!(cache.is_empty());
        // Another tolerance: computed with it.
        let coarse = Tolerances::default().resolve(100.0);
        let r = cache.repair(&a, &coarse).unwrap();
        assert_eq!(r.mesh, repair(&a, &coarse).unwrap().mesh);
        let empty = Mesh { vertices: Vec::new(), faces: Vec::new() };
        assert!(cache.repair(&empty, &tol).is_err());
        assert_eq!(cache.len(), 1);
    }
}
