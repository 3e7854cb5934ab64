//! Each force point's algebra, four points at a time (module docs of the kkt): forming S —
//! H_p = P + εI + G_pᵀ Hs_p⁻¹ G_p, its Cholesky factor and the local force covariance
//! Y_p = N H_p⁻¹ Nᵀ ([`factor_points`]); S's right-hand side ([`reduce_points`]); and the back
//! substitution from z_E ([`back_points`]). With [`Shape::split`], each kernel cuts the
//! points in two at a multiple of four and computes the halves on rayon's two threads: every
//! point in the same batch either way, the same bits.
//!
//! One point's algebra is a C×C Cholesky with C ≤ 5: a chain of square roots and divisions
//! that no vector lane count divides, so one point at a time runs at the latency of that chain
//! (docs/benchmarks.md, the roofline table). Here every step is taken for [`LANES`] points at
//! once (arrays indexed by lane innermost), which the compiler maps onto vector lanes. Each
//! lane computes exactly the scalar expressions of one point, in the same order: the same bits.

use super::cones::Scaling;
use super::iterate::{Rhs, Step};
use super::shape::Shape;
use std::ops::Range;

/// Points per batch.
const LANES: usize = 4;

type Lanes = [f64; LANES];

/// The factors and covariances of a batch.
struct Batch<const C: usize> {
    l: [[Lanes; C]; C],
    y: [[Lanes; 3]; 3],
}

/// For every point: H_p's Cholesky factor into `chol` (lower, its diagonal inverted, as
/// the solves of the kkt take it) and Y_p into `y`; false when an H_p is not numerically positive
/// definite. A factor, not H⁻¹: near the optimum H_p's eigenvalues spread over many decades,
/// where substitution with the factor stays backward stable and the explicit inverse does not.
pub(super) fn factor_points<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    eps: f64,
    chol: &mut [[[f64; C]; C]],
    y: &mut [[[f64; 3]; 3]],
) -> bool {
    let run = |range: Range<usize>, chol: &mut [[[f64; C]; C]], y: &mut [[[f64; 3]; 3]]| {
        factor_range(sh, sc, eps, range, chol, y)
    };
    match sh.split {
        None => run(0..sh.points(), chol, y),
        Some(mid) => {
            let ((c0, c1), (y0, y1)) = (chol.split_at_mut(mid), y.split_at_mut(mid));
            let (a, b) = rayon::join(|| run(0..mid, c0, y0), || run(mid..sh.points(), c1, y1));
            a && b
        }
    }
}

/// [`factor_points`] for the points of `range`; `chol` and `y` start at its first point.
fn factor_range<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    eps: f64,
    range: Range<usize>,
    chol: &mut [[[f64; C]; C]],
    y: &mut [[[f64; 3]; 3]],
) -> bool {
    let lo = range.start;
    batches(range, |points, lanes| {
        let Some(b) = batch(sh, sc, eps, points) else { return false };
        for (q, &p) in points.iter().enumerate().take(lanes) {
            for i in 0..C {
                for j in 0..C {
                    chol[p - lo][i][j] = b.l[i][j][q];
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    y[p - lo][i][j] = b.y[i][j][q];
                }
            }
        }
        true
    })
}

/// One batch: H, its factor, M = L⁻¹Nᵀ and Y = MᵀM.
fn batch<const C: usize>(sh: &Shape<C>, sc: &Scaling, eps: f64, points: &[usize; LANES]) -> Option<Batch<C>> {
    let h = hessians(sh, sc, eps, points);
    let l = cholesky(&h)?;
    let m: [[Lanes; C]; 3] = std::array::from_fn(|i| forward(&l, &std::array::from_fn(|k| [sh.fmap[i][k]; LANES])));
    let mut y = [[[0.0; LANES]; 3]; 3];
    for i in 0..3 {
        for j in 0..=i {
            let mut s = [0.0; LANES];
            for k in 0..C {
                for q in 0..LANES {
                    s[q] += m[i][k][q] * m[j][k][q];
                }
            }
            y[i][j] = s;
            y[j][i] = s;
        }
    }
    Some(Batch { l, y })
}

/// The lower triangles of the batch's H_p.
fn hessians<const C: usize>(sh: &Shape<C>, sc: &Scaling, eps: f64, points: &[usize; LANES]) -> [[Lanes; C]; C] {
    let mp = sh.m_p;
    let mut h = [[[0.0f64; LANES]; C]; C];
    for k in 0..C {
        h[k][k] = [sh.p[k] + eps; LANES];
    }
    for (r, g) in sh.nonneg.iter().enumerate() {
        let w: Lanes = std::array::from_fn(|q| sc.dinv[points[q] * mp + r]);
        for a in 0..C {
            for b in 0..=a {
                for q in 0..LANES {
                    h[a][b][q] += g[a] * w[q] * g[b];
                }
            }
        }
    }
    if let Some(soc) = &sh.soc {
        // Gᵀ Hs⁻¹ G = MᵀM with M = W⁻¹ G: a Gram matrix, positive semidefinite whatever the
        // rounding.
        for (q, &p) in points.iter().enumerate() {
            let mut mm = [[0.0f64; C]; 3];
            for k in 0..C {
                let col = sc.winv_mul(p, &[soc[0][k], soc[1][k], soc[2][k]]);
                for i in 0..3 {
                    mm[i][k] = col[i];
                }
            }
            for a in 0..C {
                for b in 0..=a {
                    h[a][b][q] += mm[0][a] * mm[0][b] + mm[1][a] * mm[1][b] + mm[2][a] * mm[2][b];
                }
            }
        }
    }
    h
}

/// The batch's Cholesky factors (lower, the diagonal stored inverted); `None` when a pivot of
/// any lane is not positive and finite.
fn cholesky<const C: usize>(h: &[[Lanes; C]; C]) -> Option<[[Lanes; C]; C]> {
    let mut l = [[[0.0f64; LANES]; C]; C];
    for j in 0..C {
        let mut d = h[j][j];
        for k in 0..j {
            for q in 0..LANES {
                d[q] -= l[j][k][q] * l[j][k][q];
            }
        }
        if d.iter().any(|d| *d <= 0.0 || !d.is_finite()) {
            return None;
        }
        let dinv: Lanes = std::array::from_fn(|q| 1.0 / d[q].sqrt());
        l[j][j] = dinv;
        for i in j + 1..C {
            let mut v = h[i][j];
            for k in 0..j {
                for q in 0..LANES {
                    v[q] -= l[i][k][q] * l[j][k][q];
                }
            }
            for q in 0..LANES {
                l[i][j][q] = v[q] * dinv[q];
            }
        }
    }
    Some(l)
}

/// L⁻¹ r for each lane's factor and right-hand side.
fn forward<const C: usize>(l: &[[Lanes; C]; C], r: &[Lanes; C]) -> [Lanes; C] {
    let mut y = [[0.0; LANES]; C];
    for i in 0..C {
        let mut v = r[i];
        for k in 0..i {
            for q in 0..LANES {
                v[q] -= l[i][k][q] * y[k][q];
            }
        }
        for q in 0..LANES {
            y[i][q] = v[q] * l[i][i][q];
        }
    }
    y
}

/// L⁻ᵀ y for each lane's factor and right-hand side.
fn backward<const C: usize>(l: &[[Lanes; C]; C], y: &[Lanes; C]) -> [Lanes; C] {
    let mut x = [[0.0; LANES]; C];
    for i in (0..C).rev() {
        let mut v = y[i];
        for k in i + 1..C {
            for q in 0..LANES {
                v[q] -= l[k][i][q] * x[k][q];
            }
        }
        for q in 0..LANES {
            x[i][q] = v[q] * l[i][i][q];
        }
    }
    x
}

/// Calls `f(points, lanes)` for each batch of the points of `range` (its start a multiple of
/// [`LANES`]): a short last batch repeats its last point in the spare lanes, whose results the
/// caller drops. Stops at the first `false`.
fn batches(range: Range<usize>, mut f: impl FnMut(&[usize; LANES], usize) -> bool) -> bool {
    let (mut p0, np) = (range.start, range.end);
    while p0 < np {
        let lanes = LANES.min(np - p0);
        let points: [usize; LANES] = std::array::from_fn(|l| p0 + l.min(lanes - 1));
        if !f(&points, lanes) {
            return false;
        }
        p0 += LANES;
    }
    true
}

/// The batch's factors from the per-point store, lanes innermost.
fn load_factors<const C: usize>(chol: &[[[f64; C]; C]], points: &[usize; LANES]) -> [[Lanes; C]; C] {
    std::array::from_fn(|i| std::array::from_fn(|j| std::array::from_fn(|q| chol[points[q]][i][j])))
}

/// The right-hand side of S, its per-point part: for every point r̃x = r_x + G_pᵀ Hs_p⁻¹ r_G
/// into `rt`, w = H_p⁻¹ r̃x into `w` and w's wrench [N w; ρ × N w] into `wr`.
#[allow(clippy::too_many_arguments)]
pub(super) fn reduce_points<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    chol: &[[[f64; C]; C]],
    (rx, rg): (&[f64], &[f64]),
    rt: &mut [[f64; C]],
    w: &mut [[f64; C]],
    wr: &mut [[f64; 6]],
) {
    let run = |range: Range<usize>, rt: &mut [[f64; C]], w: &mut [[f64; C]], wr: &mut [[f64; 6]]| {
        reduce_range(sh, sc, chol, (rx, rg), range, rt, w, wr)
    };
    match sh.split {
        None => run(0..sh.points(), rt, w, wr),
        Some(mid) => {
            let ((rt0, rt1), (w0, w1), (wr0, wr1)) = (rt.split_at_mut(mid), w.split_at_mut(mid), wr.split_at_mut(mid));
            rayon::join(|| run(0..mid, rt0, w0, wr0), || run(mid..sh.points(), rt1, w1, wr1));
        }
    }
}

/// [`reduce_points`] for the points of `range`; `rt`, `w` and `wr` start at its first point.
#[allow(clippy::too_many_arguments)]
fn reduce_range<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    chol: &[[[f64; C]; C]],
    (rx, rg): (&[f64], &[f64]),
    range: Range<usize>,
    rt: &mut [[f64; C]],
    w: &mut [[f64; C]],
    wr: &mut [[f64; 6]],
) {
    let lo = range.start;
    batches(range, |points, lanes| {
        let l = load_factors(chol, points);
        let r = point_rhs(sh, sc, rx, rg, points);
        let x = backward(&l, &forward(&l, &r));
        let mut f = [[0.0f64; LANES]; 3];
        for i in 0..3 {
            for k in 0..C {
                for q in 0..LANES {
                    f[i][q] += sh.fmap[i][k] * x[k][q];
                }
            }
        }
        let rho: [[f64; 3]; LANES] = std::array::from_fn(|q| sh.rho[points[q]]);
        for q in 0..lanes {
            let p = points[q] - lo;
            let (f, rho) = ([f[0][q], f[1][q], f[2][q]], &rho[q]);
            wr[p] = [
                f[0],
                f[1],
                f[2],
                rho[1] * f[2] - rho[2] * f[1],
                rho[2] * f[0] - rho[0] * f[2],
                rho[0] * f[1] - rho[1] * f[0],
            ];
            for k in 0..C {
                rt[p][k] = r[k][q];
                w[p][k] = x[k][q];
            }
        }
        true
    });
}

/// r̃x = r_x + G_pᵀ Hs_p⁻¹ r_G of the batch's points.
fn point_rhs<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    rx: &[f64],
    rg: &[f64],
    points: &[usize; LANES],
) -> [Lanes; C] {
    let (mp, nn) = (sh.m_p, sh.nonneg.len());
    let mut rt: [Lanes; C] = std::array::from_fn(|k| std::array::from_fn(|q| rx[points[q] * C + k]));
    for (r, g) in sh.nonneg.iter().enumerate() {
        let f: Lanes = std::array::from_fn(|q| {
            let i = points[q] * mp + r;
            rg[i] * sc.dinv[i]
        });
        for k in 0..C {
            for q in 0..LANES {
                rt[k][q] += g[k] * f[q];
            }
        }
    }
    if let Some(soc) = &sh.soc {
        for (q, &p) in points.iter().enumerate() {
            let at = p * mp + nn;
            let f = sc.hs_inv_mul(p, &[rg[at], rg[at + 1], rg[at + 2]]);
            for i in 0..3 {
                for k in 0..C {
                    rt[k][q] += soc[i][k] * f[i];
                }
            }
        }
    }
    rt
}

/// The work of [`apply`]: each contact's block rows of z_E seen in its frame, each point's
/// contact, and each point's wrench of E x (summed per contact afterwards, in the order one
/// contact's points are taken one by one).
pub(super) struct ApplyWork {
    pub seen: Vec<[f64; 6]>,
    pub contact_of: Vec<u32>,
    pub wrench: Vec<[f64; 6]>,
}

impl ApplyWork {
    pub fn new<const C: usize>(sh: &Shape<C>) -> Self {
        let np = sh.points();
        let mut contact_of = vec![0u32; np];
        for (ci, contact) in sh.contacts.iter().enumerate() {
            contact_of[contact.points.clone()].fill(ci as u32);
        }
        Self { seen: vec![[0.0; 6]; sh.contacts.len()], contact_of, wrench: vec![[0.0; 6]; np] }
    }

    /// Each contact's block rows of `ze` seen in its frame.
    pub fn see<const C: usize>(&mut self, sh: &Shape<C>, ze: &[f64]) {
        for (u, contact) in self.seen.iter_mut().zip(sh.contacts) {
            *u = [0.0f64; 6];
            for side in contact.sides.iter().flatten() {
                side.add_seen(&ze[6 * side.block..6 * side.block + 6], u);
            }
        }
    }

    /// The points' wrenches summed per contact and mapped onto its blocks' rows of `out_e`.
    pub fn add_wrenches<const C: usize>(&self, sh: &Shape<C>, out_e: &mut [f64]) {
        for contact in sh.contacts {
            let mut w6 = [0.0f64; 6];
            for w in &self.wrench[contact.points.clone()] {
                for i in 0..6 {
                    w6[i] += w[i];
                }
            }
            for side in contact.sides.iter().flatten() {
                side.add_wrench(&w6, &mut out_e[6 * side.block..6 * side.block + 6]);
            }
        }
    }
}

/// The unregularised KKT matrix times `sol` = [x; z_E; z_G] (module docs of the kkt) into
/// `out`: E x, G x − Hs z_G and Eᵀz_E + Gᵀz_G + P x with the scaling `kkt` (refinement's
/// residual), or the constraint products E x, G x and Eᵀz_E + Gᵀz_G without (the measures) —
/// in one sweep over the points, four at a time. Each lane takes one point's expressions in the
/// order separate passes would (G x, then − Hs z per row; Eᵀz_E + Gᵀz_G, then + P x) and
/// the contacts' sums run in point order: the same bits as one point at a time.
pub(super) fn apply<const C: usize>(sh: &Shape<C>, kkt: Option<&Scaling>, sol: Rhs, out: Step, work: &mut ApplyWork) {
    out.eq.iter_mut().for_each(|v| *v = 0.0);
    work.see(sh, sol.eq);
    let ApplyWork { seen, contact_of, wrench } = work;
    let (np, mp) = (sh.points(), sh.m_p);
    let seen = (seen.as_slice(), contact_of.as_slice());
    let run = |range: Range<usize>, mut rows: Rows| {
        let (cx, cg) = (range.start * C, range.start * mp);
        let sol = Rhs { x: &sol.x[cx..], eq: sol.eq, ineq: &sol.ineq[cg..] };
        batches(range, |points, lanes| {
            apply_batch(sh, kkt, (points, lanes), seen, sol, &mut rows);
            true
        });
    };
    let rows = Rows::of(sh, Step { x: &mut *out.x, eq: &mut *out.eq, ineq: &mut *out.ineq }, wrench);
    match sh.split {
        None => run(0..np, rows),
        Some(mid) => {
            let (r0, r1) = rows.halves::<C>(mid, mp);
            rayon::join(|| run(0..mid, r0), || run(mid..np, r1));
        }
    }
    work.add_wrenches(sh, out.eq);
    sh.apply_tail(kkt, sol, out);
}

/// Where [`apply_batch`] writes the points of a range from `lo` on: their rows of x and of the
/// inequalities and their wrenches (each slice from point `lo`), and the budget rows of the
/// equalities (summed over the points: a range with budgets is all of them).
struct Rows<'a> {
    lo: usize,
    x: &'a mut [f64],
    ineq: &'a mut [f64],
    wrench: &'a mut [[f64; 6]],
    budgets: &'a mut [f64],
}

impl<'a> Rows<'a> {
    /// All the points' rows of `out` and their wrenches.
    fn of<const C: usize>(sh: &Shape<C>, out: Step<'a>, wrench: &'a mut [[f64; 6]]) -> Self {
        let Step { x, eq, ineq } = out;
        Rows { lo: 0, x, ineq, wrench, budgets: &mut eq[6 * sh.blocks..] }
    }

    /// These rows (all the points') cut at point `mid`, `mp` inequality rows per point; a
    /// problem is only cut without budget rows ([`Shape::split`]).
    fn halves<const C: usize>(self, mid: usize, mp: usize) -> (Rows<'a>, Rows<'a>) {
        let (x0, x1) = self.x.split_at_mut(mid * C);
        let (g0, g1) = self.ineq.split_at_mut(mid * mp);
        let (w0, w1) = self.wrench.split_at_mut(mid);
        (
            Rows { lo: 0, x: x0, ineq: g0, wrench: w0, budgets: &mut [] },
            Rows { lo: mid, x: x1, ineq: g1, wrench: w1, budgets: &mut [] },
        )
    }
}

/// The batch's part of [`apply`]: its rows of x and of the inequalities, its wrenches, its
/// budget columns added; `sol.x` and `sol.ineq` start at point `out.lo`.
#[inline]
fn apply_batch<const C: usize>(
    sh: &Shape<C>,
    kkt: Option<&Scaling>,
    (points, lanes): (&[usize; LANES], usize),
    (seen, contact_of): (&[[f64; 6]], &[u32]),
    sol: Rhs,
    out: &mut Rows,
) {
    let (nb, lo) = (sh.blocks, out.lo);
    let xp: [Lanes; C] = std::array::from_fn(|k| std::array::from_fn(|q| sol.x[(points[q] - lo) * C + k]));
    let mut f = [[0.0f64; LANES]; 3];
    for i in 0..3 {
        for k in 0..C {
            for q in 0..LANES {
                f[i][q] += sh.fmap[i][k] * xp[k][q];
            }
        }
    }
    for q in 0..lanes {
        let p = points[q];
        out.wrench[p - lo] = crate::statics::problem::wrench(&sh.rho[p], &[f[0][q], f[1][q], f[2][q]]);
        for (kb, &col) in sh.budget_vars.iter().enumerate() {
            out.budgets[kb] += xp[col][q];
        }
    }
    row_products(sh, kkt, (points, lanes, lo), &xp, sol.ineq, out.ineq);
    let mut t = point_motions(sh, seen, contact_of, &sol.eq[6 * nb..], points);
    transposed_rows(sh, (points, lo), sol.ineq, &mut t);
    if kkt.is_some() {
        for k in 0..C {
            for q in 0..LANES {
                t[k][q] += sh.p[k] * xp[k][q];
            }
        }
    }
    for q in 0..lanes {
        for k in 0..C {
            out.x[(points[q] - lo) * C + k] = t[k][q];
        }
    }
}

/// The batch's G_p x_p, less Hs_p z_G with `kkt`, into its rows of `og`.
/// `zg` and `og` start at point `lo`.
fn row_products<const C: usize>(
    sh: &Shape<C>,
    kkt: Option<&Scaling>,
    (points, lanes, lo): (&[usize; LANES], usize, usize),
    xp: &[Lanes; C],
    zg: &[f64],
    og: &mut [f64],
) {
    let (mp, nn) = (sh.m_p, sh.nonneg.len());
    let off = lo * mp;
    for (r, g) in sh.nonneg.iter().enumerate() {
        let mut s = [0.0f64; LANES];
        for k in 0..C {
            for q in 0..LANES {
                s[q] += g[k] * xp[k][q];
            }
        }
        if let Some(sc) = kkt {
            for q in 0..LANES {
                let i = points[q] * mp + r;
                s[q] -= sc.d[i] * zg[i - off];
            }
        }
        for q in 0..lanes {
            og[points[q] * mp + r - off] = s[q];
        }
    }
    if let Some(soc) = &sh.soc {
        for q in 0..lanes {
            let at = points[q] * mp + nn - off;
            for i in 0..3 {
                let mut s = 0.0;
                for k in 0..C {
                    s += soc[i][k] * xp[k][q];
                }
                og[at + i] = s;
            }
            if let Some(sc) = kkt {
                let hz = sc.hs_mul(points[q], &[zg[at], zg[at + 1], zg[at + 2]]);
                for i in 0..3 {
                    og[at + i] -= hz[i];
                }
            }
        }
    }
}

/// Gᵀ z_G of the batch's points added to `t`; `zg` starts at point `lo`.
fn transposed_rows<const C: usize>(
    sh: &Shape<C>,
    (points, lo): (&[usize; LANES], usize),
    zg: &[f64],
    t: &mut [Lanes; C],
) {
    let (mp, nn) = (sh.m_p, sh.nonneg.len());
    let off = lo * mp;
    for (r, g) in sh.nonneg.iter().enumerate() {
        let zr: Lanes = std::array::from_fn(|q| zg[points[q] * mp + r - off]);
        for k in 0..C {
            for q in 0..LANES {
                t[k][q] += g[k] * zr[q];
            }
        }
    }
    if let Some(soc) = &sh.soc {
        for i in 0..3 {
            let zr: Lanes = std::array::from_fn(|q| zg[points[q] * mp + nn + i - off]);
            for k in 0..C {
                for q in 0..LANES {
                    t[k][q] += soc[i][k] * zr[q];
                }
            }
        }
    }
}

/// Where [`back_points`] also writes, at the solution it forms, K's rows of each point
/// ([`apply`] with the scaling: iterative refinement's residual without a second sweep over
/// the points): `ze` the solution's z_E, `out` K's rows, `wrench` each point's wrench of E x.
pub(super) struct PointProducts<'a> {
    pub ze: &'a [f64],
    pub out: Step<'a>,
    pub wrench: &'a mut [[f64; 6]],
}

/// The points' part of the back substitution, from z_E: for every point x_p = H_p⁻¹ (r̃x −
/// Nᵀ(u + u×ρ) − budgets) into `x` and z_G = Hs_p⁻¹ (G_p x_p − r_G) into `zg`; `u` is each
/// contact's block rows of z_E seen in its frame, `contact_of` each point's contact, `budgets`
/// the budget rows of z_E. With `products`, K's point rows at (x, z_E, z_G) as well.
#[allow(clippy::too_many_arguments)]
pub(super) fn back_points<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    chol: &[[[f64; C]; C]],
    rt: &[[f64; C]],
    seen: (&[[f64; 6]], &[u32]),
    (budgets, rg): (&[f64], &[f64]),
    x: &mut [f64],
    zg: &mut [f64],
    products: Option<PointProducts>,
) {
    let (np, mp) = (sh.points(), sh.m_p);
    let run = |range: Range<usize>, x: &mut [f64], zg: &mut [f64], products: Option<(&[f64], Rows)>| {
        back_range(sh, sc, (chol, rt), seen, (budgets, rg), range, (x, zg), products)
    };
    let products = products.map(|pr| (pr.ze, Rows::of(sh, pr.out, pr.wrench)));
    let Some(mid) = sh.split else {
        return run(0..np, x, zg, products);
    };
    let (x0, x1) = x.split_at_mut(mid * C);
    let (z0, z1) = zg.split_at_mut(mid * mp);
    let (p0, p1) = match products {
        None => (None, None),
        Some((ze, rows)) => {
            let (r0, r1) = rows.halves::<C>(mid, mp);
            (Some((ze, r0)), Some((ze, r1)))
        }
    };
    rayon::join(|| run(0..mid, x0, z0, p0), || run(mid..np, x1, z1, p1));
}

/// [`back_points`] for the points of `range`; `x` and `zg` start at its first point, and so do
/// the products' rows.
#[allow(clippy::too_many_arguments)]
fn back_range<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    (chol, rt): (&[[[f64; C]; C]], &[[f64; C]]),
    (u, contact_of): (&[[f64; 6]], &[u32]),
    (budgets, rg): (&[f64], &[f64]),
    range: Range<usize>,
    (x, zg): (&mut [f64], &mut [f64]),
    mut products: Option<(&[f64], Rows)>,
) {
    let lo = range.start;
    batches(range, |points, lanes| {
        let l = load_factors(chol, points);
        let mut r: [Lanes; C] = std::array::from_fn(|k| std::array::from_fn(|q| rt[points[q]][k]));
        let t = point_motions(sh, u, contact_of, budgets, points);
        for k in 0..C {
            for q in 0..LANES {
                r[k][q] -= t[k][q];
            }
        }
        let xp = backward(&l, &forward(&l, &r));
        for q in 0..lanes {
            for k in 0..C {
                x[(points[q] - lo) * C + k] = xp[k][q];
            }
        }
        point_duals(sh, sc, rg, (points, lanes, lo), &xp, zg);
        if let Some((ze, rows)) = products.as_mut() {
            let sol = Rhs { x: &*x, eq: ze, ineq: &*zg };
            apply_batch(sh, Some(sc), (points, lanes), (u, contact_of), sol, rows);
        }
        true
    });
}

/// Nᵀ(u + u×ρ) plus the budget rows, what each of the batch's points sees of z_E.
fn point_motions<const C: usize>(
    sh: &Shape<C>,
    u: &[[f64; 6]],
    contact_of: &[u32],
    budgets: &[f64],
    points: &[usize; LANES],
) -> [Lanes; C] {
    let uq: [[f64; 6]; LANES] = std::array::from_fn(|q| u[contact_of[points[q]] as usize]);
    let rho: [[f64; 3]; LANES] = std::array::from_fn(|q| sh.rho[points[q]]);
    let mut g = [[0.0f64; LANES]; 3];
    for q in 0..LANES {
        let (u, rho) = (&uq[q], &rho[q]);
        g[0][q] = u[0] + u[4] * rho[2] - u[5] * rho[1];
        g[1][q] = u[1] + u[5] * rho[0] - u[3] * rho[2];
        g[2][q] = u[2] + u[3] * rho[1] - u[4] * rho[0];
    }
    let mut t = [[0.0f64; LANES]; C];
    for k in 0..C {
        for q in 0..LANES {
            t[k][q] = sh.fmap[0][k] * g[0][q] + sh.fmap[1][k] * g[1][q] + sh.fmap[2][k] * g[2][q];
        }
    }
    for (kb, &col) in sh.budget_vars.iter().enumerate() {
        for q in 0..LANES {
            t[col][q] += budgets[kb];
        }
    }
    t
}

/// z_G = Hs_p⁻¹ (G_p x_p − r_G) of the batch's first `lanes` points into `zg`, which starts
/// at point `lo`.
fn point_duals<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    rg: &[f64],
    (points, lanes, lo): (&[usize; LANES], usize, usize),
    xp: &[Lanes; C],
    zg: &mut [f64],
) {
    let (mp, nn) = (sh.m_p, sh.nonneg.len());
    let off = lo * mp;
    for (r, g) in sh.nonneg.iter().enumerate() {
        let mut gx = [0.0f64; LANES];
        for k in 0..C {
            for q in 0..LANES {
                gx[q] += g[k] * xp[k][q];
            }
        }
        for q in 0..lanes {
            let i = points[q] * mp + r;
            zg[i - off] = (gx[q] - rg[i]) * sc.dinv[i];
        }
    }
    if let Some(soc) = &sh.soc {
        for q in 0..lanes {
            let at = points[q] * mp + nn;
            let mut gx = [0.0; 3];
            for i in 0..3 {
                let mut s = -rg[at + i];
                for k in 0..C {
                    s += soc[i][k] * xp[k][q];
                }
                gx[i] = s;
            }
            zg[at - off..at - off + 3].copy_from_slice(&sc.hs_inv_mul(points[q], &gx));
        }
    }
}

#[cfg(test)]
mod tests {
    //! Invariant: the four-lane kernels give, for every point (the short last batch included),
    //! what the algebra gives one point at a time, written out here with nalgebra: H_p from its
    //! rows (L Lᵀ = H_p), Y_p = N H_p⁻¹ Nᵀ, r̃x and H_p⁻¹ r̃x and its wrench, x_p and z_G of
    //! the back substitution — pyramid8, box4 and the cone, each to 1e-12 of its largest entry
    //! (the 1e-14 holds for the factor; the solves carry H_p's condition number).
    use super::*;
    use crate::interfaces::detect;
    use crate::model::{Assembly, builtin};
    use crate::statics::assemble::{Stage, System, contact_problem};
    use crate::statics::backend::structured::cones::Layout;
    use crate::statics::backend::structured::iterate::Blocks;
    use crate::statics::components::components;
    use crate::statics::problem::{ContactProblem, FrictionModel};
    use crate::statics::settings::StaticsSettings;
    use nalgebra::{DMatrix, DVector};

    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The 3×3 wall's strict QP in `model` as a [`Shape`] with its last point dropped (the
    /// wall's faces have four points each: the last batch is short), handed to `check`.
    fn short_wall<const C: usize>(model: FrictionModel, check: impl FnOnce(Shape<C>, FrictionModel)) {
        wall_problem(model, |cp| {
            let mut sh = Shape::<C>::new(cp).expect("the strict QP's shape");
            let mut contacts = sh.contacts.to_vec();
            contacts.last_mut().expect("contacts").points.end -= 1;
            let rho = &sh.rho[..sh.rho.len() - 1];
            (sh.contacts, sh.rho) = (&contacts, rho);
            check(sh, model);
        });
    }

    /// The 3×3 wall's strict QP in `model`, handed to `f`.
    fn wall_problem<R>(model: FrictionModel, f: impl FnOnce(&ContactProblem) -> R) -> R {
        let asm = Assembly::new(&builtin("wall?courses=3&bricks=3").unwrap(), &Default::default()).unwrap();
        let ifs = detect(&asm);
        let sys = System::new(&asm, &ifs, &components(&asm, &ifs)[0], 0.6, model, false);
        f(&contact_problem(&sys, Stage::Strict, &StaticsSettings::default()))
    }

    /// `$check::<C>` on the short wall of each friction model, C its variables per point.
    macro_rules! on_short_walls {
        ($check:ident) => {
            for model in [FrictionModel::Pyramid8, FrictionModel::Box4, FrictionModel::Cone] {
                match wall_problem(model, |cp| cp.per_point()) {
                    3 => short_wall::<3>(model, $check::<3>),
                    4 => short_wall::<4>(model, $check::<4>),
                    5 => short_wall::<5>(model, $check::<5>),
                    c => panic!("{c} variables per point"),
                }
            }
        };
    }

    /// G_p as a dense (rows × C) matrix.
    fn rows<const C: usize>(sh: &Shape<C>) -> DMatrix<f64> {
        let soc = sh.soc.map(|s| s.to_vec()).unwrap_or_default();
        let all: Vec<[f64; C]> = sh.nonneg.iter().copied().chain(soc).collect();
        DMatrix::from_fn(all.len(), C, |r, k| all[r][k])
    }

    /// Hs_p⁻¹ applied to a vector of point p's rows.
    fn hs_inv<const C: usize>(sh: &Shape<C>, sc: &Scaling, p: usize, v: &DVector<f64>) -> DVector<f64> {
        let (mp, nn) = (sh.m_p, sh.nonneg.len());
        let mut out = DVector::from_fn(v.len(), |r, _| if r < nn { v[r] * sc.dinv[p * mp + r] } else { 0.0 });
        if sh.soc.is_some() {
            let f = sc.hs_inv_mul(p, &[v[nn], v[nn + 1], v[nn + 2]]);
            for i in 0..3 {
                out[nn + i] = f[i];
            }
        }
        out
    }

    /// The scaling at a random interior (s, z): non-negative rows in [0.5, 1.5], cones with
    /// s₀ > |s₁|.
    fn interior_scaling<const C: usize>(sh: &Shape<C>, rng: &mut Lcg) -> Scaling {
        let (np, mp, nn) = (sh.points(), sh.m_p, sh.nonneg.len());
        let layout = Layout { points: np, per_point: mp, nonneg: nn, soc: sh.soc.is_some(), tail: sh.tail_rows() };
        let mut interior =
            |i: usize| if i % mp >= nn && (i % mp - nn) == 0 { 2.0 + rng.next() } else { 0.5 + rng.next() };
        let (s, z): (Vec<f64>, Vec<f64>) = (0..sh.m_g()).map(|i| (interior(i), interior(i))).unzip();
        let mut sc = Scaling::identity(layout);
        assert!(sc.update(&s, &z));
        sc
    }

    fn check<const C: usize>(sh: Shape<C>, model: FrictionModel) {
        let (np, mp) = (sh.points(), sh.m_p);
        assert_ne!(np % LANES, 0, "a short last batch is exercised");
        let mut rng = Lcg(11);
        let sc = interior_scaling(&sh, &mut rng);
        let eps = 1e-13;
        let (mut chol, mut y) = (vec![[[0.0; C]; C]; np], vec![[[0.0; 3]; 3]; np]);
        assert!(factor_points(&sh, &sc, eps, &mut chol, &mut y));
        let rx: Vec<f64> = (0..sh.n()).map(|_| rng.next() - 0.5).collect();
        let rg: Vec<f64> = (0..sh.m_g()).map(|_| rng.next() - 0.5).collect();
        let (mut rt, mut w, mut wr) = (vec![[0.0; C]; np], vec![[0.0; C]; np], vec![[0.0; 6]; np]);
        reduce_points(&sh, &sc, &chol, (&rx, &rg), &mut rt, &mut w, &mut wr);
        let u: Vec<[f64; 6]> = sh.contacts.iter().map(|_| std::array::from_fn(|_| rng.next() - 0.5)).collect();
        let mut contact_of = vec![0u32; np];
        for (ci, c) in sh.contacts.iter().enumerate() {
            contact_of[c.points.clone()].fill(ci as u32);
        }
        let (mut x, mut zg) = (vec![0.0; sh.n()], vec![0.0; sh.m_g()]);
        back_points(&sh, &sc, &chol, &rt, (&u, &contact_of), (&[], &rg), &mut x, &mut zg, None);

        let g = rows(&sh);
        let n = DMatrix::from_fn(3, C, |i, k| sh.fmap[i][k]);
        let close = |a: &[f64], b: &[f64], what: &str, p: usize| {
            let scale = b.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
            let off = a.iter().zip(b).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(off <= 1e-12 * scale, "{model:?} point {p}: {what} off by {off:e} of {scale:e}");
        };
        for p in 0..np {
            // H_p = P + εI + Gᵀ Hs⁻¹ G, column by column.
            let mut h = DMatrix::from_fn(C, C, |a, b| if a == b { sh.p[a] + eps } else { 0.0 });
            for k in 0..C {
                h.set_column(k, &(h.column(k) + g.transpose() * hs_inv(&sh, &sc, p, &g.column(k).into_owned())));
            }
            let l = DMatrix::from_fn(C, C, |i, j| match i.cmp(&j) {
                std::cmp::Ordering::Less => 0.0,
                std::cmp::Ordering::Equal => 1.0 / chol[p][i][i],
                std::cmp::Ordering::Greater => chol[p][i][j],
            });
            close((&l * l.transpose()).as_slice(), h.as_slice(), "L Lᵀ", p);
            let hinv = h.clone().try_inverse().expect("H_p invertible");
            close(y[p].as_flattened(), (&n * &hinv * n.transpose()).as_slice(), "Y", p);
            let rgp = DVector::from_fn(mp, |r, _| rg[p * mp + r]);
            let rt_ref = DVector::from_fn(C, |k, _| rx[p * C + k]) + g.transpose() * hs_inv(&sh, &sc, p, &rgp);
            close(&rt[p], rt_ref.as_slice(), "r̃x", p);
            let w_ref = &hinv * &rt_ref;
            close(&w[p], w_ref.as_slice(), "H⁻¹ r̃x", p);
            let f = &n * &w_ref;
            let rho = sh.rho[p];
            let m = [rho[1] * f[2] - rho[2] * f[1], rho[2] * f[0] - rho[0] * f[2], rho[0] * f[1] - rho[1] * f[0]];
            let wr_ref = [f[0], f[1], f[2], m[0], m[1], m[2]];
            close(&wr[p], &wr_ref, "wrench", p);
            let uc = u[contact_of[p] as usize];
            let motion = DVector::from_fn(3, |i, _| {
                let (a, b) = ((i + 1) % 3, (i + 2) % 3);
                uc[i] + uc[3 + a] * rho[b] - uc[3 + b] * rho[a]
            });
            let x_ref = &hinv * (rt_ref - n.transpose() * motion);
            close(&x[p * C..(p + 1) * C], x_ref.as_slice(), "x_p", p);
            let zg_ref = hs_inv(&sh, &sc, p, &(&g * &x_ref - rgp));
            close(&zg[p * mp..(p + 1) * mp], zg_ref.as_slice(), "z_G", p);
        }
    }

    /// K's products ([`apply`], with and without the scaling) against each point's algebra
    /// written out with nalgebra ([`reference_products`]), to 1e-14 of each block's largest
    /// entry; and the products [`back_points`] leaves at the solution it forms against
    /// [`apply`] there, bit for bit ([`check_fused`]).
    fn check_products<const C: usize>(sh: Shape<C>, model: FrictionModel) {
        let mut rng = Lcg(5);
        let sc = interior_scaling(&sh, &mut rng);
        let mut random = |len: usize| (0..len).map(|_| rng.next() - 0.5).collect::<Vec<f64>>();
        let (x, ze, zg) = (random(sh.n()), random(sh.m_e()), random(sh.m_g()));
        let sol = Rhs { x: &x, eq: &ze, ineq: &zg };
        let mut work = ApplyWork::new(&sh);
        let mut out = Blocks::zeros(sh.n(), sh.m_e(), sh.m_g());
        let close = |a: &[f64], b: &[f64], what: &str| {
            let scale = b.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
            let off = a.iter().zip(b).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(off <= 1e-14 * scale, "{model:?}: {what} off by {off:e} of {scale:e}");
        };
        for kkt in [None, Some(&sc)] {
            apply(&sh, kkt, sol, out.step(), &mut work);
            let reference = reference_products(&sh, kkt, sol);
            close(&out.x, &reference.x, "Eᵀz_E + Gᵀz_G (+ P x)");
            close(&out.eq, &reference.eq, "E x");
            close(&out.ineq, &reference.ineq, "G x (− Hs z_G)");
        }
        check_fused(&sh, &sc, sol, &mut work, model);
    }

    /// K's products at `sol` one point at a time with nalgebra: Ψ and the rows as dense
    /// matrices, the wrench [f; ρ × f], the motion u_f + u_m × ρ.
    fn reference_products<const C: usize>(sh: &Shape<C>, kkt: Option<&Scaling>, sol: Rhs) -> Blocks {
        let (mp, nn) = (sh.m_p, sh.nonneg.len());
        let (g, n) = (rows(sh), DMatrix::from_fn(3, C, |i, k| sh.fmap[i][k]));
        let mut out = Blocks::zeros(sh.n(), sh.m_e(), sh.m_g());
        let psi = |side: &crate::statics::problem::Side| DMatrix::from_fn(6, 6, |r, c| side.psi[r][c]);
        for contact in sh.contacts {
            let mut u = DVector::zeros(6);
            for side in contact.sides.iter().flatten() {
                u += psi(side).transpose() * DVector::from_fn(6, |r, _| sol.eq[6 * side.block + r]);
            }
            let mut w6 = DVector::zeros(6);
            for p in contact.points.clone() {
                let [a, b, c] = sh.rho[p];
                let r = DMatrix::from_row_slice(3, 3, &[0.0, -c, b, c, 0.0, -a, -b, a, 0.0]);
                let xp = DVector::from_fn(C, |k, _| sol.x[p * C + k]);
                let zp = DVector::from_fn(mp, |i, _| sol.ineq[p * mp + i]);
                let f = &n * &xp;
                w6 += DVector::from_iterator(6, f.iter().copied().chain((&r * &f).iter().copied()));
                let motion = u.rows(0, 3) - &r * u.rows(3, 3);
                let mut kx = n.transpose() * motion + g.transpose() * &zp;
                let mut kg = &g * &xp;
                if let Some(sc) = kkt {
                    kx += DVector::from_fn(C, |k, _| sh.p[k] * xp[k]);
                    let mut hz = DVector::from_fn(mp, |i, _| if i < nn { sc.d[p * mp + i] * zp[i] } else { 0.0 });
                    if sh.soc.is_some() {
                        hz.rows_mut(nn, 3).copy_from_slice(&sc.hs_mul(p, &[zp[nn], zp[nn + 1], zp[nn + 2]]));
                    }
                    kg -= hz;
                }
                out.x[p * C..(p + 1) * C].copy_from_slice(kx.as_slice());
                out.ineq[p * mp..(p + 1) * mp].copy_from_slice(kg.as_slice());
            }
            for side in contact.sides.iter().flatten() {
                let e = psi(side) * &w6;
                for r in 0..6 {
                    out.eq[6 * side.block + r] += e[r];
                }
            }
        }
        out
    }

    /// The back substitution's products at its own solution (r̃x = `sol.x`, z_E = `sol.eq`,
    /// r_G = `sol.ineq`) against [`apply`] there, bit for bit.
    fn check_fused<const C: usize>(sh: &Shape<C>, sc: &Scaling, sol: Rhs, work: &mut ApplyWork, model: FrictionModel) {
        let np = sh.points();
        let (mut chol, mut y) = (vec![[[0.0; C]; C]; np], vec![[[0.0; 3]; 3]; np]);
        assert!(factor_points(sh, sc, 1e-13, &mut chol, &mut y));
        let rt: Vec<[f64; C]> = (0..np).map(|p| std::array::from_fn(|k| sol.x[p * C + k])).collect();
        work.see(sh, sol.eq);
        let (mut xb, mut zb) = (vec![0.0; sh.n()], vec![0.0; sh.m_g()]);
        let mut fused = Blocks::zeros(sh.n(), sh.m_e(), sh.m_g());
        let mut wrench = vec![[0.0; 6]; np];
        let products = PointProducts { ze: sol.eq, out: fused.step(), wrench: &mut wrench };
        let (seen, budgets) = ((work.seen.as_slice(), work.contact_of.as_slice()), &sol.eq[6 * sh.blocks..]);
        back_points(sh, sc, &chol, &rt, seen, (budgets, sol.ineq), &mut xb, &mut zb, Some(products));
        work.wrench = wrench;
        work.add_wrenches(sh, &mut fused.eq);
        let mut out = Blocks::zeros(sh.n(), sh.m_e(), sh.m_g());
        apply(sh, Some(sc), Rhs { x: &xb, eq: sol.eq, ineq: &zb }, out.step(), work);
        for (a, b) in [(&fused.x, &out.x), (&fused.eq, &out.eq), (&fused.ineq, &out.ineq)] {
            assert!(a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits()), "{model:?}: fused products differ");
        }
    }

    /// Every kernel's outputs with the points cut at `split` (`None`: all on one thread).
    fn kernels_split_at<const C: usize>(sh: &mut Shape<C>, sc: &Scaling, split: Option<usize>) -> Vec<u64> {
        sh.split = split;
        let (np, mut rng) = (sh.points(), Lcg(7));
        let mut random = |len: usize| (0..len).map(|_| rng.next() - 0.5).collect::<Vec<f64>>();
        let (rx, ze, rg) = (random(sh.n()), random(sh.m_e()), random(sh.m_g()));
        let (mut chol, mut y) = (vec![[[0.0; C]; C]; np], vec![[[0.0; 3]; 3]; np]);
        assert!(factor_points(sh, sc, 1e-13, &mut chol, &mut y));
        let (mut rt, mut w, mut wr) = (vec![[0.0; C]; np], vec![[0.0; C]; np], vec![[0.0; 6]; np]);
        reduce_points(sh, sc, &chol, (&rx, &rg), &mut rt, &mut w, &mut wr);
        let mut work = ApplyWork::new(sh);
        work.see(sh, &ze);
        let (mut x, mut zg) = (vec![0.0; sh.n()], vec![0.0; sh.m_g()]);
        let mut fused = Blocks::zeros(sh.n(), sh.m_e(), sh.m_g());
        let mut wrench = vec![[0.0; 6]; np];
        let products = PointProducts { ze: &ze, out: fused.step(), wrench: &mut wrench };
        let seen = (work.seen.as_slice(), work.contact_of.as_slice());
        back_points(sh, sc, &chol, &rt, seen, (&ze[6 * sh.blocks..], &rg), &mut x, &mut zg, Some(products));
        let mut applied = Blocks::zeros(sh.n(), sh.m_e(), sh.m_g());
        apply(sh, Some(sc), Rhs { x: &x, eq: &ze, ineq: &zg }, applied.step(), &mut work);
        let flat = [chol.as_flattened().as_flattened(), y.as_flattened().as_flattened(), rt.as_flattened()];
        let more = [w.as_flattened(), wr.as_flattened(), &x, &zg, &fused.x, &fused.ineq, wrench.as_flattened()];
        let last = [&applied.x[..], &applied.eq, &applied.ineq];
        flat.into_iter().chain(more).chain(last).flatten().map(|v| v.to_bits()).collect()
    }

    /// Invariant: the points cut in two halves on two threads ([`Shape::split`]) give every
    /// kernel's outputs bit for bit as one thread does — each point is computed by the same
    /// batch either way (the cut at a multiple of four) and nothing sums across the halves.
    fn check_halves<const C: usize>(mut sh: Shape<C>, model: FrictionModel) {
        assert!(sh.points() > 12 && !sh.points().is_multiple_of(LANES), "two halves and a short last batch");
        let sc = interior_scaling(&sh, &mut Lcg(3));
        let whole = kernels_split_at(&mut sh, &sc, None);
        for mid in [4, sh.points() / 8 * 4] {
            assert_eq!(kernels_split_at(&mut sh, &sc, Some(mid)), whole, "{model:?}: cut at point {mid}");
        }
    }

    #[test]
    fn two_halves_give_one_threads_bits() {
        on_short_walls!(check_halves);
    }

    #[test]
    fn products_four_at_a_time_are_each_points_and_fused_ones_the_same() {
        on_short_walls!(check_products);
    }

    #[test]
    fn four_lanes_give_each_points_algebra() {
        on_short_walls!(check);
    }
}
