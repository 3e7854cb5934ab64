//! Why the statics cannot run: invalid settings (solver trouble is not an error but a
//! [`SolverStatus`](super::problem::SolverStatus) with its residual).

use thiserror::Error;

/// Invalid statics settings.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StaticsError {
    #[error("friction coefficient {0} must be a finite number ≥ 0")]
    BadFriction(f64),
    #[error("compressive strength {0} Pa must be a finite number > 0")]
    BadStrength(f64),
    #[error("objective weight {name} = {value} must be a finite number > 0")]
    BadWeight { name: &'static str, value: f64 },
    #[error("stand tolerance {0} must be a finite number > 0")]
    BadTolerance(f64),
}
