//! Ground motion: a base acceleration history, the shake table's input (read from records by
//! [`crate::io::accelerogram`]). Time in s from the history's start; acceleration in m/s².

/// Standard gravity, m/s² (a history given in g is converted with it).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// A base acceleration history.
#[derive(Clone, Debug, PartialEq)]
pub struct Accelerogram {
    /// Sample times, s, strictly increasing from the history's first.
    pub times: Vec<f64>,
    /// Acceleration at each time, m/s².
    pub acceleration: Vec<f64>,
}

impl Accelerogram {
    /// The largest |acceleration|, m/s².
    pub fn peak(&self) -> f64 {
        self.acceleration.iter().fold(0.0, |m, a| m.max(a.abs()))
    }

    /// The history's length, s.
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0) - self.times.first().copied().unwrap_or(0.0)
    }
}
