//! Invariant: replaying a cut history is deterministic, names pieces from the history, skips
//! supports unless they are targeted, and with a content cache recomputes only the pieces
//! downstream of an edited cut.

use crate::common::*;
use voussoir::geometry::Mesh;
use voussoir::history::{CutCache, CutError, replay};
use voussoir::model::{Block, Cut};

fn plane_x(x: f64) -> Cut {
    Cut::plane([x, 0.0, 0.0], [1.0, 0.0, 0.0])
}

fn beam() -> Vec<Block> {
    vec![
        cuboid("beam", [0.0, 0.0, 0.0], [4.0, 1.0, 1.0]),
        cuboid("base", [0.0, 0.0, -1.0], [4.0, 1.0, 0.0]).support(true),
    ]
}

fn names(blocks: &[Block]) -> Vec<&str> {
    blocks.iter().map(|b| b.name.as_str()).collect()
}

#[test]
fn names_follow_the_history_and_supports_stay_whole() {
    let cuts = [plane_x(1.0), plane_x(2.0), plane_x(3.0)];
    let (blocks, _) = replay(&beam(), &cuts, 1e-9, &mut CutCache::new()).unwrap();
    assert_eq!(names(&blocks), ["beam.0-", "beam.0+.1-", "beam.0+.1+.2-", "beam.0+.1+.2+", "base"]);
    for b in &blocks[..4] {
        assert_close(voussoir::geometry::MassProperties::of_mesh(&b.mesh).volume, 1.0, 1e-12, &b.name);
    }
    // Targeting the support cuts it.
    let cut = Cut { target: Some("base".into()), ..plane_x(2.0) };
    let (blocks, _) = replay(&beam(), &[cut], 1e-9, &mut CutCache::new()).unwrap();
    assert_eq!(names(&blocks), ["beam", "base.0-", "base.0+"]);
    assert!(blocks[1].support && blocks[2].support, "pieces of a support are supports");
}

#[test]
fn a_side_that_falls_apart_gets_numbered_pieces() {
    let u = [[0., 0.], [3., 0.], [3., 3.], [2., 3.], [2., 1.], [1., 1.], [1., 3.], [0., 3.]];
    let src = vec![Block::new("u", Mesh::extrude_z(&u, 0.0, 1.0))];
    let cut = Cut::plane([0.0, 2.0, 0.0], [0.0, 1.0, 0.0]);
    let (blocks, _) = replay(&src, &[cut], 1e-9, &mut CutCache::new()).unwrap();
    assert_eq!(names(&blocks), ["u.0-", "u.0+0", "u.0+1"]);
}

#[test]
fn replay_is_deterministic() {
    let cuts = [plane_x(1.3), Cut::plane([0.0, 0.0, 0.5], [0.2, 0.1, 1.0])];
    let a = replay(&beam(), &cuts, 1e-9, &mut CutCache::new()).unwrap().0;
    let b = replay(&beam(), &cuts, 1e-9, &mut CutCache::new()).unwrap().0;
    assert_eq!(a, b);
}

#[test]
fn editing_a_cut_recomputes_only_what_is_downstream() {
    let mut cuts = vec![plane_x(1.0), plane_x(2.0), plane_x(3.0)];
    let mut cache = CutCache::new();
    let (_, first) = replay(&beam(), &cuts, 1e-9, &mut cache).unwrap();
    // Cut 0 meets 1 piece, cut 1 meets 2, cut 2 meets 3 (the support is skipped).
    assert_eq!((first.splits, first.cached), (6, 0));
    let (_, again) = replay(&beam(), &cuts, 1e-9, &mut cache).unwrap();
    assert_eq!((again.splits, again.cached), (0, 6), "nothing changed, nothing recomputed");
    // Move the last cut: only its three splits are new.
    cuts[2] = plane_x(3.5);
    let (blocks, last) = replay(&beam(), &cuts, 1e-9, &mut cache).unwrap();
    assert_eq!((last.splits, last.cached), (3, 3));
    assert_close(voussoir::geometry::MassProperties::of_mesh(&blocks[3].mesh).volume, 0.5, 1e-12, "moved piece");
    // Move the middle cut: cut 0 is reused; cut 1 meets two pieces with a new plane; cut 2
    // meets beam.0- again unchanged (cached) and the two new pieces of cut 1.
    cuts[1] = plane_x(2.5);
    let (_, mid) = replay(&beam(), &cuts, 1e-9, &mut cache).unwrap();
    assert_eq!((mid.splits, mid.cached), (4, 2));
}

#[test]
fn bad_histories_are_named_errors() {
    let bad_normal = Cut::plane([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]);
    assert_eq!(
        replay(&beam(), &[bad_normal], 1e-9, &mut CutCache::new()).unwrap_err(),
        CutError::BadNormal { index: 0, normal: [0.0, 0.0, 0.0] }
    );
    let unknown = Cut { target: Some("nothing".into()), ..plane_x(1.0) };
    let e = replay(&beam(), &[plane_x(2.0), unknown], 1e-9, &mut CutCache::new()).unwrap_err();
    assert_eq!(e, CutError::UnknownTarget { index: 1, target: "nothing".into() });
    // A plane 1e-7 inside the end face cuts a sliver of 2.5e-8 of the beam.
    let e = replay(&beam(), &[plane_x(4.0 - 1e-7)], 1e-9, &mut CutCache::new()).unwrap_err();
    assert!(matches!(e, CutError::Sliver { index: 0, .. }), "{e}");
    assert!(e.to_string().contains("'beam'"), "{e}");
}

#[test]
fn a_design_with_cuts_round_trips_and_analyses() {
    let mut s = voussoir::model::Scene::new("cut beam", beam());
    s.cuts = vec![plane_x(1.0), Cut { target: Some("beam.0+".into()), ..plane_x(3.0) }];
    let text = voussoir::io::scene_json::scene_to_string(&s);
    let back = voussoir::io::scene_json::scene_from_str(std::path::Path::new("mem.json"), &text).unwrap();
    assert_eq!(back, s);
    let an = run(&back, &Default::default());
    assert_eq!(an.assembly.blocks.len(), 4);
    assert!(an.statics.stands);
    // Two joints between the three pieces and three contacts with the base.
    assert_eq!(an.interfaces.len(), 5);
}
