//! The interface diagrams of an analysis as a picture, without a window or GPU: an orthographic
//! view drawn through plotters in layers — translucent block faces back to front, then the
//! interfaces back to front over them (an X-ray: the diagram is what the picture is for, and an
//! interface lies on two block faces, so interleaving them by depth would cut it), then the
//! block edges —
//! interface polygons coloured per vertex (each triangle subdivided so the per-vertex colours
//! blend into the seed paper's per-face gradients), force arrows in vectors mode, mass centres,
//! and a text panel with the verdict and a colour legend. The 3D viewer draws the same colours
//! interactively; this is what CI and headless servers can render.

use super::{Drawing, PlotError, rgb};
use crate::pipeline::Analysis;
use crate::report::words::share_of_weight;
use crate::viz::colors::{self, Rgb};
use crate::viz::{DiagramMode, interface_triangles};
use nalgebra::{Point3, Vector3};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What to draw and from where.
pub struct DiagramPicture<'a> {
    /// The analysed design: its blocks, interfaces and forces.
    pub analysis: &'a Analysis,
    /// Which diagram colours the interfaces.
    pub mode: DiagramMode,
    /// View direction: azimuth from +x towards +y and elevation above the horizon, degrees.
    pub azimuth_deg: f64,
    /// Elevation of the view above the horizon, degrees.
    pub elevation_deg: f64,
    /// Picture size in pixels (width, height).
    pub size: (u32, u32),
    /// Fill the free blocks by density ([`colors::density`], lightest to densest) instead of
    /// translucent stone: an infill design.
    pub densities: bool,
}

impl<'a> DiagramPicture<'a> {
    /// The default view (azimuth −60°, elevation 25°, 1280 × 900 px); the blocks by density
    /// when their densities differ.
    pub fn new(analysis: &'a Analysis, mode: DiagramMode) -> Self {
        let mut p =
            Self { analysis, mode, azimuth_deg: -60.0, elevation_deg: 25.0, size: (1280, 900), densities: false };
        let (lo, hi) = p.density_range();
        p.densities = hi > lo * (1.0 + 1e-9);
        p
    }

    /// The free blocks' lightest and densest density, kg/m³.
    fn density_range(&self) -> (f64, f64) {
        let free = self.analysis.assembly.blocks.iter().filter(|b| !b.support);
        free.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| (lo.min(b.density), hi.max(b.density)))
    }
}

/// Writes the picture to `path` (.png or .svg), atomically.
pub fn write_diagram(p: &DiagramPicture, path: &Path) -> Result<(), PlotError> {
    super::write(p, path, p.size)
}

/// One filled polygon in view space, drawn in order of `depth` (far first).
struct Prim {
    depth: f64,
    points: Vec<(f64, f64)>,
    fill: RGBAColor,
    outline: Option<RGBAColor>,
}

/// A linear colour as the sRGB bytes a PNG holds: what the viewer shows of the same colour.
pub(super) fn rgba(c: Rgb, alpha: f64) -> RGBAColor {
    let [r, g, b] = crate::viz::colors::linear_to_srgb(c).map(|v| (v * 255.0).round() as u8);
    RGBAColor(r, g, b, alpha)
}

pub(super) struct View {
    right: Vector3<f64>,
    up: Vector3<f64>,
    toward_eye: Vector3<f64>,
}

impl View {
    pub(super) fn new(azimuth_deg: f64, elevation_deg: f64) -> Self {
        let (a, e) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        let toward_eye = Vector3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin());
        let right = Vector3::new(-a.sin(), a.cos(), 0.0);
        let up = toward_eye.cross(&right);
        Self { right, up, toward_eye }
    }
    pub(super) fn xy(&self, p: &Point3<f64>) -> (f64, f64) {
        (p.coords.dot(&self.right), p.coords.dot(&self.up))
    }
    pub(super) fn depth(&self, p: &Point3<f64>) -> f64 {
        p.coords.dot(&self.toward_eye)
    }
}

/// Subdivides triangle (a, b, c) with colours (ca, cb, cc) `levels` times (4^levels triangles),
/// each filled with the colour at its centre.
fn subdivide(view: &View, tri: [(Point3<f64>, Rgb); 3], levels: u32, out: &mut Vec<Prim>) {
    if levels == 0 {
        let centre = Point3::from((tri[0].0.coords + tri[1].0.coords + tri[2].0.coords) / 3.0);
        let colour = [0, 1, 2].map(|k| (tri[0].1[k] + tri[1].1[k] + tri[2].1[k]) / 3.0);
        out.push(Prim {
            depth: view.depth(&centre),
            points: tri.iter().map(|t| view.xy(&t.0)).collect(),
            fill: rgba(colour, 1.0),
            outline: None,
        });
        return;
    }
    let mid = |i: usize, j: usize| {
        (Point3::from((tri[i].0.coords + tri[j].0.coords) / 2.0), [0, 1, 2].map(|k| (tri[i].1[k] + tri[j].1[k]) / 2.0))
    };
    let (ab, bc, ca) = (mid(0, 1), mid(1, 2), mid(2, 0));
    for t in [[tri[0], ab, ca], [ab, tri[1], bc], [ca, bc, tri[2]], [ab, bc, ca]] {
        subdivide(view, t, levels - 1, out);
    }
}

impl DiagramPicture<'_> {
    /// Block faces and interface triangles, each layer sorted back to front.
    fn prims(&self, view: &View) -> (Vec<Prim>, Vec<Prim>) {
        let a = self.analysis;
        let mut prims = Vec::new();
        let stone: Rgb = [0.85, 0.82, 0.76];
        let (lo, hi) = self.density_range();
        for block in &a.assembly.blocks {
            let m = &block.mesh;
            let (fill, alpha) = match (block.support, self.densities) {
                (true, _) => ([0.4, 0.4, 0.43], 0.45),
                (false, true) => (colors::density(block.density, lo, hi), 0.55),
                (false, false) => (stone, 0.16),
            };
            for face in &m.faces {
                let pts: Vec<Point3<f64>> = face.iter().map(|&k| m.vertices[k]).collect();
                let centre = Point3::from(pts.iter().map(|p| p.coords).sum::<Vector3<f64>>() / pts.len() as f64);
                prims.push(Prim {
                    depth: view.depth(&centre),
                    points: pts.iter().map(|p| view.xy(p)).collect(),
                    fill: rgba(fill, alpha),
                    outline: Some(rgb([0.25, 0.25, 0.25]).mix(0.45)),
                });
            }
        }
        let mut faces = std::mem::take(&mut prims);
        faces.sort_by(|x, y| x.depth.total_cmp(&y.depth));
        // Few interfaces: finer gradients; many: coarser (the picture stays fast).
        let levels = if a.statics.interfaces.len() > 400 { 1 } else { 3 };
        for (_, _, tris) in interface_triangles(a, self.mode) {
            for t in tris {
                subdivide(view, t.map(|(p, c)| (Point3::from(p), c)), levels, &mut prims);
            }
        }
        prims.sort_by(|x, y| x.depth.total_cmp(&y.depth));
        (faces, prims)
    }
}

impl Drawing for DiagramPicture<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let a = self.analysis;
        let view = View::new(self.azimuth_deg, self.elevation_deg);
        let (faces, interfaces) = self.prims(&view);
        // Fit the projected assembly into the area left of the text panel.
        let (w, h) = root.dim_in_pixel();
        let (panel, margin) = (330.0, 30.0);
        let all = a.assembly.blocks.iter().flat_map(|b| b.mesh.vertices.iter()).map(|p| view.xy(p));
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for (x, y) in all {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let scale = ((w as f64 - panel - 2.0 * margin) / (x1 - x0).max(1e-12))
            .min((h as f64 - 2.0 * margin) / (y1 - y0).max(1e-12));
        let (cx, cy) = (margin + (w as f64 - panel - 2.0 * margin) / 2.0, h as f64 / 2.0);
        let (mx, my) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let px =
            |(x, y): (f64, f64)| -> (i32, i32) { ((cx + (x - mx) * scale) as i32, (cy - (y - my) * scale) as i32) };
        for p in faces.iter().chain(&interfaces) {
            let pts: Vec<(i32, i32)> = p.points.iter().map(|&q| px(q)).collect();
            root.draw(&Polygon::new(pts, p.fill.filled())).map_err(err)?;
        }
        for p in &faces {
            if let Some(o) = p.outline {
                let mut closed: Vec<(i32, i32)> = p.points.iter().map(|&q| px(q)).collect();
                closed.push(closed[0]);
                root.draw(&PathElement::new(closed, o.stroke_width(1))).map_err(err)?;
            }
        }
        // Mass centres of the free blocks.
        let dot = if a.assembly.blocks.len() > 100 { 2 } else { 3 };
        for b in a.assembly.blocks.iter().filter(|b| !b.support) {
            root.draw(&Circle::new(px(view.xy(&b.mass.centroid)), dot, BLACK.filled())).map_err(err)?;
        }
        if self.mode == DiagramMode::Vectors {
            let biggest = a.statics.interfaces.iter().map(|r| Vector3::from(r.resultant).norm()).fold(0.0, f64::max);
            let length = 0.15 * ((x1 - x0).max(y1 - y0));
            let arrow = RGBColor(0, 120, 70);
            for r in &a.statics.interfaces {
                let (Some(at), f) = (r.resultant_point, Vector3::from(r.resultant)) else { continue };
                if biggest <= 0.0 || f.norm() < 1e-3 * biggest {
                    continue;
                }
                let from = Point3::from(at);
                let to = from + f / biggest * length;
                let (p, q) = (px(view.xy(&from)), px(view.xy(&to)));
                root.draw(&PathElement::new(vec![p, q], arrow.stroke_width(2))).map_err(err)?;
                root.draw(&Circle::new(q, 3, arrow.filled())).map_err(err)?;
            }
        }
        self.panel(&root, w as i32 - panel as i32 + 10).map_err(err)?;
        root.present().map_err(err)?;
        Ok(())
    }
}

impl DiagramPicture<'_> {
    fn panel<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        x: i32,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let s = &self.analysis.statics;
        let font = ("sans-serif", 15).into_font();
        let title = ("sans-serif", 18).into_font();
        let mode = match self.mode {
            DiagramMode::Compression => "compression / tension".to_string(),
            DiagramMode::Friction { threshold } => format!("friction (yellow ≤ {threshold:.2} μ)"),
            DiagramMode::Vectors => "force vectors".to_string(),
        };
        let verdict = if s.stands { "STANDS" } else { "DOES NOT STAND" };
        let lines = [
            self.analysis.assembly.name.clone(),
            mode,
            String::new(),
            verdict.to_string(),
            format!("tension needed     {}", share_of_weight(s.tension_ratio)),
            format!("friction beyond μ  {}", share_of_weight(s.friction_excess_ratio)),
            format!("W = free weight    {}", crate::report::words::force(s.free_weight)),
            format!("largest use        {:.2} μN", s.max_friction_utilization),
            format!("{} blocks, {} interfaces", self.analysis.assembly.blocks.len(), s.interfaces.len()),
            format!("solve {:.1} ms", 1e3 * self.analysis.timings.solve),
        ];
        for (k, line) in lines.iter().enumerate() {
            let f = if k == 0 || k == 3 { title.clone() } else { font.clone() };
            let colour = if k == 3 { rgb(colors::stands_on_white(s.stands)) } else { BLACK };
            root.draw(&Text::new(line.clone(), (x, 20 + 24 * k as i32), f.color(&colour)))?;
        }
        let mut legend = crate::viz::legend(self.mode);
        if self.densities {
            let (lo, hi) = self.density_range();
            legend.push((colors::DENSITY_LOW, format!("lightest block {lo:.0} kg/m³")));
            legend.push((colors::DENSITY_HIGH, format!("densest block {hi:.0} kg/m³")));
        }
        let y0 = 20 + 24 * lines.len() as i32 + 20;
        for (k, (c, label)) in legend.iter().enumerate() {
            let y = y0 + 26 * k as i32;
            root.draw(&Rectangle::new([(x, y), (x + 22, y + 16)], rgba(*c, 1.0).filled()))?;
            root.draw(&Text::new(label.to_string(), (x + 30, y), font.clone()))?;
        }
        Ok(())
    }
}
