//! `lgh.inspect`: what `lgh inspect --json` prints of an OpenVDB file — each grid's name, value
//! type, voxel size, active box and statistics — for a tool that must know a file's grids before
//! it renders (the Blender add-on reading a fluid domain's cache).

use std::path::PathBuf;

use pyo3::prelude::*;

use lgh_cli::memory::InMemoryError;

use crate::command::exception;

/// The grids of the OpenVDB file ``vdb``, as ``lgh inspect --json`` prints them: a dict
/// ``{"grids": [{"name", "value_type", "voxel_size", "active_voxels", "bbox_min", "bbox_max",
/// "min", "max", "sum"}, ...]}`` (``voxel_size`` per axis; ``bbox_*`` the active voxels' index
/// box, ``None`` for an empty grid; vector grids' statistics are of the vector length; a
/// number that is not finite is ``None``). The file is read whole, with the GIL released. A
/// missing file is ``FileNotFoundError``, one that is no OpenVDB file ``lgh.RenderError``.
#[pyfunction]
pub fn inspect<'py>(py: Python<'py>, vdb: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let report = py
        .detach(|| lgh_cli::inspect::report(&vdb).map(|v| v.to_string()))
        .map_err(|e| exception(&InMemoryError::Failed(e)))?;
    py.import("json")?.call_method1("loads", (report,))
}
