//! The interior-point Newton system, reduced to the equality rows.
//!
//! KKT system (the same as clarabel's, static regularisation ε):
//! ```text
//! [ P + εI      Eᵀ        Gᵀ       ] [x  ]   [rx  ]
//! [ E          −εI        0        ] [z_E] = [rz_E]
//! [ G           0     −(D + εI)    ] [z_G]   [rz_G]      D = diag(s/z) of the inequality rows
//! ```
//! Eliminating z_G (diagonal) and then x (block diagonal: H_g = P_g + εI + G_gᵀ(D+ε)⁻¹G_g per
//! group of a few variables) leaves the normal equations on the equality rows,
//! `S z_E = E H⁻¹ r̃x − rz_E` with `S = E H⁻¹ Eᵀ + εI` — 6 rows per block, sparse like the
//! block contact graph, positive definite. S is factorised by faer's supernodal sparse
//! Cholesky (symbolic analysis and AMD ordering once per problem); each group's H by a dense
//! Cholesky. Iterative refinement against the unregularised system removes what ε and
//! round-off leave.

use super::structure::{MAX_GROUP, Structured};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// Regularisation of H and S. The elimination is exact (H is positive definite: every
/// variable sits in an inequality row, and P ≥ 0), so this only guards round-off; clarabel
/// needs 1e-8 for its LDL without pivoting, which here would cost extra refinement steps.
const EPS: f64 = 1e-13;

/// Group data in flat arrays (offsets per group): the columns, inequality rows and equality
/// rows a group touches, E and G restricted to them (row-major), and after each
/// factorisation H⁻¹ and B = E_loc H⁻¹.
#[derive(Default)]
struct Groups {
    cols: Flat<usize>,
    g_rows: Flat<usize>,
    e_rows: Flat<usize>,
    e_loc: Flat<f64>,
    g_loc: Flat<f64>,
    h_inv: Flat<f64>,
    b: Flat<f64>,
}

/// Concatenated slices.
struct Flat<T> {
    off: Vec<usize>,
    data: Vec<T>,
}

impl<T> Default for Flat<T> {
    fn default() -> Self {
        Self { off: vec![0], data: Vec::new() }
    }
}

impl<T: Copy> Flat<T> {
    fn push(&mut self, items: &[T]) {
        self.data.extend_from_slice(items);
        self.off.push(self.data.len());
    }
    fn get(&self, g: usize) -> &[T] {
        &self.data[self.off[g]..self.off[g + 1]]
    }
    fn get_mut(&mut self, g: usize) -> &mut [T] {
        &mut self.data[self.off[g]..self.off[g + 1]]
    }
}

/// Consecutive groups with the same equality rows (the points of one interface): their S
/// contributions are summed densely and scattered once.
struct Cluster {
    groups: std::ops::Range<usize>,
    /// Index into S's values of each lower-triangle pair (a ≥ b) of the rows.
    scatter: Vec<usize>,
}

pub struct Kkt {
    g: Groups,
    clusters: Vec<Cluster>,
    n: usize,
    m_e: usize,
    /// S lower triangle in CSC.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    diag_at: Vec<usize>,
    values: Vec<f64>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    buffer: MemBuffer,
    /// Current inequality scaling D (s/z) and its inverse.
    d: Vec<f64>,
    d_inv: Vec<f64>,
}

/// Dense Cholesky in place (row-major lower); false if not positive definite.
fn chol(a: &mut [f64], c: usize) -> bool {
    for j in 0..c {
        let mut d = a[j * c + j];
        for k in 0..j {
            d -= a[j * c + k] * a[j * c + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * c + j] = d;
        for i in j + 1..c {
            let mut v = a[i * c + j];
            for k in 0..j {
                v -= a[i * c + k] * a[j * c + k];
            }
            a[i * c + j] = v / d;
        }
        for k in j + 1..c {
            a[j * c + k] = 0.0;
        }
    }
    true
}

/// Solves L Lᵀ y = y in place.
fn chol_solve(l: &[f64], c: usize, y: &mut [f64]) {
    for i in 0..c {
        let mut v = y[i];
        for k in 0..i {
            v -= l[i * c + k] * y[k];
        }
        y[i] = v / l[i * c + i];
    }
    for i in (0..c).rev() {
        let mut v = y[i];
        for k in i + 1..c {
            v -= l[k * c + i] * y[k];
        }
        y[i] = v / l[i * c + i];
    }
}

impl Kkt {
    pub fn new(s: &Structured) -> Option<Self> {
        let m_e = s.e_rows.len();
        // E by columns.
        let mut e_cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); s.n];
        for (i, row) in s.e_rows.iter().enumerate() {
            for &(j, v) in row {
                e_cols[j].push((i, v));
            }
        }
        let mut g = Groups::default();
        let mut pattern: Vec<Vec<usize>> = (0..m_e).map(|i| vec![i]).collect();
        let mut clusters: Vec<Cluster> = Vec::new();
        for (k, grp) in s.groups.iter().enumerate() {
            let c = grp.cols.len();
            let mut rows: Vec<usize> = grp.cols.iter().flat_map(|&j| e_cols[j].iter().map(|e| e.0)).collect();
            rows.sort_unstable();
            rows.dedup();
            let r = rows.len();
            let mut e_loc = vec![0.0; r * c];
            for (lc, &j) in grp.cols.iter().enumerate() {
                for &(i, v) in &e_cols[j] {
                    let lr = rows.binary_search(&i).expect("row collected above");
                    e_loc[lr * c + lc] += v;
                }
            }
            let mut g_loc = vec![0.0; grp.g_rows.len() * c];
            for (kk, &gr) in grp.g_rows.iter().enumerate() {
                for &(j, v) in &s.g_rows[gr] {
                    let lc = grp.cols.binary_search(&j).expect("a group holds its rows' columns");
                    g_loc[kk * c + lc] += v;
                }
            }
            let same = k > 0 && g.e_rows.get(k - 1) == &rows[..];
            if same {
                clusters.last_mut().expect("a previous group").groups.end = k + 1;
            } else {
                for a in 0..r {
                    for b in 0..=a {
                        pattern[rows[b]].push(rows[a]);
                    }
                }
                clusters.push(Cluster { groups: k..k + 1, scatter: Vec::new() });
            }
            g.cols.push(&grp.cols);
            g.g_rows.push(&grp.g_rows);
            g.e_rows.push(&rows);
            g.e_loc.push(&e_loc);
            g.g_loc.push(&g_loc);
            g.h_inv.push(&vec![0.0; c * c]);
            g.b.push(&e_loc);
        }
        let mut col_ptr = vec![0usize; m_e + 1];
        let mut row_idx = Vec::new();
        for (j, col) in pattern.iter_mut().enumerate() {
            col.sort_unstable();
            col.dedup();
            row_idx.extend_from_slice(col);
            col_ptr[j + 1] = row_idx.len();
        }
        let find = |i: usize, j: usize| -> usize {
            col_ptr[j] + row_idx[col_ptr[j]..col_ptr[j + 1]].binary_search(&i).expect("entry in the pattern")
        };
        for cl in clusters.iter_mut() {
            let rows = g.e_rows.get(cl.groups.start);
            let r = rows.len();
            let mut scatter = Vec::with_capacity(r * (r + 1) / 2);
            for a in 0..r {
                for b in 0..=a {
                    scatter.push(find(rows[a], rows[b]));
                }
            }
            cl.scatter = scatter;
        }
        let diag_at: Vec<usize> = (0..m_e).map(|i| find(i, i)).collect();
        let sym = SymbolicSparseColMatRef::new_checked(m_e, m_e, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .ok()?;
        let req = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let buffer = MemBuffer::new(req);
        let l_values = vec![0.0; symbolic.len_val()];
        let values = vec![0.0; row_idx.len()];
        let mg = s.g_rows.len();
        Some(Self {
            g,
            clusters,
            n: s.n,
            m_e,
            col_ptr,
            row_idx,
            diag_at,
            values,
            symbolic,
            l_values,
            buffer,
            d: vec![0.0; mg],
            d_inv: vec![0.0; mg],
        })
    }

    /// Factorises the system for the scaling `d` (s/z per inequality row) and diagonal `p`.
    pub fn factor(&mut self, p: &[f64], d: &[f64]) -> bool {
        self.d.copy_from_slice(d);
        for (di, &dv) in self.d_inv.iter_mut().zip(d) {
            *di = 1.0 / dv;
        }
        self.values.iter_mut().for_each(|v| *v = 0.0);
        let g = &mut self.g;
        let mut acc = Vec::new();
        let mut h = [0.0f64; MAX_GROUP * MAX_GROUP];
        for cl in &self.clusters {
            let r = g.e_rows.get(cl.groups.start).len();
            acc.clear();
            acc.resize(r * (r + 1) / 2, 0.0);
            for k in cl.groups.clone() {
                let cols = g.cols.get(k);
                let c = cols.len();
                let h = &mut h[..c * c];
                h.iter_mut().for_each(|v| *v = 0.0);
                for (lc, &j) in cols.iter().enumerate() {
                    h[lc * c + lc] = p[j] + EPS;
                }
                let g_loc = g.g_loc.get(k);
                for (kk, &gr) in g.g_rows.get(k).iter().enumerate() {
                    let inv = self.d_inv[gr];
                    let row = &g_loc[kk * c..(kk + 1) * c];
                    for a in 0..c {
                        let ra = row[a] * inv;
                        if ra == 0.0 {
                            continue;
                        }
                        for b in 0..=a {
                            h[a * c + b] += ra * row[b];
                        }
                    }
                }
                if !chol(h, c) {
                    return false;
                }
                // H⁻¹ column by column from the factor.
                let h_inv = g.h_inv.get_mut(k);
                for col in 0..c {
                    let mut e = [0.0f64; MAX_GROUP];
                    e[col] = 1.0;
                    chol_solve(h, c, &mut e[..c]);
                    for row in 0..c {
                        h_inv[row * c + col] = e[row];
                    }
                }
                // B = E_loc H⁻¹, and S += B E_locᵀ (lower triangle).
                let e_loc = g.e_loc.get(k);
                let b = &mut g.b.data[g.b.off[k]..g.b.off[k + 1]];
                for a in 0..r {
                    for col in 0..c {
                        let mut v = 0.0;
                        for i in 0..c {
                            v += e_loc[a * c + i] * h_inv[i * c + col];
                        }
                        b[a * c + col] = v;
                    }
                }
                let mut idx = 0;
                for a in 0..r {
                    let ba = &b[a * c..(a + 1) * c];
                    for bb in 0..=a {
                        let eb = &e_loc[bb * c..(bb + 1) * c];
                        let mut v = 0.0;
                        for i in 0..c {
                            v += ba[i] * eb[i];
                        }
                        acc[idx] += v;
                        idx += 1;
                    }
                }
            }
            for (&at, &v) in cl.scatter.iter().zip(&acc) {
                self.values[at] += v;
            }
        }
        for &k in &self.diag_at {
            self.values[k] += EPS;
        }
        let mat = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(self.m_e, self.m_e, &self.col_ptr, None, &self.row_idx),
            &self.values,
        );
        let reg = LltRegularization { dynamic_regularization_delta: 2e-7, dynamic_regularization_epsilon: 1e-13 };
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                mat,
                Side::Lower,
                reg,
                Par::Seq,
                MemStack::new(&mut self.buffer),
                Default::default(),
            )
            .is_ok()
    }

    /// One solve of the regularised system: (rx, rz_E, rz_G) → (x, z_E, z_G).
    fn solve_reg(&mut self, rx: &[f64], rz: &[f64], x: &mut [f64], z: &mut [f64]) {
        let m_e = self.m_e;
        let (rz_e, rz_g) = rz.split_at(m_e);
        let g = &self.g;
        // r̃x = rx + Gᵀ D⁻¹ rz_G (kept in x), and the right side E H⁻¹ r̃x − rz_E = B r̃x − rz_E.
        let mut rhs_s: Vec<f64> = rz_e.iter().map(|v| -v).collect();
        let mut rt = [0.0f64; MAX_GROUP];
        for k in 0..g.cols.off.len() - 1 {
            let cols = g.cols.get(k);
            let c = cols.len();
            for (lc, &j) in cols.iter().enumerate() {
                rt[lc] = rx[j];
            }
            let g_loc = g.g_loc.get(k);
            for (kk, &gr) in g.g_rows.get(k).iter().enumerate() {
                let f = rz_g[gr] * self.d_inv[gr];
                for lc in 0..c {
                    rt[lc] += g_loc[kk * c + lc] * f;
                }
            }
            for (lc, &j) in cols.iter().enumerate() {
                x[j] = rt[lc];
            }
            let b = g.b.get(k);
            for (a, &row) in g.e_rows.get(k).iter().enumerate() {
                let mut v = 0.0;
                for lc in 0..c {
                    v += b[a * c + lc] * rt[lc];
                }
                rhs_s[row] += v;
            }
        }
        let llt = LltRef::new(&self.symbolic, &self.l_values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut rhs_s, m_e, 1),
            Par::Seq,
            MemStack::new(&mut self.buffer),
        );
        let (z_e, z_g) = z.split_at_mut(m_e);
        z_e.copy_from_slice(&rhs_s);
        // x = H⁻¹ r̃x − Bᵀ z_E, z_G = D⁻¹ (G x − rz_G).
        let mut y = [0.0f64; MAX_GROUP];
        for k in 0..g.cols.off.len() - 1 {
            let cols = g.cols.get(k);
            let c = cols.len();
            let h_inv = g.h_inv.get(k);
            for (a, yv) in y[..c].iter_mut().enumerate() {
                let mut v = 0.0;
                for (i, &j) in cols.iter().enumerate() {
                    v += h_inv[a * c + i] * x[j];
                }
                *yv = v;
            }
            let b = g.b.get(k);
            for (a, &row) in g.e_rows.get(k).iter().enumerate() {
                let ze = z_e[row];
                for lc in 0..c {
                    y[lc] -= b[a * c + lc] * ze;
                }
            }
            for (lc, &j) in cols.iter().enumerate() {
                x[j] = y[lc];
            }
            let g_loc = g.g_loc.get(k);
            for (kk, &gr) in g.g_rows.get(k).iter().enumerate() {
                let mut v = -rz_g[gr];
                for lc in 0..c {
                    v += g_loc[kk * c + lc] * y[lc];
                }
                z_g[gr] = v * self.d_inv[gr];
            }
        }
    }

    /// K [x; z] with the unregularised matrix.
    fn apply(&self, p: &[f64], x: &[f64], z: &[f64], out_x: &mut [f64], out_z: &mut [f64]) {
        let m_e = self.m_e;
        for j in 0..self.n {
            out_x[j] = p[j] * x[j];
        }
        out_z[..m_e].iter_mut().for_each(|v| *v = 0.0);
        let g = &self.g;
        for k in 0..g.cols.off.len() - 1 {
            let cols = g.cols.get(k);
            let c = cols.len();
            let e_loc = g.e_loc.get(k);
            for (a, &row) in g.e_rows.get(k).iter().enumerate() {
                let mut v = 0.0;
                let zr = z[row];
                for (lc, &j) in cols.iter().enumerate() {
                    let e = e_loc[a * c + lc];
                    v += e * x[j];
                    out_x[j] += e * zr;
                }
                out_z[row] += v;
            }
            let g_loc = g.g_loc.get(k);
            for (kk, &gr) in g.g_rows.get(k).iter().enumerate() {
                let zg = z[m_e + gr];
                let mut v = -self.d[gr] * zg;
                for (lc, &j) in cols.iter().enumerate() {
                    let gv = g_loc[kk * c + lc];
                    v += gv * x[j];
                    out_x[j] += gv * zg;
                }
                out_z[m_e + gr] = v;
            }
        }
    }

    /// Solves K [x; z] = [rx; rz]; with `refine`, iterative refinement against the
    /// unregularised matrix (clarabel's defaults: relative 1e-13, absolute 1e-12, ≤ 10 steps,
    /// stop when a step gains less than 5×).
    pub fn solve(&mut self, p: &[f64], rx: &[f64], rz: &[f64], x: &mut [f64], z: &mut [f64], refine: bool) -> bool {
        self.solve_reg(rx, rz, x, z);
        if refine {
            let norm_b = rx.iter().chain(rz).fold(0.0f64, |a, v| a.max(v.abs()));
            let (mut kx, mut kz) = (vec![0.0; x.len()], vec![0.0; z.len()]);
            let (mut dx, mut dz) = (vec![0.0; x.len()], vec![0.0; z.len()]);
            let error = |kx: &mut Vec<f64>, kz: &mut Vec<f64>, x: &[f64], z: &[f64], this: &Self| -> f64 {
                this.apply(p, x, z, kx, kz);
                let mut e = 0.0f64;
                for (k, r) in kx.iter_mut().zip(rx) {
                    *k = r - *k;
                    e = e.max(k.abs());
                }
                for (k, r) in kz.iter_mut().zip(rz) {
                    *k = r - *k;
                    e = e.max(k.abs());
                }
                e
            };
            let mut norm_e = error(&mut kx, &mut kz, x, z, self);
            for _ in 0..10 {
                if norm_e <= 1e-12 + 1e-13 * norm_b {
                    break;
                }
                let (ex, ez) = (kx.clone(), kz.clone());
                self.solve_reg(&ex, &ez, &mut dx, &mut dz);
                let xn: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + b).collect();
                let zn: Vec<f64> = z.iter().zip(&dz).map(|(a, b)| a + b).collect();
                let new_e = error(&mut kx, &mut kz, &xn, &zn, self);
                if new_e < norm_e {
                    x.copy_from_slice(&xn);
                    z.copy_from_slice(&zn);
                }
                if new_e * 5.0 > norm_e {
                    break;
                }
                norm_e = new_e;
            }
        }
        x.iter().chain(z.iter()).all(|v| v.is_finite())
    }
}
