//! The rapier3d engine of the drop test: the physics engine's yes/no beside the statics' graded
//! answer. rapier is touched only in this module (`world`, `colliders`).
//!
//! The assembly becomes rigid bodies at their volume centroids with the exact mass and inertia
//! of [`crate::geometry::MassProperties`]. Blocks collide as their convex hulls; where two
//! hulls overlap at a joint (a warped joint triangulated differently on its two sides) both are
//! cut back to the joint plane when that takes only a sliver; a block whose hull is more than
//! 2 % larger than it *and* still reaches into another block gets a convex decomposition (exact
//! parts along its face planes, V-HACD beyond 16). The volume error of either is reported.
//! Solver contacts deeper than 1 % of the median block size are dropped (rapier's manifolds
//! between many-sided hulls can carry points reported far too deep). Supports and the
//! ground (a box under z = 0; with a floor, under [`crate::dynamics::scene::floor_level`]) are fixed. Restitution 0, sleeping off, friction μ combined with
//! an explicit rule, rapier's length unit set to the median block size (its slop and
//! prediction distances are absolute otherwise). rapier computes in f32: coordinates are taken
//! relative to the model's centre in x and y.
//!
//! Metrics per block: largest centroid drift (m, and relative to the block's size, its
//! bounding-box diagonal), largest rotation (rad), final kinetic energy (J), time of first
//! significant motion (s). It stands when every free block stays within the drift and rotation
//! tolerances for the whole run. Same input, same trajectory (rapier single-threaded).
//! Units SI, z up.

mod colliders;
mod world;

pub use world::Simulation;
