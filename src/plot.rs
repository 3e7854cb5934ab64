//! Plots (plotters is touched only here): a threshold sweep's verdicts and margins against its
//! parameter, written as PNG or SVG by the file's extension. Text uses the bundled DejaVu Sans
//! Mono (assets/fonts, so no system fonts are needed). Writes are atomic.

use crate::sweep::{ScanPoint, SweepResult};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use thiserror::Error;

/// Why a plot could not be written.
#[derive(Debug, Error)]
pub enum PlotError {
    #[error("{path}: plots are written as .png or .svg")]
    Format { path: String },
    #[error("{path}: cannot draw the plot: {message}")]
    Draw { path: String, message: String },
    #[error("{path}: cannot write: {message}")]
    Write { path: String, message: String },
}

static FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSansMono.ttf");

/// Registers the bundled font as "sans-serif" for every plotters backend (idempotent).
pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The bundled font is valid: registering it cannot fail.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// What a sweep plot shows.
pub struct SweepPlot<'a> {
    pub title: String,
    pub parameter: String,
    pub scan: &'a [ScanPoint],
    pub result: Option<&'a SweepResult>,
}

/// Writes `plot` to `path` (.png or .svg), atomically.
pub fn write_sweep(plot: &SweepPlot, path: &Path) -> Result<(), PlotError> {
    register_font();
    let shown = path.display().to_string();
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    // A temporary file beside the target with the same extension (the bitmap backend picks the
    // encoder by extension), renamed over the target when complete.
    let tmp = path.with_file_name(format!(
        ".{}.{}.tmp.{}",
        path.file_stem().and_then(|s| s.to_str()).unwrap_or("plot"),
        std::process::id(),
        ext.as_deref().unwrap_or("")
    ));
    let size = (960, 640);
    let drawn = match ext.as_deref() {
        Some("png") => draw(BitMapBackend::new(&tmp, size).into_drawing_area(), plot),
        Some("svg") => draw(SVGBackend::new(&tmp, size).into_drawing_area(), plot),
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

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, plot: &SweepPlot) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(&plot.title, ("sans-serif", 20)).map_err(err)?;
    let (top, bottom) = root.split_vertically(170);
    let xs: Vec<f64> = plot.scan.iter().map(|p| p.parameter).collect();
    let (lo, hi) = xs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let (lo, hi) = if lo < hi { (lo, hi) } else { (lo - 0.5, lo + 0.5) };
    let half = if xs.len() > 1 { 0.5 * (hi - lo) / (xs.len() - 1) as f64 } else { 0.5 };

    // Verdict strips: statics (y = 1) and drop test (y = 0); green stands, red fails.
    let mut strips = ChartBuilder::on(&top)
        .margin(10)
        .x_label_area_size(0)
        .y_label_area_size(110)
        .right_y_label_area_size(90)
        .build_cartesian_2d(lo - half..hi + half, -0.5f64..1.5)
        .map_err(err)?;
    strips
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(2)
        .y_label_formatter(&|y| if *y > 0.5 { "statics".into() } else { "drop test".into() })
        .draw()
        .map_err(err)?;
    let green = RGBColor(60, 160, 80);
    let red = RGBColor(210, 50, 50);
    for p in plot.scan {
        for (row, ok) in [(1.0, p.statics_stands), (0.0, p.drop_stands)] {
            let c = if ok { green } else { red };
            strips
                .draw_series(std::iter::once(Rectangle::new(
                    [(p.parameter - half, row - 0.35), (p.parameter + half, row + 0.35)],
                    c.filled(),
                )))
                .map_err(err)?;
        }
    }

    // Margins: the static graded answer (tension + friction excess, / W) and the drop test's
    // largest motion relative to its tolerance (> 1 falls), both against the parameter.
    let top_margin = plot.scan.iter().map(|p| p.static_margin).fold(0.0f64, f64::max).max(1e-3) * 1.1;
    let top_motion = plot.scan.iter().map(|p| p.drop_motion.min(10.0)).fold(1.2f64, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(&bottom)
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(110)
        .right_y_label_area_size(90)
        .build_cartesian_2d(lo - half..hi + half, 0.0..top_margin)
        .map_err(err)?
        .set_secondary_coord(lo - half..hi + half, 0.0..top_motion);
    chart
        .configure_mesh()
        .x_desc(plot.parameter.as_str())
        .y_desc("static: (tension + excess) / W")
        .y_label_formatter(&|y| format!("{y:.3}"))
        .draw()
        .map_err(err)?;
    chart.configure_secondary_axes().y_desc("drop: motion / tolerance").draw().map_err(err)?;
    let blue = RGBColor(40, 90, 200);
    let orange = RGBColor(230, 130, 20);
    chart
        .draw_series(LineSeries::new(plot.scan.iter().map(|p| (p.parameter, p.static_margin)), blue.stroke_width(2)))
        .map_err(err)?
        .label("statics: minimum tension + friction excess (/ W)")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], blue.stroke_width(2)));
    chart
        .draw_series(plot.scan.iter().map(|p| Circle::new((p.parameter, p.static_margin), 3, blue.filled())))
        .map_err(err)?;
    chart
        .draw_secondary_series(LineSeries::new(
            plot.scan.iter().map(|p| (p.parameter, p.drop_motion.min(10.0))),
            orange.stroke_width(2),
        ))
        .map_err(err)?
        .label("drop test: largest motion / tolerance (right axis, capped at 10)")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], orange.stroke_width(2)));
    chart
        .draw_secondary_series(std::iter::once(PathElement::new(
            vec![(lo - half, 1.0), (hi + half, 1.0)],
            orange.mix(0.5).stroke_width(1),
        )))
        .map_err(err)?;
    if let Some(r) = plot.result {
        for (x, c, name) in
            [(r.statics.mid(), blue, "static threshold"), (r.dynamic.mid(), orange, "drop-test threshold")]
        {
            chart
                .draw_series(std::iter::once(PathElement::new(vec![(x, 0.0), (x, top_margin)], c.stroke_width(1))))
                .map_err(err)?
                .label(format!("{name} {x:.4}"))
                .legend(move |(lx, ly)| PathElement::new(vec![(lx, ly), (lx + 20, ly)], c.stroke_width(1)));
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}
