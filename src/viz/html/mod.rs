//! One self-contained HTML report of an analysis: the design in 3D with its interface-force
//! diagrams, the verdict and the graded numbers, the motions (collapse mechanism, drop test,
//! settlement) played beside it, and the plots — one file that opens offline in any current
//! browser.
//!
//! What the file holds, all inline:
//! - the page ([`PAGE`], its style and its script [`APP`]);
//! - three.js (MIT, vendored and pinned in `assets/report/three`, its README names the version
//!   and the npm tarball's integrity) and its glTF loader and orbit controls, gzip-compressed
//!   and base64-encoded; the page inflates them with the browser's `DecompressionStream` and
//!   imports them as module blobs (their `import` specifiers rewritten to the blobs' URLs);
//! - the design as the glTF binaries `voussoir export` writes ([`crate::viz::glb`]), one per
//!   diagram mode, and the motions as the glTF animations the CLI's `--frames` write, each
//!   compressed the same way;
//! - the JSON report ([`crate::report::json`]: what a click on a block or an interface shows; compressed
//!   as the assets are), the text report (the panel), and the plots as inline SVG.
//!
//! The studies a report can show beside the statics add themselves ([`HtmlReport::add_mechanism`],
//! [`HtmlReport::add_drop`], [`HtmlReport::add_settlement`]).
//!
//! Colours: the diagrams' linear RGB as the legends give them (the glTF's interface material
//! is unlit), CSS colours in sRGB.

mod parts;

pub use parts::MECHANISM_SECONDS;

use crate::pipeline::Analysis;
use crate::viz::{DiagramMode, colors, legend};
use serde::Serialize;
use std::io::Write;

/// The page: `{{TITLE}}`, `{{STYLE}}`, `{{DATA}}`, `{{ASSETS}}` and `{{APP}}` are filled in.
pub const PAGE: &str = include_str!("../../../assets/report/page.html");
/// The page's style.
pub const STYLE: &str = include_str!("../../../assets/report/report.css");
/// The page's script (an ES module importing `three` and its addons by name).
pub const APP: &str = include_str!("../../../assets/report/app.js");

/// The vendored modules in import order: (name the page imports it by, source).
const THREE: [(&str, &str); 6] = [
    ("three.core.js", include_str!("../../../assets/report/three/three.core.js")),
    ("three", include_str!("../../../assets/report/three/three.module.js")),
    ("three/addons/utils/BufferGeometryUtils.js", include_str!("../../../assets/report/three/BufferGeometryUtils.js")),
    ("three/addons/utils/SkeletonUtils.js", include_str!("../../../assets/report/three/SkeletonUtils.js")),
    ("three/addons/loaders/GLTFLoader.js", include_str!("../../../assets/report/three/GLTFLoader.js")),
    ("three/addons/controls/OrbitControls.js", include_str!("../../../assets/report/three/OrbitControls.js")),
];

/// A motion played in the report's motion pane.
#[derive(Clone, Debug)]
pub struct MotionPane {
    /// Its tab's label (`mechanism`, `drop test`, `settlement`).
    pub title: String,
    /// One line under it: what is shown, with its numbers.
    pub caption: String,
    /// The glTF animation ([`crate::viz::gltf::animation_glb`], [`crate::viz::gltf::mechanism_glb`]).
    pub glb: Vec<u8>,
    /// The blocks drawn in the moved colour ([`colors::MOVED`]), by index.
    pub moved: Vec<usize>,
}

/// A plot shown under the panes.
#[derive(Clone, Debug)]
pub struct Plot {
    /// Its title.
    pub title: String,
    /// The plot as an SVG document ([`crate::viz::plot::svg_string`]).
    pub svg: String,
}

/// What one report shows.
#[derive(Clone, Debug)]
pub struct HtmlReport<'a> {
    /// The analysed design.
    pub analysis: &'a Analysis,
    /// The diagram shown first; the page switches between compression, friction and vectors.
    pub mode: DiagramMode,
    /// The panel: the text report of everything that ran.
    pub text: String,
    /// The JSON report ([`crate::report::json::to_json_with`]).
    pub json: String,
    /// The motions, in tab order.
    pub motions: Vec<MotionPane>,
    /// The plots.
    pub plots: Vec<Plot>,
}

impl<'a> HtmlReport<'a> {
    /// The report of the statics alone: the text and JSON reports of `analysis`, no motion.
    pub fn new(analysis: &'a Analysis, mode: DiagramMode) -> Self {
        Self {
            analysis,
            mode,
            text: crate::report::text::summary(analysis, 5),
            json: crate::report::json::to_json(analysis),
            motions: Vec::new(),
            plots: Vec::new(),
        }
    }

    /// The page, one self-contained HTML document.
    pub fn html(&self) -> String {
        let mut assets = Assets { html: three_assets().to_string() };
        let data = self.data(&mut assets);
        let title = format!("voussoir report: {}", self.analysis.assembly.name);
        PAGE.replace("{{TITLE}}", &escape_html(&title))
            .replace("{{STYLE}}", STYLE)
            .replace("{{APP}}", &APP.replace("</script", "<\\/script"))
            .replace("{{ASSETS}}", &assets.html)
            .replace("{{DATA}}", &data)
    }

    /// The page's data as JSON safe inside a `<script>` element; the glTF binaries go to `assets`.
    fn data(&self, assets: &mut Assets) -> String {
        let a = self.analysis;
        let s = &a.statics;
        let threshold = match self.mode {
            DiagramMode::Friction { threshold } => threshold,
            _ => DiagramMode::DEFAULT_THRESHOLD,
        };
        let friction = DiagramMode::Friction { threshold };
        let mut diagrams = Vec::new();
        for (name, mode) in [("compression", DiagramMode::Compression), ("friction", friction)] {
            let id = format!("design:{name}");
            assets.add(&id, &crate::viz::glb(a, mode));
            diagrams.push(Diagram { name, asset: id, legend: css_legend(mode) });
        }
        let motions = self
            .motions
            .iter()
            .enumerate()
            .map(|(k, m)| {
                let id = format!("motion:{k}");
                assets.add(&id, &m.glb);
                Motion { title: &m.title, caption: &m.caption, asset: id, moved: &m.moved }
            })
            .collect();
        assets.add("report.json", self.json.as_bytes());
        let data = Data {
            scene: &a.assembly.name,
            verdict: crate::report::text::headline(s.verdict),
            verdict_colour: css(colors::verdict(Some(s.verdict))),
            stands: s.stands,
            first: match self.mode {
                DiagramMode::Compression => "compression",
                DiagramMode::Friction { .. } => "friction",
                DiagramMode::Vectors => "vectors",
            },
            diagrams,
            moved_colour: css(colors::MOVED),
            detected: a.interfaces.len(),
            solved: s.interfaces.len(),
            ground: a.assembly.ground,
            notes: notes(a),
            panel: &self.text,
            motions,
            plots: self.plots.iter().map(|p| PlotData { title: &p.title, svg: &p.svg }).collect(),
        };
        // `</` only occurs inside JSON strings, where `<\/` means the same.
        serde_json::to_string(&data).expect("the report's data serialises").replace("</", "<\\/")
    }
}

/// The page's data (read by [`APP`]).
#[derive(Serialize)]
struct Data<'a> {
    scene: &'a str,
    verdict: &'a str,
    verdict_colour: String,
    stands: bool,
    first: &'a str,
    diagrams: Vec<Diagram>,
    moved_colour: String,
    /// The interfaces detected, and those solved (the JSON report's: none when nothing holds
    /// the design).
    detected: usize,
    solved: usize,
    /// Whether the design stands on the ground plane z = 0 (the page draws it).
    ground: bool,
    notes: Vec<String>,
    panel: &'a str,
    motions: Vec<Motion<'a>>,
    plots: Vec<PlotData<'a>>,
}

#[derive(Serialize)]
struct Diagram {
    name: &'static str,
    asset: String,
    legend: Vec<(String, String)>,
}

#[derive(Serialize)]
struct Motion<'a> {
    title: &'a str,
    caption: &'a str,
    asset: String,
    moved: &'a [usize],
}

#[derive(Serialize)]
struct PlotData<'a> {
    title: &'a str,
    svg: &'a str,
}

/// What the page says in words before any picture: a design with nothing to draw, one that
/// touches no support.
fn notes(a: &Analysis) -> Vec<String> {
    let mut notes = Vec::new();
    if a.interfaces.is_empty() {
        notes.push("This design has no interfaces: no block touches another or a support, so there are no interface forces to draw.".into());
    }
    if a.statics.verdict == crate::statics::Verdict::Unsupported {
        notes.push("This design is not supported: some block touches no support, so no forces can hold it (the panel names it).".into());
    }
    notes
}

/// The legend of `mode` with CSS colours.
fn css_legend(mode: DiagramMode) -> Vec<(String, String)> {
    legend(mode).into_iter().map(|(c, label)| (css(colors::linear_to_srgb(c)), label)).collect()
}

/// An sRGB colour as CSS `#rrggbb`.
fn css(c: colors::Srgb) -> String {
    let [r, g, b] = c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
    format!("#{r:02x}{g:02x}{b:02x}")
}

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The vendored modules as asset elements: the same 2.3 MB compressed for every page, so once
/// per process (a notebook shows many).
fn three_assets() -> &'static str {
    static THREE_ASSETS: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    THREE_ASSETS.get_or_init(|| {
        let mut assets = Assets::default();
        for (name, source) in THREE {
            assets.add(&format!("module:{name}"), source.as_bytes());
        }
        assets.html
    })
}

/// The binary assets as `<script>` elements of gzip-compressed base64 text.
#[derive(Default)]
struct Assets {
    html: String,
}

impl Assets {
    fn add(&mut self, id: &str, bytes: &[u8]) {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        // Writing into a Vec cannot fail.
        let compressed = gz.write_all(bytes).and_then(|_| gz.finish()).expect("compressing into memory");
        self.html.push_str(&format!(
            "<script type=\"application/gzip+base64\" data-asset=\"{}\">{}</script>\n",
            escape_html(id),
            base64(&compressed)
        ));
    }
}

/// Standard base64 (RFC 4648, with padding).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (k, &b)| n | (b as u32) << (16 - 8 * k));
        for k in 0..4 {
            let c = if k <= chunk.len() { ALPHABET[(n >> (18 - 6 * k) & 63) as usize] } else { b'=' };
            out.push(c as char);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RFC 4648 §10's test vectors.
    #[test]
    fn base64_is_rfc_4648() {
        for (plain, encoded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), encoded);
        }
    }

    /// The sRGB transfer function's fixed points and its value at one half (0.7354).
    #[test]
    fn linear_to_srgb_is_the_srgb_curve() {
        let [black, white, half] = colors::linear_to_srgb([0.0, 1.0, 0.5]);
        assert_eq!(black, 0.0);
        assert!((white - 1.0).abs() < 1e-6 && (half - 0.735_357).abs() < 1e-5, "{white} {half}");
        assert_eq!(css([1.0, 0.0, 0.5]), "#ff0080");
    }
}
