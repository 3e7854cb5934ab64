//! The keyword arguments the solving functions share (`mu`, `friction_model`, `solver`,
//! `supports`, `ground`, `density`, `strength`: the compressive strength in Pa), and the one place they become the library's settings and
//! amend the scene (as the command line's options do). `None` keeps the library's default
//! (each written once, in its `Default`).
//!
//! [`solve_function!`] declares a Python function with them: they stay explicit keywords in its
//! pyo3 signature, so Python sees each with its default (and pyo3's own errors for an unknown
//! keyword or a wrong type), and its body gets them as one [`SolveOptions`].

use crate::errors;
use crate::scene::Scene as PyScene;
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

/// The shared keyword arguments, as Python passed them (`None` also for those a function does
/// not take).
#[derive(Default)]
pub struct SolveOptions {
    pub mu: Option<f64>,
    pub friction_model: Option<String>,
    pub solver: Option<String>,
    pub supports: Option<Supports>,
    pub ground: Option<bool>,
    pub density: Option<f64>,
    pub strength: Option<f64>,
}

/// A value of one of the library's named choices (`friction_model="pyramid8"`), by the names
/// the command line takes.
pub(crate) fn choice<T: ValueEnum>(what: &str, name: &str) -> PyResult<T> {
    T::from_str(name, true).map_err(|_| {
        let names: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|p| p.get_name().to_string())
            .collect();
        errors::setting(format!("{what}: '{name}' is not one of {}", names.join(", ")))
    })
}

impl SolveOptions {
    /// The analysis settings (the library's defaults with these options) and `scene`'s design
    /// amended by `supports`, `ground` and `density` (a copy; the caller's scene is kept).
    pub fn apply(&self, scene: &PyScene) -> PyResult<(Scene, AnalysisSettings)> {
        let settings = self.settings()?;
        let design = self.amend(&scene.scene, &scene.source, &settings)?;
        Ok((design, settings))
    }

    fn settings(&self) -> PyResult<AnalysisSettings> {
        let mut settings = AnalysisSettings::default();
        if let Some(name) = &self.friction_model {
            settings.statics.friction_model = choice::<FrictionModel>("friction_model", name)?;
        }
        if let Some(name) = &self.solver {
            settings.statics.backend = choice::<Backend>("solver", name)?;
        }
        settings.statics.friction = self.mu;
        settings.statics.strength = self.strength;
        Ok(settings)
    }

    fn amend(&self, scene: &Scene, source: &str, settings: &AnalysisSettings) -> PyResult<Scene> {
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

/// Declares a Python function that takes shared keywords:
/// `pub fn name<'py>(py, scene, own: Type = default, …, ..options(mu, …), own: Type = default, …)
/// -> Ret { body }`. Every keyword is keyword-only and listed in the pyo3 signature in the order
/// written, the shared ones (typed as [`SolveOptions`]' fields) with the default `None`; the body
/// sees the shared ones as `options`, a [`SolveOptions`].
macro_rules! solve_function {
    (
        $(#[$attr:meta])*
        pub fn $name:ident<$lt:lifetime>(
            $py:ident, $scene:ident,
            $($arg:ident: $ty:ty = $default:tt,)*
            ..$options:ident($($shared:ident),+)
            $(, $later:ident: $lty:ty = $ldefault:tt)* $(,)?
        ) -> $ret:ty $body:block
    ) => {
        $(#[$attr])*
        #[pyo3::pyfunction]
        #[pyo3(signature = ($scene, *, $($arg = $default,)* $($shared = None,)* $($later = $ldefault,)*))]
        #[allow(clippy::too_many_arguments)] // Python's keyword arguments
        pub fn $name<$lt>(
            $py: pyo3::Python<$lt>,
            $scene: &crate::scene::Scene,
            $($arg: $ty,)*
            $($shared: $crate::settings::solve_function!(@type $shared),)*
            $($later: $lty,)*
        ) -> $ret {
            #[allow(clippy::needless_update)] // when it takes them all
            let $options = crate::settings::SolveOptions { $($shared,)+ ..Default::default() };
            $body
        }
    };
    (@type mu) => { Option<f64> };
    (@type friction_model) => { Option<String> };
    (@type solver) => { Option<String> };
    (@type supports) => { Option<crate::settings::Supports> };
    (@type ground) => { Option<bool> };
    (@type density) => { Option<f64> };
    (@type strength) => { Option<f64> };
}
pub(crate) use solve_function;
