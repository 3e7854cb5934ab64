//! Geometry of blocks: polygon meshes, their validation and repair, exact mass properties,
//! planar polygons and the tolerances that scale with the model.
//!
//! Units: metres (any consistent length unit works: every tolerance is relative to the model
//! size). Axes: right-handed, z up. Faces are listed counter-clockwise seen from outside, so
//! Newell normals point outward.

pub mod cells;
pub mod convex;
pub mod cut;
pub(crate) mod format;
pub mod mass;
pub mod mesh;
pub(crate) mod overlap;
pub mod polygon;
pub mod repair_cache;
pub mod tolerances;
pub mod validate;

pub use mass::MassProperties;
pub use mesh::{Aabb3, Mesh};
pub use polygon::Plane;
pub use repair_cache::RepairCache;
pub use tolerances::{ToleranceError, Tolerances};
pub use validate::{MeshError, MeshWarning, Repaired, repair};

/// A hash map for lookups only (never iterated: its order is the hasher's): FxHash, fast and
/// deterministic.
pub(crate) type LookupMap<K, V> = rustc_hash::FxHashMap<K, V>;

/// 3D point and vector type of the core (f64, z up).
pub type Point3 = nalgebra::Point3<f64>;
/// 3D vector type of the core.
pub type Vector3 = nalgebra::Vector3<f64>;
