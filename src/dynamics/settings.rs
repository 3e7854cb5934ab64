//! Drop-test settings with documented, measured defaults.

use thiserror::Error;

/// How the drop test simulates.
#[derive(Clone, Debug, PartialEq)]
pub struct DropSettings {
    /// Simulated time, s. Default 2.
    pub duration: f64,
    /// Time step, s. Default 1/240 (rapier's soft contacts make stacks sink ~g·n(n+1)/ω²; small
    /// steps and stiff contacts keep that far below the drift tolerance).
    pub dt: f64,
    /// Velocity solver iterations per step. Default 10.
    pub solver_iterations: usize,
    /// Contact stiffness as a natural frequency, Hz (rapier's default 30). Default 120.
    pub contact_frequency: f64,
    /// Contact damping ratio (rapier's default 5). Default 1 (the 15-voussoir arch at t/R 0.15
    /// settled least with it: 0.95 % drift against 1.1 % at 5).
    pub contact_damping: f64,
    /// Friction coefficient; `None`: the material's. Combined between two blocks with the
    /// `Min` rule (all blocks share it, so any rule gives μ).
    pub friction: Option<f64>,
    /// Initial horizontal speed given to every free block (+x), as a fraction of √(g·size) of
    /// the block. Default 0 (no perturbation).
    pub perturbation: f64,
    /// A block whose convex hull exceeds its volume by at most this fraction collides as its
    /// hull. Beyond it — a curved voussoir, a notched block — it still collides as its hull
    /// when the hull reaches into no other block (the excess is where nothing is); otherwise
    /// as a convex decomposition. Default 0.02. The volume error of either is reported.
    pub hull_tolerance: f64,
    /// Where two blocks' hulls overlap at a joint (a warped joint triangulated differently on
    /// its two sides), both are cut back to the joint plane — if the cut takes at most this
    /// fraction of the block's volume (a warp's sliver: ≤ 0.24 % on the Armadillo). Default
    /// 0.005 (the compas crossvault fell with cuts of up to 0.85 % allowed, stands with 0.5 %).
    pub max_joint_cut: f64,
    /// Solver contacts deeper than this fraction of the median block size are dropped for the
    /// step: rapier's manifolds between many-sided hulls sometimes carry points reported far
    /// deeper than the shapes overlap (0.79 m on the Armadillo where they touch), and their
    /// impulses burst a vault open. Default 0.01 (1 cm on the Armadillo; 0.025 let it burst; a
    /// standing stack's contacts sink by well under 1e-3).
    pub max_contact_depth: f64,
    /// A block has moved when its centroid drifted more than this fraction of its size (the
    /// bounding-box diagonal). Default 0.02.
    pub drift_tolerance: f64,
    /// … or turned more than this angle, rad. Default 0.05 (≈ 2.9°; a standing arch settles by
    /// up to 0.015 rad at the default stiffness, a falling block turns by far more).
    pub rotation_tolerance: f64,
}

impl Default for DropSettings {
    fn default() -> Self {
        Self {
            duration: 2.0,
            dt: 1.0 / 240.0,
            solver_iterations: 10,
            contact_frequency: 120.0,
            contact_damping: 1.0,
            friction: None,
            perturbation: 0.0,
            hull_tolerance: 0.02,
            max_contact_depth: 0.01,
            max_joint_cut: 0.005,
            drift_tolerance: 0.02,
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
