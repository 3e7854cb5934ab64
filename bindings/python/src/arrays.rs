//! numpy arrays from the library's rows (one touchpoint for the numpy crate).

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// An (n,) float array.
pub fn vector<'py>(py: Python<'py>, values: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, values)
}

/// An (n,) int array.
pub fn indices<'py>(py: Python<'py>, values: Vec<i64>) -> Bound<'py, PyArray1<i64>> {
    PyArray1::from_vec(py, values)
}

/// An (n, K) array from rows of K values (also for n = 0).
pub fn rows<'py, T: numpy::Element + Copy, const K: usize>(
    py: Python<'py>,
    rows: &[[T; K]],
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let flat: Vec<T> = rows.iter().flatten().copied().collect();
    PyArray1::from_vec(py, flat).reshape([rows.len(), K])
}
