//! Fuzz target `perturbed`: its body is `bodies::run("perturbed", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/perturbed/, the kept corpus in fuzz/corpus/perturbed/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("perturbed", data);
});
