//! The interior-point iterate and the vector helpers every step uses.

pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub fn norm_inf(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, v| m.max(v.abs()))
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
