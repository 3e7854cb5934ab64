//! A block-sparse LU of 6×6 blocks, for matrices with a symmetric block pattern but unsymmetric
//! values (the exact engine's states' systems M + Σ ρ f rᵀ: a force f along another direction
//! than its row r where a contact slides).
//!
//! The structure is [`BlockSymbolic`]'s (faer's AMD ordering of the block graph, the columns'
//! rows from the elimination tree, each update's target found once); numerically a right-looking
//! block elimination A = L U, L unit block-lower, U block-upper with the pivot blocks D_j on its
//! diagonal: L_ij = A_ij D_j⁻¹, then A_ab −= L_aj A_jb for every pair of column j's rows.
//! Pivoting is within a pivot block only (nalgebra's partial-pivoting LU of D_j), none across
//! blocks: enough where every D_j is dominated by its own body's mass and rows, which the
//! caller checks by the residuals of its solves.

use super::block_cholesky::BlockSymbolic;
use nalgebra::{Matrix6, Vector6};

/// The factorisation of one pattern: assemble with [`BlockLu::add`], then [`BlockLu::factor`]
/// and [`BlockLu::solve`]. Blocks are named by the caller's indices.
#[derive(Clone)]
pub(crate) struct BlockLu {
    symbolic: BlockSymbolic,
    /// Caller's block → elimination position.
    position: Vec<usize>,
    /// Pivot blocks (inverted once factored), then per stored off-diagonal slot its block below
    /// the diagonal (row position > column position) and its transpose-placed block above.
    diag: Vec<Matrix6<f64>>,
    lower: Vec<Matrix6<f64>>,
    upper: Vec<Matrix6<f64>>,
    /// [`BlockLu::solve`]'s right-hand side in elimination order, kept between solves.
    work: Vec<Vector6<f64>>,
}

impl BlockLu {
    /// The pattern of `blocks` blocks coupled by `links` (pairs of blocks, any order, repeats
    /// and self-pairs ignored), all entries zero; `None` when the ordering fails.
    pub fn new(blocks: usize, links: impl IntoIterator<Item = (usize, usize)>) -> Option<Self> {
        let mut below: Vec<Vec<usize>> = vec![Vec::new(); blocks];
        for (a, b) in links {
            let (hi, lo) = (a.max(b), a.min(b));
            if hi != lo && hi < blocks {
                below[lo].push(hi);
            }
        }
        below.iter_mut().for_each(|rows| {
            rows.sort_unstable();
            rows.dedup();
        });
        let (symbolic, position) = BlockSymbolic::structure(blocks, &below, usize::MAX)?;
        let slots = symbolic.rows.len();
        Some(Self {
            symbolic,
            position,
            diag: vec![Matrix6::zeros(); blocks],
            lower: vec![Matrix6::zeros(); slots],
            upper: vec![Matrix6::zeros(); slots],
            work: vec![Vector6::zeros(); blocks],
        })
    }

    /// Sets every entry back to zero, keeping the pattern: a new matrix of the same links.
    pub fn clear(&mut self) {
        for m in self.diag.iter_mut().chain(&mut self.lower).chain(&mut self.upper) {
            m.fill(0.0);
        }
    }

    /// A(i, j) += `block`; false where (i, j) is not in the pattern.
    pub fn add(&mut self, i: usize, j: usize, block: &Matrix6<f64>) -> bool {
        let (pi, pj) = (self.position[i], self.position[j]);
        if pi == pj {
            self.diag[pi] += block;
            return true;
        }
        let (row, col) = (pi.max(pj), pi.min(pj));
        let Some(slot) = self.slot(row, col) else { return false };
        if pi > pj {
            self.lower[slot] += block;
        } else {
            self.upper[slot] += block;
        }
        true
    }

    /// The stored slot of block (row, col), row > col, in elimination positions.
    fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let s = &self.symbolic;
        let run = &s.rows[s.col_ptr[col]..s.col_ptr[col + 1]];
        run.binary_search(&row).ok().map(|k| s.col_ptr[col] + k)
    }

    /// Factors the assembled matrix in place; false where a pivot block is singular or the
    /// factor is not finite.
    pub fn factor(&mut self) -> bool {
        let s = &self.symbolic;
        let n = s.perm.len();
        for j in 0..n {
            let Some(inverse) = invert(&self.diag[j]) else { return false };
            if !inverse.iter().all(|v| v.is_finite()) {
                return false;
            }
            self.diag[j] = inverse;
            let (start, end) = (s.col_ptr[j], s.col_ptr[j + 1]);
            for k in start..end {
                self.lower[k] *= inverse;
            }
            let mut t = s.upd_ptr[j];
            for a in start..end {
                for b in start..=a {
                    let target = s.upd[t] as usize;
                    t += 1;
                    let (la, ua) = (self.lower[a], self.upper[a]);
                    if target < n {
                        self.diag[target] -= la * ua;
                    } else {
                        let (lb, ub) = (self.lower[b], self.upper[b]);
                        self.lower[target - n] -= la * ub;
                        self.upper[target - n] -= lb * ua;
                    }
                }
            }
        }
        true
    }

    /// Solves A x = `b` in place (6 entries per block, the caller's order) with the factor.
    pub fn solve(&mut self, b: &mut [f64]) {
        let s = &self.symbolic;
        let n = s.perm.len();
        let work = &mut self.work;
        for (w, &p) in work.iter_mut().zip(&s.perm) {
            *w = Vector6::from_column_slice(&b[6 * p..6 * p + 6]);
        }
        for j in 0..n {
            let z = work[j];
            for k in s.col_ptr[j]..s.col_ptr[j + 1] {
                work[s.rows[k]] -= self.lower[k] * z;
            }
        }
        for j in (0..n).rev() {
            let mut y = work[j];
            for k in s.col_ptr[j]..s.col_ptr[j + 1] {
                y -= self.upper[k] * work[s.rows[k]];
            }
            work[j] = self.diag[j] * y;
        }
        for (j, &p) in s.perm.iter().enumerate() {
            b[6 * p..6 * p + 6].copy_from_slice(work[j].as_slice());
        }
    }
}

/// A 6×6 block's inverse by Gauss–Jordan elimination with partial pivoting on fixed arrays
/// (the factorisation's hot loop, where nalgebra's general LU inverse showed in the profile);
/// None where a pivot is zero.
fn invert(block: &Matrix6<f64>) -> Option<Matrix6<f64>> {
    let mut a: [[f64; 6]; 6] = std::array::from_fn(|r| std::array::from_fn(|c| block[(r, c)]));
    let mut inv: [[f64; 6]; 6] = std::array::from_fn(|r| std::array::from_fn(|c| f64::from(u8::from(r == c))));
    for c in 0..6 {
        let p = (c..6).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[p][c] == 0.0 {
            return None;
        }
        a.swap(c, p);
        inv.swap(c, p);
        let d = 1.0 / a[c][c];
        a[c].iter_mut().chain(inv[c].iter_mut()).for_each(|v| *v *= d);
        let (pivot, pivot_inv) = (a[c], inv[c]);
        for r in (0..6).filter(|&r| r != c) {
            let f = a[r][c];
            for k in 0..6 {
                a[r][k] -= f * pivot[k];
                inv[r][k] -= f * pivot_inv[k];
            }
        }
    }
    Some(Matrix6::from_fn(|r, c| inv[r][c]))
}

#[cfg(test)]
mod tests {
    //! Invariant: the block LU solves A x = b for a random unsymmetric A of 6×6 blocks on a
    //! sparse symmetric pattern (a chain with cross links and fill), to round-off against the
    //! dense residual.
    use super::*;

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    }

    #[test]
    fn solves_a_random_unsymmetric_block_system() {
        let nb = 30;
        let mut seed = 11u64;
        let links: Vec<(usize, usize)> =
            (0..nb).flat_map(|j| [(j, j + 1), (j + 5, j)]).filter(|&(a, b)| a < nb && b < nb).collect();
        let mut lu = BlockLu::new(nb, links.iter().copied()).expect("pattern");
        let m = 6 * nb;
        let mut dense = nalgebra::DMatrix::<f64>::zeros(m, m);
        let random = |seed: &mut u64| Matrix6::from_fn(|_, _| lcg(seed));
        for &(a, b) in &links {
            for (i, j) in [(a, b), (b, a)] {
                let block = random(&mut seed);
                assert!(lu.add(i, j, &block));
                let mut view = dense.view_mut((6 * i, 6 * j), (6, 6));
                view += &block;
            }
        }
        for j in 0..nb {
            let block = random(&mut seed) + Matrix6::identity() * 12.0;
            assert!(lu.add(j, j, &block));
            let mut view = dense.view_mut((6 * j, 6 * j), (6, 6));
            view += &block;
        }
        assert!(!lu.add(0, 2, &Matrix6::identity()), "a block outside the pattern is refused");
        assert!(lu.factor());
        let b: Vec<f64> = (0..m).map(|_| lcg(&mut seed)).collect();
        let mut x = b.clone();
        lu.solve(&mut x);
        let residual = &dense * nalgebra::DVector::from_vec(x) - nalgebra::DVector::from_vec(b);
        assert!(residual.amax() < 1e-12, "residual {:e}", residual.amax());
    }

    /// Invariant: the pivot blocks' inverse is nalgebra's to round-off on a block that needs
    /// pivoting (a zero leading entry), and a singular block has none.
    #[test]
    fn inverts_pivot_blocks() {
        let mut seed = 3u64;
        let mut block = Matrix6::from_fn(|_, _| lcg(&mut seed)) + Matrix6::identity();
        block[(0, 0)] = 0.0;
        let ours = invert(&block).expect("regular");
        let theirs = block.try_inverse().expect("regular");
        assert!((ours - theirs).amax() < 1e-12 * theirs.amax(), "{}", (ours - theirs).amax());
        let mut singular = block;
        singular.set_row(5, &block.row(4));
        assert!(invert(&singular).is_none_or(|m| !m.iter().all(|v| v.is_finite()) || m.amax() > 1e12));
    }
}
