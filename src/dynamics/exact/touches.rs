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
//!
//! Shapes are given to parry (f32) relative to each block's centroid in units of the median
//! block size, and the pair's relative pose is formed in f64 first: a contact point is exact to
//! ~1e-7 of a block whatever the model's size or distance from the origin.

use super::World;
use super::contacts::{Contact, Origin, Side};
use crate::geometry::polygon::Frame;
use crate::geometry::{Point3, Vector3};
use crate::interfaces::penetration::{convex_shapes, hull_shape, v32};
use crate::model::AssemblyBlock;
use nalgebra::UnitQuaternion;
use rapier3d::math::{Pose, Rotation, Vector};
use rapier3d::parry::query::{DefaultQueryDispatcher, QueryDispatcher};
use rapier3d::parry::shape::SharedShape;
use std::collections::BTreeSet;
use std::sync::{Arc, OnceLock};

/// Every block's convex parts, built when a pair first needs them.
#[derive(Clone)]
pub(super) struct Solids {
    blocks: Arc<[AssemblyBlock]>,
    /// Per block: its start centroid (m) and the farthest vertex from it (m).
    centres: Vec<(Point3, f64)>,
    parts: Vec<OnceLock<Arc<[SharedShape]>>>,
    /// The shapes' length unit, m (the median block size).
    unit: f64,
}

impl Solids {
    pub fn new(blocks: &[AssemblyBlock], unit: f64) -> Self {
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
            let proj = s.project_local_point(local, false);
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
    fn parts(&self, i: usize) -> Arc<[SharedShape]> {
        let (b, unit) = (&self.blocks[i], self.unit);
        self.parts[i]
            .get_or_init(|| {
                let tol = 1e-3 * b.aabb.diagonal();
                let shapes = convex_shapes(b, tol, unit).or_else(|| hull_shape(b, unit).map(|h| vec![h]));
                shapes.unwrap_or_default().into()
            })
            .clone()
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

    /// Drops the last step's touches and finds this step's (module docs).
    pub(super) fn find_touches(&mut self) {
        self.contacts.truncate(self.persistent);
        let envelope = self.settings.envelope;
        let candidates = self.touch_candidates(envelope);
        if candidates.is_empty() {
            return;
        }
        let held = self.held_pairs(&candidates);
        let mut found = Vec::new();
        for &[i, j] in candidates.difference(&held) {
            let (pi, pj) = (self.placed(i), self.placed(j));
            let scale = self.solids.size(i).min(self.solids.size(j));
            let prediction = envelope * scale + 2.0 * self.ctx.h * (pi.speed + pj.speed);
            let (ri, rj) = (self.solids.centres[i].1, self.solids.centres[j].1);
            if (pj.x - pi.x).norm() > ri + rj + prediction {
                continue;
            }
            self.pair_touches(i, j, &pi, &pj, prediction, &mut found);
        }
        self.contacts.extend(found);
    }

    /// The pairs of blocks (ascending) one of which is awake and has moved by more than
    /// `envelope` of its own size since the start, the other any block.
    fn touch_candidates(&self, envelope: f64) -> BTreeSet<[usize; 2]> {
        // A block held by no interface at the start (set on an edge, or above its support) may
        // meet any block from the first step.
        let held: BTreeSet<usize> = self.contacts[..self.persistent].iter().filter_map(|c| c.pair).flatten().collect();
        let moved = |b: &super::Body| {
            !held.contains(&b.block)
                || (b.x - b.start).norm() + b.q.angle() * b.radius > envelope * self.solids.size(b.block)
        };
        let mut pairs = BTreeSet::new();
        let movers = self.bodies.iter().filter(|b| !b.asleep).chain(&self.movers);
        for b in movers.filter(|b| moved(b)) {
            for j in (0..self.solids.centres.len()).filter(|&j| j != b.block) {
                pairs.insert([b.block.min(j), b.block.max(j)]);
            }
        }
        pairs
    }

    /// Those of `candidates` an interface contact holds this step: one not released and within
    /// the envelope (or closing it), as the step's persistent contacts are chosen.
    fn held_pairs(&self, candidates: &BTreeSet<[usize; 2]>) -> BTreeSet<[usize; 2]> {
        self.contacts
            .iter()
            .enumerate()
            .filter(|(_, c)| matches!(c.origin, Origin::Interface { .. }))
            .filter(|(_, c)| c.pair.is_some_and(|p| candidates.contains(&p)))
            .filter_map(|(i, c)| self.near(i, c).and(c.pair))
            .collect()
    }

    pub(super) fn placed(&self, i: usize) -> Placed {
        match self.poses().of(self.sides[i]) {
            Some(b) => Placed { x: b.x, q: b.q, speed: b.v.norm() + b.w.norm() * b.radius },
            None => Placed { x: self.solids.centres[i].0, q: UnitQuaternion::identity(), speed: 0.0 },
        }
    }

    /// The contact points of blocks `i` and `j` within `prediction` (m), from every pair of
    /// their convex parts, as contacts from i (side a) into j (side b).
    fn pair_touches(&self, i: usize, j: usize, pi: &Placed, pj: &Placed, prediction: f64, out: &mut Vec<Contact>) {
        let unit = self.solids.unit;
        let (si, sj) = (self.solids.parts(i), self.solids.parts(j));
        let inv = pi.q.inverse();
        let rot = inv * pj.q;
        let t = v32(inv * (pj.x - pi.x) / unit);
        let rot = Rotation::from_xyzw(rot.i as f32, rot.j as f32, rot.k as f32, rot.w as f32).normalize();
        let pos12 = Pose::from_parts(t, rot);
        let (a, b) = (self.sides[i], self.sides[j]);
        // A fixed side's material point is the world point; a moving one's its offset.
        let anchor =
            |s: Side, k: usize| if s == Side::Fixed { self.solids.centres[k].0.coords } else { Vector3::zeros() };
        let (oa, ob) = (anchor(a, i), anchor(b, j));
        let reach = (prediction / unit) as f32;
        for (pa, part_a) in si.iter().enumerate() {
            for (pb, part_b) in sj.iter().enumerate() {
                for (k, point) in part_touches(part_a, part_b, &pos12, reach).into_iter().enumerate() {
                    // b's material point back in b's own frame, in f64.
                    let on_b = pj.q.inverse() * (pi.x + pi.q * (point.on_b * unit) - pj.x);
                    out.push(Contact {
                        a,
                        b,
                        origin: Origin::Touch { parts: [pa, pb], point: k },
                        pair: Some([i, j]),
                        ra: oa + point.on_a * unit,
                        rb: ob + on_b,
                        frame: point.frame,
                        reach: f64::INFINITY,
                        scale: self.solids.size(i).min(self.solids.size(j)),
                        last_normal: 0.0,
                    });
                }
            }
        }
    }
}

/// A contact point of two convex parts, in a's frame (a's shape units).
struct PartPoint {
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
fn part_touches(a: &SharedShape, b: &SharedShape, pos12: &Pose, reach: f32) -> Vec<PartPoint> {
    let Ok(Some(c)) = DefaultQueryDispatcher.contact(pos12, a.as_ref(), b.as_ref(), reach) else {
        return Vec::new();
    };
    let f64v = |v: Vector| Vector3::new(v.x as f64, v.y as f64, v.z as f64);
    let pair = f64v(c.normal1);
    if pair.norm().is_nan() || pair.norm() <= 0.5 {
        return Vec::new();
    }
    let pair = pair.normalize();
    let point = |on_a: Vector3, on_b: Vector3, n: Vector3| {
        let f = Frame::from_normal(Point3::origin(), n);
        PartPoint { on_a, on_b, frame: [f.n, f.u, f.v] }
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
    let vertices = |s: &SharedShape| s.as_convex_polyhedron().map(|p| p.points().to_vec()).unwrap_or_default();
    let mut out: Vec<PartPoint> = Vec::new();
    // Coincident points (a corner on a corner) would make the step's problem degenerate.
    let mut push = |p: PartPoint| {
        if !out.iter().any(|q| (q.on_b - p.on_b).norm() <= 1e-6) {
            out.push(p);
        }
    };
    for w in vertices(b).into_iter().map(|w| pos12.transform_point(w)) {
        let proj = a.project_local_point(w, false);
        let (w, p) = (f64v(w), f64v(proj.point));
        if (w - p).norm() <= reach as f64 || proj.is_inside {
            // b's vertex outside a: a → b is p → w; inside, the way out is w → p.
            push(point(p, w, along(p, w, proj.is_inside)));
        }
    }
    let inv = pos12.inverse();
    for v in vertices(a) {
        let proj = b.project_local_point(inv.transform_point(v), false);
        let (v, p) = (f64v(v), f64v(pos12.transform_point(proj.point)));
        if (p - v).norm() <= reach as f64 || proj.is_inside {
            // a's vertex outside b: a → b is v → p; inside, b leaves it along p → v.
            push(point(v, p, along(v, p, proj.is_inside)));
        }
    }
    if out.is_empty() {
        out.push(point(f64v(c.point1), f64v(pos12.transform_point(c.point2)), pair));
    }
    out
}
