//! Fuzz target `mesh`: its body is `bodies::run("mesh", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/mesh/, the kept corpus in fuzz/corpus/mesh/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("mesh", data);
});
