//! The keyword arguments every solving function shares, and the one place they become the
//! library's settings and amend the scene (as the command line's options do). `None` keeps the
//! library's default (each written once, in its `Default`).

use crate::errors;
use clap::ValueEnum;
use pyo3::prelude::*;
use voussoir::model::{Scene, SupportChoice};
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::{Backend, FrictionModel};

/// `supports=`: `"lowest"`, or the names of the blocks that are supports.
#[derive(FromPyObject)]
pub enum Supports {
    Keyword(String),
    Names(Vec<String>),
}

impl Supports {
    /// The library's support choice.
    pub fn choice(&self) -> PyResult<SupportChoice> {
        match self {
            Supports::Keyword(k) if k == "lowest" => Ok(SupportChoice::Lowest),
            Supports::Keyword(k) => {
                Err(errors::setting(format!("supports: '{k}' is neither \"lowest\" nor a list of block names")))
            }
            Supports::Names(names) => Ok(SupportChoice::Named(names.clone())),
        }
    }
}

/// The shared keyword arguments, as Python passed them.
pub struct Options {
    pub mu: Option<f64>,
    pub friction_model: Option<String>,
    pub solver: Option<String>,
    pub supports: Option<Supports>,
    pub ground: Option<bool>,
    pub density: Option<f64>,
    pub strict: bool,
}

/// A value of one of the library's named choices (`friction_model="pyramid8"`), by the names
/// the command line takes.
fn choice<T: ValueEnum>(what: &str, name: &str) -> PyResult<T> {
    T::from_str(name, true).map_err(|_| {
        let names: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|p| p.get_name().to_string())
            .collect();
        errors::setting(format!("{what}: '{name}' is not one of {}", names.join(", ")))
    })
}

impl Options {
    /// The analysis settings: the library's defaults with these options.
    pub fn settings(&self) -> PyResult<AnalysisSettings> {
        let mut settings = AnalysisSettings::default();
        if let Some(name) = &self.friction_model {
            settings.statics.friction_model = choice::<FrictionModel>("friction_model", name)?;
        }
        if let Some(name) = &self.solver {
            settings.statics.backend = choice::<Backend>("solver", name)?;
        }
        settings.statics.friction = self.mu;
        settings.strict = self.strict;
        Ok(settings)
    }

    /// `scene` amended by `supports`, `ground` and `density` (a copy; the caller's is kept).
    pub fn amend(&self, scene: &Scene, source: &str, settings: &AnalysisSettings) -> PyResult<Scene> {
        let mut scene = scene.clone();
        if let Some(d) = self.density {
            scene.set_density(d);
        }
        if let Some(g) = self.ground {
            scene.ground = g;
        }
        let Some(supports) = &self.supports else { return Ok(scene) };
        let choice = supports.choice()?;
        scene
            .choose_supports(&choice, settings.tolerances.coplanar)
            .map_err(|e| errors::input(source, format!("supports: {e}")))?;
        Ok(scene)
    }
}
