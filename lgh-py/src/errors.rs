//! The library's errors as Python exceptions, each carrying the library's own message: bad
//! input (a light that is not finite, α ≤ 0, a point with a NaN, arrays of the wrong shape) is a
//! `ValueError`, a missing file a `FileNotFoundError`, and the rest `lgh.RenderError`.

use lgh_core::{BuildError, QueryError};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::PyErr;

create_exception!(
    lgh,
    RenderError,
    PyException,
    "An error of the library that is not a bad argument (`ValueError`) or a missing file (`FileNotFoundError`); its message is the library's."
);

/// A build refused: every [`BuildError`] is a property of the lights or settings given.
pub fn build(e: BuildError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A query refused: a bad α, or a point that is not finite.
pub fn query(e: QueryError) -> PyErr {
    PyValueError::new_err(e.to_string())
}
