//! Invariant: input that cannot be analysed as given gets one clear error naming the file, block,
//! face, vertex or pair — never a panic, never a silent wrong answer — and sound input passes
//! untouched: broken meshes and files ([`meshes_and_files`]); input the analysis cannot trust
//! (unknown keys, stray coordinates, interpenetrating blocks: [`trust`]).

mod meshes_and_files;
mod trust;
