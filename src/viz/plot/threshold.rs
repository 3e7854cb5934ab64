//! A threshold sweep's verdicts and margins against its parameter.

use super::{PlotError, rgb};
use crate::studies::threshold::{ScanPoint, ThresholdStudy};
use crate::viz::colors;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What a sweep plot shows.
pub struct ThresholdPlot<'a> {
    /// The plot's title (the family and its settings).
    pub title: String,
    /// The swept parameter's name and unit, for the x axis.
    pub parameter: String,
    /// The scanned parameters with both verdicts and margins.
    pub scan: &'a [ScanPoint],
    /// The bisection's thresholds to mark, when the sweep found them.
    pub result: Option<&'a ThresholdStudy>,
}

/// Writes `plot` to `path` (.png or .svg), atomically.
pub fn write_thresholds(plot: &ThresholdPlot, path: &Path) -> Result<(), PlotError> {
    super::write(plot, path, (960, 640))
}

impl super::Drawing for ThresholdPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        panels(root, self).map_err(|e| e.to_string())
    }
}

/// The statics' series (the margin and its threshold).
const STATICS: RGBColor = RGBColor(40, 90, 200);
/// The drop test's series (the motion, its limit and its threshold).
const DROP: RGBColor = RGBColor(230, 130, 20);

type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// The parameter axis: the scanned values with half a step of room on either side.
#[derive(Clone, Copy)]
struct Axis {
    lo: f64,
    hi: f64,
    /// Half the step between scanned values: each strip's half width.
    half: f64,
}

impl Axis {
    fn new(scan: &[ScanPoint]) -> Self {
        let (lo, hi) =
            scan.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.parameter), b.max(p.parameter)));
        let (lo, hi) = if lo < hi { (lo, hi) } else { (lo - 0.5, lo + 0.5) };
        let half = if scan.len() > 1 { 0.5 * (hi - lo) / (scan.len() - 1) as f64 } else { 0.5 };
        Self { lo, hi, half }
    }

    fn range(self) -> std::ops::Range<f64> {
        self.lo - self.half..self.hi + self.half
    }
}

/// The title, the verdict strips above and the margins below.
fn panels<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, plot: &ThresholdPlot) -> Drawn<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(&plot.title, ("sans-serif", 20))?;
    let (top, bottom) = root.split_vertically(170);
    let axis = Axis::new(plot.scan);
    verdict_strips(&top, plot, axis)?;
    margins(&bottom, plot, axis)?;
    root.present()
}

/// Verdict strips: statics (y = 1) and drop test (y = 0), each point coloured stands or fails.
fn verdict_strips<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, plot: &ThresholdPlot, axis: Axis) -> Drawn<DB> {
    let mut strips = ChartBuilder::on(area)
        .margin(10)
        .x_label_area_size(0)
        .y_label_area_size(110)
        .right_y_label_area_size(90)
        .build_cartesian_2d(axis.range(), -0.5f64..1.5)?;
    strips
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(2)
        .y_label_formatter(&|y| if *y > 0.5 { "statics".into() } else { "drop test".into() })
        .draw()?;
    for p in plot.scan {
        for (row, ok) in [(1.0, p.statics_stands), (0.0, p.drop_stands)] {
            let corners = [(p.parameter - axis.half, row - 0.35), (p.parameter + axis.half, row + 0.35)];
            strips.draw_series(std::iter::once(Rectangle::new(corners, rgb(colors::stands_on_white(ok)).filled())))?;
        }
    }
    Ok(())
}

/// Margins: the static graded answer (tension + friction excess, / W) and the drop test's
/// largest motion relative to its tolerance (> 1 falls), both against the parameter; the
/// thresholds found as vertical lines.
fn margins<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, plot: &ThresholdPlot, axis: Axis) -> Drawn<DB> {
    let top_margin = plot.scan.iter().map(|p| p.static_margin).fold(0.0f64, f64::max).max(1e-3) * 1.1;
    let top_motion = plot.scan.iter().map(|p| p.drop_motion.min(10.0)).fold(1.2f64, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(area)
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(110)
        .right_y_label_area_size(90)
        .build_cartesian_2d(axis.range(), 0.0..top_margin)?
        .set_secondary_coord(axis.range(), 0.0..top_motion);
    chart
        .configure_mesh()
        .x_desc(plot.parameter.as_str())
        .y_desc("static: (tension + excess) / W")
        .y_label_formatter(&|y| format!("{y:.3}"))
        .draw()?;
    chart.configure_secondary_axes().y_desc("drop: motion / tolerance").draw()?;
    let key = |c: RGBColor, width: u32| {
        move |(x, y): (i32, i32)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(width))
    };
    chart
        .draw_series(LineSeries::new(
            plot.scan.iter().map(|p| (p.parameter, p.static_margin)),
            STATICS.stroke_width(2),
        ))?
        .label("statics: minimum tension + friction excess (/ W)")
        .legend(key(STATICS, 2));
    chart.draw_series(plot.scan.iter().map(|p| Circle::new((p.parameter, p.static_margin), 3, STATICS.filled())))?;
    chart
        .draw_secondary_series(LineSeries::new(
            plot.scan.iter().map(|p| (p.parameter, p.drop_motion.min(10.0))),
            DROP.stroke_width(2),
        ))?
        .label("drop test: largest motion / tolerance (right axis, capped at 10)")
        .legend(key(DROP, 2));
    let range = axis.range();
    chart.draw_secondary_series(std::iter::once(PathElement::new(
        vec![(range.start, 1.0), (range.end, 1.0)],
        DROP.mix(0.5).stroke_width(1),
    )))?;
    if let Some(r) = plot.result {
        for (x, c, name) in
            [(r.statics.mid(), STATICS, "static threshold"), (r.dynamic.mid(), DROP, "drop-test threshold")]
        {
            chart
                .draw_series(std::iter::once(PathElement::new(vec![(x, 0.0), (x, top_margin)], c.stroke_width(1))))?
                .label(format!("{name} {x:.4}"))
                .legend(key(c, 1));
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
}
