//! `voussoir._native`: the Python extension over the voussoir library (the pure-Python package
//! `voussoir` around it adds the compas conveniences). Units as the library's: m, kg, N, s;
//! z up; compression positive.
//!
//! Each function is the library's stage of the same name with Python's arguments: the scene
//! and settings in, a result object out; solves run with the GIL released. Bad input raises
//! [`errors::InputError`] (a `ValueError`) or [`errors::FileError`] (an `OSError`) with the
//! message the command line prints; solver trouble is not an exception but a status with its
//! residual on the result, as in the library.

mod analysis;
mod arrays;
mod design;
mod errors;
mod report;
mod scene;
mod settings;
mod tasks;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("FileError", py.get_type::<errors::FileError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<analysis::Analysis>()?;
    m.add_function(wrap_pyfunction!(analysis::analyze, m)?)?;
    m.add_function(wrap_pyfunction!(tasks::detect_interfaces, m)?)?;
    m.add_function(wrap_pyfunction!(tasks::load_factor, m)?)?;
    m.add_function(wrap_pyfunction!(tasks::tolerance, m)?)?;
    m.add_function(wrap_pyfunction!(tasks::settle, m)?)?;
    m.add_function(wrap_pyfunction!(tasks::sequence, m)?)?;
    m.add_function(wrap_pyfunction!(tasks::drop, m)?)?;
    m.add_function(wrap_pyfunction!(tasks::shake, m)?)?;
    m.add_function(wrap_pyfunction!(design::repair, m)?)?;
    m.add_function(wrap_pyfunction!(design::decompose, m)?)?;
    m.add_function(wrap_pyfunction!(design::infill, m)?)?;
    m.add_function(wrap_pyfunction!(report::report, m)?)?;
    Ok(())
}
