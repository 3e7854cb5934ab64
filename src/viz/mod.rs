//! What the diagrams show, without a window: the seed paper's colour mappings (pure functions)
//! and the glTF export. The bevy viewer (feature `viewer`) draws with the same colours.

pub mod colors;
pub mod gltf;

pub use gltf::{DiagramMode, glb};
