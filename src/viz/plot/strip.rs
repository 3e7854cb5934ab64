//! A drop test's motion as a strip of key frames: the blocks at evenly spaced times side by
//! side, one panel each, the same view and scale in every panel (so a block's fall reads across
//! the strip), each panel labelled with its time, supports grey, moving blocks by how far they
//! have moved. The picture beside the glTF animation for a report or a README.

use super::diagram::{View, rgba};
use super::{Drawing, PlotError};
use crate::dynamics::Trajectory;
use crate::model::Assembly;
use crate::viz::colors;
use nalgebra::{Point3, UnitQuaternion, Vector3};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// A key-frame strip of `trajectory` (same view as the diagrams).
pub struct FrameStrip<'a> {
    /// The design whose blocks move.
    pub assembly: &'a Assembly,
    /// The recorded poses (per block, per frame) and their times.
    pub trajectory: &'a Trajectory,
    /// Key frames drawn, the first and the last recorded included.
    pub frames: usize,
    /// View azimuth from +x towards +y, degrees.
    pub azimuth_deg: f64,
    /// View elevation above the horizon, degrees.
    pub elevation_deg: f64,
    /// Pixels of one panel.
    pub panel: (u32, u32),
    /// What the trajectory's times are.
    pub clock: Clock,
}

/// What a trajectory's times measure, for the panels' captions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// Simulated seconds (a drop test).
    Seconds,
    /// Fractions of the supports' path (a settlement).
    Path,
}

impl<'a> FrameStrip<'a> {
    /// Six key frames, the diagrams' view, 360 × 420 px panels, times in seconds.
    pub fn new(assembly: &'a Assembly, trajectory: &'a Trajectory) -> Self {
        Self {
            assembly,
            trajectory,
            frames: 6,
            azimuth_deg: -60.0,
            elevation_deg: 25.0,
            panel: (360, 420),
            clock: Clock::Seconds,
        }
    }

    /// The recorded frames drawn: `frames` evenly spaced indices, first and last included.
    pub fn key_frames(&self) -> Vec<usize> {
        let n = self.trajectory.times.len();
        let k = self.frames.clamp(1, n.max(1));
        let mut picked: Vec<usize> =
            (0..k).map(|j| if k == 1 { 0 } else { (j * (n - 1) + (k - 1) / 2) / (k - 1) }).collect();
        picked.dedup();
        picked
    }

    /// Block `i`'s vertices at frame `f`.
    fn placed(&self, i: usize, f: usize) -> Vec<Point3<f64>> {
        let block = &self.assembly.blocks[i];
        let (x, q) = self.trajectory.poses[f][i];
        let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
        let c = block.mass.centroid;
        block.mesh.vertices.iter().map(|p| x + q * (p - c)).collect()
    }
}

/// Writes the strip to `path` (.png or .svg), atomically.
pub fn write_strip(s: &FrameStrip, path: &Path) -> Result<(), PlotError> {
    let panels = s.key_frames().len().max(1) as u32;
    super::write(s, path, (s.panel.0 * panels, s.panel.1))
}

struct Face {
    depth: f64,
    points: Vec<(f64, f64)>,
    fill: RGBAColor,
}

impl FrameStrip<'_> {
    /// Frame `f`'s block faces in view space, back to front.
    fn faces(&self, view: &View, f: usize) -> Vec<Face> {
        let size = self.assembly.median_block_size().unwrap_or(1.0).max(f64::MIN_POSITIVE);
        let mut faces = Vec::new();
        for (i, block) in self.assembly.blocks.iter().enumerate() {
            let pts = self.placed(i, f);
            let moved = (self.trajectory.poses[f][i].0 - block.mass.centroid).norm() / size;
            let (fill, alpha) = if block.support {
                ([0.4, 0.4, 0.43], 0.55)
            } else {
                // Stone at rest, the mechanism's colour once it has moved a tenth of a block.
                let t = (moved / 0.1).min(1.0) as f32;
                let stone = [0.85, 0.82, 0.76];
                let mix = [0, 1, 2].map(|k| stone[k] * (1.0 - t) + colors::MOVED[k] * t);
                (mix, 0.7)
            };
            for face in &block.mesh.faces {
                let c = Point3::from(face.iter().map(|&k| pts[k].coords).sum::<Vector3<f64>>() / face.len() as f64);
                faces.push(Face {
                    depth: view.depth(&c),
                    points: face.iter().map(|&k| view.xy(&pts[k])).collect(),
                    fill: rgba(fill, alpha),
                });
            }
        }
        faces.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        faces
    }
}

impl Drawing for FrameStrip<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let view = View::new(self.azimuth_deg, self.elevation_deg);
        let keys = self.key_frames();
        let frames: Vec<Vec<Face>> = keys.iter().map(|&f| self.faces(&view, f)).collect();
        // One scale for every panel: the bounding box of all the key frames.
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in frames.iter().flatten().flat_map(|f| f.points.iter()) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let (pw, ph) = (self.panel.0 as f64, self.panel.1 as f64);
        let (margin, label) = (16.0, 40.0);
        let scale =
            ((pw - 2.0 * margin) / (x1 - x0).max(1e-12)).min((ph - 2.0 * margin - label) / (y1 - y0).max(1e-12));
        let (mx, my) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let outline = super::rgb([0.2, 0.2, 0.2]).mix(0.7);
        let font = ("sans-serif", 16).into_font();
        for (p, (faces, &f)) in frames.iter().zip(&keys).enumerate() {
            let (cx, cy) = (pw * (p as f64 + 0.5), label + (ph - label) / 2.0);
            let px = |(x, y): (f64, f64)| ((cx + (x - mx) * scale) as i32, (cy - (y - my) * scale) as i32);
            for face in faces {
                let pts: Vec<(i32, i32)> = face.points.iter().map(|&q| px(q)).collect();
                root.draw(&Polygon::new(pts.clone(), face.fill.filled())).map_err(err)?;
                let mut closed = pts;
                closed.push(closed[0]);
                root.draw(&PathElement::new(closed, outline.stroke_width(1))).map_err(err)?;
            }
            let x = (pw * p as f64) as i32;
            let t = self.trajectory.times[f];
            let text = match self.clock {
                Clock::Seconds => format!("t = {t:.2} s ({})", self.trajectory.engine),
                Clock::Path => format!("path {:.1} %", 100.0 * t),
            };
            root.draw(&Text::new(text, (x + 12, 12), font.clone())).map_err(err)?;
            if p > 0 {
                root.draw(&PathElement::new(vec![(x, 0), (x, ph as i32)], BLACK.mix(0.25).stroke_width(1)))
                    .map_err(err)?;
            }
        }
        root.present().map_err(err)?;
        Ok(())
    }
}
