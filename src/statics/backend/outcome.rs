//! Which solver ran a problem, and what it returned.

use crate::statics::problem::SolverStatus;

/// The interior-point solver of the equilibrium problems (`--solver structured|clarabel`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Backend {
    /// clarabel's algorithm with the Newton system reduced to the equilibrium rows
    /// (`backend::structured`); falls back to clarabel for any problem of another shape.
    #[default]
    Structured,
    /// clarabel with its general sparse LDL (QDLDL) on the whole KKT matrix.
    Clarabel,
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Structured => "structured",
            Self::Clarabel => "clarabel",
        })
    }
}

/// Result of one conic solve.
#[derive(Clone, Debug)]
pub struct QpOutcome {
    pub status: SolverStatus,
    pub x: Vec<f64>,
    /// Duals of the equality rows, the block rows first (clarabel's sign: A x + s = b,
    /// Aᵀz + P x + q = 0): with a load factor, the mechanism.
    pub duals: Vec<f64>,
    pub objective: f64,
    pub iterations: u32,
    /// Which solver ran it.
    pub backend: Backend,
    /// Seconds converting to clarabel's matrices (0 on the structured backend), and in the
    /// solver that ran (set-up and solve).
    pub convert_seconds: f64,
    pub solver_seconds: f64,
}
