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

    /// Symplectic Euler's position update with the new velocities: x += h v, R ← exp(h ω) R.
    /// Turning with ω fixed keeps ½ ωᵀ I ω (the gyroscopic term is left out: the energy
    /// balance stays exact, and a block turns little before it lands).
    pub fn advance(&mut self, h: f64) {
        self.x += self.v * h;
        self.q = UnitQuaternion::from_scaled_axis(self.w * h) * self.q;
        self.q.renormalize();
    }

    pub fn at_rest(&self) -> bool {
        self.v == Vector3::zeros() && self.w == Vector3::zeros()
    }
}
