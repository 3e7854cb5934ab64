//! # voussoir
//!
//! Rigid-block (discrete-element) assemblies: does a set of blocks stand by compression and
//! friction alone, and if not, where and by how much does it fail?
//!
//! ## Quick start
//!
//! Analyse the scene `voussoir` runs without arguments (a 15-voussoir semicircular arch,
//! t/R = 0.15, embedded in the crate) and read the graded answer:
//!
//! ```
//! use std::path::Path;
//! use voussoir::pipeline::{AnalysisSettings, analyze};
//!
//! let scene = voussoir::io::scene_json::scene_from_str(Path::new("default.json"), voussoir::cli::DEFAULT_SCENE)?;
//! let result = analyze(&scene, &AnalysisSettings::default())?;
//! assert!(result.statics.stands); // by compression and friction alone
//! assert_eq!(result.statics.tension_ratio, 0.0); // the least tension it needs, / its weight
//! assert!(result.statics.max_friction_utilization < 1.0); // every joint within μ
//!
//! // A built-in parametric scene: the same arch too thin (t/R = 0.08) needs tension.
//! let thin = analyze(&voussoir::model::builtin("arch?n=15&t=0.08")?, &AnalysisSettings::default())?;
//! assert!(!thin.statics.stands && thin.statics.tension_ratio > 0.1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Other questions start from the same [`model::Scene`]: how safely it stands
//! ([`stability`], the load factor and collapse mechanism), what the blocks do when let go
//! ([`dynamics`]), how to make it stand ([`synthesis`]); the `voussoir` command line ([`cli`])
//! runs each, and the guide (`docs/guide/` in the repository) shows them from there.
//!
//! ## The pipeline
//!
//! [`pipeline::analyze`]: a [`model::Scene`] (named source shapes, supports, material, cut
//! history) is decomposed into blocks by replaying its cuts ([`history`]), validated into an
//! [`model::Assembly`] (repaired meshes, mass properties), whose contact [`interfaces`] are
//! detected automatically; the [`statics`] module solves the rigid-block equilibrium problem
//! over them and gives a graded verdict. [`io`] reads and writes scenes, [`report`] writes the
//! reports.
//!
//! Conventions: SI units, z up, gravity (0, 0, −9.81); moments about each block's volume
//! centroid; an interface a→b has its normal pointing from a into b and b receives +f.

// Every public item of the library documented.
#![warn(missing_docs)]

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
// The viewer is an app behind a feature, not library API: its systems and panels are not
// held to a doc line each.
#[cfg(feature = "viewer")]
#[allow(missing_docs)]
pub mod viewer;
pub mod viz;

// The guide's Rust examples run as doctests (the bevy app's chapter needs the ECS plugins).
#[cfg(all(doctest, feature = "ecs"))]
#[doc = include_str!("../docs/guide/07-bevy-app.md")]
struct GuideBevyApp;
