//! A shake's history (the ground's acceleration with ±λ* above, the largest rotation of a
//! block per engine below) and a collapse spectrum (the least collapsing amplitude against the
//! pulse's duration, λ* its long-pulse limit).

use super::PlotError;
use crate::studies::shake::{ShakeStudy, Spectrum};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What a shake plot shows.
pub struct ShakePlot<'a> {
    /// The plot's title (the design and the motion).
    pub title: String,
    /// The shake: λ* (not drawn when not finite) and each engine's result and history.
    pub study: &'a ShakeStudy,
}

/// What a spectrum plot shows.
pub struct SpectrumPlot<'a> {
    /// The plot's title.
    pub title: String,
    /// The spectrum.
    pub spectrum: &'a Spectrum,
}

/// Writes `plot` to `path` (.png or .svg), atomically.
pub fn write_shake(plot: &ShakePlot, path: &Path) -> Result<(), PlotError> {
    super::write(plot, path, (960, 720))
}

/// Writes `plot` to `path` (.png or .svg), atomically.
pub fn write_spectrum(plot: &SpectrumPlot, path: &Path) -> Result<(), PlotError> {
    super::write(plot, path, (960, 640))
}

impl super::Drawing for ShakePlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        history(root, self).map_err(|e| e.to_string())
    }
}

impl super::Drawing for SpectrumPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        spectrum(root, self).map_err(|e| e.to_string())
    }
}

type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// The ground's series and λ*.
const GROUND: RGBColor = RGBColor(90, 90, 90);
const LAMBDA: RGBColor = RGBColor(200, 40, 40);
/// The engines' series, in the runs' order.
const ENGINES: [RGBColor; 2] = [RGBColor(230, 130, 20), RGBColor(40, 90, 200)];

fn key(c: RGBColor) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
}

/// The ground acceleration panel above, the response panel below.
fn history<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, plot: &ShakePlot) -> Drawn<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(&plot.title, ("sans-serif", 20))?;
    let (top, bottom) = root.split_vertically(300);
    let runs = &plot.study.runs;
    let Some(first) = runs.first().map(|r| &r.trace) else { return root.present() };
    let end = runs.iter().filter_map(|r| r.trace.times.last()).fold(f64::MIN_POSITIVE, |a, b| a.max(*b));
    let lambda = plot.study.static_load_factor.is_finite().then_some(plot.study.static_load_factor);
    let peak = first.ground_g.iter().fold(lambda.unwrap_or(0.0), |m, a| m.max(a.abs())).max(1e-6) * 1.15;
    let mut c = ChartBuilder::on(&top)
        .margin(12)
        .x_label_area_size(30)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..end, -peak..peak)?;
    c.configure_mesh().y_desc("ground acceleration (g)").draw()?;
    c.draw_series(LineSeries::new(first.times.iter().copied().zip(first.ground_g.iter().copied()), GROUND))?
        .label("ground")
        .legend(key(GROUND));
    if let Some(l) = lambda {
        for y in [l, -l] {
            c.draw_series(DashedLineSeries::new([(0.0, y), (end, y)], 8, 5, LAMBDA.stroke_width(2)))?;
        }
        c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
            .label(format!("±λ* = {l:.4} g (statics)"))
            .legend(key(LAMBDA));
    }
    c.configure_series_labels().border_style(BLACK).background_style(WHITE).draw()?;
    response(&bottom, plot, end)?;
    root.present()
}

/// The largest rotation of a block (degrees) per engine, each collapse marked.
fn response<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, plot: &ShakePlot, end: f64) -> Drawn<DB> {
    let runs = &plot.study.runs;
    let top = runs.iter().flat_map(|r| &r.trace.rotation).fold(0.0f64, |m, r| m.max(r.to_degrees())).max(0.1) * 1.1;
    let mut c = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..end, 0.0..top)?;
    c.configure_mesh().x_desc("time (s)").y_desc("largest rotation of a block (°)").draw()?;
    for (run, color) in runs.iter().zip(ENGINES) {
        let (result, trace) = (&run.result, &run.trace);
        let label = match result.fell {
            Some(t) => format!("{}: collapses at {t:.2} s", result.engine.name()),
            None => format!("{}: survives", result.engine.name()),
        };
        let points = trace.times.iter().copied().zip(trace.rotation.iter().map(|r| r.to_degrees()));
        c.draw_series(LineSeries::new(points, color.stroke_width(2)))?.label(label).legend(key(color));
        if let Some(t) = result.fell {
            c.draw_series(std::iter::once(PathElement::new(vec![(t, 0.0), (t, top)], color.stroke_width(1))))?;
        }
    }
    c.configure_series_labels().border_style(BLACK).background_style(WHITE).draw()
}

/// The least collapsing amplitude against the duration (log axis), the bracket's lower end
/// dotted, λ* dashed.
fn spectrum<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, plot: &SpectrumPlot) -> Drawn<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(&plot.title, ("sans-serif", 20))?;
    let s = plot.spectrum;
    let (lo, hi) = s.points.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.duration), b.max(p.duration)));
    let (lo, hi) = if lo < hi { (lo / 1.2, hi * 1.2) } else { (lo / 2.0, lo * 2.0) };
    let lambda = s.static_load_factor.is_finite().then_some(s.static_load_factor);
    let top =
        s.points.iter().map(|p| p.collapses_g.unwrap_or(p.stands_g)).fold(lambda.unwrap_or(0.0), f64::max).max(1e-3)
            * 1.15;
    let mut c = ChartBuilder::on(&root)
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d((lo..hi).log_scale(), 0.0..top)?;
    c.configure_mesh().x_desc("pulse duration (s)").y_desc("least collapsing amplitude (g)").draw()?;
    let color = ENGINES[0];
    let points: Vec<(f64, f64)> = s.points.iter().filter_map(|p| p.collapses_g.map(|g| (p.duration, g))).collect();
    let label = format!("{} pulses, {} engine", s.shape.name(), s.engine.name());
    c.draw_series(LineSeries::new(points.iter().copied(), color.stroke_width(2)))?.label(label).legend(key(color));
    c.draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))?;
    if let Some(l) = lambda {
        c.draw_series(DashedLineSeries::new([(lo, l), (hi, l)], 8, 5, LAMBDA.stroke_width(2)))?
            .label(format!("λ* = {l:.4} g (statics: the long-pulse limit)"))
            .legend(key(LAMBDA));
    }
    c.configure_series_labels().border_style(BLACK).background_style(WHITE).draw()?;
    root.present()
}
