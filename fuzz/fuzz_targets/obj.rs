//! Fuzz target `obj`: its body is `bodies::run("obj", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/obj/, the kept corpus in fuzz/corpus/obj/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("obj", data);
});
