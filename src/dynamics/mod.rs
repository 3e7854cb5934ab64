//! Dynamics: the drop test of an assembly on two engines — rapier3d ([`rapier`], a physics
//! engine's yes/no beside the statics' graded answer) and the exact-contact engine ([`exact`],
//! the statics' own contact model stepped in time) — behind one run ([`run`]) that tracks every
//! free block against the fall criteria and gives the verdict. What the engines share sits in
//! its own module (`settings`, [`scene`]); neither engine reads this front module. A base
//! acceleration history, the shake table's input, is a [`ground_motion::Accelerogram`]. Units
//! SI, z up.

pub mod exact;
pub mod ground_motion;
pub mod rapier;
pub mod run;
pub mod scene;
pub(crate) mod settings;

pub use exact::{EnergyBalance, ExactStats};
pub use ground_motion::{Accelerogram, Component, Excitation, GroundMotion, GroundMotionError, PulseShape, Record};
pub use rapier::Simulation;
pub use run::{BlockMotion, DropResult, DropRun, Stepper, Trajectory, drop_test, record};
pub use scene::{SupportPath, floor_level};
pub use settings::{ColliderForm, Coulomb, DropError, DropSettings, Engine, ExactSettings, Selection};
