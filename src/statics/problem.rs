//! The statics' shared vocabulary, a leaf (it imports no other statics module): the variables
//! of a force point, the friction models, one stage's equilibrium problem as plain data in
//! contact form — the shape the structured interior-point method exploits
//! ([`super::backend`]) and from which clarabel's triplets are generated
//! ([`ContactProblem::to_conic`]), so both backends solve the same data — and what a solve must
//! reach ([`Accuracy`]) and how it ended ([`SolverStatus`]).
//!
//! Non-dimensional: lengths by the model size, forces by the component's free weight.
//!
//! ## Equilibrium rows (6 per free block, then one per budget)
//! A force point p of interface I carries variables `x_p` (the stage's [`Var`]s, in order);
//! its force in the interface frame (n, u, v) is `f_p = N x_p` (c_n⁺ → +n, c_n⁻ → −n,
//! c_u → u, c_v → v, the slack → nothing). With `ρ_p` the point's position relative to the
//! interface origin o in the same frame, the local wrench about o is `T_p f_p = [f_p; ρ_p × f_p]`,
//! and block j's six rows (force, moment about its centroid c_j, world axes) receive
//! `Ψ_j T_p f_p` with `Ψ_j = ±[F 0; [o − c_j]× F  F]`, F = [n u v] (right-handed), + for the
//! block b the normal points into, − for a. A budget `Σ_p x_p[v] ≤ limit` is an equality row
//! `Σ_p x_p[v] + σ = limit` with its own slack σ ≥ 0 (in the structured solver; clarabel gets
//! the inequality).
//!
//! ## Inequality rows per point (A x + s = b, s in the cone; b = 0)
//! Sign rows `c_n⁺ ≥ 0` (left out when friction rows without slack imply it), `c_n⁻ ≥ 0`,
//! `s ≥ 0`; then for the pyramid models `±c_u − μc_n⁺ − s ≤ 0`, `±c_v − μc_n⁺ − s ≤ 0` (box4,
//! pyramid8) and `±c_u ± c_v − √2(μc_n⁺ + s) ≤ 0` (pyramid8); for the cone model one
//! second-order cone `‖(c_u, c_v)‖ ≤ μc_n⁺ + s`.
//!
//! ## Crushing rows per interface ([`Crushing`], when a compressive strength σ is given)
//! The rectangular stress block, biaxial: the interface's net normal force N = Σ c_n at the
//! resultant point e = (e₀, e₁) (along two in-plane axes: its longest edge and the normal to
//! it; lo_k ≤ e_k ≤ hi_k the polygon's extremes) needs a compressed rectangle centred on e,
//! 2a₀ × 2a₁ with a_k = min(e_k − lo_k, hi_k − e_k), scaled to the polygon's share of its
//! bounding rectangle (κ = 4A / (L₀L₁), [`StressBlock::kappa`]): N ≤ σ κ a₀ a₁. With M_k =
//! N e_k and X = ±(M₀ − edge₀ N), Y = ±(M₁ − edge₁ N) for each of the four corners the resultant
//! may approach, that is N³ ≤ κ σ X Y — convex in the forces and in σ (three rotated
//! second-order cones per corner, [`stress_block_cones`]). Exact for a rectangle loaded
//! eccentrically along both axes; along one axis it is N ≤ 2 σ w a (w = A / L the width).

use serde::Serialize;

pub use crate::model::FrictionModel;

/// Cones in row order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cone {
    /// `n` equality rows (the block equilibria).
    Zero(usize),
    /// `n` rows in the non-negative cone (signs, polyhedral friction).
    Nonnegative(usize),
    /// One second-order cone of `n` rows (a friction cone: `n` = 3).
    SecondOrder(usize),
}

/// A general conic problem (clarabel's form): minimise ½ xᵀ diag(p) x + qᵀ x subject to
/// A x + s = b, s ∈ cones.
#[derive(Clone, Debug, Default)]
pub struct ConicProblem {
    /// The number of variables (columns).
    pub n: usize,
    /// The diagonal of the quadratic objective P, one entry per column.
    pub p_diag: Vec<f64>,
    /// The linear objective q, one entry per column.
    pub q: Vec<f64>,
    /// (row, column, value) of A.
    pub a: Vec<(usize, usize, f64)>,
    /// The right-hand side b, one entry per row.
    pub b: Vec<f64>,
    /// The cones the rows belong to, in row order.
    pub cones: Vec<Cone>,
}

impl ConicProblem {
    /// The number of rows.
    pub fn m(&self) -> usize {
        self.b.len()
    }
}

/// Variables of a force point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Var {
    CnPos,
    CnNeg,
    Cu,
    Cv,
    Slack,
}

/// How a solve ended. Data, not an error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverStatus {
    /// Solved to full accuracy.
    Solved,
    /// Solved to clarabel's reduced accuracy.
    AlmostSolved,
    /// Stopped at the iteration limit.
    MaxIterations,
    /// The solver stopped making progress before the tolerances.
    InsufficientProgress,
    /// The solver hit a numerical failure (a factorisation broke down).
    NumericalError,
    /// The objective is unbounded (for a load factor: no multiple of the live load collapses it).
    Unbounded,
    /// No equilibrium exists at all (not even with tension).
    Infeasible,
    /// A block or group touches no support: nothing can hold it (no solve was run).
    Unsupported,
}

impl SolverStatus {
    /// Whether the solve reached an answer: solved, at full or reduced accuracy.
    pub fn solved(self) -> bool {
        matches!(self, SolverStatus::Solved | SolverStatus::AlmostSolved)
    }
}

/// What a solve must reach: clarabel's feasibility and duality-gap tolerances. The relative
/// gap is taken against max(1, |objective|) (clarabel's definition), or with `pure_relative`
/// against |objective| itself — then near a zero optimum only `gap_abs` decides, and a large
/// optimum needs only `gap_rel` of itself (the structured solver; clarabel keeps its own).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accuracy {
    /// Primal and dual feasibility tolerance (relative residuals).
    pub feas: f64,
    /// Absolute duality-gap tolerance.
    pub gap_abs: f64,
    /// Relative duality-gap tolerance.
    pub gap_rel: f64,
    /// Whether the relative gap is against |objective| alone, not max(1, |objective|).
    pub pure_relative: bool,
}

impl Accuracy {
    /// clarabel's definition with one tolerance for all three.
    pub fn uniform(tol: f64) -> Self {
        Self { feas: tol, gap_abs: tol, gap_rel: tol, pure_relative: false }
    }
}

/// One side of an interface that is a free block of the component.
#[derive(Clone, Debug)]
pub struct Side {
    /// Local block index (rows 6·block … 6·block + 5).
    pub block: usize,
    /// Maps the local wrench about the interface origin to the block's rows:
    /// `[[P, 0], [[arm]× P, P]]`, P = sign · F (F the frame's axes as columns).
    pub psi: [[f64; 6]; 6],
    /// The interface origin from the block's centroid.
    pub arm: [f64; 3],
}

impl Side {
    /// The side of `block` for an interface with axes `frame` (n, u, v; world components) whose
    /// origin is at `arm` from the block's centroid: `sign` −1 for side a, +1 for b.
    pub fn new(block: usize, frame: [[f64; 3]; 3], arm: [f64; 3], sign: f64) -> Self {
        let mut psi = [[0.0; 6]; 6];
        for (c, col) in frame.iter().enumerate() {
            let m = [
                arm[1] * col[2] - arm[2] * col[1],
                arm[2] * col[0] - arm[0] * col[2],
                arm[0] * col[1] - arm[1] * col[0],
            ];
            for r in 0..3 {
                psi[r][c] = sign * col[r];
                psi[3 + r][c] = sign * m[r];
                psi[3 + r][3 + c] = sign * col[r];
            }
        }
        Self { block, psi, arm }
    }

    /// `out += Ψ w`: a wrench about the interface origin (in its frame) added to the block's
    /// six rows `out` — by Ψ's blocks: u = P w_f, then [u; arm × u + P w_m].
    pub fn add_wrench(&self, w: &[f64; 6], out: &mut [f64]) {
        let u = self.p_mul(&[w[0], w[1], w[2]]);
        let t = self.p_mul(&[w[3], w[4], w[5]]);
        let m = cross(&self.arm, &u);
        for r in 0..3 {
            out[r] += u[r];
            out[3 + r] += m[r] + t[r];
        }
    }

    /// `out += Ψᵀ y`: the block's six rows `y` seen in the interface frame — by Ψ's blocks:
    /// [Pᵀ (y_f + y_m × arm); Pᵀ y_m].
    pub fn add_seen(&self, y: &[f64], out: &mut [f64; 6]) {
        let ym = [y[3], y[4], y[5]];
        let shift = cross(&ym, &self.arm);
        let f = self.pt_mul(&[y[0] + shift[0], y[1] + shift[1], y[2] + shift[2]]);
        let m = self.pt_mul(&ym);
        for c in 0..3 {
            out[c] += f[c];
            out[3 + c] += m[c];
        }
    }

    /// P v (P: Ψ's upper left 3×3).
    fn p_mul(&self, v: &[f64; 3]) -> [f64; 3] {
        let p = &self.psi;
        std::array::from_fn(|r| p[r][0] * v[0] + p[r][1] * v[1] + p[r][2] * v[2])
    }

    /// Pᵀ v.
    fn pt_mul(&self, v: &[f64; 3]) -> [f64; 3] {
        let p = &self.psi;
        std::array::from_fn(|c| p[0][c] * v[0] + p[1][c] * v[1] + p[2][c] * v[2])
    }
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// An interface of the component: its force points and the free blocks it touches.
#[derive(Clone, Debug)]
pub struct Contact {
    pub points: std::ops::Range<usize>,
    /// Block a (−) and block b (+), when free.
    pub sides: [Option<Side>; 2],
}

impl Contact {
    /// The block rows a force `f` (interface frame) at `rho` enters, as `push(row, value)`:
    /// one equilibrium column, zeros left out.
    pub fn force_rows(&self, rho: &[f64; 3], f: &[f64; 3], mut push: impl FnMut(usize, f64)) {
        let w = wrench(rho, f);
        for side in self.sides.iter().flatten() {
            let mut rows = [0.0; 6];
            side.add_wrench(&w, &mut rows);
            for (r, v) in rows.into_iter().enumerate() {
                if v != 0.0 {
                    push(6 * side.block + r, v);
                }
            }
        }
    }
}

/// The stage-independent geometry of a component's problem.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    pub blocks: usize,
    /// Right-hand side of the block rows: minus the load, 6 per block.
    pub rhs: Vec<f64>,
    pub contacts: Vec<Contact>,
    /// Per force point (in contact order): (x_p − o)/L in the interface frame (n, u, v).
    pub rho: Vec<[f64; 3]>,
}

impl Geometry {
    pub fn points(&self) -> usize {
        self.rho.len()
    }
}

/// A budget row `Σ_p x_p[var] ≤ limit`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    pub var: Var,
    pub limit: f64,
}

/// One stage's problem: minimise Σ_p ½ Σ_c p_c x_pc² + q_c x_pc over the geometry's points.
#[derive(Clone, Debug)]
pub struct ContactProblem<'a> {
    pub geometry: &'a Geometry,
    /// The variables of each point, in column order.
    pub vars: Vec<Var>,
    pub model: FrictionModel,
    pub mu: f64,
    /// Quadratic (the diagonal of P) and linear weights per variable.
    pub p: Vec<f64>,
    pub q: Vec<f64>,
    pub budgets: Vec<Budget>,
    /// A load factor λ: one more variable, after the points' (and the budgets' slacks), with
    /// `column` in the block rows (6 per block: the live load) and linear cost `cost`.
    pub factor: Option<LoadColumn>,
    /// Threads the solver may use for this solve (its per-point kernels and a large
    /// factorisation): 2 when the statics may use both cores and nothing else runs beside this
    /// solve ([`super::StaticsSettings::parallel`]), else 1.
    pub threads: usize,
    /// The crushing rows, when the material has a compressive strength.
    pub crushing: Option<Crushing<'a>>,
    /// Variables after λ that each enter one block's rows only: the densities of
    /// [`super::infill`], the momentum residual of the exact-contact engine's step.
    pub columns: Vec<BlockColumn>,
    /// The points' rows, when not the stage's ([`Self::point_rows`]): the engine's contacts.
    pub rows: Option<PointRows>,
    /// Per point, its variables' linear costs (C each, point-major), when they are not all `q`.
    pub point_q: Vec<f64>,
    /// Per point, the right-hand side of its rows (non-negative first, then the cone's; point-
    /// major), when not all zero.
    pub point_b: Vec<f64>,
}

/// A variable that enters one block's six rows only (`column`: its entries there, added to the
/// equilibrium's left side as a force column is), with weights ½ p x² + cost x and optional
/// bounds lo ≤ x ≤ hi.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockColumn {
    /// The block's index in the component (its six rows).
    pub block: usize,
    /// Its entries in the block's six rows (force x, y, z, moment x, y, z).
    pub column: [f64; 6],
    /// Quadratic weight of the variable in the objective (½ p x²).
    pub p: f64,
    /// Linear weight of the variable in the objective (cost x).
    pub cost: f64,
    /// Lower and upper bounds, when bounded.
    pub bounds: Option<(f64, f64)>,
}

/// The column of a load factor λ in the block rows, its cost in the objective, and whether
/// λ ≥ 0 (a row of the non-negative cone) or free.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadColumn {
    pub column: Vec<f64>,
    pub cost: f64,
    pub bounded: bool,
}

/// One interface's stress block (module docs): its points, two orthogonal in-plane axes in
/// the interface's (u, v) coordinates, the polygon's extent along each (lo, hi, relative to the
/// interface origin), and its width across each (area / extent). Non-dimensional.
#[derive(Clone, Debug, PartialEq)]
pub struct StressBlock {
    /// The interface's force points (indices into the problem's points).
    pub points: std::ops::Range<usize>,
    /// Two orthogonal in-plane axes, in the interface's (u, v) coordinates.
    pub axes: [[f64; 2]; 2],
    /// The polygon's lowest coordinate along each axis, from the interface origin.
    pub lo: [f64; 2],
    /// The polygon's highest coordinate along each axis, from the interface origin.
    pub hi: [f64; 2],
    /// The polygon's width across each axis: its area over its extent along it.
    pub width: [f64; 2],
}

impl StressBlock {
    /// κ = 4 A / (L₀ L₁) (A the polygon's area, L its extents): the compressed rectangle 2a₀ ×
    /// 2a₁ about the resultant, scaled to the polygon's share of its bounding rectangle, has
    /// area κ a₀ a₁ (a rectangle: 4 a₀ a₁). 0 for a polygon without extent.
    pub fn kappa(&self) -> f64 {
        let extent = self.hi[1] - self.lo[1];
        if extent > 0.0 { 4.0 * self.width[0] / extent } else { 0.0 }
    }

    /// The strength the normal forces `cn` at in-plane points `at` ((u, v), same units as the
    /// block) need under the biaxial stress block ([`Self::need`]).
    pub fn demand(&self, at: &[[f64; 2]], cn: &[f64]) -> f64 {
        let along = at.iter().map(|p| self.axes.map(|a| p[0] * a[0] + p[1] * a[1]));
        self.need(along.zip(cn.iter().copied()))
    }

    /// The strength normal forces need, each given with its point's coordinates along the two
    /// axes: N / (κ a₀ a₁), a_k the resultant's distance to the nearer edge along axis k
    /// ([`Self::reach`]); 0 without compression, ∞ when the resultant leaves the polygon's extent.
    pub fn need(&self, forces: impl Iterator<Item = ([f64; 2], f64)> + Clone) -> f64 {
        let Some([a0, a1]) = self.reach(forces.clone()) else { return 0.0 };
        let total: f64 = forces.map(|f| f.1).sum();
        let area = self.kappa() * a0 * a1;
        if a0 <= 0.0 || a1 <= 0.0 || area <= 0.0 { f64::INFINITY } else { total / area }
    }

    /// The resultant's distance to the nearer edge along each axis, min(e_k − lo_k, hi_k − e_k),
    /// of normal forces given with their points' coordinates along the axes; `None` without
    /// compression.
    pub fn reach(&self, forces: impl Iterator<Item = ([f64; 2], f64)>) -> Option<[f64; 2]> {
        let (mut total, mut moment) = (0.0, [0.0; 2]);
        for (along, f) in forces {
            total += f;
            moment[0] += f * along[0];
            moment[1] += f * along[1];
        }
        (total > 0.0).then(|| [0, 1].map(|k| (moment[k] / total - self.lo[k]).min(self.hi[k] - moment[k] / total)))
    }
}

/// The strength of the crushing rows: a given σ (non-dimensional), or σ as one more variable
/// (after the points' and λ), minimised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Strength {
    Fixed(f64),
    Least,
}

/// The crushing rows of a problem: a stress block per interface, at a strength.
#[derive(Clone, Copy, Debug)]
pub struct Crushing<'a> {
    pub blocks: &'a [StressBlock],
    pub strength: Strength,
}

impl Geometry {
    /// The stress block of every contact (module docs): axes along the polygon's longest edge
    /// and across it; the area from the polygon (shoelace in the interface plane).
    pub fn stress_blocks(&self) -> Vec<StressBlock> {
        self.contacts
            .iter()
            .map(|c| {
                let pts: Vec<[f64; 2]> = self.rho[c.points.clone()].iter().map(|r| [r[1], r[2]]).collect();
                stress_block(c.points.clone(), &pts)
            })
            .collect()
    }
}

/// The stress block of a polygon `pts` ((u, v) about the interface origin) whose points are
/// `points` of a problem.
pub(crate) fn stress_block(points: std::ops::Range<usize>, pts: &[[f64; 2]]) -> StressBlock {
    let n = pts.len();
    let edge = |i: usize| [pts[(i + 1) % n][0] - pts[i][0], pts[(i + 1) % n][1] - pts[i][1]];
    let longest = (0..n)
        .map(edge)
        .fold([0.0f64, 0.0], |best, e| if e[0].hypot(e[1]) > best[0].hypot(best[1]) { e } else { best });
    let len = longest[0].hypot(longest[1]);
    let a0 = if len > 0.0 { [longest[0] / len, longest[1] / len] } else { [1.0, 0.0] };
    let axes = [a0, [-a0[1], a0[0]]];
    let area = crate::geometry::polygon::signed_area_2d(pts).abs();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in pts {
        for (k, a) in axes.iter().enumerate() {
            let t = p[0] * a[0] + p[1] * a[1];
            lo[k] = lo[k].min(t);
            hi[k] = hi[k].max(t);
        }
    }
    let width = [0, 1].map(|k| if hi[k] > lo[k] { area / (hi[k] - lo[k]) } else { 0.0 });
    StressBlock { points, axes, lo, hi, width }
}

/// The inequality rows every point shares: `rows` of the non-negative cone, then optionally
/// one second-order cone of three rows. Each row is a dense vector over the point's variables.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRows {
    pub nonneg: Vec<Vec<f64>>,
    pub soc: Option<[Vec<f64>; 3]>,
}

impl PointRows {
    pub fn count(&self) -> usize {
        self.nonneg.len() + if self.soc.is_some() { 3 } else { 0 }
    }
}

impl ContactProblem<'_> {
    pub fn per_point(&self) -> usize {
        self.vars.len()
    }

    /// Column of `var` within a point.
    pub fn index(&self, var: Var) -> Option<usize> {
        self.vars.iter().position(|&v| v == var)
    }

    fn has_friction(&self) -> bool {
        self.index(Var::Cu).is_some() && self.index(Var::Cv).is_some()
    }

    /// `N`: the local force (n, u, v) of a point's variables.
    pub fn force_map(&self) -> [Vec<f64>; 3] {
        let c = self.per_point();
        let mut n = [vec![0.0; c], vec![0.0; c], vec![0.0; c]];
        for (k, v) in self.vars.iter().enumerate() {
            match v {
                Var::CnPos => n[0][k] = 1.0,
                Var::CnNeg => n[0][k] = -1.0,
                Var::Cu => n[1][k] = 1.0,
                Var::Cv => n[2][k] = 1.0,
                Var::Slack => {}
            }
        }
        n
    }

    /// The rows of the module docs, for this stage's variables and friction model.
    pub fn point_rows(&self) -> PointRows {
        if let Some(rows) = &self.rows {
            return rows.clone();
        }
        let c = self.per_point();
        let unit = |var: Var, value: f64| -> Option<Vec<f64>> {
            self.index(var).map(|k| {
                let mut r = vec![0.0; c];
                r[k] = value;
                r
            })
        };
        let slack = self.index(Var::Slack);
        let friction = self.has_friction();
        let mut nonneg = Vec::new();
        if !friction || slack.is_some() {
            nonneg.extend(unit(Var::CnPos, -1.0));
        }
        nonneg.extend(unit(Var::CnNeg, -1.0));
        nonneg.extend(unit(Var::Slack, -1.0));
        let mut soc = None;
        if friction {
            let (cn, cu, cv) = (self.index(Var::CnPos), self.index(Var::Cu), self.index(Var::Cv));
            let row = |du: f64, dv: f64, scale: f64| {
                let mut r = vec![0.0; c];
                if let Some(k) = cu {
                    r[k] += du;
                }
                if let Some(k) = cv {
                    r[k] += dv;
                }
                if let Some(k) = cn {
                    r[k] -= scale * self.mu;
                }
                if let Some(k) = slack {
                    r[k] -= scale;
                }
                r
            };
            match self.model {
                FrictionModel::Box4 | FrictionModel::Pyramid8 => {
                    nonneg.extend(self.model.facets().iter().map(|&(du, dv, scale)| row(du, dv, scale)));
                }
                FrictionModel::Cone => {
                    // s = −A x = (μ c_n⁺ + s, c_u, c_v): the head row is −(μ e_n + e_s).
                    let head = row(0.0, 0.0, 1.0);
                    soc = Some([head, unit(Var::Cu, -1.0).expect("friction"), unit(Var::Cv, -1.0).expect("friction")]);
                }
            }
        }
        PointRows { nonneg, soc }
    }

    /// The equilibrium rows of one point as (row, column-in-point, value), for a point of
    /// `contact` with local offset `rho`.
    fn point_equilibrium(&self, contact: &Contact, rho: &[f64; 3], out: &mut Vec<(usize, usize, f64)>) {
        let n = self.force_map();
        for (k, _) in self.vars.iter().enumerate() {
            let f = [n[0][k], n[1][k], n[2][k]];
            if f != [0.0; 3] {
                contact.force_rows(rho, &f, |row, v| out.push((row, k, v)));
            }
        }
    }

    /// The same problem for a general conic solver (clarabel): rows in the order zero cone
    /// (block rows), non-negative cone (every point's rows, then the budgets, λ ≥ 0 and each
    /// bounded block column's two bounds), then one second-order cone per point. Columns: the points', λ,
    /// the block columns, then the crushing cones' own.
    pub fn to_conic(&self) -> ConicProblem {
        let g = self.geometry;
        let c = self.per_point();
        let np = g.points();
        let n = np * c;
        let mut a = Vec::new();
        let mut b = g.rhs.clone();
        let mut local = Vec::new();
        for contact in &g.contacts {
            for p in contact.points.clone() {
                local.clear();
                self.point_equilibrium(contact, &g.rho[p], &mut local);
                a.extend(local.iter().map(|&(r, k, v)| (r, p * c + k, v)));
            }
        }
        let mut cones = vec![Cone::Zero(b.len())];
        let start = b.len();
        let rows = self.point_rows();
        let m_p = rows.count();
        let rhs = |p: usize, r: usize| self.point_b.get(p * m_p + r).copied().unwrap_or(0.0);
        for p in 0..np {
            for (r, g) in rows.nonneg.iter().enumerate() {
                let row = b.len();
                a.extend(g.iter().enumerate().filter(|e| *e.1 != 0.0).map(|(k, &v)| (row, p * c + k, v)));
                b.push(rhs(p, r));
            }
        }
        for budget in &self.budgets {
            let row = b.len();
            let k = self.index(budget.var).expect("a budget over a variable of the stage");
            a.extend((0..np).map(|p| (row, p * c + k, 1.0)));
            b.push(budget.limit);
        }
        // λ's column in the block rows; λ ≥ 0 as the row −λ ≤ 0.
        let lambda = n;
        if let Some(f) = &self.factor {
            a.extend(f.column.iter().enumerate().filter(|e| *e.1 != 0.0).map(|(r, &v)| (r, lambda, v)));
            if f.bounded {
                a.push((b.len(), lambda, -1.0));
                b.push(0.0);
            }
        }
        let first_column = lambda + usize::from(self.factor.is_some());
        for (j, d) in self.columns.iter().enumerate() {
            let col = first_column + j;
            a.extend((0..6).filter(|&k| d.column[k] != 0.0).map(|k| (6 * d.block + k, col, d.column[k])));
            if let Some((lo, hi)) = d.bounds {
                a.extend([(b.len(), col, -1.0), (b.len() + 1, col, 1.0)]);
                b.extend([-lo, hi]);
            }
        }
        cones.push(Cone::Nonnegative(b.len() - start));
        if let Some(soc) = &rows.soc {
            let nn = rows.nonneg.len();
            for p in 0..np {
                for (r, g) in soc.iter().enumerate() {
                    let row = b.len();
                    a.extend(g.iter().enumerate().filter(|e| *e.1 != 0.0).map(|(k, &v)| (row, p * c + k, v)));
                    b.push(rhs(p, nn + r));
                }
                cones.push(Cone::SecondOrder(3));
            }
        }
        let mut p_diag: Vec<f64> = (0..n).map(|j| self.p[j % c]).collect();
        let mut q: Vec<f64> = (0..n).map(|j| self.point_q.get(j).copied().unwrap_or(self.q[j % c])).collect();
        if let Some(f) = &self.factor {
            p_diag.push(0.0);
            q.push(f.cost);
        }
        p_diag.extend(self.columns.iter().map(|d| d.p));
        q.extend(self.columns.iter().map(|d| d.cost));
        let mut conic = ConicProblem { n: p_diag.len(), p_diag, q, a, b, cones };
        if let Some(crushing) = &self.crushing {
            self.crushing_rows(crushing, &mut conic);
        }
        conic
    }

    /// The biaxial stress-block cones of every interface ([`stress_block_cones`]); with
    /// [`Strength::Least`], σ is one more column (cost 1), before the cones' own.
    fn crushing_rows(&self, crushing: &Crushing, p: &mut ConicProblem) {
        let c = self.per_point();
        let normal = &self.force_map()[0];
        let strength = match crushing.strength {
            Strength::Fixed(s) => StrengthColumn::Fixed(s),
            Strength::Least => StrengthColumn::Column(p.add_column(0.0, 1.0)),
        };
        for block in crushing.blocks {
            let terms: Vec<(usize, f64, [f64; 2])> = block
                .points
                .clone()
                .flat_map(|pt| {
                    let at = [self.geometry.rho[pt][1], self.geometry.rho[pt][2]];
                    let along = block.axes.map(|a| at[0] * a[0] + at[1] * a[1]);
                    normal.iter().enumerate().filter(|e| *e.1 != 0.0).map(move |(j, &nj)| (pt * c + j, nj, along))
                })
                .collect();
            stress_block_cones(block, &terms, strength, p);
        }
    }
}

/// The strength in a problem's stress-block cones: a given σ, or σ's column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum StrengthColumn {
    Fixed(f64),
    Column(usize),
}

/// An affine form `constant + Σ coefficient × x[column]`.
type Affine = (f64, Vec<(usize, f64)>);

/// Appends the biaxial stress-block bound of one interface (module docs): `terms` are its
/// normal force's columns, each with its coefficient in N and its point's coordinates along
/// the block's two axes (the block's units). For each corner the resultant may approach —
/// (lo or hi) along each axis — X = ±(M₀ − edge₀ N) and Y = ±(M₁ − edge₁ N) (N times the
/// resultant's distance to those edges) bound N³ ≤ κ σ X Y, κ = 4 A / (L₀ L₁); as three rotated
/// cones with two new columns t₁, t₂: t₁² ≤ κ σ X, t₂² ≤ Y N, N² ≤ t₁ t₂ (exact: N⁴ ≤ t₁² t₂²
/// ≤ κ σ X Y N, and t₁ = √(κσX), t₂ = √(YN) reach it).
pub(crate) fn stress_block_cones(
    block: &StressBlock,
    terms: &[(usize, f64, [f64; 2])],
    strength: StrengthColumn,
    p: &mut ConicProblem,
) {
    let kappa = block.kappa();
    let normal: Affine = (0.0, terms.iter().map(|&(j, n, _)| (j, n)).collect());
    let distance = |k: usize, sign: f64, edge: f64| -> Affine {
        (0.0, terms.iter().map(|&(j, n, along)| (j, sign * (along[k] - edge) * n)).collect())
    };
    let half_kappa_sigma: Affine = match strength {
        StrengthColumn::Fixed(s) => (0.5 * kappa * s, Vec::new()),
        StrengthColumn::Column(col) => (0.0, vec![(col, 0.5 * kappa)]),
    };
    for (s0, e0) in [(1.0, block.lo[0]), (-1.0, block.hi[0])] {
        for (s1, e1) in [(1.0, block.lo[1]), (-1.0, block.hi[1])] {
            let (x, y) = (distance(0, s0, e0), distance(1, s1, e1));
            let t1 = p.add_column(0.0, 0.0);
            let t2 = p.add_column(0.0, 0.0);
            let scaled =
                |f: &Affine, by: f64| -> Affine { (f.0 * by, f.1.iter().map(|&(j, v)| (j, v * by)).collect()) };
            p.push_rotated_cone(&half_kappa_sigma, &x, &(0.0, vec![(t1, 1.0)]));
            p.push_rotated_cone(&scaled(&y, 0.5), &normal, &(0.0, vec![(t2, 1.0)]));
            p.push_rotated_cone(&(0.0, vec![(t1, 0.5)]), &(0.0, vec![(t2, 1.0)]), &normal);
        }
    }
}

impl ConicProblem {
    /// A new variable with quadratic weight `p` and linear cost `q`; its column.
    pub(crate) fn add_column(&mut self, p: f64, q: f64) -> usize {
        self.p_diag.push(p);
        self.q.push(q);
        self.n += 1;
        self.n - 1
    }

    /// Appends `2 a b ≥ z²` (a, b ≥ 0) as the second-order cone ((a + b)/√2, z, (a − b)/√2);
    /// the slack is b − A x, so each row holds the constant in b and minus the coefficients.
    fn push_rotated_cone(&mut self, a: &Affine, b: &Affine, z: &Affine) {
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let row = self.b.len();
        let mut put = |row: usize, f: &Affine, by: f64| {
            self.a.extend(f.1.iter().filter(|e| e.1 != 0.0).map(|&(j, v)| (row, j, -by * v)));
            by * f.0
        };
        let first = put(row, a, r) + put(row, b, r);
        let middle = put(row + 1, z, 1.0);
        let last = put(row + 2, a, r) + put(row + 2, b, -r);
        self.b.extend([first, middle, last]);
        self.cones.push(Cone::SecondOrder(3));
    }
}

/// `[f; ρ × f]`: a force's wrench about the interface origin.
pub fn wrench(rho: &[f64; 3], f: &[f64; 3]) -> [f64; 6] {
    [f[0], f[1], f[2], rho[1] * f[2] - rho[2] * f[1], rho[2] * f[0] - rho[0] * f[2], rho[0] * f[1] - rho[1] * f[0]]
}

/// The transpose of [`wrench`]: what the interface-frame rows `u` (force part, moment part)
/// see of a unit force component at `rho`, `u_f + u_m × ρ`.
pub fn motion_at(u: &[f64; 6], rho: &[f64; 3]) -> [f64; 3] {
    [u[0] + u[4] * rho[2] - u[5] * rho[1], u[1] + u[5] * rho[0] - u[3] * rho[2], u[2] + u[3] * rho[1] - u[4] * rho[0]]
}

#[cfg(test)]
mod tests {
    use super::FrictionModel;

    /// The largest |f_t| a model's rows allow in direction θ (μ f_n = 1), found from the rows
    /// as assembled: |u|, |v| ≤ 1 (box and pyramid), |u ± v| ≤ √2 (pyramid), u² + v² ≤ 1 (cone).
    fn reach(model: FrictionModel, theta: f64) -> f64 {
        let (c, s) = (theta.cos().abs(), theta.sin().abs());
        let r2 = std::f64::consts::SQRT_2;
        match model {
            FrictionModel::Cone => 1.0,
            FrictionModel::Box4 => 1.0 / c.max(s),
            FrictionModel::Pyramid8 => (1.0 / c.max(s)).min(r2 / (c + s)),
        }
    }

    #[test]
    fn max_utilization_is_the_farthest_corner_of_the_model() {
        for model in [FrictionModel::Pyramid8, FrictionModel::Cone, FrictionModel::Box4] {
            let far = (0..=7200).map(|k| reach(model, k as f64 * std::f64::consts::TAU / 7200.0)).fold(0.0, f64::max);
            assert!((far - model.max_utilization()).abs() < 1e-9, "{model}: {far} vs {}", model.max_utilization());
        }
        assert!((FrictionModel::Pyramid8.max_utilization() - 1.0823922).abs() < 1e-7);
    }
}
