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
    let np = sh.points();
    let mut p0 = 0;
    while p0 < np {
        let lanes = LANES.min(np - p0);
        // A short last batch repeats its last point in the spare lanes (and drops them).
        let points: [usize; LANES] = std::array::from_fn(|l| p0 + l.min(lanes - 1));
        let Some(b) = batch(sh, sc, eps, &points) else { return false };
        for l in 0..lanes {
            let p = p0 + l;
            for i in 0..C {
                for j in 0..C {
                    chol[p][i][j] = b.l[i][j][l];
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    y[p][i][j] = b.y[i][j][l];
                }
            }
        }
        p0 += LANES;
    }
    true
}

/// One batch: H, its factor, M = L⁻¹Nᵀ and Y = MᵀM.
fn batch<const C: usize>(sh: &Shape<C>, sc: &Scaling, eps: f64, points: &[usize; LANES]) -> Option<Batch<C>> {
    let h = hessians(sh, sc, eps, points);
    let l = cholesky(&h)?;
    let m: [[Lanes; C]; 3] = std::array::from_fn(|i| forward(&l, &sh.fmap[i]));
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

/// L⁻¹ r for each lane's factor, r shared.
fn forward<const C: usize>(l: &[[Lanes; C]; C], r: &[f64; C]) -> [Lanes; C] {
    let mut y = [[0.0; LANES]; C];
    for i in 0..C {
        let mut v = [r[i]; LANES];
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
