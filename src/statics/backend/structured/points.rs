//! Each force point's share of S, four points at a time: H_p = P + εI + G_pᵀ Hs_p⁻¹ G_p, its
//! Cholesky factor and the local force covariance Y_p = N H_p⁻¹ Nᵀ (module docs of the kkt).
//!
//! One point's algebra is a C×C Cholesky with C ≤ 5: a chain of square roots and divisions
//! that no vector lane count divides, so one point at a time runs at the latency of that chain
//! (docs/benchmarks.md, the roofline table). Here every step is taken for [`LANES`] points at
//! once (arrays indexed by lane innermost), which the compiler maps onto vector lanes. Each
//! lane computes exactly the scalar expressions of one point, in the same order: the same bits.

use super::cones::Scaling;
use super::shape::Shape;

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
    batches(sh.points(), |points, lanes| {
        let Some(b) = batch(sh, sc, eps, points) else { return false };
        for (q, &p) in points.iter().enumerate().take(lanes) {
            for i in 0..C {
                for j in 0..C {
                    chol[p][i][j] = b.l[i][j][q];
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    y[p][i][j] = b.y[i][j][q];
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

/// Calls `f(points, lanes)` for each batch of `np` points: a short last batch repeats its last
/// point in the spare lanes, whose results the caller drops. Stops at the first `false`.
fn batches(np: usize, mut f: impl FnMut(&[usize; LANES], usize) -> bool) -> bool {
    let mut p0 = 0;
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
    batches(sh.points(), |points, lanes| {
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
            let p = points[q];
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

/// The points' part of the back substitution, from z_E: for every point x_p = H_p⁻¹ (r̃x −
/// Nᵀ(u + u×ρ) − budgets) into `x` and z_G = Hs_p⁻¹ (G_p x_p − r_G) into `zg`; `u` is each
/// contact's block rows of z_E seen in its frame, `contact_of` each point's contact, `budgets`
/// the budget rows of z_E.
#[allow(clippy::too_many_arguments)]
pub(super) fn back_points<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    chol: &[[[f64; C]; C]],
    rt: &[[f64; C]],
    (u, contact_of): (&[[f64; 6]], &[u32]),
    (budgets, rg): (&[f64], &[f64]),
    x: &mut [f64],
    zg: &mut [f64],
) {
    batches(sh.points(), |points, lanes| {
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
                x[points[q] * C + k] = xp[k][q];
            }
        }
        point_duals(sh, sc, rg, points, lanes, &xp, zg);
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

/// z_G = Hs_p⁻¹ (G_p x_p − r_G) of the batch's first `lanes` points into `zg`.
fn point_duals<const C: usize>(
    sh: &Shape<C>,
    sc: &Scaling,
    rg: &[f64],
    points: &[usize; LANES],
    lanes: usize,
    xp: &[Lanes; C],
    zg: &mut [f64],
) {
    let (mp, nn) = (sh.m_p, sh.nonneg.len());
    for (r, g) in sh.nonneg.iter().enumerate() {
        let mut gx = [0.0f64; LANES];
        for k in 0..C {
            for q in 0..LANES {
                gx[q] += g[k] * xp[k][q];
            }
        }
        for q in 0..lanes {
            let i = points[q] * mp + r;
            zg[i] = (gx[q] - rg[i]) * sc.dinv[i];
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
            zg[at..at + 3].copy_from_slice(&sc.hs_inv_mul(points[q], &gx));
        }
    }
}
