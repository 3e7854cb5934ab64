//! `voussoir.report` and `Analysis._repr_html_`: the self-contained HTML report
//! (`voussoir report`'s page, one writer: [`voussoir::viz::html`]).

use crate::errors;
use crate::settings::solve_function;
use pyo3::prelude::*;
use std::path::PathBuf;
use voussoir::dynamics::DropSettings;
use voussoir::pipeline::analyze;
use voussoir::stability::{self, Question};
use voussoir::studies::settlement::SettleSettings;
use voussoir::viz::DiagramMode;
use voussoir::viz::html::HtmlReport;

/// The diagram shown first: `mode` by name ("compression", "friction", "vectors"), the friction
/// diagram's `threshold` (default: the library's).
pub fn diagram(mode: Option<&str>, threshold: Option<f64>) -> PyResult<DiagramMode> {
    let options = voussoir::cli::DiagramOptions {
        mode: match mode {
            Some(name) => crate::settings::choice::<voussoir::cli::Diagram>("mode", name)?,
            None => DiagramMode::default().into(),
        },
        threshold: threshold.unwrap_or(DiagramMode::DEFAULT_THRESHOLD),
    };
    options.mode().map_err(|e| errors::setting(e.0))
}

/// The page of an [`Analysis`](crate::analysis::Analysis) in an `<iframe srcdoc>`: the report's
/// script runs in its own document wherever a notebook puts the output.
pub fn iframe(html: &str) -> String {
    let escaped = html.replace('&', "&amp;").replace('"', "&quot;");
    format!(
        "<iframe srcdoc=\"{escaped}\" style=\"width: 100%; height: 760px; border: 0\" \
         title=\"voussoir report\"></iframe>"
    )
}

solve_function! {
    /// One self-contained HTML report (what `voussoir report` writes), returned as a str and
    /// written to `path` when given (atomically). `mode` and `threshold` choose the diagram shown
    /// first; `robustness` adds the load factor's collapse mechanism (of the live loads, or of 1 g
    /// along `direction`, or the worst of `directions` azimuths); `dynamic` the drop test
    /// (`engine`, `duration`); `settle` the quasi-static settlement on `moves` (as `--move`;
    /// default: the scene's movements).
    pub fn report<'py>(
        py, scene,
        path: Option<PathBuf> = None, mode: Option<String> = None, threshold: Option<f64> = None,
        robustness: bool = false, direction: Option<f64> = None, directions: Option<usize> = None,
        dynamic: bool = false, engine: Option<String> = None, duration: Option<f64> = None,
        settle: bool = false, moves: Option<Vec<String>> = None,
        ..options(mu, friction_model, solver, supports, ground, density, strength)
    ) -> PyResult<String> {
        let (mut design, settings) = options.apply(scene)?;
        let source = scene.source.as_str();
        let mode = diagram(mode.as_deref(), threshold)?;
        if let Some(list) = moves {
            design.movements = list.iter().map(|m| voussoir::model::Movement::parse(m)).collect::<Result<_, _>>()
                .map_err(|e| errors::input(source, e))?;
        }
        let defaults = DropSettings::default();
        let engine = engine.as_deref().map(|n| crate::settings::choice("engine", n)).transpose()?;
        let drop = DropSettings {
            engine: engine.unwrap_or(defaults.engine),
            duration: duration.unwrap_or(defaults.duration),
            friction: options.mu,
            ..defaults
        };
        let study = SettleSettings { friction: options.mu, strength: options.strength, engines: false,
            backend: settings.statics.backend, ..Default::default() };
        let html = py.detach(|| -> Result<String, String> {
            let analysis = analyze(&design, &settings).map_err(|e| e.to_string())?;
            let mut page = HtmlReport::new(&analysis, mode);
            if robustness {
                let question = Question::choose(&analysis, direction, directions);
                let answer = stability::answer(&analysis, &settings.statics, &question, &|_, _| {})
                    .map_err(|e| format!("robustness: {e}"))?;
                page.add_mechanism(&answer).map_err(|e| format!("robustness: {e}"))?;
            }
            if dynamic {
                let (d, motion) = voussoir::dynamics::record(&analysis.assembly, &drop, voussoir::viz::gltf::FRAMES_PER_SECOND).map_err(|e| e.to_string())?;
                page.add_drop(&d, &motion, &drop);
            }
            if settle {
                let result = voussoir::studies::settlement::settle(&analysis, &design.movements, &study)
                    .map_err(|e| format!("settle: {e}"))?;
                page.add_settlement(&result).map_err(|e| format!("settle: {e}"))?;
            }
            Ok(page.html())
        }).map_err(|e| errors::input(source, e))?;
        if let Some(path) = path {
            if voussoir::io::same_file(&path, std::path::Path::new(source)) {
                return Err(errors::input(source, format!("path {} would overwrite the scene's file", path.display())));
            }
            voussoir::io::write_atomic(&path, html.as_bytes()).map_err(errors::io)?;
        }
        Ok(html)
    }
}
