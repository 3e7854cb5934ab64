//! Writers of an analysis's results: the JSON report ([`json`]), the robustness report
//! ([`stability`]), the text the CLI prints ([`text`]), the compas files with interface
//! forces ([`compas`]), the self-contained HTML report ([`html`]), and numbers worded for
//! people ([`words`]). Writes go through
//! [`crate::io::write_atomic`].

pub mod compas;
pub mod html;
pub mod json;
pub mod stability;
pub mod text;
pub mod words;
