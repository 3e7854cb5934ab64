//! Planar polygons in 3D: Newell normal, area, centroid, planes and in-plane frames.
//!
//! A polygon's vertices are CCW about its normal (right-hand rule). 2D projections use a frame
//! (u, v, n) with u × v = n, so CCW about n stays CCW (positive signed area) in (u, v).

use super::{Point3, Vector3};

/// Area-weighted (Newell) normal: its length is the polygon's area for a
/// planar polygon, its direction the normal given by the vertex order. Robust for non-convex
/// polygons and for slightly non-planar ones (best-fit direction).
pub fn area_vector(points: &[Point3]) -> Vector3 {
    let n = points.len();
    let mut a = Vector3::zeros();
    if n < 3 {
        return a;
    }
    // Relative to the first point to keep cancellation small for models far from the origin.
    let o = points[0];
    for i in 1..n - 1 {
        a += (points[i] - o).cross(&(points[i + 1] - o));
    }
    a * 0.5
}

/// Area centroid of a planar polygon (fan decomposition with signed triangle areas, exact for
/// non-convex polygons). Falls back to the vertex mean when the area vanishes.
pub fn centroid(points: &[Point3]) -> Point3 {
    let n = points.len();
    let normal = area_vector(points);
    let nn = normal.norm_squared();
    if n < 3 || nn == 0.0 {
        let s: Vector3 = points.iter().map(|p| p.coords).sum();
        return Point3::from(s / n.max(1) as f64);
    }
    let o = points[0];
    let mut acc = Vector3::zeros();
    let mut total = 0.0;
    for i in 1..n - 1 {
        let a = points[i] - o;
        let b = points[i + 1] - o;
        let w = a.cross(&b).dot(&normal);
        acc += (a + b) * (w / 3.0);
        total += w;
    }
    o + acc / total
}

/// An oriented plane `n · x = d` with unit normal `n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// The unit normal n.
    pub normal: Vector3,
    /// d: the signed distance of the plane from the origin along n, m.
    pub offset: f64,
}

impl Plane {
    /// The plane through `p` with normal `n` (any length > 0).
    pub fn from_point_normal(p: &Point3, n: &Vector3) -> Self {
        let normal = n.normalize();
        Self { normal, offset: normal.dot(&p.coords) }
    }

    /// Signed distance of `p` (positive on the side the normal points to).
    pub fn distance(&self, p: &Point3) -> f64 {
        self.normal.dot(&p.coords) - self.offset
    }
}

/// A right-handed orthonormal frame (u, v, n) at an origin: `u × v = n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// The frame's origin, m.
    pub origin: Point3,
    /// The first in-plane unit axis.
    pub u: Vector3,
    /// The second in-plane unit axis (n × u).
    pub v: Vector3,
    /// The unit normal.
    pub n: Vector3,
}

impl Frame {
    /// Deterministic in-plane axes for a unit normal: u is the horizontal direction `z × n`
    /// when the plane is not horizontal, else the x axis projected into the plane.
    pub fn from_normal(origin: Point3, n: Vector3) -> Self {
        let n = n.normalize();
        let z = Vector3::z();
        let c = z.cross(&n);
        let u = if c.norm() > 1e-3 {
            c.normalize()
        } else {
            let x = Vector3::x();
            (x - n * n.dot(&x)).normalize()
        };
        let v = n.cross(&u);
        Self { origin, u, v, n }
    }

    /// `p`'s in-plane coordinates (along u, v) from the origin; its height along n is dropped.
    pub fn to_2d(&self, p: &Point3) -> [f64; 2] {
        let d = p - self.origin;
        [d.dot(&self.u), d.dot(&self.v)]
    }

    /// The point of the plane at in-plane coordinates `q` (along u, v).
    pub fn to_3d(&self, q: [f64; 2]) -> Point3 {
        self.origin + self.u * q[0] + self.v * q[1]
    }
}

/// Signed area of a 2D ring (positive when CCW).
pub fn signed_area_2d(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    let mut a = 0.0;
    for i in 0..n {
        let p = ring[i];
        let q = ring[(i + 1) % n];
        a += p[0] * q[1] - q[0] * p[1];
    }
    0.5 * a
}

/// Triangles (index triples, counter-clockwise) of a 2D polygon given as its outer ring
/// followed by hole rings starting at `hole_starts`. The only touchpoint of the triangulator
/// (earcut); like every ear clipper it may drop collinear boundary vertices.
pub fn triangulate_2d(points: &[[f64; 2]], hole_starts: &[usize]) -> Vec<[usize; 3]> {
    let mut idx: Vec<usize> = Vec::new();
    earcut::Earcut::new().earcut(points.iter().copied(), hole_starts, &mut idx);
    idx.chunks(3)
        .map(|t| {
            let ccw = signed_area_2d(&[points[t[0]], points[t[1]], points[t[2]]]) >= 0.0;
            if ccw { [t[0], t[1], t[2]] } else { [t[0], t[2], t[1]] }
        })
        .collect()
}

/// Largest distance of a vertex from the best-fit plane through the centroid with the Newell
/// normal; 0 for fewer than 4 vertices.
pub fn planarity_deviation(points: &[Point3]) -> f64 {
    if points.len() < 4 {
        return 0.0;
    }
    let n = area_vector(points);
    if n.norm_squared() == 0.0 {
        return 0.0;
    }
    let plane = Plane::from_point_normal(&centroid(points), &n);
    points.iter().map(|p| plane.distance(p).abs()).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn l_shape_area_and_centroid() {
        // L = 2x1 rectangle + 1x1 square on top of its left half: area 3, centroid (5/6, 5/6).
        let pts: Vec<Point3> = [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]]
            .iter()
            .map(|p| Point3::new(p[0], p[1], 3.0))
            .collect();
        let a = area_vector(&pts);
        assert!((a - Vector3::new(0., 0., 3.)).norm() < 1e-12);
        let c = centroid(&pts);
        assert!((c - Point3::new(5. / 6., 5. / 6., 3.)).norm() < 1e-12);
    }

    #[test]
    fn frame_is_right_handed() {
        for n in [Vector3::z(), -Vector3::z(), Vector3::new(1., 2., 3.), Vector3::x()] {
            let f = Frame::from_normal(Point3::origin(), n);
            assert!((f.u.cross(&f.v) - f.n).norm() < 1e-12);
            assert!((f.n - n.normalize()).norm() < 1e-12);
        }
    }
}
