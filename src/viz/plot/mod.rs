//! Plots and offscreen pictures (plotters is touched only here), written as PNG or SVG by the
//! file's extension: a threshold sweep's verdicts and margins ([`threshold`]), and the interface
//! diagrams of an analysis drawn without a window ([`diagram`]), a drop test's key frames
//! ([`strip`]). Text uses the bundled DejaVu
//! Sans Mono (assets/fonts, so no system fonts are needed). Writes are atomic.

pub mod diagram;
pub mod mechanism;
pub mod settlement;
pub mod shake;
pub mod strip;
pub mod threshold;

pub use diagram::{DiagramPicture, write_diagram};
pub use mechanism::{MechanismPicture, PolarPlot, write_mechanism, write_polar};
pub use settlement::{ThrustPlot, write_thrust};
pub use shake::{ShakePlot, SpectrumPlot, write_shake, write_spectrum};
pub use strip::{Clock, FrameStrip, write_strip};
pub use threshold::{ThresholdPlot, write_thresholds};

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use thiserror::Error;

/// Why a plot could not be written.
#[derive(Debug, Error)]
pub enum PlotError {
    /// The extension is neither .png nor .svg.
    #[error("{path}: plots are written as .png or .svg")]
    Format {
        /// The output path as given.
        path: String,
    },
    /// plotters could not draw it.
    #[error("{path}: cannot draw the plot: {message}")]
    Draw {
        /// The output path as given.
        path: String,
        /// plotters' message.
        message: String,
    },
    /// The file cannot be written.
    #[error("{path}: cannot write: {message}")]
    Write {
        /// The output path as given.
        path: String,
        /// What the operating system said.
        message: String,
    },
}

/// DejaVu Sans Mono (bundled with its licence): the pictures' and the viewer's text (it has μ, ·, —).
pub static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSansMono.ttf");

/// Registers the bundled font as "sans-serif" for every plotters backend (idempotent).
pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The bundled font is valid: registering it cannot fail.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// A palette colour as plotters draws it (8-bit sRGB).
pub(crate) fn rgb(c: crate::viz::colors::Srgb) -> RGBColor {
    let [r, g, b] = c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
    RGBColor(r, g, b)
}

/// Something drawable on any plotters backend.
pub trait Drawing {
    /// Draws onto `root`; a plotters error comes back as its message.
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Draws `d` into memory: `size` pixels, 8-bit RGB rows top to bottom (the viewer shows it).
pub fn render_rgb<D: Drawing>(d: &D, size: (u32, u32)) -> Result<Vec<u8>, String> {
    register_font();
    let mut buffer = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    d.draw(BitMapBackend::with_buffer(&mut buffer, size).into_drawing_area())?;
    Ok(buffer)
}

/// Draws `d` as an SVG document of `size` pixels (the HTML report inlines it).
pub fn svg_string<D: Drawing>(d: &D, size: (u32, u32)) -> Result<String, String> {
    register_font();
    let mut out = String::new();
    d.draw(SVGBackend::with_string(&mut out, size).into_drawing_area())?;
    Ok(out)
}

/// Draws `d` into `path` (.png or .svg) at `size` pixels: into a temporary file beside it (same
/// extension: the bitmap backend picks its encoder by extension), renamed over it when complete.
pub fn write<D: Drawing>(d: &D, path: &Path, size: (u32, u32)) -> Result<(), PlotError> {
    register_font();
    let shown = path.display().to_string();
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let tmp = path.with_file_name(format!(
        ".{}.{}.tmp.{}",
        path.file_stem().and_then(|s| s.to_str()).unwrap_or("plot"),
        std::process::id(),
        ext.as_deref().unwrap_or("")
    ));
    let drawn = match ext.as_deref() {
        Some("png") => d.draw(BitMapBackend::new(&tmp, size).into_drawing_area()),
        Some("svg") => d.draw(SVGBackend::new(&tmp, size).into_drawing_area()),
        _ => return Err(PlotError::Format { path: shown }),
    };
    if let Err(message) = drawn {
        let _ = std::fs::remove_file(&tmp);
        return Err(PlotError::Draw { path: shown, message });
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        PlotError::Write { path: shown, message: e.to_string() }
    })
}
