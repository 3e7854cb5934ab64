//! Contact points and their geometry at the current poses.
//!
//! - Interface contacts: every vertex of every detected interface polygon (the statics' force
//!   points) is a pair of material points, one on each block, coincident at the start. Its
//!   normal turns with block a (the interface's `a`, whose face normal points into b); its gap
//!   is the distance of b's point from a's face plane (> 0 open), so a hinge's far vertices
//!   open and its near ones stay closed. Once the two points have slipped apart by more than the
//!   interface's diameter the faces no longer overlap, and once the faces have turned more than
//!   60° apart or overlap by more than a fifth of the median block size they are not these
//!   faces' contact any more: the contact is released.
//! - Ground contacts: every vertex of a free block against the plane the blocks land on (the
//!   scene's ground z = 0, or the floor under its supports: [`crate::dynamics::scene::floor_level`]),
//!   so a block falling onto it lands.

use super::bodies::Body;
use crate::geometry::{Point3, Vector3};
use crate::interfaces::{Body as Side0, Interface};
use crate::model::Assembly;

/// One side of a contact: a fixed body (support or ground), a free one (index into the
/// engine's bodies), or a support on a prescribed path (index into its movers).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Side {
    Fixed,
    Free(usize),
    Moved(usize),
}

/// The bodies a contact's sides index: the free ones and the moved supports.
#[derive(Clone, Copy)]
pub(super) struct Poses<'a> {
    pub bodies: &'a [Body],
    pub movers: &'a [Body],
}

impl<'a> Poses<'a> {
    /// The body of a side that moves (free or moved), None for a fixed one.
    pub fn of(&self, side: Side) -> Option<&'a Body> {
        match side {
            Side::Fixed => None,
            Side::Free(k) => Some(&self.bodies[k]),
            Side::Moved(m) => Some(&self.movers[m]),
        }
    }
}

/// Where a contact comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Origin {
    /// Vertex `vertex` of interface `interface`.
    Interface { interface: usize, vertex: usize },
    /// Vertex `vertex` of the free block's mesh, on the ground.
    Ground { vertex: usize },
    /// A point found between convex parts `parts` of the contact's two blocks, closing under
    /// large motion ([`super::touches`]); found anew each step, the touching vertex `point`
    /// naming it from step to step.
    Touch { parts: [usize; 2], point: TouchVertex },
}

/// Which point of a pair of convex parts touches: a vertex of b on a, a vertex of a on b, or
/// the pair's closest points (no vertex within reach).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(super) enum TouchVertex {
    OfB(usize),
    OfA(usize),
    Closest,
}

#[derive(Clone, Debug)]
pub(super) struct Contact {
    pub a: Side,
    pub b: Side,
    pub origin: Origin,
    /// The two blocks (assembly indices, ascending); None on the ground.
    pub pair: Option<[usize; 2]>,
    /// The material points on a and on b: offsets from the body's start centroid (a fixed
    /// side's: the world point).
    pub ra: Vector3,
    pub rb: Vector3,
    /// The frame at the start: n from a into b, then u, v (right-handed).
    pub frame: [Vector3; 3],
    /// Slip (m) beyond which the faces no longer overlap (∞ on the ground).
    pub reach: f64,
    /// The smaller of its blocks' sizes (bounding-box diagonals; on the ground the block's), m:
    /// the length its envelope and overlaps are measured in, whatever the other blocks' sizes.
    pub scale: f64,
    /// The normal force of the last step that solved it, N (warms the friction capacity).
    pub last_normal: f64,
    /// Its force in that step, N on b (world axes): the next step's multipliers' start.
    pub last_force: Vector3,
    /// Its state at the end of the last step that solved it (starts the next step's states).
    pub state: State,
}

/// A contact's state at the end of its last step, in its own (u, v) frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) enum State {
    #[default]
    Open,
    Stick,
    /// Sliding, the friction force pointing at `angle` (rad, from u towards v): against the
    /// slip (on a polygon: a facet's normal, or any angle within a vertex's cone).
    Slide {
        angle: f64,
    },
}

/// A contact's geometry at the current poses.
#[derive(Clone, Copy, Debug)]
pub(super) struct Geometry {
    /// Where the force acts (midway between the two material points), m.
    pub point: Point3,
    /// n (from a into b), u, v now.
    pub frame: [Vector3; 3],
    /// Signed distance of b's point from a's face plane, m (< 0 overlapping).
    pub gap: f64,
    /// Tangential distance between the two material points, m.
    pub slip: f64,
    /// The cosine between a's normal and b's face normal reversed (1 while the faces are
    /// parallel; on the ground and for a touch, 1).
    pub facing: f64,
}

/// All contacts of a scene, in a fixed order: interfaces (detection's order, vertices in
/// polygon order), then ground vertices by block and vertex.
pub(super) fn build(
    assembly: &Assembly,
    interfaces: &[Interface],
    sides: &[Side],
    poses: Poses,
    floor: Option<f64>,
) -> Vec<Contact> {
    let bodies = poses.bodies;
    let side = |b: Side0| match b {
        Side0::Block(id) => sides[id.0],
        Side0::Ground => Side::Fixed,
    };
    let offset = |s: Side, p: Point3| poses.of(s).map_or(p.coords, |b| p - b.start);
    let mut out = Vec::new();
    for (k, itf) in interfaces.iter().enumerate() {
        // The ground is met vertex by vertex below; fixed–fixed pairs never move.
        if itf.a == Side0::Ground || itf.b == Side0::Ground {
            continue;
        }
        let (a, b) = (side(itf.a), side(itf.b));
        if !matches!(a, Side::Free(_)) && !matches!(b, Side::Free(_)) {
            continue;
        }
        let reach = diameter(&itf.polygon);
        let pair = match (itf.a, itf.b) {
            (Side0::Block(i), Side0::Block(j)) => Some([i.0.min(j.0), i.0.max(j.0)]),
            _ => None,
        };
        let scale = pair.map_or(f64::INFINITY, |[i, j]| block_size(assembly, i).min(block_size(assembly, j)));
        for (vertex, &p) in itf.polygon.iter().enumerate() {
            out.push(Contact {
                a,
                b,
                origin: Origin::Interface { interface: k, vertex },
                pair,
                ra: offset(a, p),
                rb: offset(b, p),
                frame: [itf.frame.n, itf.frame.u, itf.frame.v],
                reach,
                scale,
                last_normal: 0.0,
                last_force: Vector3::zeros(),
                state: Default::default(),
            });
        }
    }
    if let Some(level) = floor {
        for (k, body) in bodies.iter().enumerate() {
            for (vertex, p) in assembly.blocks[body.block].mesh.vertices.iter().enumerate() {
                out.push(Contact {
                    a: Side::Fixed,
                    b: Side::Free(k),
                    origin: Origin::Ground { vertex },
                    pair: None,
                    ra: Vector3::new(p.x, p.y, level),
                    rb: p - body.start,
                    frame: [Vector3::z(), Vector3::x(), Vector3::y()],
                    reach: f64::INFINITY,
                    scale: block_size(assembly, body.block),
                    last_normal: 0.0,
                    last_force: Vector3::zeros(),
                    state: Default::default(),
                });
            }
        }
    }
    out
}

/// Block `i`'s size, m: its bounding-box diagonal.
pub(super) fn block_size(assembly: &Assembly, i: usize) -> f64 {
    assembly.blocks[i].aabb.diagonal().max(f64::MIN_POSITIVE)
}

fn diameter(polygon: &[Point3]) -> f64 {
    let mut d = 0.0f64;
    for (i, p) in polygon.iter().enumerate() {
        for q in &polygon[i + 1..] {
            d = d.max((p - q).norm());
        }
    }
    d
}

impl Contact {
    pub fn geometry(&self, poses: Poses) -> Geometry {
        let at = |s: Side, r: &Vector3| poses.of(s).map_or(Point3::from(*r), |b| b.point(r));
        let pb = at(self.b, &self.rb);
        let frame = match poses.of(self.a) {
            Some(a) => self.frame.map(|d| a.q * d),
            None => self.frame,
        };
        // On the ground, a's point is b's vertex projected onto the plane (at ra's height).
        let pa = match self.origin {
            Origin::Ground { .. } => Point3::new(pb.x, pb.y, self.ra.z),
            Origin::Interface { .. } | Origin::Touch { .. } => at(self.a, &self.ra),
        };
        let d = pb - pa;
        let gap = frame[0].dot(&d);
        let slip = (d - frame[0] * gap).norm();
        // A vertex on the ground, or a touch (a vertex near a part): no face pair whose
        // turning to measure.
        let facing = match (self.origin, poses.of(self.b)) {
            (Origin::Touch { .. } | Origin::Ground { .. }, _) => 1.0,
            (_, Some(b)) => frame[0].dot(&(b.q * self.frame[0])),
            (_, None) => frame[0].dot(&self.frame[0]),
        };
        Geometry { point: pa + d * 0.5, frame, gap, slip, facing }
    }

    /// b's material point now, m.
    pub fn point_b(&self, poses: Poses) -> Point3 {
        poses.of(self.b).map_or(Point3::from(self.rb), |b| b.point(&self.rb))
    }

    /// The velocity of b's point relative to a's at `point`, m/s.
    pub fn relative_velocity(&self, poses: Poses, point: &Point3) -> Vector3 {
        let vel = |s: Side| poses.of(s).map_or(Vector3::zeros(), |b| b.velocity_at(point));
        vel(self.b) - vel(self.a)
    }

    /// The part of [`Self::relative_velocity`] the moved supports prescribe (the free blocks'
    /// part is what a step solves for), m/s.
    pub fn prescribed_velocity(&self, poses: Poses, point: &Point3) -> Vector3 {
        let vel = |s: Side| match s {
            Side::Moved(m) => poses.movers[m].velocity_at(point),
            _ => Vector3::zeros(),
        };
        vel(self.b) - vel(self.a)
    }

    /// The moved support this contact has on a side, if any.
    pub fn mover(&self) -> Option<usize> {
        [self.a, self.b].into_iter().find_map(|s| match s {
            Side::Moved(m) => Some(m),
            _ => None,
        })
    }

    pub fn touches(&self, body: usize) -> bool {
        self.a == Side::Free(body) || self.b == Side::Free(body)
    }
}
