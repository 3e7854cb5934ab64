//! Writers of an analysis's results: the JSON report ([`json`]), the robustness report
//! ([`stability`]), the text the CLI prints ([`text`]), the compas files with interface
//! forces ([`compas`]), and numbers worded for people ([`words`]). The HTML report, which
//! draws, is [`crate::viz::html`]. Writes go through
//! [`crate::io::write_atomic`].

pub mod compas;
pub mod json;
pub mod stability;
pub mod text;
pub mod words;
