//! A synthetic accelerogram: seeded white noise through the Kanai–Tajimi filter (the ground as
//! a damped oscillator on bedrock: its absolute acceleration 2ζω x' + ω² x for
//! x'' + 2ζω x' + ω² x = −w), under the Jennings–Housner–Tsai envelope ((t / t₁)² rising to
//! t₁ = 0.1 T, 1 to t₂ = 0.45 T, then decaying as e^(−c (t − t₂)) to 5 % at T), corrected by an
//! envelope-shaped constant so that the ground ends at rest (zero velocity), then scaled to
//! the peak asked for. Sampled every 0.01 s; the same seed gives the same record on every
//! machine (xoshiro256++, Box–Muller). Units: s, m/s².

use super::{Accelerogram, STANDARD_GRAVITY};

/// The record's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SyntheticRecord {
    /// The noise's seed.
    pub seed: u64,
    /// The peak ground acceleration, g.
    pub pga: f64,
    /// The record's length T, s.
    pub duration: f64,
    /// The filter's frequency ω, rad/s.
    pub frequency: f64,
    /// The filter's damping ratio ζ.
    pub damping: f64,
}

impl Default for SyntheticRecord {
    fn default() -> Self {
        // Kanai–Tajimi's firm ground (ω = 15.6 rad/s, ζ = 0.6), a strong 10 s motion of 0.3 g.
        Self { seed: 1, pga: 0.3, duration: 10.0, frequency: 15.6, damping: 0.6 }
    }
}

/// The sample interval, s.
const DT: f64 = 0.01;
/// Filter sub-steps per sample (RK4 on the oscillator, the noise held over a sample).
const SUBSTEPS: usize = 10;

/// The record of `spec` (module docs). `pga`, `duration`, `frequency` and `damping` must be
/// finite and > 0 (the caller checks).
pub fn synthetic(spec: &SyntheticRecord) -> Accelerogram {
    let n = (spec.duration / DT).round().max(2.0) as usize + 1;
    let times: Vec<f64> = (0..n).map(|k| k as f64 * DT).collect();
    let noise = gaussian_noise(spec.seed, n);
    let filtered = kanai_tajimi(&noise, spec.frequency, spec.damping);
    let envelope: Vec<f64> = times.iter().map(|&t| envelope(t, spec.duration)).collect();
    let mut a: Vec<f64> = filtered.iter().zip(&envelope).map(|(x, e)| x * e).collect();
    ending_at_rest(&mut a, &envelope);
    let peak = a.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
    let to = spec.pga * STANDARD_GRAVITY / peak;
    Accelerogram { times, acceleration: a.iter().map(|v| v * to).collect() }
}

/// `n` standard normal samples (Box–Muller on xoshiro256++'s uniform doubles).
fn gaussian_noise(seed: u64, n: usize) -> Vec<f64> {
    let mut uniform = crate::optimise::uniform(seed);
    (0..n)
        .map(|_| {
            let (u, v) = (uniform(), uniform());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        })
        .collect()
}

/// The filter's absolute acceleration per sample for the noise held over each sample.
fn kanai_tajimi(noise: &[f64], omega: f64, zeta: f64) -> Vec<f64> {
    let h = DT / SUBSTEPS as f64;
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let mut out = Vec::with_capacity(noise.len());
    for &w in noise {
        out.push(2.0 * zeta * omega * v + omega * omega * x);
        let f = |x: f64, v: f64| (v, -w - 2.0 * zeta * omega * v - omega * omega * x);
        for _ in 0..SUBSTEPS {
            let k1 = f(x, v);
            let k2 = f(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
            let k3 = f(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
            let k4 = f(x + h * k3.0, v + h * k3.1);
            x += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
    }
    out
}

/// The Jennings–Housner–Tsai envelope at `t` of a record `total` s long (module docs).
fn envelope(t: f64, total: f64) -> f64 {
    let (t1, t2) = (0.1 * total, 0.45 * total);
    let c = 20f64.ln() / (total - t2);
    if t < t1 {
        (t / t1).powi(2)
    } else if t <= t2 {
        1.0
    } else {
        (-c * (t - t2)).exp()
    }
}

/// Takes off `k` × the envelope so that the trapezoidal velocity ends at 0.
fn ending_at_rest(a: &mut [f64], envelope: &[f64]) {
    let trapezoid = |s: &[f64]| s.windows(2).map(|p| 0.5 * DT * (p[0] + p[1])).sum::<f64>();
    let k = trapezoid(a) / trapezoid(envelope).max(f64::MIN_POSITIVE);
    a.iter_mut().zip(envelope).for_each(|(v, e)| *v -= k * e);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: the record has the asked-for peak and length, ends at rest (its velocity to
    /// 1e-12 of the peak × T), is the same for the same seed and differs for another.
    #[test]
    fn a_synthetic_record_has_its_peak_and_ends_at_rest() {
        let spec = SyntheticRecord::default();
        let r = synthetic(&spec);
        assert!((r.peak() / (spec.pga * STANDARD_GRAVITY) - 1.0).abs() < 1e-12);
        assert!((r.duration() - spec.duration).abs() < 1e-9);
        let v: f64 = r.acceleration.windows(2).map(|p| 0.5 * DT * (p[0] + p[1])).sum();
        assert!(v.abs() < 1e-12 * r.peak() * spec.duration, "ends at {v} m/s");
        assert_eq!(r, synthetic(&spec));
        assert_ne!(r, synthetic(&SyntheticRecord { seed: 2, ..spec }));
    }
}
