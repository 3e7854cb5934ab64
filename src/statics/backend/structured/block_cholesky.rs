//! S's Cholesky factor by 6×6 blocks.
//!
//! S = E H⁻¹ Eᵀ has six rows per block (its wrench), and every entry of its pattern is a whole
//! 6×6 block. On problems of a few hundred blocks faer's supernodal factorisation, made for
//! scalar patterns, spends most of its time around its dense kernels (docs/benchmarks.md, the
//! roofline table). Here: an approximate-minimum-degree ordering of the block graph (faer's),
//! each block column's rows from the block elimination tree, every update's target block found
//! once; numerically, a right-looking elimination of fixed-size 6×6 blocks, which the compiler
//! unrolls. Blocks are stored column by column (`m[c][r]` is entry (r, c)), so that the updates
//! run along contiguous columns.
//!
//! Pivots are regularised as faer's are for S (a pivot ≤ 1e-13 becomes 2e-7: the zero pivots
//! of a singular S), so both factorisations solve the same system.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::amd;

/// A 6×6 block, column by column: `m[c][r]` is entry (r, c).
pub(super) type Block = [[f64; 6]; 6];

/// A pivot at or below this is replaced by [`DELTA`] (faer's dynamic regularisation of S).
const EPSILON: f64 = 1e-13;
const DELTA: f64 = 2e-7;

/// The factor's structure: the elimination order, each block column's rows and each update's
/// target, and where each stored entry of S's lower triangle goes.
#[derive(Clone)]
pub(super) struct BlockSymbolic {
    /// Elimination position → block.
    pub(super) perm: Vec<usize>,
    /// Block column j's off-diagonal blocks are `col_ptr[j]..col_ptr[j+1]`, at rows `rows`
    /// (elimination positions, increasing).
    pub(super) col_ptr: Vec<usize>,
    pub(super) rows: Vec<usize>,
    /// Column j's updates `upd_ptr[j]..upd_ptr[j+1]`: for each pair b ≤ a of its off-diagonal
    /// blocks (a outer), the target block in the storage (diagonal blocks first).
    pub(super) upd_ptr: Vec<usize>,
    pub(super) upd: Vec<u32>,
    /// Per stored entry of S's lower triangle (its CSC order), its place in the storage
    /// (block × 36 + c × 6 + r).
    gather: Vec<u32>,
}

/// The numeric factor: diagonal blocks (lower, the diagonal stored inverted) then the
/// off-diagonal blocks.
pub(super) struct BlockFactor {
    pub blocks: Vec<Block>,
}

impl BlockSymbolic {
    /// The structure for S of `nb` blocks whose lower pattern has an off-diagonal block at
    /// (i, j) for each i in `below[j]` (i > j, increasing), its CSC entries laid out as
    /// `kkt::lower_pattern` does with no budget rows. `None` when the storage would not fit
    /// 32-bit indices or holds more than `max_updates` block updates.
    pub fn new(nb: usize, below: &[Vec<usize>], max_updates: usize) -> Option<Self> {
        let (mut symbolic, inv) = Self::structure(nb, below, max_updates)?;
        symbolic.gather = gather_map(nb, below, &inv, &symbolic.col_ptr, &symbolic.rows)?;
        Some(symbolic)
    }

    /// [`BlockSymbolic::new`]'s structure without the gather map (for a caller that places its
    /// blocks itself), and the order's inverse: block → elimination position.
    pub fn structure(nb: usize, below: &[Vec<usize>], max_updates: usize) -> Option<(Self, Vec<usize>)> {
        let (perm, inv) = block_ordering(nb, below)?;
        let (col_ptr, rows) = column_rows(nb, below, &inv);
        let (upd_ptr, upd) = update_targets(nb, &col_ptr, &rows, max_updates)?;
        Some((Self { perm, col_ptr, rows, upd_ptr, upd, gather: Vec::new() }, inv))
    }

    pub fn storage_blocks(&self) -> usize {
        self.perm.len() + self.rows.len()
    }

    /// Block updates of one factorisation (each 432 flops).
    pub fn updates(&self) -> usize {
        self.upd.len()
    }

    /// Scatters S's lower values (CSC order) into `f`'s storage and factors it; false when a
    /// pivot is not finite or not positive.
    pub fn factor(&self, s_values: &[f64], f: &mut BlockFactor) -> bool {
        f.blocks.iter_mut().for_each(|b| *b = [[0.0; 6]; 6]);
        let flat = f.blocks.as_flattened_mut().as_flattened_mut();
        for (v, &at) in s_values.iter().zip(&self.gather) {
            flat[at as usize] = *v;
        }
        pulp::Arch::new().dispatch(Eliminate { symbolic: self, blocks: &mut f.blocks })
    }

    /// The right-looking elimination: per block column, its diagonal block's Cholesky, the
    /// blocks below it solved against it, then every pair of them subtracted from its target.
    #[inline(always)]
    fn eliminate(&self, blocks: &mut [Block]) -> bool {
        let n = self.perm.len();
        for j in 0..n {
            let Some(diag) = cholesky6(&blocks[j]) else { return false };
            blocks[j] = diag;
            let (s, e) = (self.col_ptr[j], self.col_ptr[j + 1]);
            for k in s..e {
                solve_right(&diag, &mut blocks[n + k]);
            }
            // Targets are diagonal blocks (before the column's own) or blocks of later
            // columns (after them): split so that both can be borrowed.
            let (before, rest) = blocks.split_at_mut(n + s);
            let (own, after) = rest.split_at_mut(e - s);
            let mut t = self.upd_ptr[j];
            for a in 0..e - s {
                for b in 0..=a {
                    let target = self.upd[t] as usize;
                    t += 1;
                    let block = if target < n { &mut before[target] } else { &mut after[target - n - e] };
                    subtract_product(block, &own[a], &own[b]);
                }
            }
        }
        true
    }

    /// Solves S x = `b` in place with the factor `f`.
    pub fn solve(&self, f: &BlockFactor, b: &mut [f64], work: &mut Vec<[f64; 6]>) {
        let n = self.perm.len();
        work.clear();
        work.extend(self.perm.iter().map(|&p| {
            let mut v = [0.0; 6];
            v.copy_from_slice(&b[6 * p..6 * p + 6]);
            v
        }));
        let blocks = &f.blocks;
        for j in 0..n {
            let y = forward6(&blocks[j], &work[j]);
            work[j] = y;
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let l = &blocks[n + k];
                let out = &mut work[self.rows[k]];
                for c in 0..6 {
                    for r in 0..6 {
                        out[r] -= l[c][r] * y[c];
                    }
                }
            }
        }
        for j in (0..n).rev() {
            let mut y = work[j];
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let (l, x) = (&blocks[n + k], &work[self.rows[k]]);
                for c in 0..6 {
                    let mut s = 0.0;
                    for r in 0..6 {
                        s += l[c][r] * x[r];
                    }
                    y[c] -= s;
                }
            }
            work[j] = backward6(&blocks[j], &y);
        }
        for (j, &p) in self.perm.iter().enumerate() {
            b[6 * p..6 * p + 6].copy_from_slice(&work[j]);
        }
    }
}

/// [`BlockSymbolic::eliminate`] compiled for the widest SIMD the CPU has (pulp's dispatch:
/// everything it calls is inlined into it).
struct Eliminate<'a> {
    symbolic: &'a BlockSymbolic,
    blocks: &'a mut [Block],
}

impl pulp::WithSimd for Eliminate<'_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> bool {
        self.symbolic.eliminate(self.blocks)
    }
}

impl BlockFactor {
    pub fn new(symbolic: &BlockSymbolic) -> Self {
        Self { blocks: vec![[[0.0; 6]; 6]; symbolic.storage_blocks()] }
    }
}

/// faer's AMD ordering of the block graph: (elimination position → block, its inverse).
fn block_ordering(nb: usize, below: &[Vec<usize>]) -> Option<(Vec<usize>, Vec<usize>)> {
    let mut col_ptr = Vec::with_capacity(nb + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for (j, rows) in below.iter().enumerate() {
        row_idx.push(j);
        row_idx.extend(rows);
        col_ptr.push(row_idx.len());
    }
    let pattern = SymbolicSparseColMatRef::new_checked(nb, nb, &col_ptr, None, &row_idx);
    let (mut perm, mut inv) = (vec![0usize; nb], vec![0usize; nb]);
    let mut buffer = MemBuffer::new(amd::order_scratch::<usize>(nb, row_idx.len()));
    amd::order(&mut perm, &mut inv, pattern, amd::Control::default(), MemStack::new(&mut buffer)).ok()?;
    Some((perm, inv))
}

/// Each block column's off-diagonal rows in the factor (elimination positions): its own rows
/// in S and its children's in the elimination tree, beyond itself.
fn column_rows(nb: usize, below: &[Vec<usize>], inv: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut own: Vec<Vec<usize>> = vec![Vec::new(); nb];
    for (j, rows) in below.iter().enumerate() {
        for &i in rows {
            let (a, b) = (inv[i].max(inv[j]), inv[i].min(inv[j]));
            own[b].push(a);
        }
    }
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); nb];
    let mut structure: Vec<Vec<usize>> = vec![Vec::new(); nb];
    let mut mark = vec![usize::MAX; nb];
    for j in 0..nb {
        let mut rows = Vec::new();
        let sources = std::iter::once(&own[j]).chain(children[j].iter().map(|&c| &structure[c]));
        for source in sources {
            for &i in source {
                if i > j && mark[i] != j {
                    mark[i] = j;
                    rows.push(i);
                }
            }
        }
        rows.sort_unstable();
        if let Some(&parent) = rows.first() {
            children[parent].push(j);
        }
        structure[j] = rows;
    }
    let mut col_ptr = Vec::with_capacity(nb + 1);
    col_ptr.push(0);
    let mut rows = Vec::new();
    for s in structure {
        rows.extend(s);
        col_ptr.push(rows.len());
    }
    (col_ptr, rows)
}

/// Per column, the target of each pair b ≤ a of its off-diagonal blocks: the diagonal block
/// of row a when a = b, else the block at (row a, column row b), found by walking column
/// row b's rows (they hold every row of column j beyond row b).
fn update_targets(nb: usize, col_ptr: &[usize], rows: &[usize], max: usize) -> Option<(Vec<usize>, Vec<u32>)> {
    let total: usize = (0..nb).map(|j| (col_ptr[j + 1] - col_ptr[j]) * (col_ptr[j + 1] - col_ptr[j] + 1) / 2).sum();
    if total > max || nb + rows.len() > u32::MAX as usize / 36 {
        return None;
    }
    let mut upd_ptr = Vec::with_capacity(nb + 1);
    let mut upd = Vec::with_capacity(total);
    upd_ptr.push(0);
    for j in 0..nb {
        let (s, e) = (col_ptr[j], col_ptr[j + 1]);
        for a in s..e {
            for b in s..=a {
                let target = if a == b {
                    rows[a]
                } else {
                    let col = rows[b];
                    let run = &rows[col_ptr[col]..col_ptr[col + 1]];
                    nb + col_ptr[col] + run.binary_search(&rows[a]).ok()?
                };
                upd.push(target as u32);
            }
        }
        upd_ptr.push(upd.len());
    }
    Some((upd_ptr, upd))
}

/// Where each stored entry of S's lower triangle (CSC, `kkt::lower_pattern`'s order with no
/// budgets) goes in the storage.
fn gather_map(nb: usize, below: &[Vec<usize>], inv: &[usize], col_ptr: &[usize], rows: &[usize]) -> Option<Vec<u32>> {
    let off_block = |i: usize, j: usize| -> Option<usize> {
        let run = &rows[col_ptr[j]..col_ptr[j + 1]];
        Some(nb + col_ptr[j] + run.binary_search(&i).ok()?)
    };
    let mut gather = Vec::new();
    for j in 0..nb {
        let nj = inv[j];
        for c in 0..6 {
            gather.extend((c..6).map(|r| (nj * 36 + c * 6 + r) as u32));
            for &i in &below[j] {
                let ni = inv[i];
                for r in 0..6 {
                    // Entry (6i + r, 6j + c) of S: in block (ni, nj) at (r, c), or its
                    // transpose's block (nj, ni) at (c, r).
                    let at =
                        if ni > nj { off_block(ni, nj)? * 36 + c * 6 + r } else { off_block(nj, ni)? * 36 + r * 6 + c };
                    gather.push(at as u32);
                }
            }
        }
    }
    Some(gather)
}

/// The lower Cholesky factor of a 6×6 block (its lower triangle read), the diagonal stored
/// inverted; `None` when a pivot, after the regularisation, is not positive and finite.
#[inline(always)]
fn cholesky6(a: &Block) -> Option<Block> {
    let mut l = *a;
    for c in 0..6 {
        let mut d = l[c][c];
        for k in 0..c {
            d -= l[k][c] * l[k][c];
        }
        if d <= EPSILON {
            d = DELTA;
        }
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        let inv = 1.0 / d.sqrt();
        l[c][c] = inv;
        for r in c + 1..6 {
            let mut v = l[c][r];
            for k in 0..c {
                v -= l[k][r] * l[k][c];
            }
            l[c][r] = v * inv;
        }
    }
    Some(l)
}

/// X ← X L⁻ᵀ for a diagonal factor L from [`cholesky6`]: column c of X is
/// (X_c − Σ_{k<c} L(c, k) X_k) / L(c, c).
#[inline(always)]
fn solve_right(l: &Block, x: &mut Block) {
    for c in 0..6 {
        let mut col = x[c];
        for k in 0..c {
            let f = l[k][c];
            for r in 0..6 {
                col[r] -= f * x[k][r];
            }
        }
        for v in col.iter_mut() {
            *v *= l[c][c];
        }
        x[c] = col;
    }
}

/// T −= A Bᵀ, whole (a diagonal block's upper triangle is computed and never read: a fixed
/// 6×6×6 loop the compiler unrolls and vectorises beats skipping it).
#[inline(always)]
fn subtract_product(t: &mut Block, a: &Block, b: &Block) {
    for c in 0..6 {
        let mut col = t[c];
        for k in 0..6 {
            let f = b[k][c];
            for r in 0..6 {
                col[r] -= a[k][r] * f;
            }
        }
        t[c] = col;
    }
}

/// L⁻¹ y for a diagonal factor from [`cholesky6`].
fn forward6(l: &Block, y: &[f64; 6]) -> [f64; 6] {
    let mut x = *y;
    for c in 0..6 {
        x[c] *= l[c][c];
        for r in c + 1..6 {
            x[r] -= l[c][r] * x[c];
        }
    }
    x
}

/// L⁻ᵀ y for a diagonal factor from [`cholesky6`].
fn backward6(l: &Block, y: &[f64; 6]) -> [f64; 6] {
    let mut x = *y;
    for c in (0..6).rev() {
        for r in c + 1..6 {
            x[c] -= l[c][r] * x[r];
        }
        x[c] *= l[c][c];
    }
    x
}

#[cfg(test)]
mod tests {
    //! Invariant: the block factorisation solves S x = b for a random sparse symmetric
    //! positive definite S of 6×6 blocks (a chain with cross links and fill), to round-off.
    use super::*;

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    }

    #[test]
    fn solves_a_random_block_system() {
        let nb = 40;
        let mut seed = 7u64;
        // Pattern: each block linked to the next and to one 7 further on.
        let below: Vec<Vec<usize>> =
            (0..nb).map(|j| [j + 1, j + 7].into_iter().filter(|&i| i < nb).collect()).collect();
        // Dense S (6nb)², symmetric, diagonally dominant.
        let m = 6 * nb;
        let mut s = vec![0.0; m * m];
        for (j, rows) in below.iter().enumerate() {
            for &i in rows {
                for r in 0..6 {
                    for c in 0..6 {
                        let v = lcg(&mut seed);
                        s[(6 * i + r) * m + 6 * j + c] = v;
                        s[(6 * j + c) * m + 6 * i + r] = v;
                    }
                }
            }
            for r in 0..6 {
                for c in 0..=r {
                    let v = lcg(&mut seed);
                    s[(6 * j + r) * m + 6 * j + c] = v;
                    s[(6 * j + c) * m + 6 * j + r] = v;
                }
            }
        }
        for i in 0..m {
            let row: f64 = (0..m).map(|k| s[i * m + k].abs()).sum();
            s[i * m + i] = row + 1.0;
        }
        // CSC lower values in kkt::lower_pattern's order.
        let mut values = Vec::new();
        for (j, rows) in below.iter().enumerate() {
            for c in 0..6 {
                values.extend((c..6).map(|r| s[(6 * j + r) * m + 6 * j + c]));
                for &i in rows {
                    values.extend((0..6).map(|r| s[(6 * i + r) * m + 6 * j + c]));
                }
            }
        }
        let sym = BlockSymbolic::new(nb, &below, usize::MAX).expect("structure");
        let mut f = BlockFactor::new(&sym);
        assert!(sym.factor(&values, &mut f));
        let b: Vec<f64> = (0..m).map(|_| lcg(&mut seed)).collect();
        let mut x = b.clone();
        sym.solve(&f, &mut x, &mut Vec::new());
        let worst =
            (0..m).map(|i| ((0..m).map(|k| s[i * m + k] * x[k]).sum::<f64>() - b[i]).abs()).fold(0.0f64, f64::max);
        assert!(worst < 1e-12, "residual {worst:e}");
    }
}
