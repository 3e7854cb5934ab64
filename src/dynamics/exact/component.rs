//! A moving component's rigid-body algebra for the steps that solve its contacts directly (by
//! their states, by Gauss–Seidel): its bodies' 6×6 mass blocks (translation, then rotation in
//! world axes), its free motion M u* (SI units), the generalized rows of contact directions.

use super::bodies::Body;
use super::contacts::Side;
use crate::geometry::{Point3, Vector3};
use nalgebra::{DVector, Matrix3, Matrix6, Vector6};

/// The component's rigid-body algebra: its bodies' mass matrices and free motion.
pub(super) struct Component<'a> {
    pub(super) bodies: Vec<&'a Body>,
    pub(super) local: &'a [usize],
    /// M's block per body (6 rows: translation, then rotation in world axes), and M u*.
    pub(super) mass: Vec<Matrix6<f64>>,
    pub(super) free: DVector<f64>,
    /// Each body's inverse inertia now, world axes.
    inverse_inertia: Vec<Matrix3<f64>>,
}

/// A generalized row with at most two bodies' parts: (the body's local index, its 6 entries).
pub(super) struct Sparse {
    parts: [(usize, Vector6<f64>); 2],
    len: usize,
}

impl Sparse {
    pub(super) fn iter(&self) -> impl Iterator<Item = &(usize, Vector6<f64>)> {
        self.parts[..self.len].iter()
    }

    pub(super) fn dot(&self, u: &DVector<f64>) -> f64 {
        self.iter().map(|(j, r)| r.dot(&u.fixed_rows::<6>(6 * j))).sum()
    }

    pub(super) fn add_to(&self, u: &mut DVector<f64>, scale: f64) {
        for (j, r) in self.iter() {
            let mut s = u.fixed_rows_mut::<6>(6 * j);
            s.axpy(scale, r, 1.0);
        }
    }
}

impl<'a> Component<'a> {
    /// The generalized row of direction `d` at `point` on a contact's sides (+ on b, − on a).
    pub(super) fn sparse_row(&self, a: Side, b: Side, point: &Point3, d: &Vector3) -> Sparse {
        let mut out = Sparse { parts: [(0, Vector6::zeros()); 2], len: 0 };
        for (side, sign) in [(a, -1.0), (b, 1.0)] {
            let Side::Free(k) = side else { continue };
            let j = self.local[k];
            let m = (point - self.bodies[j].x).cross(d);
            let r = Vector6::new(d.x, d.y, d.z, m.x, m.y, m.z) * sign;
            out.parts[out.len] = (j, r);
            out.len += 1;
        }
        out
    }

    /// r M⁻¹ rᵀ of a row (a floor keeps a row with no free body finite).
    pub(super) fn compliance(&self, row: &Sparse) -> f64 {
        row.iter().map(|(j, r)| r.dot(&self.inverse_mass(*j, r))).sum::<f64>().max(f64::MIN_POSITIVE)
    }

    /// Body `j`'s M⁻¹ applied to 6 entries.
    pub(super) fn inverse_mass(&self, j: usize, x: &Vector6<f64>) -> Vector6<f64> {
        let b = self.bodies[j];
        let t = x.fixed_rows::<3>(0) / b.mass;
        let w = self.inverse_inertia[j] * x.fixed_rows::<3>(3);
        Vector6::new(t.x, t.y, t.z, w.x, w.y, w.z)
    }

    /// Each body's (velocity, angular velocity) in `u`.
    pub(super) fn velocities(&self, u: &DVector<f64>) -> Vec<(Vector3, Vector3)> {
        (0..self.bodies.len())
            .map(|j| {
                let s = u.rows(6 * j, 6);
                (Vector3::new(s[0], s[1], s[2]), Vector3::new(s[3], s[4], s[5]))
            })
            .collect()
    }

    /// M⁻¹ x, body by body.
    pub(super) fn solve_mass(&self, x: &DVector<f64>) -> DVector<f64> {
        let mut y = x.clone();
        for j in 0..self.bodies.len() {
            let part = self.inverse_mass(j, &x.fixed_rows::<6>(6 * j).into_owned());
            y.fixed_rows_mut::<6>(6 * j).copy_from(&part);
        }
        y
    }

    /// M u, body by body.
    pub(super) fn mass_times(&self, u: &DVector<f64>) -> DVector<f64> {
        let mut y = u.clone();
        for (j, m) in self.mass.iter().enumerate() {
            let part = m * u.fixed_rows::<6>(6 * j);
            y.fixed_rows_mut::<6>(6 * j).copy_from(&part);
        }
        y
    }

    /// `rhs` − M u into `out`, body by body.
    pub(super) fn residual_of(&self, rhs: &DVector<f64>, u: &DVector<f64>, out: &mut DVector<f64>) {
        for (j, m) in self.mass.iter().enumerate() {
            let part = rhs.fixed_rows::<6>(6 * j) - m * u.fixed_rows::<6>(6 * j);
            out.fixed_rows_mut::<6>(6 * j).copy_from(&part);
        }
    }

    pub(super) fn new(all: &'a [Body], comp: &[usize], local: &'a [usize], h: f64) -> Self {
        let n = 6 * comp.len();
        let mut mass = vec![Matrix6::zeros(); comp.len()];
        let mut free = DVector::zeros(n);
        for (j, &k) in comp.iter().enumerate() {
            let b = &all[k];
            let inertia = b.inertia_now();
            let (o, l) = (6 * j, &b.load);
            for r in 0..3 {
                mass[j][(r, r)] = b.mass;
                free[o + r] = b.mass * b.v[r] + h * l[r];
            }
            mass[j].fixed_view_mut::<3, 3>(3, 3).copy_from(&inertia);
            let momentum = inertia * b.w;
            for r in 0..3 {
                free[o + 3 + r] = momentum[r] + h * l[3 + r];
            }
        }
        let inverse_inertia = comp
            .iter()
            .map(|&k| {
                let b = &all[k];
                let a = b.axes_now();
                a * Matrix3::from_diagonal(&Vector3::from(b.moments.map(|m| 1.0 / m))) * a.transpose()
            })
            .collect();
        Self { bodies: comp.iter().map(|&k| &all[k]).collect(), local, mass, free, inverse_inertia }
    }
}

/// b's point's velocity relative to a's at `point` in the component's velocities `u`, m/s
/// (a side outside the component, fixed or moved, contributes its prescribed part elsewhere).
pub(super) fn relative_velocity(parts: &Component, a: Side, b: Side, point: &Point3, u: &DVector<f64>) -> Vector3 {
    let vel = |s: Side| match s {
        Side::Free(k) => {
            let j = parts.local[k];
            let (v, w) = (u.fixed_rows::<3>(6 * j).into_owned(), u.fixed_rows::<3>(6 * j + 3).into_owned());
            v + w.cross(&(point - parts.bodies[j].x))
        }
        _ => Vector3::zeros(),
    };
    vel(b) - vel(a)
}
