//! A closed polygon mesh: vertex positions and faces as index loops (CCW seen from outside).

use super::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// Polygon mesh. Faces may have any number of vertices and may be non-convex; after
/// [`repair`](super::repair) they are planar, the mesh is closed, manifold and outward oriented.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Vertex positions, m.
    pub vertices: Vec<Point3>,
    /// Faces as vertex indices, counter-clockwise seen from outside.
    pub faces: Vec<Vec<usize>>,
}

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb3 {
    /// The lowest corner (smallest x, y and z).
    pub min: Point3,
    /// The highest corner.
    pub max: Point3,
}

impl Aabb3 {
    /// The empty box (min = +inf, max = -inf); `extend` grows it.
    pub fn empty() -> Self {
        Self {
            min: Point3::from(Vector3::repeat(f64::INFINITY)),
            max: Point3::from(Vector3::repeat(f64::NEG_INFINITY)),
        }
    }

    /// The smallest box holding `points` (empty without points).
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Point3>) -> Self {
        let mut b = Self::empty();
        for p in points {
            b.extend(p);
        }
        b
    }

    /// Grows the box to hold `p`.
    pub fn extend(&mut self, p: &Point3) {
        self.min = self.min.inf(p);
        self.max = self.max.sup(p);
    }

    /// Grows the box to hold `other`.
    pub fn merge(&mut self, other: &Aabb3) {
        self.min = self.min.inf(&other.min);
        self.max = self.max.sup(&other.max);
    }

    /// Whether the box holds no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Length of the diagonal (0 for the empty box).
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() { 0.0 } else { (self.max - self.min).norm() }
    }

    /// The box's centre.
    pub fn center(&self) -> Point3 {
        nalgebra::center(&self.min, &self.max)
    }

    /// The box grown by `margin` on every side.
    pub fn loosened(&self, margin: f64) -> Self {
        let m = Vector3::repeat(margin);
        Self { min: self.min - m, max: self.max + m }
    }

    /// Whether the boxes overlap or touch.
    pub fn intersects(&self, other: &Aabb3) -> bool {
        (0..3).all(|k| self.min[k] <= other.max[k] && other.min[k] <= self.max[k])
    }
}

impl Mesh {
    /// The mesh of these vertices and faces, as given (not checked or repaired).
    pub fn new(vertices: Vec<Point3>, faces: Vec<Vec<usize>>) -> Self {
        Self { vertices, faces }
    }

    /// Axis-aligned box `[min, max]` as a closed mesh (6 quads, outward CCW).
    pub fn cuboid(min: Point3, max: Point3) -> Self {
        let v = |x: bool, y: bool, z: bool| {
            Point3::new(if x { max.x } else { min.x }, if y { max.y } else { min.y }, if z { max.z } else { min.z })
        };
        let vertices = vec![
            v(false, false, false),
            v(true, false, false),
            v(true, true, false),
            v(false, true, false),
            v(false, false, true),
            v(true, false, true),
            v(true, true, true),
            v(false, true, true),
        ];
        let faces = vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ];
        Self { vertices, faces }
    }

    /// Prism: a planar polygon (convex or not) in the plane z = z0 extruded to z = z1 > z0.
    /// Side faces are quads, caps are single polygon faces.
    pub fn extrude_z(polygon: &[[f64; 2]], z0: f64, z1: f64) -> Self {
        let base: Vec<Point3> = polygon.iter().map(|p| Point3::new(p[0], p[1], z0)).collect();
        Self::prism(&base, Vector3::new(0.0, 0.0, z1 - z0))
    }

    /// Hexahedron from 8 corners: 0..4 one quad, 4..8 the opposite quad with i + 4 joined to
    /// i. Faces are oriented outward whatever the corner order (the volume decides).
    pub fn hexahedron(v: [Point3; 8]) -> Self {
        let mut mesh = Self::cuboid(Point3::origin(), Point3::new(1.0, 1.0, 1.0));
        mesh.vertices = v.to_vec();
        if super::MassProperties::of_mesh(&mesh).volume < 0.0 {
            mesh.faces.iter_mut().for_each(|f| f.reverse());
        }
        mesh
    }

    /// Prism: a planar polygon (convex or not) swept by `dir`, oriented outward.
    pub fn prism(base: &[Point3], dir: Vector3) -> Self {
        let n = base.len();
        let mut base = base.to_vec();
        if super::polygon::area_vector(&base).dot(&dir) < 0.0 {
            base.reverse();
        }
        let mut vertices = base.clone();
        vertices.extend(base.iter().map(|p| p + dir));
        let mut faces = vec![(0..n).rev().collect::<Vec<_>>(), (n..2 * n).collect()];
        for i in 0..n {
            let j = (i + 1) % n;
            faces.push(vec![i, j, n + j, n + i]);
        }
        Self { vertices, faces }
    }

    /// Prism of a planar polygon with one hole (a letter with a counter, a loop): `outer` and
    /// `inner` (inside it, no collinear consecutive vertices) swept by `dir`, oriented
    /// outward. The caps are ear-clipped; when a hole vertex is collinear with outline edges
    /// the clipper may emit a degenerate triangle, which validation then reports as a hole.
    pub fn prism_with_hole(outer: &[Point3], inner: &[Point3], dir: Vector3) -> Self {
        let n_dir = dir.normalize();
        let (mut outer, mut inner) = (outer.to_vec(), inner.to_vec());
        if super::polygon::area_vector(&outer).dot(&dir) < 0.0 {
            outer.reverse();
        }
        if super::polygon::area_vector(&inner).dot(&dir) > 0.0 {
            inner.reverse(); // holes run the other way
        }
        let (no, ni) = (outer.len(), inner.len());
        let base: Vec<Point3> = outer.iter().chain(&inner).copied().collect();
        let frame = super::polygon::Frame::from_normal(base[0], n_dir);
        let flat: Vec<[f64; 2]> = base.iter().map(|p| frame.to_2d(p)).collect();
        let tris = super::polygon::triangulate_2d(&flat, &[no]);
        let m = no + ni;
        let mut vertices = base.clone();
        vertices.extend(base.iter().map(|p| p + dir));
        let mut faces: Vec<Vec<usize>> = Vec::with_capacity(2 * tris.len() + m);
        for t in &tris {
            faces.push(vec![t[0], t[2], t[1]]); // base cap faces −dir
            faces.push(vec![m + t[0], m + t[1], m + t[2]]);
        }
        for (start, len) in [(0, no), (no, ni)] {
            for k in 0..len {
                let (a, b) = (start + k, start + (k + 1) % len);
                faces.push(vec![a, b, m + b, m + a]);
            }
        }
        Self { vertices, faces }
    }

    /// The bounding box of the vertices.
    pub fn aabb(&self) -> Aabb3 {
        Aabb3::from_points(&self.vertices)
    }

    /// The face's vertex positions in order.
    /// Ear-clipped triangles of every face (faces planar and simple), each with the index of
    /// the face it came from; triangles are kept as they are.
    pub fn triangles(&self) -> Vec<([usize; 3], usize)> {
        use super::polygon::{Frame, area_vector, triangulate_2d};
        let mut out = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            if face.len() == 3 {
                out.push(([face[0], face[1], face[2]], f));
                continue;
            }
            let pts: Vec<Point3> = face.iter().map(|&i| self.vertices[i]).collect();
            let frame = Frame::from_normal(pts[0], area_vector(&pts));
            let p2: Vec<[f64; 2]> = pts.iter().map(|p| frame.to_2d(p)).collect();
            out.extend(triangulate_2d(&p2, &[]).into_iter().map(|t| (t.map(|k| face[k]), f)));
        }
        out
    }

    /// Content hash of the vertices (bit patterns) and faces. SipHash with fixed keys: the
    /// same content gives the same key in every run.
    pub fn content_key(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for p in &self.vertices {
            p.iter().for_each(|c| c.to_bits().hash(&mut h));
        }
        self.faces.hash(&mut h);
        h.finish()
    }

    /// The positions of face `f`'s vertices, in its order.
    pub fn face_points(&self, f: usize) -> impl Iterator<Item = Point3> + '_ {
        self.faces[f].iter().map(|&i| self.vertices[i])
    }

    /// Every vertex mapped by an affine map `p -> s * p + t` (s > 0 keeps orientation).
    pub fn scaled_translated(&self, s: f64, t: Vector3) -> Self {
        Self {
            vertices: self.vertices.iter().map(|p| Point3::from(p.coords * s + t)).collect(),
            faces: self.faces.clone(),
        }
    }

    /// Every vertex mapped by `f` (faces unchanged).
    pub fn map_points(&self, f: impl Fn(&Point3) -> Point3) -> Self {
        Self { vertices: self.vertices.iter().map(f).collect(), faces: self.faces.clone() }
    }
}
