//! Lemke's complementary pivoting for a linear complementarity problem: find z ≥ 0 with
//! w = M z + q ≥ 0 and wᵀz = 0, on a dense tableau (Cottle, Pang & Stone, *The Linear
//! Complementarity Problem*, §4.4), the covering vector all ones. It ends at a solution or on a
//! ray; Stewart and Trinkle (1996) show the step's LCP of rigid blocks with polyhedral friction
//! sets ends at a solution.

/// A pivot entry below this fraction of its column's largest is none.
const PIVOT: f64 = 1e-11;

/// The LCP's solution z (n entries), or None where the pivots end on a ray or exceed
/// `max_pivots`. `m` is n × n, row-major.
pub(super) fn lemke(m: &[f64], q: &[f64], max_pivots: usize) -> Option<Vec<f64>> {
    let n = q.len();
    if q.iter().all(|&v| v >= 0.0) {
        return Some(vec![0.0; n]);
    }
    // Columns: w (n), z (n), z0, then the right-hand side; each row w − M z − z0 = q.
    let width = 2 * n + 2;
    let (z0, rhs) = (2 * n, 2 * n + 1);
    let mut t = vec![0.0; n * width];
    for i in 0..n {
        let row = &mut t[i * width..(i + 1) * width];
        row[i] = 1.0;
        for j in 0..n {
            row[n + j] = -m[i * n + j];
        }
        row[z0] = -1.0;
        row[rhs] = q[i];
    }
    let mut basis: Vec<usize> = (0..n).collect();
    let first = (0..n).min_by(|&a, &b| q[a].total_cmp(&q[b]))?;
    pivot(&mut t, width, first, z0);
    basis[first] = z0;
    let mut entering = n + first;
    for _ in 0..max_pivots {
        let row = leaving_row(&t, width, &basis, entering)?;
        pivot(&mut t, width, row, entering);
        let left = std::mem::replace(&mut basis[row], entering);
        if left == z0 {
            let mut z = vec![0.0; n];
            for (i, &b) in basis.iter().enumerate() {
                if (n..2 * n).contains(&b) {
                    z[b - n] = t[i * width + rhs].max(0.0);
                }
            }
            return Some(z);
        }
        entering = if left < n { n + left } else { left - n };
    }
    None
}

/// The minimum-ratio row for entering column `col` (z0's row on a tie, so the pivots end
/// there), ties among the others broken lexicographically by the rows of the basis inverse
/// (the w columns): the perturbed problem's rule, which does not cycle on degenerate problems;
/// None on a ray (no positive entry).
fn leaving_row(t: &[f64], width: usize, basis: &[usize], col: usize) -> Option<usize> {
    let n = basis.len();
    let (z0, rhs) = (2 * n, 2 * n + 1);
    let largest = (0..n).map(|i| t[i * width + col].abs()).fold(0.0, f64::max);
    let floor = PIVOT * largest.max(f64::MIN_POSITIVE);
    let rows: Vec<usize> = (0..n).filter(|&i| t[i * width + col] > floor).collect();
    let ratio = |i: usize, c: usize| t[i * width + c] / t[i * width + col];
    let least = rows.iter().map(|&i| ratio(i, rhs).max(0.0)).fold(f64::INFINITY, f64::min);
    let tol = 1e-12 * (1.0 + least.abs());
    let mut ties: Vec<usize> = rows.into_iter().filter(|&i| ratio(i, rhs).max(0.0) <= least + tol).collect();
    if let Some(&i) = ties.iter().find(|&&i| basis[i] == z0) {
        return Some(i);
    }
    for c in 0..n {
        if ties.len() <= 1 {
            break;
        }
        let least = ties.iter().map(|&i| ratio(i, c)).fold(f64::INFINITY, f64::min);
        let tol = 1e-12 * (1.0 + least.abs());
        ties.retain(|&i| ratio(i, c) <= least + tol);
    }
    ties.first().copied()
}

/// Gauss–Jordan pivot of the tableau on (row, col).
fn pivot(t: &mut [f64], width: usize, row: usize, col: usize) {
    let n = t.len() / width;
    let p = t[row * width + col];
    for v in &mut t[row * width..(row + 1) * width] {
        *v /= p;
    }
    let pivot_row: Vec<f64> = t[row * width..(row + 1) * width].to_vec();
    for i in (0..n).filter(|&i| i != row) {
        let f = t[i * width + col];
        if f == 0.0 {
            continue;
        }
        for (v, p) in t[i * width..(i + 1) * width].iter_mut().zip(&pivot_row) {
            *v -= f * p;
        }
    }
}

#[cfg(test)]
mod tests {
    //! Invariant: where Lemke's pivots end at a solution it is one: z ≥ 0, w = M z + q ≥ 0 and
    //! wᵀz = 0 to round-off, on random positive definite M (always solvable: Lemke ends there).
    use super::*;
    use proptest::prelude::*;

    /// n, an n × n matrix A (row-major) and q, entries uniform.
    fn problem() -> impl Strategy<Value = (usize, Vec<f64>, Vec<f64>)> {
        (1usize..=30).prop_flat_map(|n| {
            (Just(n), prop::collection::vec(-0.5f64..0.5, n * n), prop::collection::vec(-2.0f64..2.0, n))
        })
    }

    proptest! {
        #[test]
        fn solves_random_positive_definite_lcps((n, a, q) in problem()) {
            // M = A Aᵀ + I/10 + a skew part: positive definite, not symmetric.
            let m: Vec<f64> = (0..n * n)
                .map(|k| {
                    let (i, j) = (k / n, k % n);
                    let sym: f64 = (0..n).map(|l| a[i * n + l] * a[j * n + l]).sum();
                    sym + if i == j { 0.1 } else { 0.3 * (a[i * n + j] - a[j * n + i]) }
                })
                .collect();
            let z = lemke(&m, &q, 10 * n + 10);
            prop_assert!(z.is_some(), "a positive definite LCP has a solution");
            let z = z.unwrap_or_default();
            for i in 0..n {
                let w: f64 = (0..n).map(|j| m[i * n + j] * z[j]).sum::<f64>() + q[i];
                prop_assert!(z[i] >= 0.0 && w >= -1e-10, "n {}: z {} w {}", n, z[i], w);
                prop_assert!((z[i] * w).abs() <= 1e-10, "n {}: z {} w {}", n, z[i], w);
            }
        }
    }
}
