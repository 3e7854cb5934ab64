//! Pictures of how safely a design stands: its collapse mechanism (the blocks displaced along
//! it, exaggerated, over a ghost of the rest state; the moving interfaces coloured by what they
//! do) and the polar plot of the load factor λ* over the horizontal directions.

use super::diagram::{View, rgba};
use super::{Drawing, PlotError};
use crate::interfaces::Interface;
use crate::model::BlockId;
use crate::pipeline::Analysis;
use crate::stability::{DirectionSweep, JointState, Robustness, Safety};
use crate::viz::colors;
use nalgebra::{Point3, Vector3};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// A mechanism picture (same view as the diagrams).
pub struct MechanismPicture<'a> {
    /// The analysed design the mechanism moves.
    pub analysis: &'a Analysis,
    /// Its load factor and collapse mechanism.
    pub robustness: &'a Robustness,
    /// What the live load was, for the panel (e.g. "1 g horizontal at 90°").
    pub load: String,
    /// View azimuth from +x towards +y, degrees.
    pub azimuth_deg: f64,
    /// View elevation above the horizon, degrees.
    pub elevation_deg: f64,
    /// Picture size in pixels (width, height).
    pub size: (u32, u32),
}

impl<'a> MechanismPicture<'a> {
    /// The diagrams' default view (azimuth −60°, elevation 25°) at 1280 × 900 pixels.
    pub fn new(analysis: &'a Analysis, robustness: &'a Robustness, load: String) -> Self {
        Self { analysis, robustness, load, azimuth_deg: -60.0, elevation_deg: 25.0, size: (1280, 900) }
    }
}

/// Writes the mechanism picture to `path` (.png or .svg), atomically.
pub fn write_mechanism(p: &MechanismPicture, path: &Path) -> Result<(), PlotError> {
    super::write(p, path, p.size)
}

struct Face {
    depth: f64,
    points: Vec<(f64, f64)>,
    fill: RGBAColor,
    outline: RGBAColor,
}

impl MechanismPicture<'_> {
    /// Rest-state ghosts, then the displaced blocks and their moving interfaces, each sorted
    /// back to front.
    fn faces(&self, view: &View) -> Vec<Face> {
        let asm = &self.analysis.assembly;
        let mech = self.robustness.mechanism.as_ref();
        let scale = mech.and_then(|m| crate::viz::mechanism_scale(m, asm)).unwrap_or(0.0);
        let mut ghosts = Vec::new();
        let mut moved = Vec::new();
        for (i, block) in asm.blocks.iter().enumerate() {
            let rest = &block.mesh.vertices;
            let shifted = mech.map(|m| m.displaced(asm, BlockId(i), scale));
            let moving = mech.is_some_and(|m| m.moving.contains(&BlockId(i)));
            for face in &block.mesh.faces {
                let polygon = |pts: &[Point3<f64>]| -> (f64, Vec<(f64, f64)>) {
                    let c = Point3::from(face.iter().map(|&k| pts[k].coords).sum::<Vector3<f64>>() / face.len() as f64);
                    (view.depth(&c), face.iter().map(|&k| view.xy(&pts[k])).collect())
                };
                if moving {
                    let (depth, points) = polygon(shifted.as_deref().expect("moving"));
                    moved.push(Face {
                        depth,
                        points,
                        fill: super::rgb(colors::MOVED).mix(0.55),
                        outline: super::rgb([0.2, 0.2, 0.2]).mix(0.8),
                    });
                    let (depth, points) = polygon(rest);
                    ghosts.push(Face {
                        depth,
                        points,
                        fill: super::rgb([0.8, 0.8, 0.8]).mix(0.08),
                        outline: super::rgb([0.5, 0.5, 0.5]).mix(0.35),
                    });
                } else {
                    let (fill, alpha) =
                        if block.support { ([0.4, 0.4, 0.43], 0.45) } else { ([0.85, 0.82, 0.76], 0.3) };
                    let (depth, points) = polygon(rest);
                    let (fill, outline) = (super::rgb(fill).mix(alpha), super::rgb([0.25, 0.25, 0.25]).mix(0.5));
                    moved.push(Face { depth, points, fill, outline });
                }
            }
        }
        if let Some(m) = mech {
            for im in m.interfaces.iter().filter(|im| im.state != JointState::Closed) {
                let itf: &Interface = &self.analysis.interfaces[im.index];
                // Drawn on side b's displaced face: where the joint has moved to.
                let pts: Vec<Point3<f64>> =
                    itf.polygon.iter().map(|p| p + m.point_motion(asm, itf.b, p) * scale).collect();
                let c = Point3::from(pts.iter().map(|p| p.coords).sum::<Vector3<f64>>() / pts.len().max(1) as f64);
                moved.push(Face {
                    depth: view.depth(&c) + 1e-9 * asm.scale,
                    points: pts.iter().map(|p| view.xy(p)).collect(),
                    fill: rgba(colors::joint_state(im.state), 0.9),
                    outline: rgba(colors::joint_state(im.state), 1.0),
                });
            }
        }
        ghosts.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        moved.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        ghosts.extend(moved);
        ghosts
    }

    fn panel_lines(&self) -> Vec<String> {
        let r = self.robustness;
        let verdict = match r.safety {
            Safety::Collapses { load_factor } => format!("λ* = {load_factor:.4}"),
            Safety::Unlimited => "λ* = ∞ (never collapses)".into(),
            Safety::DoesNotStand { .. } => "DOES NOT STAND (dead load)".into(),
            Safety::SolverFailed { status, .. } => format!("solver: {status:?}"),
        };
        let mut lines = vec![self.analysis.assembly.name.clone(), self.load.clone(), String::new(), verdict];
        if let Some(m) = &r.mechanism {
            lines.push(format!("{} moving blocks", m.blocks.len()));
            for state in [JointState::Hinging, JointState::Opening, JointState::Sliding] {
                let n = m.interfaces.iter().filter(|i| i.state == state).count();
                lines.push(format!("{n} {}", format!("{state:?}").to_lowercase()));
            }
            lines.extend(m.uniqueness.label());
            lines.push(format!("motion × {:.0}% of size", 100.0 * crate::viz::EXAGGERATION));
        } else {
            lines.push("no mechanism".into());
        }
        lines
    }
}

impl Drawing for MechanismPicture<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let view = View::new(self.azimuth_deg, self.elevation_deg);
        let faces = self.faces(&view);
        let (w, h) = root.dim_in_pixel();
        let (panel, margin) = (300.0, 30.0);
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in faces.iter().flat_map(|f| f.points.iter()) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let scale = ((w as f64 - panel - 2.0 * margin) / (x1 - x0).max(1e-12))
            .min((h as f64 - 2.0 * margin) / (y1 - y0).max(1e-12));
        let (cx, cy) = (margin + (w as f64 - panel - 2.0 * margin) / 2.0, h as f64 / 2.0);
        let (mx, my) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let px = |(x, y): (f64, f64)| ((cx + (x - mx) * scale) as i32, (cy - (y - my) * scale) as i32);
        for f in &faces {
            let pts: Vec<(i32, i32)> = f.points.iter().map(|&q| px(q)).collect();
            root.draw(&Polygon::new(pts.clone(), f.fill.filled())).map_err(err)?;
            let mut closed = pts;
            closed.push(closed[0]);
            root.draw(&PathElement::new(closed, f.outline.stroke_width(1))).map_err(err)?;
        }
        let x = w as i32 - panel as i32 + 10;
        let font = ("sans-serif", 15).into_font();
        for (k, line) in self.panel_lines().iter().enumerate() {
            root.draw(&Text::new(line.clone(), (x, 20 + 24 * k as i32), font.clone())).map_err(err)?;
        }
        let y0 = 20 + 24 * 10;
        for (k, state) in [JointState::Hinging, JointState::Opening, JointState::Sliding].into_iter().enumerate() {
            let y = y0 + 26 * k as i32;
            root.draw(&Rectangle::new([(x, y), (x + 22, y + 16)], rgba(colors::joint_state(state), 1.0).filled()))
                .map_err(err)?;
            root.draw(&Text::new(format!("{state:?}").to_lowercase(), (x + 30, y), font.clone())).map_err(err)?;
        }
        root.present().map_err(err)?;
        Ok(())
    }
}

/// The polar plot of λ*(azimuth).
pub struct PolarPlot<'a> {
    /// The plot's title (the design's name).
    pub title: String,
    /// λ* per azimuth and the worst direction, marked.
    pub sweep: &'a DirectionSweep,
    /// Plot size in pixels (width, height).
    pub size: (u32, u32),
}

/// Writes the polar plot to `path` (.png or .svg), atomically.
pub fn write_polar(p: &PolarPlot, path: &Path) -> Result<(), PlotError> {
    super::write(p, path, p.size)
}

impl Drawing for PolarPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let s = self.sweep;
        let finite: Vec<f64> = s.load_factors.iter().copied().filter(|l| l.is_finite()).collect();
        let r_max = finite.iter().copied().fold(0.0, f64::max).max(1e-12) * 1.1;
        let caption = format!("{} — worst λ* = {:.4} at {:.1}°", self.title, s.worst_load_factor, s.worst_azimuth);
        let mut chart = ChartBuilder::on(&root)
            .caption(caption, ("sans-serif", 18))
            .margin(20)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(-r_max..r_max, -r_max..r_max)
            .map_err(err)?;
        chart.configure_mesh().disable_mesh().x_desc("λ* cos θ").y_desc("λ* sin θ").draw().map_err(err)?;
        let circle = |r: f64| {
            (0..=120).map(move |k| {
                let t = std::f64::consts::TAU * k as f64 / 120.0;
                (r * t.cos(), r * t.sin())
            })
        };
        for ring in 1..=4 {
            let r = r_max / 1.1 * ring as f64 / 4.0;
            chart.draw_series(LineSeries::new(circle(r), RGBColor(210, 210, 210))).map_err(err)?;
        }
        // The curve, closed; unlimited directions drawn at the rim.
        let mut pts: Vec<(f64, f64)> = s
            .azimuths
            .iter()
            .zip(&s.load_factors)
            .map(|(a, l)| {
                let r = if l.is_finite() { *l } else { r_max };
                let t = a.to_radians();
                (r * t.cos(), r * t.sin())
            })
            .collect();
        if let Some(&first) = pts.first() {
            pts.push(first);
        }
        chart.draw_series(LineSeries::new(pts.clone(), BLUE.stroke_width(2))).map_err(err)?;
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, BLUE.filled()))).map_err(err)?;
        let t = s.worst_azimuth.to_radians();
        let worst = (s.worst_load_factor * t.cos(), s.worst_load_factor * t.sin());
        chart.draw_series(LineSeries::new(vec![(0.0, 0.0), worst], RED.stroke_width(2))).map_err(err)?;
        chart.draw_series(std::iter::once(Circle::new(worst, 5, RED.filled()))).map_err(err)?;
        root.present().map_err(err)?;
        Ok(())
    }
}
