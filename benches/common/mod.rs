//! What the threshold benches share.

/// Bisection between a standing `ok` and a failing `fail` parameter, `halvings` times.
pub fn bisect(mut ok: f64, mut fail: f64, halvings: usize, stands: &mut dyn FnMut(f64) -> bool) -> f64 {
    for _ in 0..halvings {
        let mid = 0.5 * (ok + fail);
        if stands(mid) { ok = mid } else { fail = mid }
    }
    0.5 * (ok + fail)
}
