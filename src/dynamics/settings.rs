//! Drop-test settings. Each default is written once, in `Default`, with why (the measurements
//! that chose them: docs/benchmarks.md); the field docs say what a setting means.

use thiserror::Error;

/// How the drop test simulates.
#[derive(Clone, Debug, PartialEq)]
pub struct DropSettings {
    /// Simulated time, s.
    pub duration: f64,
    /// Time step, s.
    pub dt: f64,
    /// Velocity solver iterations per step.
    pub solver_iterations: usize,
    /// Contact stiffness as a natural frequency, Hz.
    pub contact_frequency: f64,
    /// Contact damping ratio.
    pub contact_damping: f64,
    /// Friction coefficient; `None`: the material's. Combined between two blocks with the
    /// `Min` rule (all blocks share it, so any rule gives μ).
    pub friction: Option<f64>,
    /// Initial horizontal speed given to every free block (+x), as a fraction of √(g·size) of
    /// the block (0: no perturbation).
    pub perturbation: f64,
    /// A block whose convex hull exceeds its volume by at most this fraction collides as its
    /// hull. Beyond it — a curved voussoir, a notched block — it still collides as its hull
    /// when the hull reaches into no other block (the excess is where nothing is); otherwise
    /// as a convex decomposition. The volume error of either is reported.
    pub hull_tolerance: f64,
    /// Where two blocks' hulls overlap at a joint (a warped joint triangulated differently on
    /// its two sides), both are cut back to the joint plane — if the cut takes at most this
    /// fraction of the block's volume (a warp's sliver).
    pub max_joint_cut: f64,
    /// Solver contacts deeper than this fraction of the median block size are dropped for the
    /// step: rapier's manifolds between many-sided hulls sometimes carry points reported far
    /// deeper than the shapes overlap, and their impulses burst a vault open.
    pub max_contact_depth: f64,
    /// A block has moved when its centroid drifted more than this fraction of its size (the
    /// bounding-box diagonal).
    pub drift_tolerance: f64,
    /// … or turned more than this angle, rad.
    pub rotation_tolerance: f64,
}

impl Default for DropSettings {
    fn default() -> Self {
        Self {
            duration: 2.0,
            // rapier's soft contacts make stacks sink ~g·n(n+1)/ω²; small steps and stiff
            // contacts keep that far below the drift tolerance.
            dt: 1.0 / 240.0,
            solver_iterations: 10,
            // rapier's own default is 30 Hz.
            contact_frequency: 120.0,
            // rapier's is 5; a thin arch settles least with 1.
            contact_damping: 1.0,
            friction: None,
            perturbation: 0.0,
            hull_tolerance: 0.02,
            // Below the depth that let the Armadillo burst, far above a standing stack's sinking.
            max_contact_depth: 0.01,
            // A warp's sliver, not the real material a larger cut took off the compas crossvault.
            max_joint_cut: 0.005,
            drift_tolerance: 0.02,
            // ≈ 2.9°: above what a standing arch settles by, far below what a falling block turns.
            rotation_tolerance: 0.05,
        }
    }
}

/// Invalid drop-test settings.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DropError {
    #[error("drop test setting {name} = {value} must be a finite number > 0")]
    NotPositive { name: &'static str, value: f64 },
    #[error("drop test setting {name} = {value} must be a finite number ≥ 0")]
    Negative { name: &'static str, value: f64 },
    #[error("drop test: solver_iterations must be at least 1")]
    NoIterations,
    #[error("drop test: {steps} steps (duration / dt) is more than the limit of 10 000 000")]
    TooManySteps { steps: f64 },
}

impl DropSettings {
    pub fn validate(&self) -> Result<(), DropError> {
        for (name, value) in [
            ("duration", self.duration),
            ("dt", self.dt),
            ("contact_frequency", self.contact_frequency),
            ("contact_damping", self.contact_damping),
            ("drift_tolerance", self.drift_tolerance),
            ("rotation_tolerance", self.rotation_tolerance),
            ("max_contact_depth", self.max_contact_depth),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(DropError::NotPositive { name, value });
            }
        }
        for (name, value) in [
            ("perturbation", self.perturbation),
            ("hull_tolerance", self.hull_tolerance),
            ("max_joint_cut", self.max_joint_cut),
            ("friction", self.friction.unwrap_or(0.0)),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(DropError::Negative { name, value });
            }
        }
        if self.solver_iterations == 0 {
            return Err(DropError::NoIterations);
        }
        let steps = (self.duration / self.dt).ceil();
        if steps > 1e7 {
            return Err(DropError::TooManySteps { steps });
        }
        Ok(())
    }
}
