//! A collapse mechanism: each moving block's virtual translation and rotation, and what every
//! interface of the moving components does — closed, hinging (opening about a line: some of
//! its vertices keep contact, the others lift off), opening (all lift off) or sliding.
//!
//! Motions are virtual velocities (linear in the block's motion): a point p of block j moves by
//! t_j + ω_j × (p − c_j), c_j its centroid; supports and the ground do not move. The relative
//! motion of an interface vertex is b's minus a's (the normal n points from a into b), so
//! opening is a positive normal component. Where friction acts the flow is associated (the
//! dual of the friction rows): a sliding joint also opens by up to μ × its slip, which is why
//! sliding is decided before opening.

use super::components::Component;
use super::load_factor::Motion;
pub use super::vertex::Uniqueness;
use crate::geometry::{Point3, Vector3};
use crate::interfaces::{Body, Interface};
use crate::model::{Assembly, BlockId};
use serde::Serialize;

/// A relative motion (or a block's) below this fraction of the mechanism's largest one is
/// none: the solver's round-off, not a motion a designer should read.
pub const STILL: f64 = 1e-3;

/// What an interface does in the mechanism.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum JointState {
    /// Both sides move as one (or not at all).
    Closed,
    /// Rotation about an edge or line of the joint: some vertices stay in contact, the others
    /// open.
    Hinging,
    /// Every vertex lifts off.
    Opening,
    /// The sides slip along the joint.
    Sliding,
}

/// A moving block's motion: translation (m) and rotation about its centroid (rad), world axes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BlockMotion {
    /// The block's name.
    pub block: String,
    /// Its virtual translation, m (world axes).
    pub translation: [f64; 3],
    /// Its virtual rotation about its centroid, rad (a rotation vector, world axes).
    pub rotation: [f64; 3],
}

/// One interface in the mechanism: its largest opening (normal relative motion, m) and slip
/// (tangential, m) over its vertices, and its state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InterfaceMotion {
    /// Index in the analysis's interface list.
    pub index: usize,
    /// The name of side a (a block, or `ground`).
    pub a: String,
    /// The name of side b.
    pub b: String,
    /// Closed, hinging, opening or sliding.
    pub state: JointState,
    /// The largest normal relative motion over its vertices, m.
    pub opening: f64,
    /// The largest tangential relative motion over its vertices, m.
    pub sliding: f64,
}

/// A mechanism over an assembly (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Mechanism {
    /// The moving blocks, in block order: those of the moving components whose motion reaches
    /// [`STILL`] × the largest block's.
    pub blocks: Vec<BlockMotion>,
    /// The interfaces of the moving components, in interface order.
    pub interfaces: Vec<InterfaceMotion>,
    /// Whether other mechanisms collapse at the same load factor.
    pub uniqueness: Uniqueness,
    /// The moving blocks' ids, in the order of `blocks`.
    #[serde(skip)]
    pub moving: Vec<BlockId>,
    /// Every block's motion by [`BlockId`] (zero for the others).
    #[serde(skip)]
    pub motion: Vec<Motion>,
}

impl Mechanism {
    /// The mechanism of `parts` (components and their blocks' motions, in component order).
    pub fn new(assembly: &Assembly, interfaces: &[Interface], parts: &[(&Component, &[Motion])]) -> Self {
        let mut motion = vec![[0.0; 6]; assembly.blocks.len()];
        let mut moving: Vec<BlockId> = Vec::new();
        let mut joints: Vec<usize> = Vec::new();
        for (comp, motions) in parts {
            for (&b, m) in comp.blocks.iter().zip(motions.iter()) {
                motion[b.0] = *m;
                moving.push(b);
            }
            joints.extend(&comp.interfaces);
        }
        moving.sort_unstable();
        joints.sort_unstable();
        // A block whose motion stays below STILL × the largest is shown still (its motion kept,
        // so the work balance holds to the last digit).
        let reach: Vec<f64> = moving.iter().map(|&b| block_reach(assembly, b, &motion[b.0])).collect();
        let largest_reach = reach.iter().copied().fold(0.0, f64::max);
        let moving: Vec<BlockId> =
            moving.iter().zip(&reach).filter(|(_, r)| **r > STILL * largest_reach).map(|(&b, _)| b).collect();
        let blocks = moving
            .iter()
            .map(|&b| {
                let m = motion[b.0];
                BlockMotion {
                    block: assembly.block(b).name.clone(),
                    translation: [m[0], m[1], m[2]],
                    rotation: [m[3], m[4], m[5]],
                }
            })
            .collect();
        let mut mech = Self { blocks, interfaces: Vec::new(), uniqueness: Uniqueness::NotExamined, moving, motion };
        let relative: Vec<Vec<(f64, f64)>> =
            joints.iter().map(|&k| mech.vertex_motions(assembly, &interfaces[k])).collect();
        let largest = relative.iter().flatten().map(|m| m.0.abs().max(m.1)).fold(0.0, f64::max);
        mech.interfaces = joints
            .iter()
            .zip(&relative)
            .map(|(&k, v)| {
                let itf = &interfaces[k];
                InterfaceMotion {
                    index: k,
                    a: itf.a.name(assembly).to_string(),
                    b: itf.b.name(assembly).to_string(),
                    state: joint_state(v, STILL * largest),
                    opening: v.iter().map(|m| m.0).fold(f64::NEG_INFINITY, f64::max),
                    sliding: v.iter().map(|m| m.1).fold(0.0, f64::max),
                }
            })
            .collect();
        mech
    }

    /// The mechanism with what is known of its uniqueness.
    pub fn with_uniqueness(mut self, uniqueness: Uniqueness) -> Self {
        self.uniqueness = uniqueness;
        self
    }

    /// The joints that move (every state but closed), the largest relative motion (opening or
    /// slip) first: where a designer looks to see the structure break.
    pub fn moving_joints(&self) -> Vec<&InterfaceMotion> {
        let mut joints: Vec<&InterfaceMotion> =
            self.interfaces.iter().filter(|i| i.state != JointState::Closed).collect();
        let size = |i: &InterfaceMotion| i.opening.max(i.sliding);
        joints.sort_by(|a, b| size(b).total_cmp(&size(a)).then(a.index.cmp(&b.index)));
        joints
    }

    /// How far point `p` of `body` moves (zero for supports and the ground).
    pub fn point_motion(&self, assembly: &Assembly, body: Body, p: &Point3) -> Vector3 {
        match body {
            Body::Block(b) => {
                let m = &self.motion[b.0];
                let r = p - assembly.block(b).mass.centroid;
                Vector3::new(m[0], m[1], m[2]) + Vector3::new(m[3], m[4], m[5]).cross(&r)
            }
            Body::Ground => Vector3::zeros(),
        }
    }

    /// Per vertex of `itf`: (normal, tangential) relative motion of b against a.
    pub fn vertex_motions(&self, assembly: &Assembly, itf: &Interface) -> Vec<(f64, f64)> {
        let n = itf.frame.n;
        itf.polygon
            .iter()
            .map(|p| {
                let d = self.point_motion(assembly, itf.b, p) - self.point_motion(assembly, itf.a, p);
                let dn = d.dot(&n);
                (dn, (d - n * dn).norm())
            })
            .collect()
    }

    /// The largest motion of any vertex of a moving block, m.
    pub fn largest_motion(&self, assembly: &Assembly) -> f64 {
        (0..assembly.blocks.len())
            .filter(|&i| self.motion[i] != [0.0; 6])
            .map(|i| block_reach(assembly, BlockId(i), &self.motion[i]))
            .fold(0.0, f64::max)
    }

    /// Block `b`'s vertices moved by `scale` × the mechanism (linearised: small rotations).
    pub fn displaced(&self, assembly: &Assembly, b: BlockId, scale: f64) -> Vec<Point3> {
        assembly
            .block(b)
            .mesh
            .vertices
            .iter()
            .map(|p| p + self.point_motion(assembly, Body::Block(b), p) * scale)
            .collect()
    }

    /// The work of a load given as wrenches per block (force N, moment N·m about the centroid)
    /// along this mechanism, N·m.
    pub fn work(&self, wrenches: impl Iterator<Item = (BlockId, [f64; 6])>) -> f64 {
        wrenches.map(|(b, w)| w.iter().zip(&self.motion[b.0]).map(|(a, m)| a * m).sum::<f64>()).sum()
    }
}

/// The largest motion of any vertex of block `b` under motion `m`, m.
fn block_reach(assembly: &Assembly, b: BlockId, m: &Motion) -> f64 {
    let block = assembly.block(b);
    let (t, w) = (Vector3::new(m[0], m[1], m[2]), Vector3::new(m[3], m[4], m[5]));
    block.mesh.vertices.iter().map(|p| (t + w.cross(&(p - block.mass.centroid))).norm()).fold(0.0, f64::max)
}

/// The state of a joint from its vertices' (normal, tangential) relative motions, motions
/// below `still` counting as none.
fn joint_state(v: &[(f64, f64)], still: f64) -> JointState {
    if v.iter().any(|m| m.1 > still) {
        JointState::Sliding
    } else if v.iter().all(|m| m.0 <= still) {
        JointState::Closed
    } else if v.iter().all(|m| m.0 > still) {
        JointState::Opening
    } else {
        JointState::Hinging
    }
}
