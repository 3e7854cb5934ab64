//! One step's problem for one component of moving blocks (the engine's module docs state it),
//! as a general conic problem for clarabel, and its reading back.

use super::bodies::{Body, Units};
use super::contacts::{Contact, Geometry, Side};
use super::crushing::Crush;
use crate::dynamics::settings::Coulomb;
use crate::geometry::Vector3;
use crate::model::FrictionModel;
use crate::statics::{Cone, ConicProblem};

/// What every step problem of a run shares.
#[derive(Clone, Copy, Debug)]
pub(super) struct StepContext {
    pub units: Units,
    /// The time step, s.
    pub h: f64,
    pub mu: f64,
    pub model: FrictionModel,
    pub coulomb: Coulomb,
    /// The largest penetration-recovery speed, non-dimensional.
    pub recovery: f64,
    /// The compressive strength σ L² / F (non-dimensional), when the stone crushes
    /// ([`super::crushing`]).
    pub strength: Option<f64>,
}

impl StepContext {
    /// The step, non-dimensional.
    fn h(&self) -> f64 {
        self.h / self.units.time()
    }
}

/// A contact taking part in the step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Active {
    pub contact: usize,
    pub geometry: Geometry,
    /// The relative velocity the moved supports prescribe at the contact (b's against a's),
    /// m/s: it enters the step as a known part of the contact's velocity.
    pub prescribed: Vector3,
    /// The friction capacity of the round (exact Coulomb), non-dimensional force.
    pub capacity: f64,
}

/// Where the variables sit: each contact's normal force and its friction pair (when it has
/// friction this round), then 6 residual columns per body (force, then moment).
pub(super) struct Columns {
    pub normal: Vec<usize>,
    pub friction: Vec<Option<(usize, usize)>>,
    pub residual: usize,
}

pub(super) struct StepProblem {
    pub conic: ConicProblem,
    pub cols: Columns,
}

/// A capacity below this fraction of the largest is none (a cone of radius ~0 leaves the
/// interior point no interior).
const CAPACITY_FLOOR: f64 = 1e-9;

/// The variables are forces (impulses / dt) f and the momentum residual r = S⁻¹(M v⁺/dt):
/// minimise ½|r|² + Σ_p (b_p / dt) f_n,p + (w_p · f_p) / dt subject to G f − S r = −(M v/dt + w), f_n ≥ 0, f_t
/// within the round's friction set; S Sᵀ = M (S = √m I for translation, A √I for rotation, A
/// the principal axes now), b_p the gap term max(gap/dt, −recovery), w_p the relative velocity
/// the moved supports prescribe at p (in its frame).
pub(super) fn build(
    ctx: &StepContext,
    bodies: &[Body],
    comp: &[usize],
    local: &[usize],
    contacts: &[Contact],
    active: &[Active],
    crush: Option<&Crush>,
) -> StepProblem {
    let cols = columns(ctx, active);
    let h = ctx.h();
    let mut p = ConicProblem { n: cols.residual + 6 * comp.len(), ..Default::default() };
    p.p_diag = vec![0.0; cols.residual];
    p.p_diag.resize(p.n, 1.0);
    p.q = vec![0.0; p.n];
    p.b = vec![0.0; 6 * comp.len()];
    for (j, &k) in comp.iter().enumerate() {
        block_rows(ctx, &bodies[k], j, cols.residual, &mut p);
    }
    for (i, act) in active.iter().enumerate() {
        let c = &contacts[act.contact];
        let g = &act.geometry;
        let gap = g.gap / ctx.units.length;
        let known = act.prescribed / ctx.units.speed();
        p.q[cols.normal[i]] = ((gap / h).max(-ctx.recovery) + known.dot(&g.frame[0])) / h;
        let mut columns = vec![(cols.normal[i], g.frame[0])];
        if let Some((u, v)) = cols.friction[i] {
            columns.extend([(u, g.frame[1]), (v, g.frame[2])]);
            p.q[u] = known.dot(&g.frame[1]) / h;
            p.q[v] = known.dot(&g.frame[2]) / h;
        }
        for (side, sign) in [(c.a, -1.0), (c.b, 1.0)] {
            let Side::Free(k) = side else { continue };
            let row = 6 * local[k];
            let lever = (g.point - bodies[k].x) / ctx.units.length;
            for &(col, d) in &columns {
                let m = lever.cross(&d);
                for r in 0..3 {
                    p.a.push((row + r, col, sign * d[r]));
                    p.a.push((row + 3 + r, col, sign * m[r]));
                }
            }
        }
    }
    p.a.retain(|e| e.2 != 0.0);
    p.cones.push(Cone::Zero(p.b.len()));
    friction_rows(ctx, active, &cols, &mut p);
    if let Some(crush) = crush {
        let normals = active.iter().zip(&cols.normal).map(|(a, &column)| (a.contact, column));
        super::crushing::rows(crush, contacts, normals, &mut p);
    }
    StepProblem { conic: p, cols }
}

/// The capacity below which a contact has no friction columns.
pub(super) fn capacity_floor(active: &[Active]) -> f64 {
    active.iter().fold(0.0f64, |m, a| m.max(a.capacity)) * CAPACITY_FLOOR
}

fn columns(ctx: &StepContext, active: &[Active]) -> Columns {
    let floor = capacity_floor(active);
    let mut n = 0;
    let mut normal = Vec::with_capacity(active.len());
    let mut friction = Vec::with_capacity(active.len());
    for a in active {
        normal.push(n);
        n += 1;
        let has = match ctx.coulomb {
            Coulomb::Relaxed => ctx.mu > 0.0,
            Coulomb::Exact => a.capacity > floor && a.capacity > 0.0,
        };
        friction.push(has.then(|| (n, n + 1)));
        n += 2 * usize::from(has);
    }
    Columns { normal, friction, residual: n }
}

/// Body `j`'s six rows: −S r on the left, −(M v/dt + w) on the right (non-dimensional).
fn block_rows(ctx: &StepContext, body: &Body, j: usize, residual: usize, p: &mut ConicProblem) {
    let u = &ctx.units;
    let (h, row, col) = (ctx.h(), 6 * j, residual + 6 * j);
    let mass = body.mass / u.mass();
    let moments = body.moments.map(|m| m / (u.mass() * u.length * u.length));
    let axes = body.axes_now();
    let inertia = body.inertia_now() / (u.mass() * u.length * u.length);
    let v = body.v / u.speed();
    let w = body.w * u.time();
    let momentum = inertia * w;
    for r in 0..3 {
        p.a.push((row + r, col + r, -mass.sqrt()));
        for k in 0..3 {
            p.a.push((row + 3 + r, col + 3 + k, -axes[(r, k)] * moments[k].sqrt()));
        }
        p.b[row + r] = -(mass * v[r] / h + body.load[r] / u.force);
        p.b[row + 3 + r] = -(momentum[r] / h + body.load[3 + r] / (u.force * u.length));
    }
}

/// f_n ≥ 0, then the friction set: the exact round's capacity c (facets du f_u + dv f_v ≤ s c,
/// or ‖(f_u, f_v)‖ ≤ c), or the relaxed coupling with μ f_n.
fn friction_rows(ctx: &StepContext, active: &[Active], cols: &Columns, p: &mut ConicProblem) {
    let start = p.b.len();
    let relaxed = ctx.coulomb == Coulomb::Relaxed;
    for (i, a) in active.iter().enumerate() {
        let n = cols.normal[i];
        p.a.push((p.b.len(), n, -1.0));
        p.b.push(0.0);
        let Some((u, v)) = cols.friction[i] else { continue };
        for &(du, dv, s) in ctx.model.facets() {
            let row = p.b.len();
            p.a.extend([(row, u, du), (row, v, dv)].into_iter().filter(|e| e.2 != 0.0));
            if relaxed {
                p.a.push((row, n, -s * ctx.mu));
                p.b.push(0.0);
            } else {
                p.b.push(s * a.capacity);
            }
        }
    }
    p.cones.push(Cone::Nonnegative(p.b.len() - start));
    if ctx.model != FrictionModel::Cone {
        return;
    }
    for (i, a) in active.iter().enumerate() {
        let Some((u, v)) = cols.friction[i] else { continue };
        // s = b − A x = (capacity, f_u, f_v) in the second-order cone.
        let row = p.b.len();
        if relaxed {
            p.a.push((row, cols.normal[i], -ctx.mu));
            p.b.push(0.0);
        } else {
            p.b.push(a.capacity);
        }
        p.a.extend([(row + 1, u, -1.0), (row + 2, v, -1.0)]);
        p.b.extend([0.0, 0.0]);
        p.cones.push(Cone::SecondOrder(3));
    }
}

/// Per active contact, its friction force in solve `x` measured by the friction model's own
/// gauge (the least capacity whose set holds it: max over the facets of (du f_u + dv f_v)/s,
/// or |f_t| on the cone), non-dimensional; 0 without friction columns.
pub(super) fn friction_gauge(model: FrictionModel, cols: &Columns, x: &[f64]) -> Vec<f64> {
    cols.friction
        .iter()
        .map(|f| {
            let Some((u, v)) = *f else { return 0.0 };
            let (fu, fv) = (x[u], x[v]);
            match model {
                FrictionModel::Cone => fu.hypot(fv),
                _ => model.facets().iter().map(|&(du, dv, s)| (du * fu + dv * fv) / s).fold(0.0, f64::max),
            }
        })
        .collect()
}

/// A solve read back in SI units.
#[derive(Clone)]
pub(super) struct Solution {
    /// Per body of the component: the new velocity (m/s) and angular velocity (rad/s).
    pub velocities: Vec<(Vector3, Vector3)>,
    /// Per active contact: the normal force, non-dimensional, and the impulse on b, N·s.
    pub normal: Vec<f64>,
    pub impulses: Vec<Vector3>,
    /// Per active contact, the impulse on b that made `velocities`, N·s: `impulses` but where a
    /// force selection picked them (its forces keep the velocities only to its pin).
    pub work: Vec<Vector3>,
    /// ‖G f − S r + M v/dt + w‖_∞ of the solve, N.
    pub residual: f64,
}

/// The stiffness η of the force-selection solve's pin: its velocities differ from the first
/// solve's by ~η × the forces, far below `still`.
const PIN: f64 = 1e-8;

impl StepProblem {
    /// Turns the problem into its force selection (as the kinematic check's second QP): the
    /// velocities are unique but the forces are not — opposite faces can squeeze a sliding bar
    /// by any amount, a face's corners share a load any way — and an interior point returns
    /// some squeeze that would become friction capacity. So: the smallest forces (Σ f²) that
    /// keep the first solve's velocities, pinned by (1/η) ½ |r − r*|² (the new momentum
    /// columns δ = (r − r*)/√η with weight 1, the block rows' right-hand side taking in S r*:
    /// its solution's momentum columns are not the velocities), none on a contact the first
    /// solve leaves `open` (complementarity: an open contact carries nothing). `first` is in
    /// the layout of a problem whose residual columns start at `first_residual`.
    pub fn select_forces(&mut self, first: &[f64], first_residual: usize, open: &[bool]) {
        let (p, residual) = (&mut self.conic, self.cols.residual);
        // An open contact's columns leave the equilibrium: their forces are then 0.
        let mut drop = vec![false; p.n];
        for (i, _) in open.iter().enumerate().filter(|(_, o)| **o) {
            drop[self.cols.normal[i]] = true;
            if let Some((u, v)) = self.cols.friction[i] {
                drop[u] = true;
                drop[v] = true;
            }
        }
        p.a.retain(|e| !drop[e.1]);
        let block_rows = p.cones.first().map_or(0, |c| match c {
            Cone::Zero(n) => *n,
            _ => 0,
        });
        for &(row, col, v) in p.a.iter().filter(|e| e.0 < block_rows && e.1 >= residual) {
            p.b[row] -= v * first[col - residual + first_residual];
        }
        // The momentum columns as δ = (r − r*)/√η: the pin ½|δ|², weighed as the forces are (the
        // interior point's scaling then spans fewer decades: on the cross vault the selection
        // with the pin's 1/η as a weight ended short of an answer on the structured solver).
        let momentum = residual..residual + block_rows;
        let stretch = PIN.sqrt();
        p.a.iter_mut().filter(|e| momentum.contains(&e.1)).for_each(|e| e.2 *= stretch);
        // The crushing cones' auxiliary columns (after the momentum residual) stay free of cost.
        for j in 0..p.n {
            p.p_diag[j] = if j < residual || momentum.contains(&j) { 1.0 } else { 0.0 };
            p.q[j] = 0.0;
        }
    }

    pub fn read(&self, ctx: &StepContext, bodies: &[Body], comp: &[usize], active: &[Active], x: &[f64]) -> Solution {
        let u = &ctx.units;
        let h = ctx.h();
        let velocities = comp
            .iter()
            .enumerate()
            .map(|(j, &k)| {
                let b = &bodies[k];
                let r = &x[self.cols.residual + 6 * j..self.cols.residual + 6 * j + 6];
                let mass = b.mass / u.mass();
                let moments = b.moments.map(|m| m / (u.mass() * u.length * u.length));
                let v = Vector3::new(r[0], r[1], r[2]) * (h / mass.sqrt());
                let w = b.axes_now()
                    * Vector3::new(r[3] / moments[0].sqrt(), r[4] / moments[1].sqrt(), r[5] / moments[2].sqrt())
                    * h;
                (v * u.speed(), w / u.time())
            })
            .collect();
        let normal: Vec<f64> = self.cols.normal.iter().map(|&c| x[c]).collect();
        let impulses: Vec<Vector3> = active
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let f = &a.geometry.frame;
                let (fu, fv) = self.cols.friction[i].map_or((0.0, 0.0), |(cu, cv)| (x[cu], x[cv]));
                (f[0] * normal[i] + f[1] * fu + f[2] * fv) * (u.force * ctx.h)
            })
            .collect();
        let block_rows = 6 * comp.len();
        let mut rows = vec![0.0; block_rows];
        for &(row, col, v) in self.conic.a.iter().filter(|e| e.0 < block_rows) {
            rows[row] += v * x[col];
        }
        let residual = rows.iter().zip(&self.conic.b).fold(0.0f64, |m, (r, b)| m.max((r - b).abs())) * u.force;
        Solution { velocities, normal, work: impulses.clone(), impulses, residual }
    }
}
