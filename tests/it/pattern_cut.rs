//! Invariant: a pattern cut (segments extruded to an apex) cuts only the pieces each segment's
//! cone meets, with planar interfaces through the apex; volumes are conserved; malformed
//! patterns are named errors.

use crate::common::*;
use voussoir::geometry::MassProperties;
use voussoir::history::{CutCache, CutError, replay};
use voussoir::model::{Block, Cut, Scene};

fn slab() -> Vec<Block> {
    vec![cuboid("slab", [-1.0, -1.0, 0.0], [1.0, 1.0, 0.5])]
}

const APEX: [f64; 3] = [0.0, 0.0, -3.0];

/// A line across the slab, then two half lines on either side of it (a brick bond).
fn bond() -> Cut {
    Cut::pattern(
        APEX,
        vec![
            [[0.0, -1.0, 0.5], [0.0, 1.0, 0.5]],
            [[-1.0, 0.3, 0.5], [0.0, 0.3, 0.5]],
            [[0.0, -0.4, 0.5], [1.0, -0.4, 0.5]],
        ],
    )
}

#[test]
fn bond_pattern_gives_four_pieces_with_conserved_volume() {
    let (blocks, stats) = replay(&slab(), &[bond()], 1e-9, &mut CutCache::new()).unwrap();
    assert_eq!(blocks.len(), 4, "{:?}", blocks.iter().map(|b| &b.name).collect::<Vec<_>>());
    // Each half line's plane crosses every piece (1 + 2 + 3 splits) but its cone meets only
    // the piece on its side, so only that one is cut: 4 pieces, not 6.
    assert_eq!(stats.splits, 6);
    let total: f64 = blocks.iter().map(|b| MassProperties::of_mesh(&b.mesh).volume).sum();
    assert_close(total, 2.0, 1e-12, "volume");
    // The segment's plane through the apex: the half lines' pieces meet at y where the plane
    // through (·, 0.3, 0.5) and the apex crosses the slab bottom: y = 0.3 · 3 / 3.5.
    let piece = blocks.iter().find(|b| b.name.ends_with(".0/1-") || b.name.ends_with(".0/1+")).unwrap();
    let ys: Vec<f64> = piece.mesh.vertices.iter().filter(|p| p.z.abs() < 1e-12).map(|p| p.y).collect();
    assert!(ys.iter().any(|y| (y.abs() - 0.3 * 3.0 / 3.5).abs() < 1e-12), "{ys:?}");
}

#[test]
fn interfaces_of_a_pattern_converge_on_the_apex() {
    let mut scene = Scene::new("slab", slab());
    scene.ground = true;
    scene.cuts = vec![bond()];
    let a = run(&scene, &Default::default());
    let internal: Vec<_> = a.interfaces.iter().filter(|i| i.a.block().is_some() && i.b.block().is_some()).collect();
    // The two half lines, and the line (x = 0) split into three overlaps by the staggered joints.
    assert_eq!(internal.len(), 5);
    for i in internal {
        let n = i.frame.n;
        let d = n.dot(&(nalgebra::Point3::from(APEX) - i.centroid()));
        assert!(d.abs() < 1e-9, "interface misses the apex by {d}");
    }
    assert!(a.statics.stands, "a flat slab on the ground stands whatever its joints");
}

#[test]
fn a_target_limits_the_pattern_to_that_piece_and_its_pieces() {
    let cuts = [Cut::plane([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), bond().on("slab.0+")];
    let (blocks, _) = replay(&slab(), &cuts, 1e-9, &mut CutCache::new()).unwrap();
    let names: Vec<&str> = blocks.iter().map(|b| b.name.as_str()).collect();
    // The line x = 0 coincides with cut 0 (nothing to cut); the half line on the right cuts
    // slab.0+; the one on the left would cut slab.0-, which is out of scope.
    assert_eq!(names, ["slab.0-", "slab.0+.1/2-", "slab.0+.1/2+"]);
}

#[test]
fn malformed_patterns_are_named_errors() {
    let degenerate = Cut::pattern(APEX, vec![[[0.0, 0.0, 0.5], [0.0, 0.0, 1.0]]]);
    let err = replay(&slab(), &[degenerate], 1e-9, &mut CutCache::new()).unwrap_err();
    assert!(matches!(err, CutError::BadSegment { index: 0, segment: 0, .. }), "{err}");
    let empty = Cut::pattern(APEX, vec![]);
    assert!(matches!(replay(&slab(), &[empty], 1e-9, &mut CutCache::new()), Err(CutError::BadSegment { .. })));
    let nan = Cut::pattern([f64::NAN, 0.0, 0.0], vec![[[0.0, -1.0, 0.5], [0.0, 1.0, 0.5]]]);
    assert!(matches!(replay(&slab(), &[nan], 1e-9, &mut CutCache::new()), Err(CutError::BadPoint { .. })));
}

#[test]
fn pattern_and_removed_round_trip_through_the_scene_file() {
    let mut scene = Scene::new("slab", slab());
    scene.cuts = vec![bond().on("slab")];
    scene.removed = vec!["slab.0/0-".into()];
    let text = voussoir::io::scene_json::scene_to_string(&scene);
    let back = voussoir::io::scene_from_bytes(std::path::Path::new("x.json"), text.as_bytes()).unwrap();
    assert_eq!(back, scene);
    // A removed name that is no piece is an error naming it.
    scene.removed = vec!["nothing".into()];
    let err = voussoir::history::resolve(&scene, &Default::default(), &mut CutCache::new()).unwrap_err();
    assert!(err.to_string().contains("'nothing'"), "{err}");
    // A cut mixing the two forms is rejected with the rule.
    let bad = r#"{"blocks": [], "cuts": [{"point": [0,0,0], "normal": [0,0,1], "apex": [0,0,1]}]}"#;
    let err = voussoir::io::scene_from_bytes(std::path::Path::new("bad.json"), bad.as_bytes()).unwrap_err();
    assert!(err.to_string().contains("either"), "{err}");
}
