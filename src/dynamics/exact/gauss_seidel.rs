//! The contacts' states by nonsmooth Gauss–Seidel, where the last step's states do not settle.
//!
//! Moreau–Jean's scheme as LMGC90 and Siconos (NSGS) solve a step's frictional contacts: one
//! contact at a time, the others' impulses held, each contact's exact-Coulomb problem in its own
//! 3 × 3 Delassus block W = H M⁻¹ Hᵀ (frame n, u, v; velocities m/s, impulses N·s on b) —
//! v = W r + q with q the velocity the rest of the step gives it (its gap term and a moved
//! side's velocity included): open where q_n ≥ 0; else sticking (v = 0) where that impulse lies
//! in the friction set; else sliding (v_n = 0) with friction at a facet of the polygon (the slip
//! along the facet's normal only) or at a vertex (the slip within the vertex's cone of normals).
//! The sweeps start from the last step's forces and stop when no impulse changes by more than
//! [`SETTLED`] of the largest, or after [`SWEEPS`].
//!
//! Its answer is not the step's: a sweep's convergence is linear and slow on a chain of blocks.
//! It gives each contact its state and a split of a face's forces among its points in which every
//! point's friction lies within its own set — the two things the states' passes
//! ([`super::active_set`]) search for where contacts land or a face's points share its load —
//! and the states' step, its multipliers started from these impulses, finishes it exactly.
//! Polygonal friction sets only (pyramid8, box4); the cone keeps the interior point.

use super::World;
use super::active_set::gauge;
use super::component::Component;
use super::contacts::State;
use super::problem::Active;
use crate::geometry::Vector3;
use crate::model::FrictionModel;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector6};
use std::f64::consts::PI;

/// Sweeps over the contacts before the states are read.
const SWEEPS: usize = 100;

/// A sweep whose largest impulse change is this fraction of the largest impulse has settled.
const SETTLED: f64 = 1e-6;

/// Round-off allowed in a local case's sign conditions, relative to the quantities compared.
const EPS: f64 = 1e-12;

/// One body's part of a contact point: its index in the component, the point's three rows
/// (n, u, v) on it, and M⁻¹ times each.
struct BodyPart {
    body: usize,
    rows: [Vector6<f64>; 3],
    pushed: [Vector6<f64>; 3],
}

/// One contact point: its three generalized rows (n, u, v) on at most two bodies, each body's
/// M⁻¹ Hᵀ (6 × 3), its Delassus block, and the velocity offset of its rows.
struct Point {
    parts: Vec<BodyPart>,
    delassus: Matrix3<f64>,
    bias: Vector3,
}

impl Point {
    /// H u + bias: the contact's velocity in its frame.
    fn velocity(&self, u: &nalgebra::DVector<f64>) -> Vector3 {
        let mut v = self.bias;
        for part in &self.parts {
            let s = u.fixed_rows::<6>(6 * part.body);
            for (vk, row) in v.iter_mut().zip(&part.rows) {
                *vk += row.dot(&s);
            }
        }
        v
    }

    /// u += M⁻¹ Hᵀ Δr.
    fn apply(&self, u: &mut nalgebra::DVector<f64>, dr: &Vector3) {
        for part in &self.parts {
            let mut s = u.fixed_rows_mut::<6>(6 * part.body);
            for (d, pushed) in dr.iter().zip(&part.pushed) {
                s.axpy(*d, pushed, 1.0);
            }
        }
    }
}

impl World {
    /// Each active contact's state and impulse (N·s on b, world axes) after Gauss–Seidel sweeps
    /// of the moving component's step (module docs); None for the cone.
    pub(super) fn states_by_gauss_seidel(
        &self,
        comp: &[usize],
        local: &[usize],
        active: &[Active],
    ) -> Option<(Vec<State>, Vec<Vector3>)> {
        let sides = match self.ctx.model {
            FrictionModel::Cone => return None,
            m => m.facets().len(),
        };
        let (h, mu) = (self.ctx.h, self.ctx.mu);
        let parts = Component::new(&self.bodies, comp, local, h);
        let points: Vec<Point> = active.iter().map(|a| self.point(&parts, a)).collect();
        let mut r: Vec<Vector3> = active
            .iter()
            .map(|a| {
                let g = self.contacts[a.contact].last_force * h;
                let f = &a.geometry.frame;
                Vector3::new(g.dot(&f[0]), g.dot(&f[1]), g.dot(&f[2]))
            })
            .collect();
        let mut u = parts.solve_mass(&parts.free);
        for (p, ri) in points.iter().zip(&r) {
            p.apply(&mut u, ri);
        }
        let mut states = vec![State::Open; active.len()];
        for _ in 0..SWEEPS {
            let (mut change, mut largest) = (0.0f64, 0.0f64);
            for ((p, ri), state) in points.iter().zip(r.iter_mut()).zip(states.iter_mut()) {
                let q = p.velocity(&u) - p.delassus * *ri;
                let (next, s) = local_coulomb(&p.delassus, &q, mu, sides, *state);
                let dr = next - *ri;
                p.apply(&mut u, &dr);
                change = change.max(dr.amax());
                largest = largest.max(next.amax());
                *ri = next;
                *state = s;
            }
            if change <= SETTLED * largest {
                break;
            }
        }
        let impulses =
            active.iter().zip(&r).map(|(a, ri)| a.geometry.frame.iter().zip(ri.iter()).map(|(d, x)| d * *x).sum());
        Some((states, impulses.collect()))
    }

    /// Contact `a`'s rows, pushes, Delassus block and velocity offset in component `parts`.
    fn point(&self, parts: &Component, a: &Active) -> Point {
        let c = &self.contacts[a.contact];
        let f = &a.geometry.frame;
        let rows = f.map(|d| parts.sparse_row(c.a, c.b, &a.geometry.point, &d));
        let mut out: Vec<BodyPart> = Vec::new();
        for (k, row_k) in rows.iter().enumerate() {
            for (j, row) in row_k.iter() {
                let at = match out.iter().position(|p| p.body == *j) {
                    Some(at) => at,
                    None => {
                        out.push(BodyPart { body: *j, rows: [Vector6::zeros(); 3], pushed: [Vector6::zeros(); 3] });
                        out.len() - 1
                    }
                };
                out[at].rows[k] = *row;
                out[at].pushed[k] = parts.inverse_mass(*j, row);
            }
        }
        let delassus = Matrix3::from_fn(|i, k| out.iter().map(|p| p.rows[i].dot(&p.pushed[k])).sum());
        let recovery = self.ctx.recovery * self.ctx.units.speed();
        let gap_term = (a.geometry.gap / self.ctx.h).max(-recovery);
        let bias = Vector3::new(gap_term + a.prescribed.dot(&f[0]), a.prescribed.dot(&f[1]), a.prescribed.dot(&f[2]));
        Point { parts: out, delassus, bias }
    }
}

/// One contact's exact-Coulomb impulse (n, u, v) for v = W r + q on a regular polygon of
/// `sides` facets at distance μ r_n, and its state: the first case whose conditions hold
/// (open, stick, the slide of the contact's last state `last`, a facet's slide, a vertex's
/// slide — a contact mostly keeps its case from sweep to sweep); where round-off leaves none,
/// the stick's impulse brought into the set.
fn local_coulomb(w: &Matrix3<f64>, q: &Vector3, mu: f64, sides: usize, last: State) -> (Vector3, State) {
    if q.x >= 0.0 {
        return (Vector3::zeros(), State::Open);
    }
    let spacing = 2.0 * PI / sides as f64;
    let stick = w.cholesky().map(|c| -c.solve(q));
    if let Some(r) = stick
        && r.x >= 0.0
        && gauge(Some(sides), (r.y, r.z)) <= mu * r.x * (1.0 + EPS)
    {
        return (r, State::Stick);
    }
    if let State::Slide { angle } = last {
        let k = angle / spacing;
        let found = if (k - k.round()).abs() < 1e-9 {
            facet_slide(w, q, mu, angle, spacing)
        } else {
            vertex_slide(w, q, mu, angle, spacing)
        };
        if let Some(found) = found {
            return found;
        }
    }
    for k in 0..sides {
        if let Some(found) = facet_slide(w, q, mu, k as f64 * spacing, spacing) {
            return found;
        }
    }
    for k in 0..sides {
        if let Some(found) = vertex_slide(w, q, mu, (k as f64 + 0.5) * spacing, spacing) {
            return found;
        }
    }
    let r = stick.unwrap_or_else(Vector3::zeros);
    let n = r.x.max(0.0);
    let g = gauge(Some(sides), (r.y, r.z));
    let scale = if g > mu * n { mu * n / g } else { 1.0 };
    let angle = (r.z.atan2(r.y) / spacing).round() * spacing;
    (Vector3::new(n, r.y * scale, r.z * scale), if n > 0.0 { State::Slide { angle } } else { State::Open })
}

/// Sliding with friction on the facet whose normal points at `angle`: r = r_n (n + μ d) + β t,
/// v_n = 0 and the slip along −d only; None where r_n < 0, β beyond the facet or the slip
/// along +d.
fn facet_slide(w: &Matrix3<f64>, q: &Vector3, mu: f64, angle: f64, spacing: f64) -> Option<(Vector3, State)> {
    let (c, s) = (angle.cos(), angle.sin());
    let f = Vector3::new(1.0, mu * c, mu * s);
    let t = Vector3::new(0.0, -s, c);
    let n = Vector3::x();
    let a = Matrix2::new(n.dot(&(w * f)), n.dot(&(w * t)), t.dot(&(w * f)), t.dot(&(w * t)));
    let x = a.lu().solve(&Vector2::new(-q.x, -q.dot(&t)))?;
    let (rn, beta) = (x.x, x.y);
    let half = mu * rn * (0.5 * spacing).tan();
    let r = f * rn + t * beta;
    let v = w * r + q;
    let along = v.y * c + v.z * s;
    let ok = rn >= 0.0 && beta.abs() <= half * (1.0 + EPS) + EPS * rn && along <= EPS * v.norm();
    ok.then_some((r, State::Slide { angle }))
}

/// Sliding with friction at the vertex at `angle` (radius 1 / cos(π/n) of a unit-distance
/// polygon): v_n = 0 and −v_t within the cone of the two facet normals beside it; None where
/// r_n < 0 or the slip leaves that cone.
fn vertex_slide(w: &Matrix3<f64>, q: &Vector3, mu: f64, angle: f64, spacing: f64) -> Option<(Vector3, State)> {
    let radius = 1.0 / (0.5 * spacing).cos();
    let f = Vector3::new(1.0, mu * radius * angle.cos(), mu * radius * angle.sin());
    let wf = w * f;
    if wf.x <= 0.0 {
        return None;
    }
    let rn = -q.x / wf.x;
    let r = f * rn;
    let v = w * r + q;
    let (a0, a1) = (angle - 0.5 * spacing, angle + 0.5 * spacing);
    let cone = Matrix2::new(a0.cos(), a1.cos(), a0.sin(), a1.sin());
    let x = cone.lu().solve(&Vector2::new(-v.y, -v.z))?;
    let slack = EPS * v.norm();
    (rn >= 0.0 && x.x >= -slack && x.y >= -slack).then_some((r, State::Slide { angle }))
}

#[cfg(test)]
mod tests {
    //! Invariant: each local case's answer meets the exact-Coulomb conditions of its state —
    //! checked on W = I, where they reduce to closed forms.
    use super::*;

    #[test]
    fn local_cases_on_the_identity() {
        let w = Matrix3::identity();
        // Separating: open.
        let (r, s) = local_coulomb(&w, &Vector3::new(1.0, 3.0, 0.0), 0.5, 8, State::Open);
        assert_eq!((r, s), (Vector3::zeros(), State::Open));
        // Approaching slowly along the tangent: r = −q, friction 0.2 ≤ μ·1.
        let (r, s) = local_coulomb(&w, &Vector3::new(-1.0, 0.2, 0.0), 0.5, 8, State::Open);
        assert_eq!(s, State::Stick);
        assert!((r - Vector3::new(1.0, -0.2, 0.0)).norm() < 1e-15);
        // Fast slip along +u: friction at the facet facing −u, r_n = 1, friction μ, slip 3 − μ.
        let (r, s) = local_coulomb(&w, &Vector3::new(-1.0, 3.0, 0.0), 0.5, 8, State::Open);
        assert_eq!(s, State::Slide { angle: PI });
        assert!((r - Vector3::new(1.0, -0.5, 0.0)).norm() < 1e-12, "{r:?}");
        // Slip at 22.5° + 180° on pyramid8: at the vertex between the facets at 180° and 225°.
        let a = PI / 8.0;
        let (r, s) = local_coulomb(&w, &Vector3::new(-1.0, 3.0 * a.cos(), 3.0 * a.sin()), 0.5, 8, State::Open);
        assert!(matches!(s, State::Slide { angle } if (angle - (PI + a)).abs() < 1e-12), "{s:?}");
        assert!((r.x - 1.0).abs() < 1e-12 && (gauge(Some(8), (r.y, r.z)) - 0.5).abs() < 1e-12, "{r:?}");
        // The last state only orders the search: a right one, a wrong facet or a wrong vertex
        // give the same case.
        let q = Vector3::new(-1.0, 3.0 * a.cos(), 3.0 * a.sin());
        for last in [State::Slide { angle: PI + a }, State::Slide { angle: 0.0 }, State::Slide { angle: a }] {
            assert_eq!(local_coulomb(&w, &q, 0.5, 8, last), (r, s), "{last:?}");
        }
    }
}
