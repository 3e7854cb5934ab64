//! Designs that stand, found rather than drawn (issue #22). The seed paper's designer moves and
//! turns cuts until the colours say it stands; [`repair`](mod@repair) does that search: a seeded particle
//! swarm over the selected cuts' parameters ([`params`]: a plane's offset and two turns, a
//! pattern's apex) for the lowest [`objective`] — first standing (minimum tension + friction
//! excess → 0), then the largest horizontal load factor. When no placement of the cuts makes
//! it stand, the answer says so, names the interfaces that keep failing and, where one column
//! holds it, the support that does ([`props`]).
//!
//! Units: metres, radians inside (degrees in settings), forces as fractions of the free weight.

pub mod generate;
pub mod generated;
pub mod infill;
pub mod load_path;
pub mod objective;
pub mod params;
pub mod pattern;
pub mod props;
pub mod repair;
pub mod thrust;

pub use generate::{BlockSize, Field, courses};
pub use generated::{Generated, ThrustRounds};
pub use infill::{InfillObjective, InfillOutcome, InfillReport, InfillSettings, infill};
pub use load_path::{fitted_axis, found_courses};
pub use objective::{Evaluator, Score};
pub use params::{CutParameters, Freedom};
pub use pattern::pattern;
pub use props::{SupportProposal, propose_support};
pub use repair::{CutChange, FailingInterface, RepairOutcome, RepairReport, repair};
pub use thrust::{ThrustSettings, thrust};

use crate::pipeline::AnalysisError;
use thiserror::Error;

/// Why a design cannot be searched (bad input or settings; a design that cannot be repaired is
/// a [`RepairOutcome`], not an error).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DesignError {
    /// The design cannot be analysed (its scene, cuts or settings).
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// A cut index beyond the history.
    #[error("cut {index}: there are only {count} cuts in the design's history")]
    UnknownCut {
        /// The index asked for.
        index: usize,
        /// How many cuts the history has.
        count: usize,
    },
    /// A cut cannot be moved as asked (the reason).
    #[error("cut {index}: {why}")]
    BadCut {
        /// The cut's position in the history.
        index: usize,
        /// Why, in words.
        why: String,
    },
    /// A setting is out of range (the message names it).
    #[error("{0}")]
    Settings(String),
    /// argmin's particle swarm stopped with an error (its message).
    #[error("the optimiser stopped: {0}")]
    Optimiser(String),
}

/// How a repair searches; every default here once.
#[derive(Clone, Debug, PartialEq)]
pub struct RepairSettings {
    /// The cuts that may move (indices in the history); `None`: all.
    pub cuts: Option<Vec<usize>>,
    /// Largest turn of a plane cut about each of its in-plane axes, degrees.
    pub max_turn_degrees: f64,
    /// Largest move of a pattern cut's apex per axis, fraction of the model size.
    pub apex_move: f64,
    /// No free piece smaller than this fraction of the design's mean piece volume (no slivers),
    /// unless the design as given has one as small.
    pub min_piece_fraction: f64,
    /// After standing, maximise the horizontal load factor (else any standing design will do).
    pub robust: bool,
    /// Azimuths of the load factor inside the search (the report uses the full sweep).
    pub directions: usize,
    /// Particles and iterations of the swarm; the seed of its random numbers.
    pub particles: usize,
    /// Iterations of the swarm.
    pub iterations: u64,
    /// The seed of the swarm's random numbers (the same seed gives the same design).
    pub seed: u64,
    /// When the search over every selected cut leaves the design failing: more searches over
    /// only the cuts that hold its failing interfaces, at most this many.
    pub focus_rounds: usize,
}

impl Default for RepairSettings {
    fn default() -> Self {
        Self {
            cuts: None,
            max_turn_degrees: 45.0,
            apex_move: 0.25,
            min_piece_fraction: 0.1,
            robust: true,
            directions: 8,
            particles: 12,
            iterations: 15,
            seed: 0,
            focus_rounds: 3,
        }
    }
}

impl RepairSettings {
    /// Refuses a turn, an apex move, a piece fraction or swarm sizes out of range.
    pub fn validate(&self) -> Result<(), DesignError> {
        let bad = |what: String| Err(DesignError::Settings(what));
        if !(0.0..=90.0).contains(&self.max_turn_degrees) {
            return bad(format!("max turn {}°: expected 0 to 90°", self.max_turn_degrees));
        }
        if !(self.apex_move >= 0.0 && self.apex_move.is_finite()) {
            return bad(format!("apex move {}: expected a fraction ≥ 0 of the model size", self.apex_move));
        }
        if !(0.0..1.0).contains(&self.min_piece_fraction) {
            return bad(format!("minimum piece fraction {}: expected 0 ≤ f < 1", self.min_piece_fraction));
        }
        if self.directions < 3 {
            return bad(format!("{} directions: at least 3 are needed to find a worst one", self.directions));
        }
        if self.particles < 2 {
            return bad(format!("{} particles: a swarm needs at least 2", self.particles));
        }
        Ok(())
    }
}
