//! The free blocks' state (SI units, world axes, z up) and the engine's non-dimensional units.

use crate::geometry::{Point3, Vector3};
use crate::model::AssemblyBlock;
use nalgebra::{Matrix3, SymmetricEigen, UnitQuaternion};

/// The units the step problems are solved in: lengths by the model size, forces by the free
/// weight, time by √(length / g) (so speeds by √(g × length)). Weights of very different sizes
/// cost an interior-point method accuracy per iteration; these make the problems O(1).
#[derive(Clone, Copy, Debug)]
pub(super) struct Units {
    pub length: f64,
    pub force: f64,
    pub g: f64,
}

impl Units {
    pub fn time(&self) -> f64 {
        (self.length / self.g).sqrt()
    }

    pub fn speed(&self) -> f64 {
        (self.g * self.length).sqrt()
    }

    pub fn mass(&self) -> f64 {
        self.force / self.g
    }
}

/// A free block as the engine moves it.
#[derive(Clone, Debug)]
pub(super) struct Body {
    /// Index in the assembly.
    pub block: usize,
    /// Centroid at the start and now, m.
    pub start: Point3,
    pub x: Point3,
    /// Rotation since the start.
    pub q: UnitQuaternion<f64>,
    /// Centroid velocity (m/s) and angular velocity (rad/s).
    pub v: Vector3,
    pub w: Vector3,
    pub mass: f64,
    /// Principal moments about the centroid (kg·m²) and their axes at the start (columns).
    pub moments: [f64; 3],
    pub axes: Matrix3<f64>,
    /// The constant load: weight plus dead loads, force (N) then moment about the centroid (N·m).
    pub load: [f64; 6],
    /// The farthest vertex from the centroid, m (a vertex's speed is at most |v| + |ω| × this).
    pub radius: f64,
    /// Held at rest, its component not solved until something moving touches it.
    pub asleep: bool,
    /// The last whole step's velocity change (m/s, rad/s): h × the acceleration then.
    pub kick: [Vector3; 2],
    /// Whether the velocities are an instant's (after a split step), not a step's middle's.
    pub instant: bool,
}

impl Body {
    pub fn new(index: usize, block: &AssemblyBlock, gravity: Vector3, dead: [f64; 6]) -> Self {
        let eig = SymmetricEigen::new(block.mass.inertia * block.density);
        let c = block.mass.centroid;
        let mass = block.mass();
        let radius = block.mesh.vertices.iter().map(|p| (p - c).norm()).fold(0.0, f64::max);
        let weight = gravity * mass;
        Self {
            block: index,
            start: c,
            x: c,
            q: UnitQuaternion::identity(),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
            mass,
            moments: [0, 1, 2].map(|k| eig.eigenvalues[k].max(f64::MIN_POSITIVE)),
            axes: eig.eigenvectors,
            load: [weight.x + dead[0], weight.y + dead[1], weight.z + dead[2], dead[3], dead[4], dead[5]],
            radius,
            asleep: false,
            kick: [Vector3::zeros(); 2],
            instant: false,
        }
    }

    /// Where the material point at `r0` (its offset from the centroid at the start) is now.
    pub fn point(&self, r0: &Vector3) -> Point3 {
        self.x + self.q * r0
    }

    /// The principal axes now (columns).
    pub fn axes_now(&self) -> Matrix3<f64> {
        self.q.to_rotation_matrix().matrix() * self.axes
    }

    /// The inertia tensor about the centroid now, world axes, kg·m².
    pub fn inertia_now(&self) -> Matrix3<f64> {
        let a = self.axes_now();
        a * Matrix3::from_diagonal(&Vector3::from(self.moments)) * a.transpose()
    }

    pub fn velocity_at(&self, p: &Point3) -> Vector3 {
        self.v + self.w.cross(&(p - self.x))
    }

    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass * self.v.norm_squared() + 0.5 * self.w.dot(&(self.inertia_now() * self.w))
    }

    /// Symplectic Euler's position update with the new velocities, as the rigid screw of the
    /// twist (v, ω) over h: R ← exp(h ω) R, x += V(h ω) h v (V the SE(3) exponential's left
    /// Jacobian). A material point whose velocity is zero stays where it is — a block turning
    /// about a corner keeps its corner on the ground, where x += h v would carry it along the
    /// chord by ½ h² ω² r each step, a drift whose correction dissipates O(h) of the motion.
    /// Turning with ω fixed keeps ½ ωᵀ I ω (the gyroscopic term is left out: the energy balance
    /// stays exact, and a block turns little before it lands). Returns x's move beyond h v, m.
    pub fn advance(&mut self, h: f64) -> Vector3 {
        let theta = self.w * h;
        let step = screw_jacobian(&theta) * (self.v * h);
        self.x += step;
        self.q = UnitQuaternion::from_scaled_axis(theta) * self.q;
        self.q.renormalize();
        step - self.v * h
    }

    /// A moved support's update along its path: the centroid by h v, the turn about it.
    pub fn advance_along_path(&mut self, h: f64) {
        self.x += self.v * h;
        self.q = UnitQuaternion::from_scaled_axis(self.w * h) * self.q;
        self.q.renormalize();
    }

    pub fn at_rest(&self) -> bool {
        self.v == Vector3::zeros() && self.w == Vector3::zeros()
    }

    /// The load's power at velocity `v` and angular velocity `w` (W), or its work on a
    /// displacement and a rotation vector (J).
    pub fn load_power(&self, v: &Vector3, w: &Vector3) -> f64 {
        let l = &self.load;
        l[0] * v.x + l[1] * v.y + l[2] * v.z + l[3] * w.x + l[4] * w.y + l[5] * w.z
    }
}

/// V(θ) = I + (1 − cos|θ|)/|θ|² [θ]× + (|θ| − sin|θ|)/|θ|³ [θ]×², by its series below 1e-4 rad.
fn screw_jacobian(theta: &Vector3) -> Matrix3<f64> {
    let t2 = theta.norm_squared();
    let k = theta.cross_matrix();
    let (a, b) = if t2 < 1e-8 {
        (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0)
    } else {
        let t = t2.sqrt();
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    Matrix3::identity() + k * a + k * k * b
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Invariant: a block turning about a fixed point (its velocity ω × (x − p)) keeps that
    /// point where it is after any step: the screw is the rotation about it.
    #[test]
    fn a_point_at_rest_stays_put() {
        let cases = [
            (Vector3::new(0.0, -0.7, 0.0), Vector3::new(0.1, 0.0, 0.0)),
            (Vector3::new(0.3, 2.0, -1.0), Vector3::new(-0.2, 0.5, 0.1)),
        ];
        for (w, p) in cases {
            let mesh = crate::geometry::Mesh::cuboid(Point3::new(0.0, 0.0, 0.0), Point3::new(0.2, 0.3, 1.0));
            let scene = crate::model::Scene::new("one", vec![crate::model::Block::new("b", mesh)]);
            let assembly = crate::model::Assembly::new(&scene, &Default::default()).expect("a valid block");
            let mut body = Body::new(0, &assembly.blocks[0], Vector3::zeros(), [0.0; 6]);
            let r0 = Point3::from(p) - body.x;
            body.w = w;
            body.v = w.cross(&(body.x - Point3::from(p)));
            body.advance(0.01);
            assert!((body.point(&r0) - Point3::from(p)).norm() < 1e-15, "{:?}", body.point(&r0));
        }
    }
}
