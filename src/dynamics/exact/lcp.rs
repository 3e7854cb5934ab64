//! A step's contact states by Lemke's pivoting ([`super::pivoting`]) on its linear
//! complementarity problem, where the states' passes and Gauss–Seidel's sweeps do not settle
//! (a conflict: blocks that pivot on their edges and slide on each other, whose states the
//! block changes and Murty's rule cycle through). Stewart and Trinkle's form for the polygonal
//! friction sets: per contact the normal impulse p_n, the impulses β_j along the polygon's k
//! vertex directions d_j (|d_j| = 1 / cos(π/k), so that the facets lie at μ p_n) and the slip
//! speed λ:
//!
//! ```text
//! 0 ≤ p_n ⊥ v_n ≥ 0,   0 ≤ β_j ⊥ λ + d_j · v_t ≥ 0,   0 ≤ λ ⊥ μ p_n − Σ β_j ≥ 0
//! ```
//! with v = W r + v* the contacts' velocities after the step (W = H M⁻¹ Hᵀ, v* the free motion's
//! and the gap terms). Contacts the free motion opens faster than gravity closes them in a step
//! (v*_n > g h) are left out, open: they rarely carry an impulse, and each contact costs ten
//! variables. The answer only proposes states and impulses: the states' step
//! ([`super::active_set`]) takes them and checks every condition (closing a left-out contact
//! that the others' impulses push shut).

use super::World;
use super::component::Component;
use super::contacts::State;
use super::gauss_seidel::Point;
use super::problem::Active;
use crate::geometry::Vector3;
use crate::model::FrictionModel;
use nalgebra::Matrix3;
use std::f64::consts::PI;

/// Contacts up to which a component's LCP is pivoted (its tableau grows as their square, each
/// pivot's work as its size).
const UP_TO: usize = 16;

/// Pivots allowed, per LCP variable.
const PIVOTS_PER_VARIABLE: usize = 4;

/// An impulse below this fraction of the largest is zero.
const ZERO: f64 = 1e-9;

impl World {
    /// Each active contact's state and impulse (N·s on b) from the step's LCP, where the
    /// component is small enough and the friction sets polygons; None otherwise or where the
    /// pivots end on a ray.
    pub(super) fn states_by_lcp(
        &self,
        comp: &[usize],
        local: &[usize],
        active: &[Active],
    ) -> Option<(Vec<State>, Vec<Vector3>)> {
        let k = match self.ctx.model {
            FrictionModel::Cone => return None,
            m => m.facets().len(),
        };
        if active.len() > UP_TO {
            return None;
        }
        let h = self.ctx.h;
        let parts = Component::new(&self.bodies, comp, local, h);
        let points: Vec<Point> = active.iter().map(|a| self.point(&parts, a)).collect();
        let free = parts.solve_mass(&parts.free);
        let velocities: Vec<Vector3> = points.iter().map(|p| p.velocity(&free)).collect();
        let opening = self.ctx.units.g * h;
        let taken: Vec<usize> = (0..active.len()).filter(|&i| velocities[i].x <= opening).collect();
        let g = impulse_columns(k);
        let (m, q) = complementarity(&points, &velocities, &taken, &g, self.ctx.mu);
        let z = super::pivoting::lemke(&m, &q, PIVOTS_PER_VARIABLE * q.len())?;
        let per = k + 2;
        // Impulses (N·s) against the largest; slip speeds (m/s) against the rest criterion's,
        // as a step's end reads a slip ([`super::active_set::state_after`]).
        let largest = z.chunks(per).flat_map(|zi| &zi[..=k]).fold(0.0f64, |s, v| s.max(*v));
        let (tiny, slow) = (ZERO * largest.max(f64::MIN_POSITIVE), self.settings.still * self.ctx.units.g * h);
        let mut out = (vec![State::Open; active.len()], vec![Vector3::zeros(); active.len()]);
        for (i, &c) in taken.iter().enumerate() {
            let zi = &z[i * per..(i + 1) * per];
            let r: Vector3 = g.iter().zip(zi).map(|(gc, zc)| gc * *zc).sum();
            let f = &active[c].geometry.frame;
            out.1[c] = f[0] * r.x + f[1] * r.y + f[2] * r.z;
            out.0[c] = if zi[0] <= tiny {
                State::Open
            } else if zi[k + 1] <= slow {
                State::Stick
            } else {
                State::Slide { angle: slide_angle(&zi[1..=k], tiny) }
            };
        }
        Some(out)
    }
}

/// A contact's impulse in its frame (n, u, v) from its variables (p_n, β_1 … β_k): column 0
/// the normal, then the polygon's vertex directions d_j (the slip speed λ has none).
fn impulse_columns(k: usize) -> Vec<Vector3> {
    let spacing = 2.0 * PI / k as f64;
    let r = 1.0 / (0.5 * spacing).cos();
    let vertex = |j: usize| {
        let a = (j as f64 + 0.5) * spacing;
        Vector3::new(0.0, r * a.cos(), r * a.sin())
    };
    std::iter::once(Vector3::x()).chain((0..k).map(vertex)).collect()
}

/// The LCP (M row-major, q) of contacts `taken` (module docs): per contact (p_n, β, λ), M's
/// velocity part Gᵢᵀ W_ib G_b, q's Gᵢᵀ v*ᵢ, and the slip speed's couplings.
fn complementarity(
    points: &[Point],
    velocities: &[Vector3],
    taken: &[usize],
    g: &[Vector3],
    mu: f64,
) -> (Vec<f64>, Vec<f64>) {
    let k = g.len() - 1;
    let per = k + 2;
    let n = per * taken.len();
    let (mut m, mut q) = (vec![0.0; n * n], vec![0.0; n]);
    for (i, &ci) in taken.iter().enumerate() {
        for (a, ga) in g.iter().enumerate() {
            q[i * per + a] = ga.dot(&velocities[ci]);
        }
        for (b, &cb) in taken.iter().enumerate() {
            let Some(w) = delassus(&points[ci], &points[cb]) else { continue };
            for (a, ga) in g.iter().enumerate() {
                let wa = w.transpose() * ga;
                for (c, gc) in g.iter().enumerate() {
                    m[(i * per + a) * n + b * per + c] = wa.dot(gc);
                }
            }
        }
        let lambda = i * per + k + 1;
        for j in 1..=k {
            m[(i * per + j) * n + lambda] = 1.0;
            m[lambda * n + i * per + j] = -1.0;
        }
        m[lambda * n + i * per] = mu;
    }
    (m, q)
}

/// W = H_a M⁻¹ H_bᵀ of two contact points (their frames' rows), over the bodies they share;
/// None where they share none.
fn delassus(a: &Point, b: &Point) -> Option<Matrix3<f64>> {
    let mut w = None;
    for x in &a.parts {
        for y in b.parts.iter().filter(|y| y.body == x.body) {
            let block = Matrix3::from_fn(|r, c| x.rows[r].dot(&y.pushed[c]));
            w = Some(w.unwrap_or_else(Matrix3::zeros) + block);
        }
    }
    w
}

/// The friction angle of a slide with vertex impulses `beta` (those above `tiny` carry it): a
/// facet's normal where two neighbouring vertices carry it, else its vertex's, within (−π, π].
fn slide_angle(beta: &[f64], tiny: f64) -> f64 {
    let k = beta.len();
    let spacing = 2.0 * PI / k as f64;
    let top = (0..k).max_by(|&a, &b| beta[a].total_cmp(&beta[b])).unwrap_or(0);
    let vertex = (top as f64 + 0.5) * spacing;
    let angle = if beta[(top + 1) % k] > tiny {
        vertex + 0.5 * spacing
    } else if beta[(top + k - 1) % k] > tiny {
        vertex - 0.5 * spacing
    } else {
        vertex
    };
    if angle > PI { angle - 2.0 * PI } else { angle }
}

#[cfg(test)]
mod tests {
    //! Invariant: the LCP's states and impulses are an exact-Coulomb step of a cube on the
    //! ground: the vertical momentum balance (Σ p_n = m g h); at rest every corner sticks or
    //! opens and the step stays at rest; sliding, every loaded corner slides with its friction
    //! on its polygon (gauge μ p_n) against the slip, the states' step from them settles, and
    //! the speed falls by between μ g h and μ g h / cos(π/8) (the polygon's facet and vertex).
    use super::*;
    use crate::dynamics::exact::active_set::gauge;
    use crate::dynamics::{DropSettings, Engine};
    use crate::geometry::{Mesh, Point3};
    use crate::model::{Assembly, Block, Scene};

    fn cube_on_the_ground() -> World {
        let cube = Mesh::cuboid(Point3::new(-0.5, -0.5, 0.0), Point3::new(0.5, 0.5, 1.0));
        let mut scene = Scene::new("cube", vec![Block::new("cube", cube)]);
        scene.ground = true;
        let asm = Assembly::new(&scene, &Default::default()).expect("a valid scene");
        World::new(&asm, &DropSettings { engine: Engine::Exact, ..Default::default() })
    }

    #[test]
    fn a_cube_rests_and_slides_with_coulomb_friction() {
        for v0 in [0.0, 1.0] {
            let mut world = cube_on_the_ground();
            let near = world.near_contacts(&[]);
            assert_eq!(near.len(), 4, "the cube's four bottom corners on the ground");
            world.bodies[0].v = Vector3::x() * v0;
            let (comp, local) = (vec![0], vec![0]);
            let (states, impulses) = world.states_by_lcp(&comp, &local, &near).expect("the LCP has an answer");
            let (h, mass, g, mu) = (world.ctx.h, world.bodies[0].mass, world.ctx.units.g, world.ctx.mu);
            let normal: f64 = impulses.iter().map(|r| r.z).sum();
            assert!((normal - mass * g * h).abs() <= 1e-9 * mass * g * h, "v0 {v0}: normal {normal:e}");
            for ((a, s), r) in near.iter().zip(&states).zip(&impulses) {
                let f = &a.geometry.frame;
                let (pn, ft) = (r.dot(&f[0]), (r.dot(&f[1]), r.dot(&f[2])));
                match s {
                    State::Open => assert!(r.norm() <= 1e-8 * mass * g * h, "{r:?}"),
                    State::Stick => assert!(v0 == 0.0 && gauge(Some(8), ft) <= mu * pn * (1.0 + 1e-9), "{s:?} {r:?}"),
                    State::Slide { .. } => {
                        assert!(v0 > 0.0, "no slide at rest");
                        assert!((gauge(Some(8), ft) - mu * pn).abs() <= 1e-9 * pn, "{s:?} {r:?}");
                        assert!(r.x < 0.0, "friction against the slip: {r:?}");
                    }
                }
            }
            let sol = world.step_by_states(&comp, &local, &near, (states, Some(&impulses))).expect("settles");
            let speed = sol.velocities[0].0.x;
            let (least, most) = (mu * g * h, mu * g * h / (PI / 8.0).cos());
            if v0 == 0.0 {
                assert!(sol.velocities[0].0.norm() <= 1e-12, "at rest: {:?}", sol.velocities[0]);
            } else {
                let drop = v0 - speed;
                assert!(drop >= least * (1.0 - 1e-9) && drop <= most * (1.0 + 1e-9), "speed drop {drop:e}");
            }
        }
    }
}
