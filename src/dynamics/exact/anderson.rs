//! Anderson acceleration (type II) of a step's Tresca rounds: the capacities' fixed point
//! c = G(c) = μ f_n(c), where a plain iteration c ← G(c) can cycle slowly among contacts that
//! take load in turn (a hinge's corners, a block rocking on two edges).
//!
//! With the last m rounds' residuals r_j = G(c_j) − c_j, the next capacities are
//! G(c_k) − ΔG γ, where γ minimises |r_k − ΔR γ| (ΔR, ΔG the differences of successive rounds'
//! residuals and images): the combination of the recent rounds whose linearised residual is
//! least. Capacities stay ≥ 0. Safeguarded: a round whose residual grew restarts the history
//! with a damped plain step. Non-dimensional, like the capacities.

use nalgebra::{DMatrix, DVector};
use std::collections::VecDeque;

/// Rounds remembered: a cycle among a few groups of contacts spans 3–4 rounds.
const MEMORY: usize = 4;

/// Ridge on the least-squares normal equations, relative to their diagonal's largest entry:
/// keeps γ bounded when two rounds' residual differences are parallel.
const RIDGE: f64 = 1e-10;

/// The recent rounds of one step.
#[derive(Default)]
pub(super) struct Anderson {
    /// Per remembered round (oldest first): its capacities' image G(c) and residual G(c) − c.
    images: VecDeque<DVector<f64>>,
    residuals: VecDeque<DVector<f64>>,
}

impl Anderson {
    /// Forgets the rounds (the map changed: a joint reached its crushing bound).
    pub fn restart(&mut self) {
        self.images.clear();
        self.residuals.clear();
    }

    /// The next round's capacities after a round at `capacities` whose forces gave `image`.
    /// A round whose residual grew (the map is not smooth where contacts open, close or start
    /// to slide) drops the history and takes half a plain step instead: a cycle's iterates are
    /// averaged rather than extrapolated.
    pub fn next(&mut self, capacities: &[f64], image: &[f64]) -> Vec<f64> {
        let g = DVector::from_column_slice(image);
        let r = &g - DVector::from_column_slice(capacities);
        let grew = self.residuals.back().is_some_and(|last| r.norm() > last.norm());
        if grew {
            self.restart();
        }
        if self.images.len() > MEMORY {
            self.images.pop_front();
            self.residuals.pop_front();
        }
        self.images.push_back(g.clone());
        self.residuals.push_back(r.clone());
        if grew {
            return capacities.iter().zip(image).map(|(c, g)| 0.5 * (c + g)).collect();
        }
        let m = self.images.len() - 1;
        if m == 0 {
            return image.to_vec();
        }
        let column = |v: &VecDeque<DVector<f64>>, j: usize| &v[j + 1] - &v[j];
        let dr = DMatrix::from_columns(&(0..m).map(|j| column(&self.residuals, j)).collect::<Vec<_>>());
        let dg = DMatrix::from_columns(&(0..m).map(|j| column(&self.images, j)).collect::<Vec<_>>());
        let Some(gamma) = least_squares(&dr, &r) else {
            self.restart();
            return image.to_vec();
        };
        (g - dg * gamma).iter().map(|c| c.max(0.0)).collect()
    }
}

/// γ minimising |r − A γ| (ridge-regularised normal equations); `None` when A is zero or the
/// solve is not finite.
fn least_squares(a: &DMatrix<f64>, r: &DVector<f64>) -> Option<DVector<f64>> {
    let mut normal = a.transpose() * a;
    let scale = normal.diagonal().max();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    (0..normal.nrows()).for_each(|i| normal[(i, i)] += RIDGE * scale);
    let gamma = normal.cholesky()?.solve(&(a.transpose() * r));
    gamma.iter().all(|g| g.is_finite()).then_some(gamma)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: on an affine map G(c) = B c + d (the linearised rounds) that rotates with
    /// spectral radius 0.95 — a slow cycle — the accelerated rounds reach the fixed point to
    /// 1e-7 within 6 rounds, where the plain iteration is still more than half its first
    /// distance away (0.95⁶ = 0.74).
    #[test]
    fn an_affine_cycle_settles_in_a_few_rounds() {
        let (c, s) = (0.95 * (2.1f64).cos(), 0.95 * (2.1f64).sin());
        let b = nalgebra::Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 0.5);
        let fixed = nalgebra::Vector3::new(1.0, 2.0, 1.0);
        let d = (nalgebra::Matrix3::identity() - b) * fixed;
        let start = nalgebra::Vector3::new(1.5, 2.0, 1.5);
        let mut acc = Anderson::default();
        let (mut x, mut plain) = (start, start);
        for _ in 0..6 {
            let g = b * x + d;
            x = nalgebra::Vector3::from_vec(acc.next(x.as_slice(), g.as_slice()));
            plain = b * plain + d;
        }
        assert!((x - fixed).norm() <= 1e-7 * fixed.norm(), "{x} against {fixed}");
        assert!((plain - fixed).norm() > 0.5 * (start - fixed).norm(), "the plain rounds are slow here");
    }

    /// Invariant: where the residual grows (a two-cycle G(c) = 1 − c around the fixed point
    /// ½, residual 1 − 2c), the next capacities are the average of the round's and its image,
    /// which on this map is the fixed point itself.
    #[test]
    fn a_growing_residual_takes_half_a_plain_step() {
        let mut acc = Anderson::default();
        let g = |c: f64| 1.0 - c;
        let first = acc.next(&[0.4], &[g(0.4)]);
        assert_eq!(first, vec![0.6], "the first round is plain");
        // Residuals 0.2 then −0.2: not grown, Anderson's secant lands on ½ exactly.
        let second = acc.next(&[0.6], &[g(0.6)]);
        assert!((second[0] - 0.5).abs() < 1e-9, "{second:?}");
        // A round farther out than the last: its residual grew, half a plain step.
        let third = acc.next(&[0.9], &[g(0.9)]);
        assert!((third[0] - 0.5).abs() < 1e-15, "{third:?}");
    }

    /// Invariant: the first round is the plain iteration, and capacities never go negative.
    #[test]
    fn the_first_round_is_plain_and_capacities_stay_non_negative() {
        let mut acc = Anderson::default();
        assert_eq!(acc.next(&[1.0, 0.0], &[0.5, 0.25]), vec![0.5, 0.25]);
        // A residual pointing through zero: the extrapolation would go negative.
        let next = acc.next(&[0.5, 0.25], &[0.1, 0.0]);
        assert!(next.iter().all(|&c| c >= 0.0), "{next:?}");
    }
}
