//! A threshold sweep's verdicts and margins against its parameter.

use super::PlotError;
use crate::studies::threshold::{ScanPoint, ThresholdStudy};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What a sweep plot shows.
pub struct ThresholdPlot<'a> {
    pub title: String,
    pub parameter: String,
    pub scan: &'a [ScanPoint],
    pub result: Option<&'a ThresholdStudy>,
}

/// Writes `plot` to `path` (.png or .svg), atomically.
pub fn write_thresholds(plot: &ThresholdPlot, path: &Path) -> Result<(), PlotError> {
    super::write(plot, path, (960, 640))
}

impl super::Drawing for ThresholdPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(root, self)
    }
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, plot: &ThresholdPlot) -> Result<(), String> {
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
