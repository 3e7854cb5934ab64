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
//! [`SETTLED`] of the largest, or when, checked every [`CHECK_EVERY`] sweeps, every contact's
//! conditions hold on their answer to [`CONDITIONS`] of the largest impulse (impulses may still
//! move among a face's redundant points, which moves no velocity), or after [`SWEEPS`]; either
//! way only where the contacts' work on the blocks' motion creates no energy beyond round-off
//! ([`ENERGY`]: a sweep's answer is not exact, and a push on parting faces would feed the motion).
//!
//! A sweep's convergence is linear and slow on a chain of blocks, so its answer first serves as
//! a start: it gives each contact its state and a split of a face's forces among its points in
//! which every point's friction lies within its own set — the two things the states' passes
//! ([`super::active_set`]) search for where contacts land or a face's points share its load —
//! and the states' step, its multipliers started from these impulses, finishes it exactly.
//! Where those passes do not settle (a face landing whose rows hold only with one of its points
//! open, which their block changes miss) but the sweeps did, the sweeps' answer is the step's:
//! each contact's conditions then hold to [`SETTLED`] of the largest impulse with the others'
//! impulses as they ended (or to [`CONDITIONS`] of it, checked), and the momentum exactly
//! (every impulse change is applied to the velocities as it is made) — as close to the
//! exact-Coulomb step as the Tresca rounds' own settling (1e-4 of the largest capacity), at no
//! interior-point solve.
//! Polygonal friction sets only (pyramid8, box4); the cone keeps the interior point.

use super::World;
use super::active_set::gauge;
use super::component::Component;
use super::contacts::State;
use super::problem::{Active, Solution};
use crate::geometry::Vector3;
use crate::model::FrictionModel;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector6};
use std::f64::consts::PI;

/// Sweeps over the contacts before the states are read.
const SWEEPS: usize = 100;

/// A sweep whose largest impulse change is this fraction of the largest impulse has settled.
const SETTLED: f64 = 1e-6;

/// Sweeps between checks of the step's conditions on the sweeps' answer ([`conditions_hold`]).
const CHECK_EVERY: usize = 10;

/// The step's conditions hold on the sweeps' answer to this fraction of the largest impulse
/// (a speed: that impulse's on the component's mass): the tolerance their test states.
const CONDITIONS: f64 = 1e-5;

/// A slipping contact's friction dissipates at least this fraction less than the most its set
/// allows.
const DISSIPATION: f64 = 1e-4;

/// A settled answer's contacts may create this fraction of the largest impulse's kinetic energy
/// on the component's mass (J: round-off), no more.
const ENERGY: f64 = 1e-8;

/// Round-off allowed in a local case's sign conditions, relative to the quantities compared.
const EPS: f64 = 1e-12;

/// What the sweeps give: each contact's state and impulse (N·s on b, world axes), and where
/// they settled, the step's answer (its velocities, normal forces non-dimensional).
pub(super) struct Sweeps {
    pub states: Vec<State>,
    pub impulses: Vec<Vector3>,
    pub settled: Option<Solution>,
}

/// One body's part of a contact point: its index in the component, the point's three rows
/// (n, u, v) on it, and M⁻¹ times each.
pub(super) struct BodyPart {
    pub(super) body: usize,
    pub(super) rows: [Vector6<f64>; 3],
    pub(super) pushed: [Vector6<f64>; 3],
}

/// One contact point: its three generalized rows (n, u, v) on at most two bodies, each body's
/// M⁻¹ Hᵀ (6 × 3), its Delassus block, and the velocity offset of its rows.
pub(super) struct Point {
    pub(super) parts: Vec<BodyPart>,
    delassus: Matrix3<f64>,
    bias: Vector3,
    /// The gap term within `bias`'s normal part, m/s: not a velocity of the blocks.
    gap_term: f64,
}

impl Point {
    /// H u + bias: the contact's velocity in its frame.
    pub(super) fn velocity(&self, u: &nalgebra::DVector<f64>) -> Vector3 {
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
    /// Each active contact's state and impulse after Gauss–Seidel sweeps of the moving
    /// component's step, and the answer where they settled (module docs); None for the cone.
    pub(super) fn states_by_gauss_seidel(&self, comp: &[usize], local: &[usize], active: &[Active]) -> Option<Sweeps> {
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
        let mut settled = false;
        let mass: f64 = comp.iter().map(|&k| self.bodies[k].mass).sum();
        let floor = mass * self.ctx.units.g * h;
        for sweep in 0..SWEEPS {
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
            // Impulses can still move among a face's redundant points (no velocity moves with
            // them) where every contact's conditions already hold.
            let by_change = change <= SETTLED * largest;
            if by_change || sweep % CHECK_EVERY == CHECK_EVERY - 1 {
                let v: Vec<Vector3> = points.iter().map(|p| p.velocity(&u)).collect();
                let scale = (largest.max(floor), mass);
                let holds = by_change || conditions_hold(&v, &r, (mu, sides), scale);
                if holds && creates_no_energy(&points, &v, &r, scale) {
                    settled = true;
                    break;
                }
            }
        }
        let impulses: Vec<Vector3> = active
            .iter()
            .zip(&r)
            .map(|(a, ri)| a.geometry.frame.iter().zip(ri.iter()).map(|(d, x)| d * *x).sum())
            .collect();
        let settled = settled.then(|| {
            let normal = r.iter().map(|ri| ri.x / (h * self.ctx.units.force)).collect();
            self.solution(&parts, active, &u, normal, impulses.clone())
        });
        Some(Sweeps { states, impulses, settled })
    }

    /// Contact `a`'s rows, pushes, Delassus block and velocity offset in component `parts`.
    pub(super) fn point(&self, parts: &Component, a: &Active) -> Point {
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
        Point { parts: out, delassus, bias, gap_term }
    }
}

/// Whether the sweeps' impulses `r` and the contacts' velocities `v` (per contact, in its
/// frame, gap terms included) meet every contact's exact-Coulomb conditions to [`CONDITIONS`]
/// of the `largest` impulse (speeds: that impulse on the component's `mass`): no closing, no
/// push where it opens, and a slip's friction dissipating the most its polygon (μ r_n, `sides`
/// facets) allows, to [`DISSIPATION`]. The friction set holds by each local case; the momentum
/// by every change applied as made.
fn conditions_hold(v: &[Vector3], r: &[Vector3], (mu, sides): (f64, usize), (largest, mass): (f64, f64)) -> bool {
    let speed = CONDITIONS * largest / mass;
    let spacing = 2.0 * PI / sides as f64;
    // The polygon's vertices lie half a facet round from its facets' normals, at 1 / cos of it.
    let (s, c) = (0.5 * spacing).sin_cos();
    v.iter().zip(r).all(|(v, r)| {
        if v.x < -speed || (r.x > CONDITIONS * largest && v.x > speed) {
            return false;
        }
        if v.y.hypot(v.z) <= speed {
            return true;
        }
        let dissipated = -(r.y * v.y + r.z * v.z);
        // The most −v_t · t over the set: its support at −v_t, by the facets' gauge turned.
        let (x, y) = (-v.y, -v.z);
        let most = mu * r.x * gauge(Some(sides), (x * c + y * s, y * c - x * s)) / c;
        dissipated >= most * (1.0 - DISSIPATION)
    })
}

/// Whether the contacts' work on the blocks' motion (their impulses `r` against their
/// velocities `v`, per contact in its frame, each point's gap term aside) creates no energy
/// beyond [`ENERGY`] × `largest`² / `mass`.
fn creates_no_energy(points: &[Point], v: &[Vector3], r: &[Vector3], (largest, mass): (f64, f64)) -> bool {
    let work: f64 = points.iter().zip(v).zip(r).map(|((p, v), r)| -(v - Vector3::x() * p.gap_term).dot(r)).sum();
    work >= -ENERGY * largest * largest / mass
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
    //! Invariants: each local case's answer meets the exact-Coulomb conditions of its state —
    //! checked on W = I, where they reduce to closed forms; and where the sweeps settle, their
    //! answer is a step of the exact-Coulomb problem: the momentum balance to round-off, every
    //! contact's Signorini condition and friction set, and a slipping contact's friction at
    //! its set's edge against the slip, to the settling tolerance.
    use super::*;
    use crate::dynamics::{DropSettings, Engine};
    use crate::geometry::{Mesh, Point3};
    use crate::model::{Assembly, Block, Scene};

    /// A 0.4 × 0.3 × 0.2 m block turned 4° about x and 3° about y, its lowest corner 5 mm
    /// above the ground plane: it lands on a corner, an edge, then a face.
    fn tilted_block() -> Assembly {
        let q = nalgebra::UnitQuaternion::from_euler_angles(4f64.to_radians(), 3f64.to_radians(), 0.0);
        let mesh = Mesh::cuboid(Point3::new(-0.2, -0.15, -0.1), Point3::new(0.2, 0.15, 0.1))
            .map_points(|p| Point3::from(q * p.coords));
        let lowest = mesh.vertices.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        let mesh = mesh.map_points(|p| Point3::new(p.x, p.y, p.z - lowest + 0.005));
        let mut scene = Scene::new("tilted", vec![Block::new("block", mesh)]);
        scene.ground = true;
        Assembly::new(&scene, &Default::default()).expect("a valid scene")
    }

    #[test]
    fn a_settled_answer_meets_the_step_conditions() {
        let asm = tilted_block();
        let settings = DropSettings { engine: Engine::Exact, ..Default::default() };
        let mut world = World::new(&asm, &settings);
        let (h, mu) = (world.ctx.h, world.ctx.mu);
        let mut checked = 0;
        for _ in 0..240 {
            world.step();
            let near = world.near_contacts(&[]);
            for comp in world.components(&near) {
                let mut local = vec![usize::MAX; world.bodies.len()];
                comp.iter().enumerate().for_each(|(j, &k)| local[k] = j);
                let active: Vec<Active> = near
                    .iter()
                    .filter(|a| comp.iter().any(|&k| world.contacts[a.contact].touches(k)))
                    .copied()
                    .collect();
                let Some(Sweeps { settled: Some(sol), .. }) = world.states_by_gauss_seidel(&comp, &local, &active)
                else {
                    continue;
                };
                let parts = Component::new(&world.bodies, &comp, &local, h);
                let mut momentum = parts.mass_times(&sol_vector(&sol)) - &parts.free;
                // Impulses against the largest, or the weight's over the step where all are ~0.
                let mass: f64 = comp.iter().map(|&k| world.bodies[k].mass).sum();
                let largest = sol.impulses.iter().map(|r| r.norm()).fold(mass * world.ctx.units.g * h, f64::max);
                let speed = 1e-5 * largest / mass;
                for (a, r) in active.iter().zip(&sol.impulses) {
                    let c = &world.contacts[a.contact];
                    let f = &a.geometry.frame;
                    parts.sparse_row(c.a, c.b, &a.geometry.point, r).add_to(&mut momentum, -1.0);
                    let rel = super::super::component::relative_velocity(
                        &parts,
                        c.a,
                        c.b,
                        &a.geometry.point,
                        &sol_vector(&sol),
                    ) + a.prescribed;
                    let (rn, rt) = (r.dot(&f[0]), (r.dot(&f[1]), r.dot(&f[2])));
                    let vn = rel.dot(&f[0]) + (a.geometry.gap / h).max(0.0);
                    let vt = rel - f[0] * rel.dot(&f[0]);
                    assert!(rn >= -1e-12 * largest && vn >= -speed, "Signorini: r_n {rn:e}, v_n {vn:e}");
                    assert!(rn <= 1e-5 * largest || vn <= speed, "complementarity: r_n {rn:e}, v_n {vn:e}");
                    let friction = gauge(Some(8), rt);
                    assert!(friction <= mu * rn * (1.0 + 1e-6) + 1e-9 * largest, "friction {friction:e} > μ r_n");
                    if vt.norm() > speed {
                        let against = f[1] * rt.0 + f[2] * rt.1;
                        assert!(
                            friction >= mu * rn * (1.0 - 1e-4) && against.dot(&vt) <= 0.0,
                            "a slip without its friction"
                        );
                    }
                }
                assert!(momentum.amax() <= 1e-9 * largest, "momentum {:e}", momentum.amax());
                checked += usize::from(sol.normal.iter().any(|&n| n > 0.0));
            }
        }
        assert!(checked >= 10, "only {checked} settled answers with contact forces checked");
    }

    /// A solution's velocities as the component's vector (6 per body).
    fn sol_vector(sol: &Solution) -> nalgebra::DVector<f64> {
        nalgebra::DVector::from_iterator(
            6 * sol.velocities.len(),
            sol.velocities.iter().flat_map(|(v, w)| [v.x, v.y, v.z, w.x, w.y, w.z]),
        )
    }

    /// One contact on one body whose linear velocity is its (n, u, v) velocity: W = I, the
    /// contact's velocity its bias plus the body's velocity.
    fn lone_point(gap_term: f64) -> Point {
        let unit = |k: usize| Vector6::from_fn(|i, _| if i == k { 1.0 } else { 0.0 });
        let rows = [unit(0), unit(1), unit(2)];
        let part = BodyPart { body: 0, rows, pushed: rows };
        Point { parts: vec![part], delassus: Matrix3::identity(), bias: Vector3::new(gap_term, 0.0, 0.0), gap_term }
    }

    fn velocity(v: [f64; 3]) -> nalgebra::DVector<f64> {
        nalgebra::DVector::from_column_slice(&[v[0], v[1], v[2], 0.0, 0.0, 0.0])
    }

    /// The points' velocities in their frames at the body's velocity `u`.
    fn at(points: &[Point], u: &nalgebra::DVector<f64>) -> Vec<Vector3> {
        points.iter().map(|p| p.velocity(u)).collect()
    }

    /// Invariant: the sweeps' answer passes the conditions' check exactly where it is an
    /// exact-Coulomb answer to the check's tolerance (1e-5 of the largest impulse, 1 here, on a
    /// mass of 1): a closed contact may not close further nor push while it opens, and a slip's
    /// friction is the polygon's point that dissipates most — at a vertex for a slip between
    /// two facets' normals, not the facet's point that also opposes it.
    #[test]
    fn the_conditions_check_holds_a_slip_to_its_most_dissipating_friction() {
        let (mu, sides) = (0.5, 8);
        let p = [lone_point(0.0)];
        let scale = (1.0, 1.0);
        let resting = [Vector3::new(1.0, 0.0, 0.0)];
        assert!(conditions_hold(&at(&p, &velocity([0.0, 0.0, 0.0])), &resting, (mu, sides), scale));
        assert!(!conditions_hold(&at(&p, &velocity([-1e-4, 0.0, 0.0])), &resting, (mu, sides), scale), "closing");
        assert!(!conditions_hold(&at(&p, &velocity([1e-4, 0.0, 0.0])), &resting, (mu, sides), scale), "pushing");
        assert!(conditions_hold(
            &at(&[lone_point(1e-3)], &velocity([0.0; 3])),
            &[Vector3::zeros()],
            (mu, sides),
            scale
        ));
        // Slip along −(cos 22.5°, sin 22.5°): the vertex at 22.5° (radius μ / cos 22.5°) dissipates most.
        let a = PI / 8.0;
        let slip = velocity([0.0, -a.cos(), -a.sin()]);
        let vertex = Vector3::new(1.0, mu * a.cos() / a.cos(), mu * a.sin() / a.cos());
        assert!(conditions_hold(&at(&p, &slip), &[vertex], (mu, sides), scale));
        let facet = Vector3::new(1.0, mu, 0.0);
        assert!(
            !conditions_hold(&at(&p, &slip), &[facet], (mu, sides), scale),
            "a facet's friction on a vertex's slip"
        );
        assert!(
            !conditions_hold(&at(&p, &slip), &[Vector3::new(1.0, 0.0, 0.0)], (mu, sides), scale),
            "a slip without friction"
        );
    }

    /// Invariant: a settled answer whose impulses do work on the blocks' separating motion (a
    /// push while they part, gap terms aside) is refused beyond round-off; one whose contact
    /// only stops a closing gap, or dissipates, is not.
    #[test]
    fn a_settled_answer_may_not_create_energy() {
        let scale = (1.0, 1.0);
        let (touching, closing) = ([lone_point(0.0)], [lone_point(1e-3)]);
        let no_energy = |p: &[Point], u: [f64; 3], r: Vector3| creates_no_energy(p, &at(p, &velocity(u)), &[r], scale);
        let push = Vector3::new(1.0, 0.0, 0.0);
        assert!(!no_energy(&touching, [1e-6, 0.0, 0.0], push));
        assert!(no_energy(&touching, [0.0; 3], push));
        // Closing its 1e-3 m/s gap term exactly (its velocity −1e-3 m/s): work 1e-3 J absorbed.
        assert!(no_energy(&closing, [-1e-3, 0.0, 0.0], push));
        // Friction against a slip dissipates.
        let rubbing = Vector3::new(1.0, 0.5, 0.0);
        assert!(no_energy(&touching, [0.0, -1.0, 0.0], rubbing));
        assert!(!no_energy(&touching, [0.0, 1.0, 0.0], rubbing));
    }

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
