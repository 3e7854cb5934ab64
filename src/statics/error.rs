//! Why the statics cannot run: invalid settings (solver trouble is not an error but a
//! [`SolverStatus`](super::problem::SolverStatus) with its residual).

use thiserror::Error;

/// Invalid statics settings.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StaticsError {
    /// μ is negative, infinite or NaN.
    #[error("friction coefficient {0} must be a finite number ≥ 0")]
    BadFriction(f64),
    /// σ_c is not a finite positive number (Pa).
    #[error("compressive strength {0} Pa must be a finite number > 0")]
    BadStrength(f64),
    #[error("objective weight {name} = {value} must be a finite number > 0")]
    /// A penalty weight of the objective is not a finite positive number.
    BadWeight {
        /// The weight's name (`w_c`, `w_f`, …).
        name: &'static str,
        /// Its value as given.
        value: f64,
    },
    /// The stand tolerance is not a finite positive number.
    #[error("stand tolerance {0} must be a finite number > 0")]
    BadTolerance(f64),
}
