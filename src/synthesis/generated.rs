//! What a generation strategy returns: the design with its new cut history and how it was
//! made (a leaf both strategies import, so neither imports the other for it).

use crate::model::Scene;
use serde::Serialize;

/// What a strategy makes ([`super::courses`], [`super::thrust`](mod@super::thrust)).
#[derive(Clone, Debug, PartialEq)]
pub struct Generated {
    /// The shape with its new cut history.
    pub design: Scene,
    /// The largest block dimension used, m, the number of courses and of free pieces.
    pub max_size: f64,
    /// The number of courses.
    pub courses: usize,
    /// The number of free pieces made.
    pub pieces: usize,
    /// Strategy *thrust*: how the bed joints settled.
    pub rounds: Option<ThrustRounds>,
}

/// How the beds settled.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ThrustRounds {
    /// Analyses run (the last one of the settled beds).
    pub rounds: usize,
    /// The largest turn of the last round, degrees; settled when below the settle angle.
    pub last_turn_degrees: f64,
    /// Whether the last round turned no bed by more than the settle angle.
    pub settled: bool,
    /// The largest angle between a bed and the field's joint it came from, degrees.
    pub largest_turn_degrees: f64,
    /// Beds whose turn was held at the largest turn.
    pub held: usize,
}
