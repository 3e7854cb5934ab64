//! The ECS edit loop: one `EditDesign` message (move a cut) → app.update() → cut, detect,
//! solve and entities written. On 10 independent stacks of 10 blocks (100 blocks; the edit
//! touches one stack), a 100-brick wall (one component: the whole wall is solved again) and
//! the Armadillo vault (399 blocks, one of them cut; one component). The app's solves start
//! from the previous edit's iterates (`warm_start`, the editor's setting); the `_cold` benches
//! run the same edits with it off.

use bevy::prelude::*;
use criterion::{Criterion, criterion_group, criterion_main};
use std::path::PathBuf;
use std::time::Duration;
use voussoir::ecs::{EditDesign, SceneStatus, Settings, VoussoirPlugins};
use voussoir::model::edit::Edit;
use voussoir::model::{Cut, Scene, builtin};
use voussoir::pipeline::AnalysisSettings;

/// An app with `scene` loaded and a cut of block `target` through `point` with `normal`; its
/// solves cold with `cold`.
fn app_with(scene: Scene, target: &str, point: [f64; 3], normal: [f64; 3], cold: bool) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, VoussoirPlugins));
    if cold {
        app.insert_resource(Settings(AnalysisSettings::default()));
    }
    app.world_mut().write_message(EditDesign(Edit::Load(Box::new(scene))));
    app.world_mut().write_message(EditDesign(Edit::AddCut(Cut::plane(point, normal).on(target))));
    app.update();
    let s = app.world().resource::<SceneStatus>();
    assert!(s.error.is_none(), "{:?}", s.error);
    app
}

/// Moves the cut by ±`step` along its normal each iteration.
fn bench_moves(c: &mut Criterion, name: &str, mut app: App, point: [f64; 3], normal: [f64; 3], step: f64) {
    let mut flip = false;
    let target = {
        let scene = app.world().resource::<voussoir::ecs::Design>().0.clone().unwrap();
        scene.cuts[0].target.clone().unwrap()
    };
    c.bench_function(name, |b| {
        b.iter(|| {
            flip = !flip;
            let d = if flip { step } else { 0.0 };
            let p = [point[0] + d * normal[0], point[1] + d * normal[1], point[2] + d * normal[2]];
            let cut = Cut::plane(p, normal).on(&target);
            app.world_mut().write_message(EditDesign(Edit::MoveCut { index: 0, cut }));
            app.update();
        })
    });
}

fn edit_loop(c: &mut Criterion) {
    // 10 stacks × 10 unit boxes; cut the middle box of the first stack, tilted.
    let stacks = builtin("stacks?k=10&n=10").unwrap();
    let name = stacks.blocks[5].name.clone();
    let cz = stacks.blocks[5].mesh.aabb().center().z;
    let cx = stacks.blocks[5].mesh.aabb().center().x;
    let app = app_with(stacks, &name, [cx, 0.0, cz], [0.3, 0.0, 1.0], false);
    bench_moves(c, "edit_loop/stacks_10x10_move_cut", app, [cx, 0.0, cz], [0.3, 0.0, 1.0], 0.05);

    let wall = builtin("wall?courses=10&bricks=10").unwrap();
    let brick = &wall.blocks[wall.blocks.len() / 2];
    let (name, c0) = (brick.name.clone(), brick.mesh.aabb().center());
    for (cold, bench) in [(false, "edit_loop/wall_100_move_cut"), (true, "edit_loop/wall_100_move_cut_cold")] {
        let app = app_with(wall.clone(), &name, [c0.x, c0.y, c0.z], [1.0, 0.0, 0.0], cold);
        bench_moves(c, bench, app, [c0.x, c0.y, c0.z], [1.0, 0.0, 0.0], 0.01);
    }

    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/compas/compas_cra/armadillo_cra.json");
    let mut armadillo = voussoir::io::load_scene(&path).unwrap();
    armadillo.material.friction = 0.84;
    let block = armadillo.blocks.iter().find(|b| !b.support).unwrap();
    let (name, c0) = (block.name.clone(), block.mesh.aabb().center());
    for (cold, bench) in [(false, "edit_loop/armadillo_move_cut"), (true, "edit_loop/armadillo_move_cut_cold")] {
        let app = app_with(armadillo.clone(), &name, [c0.x, c0.y, c0.z], [0.0, 0.0, 1.0], cold);
        bench_moves(c, bench, app, [c0.x, c0.y, c0.z], [0.0, 0.0, 1.0], 0.005);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(6));
    targets = edit_loop
}
criterion_main!(benches);
