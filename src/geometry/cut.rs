//! Plane split of a closed polygon mesh (convex or not) into closed pieces with cap faces.
//!
//! Method: every face is triangulated in its plane (ear clipping), each triangle is cut by the
//! plane with the edge intersection points shared between neighbouring triangles (so the
//! pieces stay watertight), the sub-triangles of each original face on each side are merged
//! back into polygon faces (their boundary loops), and the cut plane's boundary loops become
//! the caps (outer loops as polygon faces; a cap with holes is triangulated with its holes).
//! Each side is split into its connected pieces. Vertices within `eps` of the plane are
//! snapped onto it and belong to both sides.
//!
//! Sign convention: the plane `n · x = d`; the *negative* side is `n · x < d`. The negative
//! pieces' caps face +n, the positive pieces' caps face −n.

use super::polygon::{Frame, Plane, area_vector, signed_area_2d, triangulate_2d};
use super::{Mesh, Point3};
use std::collections::{BTreeMap, HashMap};

/// Outcome of [`split`], in the style of parry's `SplitResult`.
#[derive(Clone, Debug, PartialEq)]
pub enum SplitResult {
    /// The plane crosses the solid: pieces on the negative and positive sides (each side may
    /// have several disconnected pieces, e.g. a U cut across both legs).
    Pair {
        /// The pieces on the side the normal points away from.
        negative: Vec<Mesh>,
        /// The pieces on the side it points to.
        positive: Vec<Mesh>,
    },
    /// Everything is on the negative side (or on the plane).
    Negative,
    /// Everything is on the positive side (or on the plane).
    Positive,
}

/// A triangle of the input with the index of the face it came from.
#[derive(Clone, Copy)]
struct Tri {
    v: [usize; 3],
    face: usize,
}

/// Splits `mesh` (closed, outward-oriented, planar faces) by `plane`; `eps` is the absolute
/// distance under which a vertex counts as on the plane.
pub fn split(mesh: &Mesh, plane: &Plane, eps: f64) -> SplitResult {
    let side = sides(mesh, plane, eps);
    if side.iter().all(|&s| s >= 0) {
        return SplitResult::Positive;
    }
    if side.iter().all(|&s| s <= 0) {
        return SplitResult::Negative;
    }
    let mut work = Working::new(mesh, plane, side);
    let out = work.split_triangles(&triangulate(mesh));
    let build = |tris: &[Tri], cap_normal: nalgebra::Vector3<f64>| -> Vec<Mesh> {
        pieces(mesh, &work.verts, &work.on_diagonal, tris, plane, cap_normal)
    };
    SplitResult::Pair { negative: build(&out[0], plane.normal), positive: build(&out[1], -plane.normal) }
}

/// Each vertex's side of `plane`: 1 above `eps`, −1 below −`eps`, 0 on it.
fn sides(mesh: &Mesh, plane: &Plane, eps: f64) -> Vec<i8> {
    let side_of = |p: &Point3| {
        let d = plane.distance(p);
        if d > eps {
            1
        } else if d < -eps {
            -1
        } else {
            0
        }
    };
    mesh.vertices.iter().map(side_of).collect()
}

/// The split's working vertex list: the input's (those on the plane projected onto it), then
/// the intersection points, each made once per edge.
struct Working<'a> {
    plane: &'a Plane,
    verts: Vec<Point3>,
    vside: Vec<i8>,
    cut_point: HashMap<(usize, usize), usize>,
    /// Edges of the input faces: a cut point on any other edge lies on a triangulation
    /// diagonal, inside a straight cut segment, and is dropped from the output loops.
    original_edges: std::collections::HashSet<(usize, usize)>,
    on_diagonal: Vec<bool>,
}

impl<'a> Working<'a> {
    fn new(mesh: &Mesh, plane: &'a Plane, side: Vec<i8>) -> Self {
        let verts: Vec<Point3> = mesh
            .vertices
            .iter()
            .zip(&side)
            .map(|(p, &s)| if s == 0 { p - plane.normal * plane.distance(p) } else { *p })
            .collect();
        let mut original_edges = std::collections::HashSet::new();
        for face in &mesh.faces {
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                original_edges.insert((a.min(b), a.max(b)));
            }
        }
        let on_diagonal = vec![false; verts.len()];
        Self { plane, verts, vside: side, cut_point: HashMap::new(), original_edges, on_diagonal }
    }

    /// The point where edge (a, b) crosses the plane, projected onto it.
    fn intersect(&mut self, a: usize, b: usize) -> usize {
        let key = (a.min(b), a.max(b));
        if let Some(&x) = self.cut_point.get(&key) {
            return x;
        }
        self.on_diagonal.push(!self.original_edges.contains(&key));
        let (p, q) = (self.verts[key.0], self.verts[key.1]);
        let (dp, dq) = (self.plane.distance(&p), self.plane.distance(&q));
        let t = dp / (dp - dq);
        let x = p + (q - p) * t;
        self.verts.push(x - self.plane.normal * self.plane.distance(&x));
        self.vside.push(0);
        let index = self.verts.len() - 1;
        self.cut_point.insert(key, index);
        index
    }

    /// The sub-triangles on the negative side, then on the positive side.
    fn split_triangles(&mut self, tris: &[Tri]) -> [Vec<Tri>; 2] {
        let mut out: [Vec<Tri>; 2] = [Vec::new(), Vec::new()];
        for t in tris {
            let s = t.v.map(|i| self.vside[i]);
            let (neg, pos) = (s.iter().any(|&x| x < 0), s.iter().any(|&x| x > 0));
            match (neg, pos) {
                (false, false) => {
                    // On the plane: a boundary face of the side the solid lies on.
                    let n = area_vector(&t.v.map(|i| self.verts[i]));
                    out[if n.dot(&self.plane.normal) > 0.0 { 0 } else { 1 }].push(*t);
                }
                (true, false) => out[0].push(*t),
                (false, true) => out[1].push(*t),
                (true, true) => self.split_triangle(t, &mut out),
            }
        }
        out
    }

    /// Walks a triangle that crosses the plane, emits the polygon on each side, fans it.
    fn split_triangle(&mut self, t: &Tri, out: &mut [Vec<Tri>; 2]) {
        let mut polys: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
        for k in 0..3 {
            let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
            let (sa, sb) = (self.vside[a], self.vside[b]);
            if sa <= 0 {
                polys[0].push(a);
            }
            if sa >= 0 {
                polys[1].push(a);
            }
            if sa * sb < 0 {
                let x = self.intersect(a, b);
                polys[0].push(x);
                polys[1].push(x);
            }
        }
        for (k, poly) in polys.iter().enumerate() {
            for i in 1..poly.len().saturating_sub(1) {
                out[k].push(Tri { v: [poly[0], poly[i], poly[i + 1]], face: t.face });
            }
        }
    }
}

/// Ear-clipped triangles of every face (faces are planar and simple).
fn triangulate(mesh: &Mesh) -> Vec<Tri> {
    mesh.triangles().into_iter().map(|(v, face)| Tri { v, face }).collect()
}

/// Directed boundary edges (used once, not cancelled by a reverse edge) of a triangle set, in
/// ascending order. (A sorted list and binary searches: a third of the cost of a map.)
fn boundary_edges(tris: &[Tri]) -> Vec<(usize, usize)> {
    let mut edges: Vec<(usize, usize)> = Vec::with_capacity(3 * tris.len());
    for t in tris {
        for k in 0..3 {
            let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
            if a != b {
                edges.push((a, b));
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges.iter().copied().filter(|&(a, b)| edges.binary_search(&(b, a)).is_err()).collect()
}

/// Chains directed edges into closed loops (deterministic: starts from the smallest edge).
fn loops(edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let mut next: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &(a, b) in edges {
        next.entry(a).or_default().push(b);
    }
    let mut out = Vec::new();
    while let Some((&start, _)) = next.iter().find(|(_, v)| !v.is_empty()) {
        let mut lp = vec![start];
        let mut cur = start;
        while let Some(list) = next.get_mut(&cur) {
            let Some(n) = list.pop() else { break };
            if n == start {
                break;
            }
            lp.push(n);
            cur = n;
            if lp.len() > edges.len() {
                break;
            }
        }
        if lp.len() >= 3 {
            out.push(lp);
        }
    }
    out
}

/// Faces of one side: merged polygons per original face, plus caps; split into pieces.
fn pieces(
    mesh: &Mesh,
    verts: &[Point3],
    on_diagonal: &[bool],
    tris: &[Tri],
    plane: &Plane,
    cap_normal: nalgebra::Vector3<f64>,
) -> Vec<Mesh> {
    let mut faces: Vec<Vec<usize>> = Vec::new();
    let mut by_face: BTreeMap<usize, Vec<Tri>> = BTreeMap::new();
    for t in tris {
        by_face.entry(t.face).or_default().push(*t);
    }
    for (&f, group) in &by_face {
        for lp in loops(&boundary_edges(group)) {
            // Ear clipping skips collinear vertices of the input face: put them back, or the
            // neighbouring face (which has them) would meet this one at a T-junction.
            let lp = expand(&lp, &mesh.faces[f], verts);
            let lp: Vec<usize> = lp.into_iter().filter(|&v| !on_diagonal[v]).collect();
            if lp.len() >= 3 {
                faces.push(lp);
            }
        }
    }
    // The side's open boundary lies on the plane: close it with caps.
    let mut side_faces_tris: Vec<Tri> = Vec::new();
    for f in &faces {
        for i in 1..f.len() - 1 {
            side_faces_tris.push(Tri { v: [f[0], f[i], f[i + 1]], face: 0 });
        }
    }
    // Boundary of the side, reversed, is the caps' boundary (caps face `cap_normal`).
    let open: Vec<(usize, usize)> = boundary_edges(&side_faces_tris).into_iter().map(|(a, b)| (b, a)).collect();
    faces.extend(caps(verts, &loops(&open), plane, cap_normal));
    split_connected(verts, faces)
}

/// Cap faces from loops on the plane: loops CCW about `cap_normal` are outer boundaries, the
/// others holes; an outer loop with holes is triangulated together with them.
fn caps(verts: &[Point3], loops: &[Vec<usize>], plane: &Plane, cap_normal: nalgebra::Vector3<f64>) -> Vec<Vec<usize>> {
    let origin = Point3::from(plane.normal * plane.offset);
    let frame = Frame::from_normal(origin, cap_normal);
    let rings: Vec<Vec<[f64; 2]>> = loops.iter().map(|l| l.iter().map(|&i| frame.to_2d(&verts[i])).collect()).collect();
    let (outer, holes): (Vec<usize>, Vec<usize>) = (0..loops.len()).partition(|&k| signed_area_2d(&rings[k]) > 0.0);
    let mut owner: Vec<Vec<usize>> = vec![Vec::new(); loops.len()];
    for &h in &holes {
        // The smallest outer loop containing the hole's first vertex.
        let p = rings[h][0];
        let best = outer
            .iter()
            .filter(|&&o| contains(&rings[o], p))
            .min_by(|&&a, &&b| signed_area_2d(&rings[a]).total_cmp(&signed_area_2d(&rings[b])));
        if let Some(&o) = best {
            owner[o].push(h);
        }
    }
    let mut out = Vec::new();
    for &o in &outer {
        if owner[o].is_empty() {
            out.push(loops[o].clone());
            continue;
        }
        let mut ids: Vec<usize> = loops[o].clone();
        let mut pts: Vec<[f64; 2]> = rings[o].clone();
        let mut starts = Vec::new();
        for &h in &owner[o] {
            starts.push(ids.len());
            ids.extend(&loops[h]);
            pts.extend(&rings[h]);
        }
        for t in triangulate_2d(&pts, &starts) {
            // Ear clipping skipped collinear boundary vertices: put them back so the cap
            // meets the side faces vertex to vertex.
            let mut face = t.map(|k| ids[k]).to_vec();
            for &l in std::iter::once(&o).chain(&owner[o]) {
                face = expand(&face, &loops[l], verts);
            }
            out.push(face);
        }
    }
    out
}

/// Inserts into `lp` the vertices of `reference` (a loop in the same orientation) that lie
/// strictly between two consecutive vertices of `lp` along `reference` and on the straight
/// segment joining them (the collinear vertices an ear clipper drops).
fn expand(lp: &[usize], reference: &[usize], verts: &[Point3]) -> Vec<usize> {
    let pos: HashMap<usize, usize> = reference.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    let n = reference.len();
    let mut out = Vec::with_capacity(lp.len());
    for k in 0..lp.len() {
        let (a, b) = (lp[k], lp[(k + 1) % lp.len()]);
        out.push(a);
        let (Some(&ia), Some(&ib)) = (pos.get(&a), pos.get(&b)) else { continue };
        let gap = (ib + n - ia) % n;
        if gap < 2 || gap >= n - 1 {
            continue;
        }
        let (pa, pb) = (verts[a], verts[b]);
        let len = (pb - pa).norm();
        let between: Vec<usize> = (1..gap).map(|j| reference[(ia + j) % n]).collect();
        let collinear = between.iter().all(|&v| {
            let p = verts[v];
            let t = (p - pa).dot(&(pb - pa)) / (len * len);
            t > 0.0 && t < 1.0 && ((p - pa) - (pb - pa) * t).norm() <= 1e-9 * len
        });
        if collinear {
            out.extend(between);
        }
    }
    out
}

fn contains(ring: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut inside = false;
    let n = ring.len();
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]) {
            inside = !inside;
        }
    }
    inside
}

/// Groups faces into edge-connected pieces and re-indexes each piece's vertices compactly.
fn split_connected(verts: &[Point3], faces: Vec<Vec<usize>>) -> Vec<Mesh> {
    let n = faces.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let mut edge_owner: HashMap<(usize, usize), usize> = HashMap::new();
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            if let Some(&g) = edge_owner.get(&(a.min(b), a.max(b))) {
                let (ra, rb) = (find(&mut parent, f), find(&mut parent, g));
                parent[ra.max(rb)] = ra.min(rb);
            } else {
                edge_owner.insert((a.min(b), a.max(b)), f);
            }
        }
    }
    let mut groups: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for f in 0..n {
        groups.entry(find(&mut parent, f)).or_default().push(f);
    }
    groups
        .values()
        .map(|fs| {
            let mut map: BTreeMap<usize, usize> = BTreeMap::new();
            let mut vertices = Vec::new();
            let faces = fs
                .iter()
                .map(|&f| {
                    faces[f]
                        .iter()
                        .map(|&v| {
                            *map.entry(v).or_insert_with(|| {
                                vertices.push(verts[v]);
                                vertices.len() - 1
                            })
                        })
                        .collect()
                })
                .collect();
            Mesh { vertices, faces }
        })
        .collect()
}
