//! The interior-point iterate and the vector helpers every step uses.

// Four lanes indexed in step by one loop variable.
#![allow(clippy::needless_range_loop)]

/// Σ a_i b_i over the shorter length, in four partial sums (independent chains, which the
/// compiler vectorises; one chain waits on each addition's latency), then the tail.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (ac, bc) = (a[..n].chunks_exact(4), b[..n].chunks_exact(4));
    let rest = ac.remainder().iter().zip(bc.remainder());
    let mut lanes = [0.0f64; 4];
    for (a4, b4) in ac.zip(bc) {
        for k in 0..4 {
            lanes[k] += a4[k] * b4[k];
        }
    }
    rest.fold((lanes[0] + lanes[1]) + (lanes[2] + lanes[3]), |s, (x, y)| s + x * y)
}

/// max |a_i|, NaN entries ignored (as `f64::max` does), in four lanes the compiler vectorises:
/// a maximum does not depend on the order, so the value is a scalar fold's.
pub fn norm_inf(a: &[f64]) -> f64 {
    let larger = |m: f64, v: f64| if v > m { v } else { m };
    let chunks = a.chunks_exact(4);
    let rest = chunks.remainder();
    let mut lanes = [0.0f64; 4];
    for c in chunks {
        for k in 0..4 {
            lanes[k] = larger(lanes[k], c[k].abs());
        }
    }
    let m = lanes.into_iter().fold(0.0, larger);
    rest.iter().fold(m, |m, v| larger(m, v.abs()))
}

/// Whether every entry is finite, in four lanes without branches: 0·v is 0 for a finite v
/// and NaN for an infinite or NaN one.
pub fn all_finite(a: &[f64]) -> bool {
    let chunks = a.chunks_exact(4);
    let rest = chunks.remainder();
    let mut lanes = [0.0f64; 4];
    for c in chunks {
        for k in 0..4 {
            lanes[k] += c[k] * 0.0;
        }
    }
    lanes.iter().all(|l| *l == 0.0) && rest.iter().all(|v| v.is_finite())
}

/// A right-hand side of the KKT system by block (r_x, r_E, r_G), or a solution read back.
#[derive(Clone, Copy)]
pub struct Rhs<'a> {
    pub x: &'a [f64],
    pub eq: &'a [f64],
    pub ineq: &'a [f64],
}

/// Where a solve of the KKT system writes its solution by block: x, z_E, z_G.
pub struct Step<'a> {
    pub x: &'a mut [f64],
    pub eq: &'a mut [f64],
    pub ineq: &'a mut [f64],
}

impl Step<'_> {
    /// The solution written so far, read-only.
    pub fn view(&self) -> Rhs<'_> {
        Rhs { x: self.x, eq: self.eq, ineq: self.ineq }
    }
}

/// Vectors with the KKT system's blocks (x, the equality rows, the inequality rows), owned.
#[derive(Default)]
pub struct Blocks {
    pub x: Vec<f64>,
    pub eq: Vec<f64>,
    pub ineq: Vec<f64>,
}

impl Blocks {
    pub fn zeros(n: usize, m_e: usize, m_g: usize) -> Self {
        Self { x: vec![0.0; n], eq: vec![0.0; m_e], ineq: vec![0.0; m_g] }
    }

    pub fn rhs(&self) -> Rhs<'_> {
        Rhs { x: &self.x, eq: &self.eq, ineq: &self.ineq }
    }

    pub fn step(&mut self) -> Step<'_> {
        Step { x: &mut self.x, eq: &mut self.eq, ineq: &mut self.ineq }
    }
}

/// The iterate: x, the equality duals z_E, the inequality slacks and duals (s, z), τ, κ.
#[derive(Clone)]
pub(crate) struct Vars {
    pub x: Vec<f64>,
    pub ze: Vec<f64>,
    pub s: Vec<f64>,
    pub z: Vec<f64>,
    pub tau: f64,
    pub kappa: f64,
}

impl Vars {
    pub fn zeros(n: usize, me: usize, mg: usize) -> Self {
        Self { x: vec![0.0; n], ze: vec![0.0; me], s: vec![0.0; mg], z: vec![0.0; mg], tau: 0.0, kappa: 0.0 }
    }
}

#[cfg(test)]
mod tests {
    //! Invariant: the four-lane helpers give the scalar folds' values exactly, on every length
    //! of tail (0–3 past the lanes) and with NaN and infinite entries anywhere.
    use super::*;

    /// Invariant: the four-sum dot product is the scalar sum to within the round-off of
    /// either (n ε Σ|a_i b_i|), on every tail length.
    #[test]
    fn dot_in_four_sums_is_the_sum() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for len in [0, 1, 3, 4, 5, 7, 8, 1001] {
            let (a, b): (Vec<f64>, Vec<f64>) = (0..len).map(|_| (next(), next() * 1e3)).unzip();
            let scalar: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            let bound = len as f64 * f64::EPSILON * a.iter().zip(&b).map(|(x, y)| (x * y).abs()).sum::<f64>();
            assert!((dot(&a, &b) - scalar).abs() <= bound, "length {len}");
            assert_eq!(dot(&a, &b[..len / 2]).to_bits(), dot(&a[..len / 2], &b[..len / 2]).to_bits());
        }
    }

    #[test]
    fn lanes_give_the_scalar_folds() {
        let base = [0.5, -3.25, 1e-300, -0.0, 7.5, -7.5, 2.0, 1e300, -1e-3, 4.0, 0.25];
        for len in 0..base.len() {
            for special in [None, Some(f64::NAN), Some(f64::INFINITY), Some(f64::NEG_INFINITY)] {
                for at in 0..len.max(1) {
                    let mut a = base[..len].to_vec();
                    if let (Some(v), true) = (special, at < len) {
                        a[at] = v;
                    }
                    let max = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    assert_eq!(norm_inf(&a).to_bits(), max.to_bits(), "{a:?}");
                    assert_eq!(all_finite(&a), a.iter().all(|v| v.is_finite()), "{a:?}");
                }
            }
        }
    }
}
