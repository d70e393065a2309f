//! `lgh.render_explosion`: `lgh explosion` rendered into memory — a simulation cache lit by
//! its own fire (the paper's Sec. 5 and 6), with every setting of the command a keyword
//! argument at the command's default, the same checks and the same image, bit for bit.

use std::ffi::OsString;
use std::path::PathBuf;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyTuple};

use lgh_cli::explosion::InMemoryError;

use crate::errors::RenderError;
use crate::progress::{watched, Watch};

/// The command line of `settings`: `name=value` is `--name=value` (underscores as dashes; the
/// `=` form, so that a value may start with `-`),
/// `True` the flag alone, `False` and `None` nothing, a tuple or list its items joined by
/// commas (`camera=(0, -4, 0, 0, 0, 0, 40)`).
fn command_line(settings: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    let mut argv = Vec::new();
    let Some(settings) = settings else {
        return Ok(argv);
    };
    for (k, v) in settings.iter() {
        let flag = format!("--{}", k.extract::<String>()?.replace('_', "-"));
        if v.is_none() {
            continue;
        }
        if let Ok(b) = v.cast::<PyBool>() {
            if b.is_true() {
                argv.push(flag);
            }
            continue;
        }
        let value = if v.is_instance_of::<PyTuple>() || v.is_instance_of::<PyList>() {
            let items: Vec<String> = v
                .try_iter()?
                .map(|x| x.and_then(|x| x.str().map(|s| s.to_string())))
                .collect::<PyResult<_>>()?;
            items.join(",")
        } else {
            v.str()?.to_string()
        };
        argv.push(format!("{flag}={value}"));
    }
    Ok(argv)
}

/// The library's error as a Python exception with the command's one-line message: a missing
/// input file is `FileNotFoundError`; a flag or setting refused before any work `ValueError`;
/// an error of the render itself `lgh.RenderError`.
fn exception(e: &InMemoryError) -> PyErr {
    let message = lgh_cli::describe(e.error().as_ref());
    if e.error().downcast_ref::<lgh_cli::MissingFile>().is_some() {
        return PyFileNotFoundError::new_err(message);
    }
    match e {
        InMemoryError::Refused(_) => PyValueError::new_err(message),
        InMemoryError::Failed(_) => RenderError::new_err(message),
    }
}

/// ``image`` as an ``(h, w, 3)`` float32 array, rows from the top.
fn array<'py>(py: Python<'py>, image: &lgh_image::Image) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = image.pixels.iter().flat_map(|p| p.to_array()).collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([image.height, image.width, 3])?
        .into_any())
}

/// A setting as Python sees it: `(name, takes_value, default, choices, help)`.
type SettingRow = (String, bool, Option<String>, Vec<String>, String);

/// Every setting ``render_explosion`` takes, in ``lgh explosion``'s order: a list of
/// ``(name, takes_value, default, choices, help)``, ``name`` the keyword (the flag with
/// underscores), ``default`` the command's (``None`` where it has none), ``choices`` the
/// accepted values where they are a fixed list, ``help`` the help's first sentence.
#[pyfunction]
pub fn explosion_settings() -> Vec<SettingRow> {
    lgh_cli::explosion::settings()
        .into_iter()
        .map(|s| {
            let default = s.default.filter(|_| s.takes_value);
            (
                s.flag.replace('-', "_"),
                s.takes_value,
                default,
                s.choices,
                s.help,
            )
        })
        .collect()
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
    let pool = match threads {
        Some(0) => return Err(PyValueError::new_err("threads must be at least 1")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| RenderError::new_err(format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    };
    let frames = match settings {
        Some(s) => match s.get_item("frames")? {
            Some(f) => f.is_truthy()?,
            None => false,
        },
        None => false,
    };
    let mut argv: Vec<OsString> = vec!["--vdb".into(), vdb.into_os_string()];
    let given = command_line(settings)?;
    if !settings.is_some_and(|s| s.contains("quiet").unwrap_or(false)) {
        argv.push("--quiet".into());
    }
    argv.extend(given.into_iter().map(OsString::from));
    let bars = !argv.iter().any(|a| a == "--quiet");
    let watch = Watch::new(progress.map(|p| p.clone().unbind()), bars);
    let images = watched(py, &watch, |watch| {
        let render = || lgh_cli::explosion::render_in_memory_with(&argv, Some(watch));
        match &pool {
            Some(pool) => pool.install(render),
            None => render(),
        }
    })?
    .map_err(|e| exception(&e))?;
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
