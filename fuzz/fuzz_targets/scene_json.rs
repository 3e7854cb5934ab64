//! Fuzz target `scene_json`: its body is `bodies::run("scene_json", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/scene_json/, the kept corpus in fuzz/corpus/scene_json/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("scene_json", data);
});
