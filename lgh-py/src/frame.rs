//! `lgh.FrameRender`: one frame of a simulation cache made ready once — read, its lights set,
//! its multiple-scattering pass run and its shadows made (the paper's Sec. 4 and 5) — then
//! rendered from any number of cameras, each render only the camera's rays through the
//! prepared frame (the lighting cache filled where they need it, and kept for the next).
//! A viewport's preview and a turntable pay the preparation once.

use std::ffi::OsString;
use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use self_cell::self_cell;

use lgh_cli::explosion::FrameParts;
use lgh_cli::memory::InMemoryError;

use crate::command::{array, command_line, exception, on_pool, value_text};
use crate::errors::RenderError;

/// The library's frame render, borrowing the prepared parts.
type Render<'a> = lgh_volume::FrameRender<'a>;

self_cell!(
    /// The prepared parts and the frame render that borrows them, held together.
    struct Ready {
        owner: FrameParts,
        #[covariant]
        dependent: Render,
    }
);

/// A frame of a simulation cache made ready once and rendered from many cameras:
/// ``FrameRender(vdb, **settings)`` takes ``render_explosion``'s arguments (one file: no
/// ``frames``; the ray marcher) and does its work up to the image — reading the frame, its
/// lights, the scattering pass, the shadows — with the same checks and exceptions;
/// ``render(camera=..., ...)`` then renders a camera (``camera``, ``camera_up``,
/// ``camera_shift`` and ``width``, ``height`` as ``lgh explosion``'s flags; none: the camera
/// of ``settings``). The settings that depend on a camera (``pixel_samples``,
/// ``emission_samples`` and ``cache_level`` ``auto``) are resolved for the camera of ``settings``: a render of that
/// camera is ``render_explosion``'s image, bit for bit, and so is any camera's where those
/// resolve alike or are given. ``progress`` and ``threads`` as ``render_explosion``'s.
#[pyclass(frozen, module = "lgh")]
pub struct FrameRender {
    ready: Ready,
    threads: Option<usize>,
}

#[pymethods]
impl FrameRender {
    #[new]
    #[pyo3(signature = (vdb, *, progress = None, threads = None, **settings))]
    fn new(
        py: Python<'_>,
        vdb: PathBuf,
        progress: Option<&Bound<'_, PyAny>>,
        threads: Option<usize>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let mut argv: Vec<OsString> = vec!["--vdb".into(), vdb.into_os_string()];
        argv.push("--quiet".into());
        argv.extend(command_line(settings)?.into_iter().map(OsString::from));
        let ready = on_pool(py, threads, progress, false, |watch| {
            let parts = lgh_cli::explosion::prepare_in_memory(&argv)?;
            Ready::try_new(parts, |parts| {
                parts.frame_render(watch).map_err(InMemoryError::Failed)
            })
        })?
        .map_err(|e| exception(&e))?;
        Ok(FrameRender { ready, threads })
    }

    /// Renders ``camera`` (``EX,EY,EZ,TX,TY,TZ[,FOV]`` as a string or a sequence), with the
    /// keywords ``width``, ``height`` (default: the prepared camera's size), ``camera_up`` and
    /// ``camera_shift`` (``--camera-up``, ``--camera-shift``); with no ``camera``, the prepared
    /// one. An ``(h, w, 3)`` float32 array of linear RGB.
    #[pyo3(signature = (camera = None, *, progress = None, **view))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        camera: Option<&Bound<'py, PyAny>>,
        progress: Option<&Bound<'py, PyAny>>,
        view: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let parts = self.ready.borrow_owner();
        let view = View::of(view)?;
        let size = (
            view.width.unwrap_or(parts.camera.width()),
            view.height.unwrap_or(parts.camera.height()),
        );
        let camera = match camera {
            None if view.up.is_some() || view.shift.is_some() => {
                return Err(PyValueError::new_err(
                    "camera_up and camera_shift turn and shift a camera: give camera too",
                ))
            }
            None if size != (parts.camera.width(), parts.camera.height()) => {
                return Err(PyValueError::new_err(
                    "width and height size a camera: give camera too (the prepared camera \
                     frames the smoke at its own size)",
                ))
            }
            None => parts.camera,
            Some(c) => parts
                .camera_of(
                    &value_text(c)?,
                    view.up.as_deref(),
                    view.shift.as_deref(),
                    size,
                )
                .map_err(|e| PyValueError::new_err(lgh_cli::describe(e.as_ref())))?,
        };
        let image = on_pool(py, self.threads, progress, false, |watch| {
            self.ready.borrow_dependent().render(&camera, watch)
        })?
        .map_err(|e| RenderError::new_err(e.to_string()))?;
        array(py, &image.0)
    }

    /// The prepared camera's ``(width, height)``.
    #[getter]
    fn size(&self) -> (usize, usize) {
        let c = &self.ready.borrow_owner().camera;
        (c.width(), c.height())
    }

    /// The number of lights of the frame (its hot voxels).
    #[getter]
    fn lights(&self) -> usize {
        self.ready.borrow_owner().lights.lit()
    }
}

/// The keywords of ``FrameRender.render`` beside the camera.
#[derive(Default)]
struct View {
    width: Option<usize>,
    height: Option<usize>,
    /// ``camera_up`` and ``camera_shift`` as the command line writes them.
    up: Option<String>,
    shift: Option<String>,
}

impl View {
    /// The keywords of `view`; any other is a `ValueError`.
    fn of(view: Option<&Bound<'_, PyDict>>) -> PyResult<View> {
        let mut out = View::default();
        let Some(view) = view else {
            return Ok(out);
        };
        for (k, v) in view.iter() {
            if v.is_none() {
                continue;
            }
            match k.extract::<String>()?.as_str() {
                "width" => out.width = Some(v.extract()?),
                "height" => out.height = Some(v.extract()?),
                "camera_up" => out.up = Some(value_text(&v)?),
                "camera_shift" => out.shift = Some(value_text(&v)?),
                other => {
                    return Err(PyValueError::new_err(format!(
                        "render() takes camera, width, height, camera_up, camera_shift and \
                         progress, not {other}"
                    )))
                }
            }
        }
        Ok(out)
    }
}
