//! Automatic design from Python: `repair` (move and turn a design's cuts until it stands, then
//! stands most safely), `infill` (per-block or per-cell densities that make it stand) and `decompose` (a cut history for a source shape, by courses or with
//! the beds normal to the thrust) — the library's `design` stages with Python's arguments;
//! solves run with the GIL released.

use crate::errors;
use crate::scene::Scene;
use crate::settings::solve_function;
use crate::tasks::json_to_python;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use voussoir::synthesis::{self, BlockSize, Field, InfillObjective, InfillSettings, RepairSettings, ThrustSettings};

solve_function! {
    /// Moves and turns the cuts of `scene` (all, or the indices in `cuts`) until it stands and, with
    /// `robust`, until its worst-direction horizontal load factor is largest (`voussoir repair`).
    /// Returns the repaired design and the report as a dict (`voussoir repair --json`): `outcome`,
    /// `before` / `after` scores, `load_factor_before` / `_after`, `changed` cuts, `history`,
    /// `failing` interfaces and a proposed `support` when it still fails. The same `seed` gives
    /// the same design.
    pub fn repair<'py>(
        py, scene,
        cuts: Option<Vec<usize>> = None, max_turn: Option<f64> = None, robust: bool = true, seed: Option<u64> = None,
        particles: Option<usize> = None, iterations: Option<u64> = None,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<(Scene, Bound<'py, PyAny>)> {
        let (design, settings) = options.apply(scene)?;
        let d = RepairSettings::default();
        let repair = RepairSettings {
            cuts,
            max_turn_degrees: max_turn.unwrap_or(d.max_turn_degrees),
            robust,
            seed: seed.unwrap_or(d.seed),
            particles: particles.unwrap_or(d.particles),
            iterations: iterations.unwrap_or(d.iterations),
            ..d
        };
        let source = scene.source.as_str();
        let report = py
            .detach(|| synthesis::repair(&design, &settings, &repair, &|_, _, _| {}).map_err(|e| e.to_string()))
            .map_err(|e| errors::input(source, e))?;
        let text = serde_json::to_string(&report).map_err(errors::setting)?;
        Ok((scene.edited(report.design), json_to_python(py, &text)?))
    }
}

solve_function! {
    /// A cut history for the source shape `scene` (no history yet; `voussoir decompose`): about
    /// `blocks` blocks or none larger than `max_size` (m); beds horizontal, or through the axis
    /// `center` + s·`axis` (default axis +y) for arches and vaults; `strategy` "courses",
    /// "thrust" (beds turned normal to the force an analysis finds crossing them) or "pattern" (a
    /// running bond on the outer surface extruded to `apex`: every joint through it); head joints
    /// staggered unless `stagger` is false. Returns the design and a dict: `courses`, `pieces`,
    /// `max_size` and, for "thrust", `rounds` (analyses, settled, last and largest turn in degrees).
    pub fn decompose<'py>(
        py, scene,
        blocks: Option<usize> = None, max_size: Option<f64> = None, strategy: &str = "courses",
        center: Option<[f64; 3]> = None, axis: Option<[f64; 3]> = None, stagger: bool = true,
        apex: Option<[f64; 3]> = None,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<(Scene, Bound<'py, PyDict>)> {
        let size = match (blocks, max_size) {
            (Some(n), None) => BlockSize::Count(n),
            (None, Some(l)) => BlockSize::Max(l),
            _ => return Err(errors::setting("decompose: give exactly one of blocks and max_size")),
        };
        // No center: the load path is found (horizontal beds, or radial about the fitted axis).
        let field = match (center, axis) {
            (Some(center), axis) => Some(Field::Radial { center, axis: axis.unwrap_or([0.0, 1.0, 0.0]) }),
            (None, None) => None,
            (None, Some(_)) => return Err(errors::setting("decompose: axis needs center (a point on it)")),
        };
        let (thrust, pattern) = match (strategy, apex) {
            ("courses", _) => (false, None),
            ("thrust", _) => (true, None),
            ("pattern", Some(apex)) => (false, Some(apex)),
            ("pattern", None) => return Err(errors::setting("decompose: strategy \"pattern\" needs apex")),
            (other, _) => {
                return Err(errors::setting(format!(
                    "strategy: '{other}' is none of \"courses\", \"thrust\" and \"pattern\""
                )));
            }
        };
        let (shape, settings) = options.apply(scene)?;
        let source = scene.source.as_str();
        let generated = py
            .detach(|| {
                match (pattern, thrust, &field) {
                    (Some(apex), _, _) => synthesis::pattern(&shape, apex, &size, stagger),
                    (None, true, f) => {
                        let f = f.unwrap_or(Field::Vertical);
                        synthesis::thrust(&shape, &f, &size, stagger, &ThrustSettings::default(), &settings)
                    }
                    (None, false, Some(f)) => synthesis::courses(&shape, f, &size, stagger),
                    (None, false, None) => synthesis::found_courses(&shape, &size, stagger, &settings).map(|(g, _)| g),
                }
                .map_err(|e| e.to_string())
            })
            .map_err(|e| errors::input(source, e))?;
        let out = PyDict::new(py);
        out.set_item("courses", generated.courses)?;
        out.set_item("pieces", generated.pieces)?;
        out.set_item("max_size", generated.max_size)?;
        let rounds = match &generated.rounds {
            Some(r) => Some(json_to_python(py, &serde_json::to_string(r).map_err(errors::setting)?)?),
            None => None,
        };
        out.set_item("rounds", rounds)?;
        Ok((scene.edited(generated.design), out))
    }
}

solve_function! {
    /// Densities within `density_range` (kg/m³; default: from a quarter of each block's density to
    /// it) that make `scene` stand (`voussoir infill`): `objective` "stand" (the lightest) or
    /// "robust" (the largest horizontal load carried: along `azimuth`, else `directions` azimuths;
    /// the scene's live loads when it has some); `cells` per axis of each block's box, each with
    /// its own density. Returns the infilled design (None when no density holds it) and the
    /// report as a dict (`infill --json`): `outcome`, `blocks`, masses, verdicts, `load_factor`,
    /// and when impossible the `mechanism` every admissible mass drives.
    pub fn infill<'py>(
        py, scene,
        density_range: Option<(f64, f64)> = None, objective: &str = "stand", cells: Option<usize> = None,
        azimuth: Option<f64> = None, directions: Option<usize> = None,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<(Option<Scene>, Bound<'py, PyAny>)> {
        let objective = match objective {
            "stand" => InfillObjective::Stand,
            "robust" => InfillObjective::Robust,
            other => return Err(errors::setting(format!("objective: '{other}' is neither \"stand\" nor \"robust\""))),
        };
        let d = InfillSettings::default();
        let infill = InfillSettings {
            range: density_range,
            objective,
            cells: cells.unwrap_or(d.cells),
            azimuth,
            directions: directions.unwrap_or(d.directions),
            ..d
        };
        let (design, settings) = options.apply(scene)?;
        let source = scene.source.as_str();
        let mut report = py
            .detach(|| synthesis::infill(&design, &settings, &infill).map_err(|e| e.to_string()))
            .map_err(|e| errors::input(source, e))?;
        let text = serde_json::to_string(&report).map_err(errors::setting)?;
        Ok((report.design.take().map(|d| scene.edited(d)), json_to_python(py, &text)?))
    }
}
