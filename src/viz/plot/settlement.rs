//! A settlement analysis's support reactions against the support movement: the thrust curve.

use super::PlotError;
use crate::studies::settlement::{Outcome, Run, Settlement};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What the plot shows: each run's horizontal reaction on its first moved support (the thrust)
/// against the movement, the collapses marked.
pub struct ThrustPlot<'a> {
    /// The plot's title (the design's name).
    pub title: String,
    /// The runs to draw: their stages' reactions and movements, and each collapse.
    pub settlement: &'a Settlement,
}

/// Writes `plot` to `path` (.png or .svg), atomically.
pub fn write_thrust(plot: &ThrustPlot, path: &Path) -> Result<(), PlotError> {
    super::write(plot, path, ThrustPlot::SIZE)
}

impl ThrustPlot<'_> {
    /// The plot's size in pixels.
    pub const SIZE: (u32, u32) = (960, 640);
}

impl super::Drawing for ThrustPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        chart(root, self).map_err(|e| e.to_string())
    }
}

type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// The horizontal reaction (N) on the first moved support at each stage of `run`.
fn thrust(run: &Run) -> Vec<(f64, f64)> {
    run.stages.iter().filter_map(|s| s.reactions.first().map(|r| (s.movement, r[0].hypot(r[1])))).collect()
}

fn chart<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, plot: &ThrustPlot) -> Drawn<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(&plot.title, ("sans-serif", 20))?;
    let s = plot.settlement;
    // rapier's reactions are left out: its friction impulses read as half the rigid thrust.
    let runs: Vec<(&Run, RGBColor)> = [Some(&s.quasi_static), s.exact.as_ref()]
        .into_iter()
        .flatten()
        .zip([RGBColor(40, 90, 200), RGBColor(230, 130, 20)])
        .collect();
    let points: Vec<Vec<(f64, f64)>> = runs.iter().map(|(r, _)| thrust(r)).collect();
    let top = points.iter().flatten().map(|p| p.1).fold(0.0f64, f64::max).max(f64::MIN_POSITIVE) * 1.1;
    let right = s.path_movement.max(f64::MIN_POSITIVE);
    let mut c = ChartBuilder::on(&root)
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(90)
        .build_cartesian_2d(0.0..right, 0.0..top)?;
    c.configure_mesh()
        .x_desc(format!("movement of '{}' (m)", s.supports.first().map_or("", String::as_str)))
        .y_desc("horizontal reaction (N)")
        .draw()?;
    for ((run, color), pts) in runs.iter().zip(&points) {
        let color = *color;
        c.draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))?
            .label(run.method)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        if let Outcome::Collapses { movement, .. } = run.outcome {
            c.draw_series(std::iter::once(PathElement::new(
                vec![(movement, 0.0), (movement, top)],
                color.stroke_width(1),
            )))?;
        }
    }
    c.configure_series_labels().border_style(BLACK).background_style(WHITE).draw()?;
    root.present()
}
