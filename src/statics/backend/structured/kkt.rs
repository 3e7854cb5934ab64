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
//! ([`factor_points`]). S is factorised by 6×6 blocks ([`super::block_cholesky`]) or, for
//! large fronts and budget rows, by faer's sparse Cholesky (ordering and symbolic analysis once
//! per problem). Iterative refinement against the unregularised
//! system removes what ε and round-off leave.
//!
//! A load factor λ ≥ 0 (its column L in the block rows) would add `L H_λ⁻¹ Lᵀ` to S: rank
//! one but dense over the loaded blocks, and H_λ⁻¹ grows without bound as λ's constraint
//! goes inactive. So λ stays an unknown beside S's factor (a bordered system): with
//! y = S⁻¹ r and w = S⁻¹ L (solved once per factorisation), `S z_E − L x_λ = r`,
//! `Lᵀ z_E + H_λ x_λ = r̃x_λ` give `x_λ = (r̃x_λ − Lᵀy) / (Lᵀw + H_λ)`, `z_E = y + w x_λ` —
//! no division by a vanishing H_λ.
//!
//! A block column y_j (its entries c_j in one block's six rows, its weight p_j, two bound rows
//! or none: a density, the engine's momentum residual) is eliminated like a point's variables:
//! H_j = p_j + ε + Σ Hs⁻¹ over its rows, and S's diagonal block of that block gains
//! c_j c_jᵀ / H_j — no new fill.

use super::block_cholesky::{BlockFactor, BlockSymbolic};
use super::cones::Scaling;
pub use super::iterate::{Blocks, Rhs, Step};
use super::iterate::{all_finite, norm_inf};
use super::points::{ApplyWork, PointProducts, apply, back_points, factor_points, reduce_points};
use super::profile::{Kernel, Timer};
use super::shape::Shape;
use crate::statics::problem::{Side as ContactSide, wrench};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use std::sync::Arc;

/// Entries of S's Cholesky factor from which its numeric factorisation and solves run on the
/// threads the problem allows: faer's supernodal kernels on rayon pay only on large supernodes.
const PARALLEL_FROM: usize = 100_000_000;

/// Regularisation of H only, against round-off (its elimination is exact: every variable sits
/// in an inequality row). S gets none: refinement would have to undo a static εI there every
/// solve, and faer's dynamic regularisation already catches a singular S's zero pivots.
const EPS: f64 = 1e-13;

type Mat6 = [[f64; 6]; 6];

/// Iterative refinement's work: the residual of the current solution, and a correction to it.
#[derive(Default)]
struct Refinement {
    residual: Blocks,
    correction: Blocks,
}

/// The load factor's part of the bordered solves (module docs).
struct LoadFactor {
    /// H_λ.
    h: f64,
    /// w = S⁻¹ L.
    w: Vec<f64>,
    /// Lᵀw.
    lw: f64,
}

/// Where a contact's blocks sit in S's values: the start of each column's run of the
/// off-diagonal 6×6 block (rows of the larger block index, columns of the smaller).
#[derive(Clone, Copy)]
struct ContactSlots {
    off: [usize; 6],
}

/// Block updates (432 flops each) up to which S is factored by 6×6 blocks
/// ([`super::block_cholesky`]); beyond, the fill makes dense fronts where faer's supernodal
/// kernels are faster (docs/benchmarks.md).
const BLOCKS_UP_TO: usize = 2_000_000;

/// How S is factored: by 6×6 blocks up to `blocks_up_to` block updates (and without budget
/// rows), else by faer, on the problem's threads from `parallel_from` entries of the factor.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FactorPlan {
    pub blocks_up_to: usize,
    pub parallel_from: usize,
}

impl Default for FactorPlan {
    fn default() -> Self {
        let blocks_up_to = if super::profile::blocks_on() { BLOCKS_UP_TO } else { 0 };
        Self { blocks_up_to, parallel_from: PARALLEL_FROM }
    }
}

/// S's pattern (lower triangle, CSC) and its symbolic factorisation — AMD ordering,
/// elimination tree, supernodes: a function of the contact graph only, so a warm start carries
/// it to the next problem of the same layout (it is most of a solve's set-up).
pub struct Pattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: Symbolic,
}

/// Which factorisation S gets: by 6×6 blocks (no budget rows, few enough updates) or faer's.
enum Symbolic {
    Blocks(BlockSymbolic),
    Faer(SymbolicCholesky<usize>),
}

/// The numeric side of [`Symbolic`]: the factor's values and its work space.
enum Numeric {
    Blocks { factor: BlockFactor, work: Vec<[f64; 6]> },
    Faer { l_values: Vec<f64>, buffer: MemBuffer, par: Par },
}

/// The per-point solves' work space: H_p⁻¹ r̃x per point, and the points' products
/// ([`ApplyWork`]: the right-hand side's wrenches per point, z_E seen per contact).
struct PointWork<const C: usize> {
    w: Vec<[f64; C]>,
    apply: ApplyWork,
}

impl<const C: usize> PointWork<C> {
    fn new(sh: &Shape<C>) -> Self {
        Self { w: vec![[0.0; C]; sh.points()], apply: ApplyWork::new(sh) }
    }
}

pub struct Kkt<const C: usize> {
    /// H_p's Cholesky factor per point (lower, its diagonal inverted: [`factor_points`]).
    chol: Vec<[[f64; C]; C]>,
    /// Y_p = N H_p⁻¹ Nᵀ per point (the local force covariance).
    y: Vec<[[f64; 3]; 3]>,
    /// H_σ⁻¹ per budget slack.
    hinv_sigma: Vec<f64>,
    /// H⁻¹ per block column, and its r̃x in the current solve.
    hinv_col: Vec<f64>,
    rt_col: Vec<f64>,
    /// With a load factor: its part of the bordered solves.
    factor: Option<LoadFactor>,
    slots: Vec<Option<ContactSlots>>,
    m_e: usize,
    /// S's pattern and symbolic factorisation, and its values.
    pattern: Arc<Pattern>,
    values: Vec<f64>,
    /// S's factor (faer's on the problem's threads for a factor of `parallel_from` entries or
    /// more, [`PARALLEL_FROM`] by default).
    numeric: Numeric,
    /// Work: the right-hand side of S, r̃x per point.
    rhs_s: Vec<f64>,
    rt: Vec<[f64; C]>,
    points: PointWork<C>,
    refinement: Refinement,
}

/// L⁻¹ r, `l` a factor from [`factor_points`] (lower, its diagonal inverted).
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

/// L⁻ᵀ y, `l` a factor from [`factor_points`].
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

/// Per block column of S, the larger blocks it shares an interface with, in order: the
/// off-diagonal 6×6 blocks below its diagonal block.
fn pairs_below<const C: usize>(sh: &Shape<C>) -> Vec<Vec<usize>> {
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
    let mut below: Vec<Vec<usize>> = vec![Vec::new(); sh.blocks];
    for &(i, j) in &pairs {
        below[j].push(i);
    }
    below
}

/// S's lower triangle (CSC column pointers and row indices) for `nb` blocks and `nk` budgets:
/// dense 6×6 diagonal blocks, an off-diagonal block per pair in `below`, budget rows against
/// every block and each other.
fn lower_pattern(nb: usize, nk: usize, below: &[Vec<usize>]) -> (Vec<usize>, Vec<usize>) {
    let m_e = 6 * nb + nk;
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
    (col_ptr, row_idx)
}

/// Each contact's [`ContactSlots`] in the pattern of [`lower_pattern`] (`None` for a contact
/// with a support, or within one block).
fn contact_slots<const C: usize>(sh: &Shape<C>, below: &[Vec<usize>], col_ptr: &[usize]) -> Vec<Option<ContactSlots>> {
    sh.contacts
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
        .collect()
}

impl Pattern {
    /// The pattern `col_ptr`, `row_idx` of an `m_e`-row S with its symbolic factorisation:
    /// `reuse`'s when it has the same pattern, else a new analysis — by blocks (`nb` of them,
    /// off-diagonal ones at `below`) when there are no budget rows (`nk`) and few enough
    /// updates, else faer's.
    fn analysed(
        (m_e, nb, nk): (usize, usize, usize),
        blocks_up_to: usize,
        below: &[Vec<usize>],
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        reuse: Option<&Arc<Self>>,
    ) -> Option<Arc<Self>> {
        if let Some(p) = reuse
            && p.col_ptr == col_ptr
            && p.row_idx == row_idx
        {
            return Some(Arc::clone(p));
        }
        if nk == 0
            && blocks_up_to > 0
            && let Some(blocks) = BlockSymbolic::new(nb, below, blocks_up_to)
        {
            return Some(Arc::new(Self { col_ptr, row_idx, symbolic: Symbolic::Blocks(blocks) }));
        }
        let sym = SymbolicSparseColMatRef::new_checked(m_e, m_e, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                // Half faer's flops-per-entry cut: vaults and walls, whose fill makes dense
                // blocks pay, go supernodal; chains such as arches stay simplicial.
                supernodal_flop_ratio_threshold: SupernodalThreshold(0.5),
                ..Default::default()
            },
        )
        .ok()?;
        Some(Arc::new(Self { col_ptr, row_idx, symbolic: Symbolic::Faer(symbolic) }))
    }

    /// Stored entries of S's lower triangle and of its factor, and the flops of one numeric
    /// factorisation: Σ over the factor's columns of their entry count squared.
    pub fn sizes(&self) -> (usize, usize, f64) {
        let symbolic = match &self.symbolic {
            Symbolic::Blocks(b) => return (self.row_idx.len(), 36 * b.storage_blocks(), 432.0 * b.updates() as f64),
            Symbolic::Faer(s) => s,
        };
        let counts: Vec<f64> = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => s.col_ptr().windows(2).map(|w| (w[1] - w[0]) as f64).collect(),
            SymbolicCholeskyRaw::Supernodal(s) => {
                let (begin, end, rows) = (s.supernode_begin(), s.supernode_end(), s.col_ptr_for_row_idx());
                let mut counts = Vec::new();
                for k in 0..s.n_supernodes() {
                    let (width, below) = (end[k] - begin[k], rows[k + 1] - rows[k]);
                    counts.extend((0..width).map(|j| (width - j + below) as f64));
                }
                counts
            }
        };
        (self.row_idx.len(), symbolic.len_val(), counts.iter().map(|c| c * c).sum())
    }
}

impl<const C: usize> Kkt<C> {
    /// The system of `sh`; with `reuse`, its symbolic factorisation when the pattern is the same.
    pub fn new(sh: &Shape<C>, threads: usize, plan: FactorPlan, reuse: Option<&Arc<Pattern>>) -> Option<Self> {
        let nk = sh.budget_vars.len();
        let m_e = 6 * sh.blocks + nk;
        let below = pairs_below(sh);
        let (col_ptr, row_idx) = lower_pattern(sh.blocks, nk, &below);
        let slots = contact_slots(sh, &below, &col_ptr);
        let pattern = Pattern::analysed((m_e, sh.blocks, nk), plan.blocks_up_to, &below, col_ptr, row_idx, reuse)?;
        let numeric = match &pattern.symbolic {
            Symbolic::Blocks(b) => Numeric::Blocks { factor: BlockFactor::new(b), work: Vec::new() },
            Symbolic::Faer(symbolic) => {
                let par = if threads > 1 && symbolic.len_val() >= plan.parallel_from {
                    Par::rayon(threads)
                } else {
                    Par::Seq
                };
                let req = symbolic
                    .factorize_numeric_llt_scratch::<f64>(par, Default::default())
                    .or(symbolic.solve_in_place_scratch::<f64>(1, par));
                Numeric::Faer { l_values: vec![0.0; symbolic.len_val()], buffer: MemBuffer::new(req), par }
            }
        };
        let values = vec![0.0; pattern.row_idx.len()];
        let (n, mg) = (sh.n(), sh.m_g());
        Some(Self {
            chol: vec![[[0.0; C]; C]; sh.points()],
            y: vec![[[0.0; 3]; 3]; sh.points()],
            hinv_sigma: vec![0.0; nk],
            hinv_col: vec![0.0; sh.columns.len()],
            rt_col: vec![0.0; sh.columns.len()],
            factor: None,
            slots,
            m_e,
            values,
            pattern,
            numeric,
            rhs_s: vec![0.0; m_e],
            rt: vec![[0.0; C]; sh.points()],
            points: PointWork::new(sh),
            refinement: Refinement { residual: Blocks::zeros(n, m_e, mg), correction: Blocks::zeros(n, m_e, mg) },
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

    /// Forms S for the scaling `sc` and factors it: per contact, the points' H_p⁻¹ and the
    /// interface's 6×6 wrench matrix K, mapped to its blocks; then the budget rows. `false` when
    /// an H_p or S cannot be factored.
    pub fn factor(&mut self, sh: &Shape<C>, sc: &Scaling) -> bool {
        let form = Timer::start(Kernel::FormS);
        if !factor_points(sh, sc, EPS, &mut self.chol, &mut self.y) {
            return false;
        }
        self.values.iter_mut().for_each(|v| *v = 0.0);
        // The budget rows' own block (at most two budgets), accumulated over all points.
        let mut bb = [[0.0f64; 2]; 2];
        for (ci, contact) in sh.contacts.iter().enumerate() {
            let (k6, v) = self.contact_matrix(sh, contact.points.clone(), &mut bb);
            self.add_contact(sh, ci, &contact.sides, &k6, &v);
        }
        self.add_budgets(sh, sc, &mut bb);
        self.add_columns(sh, sc);
        drop(form);
        let _factor = Timer::start(Kernel::FactorS);
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
        self.factor = Some(LoadFactor { h, w, lw });
        lw.is_finite()
    }

    /// One contact's points summed in the interface frame: the wrench matrix K = Σ_p T_p Y_p
    /// T_pᵀ (6×6, symmetric; Y_p = N H_p⁻¹ Nᵀ from [`factor_points`]), the budget columns'
    /// wrenches `v` and their block `bb`.
    fn contact_matrix(
        &self,
        sh: &Shape<C>,
        points: std::ops::Range<usize>,
        bb: &mut [[f64; 2]; 2],
    ) -> (Mat6, [[f64; 6]; 2]) {
        let mut k6 = [[0.0f64; 6]; 6];
        let mut v = [[0.0f64; 6]; 2];
        for p in points {
            add_point_wrench(&mut k6, &self.y[p], &sh.rho[p]);
            if sh.budget_vars.is_empty() {
                continue;
            }
            let l = self.chol[p];
            let m = [forward(&l, &sh.fmap[0]), forward(&l, &sh.fmap[1]), forward(&l, &sh.fmap[2])];
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
        (k6, v)
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

    /// Each block column's c cᵀ / H into its block's diagonal block (module docs).
    fn add_columns(&mut self, sh: &Shape<C>, sc: &Scaling) {
        for (j, (d, row)) in sh.columns.iter().zip(&sh.column_rows).enumerate() {
            let barrier = row.map_or(0.0, |r| sc.dinv[r] + sc.dinv[r + 1]);
            let hinv = 1.0 / (d.p + EPS + barrier);
            self.hinv_col[j] = hinv;
            let mut m = [[0.0f64; 6]; 6];
            for r in 0..6 {
                for c in 0..=r {
                    m[r][c] = d.column[r] * d.column[c] * hinv;
                }
            }
            self.scatter(d.block, d.block, &m, None);
        }
    }

    /// S's numeric Cholesky on the symbolic analysis made once per problem (dynamic
    /// regularisation only for the zero pivots of a singular S): by blocks, or faer's.
    fn factor_numeric(&mut self) -> bool {
        let (symbolic, numeric) = (&self.pattern.symbolic, &mut self.numeric);
        match (symbolic, numeric) {
            (Symbolic::Blocks(b), Numeric::Blocks { factor, .. }) => b.factor(&self.values, factor),
            (Symbolic::Faer(symbolic), Numeric::Faer { l_values, buffer, par }) => {
                let pattern = &self.pattern;
                let mat = SparseColMatRef::new(
                    SymbolicSparseColMatRef::new_checked(self.m_e, self.m_e, &pattern.col_ptr, None, &pattern.row_idx),
                    &self.values,
                );
                let reg =
                    LltRegularization { dynamic_regularization_delta: 2e-7, dynamic_regularization_epsilon: 1e-13 };
                let stack = MemStack::new(buffer);
                symbolic.factorize_numeric_llt(l_values, mat, Side::Lower, reg, *par, stack, Default::default()).is_ok()
            }
            _ => false,
        }
    }

    /// z_E = S⁻¹ `rhs_s` with the factor.
    fn solve_s(&mut self, ze: &mut [f64]) {
        match (&self.pattern.symbolic, &mut self.numeric) {
            (Symbolic::Blocks(b), Numeric::Blocks { factor, work }) => b.solve(factor, &mut self.rhs_s, work),
            (Symbolic::Faer(symbolic), Numeric::Faer { l_values, buffer, par }) => {
                let llt = LltRef::new(symbolic, l_values);
                let rhs = MatMut::from_column_major_slice_mut(&mut self.rhs_s, self.m_e, 1);
                llt.solve_in_place_with_conj(Conj::No, rhs, *par, MemStack::new(buffer));
            }
            _ => {}
        }
        ze.copy_from_slice(&self.rhs_s);
    }

    /// One solve of the regularised system: `rhs` (r_x, r_E, r_G) → `out` (x, z_E, z_G); with
    /// `products`, the points' rows of the unregularised K times the solution as well
    /// ([`Self::finish_residual`] completes them).
    fn solve_reg(&mut self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs, out: &mut Step, products: Option<&mut Blocks>) {
        let reduce = Timer::start(Kernel::ReduceRhs);
        let rt_sigma = self.reduce_rhs(sh, sc, rhs);
        drop(reduce);
        let triangular = Timer::start(Kernel::TriangularSolve);
        self.solve_s(out.eq);
        self.solve_load_factor(sh, sc, rhs, out);
        drop(triangular);
        let _back = Timer::start(Kernel::BackSubstitute);
        self.back_substitute(sh, sc, rhs, out, products);
        self.budget_slacks(sh, sc, rhs, &rt_sigma, out);
        self.block_columns(sh, sc, rhs, out);
    }

    /// S's right side E H⁻¹ r̃x − r_E into `rhs_s`, with r̃x = r_x + Gᵀ Hs⁻¹ r_G kept per point
    /// in `rt`; returns the budget slacks' r̃x.
    fn reduce_rhs(&mut self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs) -> [f64; 2] {
        let nb = sh.blocks;
        for (o, r) in self.rhs_s.iter_mut().zip(rhs.eq) {
            *o = -r;
        }
        let work = &mut self.points;
        reduce_points(sh, sc, &self.chol, (rhs.x, rhs.ineq), &mut self.rt, &mut work.w, &mut work.apply.wrench);
        for contact in sh.contacts {
            let mut w6 = [0.0f64; 6];
            for p in contact.points.clone() {
                for i in 0..6 {
                    w6[i] += work.apply.wrench[p][i];
                }
                for (kb, &col) in sh.budget_vars.iter().enumerate() {
                    self.rhs_s[6 * nb + kb] += work.w[p][col];
                }
            }
            for side in contact.sides.iter().flatten() {
                side.add_wrench(&w6, &mut self.rhs_s[6 * side.block..6 * side.block + 6]);
            }
        }
        let (np, mp) = (sh.points(), sh.m_p);
        let mut rt_sigma = [0.0f64; 2];
        for kb in 0..sh.budget_vars.len() {
            let i = np * mp + kb;
            // G row of σ is −1.
            rt_sigma[kb] = rhs.x[np * C + kb] - rhs.ineq[i] * sc.dinv[i];
            self.rhs_s[6 * nb + kb] += self.hinv_sigma[kb] * rt_sigma[kb];
        }
        for (j, (d, row)) in sh.columns.iter().zip(&sh.column_rows).enumerate() {
            // Its G rows are −1 (lower bound) and +1 (upper).
            let rx = rhs.x[sh.column0() + j];
            let rt = row.map_or(rx, |r| rx - rhs.ineq[r] * sc.dinv[r] + rhs.ineq[r + 1] * sc.dinv[r + 1]);
            self.rt_col[j] = rt;
            for k in 0..6 {
                self.rhs_s[6 * d.block + k] += d.column[k] * self.hinv_col[j] * rt;
            }
        }
        rt_sigma
    }

    /// λ's bordered solve (module docs), with y = S⁻¹ r already in z_E: x_λ and its z_G, and
    /// z_E += w x_λ. Nothing without a load factor.
    fn solve_load_factor(&self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs, out: &mut Step) {
        let (Some((column, _)), Some(lf)) = (sh.factor, &self.factor) else { return };
        let i = sh.points() * sh.m_p + sh.budget_vars.len();
        // r̃x_λ = rx_λ − rg_λ Hs⁻¹ (its G row is −1).
        let rt = rhs.x[sh.lambda()] - rhs.ineq[i] * sc.dinv[i];
        let ly: f64 = column.iter().zip(out.eq.iter()).map(|(l, z)| l * z).sum();
        let xl = (rt - ly) / (lf.lw + lf.h);
        out.eq.iter_mut().zip(&lf.w).for_each(|(z, w)| *z += w * xl);
        out.x[sh.lambda()] = xl;
        out.ineq[i] = (-xl - rhs.ineq[i]) * sc.dinv[i];
    }

    /// The points' x = H⁻¹ (r̃x − Eᵀ z_E) and z_G = Hs⁻¹ (G x − r_G), from z_E; with
    /// `products`, K's point rows at them ([`PointProducts`]).
    fn back_substitute(
        &mut self,
        sh: &Shape<C>,
        sc: &Scaling,
        rhs: Rhs,
        out: &mut Step,
        products: Option<&mut Blocks>,
    ) {
        let nb = sh.blocks;
        let work = &mut self.points.apply;
        work.see(sh, out.eq);
        let ApplyWork { seen, contact_of, wrench } = work;
        let products = products.map(|into| {
            into.eq.iter_mut().for_each(|v| *v = 0.0);
            PointProducts { ze: &*out.eq, out: into.step(), wrench: wrench.as_mut_slice() }
        });
        let (seen, budgets) = ((seen.as_slice(), contact_of.as_slice()), (&out.eq[6 * nb..], rhs.ineq));
        back_points(sh, sc, &self.chol, &self.rt, seen, budgets, out.x, out.ineq, products);
    }

    /// The budget slacks' x = H_σ⁻¹ (r̃x_σ − z_E) and z_G, `rt_sigma` from [`Self::reduce_rhs`].
    fn budget_slacks(&self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs, rt_sigma: &[f64; 2], out: &mut Step) {
        let (nb, np, mp) = (sh.blocks, sh.points(), sh.m_p);
        for kb in 0..sh.budget_vars.len() {
            let i = np * mp + kb;
            let xs = self.hinv_sigma[kb] * (rt_sigma[kb] - out.eq[6 * nb + kb]);
            out.x[np * C + kb] = xs;
            out.ineq[i] = (-xs - rhs.ineq[i]) * sc.dinv[i];
        }
    }

    /// The block columns' x = H⁻¹ (r̃x − cᵀ z_E) and their bound rows' z_G.
    fn block_columns(&self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs, out: &mut Step) {
        for (j, (d, row)) in sh.columns.iter().zip(&sh.column_rows).enumerate() {
            let ze = &out.eq[6 * d.block..6 * d.block + 6];
            let cz: f64 = (0..6).map(|k| d.column[k] * ze[k]).sum();
            let x = self.hinv_col[j] * (self.rt_col[j] - cz);
            out.x[sh.column0() + j] = x;
            if let Some(r) = *row {
                out.ineq[r] = (-x - rhs.ineq[r]) * sc.dinv[r];
                out.ineq[r + 1] = (x - rhs.ineq[r + 1]) * sc.dinv[r + 1];
            }
        }
    }

    /// Solves K [x; z_E; z_G] = `rhs` into `out`; with `refine`, iterative refinement against
    /// the unregularised matrix. False when the result is not finite.
    pub fn solve(&mut self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs, mut out: Step, refine: bool) -> bool {
        let mut work = std::mem::take(&mut self.refinement);
        self.solve_reg(sh, sc, rhs, &mut out, refine.then_some(&mut work.residual));
        if refine {
            let norm_e = self.finish_residual(sh, sc, rhs, out.view(), &mut work.residual);
            self.refine(sh, sc, rhs, &mut out, &mut work, norm_e);
        }
        self.refinement = work;
        all_finite(out.x) && all_finite(out.eq) && all_finite(out.ineq)
    }

    /// The residual `rhs` − K `sol` from the points' rows [`back_points`] left in `into`: the
    /// contacts' wrenches summed and mapped to their blocks, the scalar variables' rows, the
    /// difference — the sums [`residual_of`] takes, in its order: the same bits.
    fn finish_residual(&self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs, sol: Rhs, into: &mut Blocks) -> f64 {
        let _t = Timer::start(Kernel::RefineResidual);
        self.points.apply.add_wrenches(sh, &mut into.eq);
        sh.apply_tail(Some(sc), sol, into.step());
        difference(rhs, into)
    }

    /// Iterative refinement of `out`, whose residual `norm_e` is in `work.residual`
    /// (clarabel's defaults: relative 1e-13, absolute 1e-12, ≤ 10 steps, stop when a step
    /// gains less than 5×); a correction is kept when it lowers the residual. It is added in
    /// place and taken back off when it does not (rare, and the last step): no copies of the
    /// solution.
    fn refine(&mut self, sh: &Shape<C>, sc: &Scaling, rhs: Rhs, out: &mut Step, work: &mut Refinement, norm_e: f64) {
        let norm_b = norm_inf(rhs.x).max(norm_inf(rhs.eq)).max(norm_inf(rhs.ineq));
        let Refinement { residual, correction } = work;
        let mut norm_e = norm_e;
        let add = |out: &mut [f64], d: &[f64], sign: f64| out.iter_mut().zip(d).for_each(|(o, d)| *o += sign * d);
        for _ in 0..10 {
            if norm_e <= 1e-12 + 1e-13 * norm_b {
                break;
            }
            self.solve_reg(sh, sc, residual.rhs(), &mut correction.step(), None);
            add(out.x, &correction.x, 1.0);
            add(out.eq, &correction.eq, 1.0);
            add(out.ineq, &correction.ineq, 1.0);
            let new_e = residual_of(sh, sc, rhs, out.view(), residual, &mut self.points.apply);
            // Not lower (or NaN): taken back off.
            let kept = new_e < norm_e;
            if !kept {
                add(out.x, &correction.x, -1.0);
                add(out.eq, &correction.eq, -1.0);
                add(out.ineq, &correction.ineq, -1.0);
            }
            if new_e * 5.0 > norm_e {
                break;
            }
            norm_e = new_e;
        }
    }
}

/// The residual `rhs` − K `sol` into `into`; returns its largest magnitude.
fn residual_of<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    rhs: Rhs,
    sol: Rhs,
    into: &mut Blocks,
    work: &mut ApplyWork,
) -> f64 {
    let _t = Timer::start(Kernel::RefineResidual);
    apply(sh, Some(sc), sol, into.step(), work);
    difference(rhs, into)
}

/// `into` = `rhs` − `into`; returns its largest magnitude (separate passes, each vectorised: a
/// maximum does not depend on the order).
fn difference(rhs: Rhs, into: &mut Blocks) -> f64 {
    let subtract_from = |k: &mut [f64], r: &[f64]| {
        k.iter_mut().zip(r).for_each(|(k, r)| *k = r - *k);
        norm_inf(k)
    };
    let e = subtract_from(&mut into.x, rhs.x).max(subtract_from(&mut into.eq, rhs.eq));
    e.max(subtract_from(&mut into.ineq, rhs.ineq))
}
