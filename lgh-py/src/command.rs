//! What `render_explosion` and `render_gi` share: a command of `lgh` rendered into memory with
//! its settings given as keyword arguments (each the command's flag), its errors raised as
//! Python exceptions with the command's messages, on a pool of the threads asked for, watched
//! for Ctrl-C and progress ([`crate::progress`]).

use std::ffi::OsString;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString, PyTuple};

use lgh_cli::memory::{InMemoryError, Setting};

use crate::errors::RenderError;
use crate::progress::{watched, Watch};

/// The command line of `settings`: `name=value` is `--name=value` (underscores as dashes; the
/// `=` form, so that a value may start with `-`),
/// `True` the flag alone, `False` and `None` nothing, a tuple or list of numbers its items
/// joined by commas (`camera=(0, -4, 0, 0, 0, 0, 40)`), a list of strings the flag repeated
/// (`light=["point:0,1,0,5,5,5", "sun:0,-1,0,3,3,3"]`).
pub fn command_line(settings: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
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
        if let Some(strings) = strings(&v)? {
            // Strings: the flag repeated, one value each (`light=["point:…", "sun:…"]`).
            argv.extend(strings.into_iter().map(|x| format!("{flag}={x}")));
        } else {
            argv.push(format!("{flag}={}", value_text(&v)?));
        }
    }
    Ok(argv)
}

/// A list or tuple of strings, each as it is (`None`: another value).
fn strings(v: &Bound<'_, PyAny>) -> PyResult<Option<Vec<String>>> {
    if !(v.is_instance_of::<PyTuple>() || v.is_instance_of::<PyList>()) {
        return Ok(None);
    }
    let items: Vec<Bound<'_, PyAny>> = v.try_iter()?.collect::<PyResult<_>>()?;
    if items.is_empty() || !items.iter().all(|x| x.is_instance_of::<PyString>()) {
        return Ok(None);
    }
    items
        .iter()
        .map(|x| Ok(x.str()?.to_string()))
        .collect::<PyResult<_>>()
        .map(Some)
}

/// A setting's value as the command line writes it: a tuple or list its items joined by
/// commas (`camera=(0, -4, 0, 0, 0, 0, 40)` is `0,-4,0,0,0,0,40`), anything else its `str`.
pub fn value_text(v: &Bound<'_, PyAny>) -> PyResult<String> {
    if v.is_instance_of::<PyTuple>() || v.is_instance_of::<PyList>() {
        let items: Vec<String> = v
            .try_iter()?
            .map(|x| x.and_then(|x| x.str().map(|s| s.to_string())))
            .collect::<PyResult<_>>()?;
        return Ok(items.join(","));
    }
    Ok(v.str()?.to_string())
}

/// The library's error as a Python exception with the command's one-line message: a missing
/// input file is `FileNotFoundError`; a flag or setting refused before any work `ValueError`;
/// an error of the render itself `lgh.RenderError`.
pub fn exception(e: &InMemoryError) -> PyErr {
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
pub fn array<'py>(py: Python<'py>, image: &lgh_image::Image) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = image.pixels.iter().flat_map(|p| p.to_array()).collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([image.height, image.width, 3])?
        .into_any())
}

/// A setting as Python sees it: `(name, takes_value, default, choices, help)`.
pub type SettingRow = (String, bool, Option<String>, Vec<String>, String);

/// `settings` as Python sees them: `(name, takes_value, default, choices, help)`, the name the
/// flag with underscores, the default `None` for a switch.
pub fn rows(settings: Vec<Setting>) -> Vec<SettingRow> {
    settings
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

/// Runs `render(argv, watch)` — a command's render into memory — with `input` (`--vdb PATH`,
/// `--obj PATH`) and `settings` as its command line (`--quiet` unless `quiet` is given), on
/// `threads` threads (default: the global pool), watched for Ctrl-C and reported to
/// `progress`; its error raised as the exception of its stage.
pub fn run<T: Send>(
    py: Python<'_>,
    input: [OsString; 2],
    progress: Option<&Bound<'_, PyAny>>,
    threads: Option<usize>,
    settings: Option<&Bound<'_, PyDict>>,
    render: impl Fn(&[OsString], &Watch) -> Result<T, InMemoryError> + Sync,
) -> PyResult<T> {
    let mut argv: Vec<OsString> = input.into();
    let given = command_line(settings)?;
    if !settings.is_some_and(|s| s.contains("quiet").unwrap_or(false)) {
        argv.push("--quiet".into());
    }
    argv.extend(given.into_iter().map(OsString::from));
    let bars = !argv.iter().any(|a| a == "--quiet");
    on_pool(py, threads, progress, bars, |watch| render(&argv, watch))?.map_err(|e| exception(&e))
}

/// Runs `work(watch)` on `threads` threads (default: the global pool), watched for Ctrl-C
/// and reported to `progress` (or the command's bars if `bars`).
pub fn on_pool<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    progress: Option<&Bound<'_, PyAny>>,
    bars: bool,
    work: impl Fn(&Watch) -> T + Sync,
) -> PyResult<T> {
    let pool = pool(threads)?;
    let watch = Watch::new(progress.map(|p| p.clone().unbind()), bars);
    watched(py, &watch, |watch| match &pool {
        Some(pool) => pool.install(|| work(watch)),
        None => work(watch),
    })
}

/// A pool of `threads` threads (`None`: the global pool); 0 is a `ValueError`.
fn pool(threads: Option<usize>) -> PyResult<Option<rayon::ThreadPool>> {
    Ok(match threads {
        Some(0) => return Err(PyValueError::new_err("threads must be at least 1")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| RenderError::new_err(format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    })
}
