//! `lgh.render_explosion`: `lgh explosion` rendered into memory — a simulation cache lit by
//! its own fire (the paper's Sec. 5 and 6), with every setting of the command a keyword
//! argument at the command's default, the same checks and the same image, bit for bit.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::command::{array, rows, run, SettingRow};
use crate::errors::RenderError;

/// Every setting ``render_explosion`` takes, in ``lgh explosion``'s order: a list of
/// ``(name, takes_value, default, choices, help)``, ``name`` the keyword (the flag with
/// underscores), ``default`` the command's (``None`` where it has none), ``choices`` the
/// accepted values where they are a fixed list, ``help`` the help's first sentence.
#[pyfunction]
pub fn explosion_settings() -> Vec<SettingRow> {
    rows(lgh_cli::explosion::settings())
}

/// Renders an OpenVDB simulation cache lit by its own fire, as ``lgh explosion --vdb VDB``
/// with ``settings`` does, into memory: an ``(h, w, 3)`` float32 array of linear RGB (the
/// command's EXR), or with ``frames="A..B"`` a dict of them by frame number. Every setting of
/// ``lgh explosion`` is a keyword argument (``lgh explosion --help``: ``--scatter-depth auto``
/// is ``scatter_depth="auto"``, ``--no-domain-offset`` is ``no_domain_offset=True``), at the
/// command's default where not given. A missing input file (``vdb``, a frame of ``frames``,
/// ``scene``) is ``FileNotFoundError``, a flag or setting the command refuses before any work
/// (``albedo=2``) ``ValueError``, an error of the render itself (a grid the file lacks)
/// ``lgh.RenderError``. Progress bars are
/// off unless ``quiet=False``; ``progress(phase, done, total)``, if given, is called instead
/// as each frame's scattering, shadow maps and image go (at most every 0.1 s); an exception it
/// raises stops the render within a row (or a light, or a chunk of voxels) and is raised, as
/// Ctrl-C (``KeyboardInterrupt``) is. ``threads`` (default: every core; the command's
/// ``--threads``) changes nothing in the image. The GIL is released while it renders.
#[pyfunction]
#[pyo3(signature = (vdb, *, progress = None, threads = None, **settings))]
pub fn render_explosion<'py>(
    py: Python<'py>,
    vdb: PathBuf,
    progress: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    settings: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let frames = match settings {
        Some(s) => match s.get_item("frames")? {
            Some(f) => f.is_truthy()?,
            None => false,
        },
        None => false,
    };
    let input = ["--vdb".into(), vdb.into_os_string()];
    let images = run(py, input, progress, threads, settings, |argv, watch| {
        lgh_cli::explosion::render_in_memory_with(argv, Some(watch))
    })?;
    if !frames {
        let one = images
            .first()
            .ok_or_else(|| RenderError::new_err("the render gave no image"))?;
        return array(py, &one.image);
    }
    let out = PyDict::new(py);
    for f in &images {
        out.set_item(f.frame, array(py, &f.image)?)?;
    }
    Ok(out.into_any())
}
