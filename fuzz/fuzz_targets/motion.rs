//! Fuzz target `motion`: its body is `bodies::run("motion", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/motion/, the kept corpus in fuzz/corpus/motion/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("motion", data);
});
