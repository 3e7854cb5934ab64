//! Fuzz target `record`: its body is `bodies::run("record", …)` (fuzz/bodies.rs, shared with the
//! corpus replay test); seeds in fuzz/seeds/record/, the kept corpus in fuzz/corpus/record/.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    bodies::run("record", data);
});
