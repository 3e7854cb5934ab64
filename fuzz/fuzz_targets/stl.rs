//! Fuzz target `stl`: its body is `bodies::run("stl", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/stl/, the kept corpus in fuzz/corpus/stl/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("stl", data);
});
