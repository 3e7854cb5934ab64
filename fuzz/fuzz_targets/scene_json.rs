//! Fuzz target: arbitrary bytes as a .json scene through reading, validation, detection and
//! statics must never panic. Seeds: fuzz/seeds/scene_json/.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mut scene) = voussoir::io::scene_from_bytes(Path::new("fuzz.json"), data) {
        if !scene.blocks.iter().any(|b| b.support) {
            scene.ground = true;
        }
        let _ = voussoir::analysis::analyze(&scene, &Default::default());
    }
});
