//! One collapse mechanism, not the blend of all of them (`statics::vertex`).
//!
//! Invariants: where several mechanisms collapse at λ* (a degenerate design), the mechanism
//! reported is one vertex of the optimal face — every joint either closed or sliding, every
//! block either still or moving with the others as one, never a fraction of each — with λ*
//! unchanged and the work balance held (checked in `assess`), and the report says other
//! mechanisms collapse at the same λ*; where the optimal face is a point, it says the
//! mechanism is the only one, and the closed forms' hinges are where they were.

use crate::common::*;
use crate::load_factor::{assess, lambda, on_base};
use voussoir::model::{Block, Load, Scene};
use voussoir::stability::{JointState, Robustness};
use voussoir::statics::{FrictionModel, Mechanism, Uniqueness};

fn mechanism(r: &Robustness) -> &Mechanism {
    r.mechanism.as_ref().expect("a mechanism")
}

/// Pushed along +x by 1 g (live).
fn pushed(blocks: Vec<Block>, reach: f64, mu: f64) -> Scene {
    let mut s = on_base(blocks, reach, mu);
    s.loads.push(Load::horizontal(0.0, 1.0));
    s
}

/// Each joint's state by its two names.
fn state(m: &Mechanism, a: &str, b: &str) -> JointState {
    m.interfaces.iter().find(|i| (i.a == a && i.b == b) || (i.a == b && i.b == a)).expect("the joint").state
}

/// The x-translation of every moving block, by name.
fn slips(m: &Mechanism) -> Vec<(String, f64)> {
    m.blocks.iter().map(|b| (b.block.clone(), b.translation[0])).collect()
}

/// Two squat blocks (1 × 1 × 0.5, μ 0.3 < the tipping factors 1 and 2) slide at λ* = μ at
/// either joint — the top one alone, or both together on the base — and at every blend of
/// the two: a face of dimension 1 with two vertices. The answer is one of them.
#[test]
fn a_stack_that_slides_at_either_joint_reports_one() {
    let blocks = vec![cuboid("low", [0.0; 3], [1.0, 1.0, 0.5]), cuboid("top", [0.0, 0.0, 0.5], [1.0, 1.0, 1.0])];
    let (_, r) = assess(&pushed(blocks, 2.0, 0.3), FrictionModel::Pyramid8);
    assert_close(lambda(&r), 0.3, 1e-6, "sliding at μ");
    let m = mechanism(&r);
    assert_eq!(m.uniqueness, Uniqueness::OneOfMany { dimension: 1, vertices: 2 });
    let (low, top) = (state(m, "base", "low"), state(m, "low", "top"));
    let moving = slips(m);
    match moving.as_slice() {
        [(name, _)] => {
            assert_eq!(name, "top");
            assert_eq!((low, top), (JointState::Closed, JointState::Sliding));
        }
        [(_, a), (_, b)] => {
            assert_close(*a, *b, 1e-6 * b.abs(), "the two move as one");
            assert_eq!((low, top), (JointState::Sliding, JointState::Closed));
        }
        other => panic!("a blend: {other:?}"),
    }
}

/// The degenerate design: two identical columns (0.4 × 0.4 × 1) on one base slab
/// carrying a loose lintel (1.6 × 0.4 × 0.3), μ 0.2 (sliding before any tipping). At λ* = μ
/// the lintel may slide alone, or with either column, or everything on the base: the slips
/// (a₀, a₁) of the columns and s of the lintel span 0 ≤ aᵢ ≤ s — a face of dimension 2 with
/// four vertices. The answer is one of them: each moving block slides by the lintel's s,
/// each joint closed or sliding.
#[test]
fn two_columns_under_a_lintel_report_one_mechanism_of_several() {
    let blocks = vec![
        cuboid("c0", [0.0; 3], [0.4, 0.4, 1.0]),
        cuboid("c1", [1.2, 0.0, 0.0], [1.6, 0.4, 1.0]),
        cuboid("lintel", [0.0, 0.0, 1.0], [1.6, 0.4, 1.3]),
    ];
    let (_, r) = assess(&pushed(blocks, 2.6, 0.2), FrictionModel::Pyramid8);
    assert_close(lambda(&r), 0.2, 1e-6, "sliding at μ");
    let m = mechanism(&r);
    let Uniqueness::OneOfMany { dimension, vertices } = m.uniqueness else { panic!("{:?}", m.uniqueness) };
    assert_eq!(dimension, 2);
    assert!((2..=4).contains(&vertices), "{vertices} vertices of the square's 4");
    let moving = slips(m);
    let s = moving.iter().find(|b| b.0 == "lintel").expect("the lintel moves").1;
    for (name, slip) in &moving {
        assert_close(*slip, s, 1e-6 * s.abs(), &format!("{name} slides by the lintel's slip"));
    }
    for i in &m.interfaces {
        assert!(matches!(i.state, JointState::Closed | JointState::Sliding), "{} → {}: {:?}", i.a, i.b, i.state);
    }
}

/// The cone has no vertices: the same stack's mechanism is the interior point's, and says so
/// by saying nothing.
#[test]
fn the_cone_model_is_not_examined() {
    let blocks = vec![cuboid("low", [0.0; 3], [1.0, 1.0, 0.5]), cuboid("top", [0.0, 0.0, 0.5], [1.0, 1.0, 1.0])];
    let (_, r) = assess(&pushed(blocks, 2.0, 0.3), FrictionModel::Cone);
    assert_eq!(mechanism(&r).uniqueness, Uniqueness::NotExamined);
}

/// Unique mechanisms stay as they were: a block tipping (b/h 0.5), a column of 3 turning about
/// its base, and the 16-voussoir arch of t/R 0.15 under a horizontal 1 g: its optimal face is
/// a point and it turns about four hinges (the four-hinge mechanism), no joint sliding.
#[test]
fn unique_mechanisms_are_said_to_be_unique() {
    let (_, r) = assess(&pushed(vec![cuboid("block", [0.0; 3], [0.5, 0.5, 1.0])], 1.5, 0.8), FrictionModel::Pyramid8);
    assert_eq!(mechanism(&r).uniqueness, Uniqueness::Unique);
    let column = (0..3).map(|k| cuboid(&format!("b{k}"), [0.0, 0.0, k as f64], [0.5, 0.5, k as f64 + 1.0])).collect();
    let (_, r) = assess(&pushed(column, 1.5, 0.8), FrictionModel::Pyramid8);
    assert_eq!(mechanism(&r).uniqueness, Uniqueness::Unique);
    for (spec, mu, hinges, sliding) in
        [("builtin:arch?n=16&t=0.15", 0.8, 4, 0), ("builtin:arch?n=21&t=0.30", 0.7, 3, 1)]
    {
        let mut s = voussoir::model::builtin::builtin(spec.trim_start_matches("builtin:")).unwrap();
        s.material.friction = mu;
        s.loads.push(Load::horizontal(0.0, 1.0));
        let (_, r) = assess(&s, FrictionModel::Pyramid8);
        let m = mechanism(&r);
        assert_eq!(m.uniqueness, Uniqueness::Unique, "{spec}");
        let count = |st| m.interfaces.iter().filter(|i| i.state == st).count();
        assert_eq!((count(JointState::Hinging), count(JointState::Sliding)), (hinges, sliding), "{spec}");
        assert_eq!(count(JointState::Opening), 0, "{spec}");
    }
}

/// The four-hinge mechanisms of a semicircular arch of `n` voussoirs (centre-line radius 1,
/// thickness `t`) under a horizontal live g along +x, enumerated by virtual work in the
/// arch's plane — independent of the LP: every choice of four joints j₁ < j₂ < j₃ < j₄ and of
/// the side (intrados, extrados) each turns about; the outer segments turn about H₁ and H₄,
/// the middle one about the intersection of H₁H₂ and H₃H₄; kept when every hinge opens on
/// its other side. Returns the smallest λ and its joints (joint k between block k − 1 and k,
/// 0 and n the springers').
fn four_hinge_minimum(asm: &voussoir::model::Assembly, n: usize, t: f64) -> (f64, [usize; 4]) {
    type P = [f64; 2];
    let (ri, ro) = (1.0 - t / 2.0, 1.0 + t / 2.0);
    let angle = |k: usize| std::f64::consts::PI * k as f64 / n as f64;
    let point = |k: usize, r: f64| [r * angle(k).cos(), r * angle(k).sin()];
    let sub = |a: P, b: P| [a[0] - b[0], a[1] - b[1]];
    let dot = |a: P, b: P| a[0] * b[0] + a[1] * b[1];
    // The velocity of p turning at rate θ about c (about +y): θ ŷ × (p − c) in (x, z).
    let vel = |p: P, c: P, th: f64| [th * (p[1] - c[1]), -th * (p[0] - c[0])];
    let blocks: Vec<(P, f64)> = (0..n)
        .map(|i| {
            let b = asm.blocks.iter().find(|b| b.name == format!("v{i}")).expect("voussoir");
            ([b.mass.centroid.x, b.mass.centroid.z], b.mass() * asm.gravity.norm())
        })
        .collect();
    let mut best = (f64::INFINITY, [0; 4]);
    let sides = [ri, ro];
    for j1 in 0..=n {
        for j2 in j1 + 1..=n {
            for j3 in j2 + 1..=n {
                for j4 in j3 + 1..=n {
                    for mask in 0..16 {
                        let joints = [j1, j2, j3, j4];
                        let h: Vec<P> = (0..4).map(|q| point(joints[q], sides[(mask >> q) & 1])).collect();
                        // C₂: H₁ + s (H₂ − H₁) = H₃ + u (H₄ − H₃).
                        let (d1, d2, e) = (sub(h[1], h[0]), sub(h[3], h[2]), sub(h[2], h[0]));
                        let det = d1[0] * -d2[1] + d2[0] * d1[1];
                        if det.abs() < 1e-12 {
                            continue;
                        }
                        let s = (e[0] * -d2[1] + d2[0] * e[1]) / det;
                        let c2 = [h[0][0] + s * d1[0], h[0][1] + s * d1[1]];
                        let tb = dot(sub(h[1], h[0]), sub(h[1], c2)) / dot(sub(h[1], c2), sub(h[1], c2));
                        let tc = tb * dot(sub(h[2], c2), sub(h[2], h[3])) / dot(sub(h[2], h[3]), sub(h[2], h[3]));
                        // Each block's (centre, rate); still blocks turn at 0.
                        let motion = |i: usize| -> (P, f64) {
                            if i < j1 || i >= j4 {
                                ([0.0, 0.0], 0.0)
                            } else if i < j2 {
                                (h[0], 1.0)
                            } else if i < j3 {
                                (c2, tb)
                            } else {
                                (h[3], tc)
                            }
                        };
                        let (mut live, mut dead) = (0.0, 0.0);
                        for (i, (c, w)) in blocks.iter().enumerate() {
                            let (centre, th) = motion(i);
                            let v = vel(*c, centre, th);
                            live += w * v[0];
                            dead -= w * v[1];
                        }
                        let sign = live.signum();
                        // Every hinge opens on its other side: b's motion against a's along the
                        // joint normal (increasing angle), at the other corner.
                        let opens = (0..4).all(|q| {
                            let k = joints[q];
                            let other = point(k, sides[1 - ((mask >> q) & 1)]);
                            let before = if k == 0 { ([0.0, 0.0], 0.0) } else { motion(k - 1) };
                            let after = if k == n { ([0.0, 0.0], 0.0) } else { motion(k) };
                            let rel = sub(vel(other, after.0, after.1), vel(other, before.0, before.1));
                            sign * dot(rel, [-angle(k).sin(), angle(k).cos()]) > 1e-12
                        });
                        let lambda = -dead / live;
                        if opens && live.abs() > 1e-12 && lambda < best.0 {
                            best = (lambda, joints);
                        }
                    }
                }
            }
        }
    }
    best
}

/// Invariant: the 16-voussoir arch of t/R 0.15 under a horizontal g collapses by the four-hinge
/// mechanism the virtual-work enumeration finds: the same λ* (1e-4 relative: the LP works on the
/// same corners) and the same four hinging joints, all others closed.
#[test]
fn the_arch_hinges_where_the_four_hinge_enumeration_puts_them() {
    let (n, t) = (16, 0.15);
    let mut s = voussoir::model::builtin::builtin(&format!("arch?n={n}&t={t}")).unwrap();
    s.material.friction = 0.8;
    s.loads.push(Load::horizontal(0.0, 1.0));
    let (a, r) = assess(&s, FrictionModel::Pyramid8);
    let (expected, joints) = four_hinge_minimum(&a.assembly, n, t);
    assert_close(lambda(&r), expected, 1e-4 * expected, "λ* against the enumeration");
    let name = |i: isize| {
        if i < 0 {
            "springer_right".to_string()
        } else if i as usize == n {
            "springer_left".into()
        } else {
            format!("v{i}")
        }
    };
    let pair = |a: String, b: String| if a < b { (a, b) } else { (b, a) };
    let mut want: Vec<(String, String)> =
        joints.iter().map(|&k| pair(name(k as isize - 1), name(k as isize))).collect();
    want.sort();
    let m = mechanism(&r);
    let mut got: Vec<(String, String)> = m
        .interfaces
        .iter()
        .filter(|i| i.state == JointState::Hinging)
        .map(|i| pair(i.a.clone(), i.b.clone()))
        .collect();
    got.sort();
    assert_eq!(got, want, "hinges (λ* {expected:.5})");
    assert!(m.interfaces.iter().all(|i| matches!(i.state, JointState::Hinging | JointState::Closed)));
}
