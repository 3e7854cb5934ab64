//! Invariant: the glTF export round-trips through an independent reader (the `gltf` crate):
//! one mesh per block and per loaded interface, positions in glTF's y-up axes, interface vertex
//! colours that follow the statics (blue compression for a standing stack, red where tension is
//! needed, yellow/orange/red friction by utilisation).

use voussoir::model::builtin;
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::viz::{DiagramMode, glb};

struct Read {
    names: Vec<String>,
    colors: Vec<(String, Vec<[f32; 3]>)>,
    max_y: f32,
}

fn read(bytes: &[u8]) -> Read {
    let (doc, buffers, _) = gltf::import_slice(bytes).expect("a valid glb");
    let mut out = Read { names: vec![], colors: vec![], max_y: f32::NEG_INFINITY };
    for mesh in doc.meshes() {
        let name = mesh.name().unwrap_or_default().to_string();
        for prim in mesh.primitives() {
            let reader = prim.reader(|b| Some(&buffers[b.index()]));
            let pos: Vec<[f32; 3]> = reader.read_positions().expect("positions").collect();
            assert_eq!(pos.len() % 3, 0, "{name}: whole triangles");
            out.max_y = pos.iter().fold(out.max_y, |m, p| m.max(p[1]));
            assert_eq!(reader.read_normals().expect("normals").count(), pos.len());
            if let Some(c) = reader.read_colors(0) {
                out.colors.push((name.clone(), c.into_rgb_f32().collect()));
            }
        }
        out.names.push(name);
    }
    out
}

#[test]
fn standing_stack_is_blue_and_in_y_up_axes() {
    let scene = builtin("stack?n=3").unwrap();
    let a = analyze(&scene, &AnalysisSettings::default()).unwrap();
    assert!(a.statics.stands);
    let r = read(&glb(&a, DiagramMode::Compression));
    assert_eq!(r.names.len(), a.assembly.blocks.len() + a.statics.interfaces.len());
    for b in &a.assembly.blocks {
        assert!(r.names.contains(&b.name), "{}", b.name);
    }
    // z up → y up: the highest glTF y is the stack's top.
    let top = a.assembly.blocks.iter().map(|b| b.mesh.aabb().max.z).fold(f64::MIN, f64::max);
    assert!((r.max_y as f64 - top).abs() < 1e-6, "{} vs {top}", r.max_y);
    assert_eq!(r.colors.len(), a.statics.interfaces.len());
    for (name, cs) in &r.colors {
        assert!(cs.iter().all(|c| c[2] > c[0] + 0.2), "{name}: compression is blue: {cs:?}");
    }
}

#[test]
fn tension_is_red_and_friction_follows_utilisation() {
    // An offset cube needs tension at its support: some interface vertex is red.
    let scene = builtin("harmonic?n=3&s=1.3").unwrap();
    let a = analyze(&scene, &AnalysisSettings::default()).unwrap();
    assert!(!a.statics.stands && a.statics.tension_ratio > 0.0);
    let r = read(&glb(&a, DiagramMode::Compression));
    let red = |c: &[f32; 3]| c[0] > c[1] + 0.2 && c[0] > c[2] + 0.2;
    assert!(r.colors.iter().any(|(_, cs)| cs.iter().any(red)), "a red vertex where tension is needed");

    // A block on a slope with μ = tan 40° (b = 2h: no tipping). Per vertex the colour follows
    // that vertex's utilisation |f_t| / (μ f_n): at 10° (interface utilisation 0.21) every vertex
    // is yellow under a 0.8 threshold; at 30° (0.69) none is red and some are orange under 0.5;
    // at 45° (1.19, exceeded) some are red.
    let category = |c: &[f32; 3]| -> &str {
        if c[0] > 0.9 && c[1] > 0.85 && c[2] < 0.2 {
            "yellow"
        } else if c[0] > 0.85 && c[1] > 0.3 && c[1] < 0.75 && c[2] < 0.3 {
            "orange"
        } else if c[0] > 0.8 && c[1] < 0.1 && c[2] < 0.1 {
            "red"
        } else {
            "other"
        }
    };
    let colors_at = |angle: f64, threshold: f64| -> Vec<&'static str> {
        let scene = builtin(&format!("slope?angle={angle}&b=2&h=0.5")).unwrap();
        let a = analyze(&scene, &AnalysisSettings::default()).unwrap();
        let r = read(&glb(&a, DiagramMode::Friction { threshold }));
        let (_, cs) = r.colors.iter().find(|(n, _)| n.contains("block")).expect("the slope interface");
        cs.iter()
            .map(|c| match category(c) {
                "yellow" => "yellow",
                "orange" => "orange",
                "red" => "red",
                _ => panic!("{angle}°: unexpected friction colour {c:?}"),
            })
            .collect()
    };
    assert!(colors_at(10.0, 0.8).iter().all(|c| *c == "yellow"));
    let at30 = colors_at(30.0, 0.5);
    assert!(!at30.contains(&"red") && at30.contains(&"orange"), "{at30:?}");
    assert!(colors_at(45.0, 0.5).contains(&"red"));
}

/// A 7-voussoir arch too thin to stand (t/R 0.06) falling for 0.5 s in the exact engine,
/// recorded at 30 frames per simulated second.
fn collapse() -> (voussoir::model::Assembly, voussoir::dynamics::DropResult, voussoir::dynamics::Trajectory) {
    use voussoir::dynamics::{DropSettings, Engine, record};
    let scene = builtin("arch?n=7&t=0.06").unwrap();
    let asm = voussoir::model::Assembly::new(&scene, &Default::default()).unwrap();
    let settings = DropSettings { engine: Engine::Exact, duration: 0.5, ..Default::default() };
    let (result, motion) = record(&asm, &settings, 30.0).unwrap();
    (asm, result, motion)
}

/// Invariant: a drop test's motion exported as a glTF animation reads back with the `gltf`
/// crate: one translation and one rotation channel per free block (none for the supports),
/// times from 0 to the duration at 30 frames per simulated second, and the last keyframe is the
/// run's final pose in y-up axes (a collapsing arch, exact engine).
#[test]
fn a_collapse_exports_as_an_animation() {
    use gltf::animation::util::ReadOutputs;
    let (asm, result, motion) = collapse();
    assert!(!result.stands);
    let bytes = voussoir::viz::gltf::animation_glb(&asm, &motion);
    let (doc, buffers, _) = gltf::import_slice(&bytes).expect("a valid glb");
    let animation = doc.animations().next().expect("an animation");
    let free: Vec<usize> = (0..asm.blocks.len()).filter(|&i| !asm.blocks[i].support).collect();
    assert_eq!(animation.channels().count(), 2 * free.len());
    let last = motion.poses.last().unwrap();
    for channel in animation.channels() {
        let node = channel.target().node();
        let i = asm.blocks.iter().position(|b| Some(b.name.as_str()) == node.name()).expect("a block's node");
        assert!(!asm.blocks[i].support);
        let reader = channel.reader(|b| Some(&buffers[b.index()]));
        let times: Vec<f32> = reader.read_inputs().unwrap().collect();
        assert_eq!(times.len(), 16, "0.5 s at 30 frames per second, and the start");
        assert!(times[0] == 0.0 && (times[15] - 0.5).abs() < 1e-6);
        match reader.read_outputs().unwrap() {
            ReadOutputs::Translations(t) => {
                let end = t.last().unwrap();
                let p = last[i].0;
                let expected = [p.x as f32, p.z as f32, -p.y as f32];
                assert!(end.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-5), "{end:?} vs {expected:?}");
            }
            ReadOutputs::Rotations(r) => {
                let end = r.into_f32().last().unwrap();
                let [w, x, y, z] = last[i].1;
                let expected = [x as f32, z as f32, -y as f32, w as f32];
                assert!(end.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-6), "{end:?} vs {expected:?}");
            }
            _ => panic!("only translations and rotations"),
        }
    }
}

/// Invariant: a collapse's key-frame strip takes evenly spaced recorded frames, the first and
/// the last included (16 frames, 6 keys: every third), one 360 × 420 panel each; a block is
/// drawn in the mechanism's colour once it has moved a tenth of a block, so the first panel
/// (at rest) has none of it and the last (fallen) much.
#[test]
fn a_collapse_draws_as_a_strip_of_key_frames() {
    use voussoir::viz::plot::{FrameStrip, write_strip};
    let (asm, _, motion) = collapse();
    let strip = FrameStrip::new(&asm, &motion);
    assert_eq!(strip.key_frames(), [0, 3, 6, 9, 12, 15]);
    let dir = crate::common::scratch("strip");
    let png = dir.join("strip.png");
    write_strip(&strip, &png).unwrap();
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (6 * 360, 420));
    // The mechanism's violet: blue well above green.
    let violet = |panel: u32| {
        (panel * 360..(panel + 1) * 360)
            .flat_map(|x| (0..420).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let [r, g, b] = img.get_pixel(x, y).0;
                b as i32 > g as i32 + 40 && b > r
            })
            .count()
    };
    assert_eq!(violet(0), 0, "at rest nothing has moved");
    assert!(violet(5) > 1000, "fallen blocks in the mechanism's colour: {}", violet(5));
    std::fs::remove_dir_all(&dir).unwrap();
}
