//! Contacts that close under large motion: between two blocks that no interface contact holds —
//! they did not touch at the start, or their interface's contacts were released — from the
//! blocks' exact convex parts ([`part_touches`]: every vertex within reach of the other part,
//! with its nearest boundary point and normal). Rebuilt every step, after the persistent
//! contacts, so a corner that
//! lands on a face, a voussoir that falls onto another, or a block that slid off its joint and
//! hits its neighbour is a contact of the step in which it closes, and is released when it opens.
//!
//! Only a pair one of whose blocks has moved by more than the envelope since the start, or is
//! held by no interface at all (a block set on its edge, or above its support), is queried: at
//! the start every contact of a block that has interfaces is an interface's (the statics' force
//! points), so the first step stays the kinematic check's rate problem, and edges that merely
//! touch in the design (a stack bond's diagonal neighbours) carry nothing until the blocks move.
//! A pair farther apart than its reach along the line of its centroids ([`apart`]: a few dot
//! products) is passed over without parry's query, which would find nothing in it.
//!
//! Shapes are given to parry (f32) relative to each block's centroid in units of the smallest
//! block's size, and the pair's relative pose is formed in f64 first: a contact point is exact to
//! ~1e-7 of a block whatever the model's size or distance from the origin.

use super::World;
use super::contacts::{Contact, Origin, Side, TouchVertex};
use super::problem::Active;
use crate::geometry::polygon::Frame;
use crate::geometry::{Point3, Vector3};
use crate::interfaces::penetration::{convex_shapes, hull_shape, v32};
use crate::model::AssemblyBlock;
use nalgebra::UnitQuaternion;
use rapier3d::math::{Pose, Rotation, Vector};
use rapier3d::parry::query::{DefaultQueryDispatcher, QueryDispatcher};
use rapier3d::parry::shape::SharedShape;
use std::sync::{Arc, OnceLock};

/// Every block's convex parts, built when a pair first needs them.
#[derive(Clone)]
pub(super) struct Solids {
    blocks: Arc<[AssemblyBlock]>,
    /// Per block: its start centroid (m) and the farthest vertex from it (m).
    centres: Vec<(Point3, f64)>,
    parts: Vec<OnceLock<Arc<[Part]>>>,
    /// The shapes' length unit, m (the smallest block's size).
    unit: f64,
}

impl Solids {
    /// The blocks' parts in units of the smallest block's size: parry's tolerances are
    /// absolute in shape units, so a unit set by a large support would blur the small blocks'
    /// contacts (a corner 0.3 mm above a 10 m slab reported inside it).
    pub fn new(blocks: &[AssemblyBlock]) -> Self {
        let unit = blocks.iter().map(|b| b.aabb.diagonal()).filter(|d| *d > 0.0).fold(f64::INFINITY, f64::min);
        let unit = if unit.is_finite() { unit } else { 1.0 };
        let centres = blocks
            .iter()
            .map(|b| {
                let c = b.mass.centroid;
                (c, b.mesh.vertices.iter().map(|p| (p - c).norm()).fold(0.0, f64::max))
            })
            .collect();
        Self { blocks: blocks.into(), centres, parts: vec![OnceLock::new(); blocks.len()], unit }
    }

    /// Whether the world point `p` is inside block `i` placed at centroid `x` turned by `q` from
    /// its start (deeper than `depth` m).
    pub fn contains(&self, i: usize, x: &Point3, q: &UnitQuaternion<f64>, p: &Point3, depth: f64) -> bool {
        let local = v32(q.inverse() * (p - x) / self.unit);
        let depth = (depth / self.unit) as f32;
        self.parts(i).iter().any(|s| {
            let proj = s.shape.project_local_point(local, false);
            proj.is_inside && (proj.point - local).length() > depth
        })
    }

    /// Block `i`'s size, m: its bounding-box diagonal.
    pub fn size(&self, i: usize) -> f64 {
        self.blocks[i].aabb.diagonal().max(f64::MIN_POSITIVE)
    }

    /// Every block's centroid at the start, in block order.
    pub fn starts(&self) -> impl Iterator<Item = Point3> + '_ {
        self.centres.iter().map(|c| c.0)
    }

    /// Block `i`'s convex parts (its hull when it has no exact decomposition within the limits).
    fn parts(&self, i: usize) -> Arc<[Part]> {
        let (b, unit) = (&self.blocks[i], self.unit);
        self.parts[i]
            .get_or_init(|| {
                let tol = 1e-3 * b.aabb.diagonal();
                let shapes = convex_shapes(b, tol, unit).or_else(|| hull_shape(b, unit).map(|h| vec![h]));
                shapes.unwrap_or_default().into_iter().map(Part::new).collect()
            })
            .clone()
    }
}

/// A convex part (shape units) with its vertices and face planes in f64, read once.
pub(super) struct Part {
    shape: SharedShape,
    points: Vec<Vector3>,
    /// Outward unit normal n and offset d of each face: n · p = d on the face.
    planes: Vec<(Vector3, f64)>,
}

impl Part {
    fn new(shape: SharedShape) -> Self {
        let f64v = |v: Vector| Vector3::new(v.x as f64, v.y as f64, v.z as f64);
        let (points, planes) = match shape.as_convex_polyhedron() {
            Some(poly) => {
                let (points, around) = (poly.points(), poly.vertices_adj_to_face());
                let planes = poly
                    .faces()
                    .iter()
                    .map(|f| {
                        let n = f64v(f.normal);
                        (n, n.dot(&f64v(points[around[f.first_vertex_or_edge as usize] as usize])))
                    })
                    .collect();
                (points.iter().map(|p| f64v(*p)).collect(), planes)
            }
            None => (Vec::new(), Vec::new()),
        };
        Self { shape, points, planes }
    }
}

/// A block's pose now: centroid (m) and rotation since the start, and a bound on its points'
/// speed (m/s).
pub(super) struct Placed {
    pub x: Point3,
    pub q: UnitQuaternion<f64>,
    pub speed: f64,
}

impl World {
    /// Whether interface contact `c` overlaps for real: b's material point inside a's convex
    /// parts by more than half the envelope.
    /// Once faces have slipped or turned far, a vertex below the other face's plane can be
    /// beside that face, not in it: such a contact is no longer the faces' and is released (a
    /// touch takes over where the blocks do meet).
    pub(super) fn really_overlaps(&self, c: &Contact) -> bool {
        let poses = self.poses();
        let block = |s: Side| poses.of(s).map(|body| body.block);
        let (Some([i, j]), Some(b)) = (c.pair, block(c.b)) else { return true };
        let a = block(c.a).unwrap_or(if b == i { j } else { i });
        let pa = self.placed(a);
        let pb = c.point_b(poses);
        self.solids.contains(a, &pa.x, &pa.q, &pb, 0.5 * self.settings.envelope * c.scale)
    }

    /// Drops the last step's touches and finds this step's (module docs), each starting from
    /// the force and state its point had in the last step, where it was found there too. Returns
    /// the persistent contacts' [`World::near`] it read (by contact, None where not read), for
    /// the step's near contacts to take up.
    pub(super) fn find_touches(&mut self) -> Vec<Option<Option<Active>>> {
        let last: Vec<Contact> = self.contacts.drain(self.persistent..).collect();
        let envelope = self.settings.envelope;
        let candidates = self.touch_candidates(envelope);
        if candidates.is_empty() {
            return Vec::new();
        }
        let mut last: Vec<(([usize; 2], Origin), &Contact)> =
            last.iter().filter_map(|c| Some(((c.pair?, c.origin), c))).collect();
        last.sort_unstable_by_key(|(k, _)| *k);
        let (held, known) = self.held_pairs(&candidates);
        let mut found = Vec::new();
        for &[i, j] in candidates.iter().filter(|p| held.binary_search(p).is_err()) {
            let (pi, pj) = (self.placed(i), self.placed(j));
            let scale = self.solids.size(i).min(self.solids.size(j));
            let prediction = envelope * scale + 2.0 * self.ctx.h * (pi.speed + pj.speed);
            let (ri, rj) = (self.solids.centres[i].1, self.solids.centres[j].1);
            if (pj.x - pi.x).norm() > ri + rj + prediction {
                continue;
            }
            // Built only for pairs within their spheres' reach (a block nothing nears keeps none).
            let (si, sj) = (self.solids.parts(i), self.solids.parts(j));
            let units = (prediction / self.solids.unit, self.solids.unit);
            if apart((&si, &pi), (&sj, &pj), units) {
                continue;
            }
            self.pair_touches((i, &si, &pi), (j, &sj, &pj), prediction, &mut found);
        }
        for c in &mut found {
            let key = (c.pair.unwrap_or_default(), c.origin);
            if let Ok(k) = last.binary_search_by_key(&key, |(k, _)| *k) {
                let before = last[k].1;
                (c.last_normal, c.last_force, c.state) = (before.last_normal, before.last_force, before.state);
            }
        }
        self.contacts.extend(found);
        known
    }

    /// The pairs of blocks (ascending) one of which is awake and has moved by more than
    /// `envelope` of its own size since the start, the other any block.
    fn touch_candidates(&self, envelope: f64) -> Vec<[usize; 2]> {
        // A block held by no interface at the start (set on an edge, or above its support) may
        // meet any block from the first step.
        let moved = |b: &super::Body| {
            !self.interfaced[b.block]
                || (b.x - b.start).norm() + b.q.angle() * b.radius > envelope * self.solids.size(b.block)
        };
        let blocks = self.solids.centres.len();
        let mut moving = vec![false; blocks];
        let movers = self.bodies.iter().filter(|b| !b.asleep).chain(&self.movers);
        movers.filter(|b| moved(b)).for_each(|b| moving[b.block] = true);
        pairs_with(&moving)
    }

    /// Those of `candidates` an interface contact holds this step: one not released and within
    /// the envelope (or closing it), as the step's persistent contacts are chosen; and the
    /// [`World::near`] of each contact read for it (by contact, None where not read).
    fn held_pairs(&self, candidates: &[[usize; 2]]) -> (Vec<[usize; 2]>, Vec<Option<Option<Active>>>) {
        let mut known = vec![None; self.contacts.len()];
        let mut held = Vec::new();
        for (i, c) in self.contacts.iter().enumerate() {
            let Some(pair) = c.pair.filter(|p| candidates.binary_search(p).is_ok()) else { continue };
            if matches!(c.origin, Origin::Interface { .. }) {
                let near = self.near(i, c);
                known[i] = Some(near);
                if near.is_some() {
                    held.push(pair);
                }
            }
        }
        held.sort_unstable();
        held.dedup();
        (held, known)
    }

    pub(super) fn placed(&self, i: usize) -> Placed {
        match self.poses().of(self.sides[i]) {
            Some(b) => Placed { x: b.x, q: b.q, speed: b.v.norm() + b.w.norm() * b.radius },
            None => Placed { x: self.solids.centres[i].0, q: UnitQuaternion::identity(), speed: 0.0 },
        }
    }

    /// The contact points of blocks `i` and `j` within `prediction` (m), from every pair of
    /// their convex parts (`si`, `sj`), as contacts from i (side a) into j (side b).
    fn pair_touches(
        &self,
        (i, si, pi): (usize, &[Part], &Placed),
        (j, sj, pj): (usize, &[Part], &Placed),
        prediction: f64,
        out: &mut Vec<Contact>,
    ) {
        let unit = self.solids.unit;
        let (pos12, exact) = relative_pose(pi, pj, unit);
        let (a, b) = (self.sides[i], self.sides[j]);
        // A fixed side's material point is the world point; a moving one's its offset.
        let anchor =
            |s: Side, k: usize| if s == Side::Fixed { self.solids.centres[k].0.coords } else { Vector3::zeros() };
        let (oa, ob) = (anchor(a, i), anchor(b, j));
        let reach = (prediction / unit) as f32;
        for (pa, part_a) in si.iter().enumerate() {
            for (pb, part_b) in sj.iter().enumerate() {
                let poses = (&pos12, &exact);
                for point in part_touches(part_a, part_b, poses, reach) {
                    // b's material point back in b's own frame, in f64.
                    let on_b = pj.q.inverse() * (pi.x + pi.q * (point.on_b * unit) - pj.x);
                    out.push(Contact {
                        a,
                        b,
                        origin: Origin::Touch { parts: [pa, pb], point: point.vertex },
                        pair: Some([i, j]),
                        ra: oa + point.on_a * unit,
                        rb: ob + on_b,
                        frame: point.frame,
                        reach: f64::INFINITY,
                        scale: self.solids.size(i).min(self.solids.size(j)),
                        last_normal: 0.0,
                        last_force: Vector3::zeros(),
                        state: Default::default(),
                    });
                }
            }
        }
    }
}

/// The pairs of blocks (ascending) at least one of which is `moving`, without a sort: a moving
/// block pairs with every later block, a still one with the later moving ones.
fn pairs_with(moving: &[bool]) -> Vec<[usize; 2]> {
    let blocks = moving.len();
    let list: Vec<usize> = (0..blocks).filter(|&k| moving[k]).collect();
    let mut pairs = Vec::new();
    for i in 0..blocks {
        if moving[i] {
            pairs.extend((i + 1..blocks).map(|j| [i, j]));
        } else {
            pairs.extend(list[list.partition_point(|&j| j <= i)..].iter().map(|&j| [i, j]));
        }
    }
    pairs
}

/// Block j's pose in block i's frame (shape units of `unit` m): for parry (f32) and in f64.
fn relative_pose(pi: &Placed, pj: &Placed, unit: f64) -> (Pose, RelativePose) {
    let inv = pi.q.inverse();
    let exact = RelativePose { rot: inv * pj.q, t: inv * (pj.x - pi.x) / unit };
    let r = &exact.rot;
    let rot = Rotation::from_xyzw(r.i as f32, r.j as f32, r.k as f32, r.w as f32).normalize();
    (Pose::from_parts(v32(exact.t), rot), exact)
}

/// Whether two blocks' convex parts, each at its pose (centroid in m, rotation), are farther
/// apart than `reach` (shape units) along the line of their centroids: every vertex of the
/// first below every vertex of the second along it by more than that (and [`APART`]). Then
/// no point of either is within reach of the other and parry's query would find nothing: a
/// few dot products in place of its query, for neighbours apart across a joint.
fn apart((a, pa): (&[Part], &Placed), (b, pb): (&[Part], &Placed), (reach, unit): (f64, f64)) -> bool {
    let line = pb.x - pa.x;
    let Some(d) = line.try_normalize(f64::MIN_POSITIVE) else { return false };
    // The farthest a block's parts reach along `d` from its centroid, in shape units; None
    // where a part has no vertices (not a polyhedron: no bound).
    let farthest = |parts: &[Part], q: &UnitQuaternion<f64>, d: Vector3| {
        let local = q.inverse() * d;
        let far = |p: &Part| p.points.iter().map(|v| v.dot(&local)).reduce(f64::max);
        parts.iter().map(far).try_fold(f64::NEG_INFINITY, |m, r| Some(m.max(r?)))
    };
    let (Some(ahead), Some(behind)) = (farthest(a, &pa.q, d), farthest(b, &pb.q, -d)) else { return false };
    line.norm() / unit - ahead - behind > reach + APART
}

/// A contact point of two convex parts, in a's frame (a's shape units).
struct PartPoint {
    vertex: TouchVertex,
    /// The material points on a and on b, both in a's frame (b's at the pair's pose).
    on_a: Vector3,
    on_b: Vector3,
    /// n (from a into b), u, v.
    frame: [Vector3; 3],
}

/// Below this distance (shape units) a vertex and its projection are too close for the line
/// between them to be a normal: the pair's normal is taken.
const TOUCHING: f64 = 1e-5;

/// The contact points of convex parts `a` and `b` (b placed at `pos12` in a's frame) when they
/// are within `reach`: every vertex of either part within `reach` of the other part, with the
/// other part's nearest boundary point and the line between them as the normal (outside: the
/// gap; inside: the depth) — a vertex resting on a face gets the face's normal, one at an edge
/// the edge's — and parry's closest (or deepest) pair when no vertex is (two edges crossing).
/// The pair's normal serves where a vertex touches exactly. A contact manifold clipping two
/// faces can miss the far end of an edge lying on a face (the end that then swings in), and
/// one normal for the pair turns a vertex sliding off a corner into a deep overlap.
fn part_touches(a: &Part, b: &Part, (pos12, exact): (&Pose, &RelativePose), reach: f32) -> Vec<PartPoint> {
    let Ok(Some(c)) = DefaultQueryDispatcher.contact(pos12, a.shape.as_ref(), b.shape.as_ref(), reach) else {
        return Vec::new();
    };
    let f64v = |v: Vector| Vector3::new(v.x as f64, v.y as f64, v.z as f64);
    let pair = f64v(c.normal1);
    if pair.norm().is_nan() || pair.norm() <= 0.5 {
        return Vec::new();
    }
    let pair = pair.normalize();
    let point = |vertex, on_a: Vector3, on_b: Vector3, n: Vector3| {
        let f = Frame::from_normal(Point3::origin(), n);
        PartPoint { vertex, on_a, on_b, frame: [f.n, f.u, f.v] }
    };
    // The normal from a into b along `from → to`, or the pair's when they (nearly) coincide.
    let along = |from: Vector3, to: Vector3, flip: bool| {
        let d = to - from;
        match d.norm() > TOUCHING {
            true if flip => -d.normalize(),
            true => d.normalize(),
            false => pair,
        }
    };
    let mut out: Vec<PartPoint> = Vec::new();
    // Coincident points (a corner on a corner) would make the step's problem degenerate.
    let mut push = |p: PartPoint| {
        if !out.iter().any(|q| (q.on_b - p.on_b).norm() <= 1e-6) {
            out.push(p);
        }
    };
    for (k, w) in b.points.iter().map(|w| exact.to_a(*w)).enumerate() {
        let (p, inside) = project(a, w);
        if (w - p).norm() <= reach as f64 || inside {
            // b's vertex outside a: a → b is p → w; inside, the way out is w → p.
            push(point(TouchVertex::OfB(k), p, w, along(p, w, inside)));
        }
    }
    for (k, &v) in a.points.iter().enumerate() {
        let (p, inside) = project(b, exact.to_b(v));
        let p = exact.to_a(p);
        if (p - v).norm() <= reach as f64 || inside {
            // a's vertex outside b: a → b is v → p; inside, b leaves it along p → v.
            push(point(TouchVertex::OfA(k), v, p, along(v, p, inside)));
        }
    }
    if out.is_empty() {
        out.push(point(TouchVertex::Closest, f64v(c.point1), f64v(pos12.transform_point(c.point2)), pair));
    }
    out
}

/// Part b's pose in part a's frame in f64 (shape units): b's points map to a's by rot, then t.
struct RelativePose {
    rot: UnitQuaternion<f64>,
    t: Vector3,
}

impl RelativePose {
    fn to_a(&self, p: Vector3) -> Vector3 {
        self.rot * p + self.t
    }

    fn to_b(&self, p: Vector3) -> Vector3 {
        self.rot.inverse() * (p - self.t)
    }
}

/// The nearest boundary point of convex part `part` to `p` (both in its frame, shape units) and
/// whether `p` is inside, by the part's face planes in f64: exact inside the part (the nearest
/// face plane's foot) and outside over a face (the foot lies on the part). Outside near an edge
/// or a corner, parry's projection (GJK in f32, whose tolerance grows with the part's size: a
/// point 1e-3 of a block outside a slab 50 blocks wide it can call inside).
fn project(part: &Part, p: Vector3) -> (Vector3, bool) {
    let f64v = |v: Vector| Vector3::new(v.x as f64, v.y as f64, v.z as f64);
    let parry = |p: Vector3| {
        let proj = part.shape.project_local_point(v32(p), false);
        (f64v(proj.point), proj.is_inside)
    };
    let planes = &part.planes;
    let Some(&(n, d)) = planes.iter().max_by(|x, y| (x.0.dot(&p) - x.1).total_cmp(&(y.0.dot(&p) - y.1))) else {
        return parry(p);
    };
    let depth = n.dot(&p) - d;
    let foot = p - n * depth;
    if depth <= 0.0 {
        return (foot, true);
    }
    let on_part = planes.iter().all(|(m, e)| m.dot(&foot) - e <= ON_PLANE);
    if on_part { (foot, false) } else { (parry(p).0, false) }
}

/// Margin (shape units) of [`apart`] over parry's reach: the shapes are f32, the test's
/// points their f64 copies.
const APART: f64 = 1e-3;

/// How far outside a face plane (shape units) a face's foot point may lie and still be on the
/// part (the planes' f32 round-off).
const ON_PLANE: f64 = 1e-6;

#[cfg(test)]
mod tests {
    //! Invariant: a pair of blocks [`apart`] passes over is one in which [`part_touches`] (parry's
    //! query, then every vertex) finds no point within reach, so the test changes no step.
    use super::*;
    use proptest::prelude::*;

    /// A box of half-sizes `h` about its centroid, as a convex part.
    fn cuboid(h: [f64; 3]) -> Part {
        let corner = |k: usize| v32(Vector3::from_fn(|i, _| if k >> i & 1 == 1 { h[i] } else { -h[i] }));
        let corners: Vec<Vector> = (0..8).map(corner).collect();
        Part::new(SharedShape::convex_hull(&corners).expect("a box's hull"))
    }

    fn placed(x: [f64; 3], turn: [f64; 3]) -> Placed {
        Placed { x: Point3::from(x), q: UnitQuaternion::from_scaled_axis(Vector3::from(turn)), speed: 0.0 }
    }

    /// The points [`part_touches`] finds between two one-part blocks within `reach` (unit 1 m).
    fn touches(a: &Part, pa: &Placed, b: &Part, pb: &Placed, reach: f64) -> usize {
        let (pos12, exact) = relative_pose(pa, pb, 1.0);
        part_touches(a, b, (&pos12, &exact), reach as f32).len()
    }

    #[test]
    fn cubes_side_by_side_are_apart_beyond_the_reach_only() {
        let cube = cuboid([0.5; 3]);
        let at = |x: f64| placed([x, 0.0, 0.0], [0.0; 3]);
        // Gaps of 0.2 and 0.05 against a reach of 0.1 (the margin is 1e-3).
        assert!(apart((std::slice::from_ref(&cube), &at(0.0)), (std::slice::from_ref(&cube), &at(1.2)), (0.1, 1.0)));
        assert!(!apart((std::slice::from_ref(&cube), &at(0.0)), (std::slice::from_ref(&cube), &at(1.05)), (0.1, 1.0)));
        assert!(touches(&cube, &at(0.0), &cube, &at(1.05), 0.1) > 0);
        // Turned 45° about z, the second cube's edge reaches 0.707 towards the first.
        let turned = placed([1.3, 0.0, 0.0], [0.0, 0.0, std::f64::consts::FRAC_PI_4]);
        assert!(!apart((std::slice::from_ref(&cube), &at(0.0)), (std::slice::from_ref(&cube), &turned), (0.1, 1.0)));
    }

    proptest! {
        /// Invariant: the candidate pairs are every pair i < j with a moving block, ascending.
        #[test]
        fn candidate_pairs_are_every_pair_with_a_mover(moving in prop::collection::vec(any::<bool>(), 0..40)) {
            let n = moving.len();
            let every: Vec<[usize; 2]> =
                (0..n).flat_map(|i| (i + 1..n).map(move |j| [i, j])).filter(|[i, j]| moving[*i] || moving[*j]).collect();
            prop_assert_eq!(pairs_with(&moving), every);
        }

        #[test]
        fn a_pair_apart_has_no_touch(
            ha in prop::array::uniform3(0.05f64..1.0),
            hb in prop::array::uniform3(0.05f64..2.0),
            x in prop::array::uniform3(-3.0f64..3.0),
            ta in prop::array::uniform3(-3.0f64..3.0),
            tb in prop::array::uniform3(-3.0f64..3.0),
            reach in 0.0f64..0.3,
        ) {
            let (a, b) = (cuboid(ha), cuboid(hb));
            let (pa, pb) = (placed([0.0; 3], ta), placed(x, tb));
            if apart((std::slice::from_ref(&a), &pa), (std::slice::from_ref(&b), &pb), (reach, 1.0)) {
                prop_assert_eq!(touches(&a, &pa, &b, &pb, reach), 0);
            }
        }
    }
}
