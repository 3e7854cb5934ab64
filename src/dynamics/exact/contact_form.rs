//! A step's problem in the statics' contact form, for the structured interior-point solver:
//! each active contact one force point (an interface's vertices, sharing a frame, one
//! contact), the momentum residual r as block columns (each enters one body's six rows), the
//! friction capacities as the points' own right-hand side. The same rows, columns, weights and
//! costs as the general conic problem of [`super::problem::build`], read from it; the answer is
//! written back in its column layout. Where some contacts have friction columns and some not (a capacity below
//! the floor), the latter get them here with the floor's capacity — friction of 1e-9 of the
//! largest capacity, below every tolerance — so every point has the same variables; their
//! friction is dropped in the answer. Crushing cones stay on clarabel, and so does a solve the
//! structured solver ends short of an answer.

use super::bodies::Body;
use super::contacts::{Contact, Side as ContactSide};
use super::problem::{Active, Columns, StepContext, capacity_floor};
use crate::dynamics::settings::Coulomb;
use crate::model::FrictionModel;
use crate::statics::{
    Accuracy, Backend, BlockColumn, ConicOutcome, ConicProblem, Contact as Points, ContactProblem, Geometry, PointRows,
    Side, SolverStatus, Var, Warm, WarmStart, solve_contact_problem,
};
use nalgebra::{Matrix6, Vector6};

/// What the contact form needs beside the conic problem: the step's bodies and contacts, and
/// which active contacts take part (the force selection leaves the open ones out).
pub(super) struct StepData<'a> {
    pub ctx: &'a StepContext,
    pub bodies: &'a [Body],
    pub comp: &'a [usize],
    pub local: &'a [usize],
    pub contacts: &'a [Contact],
    pub active: &'a [Active],
    pub cols: &'a Columns,
    pub taking_part: &'a [bool],
}

/// Solves `conic` (built from `data`) on the structured solver, from `warm` when given (a
/// previous solve's iterate of the same layout), and the iterate it keeps for the next;
/// `None` when its shape is not the contact form's (the caller then runs clarabel). A solve
/// that ends short of an answer returns its status and keeps no iterate.
pub(super) fn solve(
    data: &StepData,
    conic: &ConicProblem,
    acc: Accuracy,
    max_iter: u32,
    warm: Option<&WarmStart>,
) -> Option<(ConicOutcome, Option<WarmStart>)> {
    let t = std::time::Instant::now();
    // Columns beyond the residual's are the crushing cones'.
    if conic.n != data.cols.residual + 6 * data.comp.len() {
        return None;
    }
    let points: Vec<usize> = (0..data.active.len()).filter(|&i| data.taking_part[i]).collect();
    if points.is_empty() {
        return without_contacts(data, conic, t).map(|out| (out, None));
    }
    let per_point = if points.iter().any(|&i| data.cols.friction[i].is_some()) { 3 } else { 1 };
    let geometry = geometry(data, conic, &points);
    let rows = point_rows(data.ctx, per_point);
    let q = |c: Option<usize>| c.map_or(0.0, |c| conic.q[c]);
    let cp = ContactProblem {
        geometry: &geometry,
        vars: [Var::CnPos, Var::Cu, Var::Cv][..per_point].to_vec(),
        model: data.ctx.model,
        mu: data.ctx.mu,
        p: uniform_weights(data, conic, &points, per_point)?,
        q: vec![0.0; per_point],
        budgets: Vec::new(),
        factor: None,
        threads: 1,
        crushing: None,
        columns: residual_columns(data, conic),
        point_q: points.iter().flat_map(|&i| point_columns(data, i, per_point).map(q)).collect(),
        point_b: point_b(data, &points, &rows),
        rows: Some(rows),
    };
    let warm = warm.map_or(Warm::Keep, Warm::From);
    let (out, kept) = solve_contact_problem(&cp, Backend::Structured, acc, max_iter, warm);
    if out.backend != Backend::Structured {
        return None;
    }
    let answered = out.status.solved();
    let kept = kept.filter(|_| answered);
    let mut x = vec![0.0; conic.n];
    for (j, &i) in points.iter().enumerate() {
        for (k, c) in point_columns(data, i, per_point).enumerate() {
            if let Some(c) = c {
                x[c] = out.x[j * per_point + k];
            }
        }
    }
    let first = points.len() * per_point;
    x[data.cols.residual..].copy_from_slice(&out.x[first..first + conic.n - data.cols.residual]);
    let out = ConicOutcome {
        status: out.status,
        x,
        z: Vec::new(),
        objective: out.objective,
        iterations: out.iterations,
        convert_seconds: 0.0,
        solver_seconds: t.elapsed().as_secs_f64(),
    };
    Some((out, kept))
}

/// A problem in which no contact takes part (a force selection whose contacts all open): each
/// body's six rows hold its six residual columns alone, so the residual is their solution
/// (no solve); the contacts' forces are zero.
fn without_contacts(data: &StepData, conic: &ConicProblem, t: std::time::Instant) -> Option<ConicOutcome> {
    let columns = residual_columns(data, conic);
    let mut x = vec![0.0; conic.n];
    for (j, body) in columns.chunks(6).enumerate() {
        let m = Matrix6::from_fn(|r, c| body[c].column[r]);
        let b = Vector6::from_column_slice(&conic.b[6 * j..6 * j + 6]);
        let r = m.lu().solve(&b)?;
        x[data.cols.residual + 6 * j..][..6].copy_from_slice(r.as_slice());
    }
    let objective = columns.iter().zip(&x[data.cols.residual..]).map(|(c, r)| 0.5 * c.p * r * r + c.cost * r).sum();
    Some(ConicOutcome {
        status: SolverStatus::Solved,
        x,
        z: Vec::new(),
        objective,
        iterations: 0,
        convert_seconds: 0.0,
        solver_seconds: t.elapsed().as_secs_f64(),
    })
}

/// Contact `i`'s columns in the conic problem: its normal force, then its friction pair (None
/// when it has none there).
fn point_columns(data: &StepData, i: usize, per_point: usize) -> impl Iterator<Item = Option<usize>> {
    let n = data.cols.normal[i];
    let (u, v) = data.cols.friction[i].unzip();
    [Some(n), u, v].into_iter().take(per_point)
}

/// The block rows' right-hand side, and the taking-part contacts as force points: each run of
/// them with the same two sides and the same frame (an interface's vertices) one contact at
/// its first point, so that its points are summed in that frame once.
fn geometry(data: &StepData, conic: &ConicProblem, points: &[usize]) -> Geometry {
    let length = data.ctx.units.length;
    let blocks = data.comp.len();
    let mut contacts: Vec<Points> = Vec::new();
    let mut rho = Vec::with_capacity(points.len());
    let mut origin = None;
    for (j, &i) in points.iter().enumerate() {
        let act = &data.active[i];
        let c = &data.contacts[act.contact];
        let frame = act.geometry.frame;
        let joins = j > 0 && {
            let prev = &data.active[points[j - 1]];
            let p = &data.contacts[prev.contact];
            (p.a, p.b) == (c.a, c.b) && prev.geometry.frame == frame
        };
        if !joins {
            let o = act.geometry.point;
            let axes = frame.map(|d| [d.x, d.y, d.z]);
            let side = |s: ContactSide, sign: f64| match s {
                ContactSide::Free(k) => {
                    let arm = (o - data.bodies[k].x) / length;
                    Some(Side::new(data.local[k], axes, [arm.x, arm.y, arm.z], sign))
                }
                _ => None,
            };
            contacts.push(Points { points: j..j, sides: [side(c.a, -1.0), side(c.b, 1.0)] });
            origin = Some(o);
        }
        let o = origin.expect("a contact starts at the run's first point");
        let d = (act.geometry.point - o) / length;
        rho.push([frame[0].dot(&d), frame[1].dot(&d), frame[2].dot(&d)]);
        contacts.last_mut().expect("a contact per run").points.end = j + 1;
    }
    Geometry { blocks, rhs: conic.b[..6 * blocks].to_vec(), contacts, rho }
}

/// Every point's rows (the general problem's friction rows): f_n ≥ 0, then the friction set —
/// the round's capacity c (facets du f_u + dv f_v ≤ s c, or ‖(f_u, f_v)‖ ≤ c: the capacity in
/// the right-hand side) or the relaxed coupling with μ f_n.
fn point_rows(ctx: &StepContext, per_point: usize) -> PointRows {
    let mut nonneg = vec![[-1.0, 0.0, 0.0][..per_point].to_vec()];
    if per_point == 1 {
        return PointRows { nonneg, soc: None };
    }
    let mu = if ctx.coulomb == Coulomb::Relaxed { ctx.mu } else { 0.0 };
    nonneg.extend(ctx.model.facets().iter().map(|&(du, dv, s)| vec![-s * mu, du, dv]));
    let soc =
        (ctx.model == FrictionModel::Cone).then(|| [vec![-mu, 0.0, 0.0], vec![0.0, -1.0, 0.0], vec![0.0, 0.0, -1.0]]);
    PointRows { nonneg, soc }
}

/// The points' rows' right-hand side: the exact round's capacities (zero when relaxed).
fn point_b(data: &StepData, points: &[usize], rows: &PointRows) -> Vec<f64> {
    let frictionless = rows.nonneg.len() == 1 && rows.soc.is_none();
    if frictionless || data.ctx.coulomb == Coulomb::Relaxed {
        return Vec::new();
    }
    let facets = data.ctx.model.facets();
    let floor = capacity_floor(data.active);
    points
        .iter()
        .flat_map(|&i| {
            let c = if data.cols.friction[i].is_some() { data.active[i].capacity } else { floor };
            let soc = rows.soc.as_ref().map(|_| [c, 0.0, 0.0]);
            std::iter::once(0.0).chain(facets.iter().map(move |&(_, _, s)| s * c)).chain(soc.into_iter().flatten())
        })
        .collect()
}

/// The quadratic weight of each of a point's variables, the same at every point (else `None`;
/// friction columns the conic problem lacks take their normal's).
fn uniform_weights(data: &StepData, conic: &ConicProblem, points: &[usize], per_point: usize) -> Option<Vec<f64>> {
    let weights = |i: usize| {
        let normal = conic.p_diag[data.cols.normal[i]];
        point_columns(data, i, per_point).map(move |c| c.map_or(normal, |c| conic.p_diag[c]))
    };
    let first: Vec<f64> = weights(points[0]).collect();
    points.iter().all(|&i| weights(i).eq(first.iter().copied())).then_some(first)
}

/// The momentum residual's columns: each one body's, with its entries in that body's rows.
fn residual_columns(data: &StepData, conic: &ConicProblem) -> Vec<BlockColumn> {
    let start = data.cols.residual;
    let mut columns: Vec<BlockColumn> = (0..conic.n - start)
        .map(|j| BlockColumn {
            block: j / 6,
            column: [0.0; 6],
            p: conic.p_diag[start + j],
            cost: conic.q[start + j],
            bounds: None,
        })
        .collect();
    for &(row, col, v) in conic.a.iter().filter(|e| e.1 >= start && e.0 < 6 * data.comp.len()) {
        let c = &mut columns[col - start];
        c.column[row - 6 * c.block] += v;
    }
    columns
}
