//! The native half of the Python package `lgh` (`lgh._lgh`): the Lighting Grid Hierarchy of
//! Yuksel & Yuksel 2017 over numpy arrays, for pipelines, DCC tools and notebooks.
//!
//! One concept a module: [`explosion`] renders a simulation cache as `lgh explosion` does,
//! [`gi`] an OBJ scene's global illumination as `lgh gi` does, both through [`command`];
//! [`frame`] prepares a frame once and renders it from many cameras;
//! [`hierarchy`] is the paper's hierarchy (Sec. 3: the build of eqs. (1),
//! (2), (4), (5) and the blended query of eq. (3)); [`arrays`] moves numpy arrays in and out
//! without a Python call per element; [`progress`] reports the library's progress to a Python
//! callback; [`inspect`] lists an OpenVDB file's grids; [`procedural`] writes lgh's procedural volumes for OpenVDB tools; [`errors`] maps the library's errors to Python's
//! exceptions; [`work`] runs long work in chunks with the GIL released, stopping on Ctrl-C and
//! reporting progress between chunks.

use pyo3::prelude::*;

mod arrays;
mod command;
mod errors;
mod explosion;
mod frame;
mod gi;
mod hierarchy;
mod inspect;
mod procedural;
mod progress;
mod work;

/// The module `lgh._lgh`; `lgh/__init__.py` re-exports it.
#[pymodule]
fn _lgh(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<hierarchy::Hierarchy>()?;
    m.add_class::<frame::FrameRender>()?;
    m.add_function(wrap_pyfunction!(explosion::render_explosion, m)?)?;
    m.add_function(wrap_pyfunction!(explosion::explosion_settings, m)?)?;
    m.add_function(wrap_pyfunction!(procedural::write_procedural, m)?)?;
    m.add_function(wrap_pyfunction!(inspect::inspect, m)?)?;
    m.add_function(wrap_pyfunction!(gi::render_gi, m)?)?;
    m.add_function(wrap_pyfunction!(gi::gi_settings, m)?)?;
    m.add("RenderError", m.py().get_type::<errors::RenderError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
