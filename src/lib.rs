//! # voussoir
//!
//! Rigid-block (discrete-element) assemblies: does a set of blocks stand by compression and
//! friction alone, and if not, where and by how much does it fail?
//!
//! The pipeline ([`analysis::analyze`]): a [`model::Scene`] (named source shapes, supports,
//! material, cut history) is decomposed into blocks by replaying its cuts ([`decompose`]),
//! validated into an [`model::Assembly`] (repaired meshes, mass properties), whose contact
//! [`interfaces`] are detected automatically; the [`statics`] module solves the rigid-block
//! equilibrium problem over them and gives a graded verdict. [`io`] reads and writes scenes
//! and reports, [`cli`] is the command line.
//!
//! ```
//! use voussoir::pipeline::{AnalysisSettings, analyze};
//! use voussoir::model::builtin;
//!
//! // A 40-voussoir semicircular arch, t/R = 0.12, on two springers: it stands
//! // (Milankovitch's minimum is t/R ≈ 0.1075).
//! let scene = builtin("arch?n=40&t=0.12").unwrap();
//! let result = analyze(&scene, &AnalysisSettings::default()).unwrap();
//! assert!(result.statics.stands);
//! assert_eq!(result.interfaces.len(), 41);
//! assert!(result.statics.solver.residual < 1e-9 * result.statics.free_weight);
//! ```
//!
//! Conventions: SI units, z up, gravity (0, 0, −9.81); moments about each block's volume
//! centroid; an interface a→b has its normal pointing from a into b and b receives +f.

pub mod cli;
pub mod dynamics;
#[cfg(feature = "ecs")]
pub mod ecs;
pub mod geometry;
pub mod history;
pub mod interfaces;
pub mod io;
pub mod model;
pub mod optimise;
pub mod pipeline;
pub mod report;
pub mod stability;
pub mod statics;
pub mod studies;
pub mod synthesis;
#[cfg(feature = "viewer")]
pub mod viewer;
pub mod viz;
