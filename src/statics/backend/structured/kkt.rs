//! The interior-point Newton system of a [`ContactProblem`], reduced to the equality rows.
//!
//! KKT system (clarabel's, with a static regularisation ε on the x block):
//! ```text
//! [ P + εI   Eᵀ    Gᵀ  ] [x  ]   [rx ]
//! [ E        0     0   ] [z_E] = [r_E]
//! [ G        0    −Hs  ] [z_G]   [r_G]      Hs = WᵀW: s/z per non-negative row, η²(2wwᵀ − J) per SOC
//! ```
//! Eliminating z_G and then x (block diagonal: `H_p = P + εI + G_pᵀ Hs_p⁻¹ G_p`, C×C per force
//! point) leaves `S z_E = E H⁻¹ r̃x − r_E`, `S = E H⁻¹ Eᵀ`: 6 rows per block plus one per
//! budget, sparse like the contact graph, positive definite. The points of an interface share
//! the rows of its two blocks, so their contributions are summed in the interface's own frame
//! first — `K = Σ_p T_p N H_p⁻¹ Nᵀ T_pᵀ`, a 6×6 wrench matrix — and mapped to the blocks once
//! (`Ψ_a K Ψ_bᵀ`). Each H_p is kept as its Cholesky factor, never inverted explicitly
//! ([`cholesky`]). S is factorised by faer's sparse Cholesky (AMD ordering and
//! symbolic analysis once per problem). Iterative refinement against the unregularised
//! system removes what ε and round-off leave.
//!
//! A load factor λ ≥ 0 (its column L in the block rows) would add `L H_λ⁻¹ Lᵀ` to S: rank
//! one but dense over the loaded blocks, and H_λ⁻¹ grows without bound as λ's constraint
//! goes inactive. So λ stays an unknown beside S's factor (a bordered system): with
//! y = S⁻¹ r and w = S⁻¹ L (solved once per factorisation), `S z_E − L x_λ = r`,
//! `Lᵀ z_E + H_λ x_λ = r̃x_λ` give `x_λ = (r̃x_λ − Lᵀy) / (Lᵀw + H_λ)`, `z_E = y + w x_λ` —
//! no division by a vanishing H_λ.

use super::cones::Scaling;
use super::shape::Shape;
use crate::statics::problem::{Side as ContactSide, motion_at, wrench};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use std::sync::Arc;

/// Entries of S's Cholesky factor from which its numeric factorisation and solves run on the
/// threads the problem allows (faer's supernodal kernels on rayon: they pay only where the
/// supernodes are large). Measured on this 2-core VM, running-bond walls, one process each,
/// the solve serial against two threads: 10 051 bricks (12 million entries) 5.6 → 5.8 s,
/// 50 051 (66 million) 29.9 → 30.5 s, 100 101 (172 million) 100.1 → 86.9 s.
pub(super) const PARALLEL_FROM: usize = 100_000_000;

/// Regularisation of H. The elimination is exact (H is positive definite: every variable sits
/// in an inequality row), so this only guards round-off. S gets none: a static εI there is a
/// −εI in the equality block that iterative refinement must undo every time (the duals run to
/// 1e2, so ε|z_E| was the largest error); faer's dynamic regularisation still catches the zero
/// pivots of a singular S. Without it the Armadillo's partial shells solve ~30 % faster.
const EPS: f64 = 1e-13;

type Mat6 = [[f64; 6]; 6];

/// Where a contact's blocks sit in S's values: the start of each column's run of the
/// off-diagonal 6×6 block (rows of the larger block index, columns of the smaller).
#[derive(Clone, Copy)]
struct ContactSlots {
    off: [usize; 6],
}

/// S's pattern (lower triangle, CSC) and its symbolic factorisation — AMD ordering,
/// elimination tree, supernodes: a function of the contact graph only, so a warm start carries
/// it to the next problem of the same layout (on the Armadillo it is 2.5 of the 3 ms of
/// setting up a solve).
pub struct Pattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
}

pub struct Kkt<const C: usize> {
    /// H_p's Cholesky factor per point ([`cholesky`]).
    chol: Vec<[[f64; C]; C]>,
    /// H_σ⁻¹ per budget slack.
    hinv_sigma: Vec<f64>,
    /// With a load factor: H_λ, w = S⁻¹ L and Lᵀw (module docs).
    factor: Option<(f64, Vec<f64>, f64)>,
    slots: Vec<Option<ContactSlots>>,
    m_e: usize,
    /// S's pattern and symbolic factorisation, and its values.
    pattern: Arc<Pattern>,
    values: Vec<f64>,
    /// Serial, or the problem's threads for a factor of `parallel_from` entries or more
    /// ([`PARALLEL_FROM`] by default).
    par: Par,
    l_values: Vec<f64>,
    buffer: MemBuffer,
    /// Work: the right-hand side of S, r̃x per point.
    rhs_s: Vec<f64>,
    rt: Vec<[f64; C]>,
    /// Refinement work.
    work: [Vec<f64>; 6],
}

/// The Cholesky factor of a symmetric positive definite C×C `h`: lower L with H = L Lᵀ, its
/// diagonal stored inverted (the solves multiply). `None` when `h` is not numerically positive
/// definite.
///
/// Why a factor and not H⁻¹: near the optimum H_p's eigenvalues spread over ~17 decades (an
/// active facet's z/s reached 1.2e9 on a sliding wall, inactive ones 1e-8), and x = H⁻¹ r by
/// the explicit inverse then misses H x = r by up to 7e3 on a right-hand side of 14 — an
/// error iterative refinement could not remove (a load factor ended `InsufficientProgress`).
/// Substitution with the factor is backward stable: the miss stays at round-off of ‖H‖‖x‖.
fn cholesky<const C: usize>(h: &[[f64; C]; C]) -> Option<[[f64; C]; C]> {
    let mut l = [[0.0f64; C]; C];
    for j in 0..C {
        let mut d = h[j][j];
        for k in 0..j {
            d -= l[j][k] * l[j][k];
        }
        if d <= 0.0 || !d.is_finite() {
            return None;
        }
        let dinv = 1.0 / d.sqrt();
        l[j][j] = dinv;
        for i in j + 1..C {
            let mut v = h[i][j];
            for k in 0..j {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v * dinv;
        }
    }
    Some(l)
}

/// L⁻¹ r, `l` from [`cholesky`].
fn forward<const C: usize>(l: &[[f64; C]; C], r: &[f64; C]) -> [f64; C] {
    let mut y = [0.0; C];
    for i in 0..C {
        let mut v = r[i];
        for k in 0..i {
            v -= l[i][k] * y[k];
        }
        y[i] = v * l[i][i];
    }
    y
}

/// L⁻ᵀ y, `l` from [`cholesky`].
fn backward<const C: usize>(l: &[[f64; C]; C], y: &[f64; C]) -> [f64; C] {
    let mut x = [0.0; C];
    for i in (0..C).rev() {
        let mut v = y[i];
        for k in i + 1..C {
            v -= l[k][i] * x[k];
        }
        x[i] = v * l[i][i];
    }
    x
}

/// H⁻¹ r by the factor of H.
fn chol_solve<const C: usize>(l: &[[f64; C]; C], r: &[f64; C]) -> [f64; C] {
    backward(l, &forward(l, r))
}

/// K += T Y Tᵀ for one point at ρ (lower triangle of K), T = [I; [ρ]×]: Y, R Y and R Y Rᵀ
/// with R = [ρ]×.
fn add_point_wrench(k6: &mut Mat6, y: &[[f64; 3]; 3], rho: &[f64; 3]) {
    let mut ry = [[0.0f64; 3]; 3];
    for j in 0..3 {
        ry[0][j] = rho[1] * y[2][j] - rho[2] * y[1][j];
        ry[1][j] = rho[2] * y[0][j] - rho[0] * y[2][j];
        ry[2][j] = rho[0] * y[1][j] - rho[1] * y[0][j];
    }
    for i in 0..3 {
        for j in 0..=i {
            k6[i][j] += y[i][j];
        }
        for j in 0..3 {
            k6[3 + i][j] += ry[i][j];
        }
    }
    // R Y Rᵀ: row i of (R Y) crossed with ρ.
    for i in 0..3 {
        let r = &ry[i];
        let rr = [r[1] * rho[2] - r[2] * rho[1], r[2] * rho[0] - r[0] * rho[2], r[0] * rho[1] - r[1] * rho[0]];
        for j in 0..=i {
            k6[3 + i][3 + j] -= rr[j];
        }
    }
}

/// `Nᵀ (U_top + U_bot × ρ)`: a contact's block motions seen by one point's variables.
fn point_motion<const C: usize>(sh: &Shape<C>, u: &[f64; 6], rho: &[f64; 3]) -> [f64; C] {
    let g = motion_at(u, rho);
    let mut t = [0.0; C];
    for k in 0..C {
        t[k] = sh.fmap[0][k] * g[0] + sh.fmap[1][k] * g[1] + sh.fmap[2][k] * g[2];
    }
    t
}

fn point_force<const C: usize>(sh: &Shape<C>, x: &[f64; C]) -> [f64; 3] {
    let mut f = [0.0; 3];
    for (i, fi) in f.iter_mut().enumerate() {
        for k in 0..C {
            *fi += sh.fmap[i][k] * x[k];
        }
    }
    f
}

fn as_point<const C: usize>(v: &[f64], p: usize) -> [f64; C] {
    let mut out = [0.0; C];
    out.copy_from_slice(&v[p * C..(p + 1) * C]);
    out
}

impl<const C: usize> Kkt<C> {
    /// The system of `sh`; with `reuse`, its symbolic factorisation when the pattern is the same.
    pub fn new(sh: &Shape<C>, threads: usize, parallel_from: usize, reuse: Option<&Arc<Pattern>>) -> Option<Self> {
        let nb = sh.blocks;
        let nk = sh.budget_vars.len();
        let m_e = 6 * nb + nk;
        // Pattern: dense 6×6 diagonal blocks, an off-diagonal block per pair of blocks that
        // share an interface, budget rows against every block and each other.
        let mut pairs: Vec<(usize, usize)> = sh
            .contacts
            .iter()
            .filter_map(|c| match (&c.sides[0], &c.sides[1]) {
                (Some(a), Some(b)) if a.block != b.block => Some((a.block.max(b.block), a.block.min(b.block))),
                _ => None,
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        // Rows below the diagonal block, per block column: the larger blocks it pairs with.
        let mut below: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for &(i, j) in &pairs {
            below[j].push(i);
        }
        let mut col_ptr = Vec::with_capacity(m_e + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for j in 0..nb {
            for c in 0..6 {
                for r in c..6 {
                    row_idx.push(6 * j + r);
                }
                for &i in &below[j] {
                    row_idx.extend(6 * i..6 * i + 6);
                }
                row_idx.extend(6 * nb..m_e);
                col_ptr.push(row_idx.len());
            }
        }
        for k in 0..nk {
            row_idx.extend(6 * nb + k..m_e);
            col_ptr.push(row_idx.len());
        }
        let slots = sh
            .contacts
            .iter()
            .map(|c| match (&c.sides[0], &c.sides[1]) {
                (Some(a), Some(b)) if a.block != b.block => {
                    let (i, j) = (a.block.max(b.block), a.block.min(b.block));
                    let at = below[j].binary_search(&i).ok()?;
                    let mut off = [0usize; 6];
                    for (c, o) in off.iter_mut().enumerate() {
                        // Column 6j + c: its diagonal-block run (6 − c rows), then 6 rows per
                        // pair before this one.
                        *o = col_ptr[6 * j + c] + (6 - c) + 6 * at;
                    }
                    Some(ContactSlots { off })
                }
                _ => None,
            })
            .collect();
        let pattern = match reuse {
            Some(p) if p.col_ptr == col_ptr && p.row_idx == row_idx => Arc::clone(p),
            _ => {
                let sym = SymbolicSparseColMatRef::new_checked(m_e, m_e, &col_ptr, None, &row_idx);
                let symbolic = factorize_symbolic_cholesky(
                    sym,
                    Side::Lower,
                    SymmetricOrdering::Amd,
                    CholeskySymbolicParams {
                        // Supernodal where the fill makes dense blocks pay (vaults, walls),
                        // simplicial for chains (an arch of 1000: 2× faster than supernodal).
                        // faer's own cut (flops per entry of L above 40) left the Armadillo and
                        // the 100-brick wall simplicial; at 20 (half of it) they go supernodal,
                        // 13 % and 18 % faster (interleaved runs, best of 4), while arches of
                        // 100–1000 stay simplicial.
                        supernodal_flop_ratio_threshold: SupernodalThreshold(0.5),
                        ..Default::default()
                    },
                )
                .ok()?;
                Arc::new(Pattern { col_ptr, row_idx, symbolic })
            }
        };
        let symbolic = &pattern.symbolic;
        let par = if threads > 1 && symbolic.len_val() >= parallel_from { Par::rayon(threads) } else { Par::Seq };
        let req = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let buffer = MemBuffer::new(req);
        let l_values = vec![0.0; symbolic.len_val()];
        let values = vec![0.0; pattern.row_idx.len()];
        let n = sh.n();
        let mg = sh.m_g();
        Some(Self {
            chol: vec![[[0.0; C]; C]; sh.points()],
            hinv_sigma: vec![0.0; nk],
            factor: None,
            slots,
            m_e,
            values,
            pattern,
            par,
            l_values,
            buffer,
            rhs_s: vec![0.0; m_e],
            rt: vec![[0.0; C]; sh.points()],
            work: [vec![0.0; n], vec![0.0; m_e], vec![0.0; mg], vec![0.0; n], vec![0.0; m_e], vec![0.0; mg]],
        })
    }

    /// S's pattern and symbolic factorisation, for the next problem of this layout.
    pub fn pattern(&self) -> Arc<Pattern> {
        Arc::clone(&self.pattern)
    }

    /// Adds `m` (a 6×6 block of S at block rows `i`, block columns `j`) into the values.
    fn scatter(&mut self, i: usize, j: usize, m: &Mat6, slots: Option<ContactSlots>) {
        if i == j {
            for c in 0..6 {
                let base = self.pattern.col_ptr[6 * j + c];
                for r in c..6 {
                    self.values[base + r - c] += m[r][c];
                }
            }
        } else if i > j {
            let s = slots.expect("an off-diagonal block has slots");
            for c in 0..6 {
                for r in 0..6 {
                    self.values[s.off[c] + r] += m[r][c];
                }
            }
        } else {
            let s = slots.expect("an off-diagonal block has slots");
            for c in 0..6 {
                for r in 0..6 {
                    self.values[s.off[c] + r] += m[c][r];
                }
            }
        }
    }

    /// Factorises the system for the current scaling.
    /// Forms S for the scaling `sc` and factors it: per contact, the points' H_p⁻¹ and the
    /// interface's 6×6 wrench matrix K, mapped to its blocks; then the budget rows. `false` when
    /// an H_p or S cannot be factored.
    pub fn factor(&mut self, sh: &Shape<C>, sc: &Scaling) -> bool {
        self.values.iter_mut().for_each(|v| *v = 0.0);
        // The budget rows' own block (at most two budgets), accumulated over all points.
        let mut bb = [[0.0f64; 2]; 2];
        for (ci, contact) in sh.contacts.iter().enumerate() {
            let Some((k6, v)) = self.contact_matrix(sh, sc, contact.points.clone(), &mut bb) else {
                return false;
            };
            self.add_contact(sh, ci, &contact.sides, &k6, &v);
        }
        self.add_budgets(sh, sc, &mut bb);
        self.factor_numeric() && self.load_factor_update(sh, sc)
    }

    /// H_λ and w = S⁻¹ L for the bordered solves (nothing without a load factor).
    fn load_factor_update(&mut self, sh: &Shape<C>, sc: &Scaling) -> bool {
        let Some((column, _)) = sh.factor else { return true };
        let h = EPS + sc.dinv[sh.points() * sh.m_p + sh.budgets()];
        self.rhs_s.iter_mut().for_each(|v| *v = 0.0);
        self.rhs_s[..column.len()].copy_from_slice(column);
        let mut w = vec![0.0; self.m_e];
        self.solve_s(&mut w);
        let lw: f64 = column.iter().zip(&w).map(|(l, w)| l * w).sum();
        self.factor = Some((h, w, lw));
        lw.is_finite()
    }

    /// H_p = P + εI + G_pᵀ Hs_p⁻¹ G_p of point `p` (C×C, symmetric, full).
    fn point_hessian(sh: &Shape<C>, sc: &Scaling, p: usize) -> [[f64; C]; C] {
        let mp = sh.m_p;
        let mut h = [[0.0f64; C]; C];
        for k in 0..C {
            h[k][k] = sh.p[k] + EPS;
        }
        let dinv = &sc.dinv[p * mp..p * mp + sh.nonneg.len()];
        for (r, g) in sh.nonneg.iter().enumerate() {
            let w = dinv[r];
            for a in 0..C {
                let ga = g[a] * w;
                if ga != 0.0 {
                    for b in 0..=a {
                        h[a][b] += ga * g[b];
                    }
                }
            }
        }
        if let Some(soc) = &sh.soc {
            // Gᵀ Hs⁻¹ G = MᵀM with M = W⁻¹ G: a Gram matrix, positive semidefinite whatever the
            // rounding.
            let mut mm = [[0.0f64; C]; 3];
            for k in 0..C {
                let col = sc.winv_mul(p, &[soc[0][k], soc[1][k], soc[2][k]]);
                for i in 0..3 {
                    mm[i][k] = col[i];
                }
            }
            for a in 0..C {
                for b in 0..=a {
                    h[a][b] += mm[0][a] * mm[0][b] + mm[1][a] * mm[1][b] + mm[2][a] * mm[2][b];
                }
            }
        }
        for a in 0..C {
            for b in 0..a {
                h[b][a] = h[a][b];
            }
        }
        h
    }

    /// One contact's points: H_p's factor kept per point, and summed in the interface frame the wrench
    /// matrix K = Σ_p T_p N H_p⁻¹ Nᵀ T_pᵀ (6×6, symmetric), the budget columns' wrenches `v`
    /// and their block `bb`. `None` when an H_p cannot be inverted.
    fn contact_matrix(
        &mut self,
        sh: &Shape<C>,
        sc: &Scaling,
        points: std::ops::Range<usize>,
        bb: &mut [[f64; 2]; 2],
    ) -> Option<(Mat6, [[f64; 6]; 2])> {
        let mut k6 = [[0.0f64; 6]; 6];
        let mut v = [[0.0f64; 6]; 2];
        for p in points {
            let h = Self::point_hessian(sh, sc, p);
            let l = cholesky(&h)?;
            self.chol[p] = l;
            // Y = N H⁻¹ Nᵀ = MᵀM with M = L⁻¹Nᵀ (local force covariance; a Gram matrix,
            // positive semidefinite whatever the rounding), then K += T Y Tᵀ.
            let m = [forward(&l, &sh.fmap[0]), forward(&l, &sh.fmap[1]), forward(&l, &sh.fmap[2])];
            let mut y = [[0.0f64; 3]; 3];
            for i in 0..3 {
                for j in 0..=i {
                    let mut s = 0.0;
                    for k in 0..C {
                        s += m[i][k] * m[j][k];
                    }
                    y[i][j] = s;
                    y[j][i] = s;
                }
            }
            add_point_wrench(&mut k6, &y, &sh.rho[p]);
            if sh.budget_vars.is_empty() {
                continue;
            }
            // The budget columns: (N H⁻¹)[i][col] = (L⁻ᵀ M)[col][i], and H⁻¹'s own entries.
            let hn = [backward(&l, &m[0]), backward(&l, &m[1]), backward(&l, &m[2])];
            for (kb, &col) in sh.budget_vars.iter().enumerate() {
                let u = [hn[0][col], hn[1][col], hn[2][col]];
                let w = wrench(&sh.rho[p], &u);
                for i in 0..6 {
                    v[kb][i] += w[i];
                }
                let mut unit = [0.0; C];
                unit[col] = 1.0;
                let column = chol_solve(&l, &unit);
                for (kb2, &col2) in sh.budget_vars.iter().enumerate().take(kb + 1) {
                    bb[kb][kb2] += column[col2];
                }
            }
        }
        for i in 0..6 {
            for j in 0..i {
                k6[j][i] = k6[i][j];
            }
        }
        Some((k6, v))
    }

    /// Maps a contact's K to its blocks: S_jj += Ψ_j K Ψ_jᵀ for each free side, S_ab += Ψ_a K
    /// Ψ_bᵀ between them, and the budget columns' Ψ_j v.
    fn add_contact(
        &mut self,
        sh: &Shape<C>,
        ci: usize,
        sides: &[Option<ContactSide>; 2],
        k6: &Mat6,
        v: &[[f64; 6]; 2],
    ) {
        let nk = sh.budget_vars.len();
        let mut m = [[[0.0f64; 6]; 6]; 2];
        for (s, side) in sides.iter().enumerate() {
            let Some(side) = side else { continue };
            // M = Ψ K, then S_jj += M Ψᵀ.
            for r in 0..6 {
                for c in 0..6 {
                    let mut acc = 0.0;
                    for k in 0..6 {
                        acc += side.psi[r][k] * k6[k][c];
                    }
                    m[s][r][c] = acc;
                }
            }
            let mut d = [[0.0f64; 6]; 6];
            for r in 0..6 {
                for c in 0..=r {
                    let mut acc = 0.0;
                    for k in 0..6 {
                        acc += m[s][r][k] * side.psi[c][k];
                    }
                    d[r][c] = acc;
                }
            }
            self.scatter(side.block, side.block, &d, None);
            for kb in 0..nk {
                let mut w = [0.0; 6];
                side.add_wrench(&v[kb], &mut w);
                for (c, wc) in w.iter().enumerate() {
                    let at = self.pattern.col_ptr[6 * side.block + c + 1] - nk + kb;
                    self.values[at] += wc;
                }
            }
        }
        if let (Some(a), Some(b)) = (&sides[0], &sides[1])
            && a.block != b.block
        {
            // S_ab = Ψ_a K Ψ_bᵀ.
            let mut o = [[0.0f64; 6]; 6];
            for r in 0..6 {
                for c in 0..6 {
                    let mut acc = 0.0;
                    for k in 0..6 {
                        acc += m[0][r][k] * b.psi[c][k];
                    }
                    o[r][c] = acc;
                }
            }
            let slots = self.slots[ci];
            self.scatter(a.block, b.block, &o, slots);
        }
    }

    /// The budget rows: each slack σ (P = 0, one row −σ ≤ 0: H_σ = ε + z/s) on the diagonal,
    /// then the accumulated block `bb` into S.
    fn add_budgets(&mut self, sh: &Shape<C>, sc: &Scaling, bb: &mut [[f64; 2]; 2]) {
        let nb = sh.blocks;
        let nk = sh.budget_vars.len();
        for kb in 0..nk {
            let d_inv = sc.dinv[sh.points() * sh.m_p + kb];
            let h = EPS + d_inv;
            self.hinv_sigma[kb] = 1.0 / h;
            bb[kb][kb] += 1.0 / h;
        }
        for kb in 0..nk {
            for kb2 in 0..=kb {
                // Column 6nb + kb2, row 6nb + kb.
                let at = self.pattern.col_ptr[6 * nb + kb2] + (kb - kb2);
                self.values[at] += bb[kb][kb2];
            }
        }
    }

    /// faer's numeric Cholesky of S on the symbolic analysis made once per problem (dynamic
    /// regularisation only for the zero pivots of a singular S).
    fn factor_numeric(&mut self) -> bool {
        let mat = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(
                self.m_e,
                self.m_e,
                &self.pattern.col_ptr,
                None,
                &self.pattern.row_idx,
            ),
            &self.values,
        );
        let reg = LltRegularization { dynamic_regularization_delta: 2e-7, dynamic_regularization_epsilon: 1e-13 };
        self.pattern
            .symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                mat,
                Side::Lower,
                reg,
                self.par,
                MemStack::new(&mut self.buffer),
                Default::default(),
            )
            .is_ok()
    }

    fn solve_s(&mut self, ze: &mut [f64]) {
        let llt = LltRef::new(&self.pattern.symbolic, &self.l_values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut self.rhs_s, self.m_e, 1),
            self.par,
            MemStack::new(&mut self.buffer),
        );
        ze.copy_from_slice(&self.rhs_s);
    }

    /// One solve of the regularised system: (rx, r_E, r_G) → (x, z_E, z_G).
    #[allow(clippy::too_many_arguments)]
    fn solve_reg(
        &mut self,
        sh: &Shape<C>,
        sc: &Scaling,
        rx: &[f64],
        re: &[f64],
        rg: &[f64],
        x: &mut [f64],
        ze: &mut [f64],
        zg: &mut [f64],
    ) {
        let nb = sh.blocks;
        let mp = sh.m_p;
        let nn = sh.nonneg.len();
        let np = sh.points();
        for (o, r) in self.rhs_s.iter_mut().zip(re) {
            *o = -r;
        }
        // r̃x = rx + Gᵀ Hs⁻¹ r_G; S's right side E H⁻¹ r̃x − r_E.
        for contact in sh.contacts {
            let mut w6 = [0.0f64; 6];
            for p in contact.points.clone() {
                let mut rt: [f64; C] = as_point(rx, p);
                let rgp = &rg[p * mp..(p + 1) * mp];
                let dinv = &sc.dinv[p * mp..p * mp + nn];
                for (r, g) in sh.nonneg.iter().enumerate() {
                    let f = rgp[r] * dinv[r];
                    for k in 0..C {
                        rt[k] += g[k] * f;
                    }
                }
                if let Some(soc) = &sh.soc {
                    let f = sc.hs_inv_mul(p, &[rgp[nn], rgp[nn + 1], rgp[nn + 2]]);
                    for i in 0..3 {
                        for k in 0..C {
                            rt[k] += soc[i][k] * f[i];
                        }
                    }
                }
                self.rt[p] = rt;
                let w = chol_solve(&self.chol[p], &rt);
                let f = point_force(sh, &w);
                let wr = wrench(&sh.rho[p], &f);
                for i in 0..6 {
                    w6[i] += wr[i];
                }
                for (kb, &col) in sh.budget_vars.iter().enumerate() {
                    self.rhs_s[6 * nb + kb] += w[col];
                }
            }
            for side in contact.sides.iter().flatten() {
                side.add_wrench(&w6, &mut self.rhs_s[6 * side.block..6 * side.block + 6]);
            }
        }
        let nk = sh.budget_vars.len();
        let mut rt_sigma = [0.0f64; 2];
        for kb in 0..nk {
            let i = np * mp + kb;
            // G row of σ is −1.
            rt_sigma[kb] = rx[np * C + kb] - rg[i] * sc.dinv[i];
            self.rhs_s[6 * nb + kb] += self.hinv_sigma[kb] * rt_sigma[kb];
        }
        self.solve_s(ze);
        // λ (module docs): r̃x_λ = rx_λ − rg_λ Hs⁻¹ (its G row is −1); y = S⁻¹ r is in z_E.
        if let (Some((column, _)), Some((h, w, lw))) = (sh.factor, &self.factor) {
            let i = np * mp + nk;
            let rt = rx[sh.lambda()] - rg[i] * sc.dinv[i];
            let ly: f64 = column.iter().zip(ze.iter()).map(|(l, z)| l * z).sum();
            let xl = (rt - ly) / (lw + h);
            ze.iter_mut().zip(w).for_each(|(z, w)| *z += w * xl);
            x[sh.lambda()] = xl;
            zg[i] = (-xl - rg[i]) * sc.dinv[i];
        }
        // x = H⁻¹ (r̃x − Eᵀ z_E), z_G = Hs⁻¹ (G x − r_G).
        for contact in sh.contacts {
            let mut u = [0.0f64; 6];
            for side in contact.sides.iter().flatten() {
                side.add_seen(&ze[6 * side.block..6 * side.block + 6], &mut u);
            }
            for p in contact.points.clone() {
                let mut t = point_motion(sh, &u, &sh.rho[p]);
                for (kb, &col) in sh.budget_vars.iter().enumerate() {
                    t[col] += ze[6 * nb + kb];
                }
                let mut r = self.rt[p];
                for k in 0..C {
                    r[k] -= t[k];
                }
                let xp = chol_solve(&self.chol[p], &r);
                x[p * C..(p + 1) * C].copy_from_slice(&xp);
                let rgp = &rg[p * mp..(p + 1) * mp];
                let dinv = &sc.dinv[p * mp..p * mp + nn];
                let zgp = &mut zg[p * mp..(p + 1) * mp];
                for (r, g) in sh.nonneg.iter().enumerate() {
                    let mut gx = 0.0;
                    for k in 0..C {
                        gx += g[k] * xp[k];
                    }
                    zgp[r] = (gx - rgp[r]) * dinv[r];
                }
                if let Some(soc) = &sh.soc {
                    let mut gx = [0.0; 3];
                    for i in 0..3 {
                        let mut s = -rgp[nn + i];
                        for k in 0..C {
                            s += soc[i][k] * xp[k];
                        }
                        gx[i] = s;
                    }
                    zgp[nn..nn + 3].copy_from_slice(&sc.hs_inv_mul(p, &gx));
                }
            }
        }
        for kb in 0..nk {
            let i = np * mp + kb;
            let xs = self.hinv_sigma[kb] * (rt_sigma[kb] - ze[6 * nb + kb]);
            x[np * C + kb] = xs;
            zg[i] = (-xs - rg[i]) * sc.dinv[i];
        }
    }

    /// Solves K [x; z_E; z_G] = [rx; r_E; r_G]; with `refine`, iterative refinement against
    /// the unregularised matrix (clarabel's defaults: relative 1e-13, absolute 1e-12, ≤ 10
    /// steps, stop when a step gains less than 5×). False when the result is not finite.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        sh: &Shape<C>,
        sc: &Scaling,
        rx: &[f64],
        re: &[f64],
        rg: &[f64],
        x: &mut [f64],
        ze: &mut [f64],
        zg: &mut [f64],
        refine: bool,
    ) -> bool {
        self.solve_reg(sh, sc, rx, re, rg, x, ze, zg);
        if refine {
            let norm_b = rx.iter().chain(re).chain(rg).fold(0.0f64, |a, v| a.max(v.abs()));
            let [mut ex, mut ee, mut eg, mut dx, mut de, mut dg] = std::mem::take(&mut self.work);
            // e = rhs − K [x; z].
            let error = |ex: &mut [f64], ee: &mut [f64], eg: &mut [f64], x: &[f64], ze: &[f64], zg: &[f64]| -> f64 {
                sh.apply(sc, x, ze, zg, ex, ee, eg);
                let mut e = 0.0f64;
                for (k, r) in ex.iter_mut().zip(rx).chain(ee.iter_mut().zip(re)).chain(eg.iter_mut().zip(rg)) {
                    *k = r - *k;
                    e = e.max(k.abs());
                }
                e
            };
            let mut norm_e = error(&mut ex, &mut ee, &mut eg, x, ze, zg);
            for _ in 0..10 {
                if norm_e <= 1e-12 + 1e-13 * norm_b {
                    break;
                }
                self.solve_reg(sh, sc, &ex, &ee, &eg, &mut dx, &mut de, &mut dg);
                // Candidate x + dx into dx (and so on).
                for (d, v) in dx.iter_mut().zip(x.iter()) {
                    *d += v;
                }
                for (d, v) in de.iter_mut().zip(ze.iter()) {
                    *d += v;
                }
                for (d, v) in dg.iter_mut().zip(zg.iter()) {
                    *d += v;
                }
                let new_e = error(&mut ex, &mut ee, &mut eg, &dx, &de, &dg);
                if new_e < norm_e {
                    x.copy_from_slice(&dx);
                    ze.copy_from_slice(&de);
                    zg.copy_from_slice(&dg);
                }
                if new_e * 5.0 > norm_e {
                    break;
                }
                norm_e = new_e;
            }
            self.work = [ex, ee, eg, dx, de, dg];
        }
        x.iter().chain(ze.iter()).chain(zg.iter()).all(|v| v.is_finite())
    }
}
