//! The other stages: interfaces alone, the load factor, an assembly sequence and the drop test.
//! Their reports are the command line's JSON reports as dicts (one schema for both); solves
//! run with the GIL released.

use crate::arrays::rows;
use crate::errors;
use crate::settings::solve_function;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use voussoir::dynamics::{DropSettings, Engine, ExactSettings};
use voussoir::interfaces::Body;
use voussoir::model::Assembly;
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::report::stability as stability_report;
use voussoir::stability::{self, Question};
use voussoir::studies::sequence::{self as assembly_sequence, OrderSpec, SearchSettings, StepChecks};

/// The validated blocks of `design` (its cut history replayed), or the error's message.
fn assembly_of(design: &voussoir::model::Scene, settings: &AnalysisSettings) -> Result<Assembly, String> {
    let (resolved, _) =
        voussoir::history::resolve(design, &settings.tolerances, &mut Default::default()).map_err(|e| e.to_string())?;
    Assembly::new(&resolved, &settings.tolerances).map_err(|e| e.to_string())
}

pub(crate) fn json_to_python<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// Analyses `design` with the GIL released and turns the analysis into a JSON report with
/// `report`; a failure of either is an input error naming `source`; the report comes back as a
/// dict.
fn analyzed_json<'py>(
    py: Python<'py>,
    source: &str,
    design: &voussoir::model::Scene,
    settings: &AnalysisSettings,
    report: impl FnOnce(&voussoir::pipeline::Analysis) -> Result<String, String> + Send,
) -> PyResult<Bound<'py, PyAny>> {
    let text = py
        .detach(|| report(&analyze(design, settings).map_err(|e| e.to_string())?))
        .map_err(|e: String| errors::input(source, e))?;
    json_to_python(py, &text)
}

solve_function! {
    /// Interfaces of `scene` (its cut history replayed) without solving anything: a dict with
    /// `block_names`, `blocks` (m, 2; -1 the ground), `area` (m,), `centroid`, `normal`, `u`, `v`
    /// (m, 3) and `polygons` (m arrays of (k, 3), counter-clockwise about the normal).
    pub fn detect_interfaces<'py>(py, scene, ..options(supports, ground)) -> PyResult<Bound<'py, PyDict>> {
        let (design, settings) = options.apply(scene)?;
        let source = scene.source.as_str();
        let (assembly, interfaces) = py
            .detach(|| {
                let assembly = assembly_of(&design, &settings)?;
                let interfaces = voussoir::interfaces::detect(&assembly);
                Ok((assembly, interfaces))
            })
            .map_err(|e: String| errors::input(source, e))?;
        let index = |b: Body| b.block().map_or(-1, |id| id.0 as i64);
        let out = PyDict::new(py);
        out.set_item("block_names", assembly.blocks.iter().map(|b| b.name.clone()).collect::<Vec<_>>())?;
        out.set_item("blocks", rows(py, &interfaces.iter().map(|i| [index(i.a), index(i.b)]).collect::<Vec<_>>())?)?;
        out.set_item("area", interfaces.iter().map(|i| i.area).collect::<Vec<_>>())?;
        let frames = |f: fn(&voussoir::interfaces::Interface) -> [f64; 3]| interfaces.iter().map(f).collect::<Vec<_>>();
        out.set_item("centroid", rows(py, &frames(|i| i.frame.origin.into()))?)?;
        out.set_item("normal", rows(py, &frames(|i| i.frame.n.into()))?)?;
        out.set_item("u", rows(py, &frames(|i| i.frame.u.into()))?)?;
        out.set_item("v", rows(py, &frames(|i| i.frame.v.into()))?)?;
        let polygons = PyList::empty(py);
        for i in &interfaces {
            let corners: Vec<[f64; 3]> = i.polygon.iter().map(|p| (*p).into()).collect();
            polygons.append(rows(py, &corners)?)?;
        }
        out.set_item("polygons", polygons)?;
        Ok(out)
    }
}

solve_function! {
    /// The load factor λ* (`voussoir robustness --json` as a dict): of the scene's live loads, of
    /// a horizontal 1 g along `direction` (degrees from +x towards +y), or — the default with no
    /// live load — in the worst horizontal direction over `directions` azimuths.
    pub fn load_factor<'py>(
        py, scene,
        direction: Option<f64> = None, directions: Option<usize> = None,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<Bound<'py, PyAny>> {
        let (design, settings) = options.apply(scene)?;
        analyzed_json(py, &scene.source, &design, &settings, |analysis| {
            let question = Question::choose(analysis, direction, directions);
            let answer =
                stability::answer(analysis, &settings.statics, &question, &|_, _| {}).map_err(|e| e.to_string())?;
            Ok(stability_report::to_json(analysis, &answer.result, answer.sweep.as_ref(), &answer.load))
        })
    }
}

solve_function! {
    /// How precisely the design must be cut (`voussoir analyze --tolerance`, its `tolerance`
    /// object as a dict): the largest shrink of every joint (m) and tilt of every joint plane
    /// (degrees) for which it still stands, each relative and with the joint that governs.
    pub fn tolerance<'py>(
        py, scene,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<Bound<'py, PyAny>> {
        let (design, settings) = options.apply(scene)?;
        analyzed_json(py, &scene.source, &design, &settings, |analysis| {
            let margins = stability::tolerance::margins(analysis, &settings.statics, &Default::default())
                .map_err(|e| e.to_string())?;
            serde_json::to_string(&margins).map_err(|e| e.to_string())
        })
    }
}

solve_function! {
    /// The design on supports that move (`voussoir settle --json` as a dict): `moves` as the
    /// command line's `--move` ("NAME:dx,dy,dz[:rx,ry,rz]", model units and degrees; default:
    /// the scene's `movements`), followed quasi-statically in `increments`, and unless
    /// `quasi_static` also in the exact-contact engine and rapier.
    pub fn settle<'py>(
        py, scene,
        moves: Option<Vec<String>> = None, increments: Option<usize> = None, quasi_static: bool = false,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<Bound<'py, PyAny>> {
        let (design, settings) = options.apply(scene)?;
        let source = scene.source.as_str();
        let movements = match moves {
            Some(list) => list.iter().map(|m| voussoir::model::Movement::parse(m)).collect::<Result<Vec<_>, _>>()
                .map_err(|e| errors::input(source, e))?,
            None => design.movements.clone(),
        };
        let defaults = voussoir::studies::settlement::SettleSettings::default();
        let study = voussoir::studies::settlement::SettleSettings {
            increments: increments.unwrap_or(defaults.increments),
            friction: options.mu,
            strength: options.strength,
            engines: !quasi_static,
            backend: settings.statics.backend,
            ..defaults
        };
        analyzed_json(py, source, &design, &settings, |analysis| {
            let result = voussoir::studies::settlement::settle(analysis, &movements, &study).map_err(|e| e.to_string())?;
            serde_json::to_string(&result).map_err(|e| e.to_string())
        })
    }
}

/// `order`: "bottom-up", "from-supports", or a list of block names.
#[derive(FromPyObject)]
pub enum Order {
    Named(String),
    Given(Vec<String>),
}

solve_function! {
    /// Checks every step of an assembly order (`voussoir sequence --json` as a dict). `order`:
    /// "bottom-up", "from-supports" or a list of names (default: the scene's own order, else
    /// bottom-up); `props`: temporary supports where a step would not stand; `search`: look for an
    /// order in which every step stands; `dynamic` / `kinematic`: those checks at every step too.
    pub fn sequence<'py>(
        py, scene,
        order: Option<Order> = None, props: bool = false, search: bool = false, dynamic: bool = false,
        kinematic: bool = false,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<Bound<'py, PyAny>> {
        let (design, settings) = options.apply(scene)?;
        let spec = match order {
            Some(Order::Named(n)) if n == "bottom-up" => OrderSpec::BottomUp,
            Some(Order::Named(n)) if n == "from-supports" => OrderSpec::FromSupports,
            Some(Order::Named(n)) => {
                return Err(errors::setting(format!(
                    "order: '{n}' is neither \"bottom-up\", \"from-supports\" nor a list of block names"
                )));
            }
            Some(Order::Given(names)) => OrderSpec::Given(names),
            None if !design.order.is_empty() => OrderSpec::Given(design.order.clone()),
            None => OrderSpec::BottomUp,
        };
        let per_step = StepChecks {
            dynamic: dynamic.then(|| DropSettings { friction: options.mu, ..Default::default() }),
            kinematic: kinematic.then(Default::default),
        };
        let source = scene.source.as_str();
        let text = py
            .detach(|| {
                let search_settings = SearchSettings::default();
                let report = if search {
                    assembly_sequence::search(&design, &settings, &search_settings, &per_step, &|| {})
                } else if props {
                    assembly_sequence::check_with_props(&design, &spec, &settings, &search_settings, &per_step, &|| {})
                } else {
                    assembly_sequence::check(&design, &spec, &settings, &per_step, &|| {})
                };
                report.map(|r| serde_json::to_string(&r).unwrap_or_default()).map_err(|e| e.to_string())
            })
            .map_err(|e: String| errors::input(source, e))?;
        json_to_python(py, &text)
    }
}

solve_function! {
    /// The drop test (`voussoir drop --json`'s `dynamic` part as a dict): the blocks released
    /// under gravity for `duration` s with step `dt` (the library's defaults when None), on
    /// `engine` "rapier" (the default) or "exact" (hard contacts with the statics' friction
    /// model and solver; its account under "exact": solves, status, overlap, energy balance).
    /// `split_impacts` (exact engine; default True) splits a step at an impact's instant;
    /// `rest_when_admissible` (default False) keeps a design at rest where an equilibrium holds
    /// it; `floor` (default True) puts a floor under a design with supports and no ground;
    /// `by_states` (default True) takes a moving step first by its contacts' last states, False
    /// solves every step by the Tresca rounds (the same answer, to cross-check).
    pub fn drop<'py>(
        py, scene,
        duration: Option<f64> = None, dt: Option<f64> = None, engine: Option<String> = None,
        split_impacts: Option<bool> = None, rest_when_admissible: Option<bool> = None,
        floor: Option<bool> = None, by_states: Option<bool> = None,
        ..options(mu, friction_model, solver, supports, ground, density)
    ) -> PyResult<Bound<'py, PyAny>> {
        let (design, settings) = options.apply(scene)?;
        let defaults = DropSettings::default();
        let engine = engine.as_deref().map(|n| crate::settings::choice::<Engine>("engine", n)).transpose()?;
        let drop_settings = DropSettings {
            engine: engine.unwrap_or(defaults.engine),
            exact: ExactSettings {
                friction_model: settings.statics.friction_model,
                backend: settings.statics.backend,
                split_impacts: split_impacts.unwrap_or(defaults.exact.split_impacts),
                rest_when_admissible: rest_when_admissible.unwrap_or(defaults.exact.rest_when_admissible),
                by_states: by_states.unwrap_or(defaults.exact.by_states),
                ..defaults.exact.clone()
            },
            duration: duration.unwrap_or(defaults.duration),
            dt: dt.unwrap_or(defaults.dt),
            friction: options.mu,
            floor: floor.unwrap_or(defaults.floor),
            ..defaults
        };
        let source = scene.source.as_str();
        let text = py
            .detach(|| {
                let assembly = assembly_of(&design, &settings)?;
                let result = voussoir::dynamics::drop_test(&assembly, &drop_settings).map_err(|e| e.to_string())?;
                Ok(serde_json::to_string(&result).unwrap_or_default())
            })
            .map_err(|e: String| errors::input(source, e))?;
        json_to_python(py, &text)
    }
}

solve_function! {
    /// The design on a shaking ground (`voussoir shake --json` as a dict): `pulse`
    /// ("rect:AMP_G,DURATION_S", "sine:…", "ricker:…"), `sine` ("AMP_G,PERIOD_S,CYCLES") or
    /// `record` (an .AT2 or .csv path, "builtin:elcentro", "builtin:synthetic?seed=N&pga=G&duration=S"),
    /// else the scene's `ground_motion`; times `scale`, along `direction` (degrees from +x), on
    /// `engine` "exact" (the default), "rapier" or "both", for `duration` s (default: the
    /// motion's end and time for what it set going to land) at step `dt`. Beside the static
    /// load factor `static_load_factor` (g), each of `runs` has `collapsed`, `collapse_time_s`,
    /// `result` (every block's largest rotation, drift, residual displacement) and `trace`
    /// with numpy arrays `times` (s), `ground_g`, `rotation` (rad, the largest of a block) and
    /// `drift` (a fraction of the block's size), one sample per step. `shake_supports` names
    /// the supports to move alone (default: every support and the floor, as one base).
    pub fn shake<'py>(
        py, scene,
        pulse: Option<String> = None, sine: Option<String> = None, record: Option<String> = None,
        scale: f64 = 1.0, direction: f64 = 0.0, engine: Option<String> = None,
        duration: Option<f64> = None, dt: Option<f64> = None, shake_supports: Option<Vec<String>> = None,
        ..options(mu, friction_model, solver, supports, ground, density)
    ) -> PyResult<Bound<'py, PyAny>> {
        use voussoir::studies::shake::{ShakeSettings, shake_study};
        let (design, settings) = options.apply(scene)?;
        let source = scene.source.as_str();
        let supports = shake_supports.unwrap_or_default();
        let named = voussoir::io::accelerogram::NamedMotion {
            pulse: pulse.as_deref(),
            sine: sine.as_deref(),
            record: record.as_deref(),
            scale,
            direction,
            supports: &supports,
        };
        let (motion, _) = voussoir::io::accelerogram::named_motion(&named, &design, std::path::Path::new(source), "")
            .map_err(|e| errors::input(source, e))?;
        let engines = match engine.as_deref() {
            None | Some("exact") => vec![Engine::Exact],
            Some("rapier") => vec![Engine::Rapier],
            Some("both") => vec![Engine::Exact, Engine::Rapier],
            Some(other) => {
                return Err(errors::setting(format!("engine: '{other}' is neither \"exact\", \"rapier\" nor \"both\"")));
            }
        };
        let mut study = ShakeSettings { duration, ..ShakeSettings::default() };
        study.drop.dt = dt.unwrap_or(study.drop.dt);
        study.drop.friction = options.mu;
        (study.drop.exact.friction_model, study.drop.exact.backend) =
            (settings.statics.friction_model, settings.statics.backend);
        let statics = settings.statics.clone();
        let report = py
            .detach(|| {
                let analysis = analyze(&design, &settings).map_err(|e| e.to_string())?;
                if !analysis.statics.stands {
                    return Err("does not stand as drawn (the statics): nothing to shake".to_string());
                }
                shake_study(&analysis, &statics, &motion, &study, &engines, None).map_err(|e| e.to_string())
            })
            .map_err(|e: String| errors::input(source, e))?;
        let out = json_to_python(py, &serde_json::to_string(&report).unwrap_or_default())?;
        let runs = out.get_item("runs")?;
        for (k, run) in report.runs.iter().enumerate() {
            let trace = runs.get_item(k)?.get_item("trace")?;
            let t = &run.trace;
            for (key, values) in [("times", &t.times), ("ground_g", &t.ground_g), ("rotation", &t.rotation), ("drift", &t.drift)] {
                trace.set_item(key, crate::arrays::vector(py, values.clone()))?;
            }
        }
        Ok(out)
    }
}
