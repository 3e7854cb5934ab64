//! Mesh validation and repair: weld, drop collapsed faces, check closed and manifold, make the
//! orientation consistent and outward, triangulate non-planar faces, reject degenerate solids.
//!
//! Errors name the face or vertex (indices into the mesh as given); the caller adds the file and
//! block. Repairs that change the mesh are returned as warnings, never done silently.

use super::LookupMap;
use super::polygon::{Frame, area_vector, planarity_deviation};
use super::tolerances::AbsTolerances;
use super::{MassProperties, Mesh, Point3};
use std::collections::VecDeque;
use thiserror::Error;

/// Why a mesh cannot be used as a block.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    /// The mesh has no vertices or no faces.
    #[error("the mesh is empty ({vertices} vertices, {faces} faces); a block needs a closed surface")]
    Empty {
        /// Its vertex count.
        vertices: usize,
        /// Its face count.
        faces: usize,
    },
    /// A coordinate is infinite or NaN.
    #[error("vertex {vertex} has a non-finite coordinate {coords:?}")]
    NonFinite {
        /// The vertex's index.
        vertex: usize,
        /// Its coordinates as given.
        coords: [f64; 3],
    },
    /// A coordinate is beyond the range where the tolerances still resolve.
    #[error("vertex {vertex} at {coords:?} is out of range: coordinates are limited to ±{limit:e} (m)")]
    OutOfRange {
        /// The vertex's index.
        vertex: usize,
        /// Its coordinates, m.
        coords: [f64; 3],
        /// The largest magnitude allowed, m.
        limit: f64,
    },
    #[error(
        "vertex {vertex} at {coords:?} lies {} m beyond the rest of the model along {axis}, more than \
         {} times the rest's size ({} m): every tolerance is relative to the model size, so it would \
         set them for every block (a corrupt or misplaced coordinate?)",
        super::format::significant(*.gap), super::format::significant(*.limit), super::format::significant(*.size)
    )]
    /// A vertex is cut off from the rest of the model by a gap many times its size (a corrupt coordinate).
    FarOutside {
        /// The vertex's index.
        vertex: usize,
        /// Its coordinates, m.
        coords: [f64; 3],
        /// The axis of the gap (`x`, `y` or `z`).
        axis: char,
        /// The gap, m.
        gap: f64,
        /// The size of the rest of the model along that axis, m.
        size: f64,
        /// The largest gap allowed, as a multiple of that size.
        limit: f64,
    },
    #[error(
        "its vertices ({vertices}) all lie at one point {coords:?}: a block needs a volume (a degenerate or corrupt mesh)"
    )]
    /// All vertices coincide: no volume.
    Point {
        /// The vertex count.
        vertices: usize,
        /// The one point, m.
        coords: [f64; 3],
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {index}, but there are only {count} vertices")]
    BadIndex {
        /// The face's index.
        face: usize,
        /// The vertex index it gives.
        index: usize,
        /// The vertex count.
        count: usize,
    },
    /// A face has fewer than 3 vertices.
    #[error("face {face} has {count} vertices; a face needs at least 3")]
    TooFewVertices {
        /// The face's index.
        face: usize,
        /// Its vertex count.
        count: usize,
    },
    /// An edge has no neighbouring face: the surface has a hole.
    #[error("the mesh is not closed: edge ({a}, {b}) of face {face} has no neighbouring face (a hole in the surface)")]
    Open {
        /// The face's index.
        face: usize,
        /// The edge's first vertex.
        a: usize,
        /// The edge's second vertex.
        b: usize,
    },
    /// An edge is shared by more than two faces.
    #[error("the mesh is not manifold: edge ({a}, {b}) is shared by {count} faces (first: face {face})")]
    NonManifold {
        /// The first face's index.
        face: usize,
        /// The edge's first vertex.
        a: usize,
        /// The edge's second vertex.
        b: usize,
        /// How many faces share it.
        count: usize,
    },
    /// Two faces cannot be oriented consistently (a one-sided surface).
    #[error("faces {face} and {other} cannot be oriented consistently (a one-sided surface, e.g. a Möbius strip)")]
    NonOrientable {
        /// One face's index.
        face: usize,
        /// The other face's index.
        other: usize,
    },
    /// The enclosed volume is zero or negligible for the block's size.
    #[error("the enclosed volume {volume:e} is zero or too small for the block's size (flat or degenerate mesh)")]
    ZeroVolume {
        /// The volume, m³.
        volume: f64,
    },
}

/// A repair that changed the mesh.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshWarning {
    /// Vertices closer than the weld tolerance were merged.
    Welded {
        /// How many vertices were merged away.
        merged: usize,
    },
    /// A degenerate face was left out.
    DroppedFace {
        /// The face's index.
        face: usize,
        /// Why (zero area, repeated vertices).
        why: &'static str,
    },
    /// Faces turned to agree with their neighbours' orientation.
    FlippedFaces {
        /// How many were flipped.
        count: usize,
    },
    /// The whole surface was turned inside out so that its normals point outwards.
    InvertedOrientation,
    /// A non-planar face was split into triangles.
    Triangulated {
        /// The face's index.
        face: usize,
        /// Its largest distance from its best-fit plane, m.
        deviation: f64,
    },
}

impl std::fmt::Display for MeshWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshWarning::Welded { merged } => write!(f, "welded {merged} duplicate vertices"),
            MeshWarning::DroppedFace { face, why } => write!(f, "dropped face {face}: {why}"),
            MeshWarning::FlippedFaces { count } => {
                write!(f, "flipped {count} faces to make the orientation consistent")
            }
            MeshWarning::InvertedOrientation => {
                write!(f, "the faces were oriented inwards; flipped all of them")
            }
            MeshWarning::Triangulated { face, deviation } => {
                write!(f, "face {face} is not planar (deviation {deviation:e}); triangulated it")
            }
        }
    }
}

/// A valid mesh and what was changed to get it.
#[derive(Debug, Clone)]
pub struct Repaired {
    /// The closed, manifold, outward-oriented mesh with planar faces.
    pub mesh: Mesh,
    /// Its volume, centroid and inertia per unit density.
    pub mass: MassProperties,
    /// Each repair made, in order.
    pub warnings: Vec<MeshWarning>,
}

/// Validates and repairs `mesh` with tolerances resolved for the model's size.
pub fn repair(mesh: &Mesh, tol: &AbsTolerances) -> Result<Repaired, MeshError> {
    if mesh.vertices.is_empty() || mesh.faces.is_empty() {
        return Err(MeshError::Empty { vertices: mesh.vertices.len(), faces: mesh.faces.len() });
    }
    for (i, p) in mesh.vertices.iter().enumerate() {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(MeshError::NonFinite { vertex: i, coords: [p.x, p.y, p.z] });
        }
    }
    for (f, face) in mesh.faces.iter().enumerate() {
        if face.len() < 3 {
            return Err(MeshError::TooFewVertices { face: f, count: face.len() });
        }
        if let Some(&index) = face.iter().find(|&&i| i >= mesh.vertices.len()) {
            return Err(MeshError::BadIndex { face: f, index, count: mesh.vertices.len() });
        }
    }
    let mut warnings = Vec::new();
    let (vertices, remap, merged) = weld(&mesh.vertices, tol.weld);
    if merged > 0 {
        warnings.push(MeshWarning::Welded { merged });
    }
    // Faces in welded indices; `origin[k]` is the input face index of face k (for messages).
    let mut faces = Vec::with_capacity(mesh.faces.len());
    let mut origin = Vec::with_capacity(mesh.faces.len());
    for (f, face) in mesh.faces.iter().enumerate() {
        let mut loop_: Vec<usize> = Vec::with_capacity(face.len());
        for &i in face {
            let j = remap[i];
            if loop_.last() != Some(&j) {
                loop_.push(j);
            }
        }
        while loop_.len() > 1 && loop_.first() == loop_.last() {
            loop_.pop();
        }
        if loop_.len() < 3 {
            warnings.push(MeshWarning::DroppedFace { face: f, why: "collapsed by welding" });
            continue;
        }
        faces.push(loop_);
        origin.push(f);
    }
    orient_consistently(&mut faces, &origin, &mut warnings)?;
    let mut out = Mesh { vertices, faces };
    let mut mass = MassProperties::of_mesh(&out);
    if mass.volume < 0.0 {
        for face in &mut out.faces {
            face.reverse();
        }
        warnings.push(MeshWarning::InvertedOrientation);
        mass = MassProperties::of_mesh(&out);
    }
    let diag = out.aabb().diagonal();
    // Written so that a NaN volume is rejected too.
    if mass.volume.partial_cmp(&(tol.min_volume_rel * diag.powi(3))) != Some(std::cmp::Ordering::Greater) {
        return Err(MeshError::ZeroVolume { volume: mass.volume });
    }
    triangulate_non_planar(&mut out, &origin, tol.planarity, &mut warnings);
    Ok(Repaired { mesh: out, mass, warnings })
}

/// Merges vertices closer than `tol` (grid hashing with cell size `tol`, neighbours checked).
/// Returns the kept vertices, the map old index → new index and the number merged.
fn weld(points: &[Point3], tol: f64) -> (Vec<Point3>, Vec<usize>, usize) {
    let mut grid: LookupMap<[i64; 3], Vec<usize>> = LookupMap::default();
    grid.reserve(points.len());
    let mut kept: Vec<Point3> = Vec::with_capacity(points.len());
    let mut remap = Vec::with_capacity(points.len());
    let origin = points.first().map_or_else(Point3::origin, |&first| points.iter().fold(first, |m, p| m.inf(p)));
    for p in points {
        let k = grid_cell(p, &origin, tol);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let neighbour = [k[0].saturating_add(dx), k[1].saturating_add(dy), k[2].saturating_add(dz)];
                    if let Some(list) = grid.get(&neighbour)
                        && let Some(&j) = list.iter().find(|&&j| (kept[j] - p).norm() <= tol)
                    {
                        found = Some(j);
                        break 'search;
                    }
                }
            }
        }
        let j = found.unwrap_or_else(|| {
            kept.push(*p);
            grid.entry(k).or_default().push(kept.len() - 1);
            kept.len() - 1
        });
        remap.push(j);
    }
    let merged = points.len() - kept.len();
    (kept, remap, merged)
}

/// The weld grid's cell of `p`: counted from the points' lowest corner (small integers for any
/// model in any unit) and saturating, so no coordinate or tolerance can overflow the neighbour
/// arithmetic; saturation is monotone, so two points within `tol` still fall in the same or
/// adjacent cells and the distance test stays exact.
fn grid_cell(p: &Point3, origin: &Point3, tol: f64) -> [i64; 3] {
    let c = |k: usize| ((p[k] - origin[k]) / tol).floor() as i64;
    [c(0), c(1), c(2)]
}

/// Checks that every edge has exactly two faces and flips faces (breadth first from face 0 of
/// each connected patch) until every edge is used once in each direction.
fn orient_consistently(
    faces: &mut [Vec<usize>],
    origin: &[usize],
    warnings: &mut Vec<MeshWarning>,
) -> Result<(), MeshError> {
    // undirected edge -> [(face, forward?)]
    let mut edges: LookupMap<(usize, usize), Vec<(usize, bool)>> = LookupMap::default();
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            let key = (a.min(b), a.max(b));
            edges.entry(key).or_default().push((f, a < b));
        }
    }
    // Report the first offending edge in face order, deterministically.
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            let uses = &edges[&(a.min(b), a.max(b))];
            match uses.len() {
                2 => {}
                1 => return Err(MeshError::Open { face: origin[f], a, b }),
                count => {
                    return Err(MeshError::NonManifold { face: origin[uses[0].0], a, b, count });
                }
            }
        }
    }
    let n = faces.len();
    let mut flip: Vec<Option<bool>> = vec![None; n];
    let mut queue = VecDeque::new();
    for seed in 0..n {
        if flip[seed].is_some() {
            continue;
        }
        flip[seed] = Some(false);
        queue.push_back(seed);
        while let Some(f) = queue.pop_front() {
            let face = &faces[f];
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                for &(g, g_forward) in &edges[&(a.min(b), a.max(b))] {
                    if g == f {
                        continue;
                    }
                    // Consistent neighbours traverse the shared edge in opposite directions.
                    let f_dir = (a < b) != flip[f].unwrap();
                    let needed = g_forward == f_dir; // same direction: g must be flipped
                    match flip[g] {
                        None => {
                            flip[g] = Some(needed);
                            queue.push_back(g);
                        }
                        Some(x) if x != needed => {
                            return Err(MeshError::NonOrientable { face: origin[f], other: origin[g] });
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    let count = flip.iter().filter(|x| **x == Some(true)).count();
    if count > 0 {
        for (face, fl) in faces.iter_mut().zip(&flip) {
            if *fl == Some(true) {
                face.reverse();
            }
        }
        // Flipping the larger part is the same repair as flipping the smaller one plus a global
        // inversion; report the smaller number so the warning describes the actual defect.
        warnings.push(MeshWarning::FlippedFaces { count: count.min(n - count) });
    }
    Ok(())
}

/// Replaces faces that leave their plane by more than `tol` with ear-clipped triangles.
fn triangulate_non_planar(mesh: &mut Mesh, origin: &[usize], tol: f64, warnings: &mut Vec<MeshWarning>) {
    let mut out = Vec::with_capacity(mesh.faces.len());
    let mut earcut = earcut::Earcut::new();
    let mut tris: Vec<usize> = Vec::new();
    for (k, face) in mesh.faces.iter().enumerate() {
        let pts: Vec<Point3> = face.iter().map(|&i| mesh.vertices[i]).collect();
        let deviation = planarity_deviation(&pts);
        if face.len() <= 3 || deviation <= tol {
            out.push(face.clone());
            continue;
        }
        let frame = Frame::from_normal(pts[0], area_vector(&pts));
        earcut.earcut(pts.iter().map(|p| frame.to_2d(p)), &[] as &[usize], &mut tris);
        if tris.is_empty() {
            // Ear clipping failed (self-overlapping projection): fall back to a fan.
            tris = (1..face.len() - 1).flat_map(|i| [0, i, i + 1]).collect();
        }
        let p2: Vec<[f64; 2]> = pts.iter().map(|p| frame.to_2d(p)).collect();
        for t in tris.chunks(3) {
            // Keep the face's orientation whatever the triangulator's winding.
            let ccw = super::polygon::signed_area_2d(&[p2[t[0]], p2[t[1]], p2[t[2]]]) >= 0.0;
            let (b, c) = if ccw { (t[1], t[2]) } else { (t[2], t[1]) };
            out.push(vec![face[t[0]], face[b], face[c]]);
        }
        warnings.push(MeshWarning::Triangulated { face: origin[k], deviation });
    }
    mesh.faces = out;
}
