//! `lgh.render_gi`: `lgh gi` rendered into memory — an OBJ scene's global illumination from
//! virtual point lights through the hierarchy (the paper's Sec. 7 and Fig. 13), with every
//! setting of the command a keyword argument at the command's default, the same checks and
//! the same image, bit for bit.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::command::{array, rows, run, SettingRow};

/// Every setting ``render_gi`` takes, in ``lgh gi``'s order: a list of ``(name, takes_value,
/// default, choices, help)``, as ``explosion_settings``.
#[pyfunction]
pub fn gi_settings() -> Vec<SettingRow> {
    rows(lgh_cli::gi::settings())
}

/// Renders the OBJ scene ``obj`` (its MTL files beside it) lit by virtual point lights, as
/// ``lgh gi --obj OBJ`` with ``settings`` does, into memory: an ``(h, w, 3)`` float32 array of
/// linear RGB (the command's EXR). Every setting of ``lgh gi`` is a keyword argument
/// (``lgh gi --help``: ``--light point:0,1,0,5,5,5`` is ``light="point:0,1,0,5,5,5"``, several
/// as a list of strings, ``--no-direct`` is ``no_direct=True``), at the command's default
/// where not given. A missing ``obj`` is ``FileNotFoundError``, a flag or setting the command
/// refuses before any work ``ValueError``, an error of the render itself ``lgh.RenderError``.
/// ``progress(phase, done, total)`` hears the rows of each phase; an exception it raises, and
/// Ctrl-C, stop the render within a row. ``threads`` changes nothing in the image. The GIL is
/// released while it renders.
#[pyfunction]
#[pyo3(signature = (obj, *, progress = None, threads = None, **settings))]
pub fn render_gi<'py>(
    py: Python<'py>,
    obj: PathBuf,
    progress: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    settings: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let input = ["--obj".into(), obj.into_os_string()];
    let image = run(py, input, progress, threads, settings, |argv, watch| {
        lgh_cli::gi::render_in_memory_with(argv, Some(watch))
    })?;
    array(py, &image)
}
