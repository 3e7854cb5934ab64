//! `voussoir.analyze` and its result: the verdict, the graded ratios, and the forces as numpy
//! arrays (per interface and per force point), in N and m, compression positive; the force of
//! an interface acts on its block `b` (block `a` receives the opposite).

use crate::arrays::{indices, rows, vector};
use crate::errors;
use crate::settings::solve_function;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use voussoir::dynamics::{DropResult, DropSettings};
use voussoir::interfaces::Body;
use voussoir::pipeline;
use voussoir::report;
use voussoir::stability::kinematic::{self, Kinematic};

/// The analysis of one scene (`voussoir.analyze`).
#[pyclass(module = "voussoir", frozen)]
pub struct Analysis {
    pub(crate) analysis: pipeline::Analysis,
    dynamic: Option<DropResult>,
    kinematic: Option<Kinematic>,
}

solve_function! {
    /// Analyses `scene`: interfaces detected, equilibrium solved (the GIL released), and on request
    /// the kinematic check and the rapier drop test beside it.
    pub fn analyze<'py>(
        py, scene,
        ..options(mu, friction_model, solver, supports, ground, density, strength),
        strict: bool = false, kinematic: bool = false, dynamic: bool = false
    ) -> PyResult<Analysis> {
        let (design, mut settings) = options.apply(scene)?;
        settings.strict = strict;
        let source = scene.source.as_str();
        py.detach(|| {
            let analysis = pipeline::analyze(&design, &settings).map_err(|e| e.to_string())?;
            let kinematic = kinematic
                .then(|| kinematic::check(&analysis, &settings.statics, &Default::default()))
                .transpose()
                .map_err(|e| e.to_string())?;
            let drop = DropSettings { friction: options.mu, ..Default::default() };
            let dynamic = dynamic
                .then(|| voussoir::dynamics::drop_test(&analysis.assembly, &drop))
                .transpose()
                .map_err(|e| e.to_string())?;
            Ok(Analysis { analysis, dynamic, kinematic })
        })
        .map_err(|e: String| errors::input(source, e))
    }
}

impl Analysis {
    fn interface_rows<T>(&self, f: impl Fn(&voussoir::statics::InterfaceResult) -> T) -> Vec<T> {
        self.analysis.statics.interfaces.iter().map(f).collect()
    }

    /// The JSON report with what ran beside the statics (`to_dict`, `to_html`).
    fn report_json(&self) -> String {
        let extras = report::json::Extras {
            dynamic: self.dynamic.as_ref(),
            kinematic: self.kinematic.as_ref(),
            tolerance: None,
        };
        report::json::to_json_with(&self.analysis, &extras)
    }

    fn point_rows<T>(&self, f: impl Fn(&voussoir::statics::VertexForce) -> T) -> Vec<T> {
        self.analysis.statics.interfaces.iter().flat_map(|r| r.vertices.iter().map(&f)).collect()
    }
}

fn name_of<T: serde::Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(s)) => s,
        other => format!("{other:?}"),
    }
}

#[pymethods]
impl Analysis {
    /// "stands", "needs_tension", "needs_friction", "needs_tension_and_friction",
    /// "crushes" (it stands by compression and friction, but some joint needs more than
    /// the `strength` given), "unsupported" or "unresolved" (the solver did not converge: see `solver_status`).
    #[getter]
    fn verdict(&self) -> String {
        name_of(&self.analysis.statics.verdict)
    }

    #[getter]
    fn stands(&self) -> bool {
        self.analysis.statics.stands
    }

    /// With a compressive strength, on a design that stands by compression and friction: the
    /// least strength its joints need (Pa), the strength, their ratio and the joint that needs it
    /// (`interface`, `a`, `b`); else None.
    #[getter]
    fn crushing<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, pyo3::types::PyDict>>> {
        let Some(c) = &self.analysis.statics.crushing else { return Ok(None) };
        let d = pyo3::types::PyDict::new(py);
        d.set_item("needed", c.needed)?;
        d.set_item("strength", c.strength)?;
        d.set_item("utilization", c.utilization)?;
        d.set_item("interface", c.interface)?;
        d.set_item("a", &c.a)?;
        d.set_item("b", &c.b)?;
        Ok(Some(d))
    }

    /// Minimum total tension / total free weight.
    #[getter]
    fn tension_ratio(&self) -> f64 {
        self.analysis.statics.tension_ratio
    }

    /// Minimum total friction excess / total free weight.
    #[getter]
    fn friction_excess_ratio(&self) -> f64 {
        self.analysis.statics.friction_excess_ratio
    }

    #[getter]
    fn max_friction_utilization(&self) -> f64 {
        self.analysis.statics.max_friction_utilization
    }

    /// Total weight of the free blocks W, N.
    #[getter]
    fn free_weight(&self) -> f64 {
        self.analysis.statics.free_weight
    }

    #[getter]
    fn friction_coefficient(&self) -> f64 {
        self.analysis.statics.friction_coefficient
    }

    #[getter]
    fn friction_model(&self) -> String {
        name_of(&self.analysis.statics.friction_model)
    }

    /// The worst solver status of any component ("solved", "almost_solved", …).
    #[getter]
    fn solver_status(&self) -> String {
        name_of(&self.analysis.statics.solver.status)
    }

    /// Largest equilibrium residual of any block, N.
    #[getter]
    fn residual(&self) -> f64 {
        self.analysis.statics.solver.residual
    }

    /// The kinematic check's verdict ("stands", "fails", "undecided") when it ran.
    #[getter]
    fn kinematic_verdict(&self) -> Option<String> {
        self.kinematic.as_ref().map(|k| name_of(&k.verdict))
    }

    /// The drop test's verdict when it ran.
    #[getter]
    fn dynamic_stands(&self) -> Option<bool> {
        self.dynamic.as_ref().map(|d| d.stands)
    }

    /// The analysed blocks' names (the pieces, when the scene has a cut history).
    #[getter]
    fn block_names(&self) -> Vec<String> {
        self.analysis.assembly.blocks.iter().map(|b| b.name.clone()).collect()
    }

    /// (n,) bool: which blocks are supports.
    #[getter]
    fn block_is_support(&self) -> Vec<bool> {
        self.analysis.assembly.blocks.iter().map(|b| b.support).collect()
    }

    /// (m, 2) int: the blocks `a`, `b` of each interface (indices into `block_names`; -1 is the
    /// ground plane). The normal points from a into b.
    #[getter]
    fn interface_blocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let index = |b: Body| b.block().map_or(-1, |id| id.0 as i64);
        let pairs = self.interface_rows(|r| {
            let i = &self.analysis.interfaces[r.index];
            [index(i.a), index(i.b)]
        });
        rows(py, &pairs)
    }

    /// (3,) the total force the supports and the ground exert on the free blocks, N (at
    /// equilibrium under self-weight: the free weight, upwards).
    #[getter]
    fn support_reaction(&self) -> [f64; 3] {
        let a = &self.analysis;
        let mut total = [0.0; 3];
        for r in &a.statics.interfaces {
            let i = &a.interfaces[r.index];
            let sign = match (i.a.is_fixed(&a.assembly), i.b.is_fixed(&a.assembly)) {
                (true, false) => 1.0,  // the force on b, a free block
                (false, true) => -1.0, // a free block receives the opposite
                _ => continue,
            };
            (0..3).for_each(|k| total[k] += sign * r.resultant[k]);
        }
        total
    }

    /// (m,) interface areas, m².
    #[getter]
    fn interface_area<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.interface_rows(|r| r.area))
    }

    /// (m, 3) unit normals (from a into b); `interface_u`, `interface_v` complete the frame.
    #[getter]
    fn interface_normal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.interface_rows(|r| r.normal))
    }

    #[getter]
    fn interface_u<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.interface_rows(|r| r.u))
    }

    #[getter]
    fn interface_v<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.interface_rows(|r| r.v))
    }

    /// (m, 3) area centroids, m.
    #[getter]
    fn interface_centroid<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.interface_rows(|r| self.analysis.interfaces[r.index].centroid().into()))
    }

    /// (m,) net normal force Σ(compression − tension), N.
    #[getter]
    fn normal_force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.interface_rows(|r| r.normal_force))
    }

    /// (m,) magnitude of the friction resultant, N.
    #[getter]
    fn friction_force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.interface_rows(|r| r.friction))
    }

    /// (m,) |friction| / (μ × compression); above 1 exceeds μ.
    #[getter]
    fn friction_utilization<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.interface_rows(|r| r.friction_utilization))
    }

    /// (m, 3) resultant force on b, N, world axes.
    #[getter]
    fn resultant<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.interface_rows(|r| r.resultant))
    }

    /// (P, 3) the force points (interface polygon vertices), m.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.point_rows(|p| p.position))
    }

    /// (P,) the interface (row of the interface arrays) each force point belongs to.
    #[getter]
    fn point_interface<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let owner = self.analysis.statics.interfaces.iter().enumerate();
        indices(py, owner.flat_map(|(k, r)| std::iter::repeat_n(k as i64, r.vertices.len())).collect())
    }

    /// (P, 4) compas' force fields per point: c_np (compression), c_nn (tension), c_u, c_v
    /// (friction along interface_u, interface_v), N, acting on b.
    #[getter]
    fn point_forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.point_rows(|p| [p.compression, p.tension, p.friction_u, p.friction_v]))
    }

    /// Stage times in seconds (cut, validate, detect, assemble, solve, total).
    #[getter]
    fn timings(&self) -> std::collections::BTreeMap<&'static str, f64> {
        let t = &self.analysis.timings;
        [
            ("cut", t.cut),
            ("validate", t.validate),
            ("detect", t.detect),
            ("assemble", t.assemble),
            ("solve", t.solve),
            ("total", t.total),
        ]
        .into_iter()
        .collect()
    }

    /// The JSON report of `voussoir analyze --json` as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (self.report_json(),))
    }

    /// The design with its interfaces and forces as compas 2 Assembly JSON (what
    /// `analyze --compas-out` writes).
    fn to_compas_json(&self) -> String {
        report::compas::assembly_json(&self.analysis)
    }

    /// Writes the forces into a compas_assembly `Assembly` (or compas_cra `CRA_Assembly`) in
    /// compas' own fields: each block pair's `interfaces` become voussoir's, with `forces`
    /// (c_np, c_nn, c_u, c_v per point). Returns a summary dict (see `voussoir._compas`).
    fn write_forces<'py>(slf: &Bound<'py, Self>, assembly: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        slf.py().import("voussoir._compas")?.call_method1("write_forces", (slf, assembly))
    }

    /// The self-contained HTML report of this analysis (`voussoir report`'s page: the diagrams
    /// in 3D, the verdict and its numbers; a drop test's verdict when one ran, without its
    /// motion — `voussoir.report(..., dynamic=True)` plays it). `mode`: the diagram shown first.
    #[pyo3(signature = (mode = None, threshold = None))]
    fn to_html(&self, mode: Option<&str>, threshold: Option<f64>) -> PyResult<String> {
        let mut page = voussoir::viz::html::HtmlReport::new(&self.analysis, crate::report::diagram(mode, threshold)?);
        page.json = self.report_json();
        Ok(page.html())
    }

    /// Jupyter's rich display: the report in an `<iframe srcdoc>`.
    fn _repr_html_(&self) -> PyResult<String> {
        Ok(crate::report::iframe(&self.to_html(None, None)?))
    }

    fn __repr__(&self) -> String {
        let s = &self.analysis.statics;
        format!(
            "Analysis({}: {} blocks, {} interfaces, tension {:.3e} W, friction excess {:.3e} W)",
            self.verdict(),
            self.analysis.assembly.blocks.len(),
            s.interfaces.len(),
            s.tension_ratio,
            s.friction_excess_ratio
        )
    }
}
