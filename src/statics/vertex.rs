//! One collapse mechanism instead of their blend: a vertex of the load factor's optimal face.
//!
//! The interior-point dual z* (the blocks' virtual motions, non-dimensional, 6 per block:
//! [`super::load_factor`]) lies at the centre of the optimal face
//! F = {z admissible : Lᵀz = 1, Dᵀz = −λ*}. Where F is a point the mechanism is unique; where
//! it is not, z* is the average of every mechanism that collapses at λ*. For the polyhedral
//! friction models admissibility is linear: at each force point p the relative motion v_p(z)
//! (interface frame) does no negative work against any generator g_k of the friction pyramid,
//! r_pk·z = g_k·v_p(z) ≥ 0 (box4: the 4 corners (1, ±μ, ±μ); pyramid8: the octagon's 8). So
//! F is a polytope and has vertices: mechanisms with as many contacts held as the motion allows.
//!
//! Recovery in three named steps, no LP solved (λ* stays the interior point's):
//! 1. [`tight_rows`]: the rows that carry force, by complementarity: the force's share of the
//!    generator against the row's work rate, each relative to its largest.
//! 2. [`face_directions`]: the null space of the tight rows (a sparse H = Σ r̂ r̂ᵀ over unit
//!    rows, factored once with a shift, a few sweeps of subspace inverse iteration, then
//!    Rayleigh–Ritz), less the directions that change the live load's work. Its dimension is
//!    F's. Every such direction d keeps the work equation: the tight rows hold the primal's
//!    support, so Dᵀd = −xᵀEᵀd − λ*Lᵀd = 0.
//! 3. [`purify`]: from z*, step along the face until a loose row closes, keep it closed,
//!    repeat until no direction is left — a vertex. Each step descends the blocks' ℓ1 motion,
//!    so the vertex reached moves few blocks; further runs along ± each face direction count
//!    the distinct vertices found.
//!
//! Why this and not a crossover by simplex or a second LP over F: a cold simplex takes minutes
//! on the Armadillo's LP (docs/benchmarks.md) and a second interior point ends again at a
//! face's centre; here the cost is one sparse Cholesky shaped like the solver's Newton system,
//! and nothing when F is a point. The cone model has no vertices; its mechanism stays the
//! interior point's.

use super::problem::{FrictionModel, Geometry};
use faer::linalg::solvers::SolveCore;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Side as FaerSide};
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use serde::Serialize;

/// A row whose work rate at the interior point is below this fraction of the largest is held:
/// at the face's centre a row is zero only where it is zero on the whole face, and an
/// interior point leaves such rows a few decades, not exactly, below the others.
const STILL_ROW: f64 = 1e-5;

/// An eigenvalue of H (unit rows) below this is a direction of the face: a singular value of
/// the tight rows below 1e-6, a rank tolerance as a simplex's.
const NULL: f64 = 1e-12;

/// The shift of H's factor: null directions are amplified by 1/SHIFT per inverse-iteration
/// sweep against ≤ 1/λ_min for the others.
const SHIFT: f64 = 1e-15;

/// Up to this many unknowns (40 blocks) H's null space comes from its dense eigenvectors;
/// beyond, from the sparse factor.
const DENSE_UP_TO: usize = 240;

/// Inverse-iteration sweeps per block of trial vectors.
const SWEEPS: usize = 3;

/// A vertex that misses the work equation or admissibility by more than this (relative) is
/// not taken: the interior point's mechanism stays.
pub const CHECK: f64 = 1e-6;

/// Further purification runs (± face directions) to count distinct vertices, at most.
const COUNT_RUNS: usize = 12;

/// A face of more dimensions is left as the interior point's blend: purification costs a
/// dense eigendecomposition of the face's size per step.
const MAX_FACE: usize = 64;

/// Vertices are counted on faces up to this dimension (each run costs a step per dimension).
const COUNT_UP_TO: usize = 32;

/// Whether a load factor's mechanism is the only one that collapses at λ*. An interior point
/// ends at the centre of the optimal face, the blend of every mechanism there; the statics
/// recover one of the face's vertices instead (`statics::vertex`, module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Uniqueness {
    /// Not examined: the cone model (no vertices), the crushing rows, a failure mechanism, and
    /// the kinematic check's (its accelerations are unique by Gauss's principle: `statics::rate`).
    #[default]
    NotExamined,
    /// The optimal face is a point: no other mechanism collapses at λ*.
    Unique,
    /// One vertex of an optimal face of `dimension` ≥ 1: `vertices` distinct vertices were
    /// found, so at least that many mechanisms (and every blend of them) collapse at λ*.
    OneOfMany {
        /// The optimal face's dimension (its free directions, the live load's work fixed).
        dimension: usize,
        /// Distinct vertices found (a lower bound on their number).
        vertices: usize,
    },
    /// The face is not a point but its vertex missed its check by `residual` (relative; NaN
    /// when the face had too many dimensions to seek one): the interior point's blend is shown.
    Blend {
        /// The optimal face's dimension.
        dimension: usize,
        /// The vertex's largest relative miss of its check.
        residual: f64,
    },
}

impl Uniqueness {
    /// A few words for a picture's panel, or `None` when there is nothing to say.
    pub fn label(&self) -> Option<String> {
        match *self {
            Uniqueness::NotExamined => None,
            Uniqueness::Unique => Some("the only mechanism".into()),
            Uniqueness::OneOfMany { vertices, .. } => Some(format!("one of {}+ mechanisms", vertices.max(2))),
            Uniqueness::Blend { .. } => Some("a blend of mechanisms".into()),
        }
    }

    /// One line for a report, or `None` when there is nothing to say.
    pub fn sentence(&self) -> Option<String> {
        match *self {
            Uniqueness::NotExamined => None,
            Uniqueness::Unique => Some("the only mechanism at this load factor".into()),
            Uniqueness::OneOfMany { dimension, vertices } => Some(format!(
                "one of {} mechanisms found at this load factor (their face has dimension {dimension}); \
                 any blend of them collapses too",
                vertices.max(2)
            )),
            Uniqueness::Blend { dimension, residual } if residual.is_nan() => Some(format!(
                "a blend of the mechanisms at this load factor (their face has dimension {dimension}: too \
                 many to pick one)"
            )),
            Uniqueness::Blend { dimension, residual } => Some(format!(
                "a blend of the mechanisms at this load factor (face of dimension {dimension}; the vertex \
                 missed its check by {residual:.1e})"
            )),
        }
    }
}

/// What the recovery found.
#[derive(Clone, Debug, PartialEq)]
pub enum FaceOutcome {
    /// The optimal face is a point: the interior point's mechanism is the only one.
    Unique,
    /// The face has `dimension` ≥ 1; `vertex` is the recovered mechanism (non-dimensional
    /// duals, 6 per block), one of at least `vertices` distinct ones found, all at λ*; its
    /// check missed by `residual` (relative).
    Vertex { vertex: Vec<f64>, dimension: usize, vertices: usize, residual: f64 },
    /// The cone model: no vertices to recover.
    NoVertices,
    /// The face has `dimension` ≥ 1 but the vertex missed its check by `residual` (NaN: the
    /// face has more than `MAX_FACE` dimensions, none was sought): the interior point's
    /// mechanism stays.
    Failed { dimension: usize, residual: f64 },
}

/// One admissibility row r_pk, scaled to unit length: its entries over the block rows.
type Row = Vec<(usize, f64)>;

/// The vertex of the optimal face reached from the interior point `z` (6 per block) with the
/// live load `live` (Lᵀz = 1) and the forces `forces` (per point, interface frame), over the
/// component's `geometry`.
pub fn vertex(
    geometry: &Geometry,
    model: FrictionModel,
    mu: f64,
    live: &[f64],
    z: &[f64],
    forces: &[[f64; 3]],
) -> FaceOutcome {
    let Some(pyramid) = Pyramid::new(model, mu) else {
        return FaceOutcome::NoVertices;
    };
    let n = 6 * geometry.blocks;
    let z = &z[..n];
    let rows = admissibility_rows(geometry, &pyramid.generators);
    let values: Vec<f64> = rows.iter().map(|r| dot(r, z)).collect();
    let shares = pyramid.shares(forces);
    let (tight, scale) = tight_rows(&values, &shares);
    let directions = face_directions(&rows, &tight, live, n);
    if directions.ncols() == 0 {
        return FaceOutcome::Unique;
    }
    if directions.ncols() > MAX_FACE {
        return FaceOutcome::Failed { dimension: directions.ncols(), residual: f64::NAN };
    }
    let face = Face::new(&rows, &values, &tight, &directions);
    let first = face.purify(&l1_descent(z, &directions));
    let mut found = vec![first.clone()];
    let counted = if directions.ncols() <= COUNT_UP_TO { directions.ncols().min(COUNT_RUNS / 2) } else { 0 };
    for k in 0..counted {
        for sign in [1.0, -1.0] {
            let mut gradient = DVector::zeros(directions.ncols());
            gradient[k] = sign;
            let v = face.purify(&gradient);
            if found.iter().all(|f| (f - &v).amax() > CHECK * (1.0 + v.amax())) {
                found.push(v);
            }
        }
    }
    let vertex: Vec<f64> = (DVector::from_column_slice(z) + &directions * &first).iter().copied().collect();
    let residual = check(&rows, &vertex, live, z, scale);
    if residual > CHECK {
        return FaceOutcome::Failed { dimension: directions.ncols(), residual };
    }
    FaceOutcome::Vertex { vertex, dimension: directions.ncols(), vertices: found.len(), residual }
}

/// The friction pyramid in the interface frame (n, u, v): its generators (edges) and its
/// facets' inward normals a (a·f ≥ 0 inside).
struct Pyramid {
    generators: Vec<[f64; 3]>,
    facets: Vec<[f64; 3]>,
}

impl Pyramid {
    /// `None` for the cone (no vertices); μ = 0: the normal ray alone.
    fn new(model: FrictionModel, mu: f64) -> Option<Self> {
        if model == FrictionModel::Cone {
            return None;
        }
        if mu <= 0.0 {
            return Some(Self { generators: vec![[1.0, 0.0, 0.0]], facets: Vec::new() });
        }
        let t = (std::f64::consts::SQRT_2 - 1.0) * mu;
        let r = std::f64::consts::SQRT_2 * mu;
        let mut facets = vec![[mu, -1.0, 0.0], [mu, 1.0, 0.0], [mu, 0.0, -1.0], [mu, 0.0, 1.0]];
        let generators = if model == FrictionModel::Box4 {
            vec![[1.0, mu, mu], [1.0, -mu, mu], [1.0, -mu, -mu], [1.0, mu, -mu]]
        } else {
            facets.extend([[r, -1.0, -1.0], [r, 1.0, -1.0], [r, -1.0, 1.0], [r, 1.0, 1.0]]);
            vec![
                [1.0, mu, t],
                [1.0, t, mu],
                [1.0, -t, mu],
                [1.0, -mu, t],
                [1.0, -mu, -t],
                [1.0, -t, -mu],
                [1.0, t, -mu],
                [1.0, mu, -t],
            ]
        };
        Some(Self { generators, facets })
    }

    /// Per (point, generator), in row order: the largest t with f − t g still in the pyramid —
    /// the share of g the point's force f can carry (zero unless g lies on every facet f
    /// touches).
    fn shares(&self, forces: &[[f64; 3]]) -> Vec<f64> {
        let dot3 = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let mut out = Vec::with_capacity(forces.len() * self.generators.len());
        for f in forces {
            for g in &self.generators {
                let room = self
                    .facets
                    .iter()
                    .filter(|a| dot3(a, g) > 1e-12)
                    .map(|a| dot3(a, f) / dot3(a, g))
                    .fold(f[0] / g[0], f64::min);
                out.push(room.max(0.0));
            }
        }
        out
    }
}

/// Every (force point, generator) row, of unit length: the equilibrium column of the force g_k
/// at p, so that r·z is the work of g_k on p's relative motion (per unit of the column).
fn admissibility_rows(geometry: &Geometry, generators: &[[f64; 3]]) -> Vec<Row> {
    let mut rows = Vec::with_capacity(geometry.points() * generators.len());
    for contact in &geometry.contacts {
        for p in contact.points.clone() {
            for g in generators {
                let mut row = Row::with_capacity(12);
                contact.force_rows(&geometry.rho[p], g, |r, v| row.push((r, v)));
                let length = row.iter().map(|(_, v)| v * v).sum::<f64>().sqrt();
                row.iter_mut().for_each(|(_, v)| *v /= length.max(f64::MIN_POSITIVE));
                rows.push(row);
            }
        }
    }
    rows
}

/// The tight rows' indices and the scale of the row values (their largest, over unit rows).
/// Complementarity decides: a row is tight where its rate is below [`STILL_ROW`], or where the
/// force's share of its generator, relative to the largest share, exceeds its work rate
/// relative to the largest rate — the interior point leaves both small only where neither
/// carries anything.
fn tight_rows(values: &[f64], shares: &[f64]) -> (Vec<usize>, f64) {
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
    let (scale, share) = (largest(values), largest(shares));
    let tight = (0..values.len())
        .filter(|&i| {
            let rate = values[i].max(0.0) / scale;
            rate <= STILL_ROW || shares[i] / share > rate
        })
        .collect();
    (tight, scale)
}

fn dot(row: &Row, z: &[f64]) -> f64 {
    row.iter().map(|&(i, v)| v * z[i]).sum()
}

/// An orthonormal basis (columns, n × f) of the directions d with r·d = 0 for every tight row
/// and Lᵀd = 0: the optimal face's directions.
fn face_directions(rows: &[Row], tight: &[usize], live: &[f64], n: usize) -> DMatrix<f64> {
    let held: Vec<&Row> = tight.iter().map(|&i| &rows[i]).collect();
    let kernel = null_space(&held, n);
    if kernel.ncols() == 0 {
        return kernel;
    }
    // Within the tight rows' null space, the directions doing no live work.
    let w = kernel.transpose() * DVector::from_column_slice(live);
    let wn = w.norm();
    if wn == 0.0 {
        return kernel;
    }
    let k = kernel.ncols();
    let projector = DMatrix::identity(k, k) - (&w * w.transpose()) / (wn * wn);
    let eig = SymmetricEigen::new(projector);
    let keep: Vec<usize> = (0..k).filter(|&i| eig.eigenvalues[i] > 0.5).collect();
    let basis = DMatrix::from_fn(k, keep.len(), |r, c| eig.eigenvectors[(r, keep[c])]);
    kernel * basis
}

/// The null space of the unit `rows` (n columns each), orthonormal columns: H = Σ r rᵀ factored once
/// with a shift, blocks of trial vectors swept by inverse iteration, H's Ritz values on them
/// below [`NULL`] kept; the block doubles while every Ritz value is null.
fn null_space(rows: &[&Row], n: usize) -> DMatrix<f64> {
    if n <= DENSE_UP_TO {
        return dense_null_space(rows, n);
    }
    let mut triplets = Vec::with_capacity(rows.len() * 78 + n);
    for row in rows {
        for &(i, a) in row.iter() {
            for &(j, b) in row.iter() {
                if j <= i {
                    triplets.push(Triplet::new(i, j, a * b));
                }
            }
        }
    }
    triplets.extend((0..n).map(|i| Triplet::new(i, i, SHIFT)));
    let h = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets).expect("indices within n");
    let Ok(llt) = h.as_ref().sp_cholesky(FaerSide::Lower) else {
        return DMatrix::zeros(n, 0);
    };
    let h_apply = |x: &DMatrix<f64>| {
        let mut out = DMatrix::zeros(n, x.ncols());
        for row in rows {
            for c in 0..x.ncols() {
                let d: f64 = row.iter().map(|&(i, v)| v * x[(i, c)]).sum();
                for &(i, v) in row.iter() {
                    out[(i, c)] += v * d;
                }
            }
        }
        out
    };
    let mut q = 4.min(n);
    loop {
        let mut x = trial_vectors(n, q);
        for _ in 0..SWEEPS {
            let mut m = Mat::<f64>::from_fn(n, q, |r, c| x[(r, c)]);
            llt.solve_in_place_with_conj(Conj::No, m.as_mut());
            x = DMatrix::from_fn(n, q, |r, c| m[(r, c)]).qr().q();
        }
        let ritz = SymmetricEigen::new(x.transpose() * h_apply(&x));
        let null: Vec<usize> = (0..q).filter(|&i| ritz.eigenvalues[i].abs() <= NULL).collect();
        if null.len() < q || q == n {
            let v = DMatrix::from_fn(q, null.len(), |r, c| ritz.eigenvectors[(r, null[c])]);
            return x * v;
        }
        q = (2 * q).min(n);
    }
}

/// [`null_space`] of a small component: H formed dense, its eigenvectors below [`NULL`].
fn dense_null_space(rows: &[&Row], n: usize) -> DMatrix<f64> {
    let mut h = DMatrix::<f64>::zeros(n, n);
    for row in rows {
        for &(i, a) in row.iter() {
            for &(j, b) in row.iter() {
                h[(i, j)] += a * b;
            }
        }
    }
    let eig = SymmetricEigen::new(h);
    let null: Vec<usize> = (0..n).filter(|&i| eig.eigenvalues[i].abs() <= NULL).collect();
    DMatrix::from_fn(n, null.len(), |r, c| eig.eigenvectors[(r, null[c])])
}

/// Deterministic pseudo-random trial vectors (splitmix64), n × q.
fn trial_vectors(n: usize, q: usize) -> DMatrix<f64> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    DMatrix::from_fn(n, q, |_, _| {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut x = state;
        x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        x ^= x >> 31;
        (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    })
}

/// The gradient of the blocks' ℓ1 motion Σ|z_i| in the face's coordinates.
fn l1_descent(z: &[f64], directions: &DMatrix<f64>) -> DVector<f64> {
    let sign = DVector::from_iterator(z.len(), z.iter().map(|v| v.signum()));
    directions.transpose() * sign
}

/// The optimal face in its own coordinates c (z = z* + N c): the loose rows' values s_j at z*
/// and their slopes w_j = r_j·N.
struct Face {
    slack: Vec<f64>,
    slope: Vec<DVector<f64>>,
    dimension: usize,
}

impl Face {
    fn new(rows: &[Row], values: &[f64], tight: &[usize], directions: &DMatrix<f64>) -> Self {
        let f = directions.ncols();
        let mut slack = Vec::new();
        let mut slope = Vec::new();
        for (j, (row, &v)) in rows.iter().zip(values).enumerate() {
            if tight.binary_search(&j).is_ok() {
                continue;
            }
            slack.push(v);
            slope.push(DVector::from_fn(f, |c, _| row.iter().map(|&(i, a)| a * directions[(i, c)]).sum::<f64>()));
        }
        Self { slack, slope, dimension: f }
    }

    /// A vertex reached from c = 0 by steps that descend `gradient` (projected on the
    /// directions still free), each to the first loose row it closes.
    fn purify(&self, gradient: &DVector<f64>) -> DVector<f64> {
        let f = self.dimension;
        let mut c = DVector::zeros(f);
        let mut held: Vec<usize> = Vec::new();
        // Each step closes a row with a component along the free directions, so the free
        // space shrinks by one; the bound guards against round-off.
        for _ in 0..2 * f + 2 {
            let free = self.free_directions(&held);
            if free.ncols() == 0 {
                break;
            }
            let mut d = -(&free * (free.transpose() * gradient));
            if d.norm() <= 1e-12 * (1.0 + gradient.norm()) {
                d = free.column(0).into_owned();
            }
            let Some((t, j)) = self.ratio_test(&c, &d, &held).or_else(|| {
                d = -d.clone();
                self.ratio_test(&c, &d, &held)
            }) else {
                break;
            };
            c += &d * t;
            held.push(j);
        }
        c
    }

    /// The first loose row (not `held`) closed along d from c: (step, row). Rows barely
    /// turning along d (below 1e-9 of |w||d|) are taken as parallel to it.
    fn ratio_test(&self, c: &DVector<f64>, d: &DVector<f64>, held: &[usize]) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        let dn = d.norm();
        for (j, (s, w)) in self.slack.iter().zip(&self.slope).enumerate() {
            let rate = w.dot(d);
            if rate < -1e-9 * w.norm() * dn && !held.contains(&j) {
                let t = ((s + w.dot(c)) / -rate).max(0.0);
                if best.is_none_or(|(b, _)| t < b) {
                    best = Some((t, j));
                }
            }
        }
        best
    }

    /// An orthonormal basis of the face directions that keep the `held` rows closed.
    fn free_directions(&self, held: &[usize]) -> DMatrix<f64> {
        let f = self.dimension;
        if held.is_empty() {
            return DMatrix::identity(f, f);
        }
        let w = DMatrix::from_fn(held.len(), f, |r, c| self.slope[held[r]][c]);
        let eig = SymmetricEigen::new(w.transpose() * &w);
        let scale = eig.eigenvalues.amax().max(f64::MIN_POSITIVE);
        let keep: Vec<usize> = (0..f).filter(|&i| eig.eigenvalues[i] <= 1e-12 * scale).collect();
        DMatrix::from_fn(f, keep.len(), |r, c| eig.eigenvectors[(r, keep[c])])
    }
}

/// The vertex's largest relative miss: live work 1, dead work unchanged from z* (both via
/// Lᵀ and the tight rows), and no row below zero (relative to the rows' scale).
fn check(rows: &[Row], vertex: &[f64], live: &[f64], z: &[f64], scale: f64) -> f64 {
    let work = |m: &[f64]| m.iter().zip(live).map(|(a, b)| a * b).sum::<f64>();
    let live_miss = (work(vertex) - work(z)).abs() / work(z).abs().max(f64::MIN_POSITIVE);
    let worst = rows.iter().map(|r| dot(r, vertex)).fold(0.0f64, f64::min);
    live_miss.max(-worst / scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: the null space of rows spanning a known subspace is its complement — rows
    /// e_0, e_1 + e_2 in R⁴ leave {e_1 − e_2, e_3}, orthonormal, to 1e-10.
    #[test]
    fn the_null_space_is_the_rows_complement() {
        let rows: Vec<Row> = vec![vec![(0, 2.0)], vec![(1, 1.0), (2, 1.0)]];
        let refs: Vec<&Row> = rows.iter().collect();
        let k = null_space(&refs, 4);
        assert_eq!(k.ncols(), 2);
        assert!((k.transpose() * &k - DMatrix::identity(2, 2)).amax() < 1e-10);
        for c in 0..2 {
            assert!(k[(0, c)].abs() < 1e-10 && (k[(1, c)] + k[(2, c)]).abs() < 1e-10);
        }
    }

    /// Invariant: purification ends at a vertex of a square face {0 ≤ c ≤ 1}² entered at its
    /// centre, one of its four corners, to 1e-12.
    #[test]
    fn purification_ends_at_a_corner() {
        let e = |a: f64, b: f64| DVector::from_vec(vec![a, b]);
        let face = Face {
            slack: vec![0.5, 0.5, 0.5, 0.5],
            slope: vec![e(1.0, 0.0), e(-1.0, 0.0), e(0.0, 1.0), e(0.0, -1.0)],
            dimension: 2,
        };
        let v = face.purify(&e(1.0, 0.3));
        assert!((v[0].abs() - 0.5).abs() < 1e-12 && (v[1].abs() - 0.5).abs() < 1e-12, "{v}");
        assert!(v[0] < 0.0 && v[1] < 0.0, "descends the gradient: {v}");
    }
}
