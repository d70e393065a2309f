//! numpy arrays in and out, without a Python call per element: any array-like is made a
//! C-contiguous float32 array once (numpy's own conversion, free when it already is one), then
//! read as one slice.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `obj` as a C-contiguous float32 numpy array (a copy only where it is not one).
fn float32<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    np.call_method1("ascontiguousarray", (obj, "float32"))
}

/// `obj` as an `(n, 3)` float32 array; `name` is the argument's, for the message.
pub fn rows<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let a = float32(obj)?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{name} must be an (n, 3) array, got shape {shape:?}"
        )));
    }
    Ok(a.cast_into::<PyArray2<f32>>()?)
}

/// `obj` as three floats (a point); `name` is the argument's, for the message.
pub fn point(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f32; 3]> {
    let a = float32(obj)?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    if shape != [3] {
        return Err(PyValueError::new_err(format!(
            "{name} must be three numbers (shape (3,)), got shape {shape:?}"
        )));
    }
    let a = a.cast_into::<PyArray1<f32>>()?;
    let v = a.readonly();
    let s = v.as_slice()?;
    Ok([s[0], s[1], s[2]])
}

/// An `(n, 3)` float32 array of zeros, to be filled.
pub fn zeros(py: Python<'_>, n: usize) -> Bound<'_, PyArray2<f32>> {
    PyArray2::zeros(py, [n, 3], false)
}

/// The rows of a C-contiguous `(n, 3)` slice.
#[must_use]
pub fn triples(s: &[f32]) -> &[[f32; 3]] {
    let (rows, rest) = s.as_chunks::<3>();
    debug_assert!(rest.is_empty());
    rows
}

/// `a`'s rows (its shape's first axis), checked to be `want`: else a `ValueError` saying
/// "`name` has n rows, `what` want".
pub fn check_len(
    a: &Bound<'_, PyArray2<f32>>,
    want: usize,
    name: &str,
    what: &str,
) -> PyResult<()> {
    let n = a.shape()[0];
    if n != want {
        return Err(PyValueError::new_err(format!(
            "{name} has {n} rows, {what} {want}"
        )));
    }
    Ok(())
}
