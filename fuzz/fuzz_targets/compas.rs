//! Fuzz target `compas`: its body is `bodies::run("compas", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/compas/, the kept corpus in fuzz/corpus/compas/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("compas", data);
});
