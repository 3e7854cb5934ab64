//! A [`ContactProblem`] in the fixed-size form the kernels use (C variables per point), and
//! the products with its constraint matrix A = [E; G].
//!
//! Vector layouts: x = [the points' variables (point-major), one σ per budget, the load factor
//! λ if any, the block columns y]; the equality rows [6 per block, one per budget]; the
//! inequality rows [each point's rows (non-negative first, then its second-order cone), one
//! `−σ ≤ 0` per budget, `−λ ≤ 0`, per bounded block column `−y ≤ −lo` and `y ≤ hi`]. λ's column
//! is the live load in the block rows, a block column's its entries in its block's rows. The
//! inequality rows' right-hand side is zero but for the block columns' bounds and the points'
//! own (`point_b`: the exact-contact engine's friction capacities).

use super::cones::Scaling;
use super::iterate::{Rhs, Step, dot, norm_inf};
use crate::statics::problem::{BlockColumn, Contact, ContactProblem, wrench};

pub struct Shape<'a, const C: usize> {
    pub blocks: usize,
    pub contacts: &'a [Contact],
    pub rho: &'a [[f64; 3]],
    /// Shared rows of every point: non-negative rows, then an optional second-order cone.
    pub nonneg: Vec<[f64; C]>,
    pub soc: Option<[[f64; C]; 3]>,
    /// N: variables → local force (n, u, v).
    pub fmap: [[f64; C]; 3],
    pub p: [f64; C],
    pub q: [f64; C],
    /// Per point its own linear costs, when not all `q` (np × C).
    pub q_points: Option<&'a [f64]>,
    /// Per point the right-hand side of its rows, when not all zero (np × m_p).
    pub b_points: Option<&'a [f64]>,
    /// Column (within a point) of each budget's variable.
    pub budget_vars: Vec<usize>,
    /// Inequality rows per point.
    pub m_p: usize,
    /// Right-hand side of the equality rows (block rows, then the budgets' limits).
    pub b_e: Vec<f64>,
    /// The load factor's column in the block rows and its cost.
    pub factor: Option<(&'a [f64], f64)>,
    pub columns: &'a [BlockColumn],
    /// The inequality row of each block column's lower bound (its upper bound's is the next).
    pub column_rows: Vec<Option<usize>>,
    /// Right-hand side of the tail's inequality rows (from [`Self::tail_row0`]).
    pub b_tail: Vec<f64>,
    /// The point where the points' kernels cut their work in two, one half on each of two
    /// threads ([`split_point`]); `None`: one thread.
    pub split: Option<usize>,
}

/// From this many points on, the split pays (docs/benchmarks.md: the Armadillo's 4 819
/// points −13 %, the dome's 7 936 −10 %; the cross vault's step problems of fewer gain ~5 %
/// for a second core's time).
const SPLIT_FROM_POINTS: usize = 2048;

/// Where to cut `points` in two for `threads` threads: at a multiple of four (the kernels'
/// batches), so that each point is computed by the same batch either way. Not with budget
/// variables, whose rows sum over all points in point order.
pub(super) fn split_point(points: usize, threads: usize, budgets: usize) -> Option<usize> {
    (threads > 1 && budgets == 0 && points >= SPLIT_FROM_POINTS).then_some(points / 8 * 4)
}

fn fixed<const C: usize>(v: &[f64]) -> [f64; C] {
    let mut out = [0.0; C];
    out.copy_from_slice(v);
    out
}

impl<'a, const C: usize> Shape<'a, C> {
    pub fn new(cp: &'a ContactProblem<'a>) -> Option<Self> {
        if cp.per_point() != C {
            return None;
        }
        let g = cp.geometry;
        let rows = cp.point_rows();
        let fm = cp.force_map();
        let budget_vars = cp.budgets.iter().map(|b| cp.index(b.var)).collect::<Option<Vec<_>>>()?;
        // A free λ has no barrier to keep beside S: clarabel takes it.
        if cp.factor.as_ref().is_some_and(|f| !f.bounded) {
            return None;
        }
        if budget_vars.len() > 2 {
            return None;
        }
        // The crushing rows have a right-hand side and cones across a whole interface: clarabel.
        if cp.crushing.is_some() {
            return None;
        }
        let m_p = rows.count();
        if !(cp.point_q.is_empty() || cp.point_q.len() == g.points() * C)
            || !(cp.point_b.is_empty() || cp.point_b.len() == g.points() * m_p)
        {
            return None;
        }
        let mut b_e = g.rhs.clone();
        b_e.extend(cp.budgets.iter().map(|b| b.limit));
        let mut b_tail = vec![0.0; budget_vars.len() + usize::from(cp.factor.is_some())];
        let row0 = g.points() * m_p;
        let mut column_rows = Vec::with_capacity(cp.columns.len());
        for c in &cp.columns {
            column_rows.push(c.bounds.map(|_| row0 + b_tail.len()));
            b_tail.extend(c.bounds.iter().flat_map(|&(lo, hi)| [-lo, hi]));
        }
        Some(Self {
            blocks: g.blocks,
            contacts: &g.contacts,
            rho: &g.rho,
            nonneg: rows.nonneg.iter().map(|r| fixed(r)).collect(),
            soc: rows.soc.as_ref().map(|s| [fixed(&s[0]), fixed(&s[1]), fixed(&s[2])]),
            fmap: [fixed(&fm[0]), fixed(&fm[1]), fixed(&fm[2])],
            p: fixed(&cp.p),
            q: fixed(&cp.q),
            q_points: (!cp.point_q.is_empty()).then_some(cp.point_q.as_slice()),
            b_points: (!cp.point_b.is_empty()).then_some(cp.point_b.as_slice()),
            budget_vars,
            m_p,
            b_e,
            factor: cp.factor.as_ref().map(|f| (f.column.as_slice(), f.cost)),
            columns: &cp.columns,
            column_rows,
            b_tail,
            split: split_point(g.points(), cp.threads, cp.budgets.len()),
        })
    }

    pub fn points(&self) -> usize {
        self.rho.len()
    }

    pub fn budgets(&self) -> usize {
        self.budget_vars.len()
    }

    /// The scalar variables after the points': the budgets' slacks, λ, the block columns.
    pub fn tail(&self) -> usize {
        self.budgets() + self.factor.is_some() as usize + self.columns.len()
    }

    /// The inequality rows after the points': one per slack and λ, two per bounded column.
    pub fn tail_rows(&self) -> usize {
        self.b_tail.len()
    }

    /// The first of them.
    pub fn tail_row0(&self) -> usize {
        self.points() * self.m_p
    }

    pub fn n(&self) -> usize {
        self.points() * C + self.tail()
    }

    /// Index of λ in x (and, less the points' variables, of its row in the inequality rows).
    pub fn lambda(&self) -> usize {
        self.points() * C + self.budgets()
    }

    /// Index of the first block column in x.
    pub fn column0(&self) -> usize {
        self.lambda() + self.factor.is_some() as usize
    }

    /// Whether P has any non-zero entry.
    pub fn quadratic(&self) -> bool {
        self.p.iter().any(|p| *p != 0.0) || self.columns.iter().any(|c| c.p != 0.0)
    }

    /// The linear cost of variable `j`.
    pub fn q_at(&self, j: usize) -> f64 {
        let np = self.points() * C;
        match (j < np, self.factor) {
            (true, _) => self.q_points.map_or(self.q[j % C], |q| q[j]),
            (false, Some((_, cost))) if j == self.lambda() => cost,
            _ if j >= self.column0() => self.columns[j - self.column0()].cost,
            _ => 0.0,
        }
    }

    /// bᵀz over the equality and inequality rows.
    pub fn b_dot(&self, ze: &[f64], zg: &[f64]) -> f64 {
        let row0 = self.tail_row0();
        let points = self.b_points.map_or(0.0, |b| dot(b, &zg[..row0]));
        dot(&self.b_e, ze) + dot(&self.b_tail, &zg[row0..]) + points
    }

    /// b_G, the inequality rows' right-hand side, into `out`.
    pub fn b_g_into(&self, out: &mut [f64]) {
        let row0 = self.tail_row0();
        match self.b_points {
            Some(b) => out[..row0].copy_from_slice(b),
            None => out[..row0].fill(0.0),
        }
        out[row0..].copy_from_slice(&self.b_tail);
    }

    /// ‖b‖_∞ over both row blocks.
    pub fn norm_b(&self) -> f64 {
        let points = self.b_points.map_or(0.0, norm_inf);
        norm_inf(&self.b_e).max(norm_inf(&self.b_tail)).max(points)
    }

    pub fn m_e(&self) -> usize {
        self.b_e.len()
    }

    pub fn m_g(&self) -> usize {
        self.tail_row0() + self.tail_rows()
    }

    /// `out_e = E x`, `out_g = G x`.
    pub fn a_mul(&self, x: &[f64], out_e: &mut [f64], out_g: &mut [f64]) {
        let mp = self.m_p;
        out_e.iter_mut().for_each(|v| *v = 0.0);
        for contact in self.contacts {
            let mut w6 = [0.0f64; 6];
            for p in contact.points.clone() {
                let xp: [f64; C] = fixed(&x[p * C..(p + 1) * C]);
                self.point_products(p, &xp, &mut w6, out_e, &mut out_g[p * mp..(p + 1) * mp]);
            }
            for side in contact.sides.iter().flatten() {
                side.add_wrench(&w6, &mut out_e[6 * side.block..6 * side.block + 6]);
            }
        }
        self.tail_products(x, out_e, out_g);
    }

    /// The scalar variables' columns of E x and G x (after the points').
    fn tail_products(&self, x: &[f64], out_e: &mut [f64], out_g: &mut [f64]) {
        let (nb, np, mp) = (self.blocks, self.points(), self.m_p);
        for kb in 0..self.budgets() {
            let xs = x[np * C + kb];
            out_e[6 * nb + kb] += xs;
            out_g[np * mp + kb] = -xs;
        }
        if let Some((column, _)) = self.factor {
            let xl = x[self.lambda()];
            out_e.iter_mut().zip(column).for_each(|(e, c)| *e += c * xl);
            out_g[np * mp + self.budgets()] = -xl;
        }
        for (j, (d, row)) in self.columns.iter().zip(&self.column_rows).enumerate() {
            let xr = x[self.column0() + j];
            for k in 0..6 {
                out_e[6 * d.block + k] += d.column[k] * xr;
            }
            if let Some(row) = *row {
                out_g[row] = -xr;
                out_g[row + 1] = xr;
            }
        }
    }

    /// One point's part of E x (its wrench into `w6`, its budget columns into `out_e`) and its
    /// rows of G x into `og`.
    fn point_products(&self, p: usize, xp: &[f64; C], w6: &mut [f64; 6], out_e: &mut [f64], og: &mut [f64]) {
        let (nb, nn) = (self.blocks, self.nonneg.len());
        let mut f = [0.0; 3];
        for (i, fi) in f.iter_mut().enumerate() {
            for k in 0..C {
                *fi += self.fmap[i][k] * xp[k];
            }
        }
        let w = wrench(&self.rho[p], &f);
        for i in 0..6 {
            w6[i] += w[i];
        }
        for (kb, &col) in self.budget_vars.iter().enumerate() {
            out_e[6 * nb + kb] += xp[col];
        }
        for (r, g) in self.nonneg.iter().enumerate() {
            let mut s = 0.0;
            for k in 0..C {
                s += g[k] * xp[k];
            }
            og[r] = s;
        }
        if let Some(soc) = &self.soc {
            for i in 0..3 {
                let mut s = 0.0;
                for k in 0..C {
                    s += soc[i][k] * xp[k];
                }
                og[nn + i] = s;
            }
        }
    }

    /// The scalar variables' rows of Eᵀ z_E + Gᵀ z_G.
    fn tail_transposed(&self, ze: &[f64], zg: &[f64], out: &mut [f64]) {
        let (nb, np, mp) = (self.blocks, self.points(), self.m_p);
        for kb in 0..self.budgets() {
            out[np * C + kb] = ze[6 * nb + kb] - zg[np * mp + kb];
        }
        if let Some((column, _)) = self.factor {
            let lz: f64 = column.iter().zip(ze).map(|(c, z)| c * z).sum();
            out[self.lambda()] = lz - zg[np * mp + self.budgets()];
        }
        for (j, (d, row)) in self.columns.iter().zip(&self.column_rows).enumerate() {
            let cz: f64 = (0..6).map(|k| d.column[k] * ze[6 * d.block + k]).sum();
            out[self.column0() + j] = cz + row.map_or(0.0, |r| zg[r + 1] - zg[r]);
        }
    }

    /// The block columns' part of x.
    fn column_x<'x>(&self, x: &'x [f64]) -> &'x [f64] {
        &x[self.column0()..self.column0() + self.columns.len()]
    }

    /// `P x` (σ and λ have no quadratic term).
    pub fn p_mul(&self, x: &[f64], out: &mut [f64]) {
        let np = self.points();
        for p in 0..np {
            for k in 0..C {
                out[p * C + k] = self.p[k] * x[p * C + k];
            }
        }
        for v in out[np * C..].iter_mut() {
            *v = 0.0;
        }
        let c0 = self.column0();
        for (j, (c, x)) in self.columns.iter().zip(self.column_x(x)).enumerate() {
            out[c0 + j] = c.p * x;
        }
    }

    /// `qᵀ x`.
    pub fn q_dot(&self, x: &[f64]) -> f64 {
        let mut s = 0.0;
        match self.q_points {
            Some(q) => s += dot(q, &x[..q.len()]),
            None => {
                // One sum per variable of a point: C independent chains.
                let mut sums = [0.0f64; C];
                for xp in x[..self.points() * C].chunks_exact(C) {
                    for k in 0..C {
                        sums[k] += self.q[k] * xp[k];
                    }
                }
                s += sums.iter().sum::<f64>();
            }
        }
        if let Some((_, cost)) = self.factor {
            s += cost * x[self.lambda()];
        }
        s + self.columns.iter().zip(self.column_x(x)).map(|(d, x)| d.cost * x).sum::<f64>()
    }

    /// ‖q‖_∞.
    pub fn norm_q(&self) -> f64 {
        let points = self.q_points.map_or_else(|| self.q.iter().fold(0.0f64, |m, v| m.max(v.abs())), norm_inf);
        let costs = self.columns.iter().fold(points, |m, d| m.max(d.cost.abs()));
        self.factor.map_or(costs, |(_, cost)| costs.max(cost.abs()))
    }

    /// `xᵀ P y`.
    pub fn p_quad(&self, x: &[f64], y: &[f64]) -> f64 {
        // One sum per variable of a point: C independent chains.
        let mut sums = [0.0f64; C];
        let np = self.points() * C;
        for (xp, yp) in x[..np].chunks_exact(C).zip(y[..np].chunks_exact(C)) {
            for k in 0..C {
                sums[k] += self.p[k] * xp[k] * yp[k];
            }
        }
        sums.iter().sum::<f64>()
            + self
                .columns
                .iter()
                .zip(self.column_x(x))
                .zip(self.column_x(y))
                .map(|((c, x), y)| c.p * x * y)
                .sum::<f64>()
    }

    /// The scalar variables' part of [`super::points::apply`] (budget slacks, λ, block
    /// columns), after the points'.
    pub fn apply_tail(&self, kkt: Option<&Scaling>, sol: Rhs, out: Step) {
        self.tail_products(sol.x, out.eq, out.ineq);
        if let Some(sc) = kkt {
            let tail = self.tail_row0();
            for i in tail..tail + self.tail_rows() {
                out.ineq[i] -= sc.d[i] * sol.ineq[i];
            }
        }
        self.tail_transposed(sol.eq, sol.ineq, out.x);
        if kkt.is_some() {
            let c0 = self.column0();
            for (j, (c, x)) in self.columns.iter().zip(self.column_x(sol.x)).enumerate() {
                out.x[c0 + j] += c.p * x;
            }
        }
    }
}
