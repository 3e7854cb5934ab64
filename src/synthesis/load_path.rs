//! The load path, found: where to lay the bed joints of a shape given without hints.
//!
//! A shape's weight flows along its centre line: down a wall or a pier (horizontal beds), round
//! an arch or a barrel vault (beds through the axis its curved faces turn about). The second
//! is read from the shape itself: the curved faces of an arch are facets whose normals all pass
//! near one line — the centre of its intrados and extrados. [`fitted_axis`] finds that line by
//! least squares (the point nearest every face's normal line, in the plane across the axis)
//! and keeps it only when the faces really turn about it: normals in at least 8 directions
//! spread over at least a quarter turn, and the normal lines passing within 15 % of the
//! shape's size of it (a pointed arch's two centres are one axis between them). A
//! wall, a corbel or a letter has no such axis.
//!
//! [`found_courses`] then cuts courses across the path: horizontal beds first; when that design
//! does not stand and the shape turns about an axis, radial beds about it — whichever stands
//! (the horizontal one when neither does, with its verdict). Units: metres.

use super::DesignError;
use super::generate::{BlockSize, Field, courses};
use super::generated::Generated;
use crate::geometry::polygon::{area_vector, centroid};
use crate::geometry::{Point3, Vector3};
use crate::model::Scene;
use crate::pipeline::{AnalysisSettings, analyze};
use nalgebra::{Matrix2, Vector2};

/// Normals spread over less than this (radians) do not define an axis: a quarter turn.
const MIN_SPREAD: f64 = std::f64::consts::FRAC_PI_2;
/// The normal lines' RMS distance from the fitted axis, as a fraction of the shape's size,
/// above which the faces do not turn about one axis (a pointed arch's two centres, 0.1 of its
/// size apart, pass).
const MAX_SCATTER: f64 = 0.15;
/// Fewer distinct face directions (5° apart) than this are flat sides, not a curve: a box's
/// four normal lines all pass through its centre too.
const MIN_DIRECTIONS: usize = 8;
/// A face is across the axis when its normal is within this of perpendicular to it (cos).
const ACROSS: f64 = 0.05;

/// One face of the free shape: centroid, unit normal, area.
struct Facet {
    centroid: Point3,
    normal: Vector3,
    area: f64,
}

fn facets(shape: &Scene) -> Vec<Facet> {
    let mut out = Vec::new();
    for b in shape.blocks.iter().filter(|b| !b.support) {
        for f in 0..b.mesh.faces.len() {
            let pts: Vec<Point3> = b.mesh.face_points(f).collect();
            let a = area_vector(&pts);
            if a.norm() > 0.0 {
                out.push(Facet { centroid: centroid(&pts), normal: a.normalize(), area: a.norm() });
            }
        }
    }
    out
}

/// The radial field of a shape whose faces turn about one axis (module docs), if it has one.
pub fn fitted_axis(shape: &Scene) -> Option<Field> {
    let faces = facets(shape);
    let vertices: Vec<Point3> =
        shape.blocks.iter().filter(|b| !b.support).flat_map(|b| b.mesh.vertices.iter().copied()).collect();
    let size = crate::geometry::Aabb3::from_points(vertices.iter()).diagonal();
    [Vector3::x(), Vector3::y(), Vector3::z()]
        .into_iter()
        .filter_map(|axis| fit_about(&faces, &vertices, axis, size))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(field, _)| field)
}

/// The centre of the faces across `axis` (in the plane normal to it) and its scatter relative
/// to `size`, when they turn about it; moved back from the shape until every vertex lies within
/// a half-turn about it (radial beds through an axis cut only one side: a pointed arch's fitted
/// centre lies above its springings).
fn fit_about(faces: &[Facet], vertices: &[Point3], axis: Vector3, size: f64) -> Option<(Field, f64)> {
    let e1 = if axis.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let e1 = (e1 - axis * e1.dot(&axis)).normalize();
    let e2 = axis.cross(&e1);
    let across: Vec<&Facet> = faces.iter().filter(|f| f.normal.dot(&axis).abs() < ACROSS).collect();
    let angles: Vec<f64> = across.iter().map(|f| f.normal.dot(&e2).atan2(f.normal.dot(&e1))).collect();
    if distinct(&angles) < MIN_DIRECTIONS || spread(&angles) < MIN_SPREAD {
        return None;
    }
    // The point c minimising Σ A |(I − n nᵀ)(c − p)|² in the plane: Σ A (I − n nᵀ) c = Σ A (I − n nᵀ) p.
    let (mut m, mut r) = (Matrix2::zeros(), Vector2::zeros());
    for f in &across {
        let n = Vector2::new(f.normal.dot(&e1), f.normal.dot(&e2));
        let p = Vector2::new(f.centroid.coords.dot(&e1), f.centroid.coords.dot(&e2));
        let proj = (Matrix2::identity() - n * n.transpose()) * f.area;
        m += proj;
        r += proj * p;
    }
    let c = m.try_inverse()? * r;
    let total: f64 = across.iter().map(|f| f.area).sum();
    let scatter = across
        .iter()
        .map(|f| {
            let n = Vector2::new(f.normal.dot(&e1), f.normal.dot(&e2));
            let d = Vector2::new(f.centroid.coords.dot(&e1), f.centroid.coords.dot(&e2)) - c;
            f.area * (d - n * n.dot(&d)).norm_squared()
        })
        .sum::<f64>()
        / total;
    let scatter = scatter.sqrt() / size;
    if scatter > MAX_SCATTER {
        return None;
    }
    let plane = |p: &Point3| Vector2::new(p.coords.dot(&e1), p.coords.dot(&e2));
    let mean = vertices.iter().map(&plane).sum::<Vector2<f64>>() / vertices.len() as f64;
    let towards = (mean - c).try_normalize(f64::MIN_POSITIVE)?;
    let behind = vertices.iter().map(|p| -(plane(p) - c).dot(&towards)).fold(0.0, f64::max);
    let c = c - towards * behind;
    let center = e1 * c.x + e2 * c.y;
    Some((Field::Radial { center: [center.x, center.y, center.z], axis: [axis.x, axis.y, axis.z] }, scatter))
}

/// How many directions 5° apart `angles` (radians) hold.
fn distinct(angles: &[f64]) -> usize {
    let step = 5f64.to_radians();
    let mut bins: Vec<i64> = angles.iter().map(|a| (a / step).round() as i64).collect();
    bins.sort_unstable();
    bins.dedup();
    bins.len()
}

/// The largest angle between normals in a set of directions (radians, at most π): the circle
/// less its largest gap.
fn spread(angles: &[f64]) -> f64 {
    let mut a: Vec<f64> = angles.to_vec();
    a.sort_by(f64::total_cmp);
    let gaps = a.windows(2).map(|w| w[1] - w[0]);
    let wrap = a.first().zip(a.last()).map_or(0.0, |(lo, hi)| lo + std::f64::consts::TAU - hi);
    let largest = gaps.fold(wrap, f64::max);
    (std::f64::consts::TAU - largest).min(std::f64::consts::PI)
}

/// Courses across the load path found (module docs): the design, the field it was cut along,
/// and whether it stands.
pub fn found_courses(
    shape: &Scene,
    size: &BlockSize,
    stagger: bool,
    settings: &AnalysisSettings,
) -> Result<(Generated, Field), DesignError> {
    let vertical = courses(shape, &Field::Vertical, size, stagger);
    if let Ok(g) = &vertical
        && analyze(&g.design, settings)?.statics.stands
    {
        return Ok((vertical?, Field::Vertical));
    }
    let Some(field) = fitted_axis(shape) else { return Ok((vertical?, Field::Vertical)) };
    match courses(shape, &field, size, stagger) {
        Ok(g) if vertical.is_err() || analyze(&g.design, settings)?.statics.stands => Ok((g, field)),
        _ => Ok((vertical?, Field::Vertical)),
    }
}
