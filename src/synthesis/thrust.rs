//! Generate, strategy *thrust*: voussoir joints normal to the force that crosses them. The
//! candidate bed joints come from a direction field, as for [`super::courses`]; an analysis of
//! the coursed shape finds the resultant force at each bed, and the bed is turned normal to it,
//! pivoting at its centre of pressure (so the force crosses the joint with no friction to
//! carry); the turned shape is analysed again, until no bed turns by more than
//! [`ThrustSettings::settle_degrees`]. Head joints follow as for courses.
//!
//! When it fits: arches, vaults and buttresses whose thrust is inclined to the field's joints —
//! joints that carry their force square need no friction, the classical rule of stereotomy.
//! On a semicircular arch the joints come out near radial but not radial: the funicular of a
//! semicircle's own weight is not a semicircle (at an angle φ from the crown the force leans
//! atan(W(φ)/H), not φ), so a joint normal to it differs from the radius by several degrees
//! towards the springing. Where the load path is straight (walls, piers) use courses: the
//! beds are already normal to it.
//!
//! Units: metres, degrees in settings; the forces are the analysis' (N).

use super::DesignError;
use super::generate::{BlockSize, Field, candidate_beds, pieces, with_head_joints};
use super::generated::{Generated, ThrustRounds};
use crate::geometry::{Point3, Vector3};
use crate::history::CutCache;
use crate::model::{Cut, Scene};
use crate::pipeline::{Analysis, AnalysisSettings, Pipeline};

/// How the beds are turned; every default here once.
#[derive(Clone, Debug, PartialEq)]
pub struct ThrustSettings {
    /// Most rounds of analyse-and-turn.
    pub rounds: usize,
    /// Settled when no bed turns by more than this in a round, degrees.
    pub settle_degrees: f64,
    /// Largest turn of a bed away from the field's joint, degrees (a joint turned further
    /// would run into the neighbouring courses).
    pub max_turn_degrees: f64,
}

impl Default for ThrustSettings {
    fn default() -> Self {
        Self { rounds: 12, settle_degrees: 0.1, max_turn_degrees: 30.0 }
    }
}

impl ThrustSettings {
    /// Refuses zero rounds or angles out of range.
    pub fn validate(&self) -> Result<(), DesignError> {
        let bad = |what: String| Err(DesignError::Settings(what));
        if self.rounds == 0 {
            return bad("0 rounds: the thrust strategy needs at least one analysis".into());
        }
        if !(self.settle_degrees > 0.0 && self.settle_degrees.is_finite()) {
            return bad(format!("settle angle {}°: expected > 0", self.settle_degrees));
        }
        if !(0.0..90.0).contains(&self.max_turn_degrees) {
            return bad(format!("max turn {}°: expected 0 ≤ turn < 90°", self.max_turn_degrees));
        }
        Ok(())
    }
}

/// Cuts `shape` into courses whose beds are normal to the thrust (see the module docs).
pub fn thrust(
    shape: &Scene,
    field: &Field,
    size: &BlockSize,
    stagger: bool,
    settings: &ThrustSettings,
    analysis: &AnalysisSettings,
) -> Result<Generated, DesignError> {
    settings.validate()?;
    let (frame, l, beds) = candidate_beds(shape, field, size)?;
    let start: Vec<Bed> = beds.iter().map(|&t| Bed::of(frame.bed_plane(t))).collect();
    let mut current = start.clone();
    let mut pipeline = Pipeline::new();
    let expected = count_pieces(shape, &current)?;
    let tolerance = 1e-6 * shape.scale();
    let mut rounds = ThrustRounds {
        rounds: 0,
        last_turn_degrees: f64::INFINITY,
        settled: false,
        largest_turn_degrees: 0.0,
        held: 0,
    };
    while rounds.rounds < settings.rounds && !rounds.settled {
        let design = with_beds(shape, &current);
        let a = pipeline.run(&design, analysis)?;
        if a.statics.verdict == crate::statics::Verdict::Unsupported {
            return Err(DesignError::Settings(
                "the coursed shape touches no support (mark supports, or give it a ground plane): the thrust strategy turns joints to the forces an analysis finds".into(),
            ));
        }
        rounds.rounds += 1;
        let mut turned = Vec::with_capacity(current.len());
        let (mut largest, mut held) = (0.0f64, 0);
        for (k, (bed, field_bed)) in current.iter().zip(&start).enumerate() {
            let force = bed_force(&a, bed, tolerance).ok_or_else(|| {
                DesignError::Settings(format!(
                    "bed joint {k} carries no compression in the analysis: the thrust strategy cannot orient it"
                ))
            })?;
            let (next, was_held) = bed.turned_to(&force, field_bed, settings.max_turn_degrees.to_radians());
            largest = largest.max(bed.normal.angle(&next.normal).to_degrees());
            held += usize::from(was_held);
            turned.push(next);
        }
        rounds.last_turn_degrees = largest;
        rounds.held = held;
        rounds.settled = largest <= settings.settle_degrees;
        if !rounds.settled {
            let count = count_pieces(shape, &turned)?;
            if count != expected {
                return Err(DesignError::Settings(format!(
                    "turned normal to the thrust, the beds cut {count} pieces instead of {expected}: a joint runs into another course (lower --max-turn, or use courses)"
                )));
            }
            current = turned;
        }
    }
    rounds.largest_turn_degrees =
        current.iter().zip(&start).map(|(b, s)| b.normal.angle(&s.normal).to_degrees()).fold(0.0, f64::max);
    let cuts = current.iter().map(Bed::cut).collect();
    let mut generated = with_head_joints(shape, &frame, &beds, cuts, l, stagger)?;
    generated.rounds = Some(rounds);
    Ok(generated)
}

/// A bed joint: the plane through `point` with unit `normal` (pointing along the course
/// coordinate).
#[derive(Clone, Debug, PartialEq)]
struct Bed {
    point: Point3,
    normal: Vector3,
}

/// The force crossing a bed: the resultant on its upper side and its centre of pressure.
struct BedForce {
    resultant: Vector3,
    point: Point3,
}

impl Bed {
    fn of((point, normal): (Point3, Vector3)) -> Self {
        Self { point, normal }
    }

    fn cut(&self) -> Cut {
        Cut::plane(self.point.into(), self.normal.into())
    }

    /// The bed normal to `force` through its centre of pressure, held within `max_turn` of the
    /// field's bed (and whether it was held).
    fn turned_to(&self, force: &BedForce, field_bed: &Bed, max_turn: f64) -> (Bed, bool) {
        let wanted = force.resultant.normalize();
        let angle = field_bed.normal.angle(&wanted);
        let normal = if angle <= max_turn {
            wanted
        } else {
            let axis = field_bed.normal.cross(&wanted).normalize();
            nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_unchecked(axis), max_turn) * field_bed.normal
        };
        (Bed { point: force.point, normal }, angle > max_turn)
    }
}

/// The shape cut by the beds alone.
fn with_beds(shape: &Scene, beds: &[Bed]) -> Scene {
    let mut design = shape.clone();
    design.cuts.extend(beds.iter().map(Bed::cut));
    design
}

fn count_pieces(shape: &Scene, beds: &[Bed]) -> Result<usize, DesignError> {
    Ok(pieces(&with_beds(shape, beds), &mut CutCache::new())?.len())
}

/// The resultant over the interfaces lying in the bed's plane (oriented along its normal) and
/// their centre of pressure; `None` when they carry no compression.
fn bed_force(a: &Analysis, bed: &Bed, tolerance: f64) -> Option<BedForce> {
    let (mut resultant, mut moment, mut normal_force) = (Vector3::zeros(), Vector3::zeros(), 0.0);
    for r in &a.statics.interfaces {
        let itf = &a.interfaces[r.index];
        let along = itf.frame.n.dot(&bed.normal);
        let offset = (itf.centroid() - bed.point).dot(&bed.normal);
        if along.abs() < 1.0 - 1e-6 || offset.abs() > tolerance {
            continue;
        }
        let sign = along.signum();
        resultant += Vector3::from(r.resultant) * sign;
        if let Some(p) = r.resultant_point {
            moment += Vector3::from(p) * r.normal_force;
            normal_force += r.normal_force;
        }
    }
    (normal_force > 0.0 && resultant.dot(&bed.normal) > 0.0)
        .then(|| BedForce { resultant, point: Point3::from(moment / normal_force) })
}
