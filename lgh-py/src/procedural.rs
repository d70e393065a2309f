//! `lgh.write_procedural`: lgh's procedural volumes as raw grids for tools that make an OpenVDB
//! file of them (`tools/cycles/write_vdb.py`): test scenes for Blender and notebooks without a
//! simulation cache.

use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lgh_volume::procedural;

use crate::errors::RenderError;

/// Writes the procedural volume ``kind`` — ``"fireball"`` (the soft fireball of the Cycles
/// comparison), ``"explosion"`` (the demo's) or ``"ball"`` (the scattering tests' ball; ``time``
/// ignored) — at ``resolution`` voxels a side and animation time ``time`` as raw grids:
/// ``PREFIX.json`` (dims, voxel size, origin, +Y up) and ``PREFIX.density.f32``,
/// ``PREFIX.temperature.f32`` (little-endian float32, x fastest).
/// ``tools/cycles/write_vdb.py PREFIX`` turns them into an OpenVDB file in Blender's +Z-up world.
#[pyfunction]
pub fn write_procedural(kind: &str, resolution: usize, time: f32, prefix: PathBuf) -> PyResult<()> {
    if !(2..=512).contains(&resolution) {
        return Err(PyValueError::new_err(format!(
            "resolution {resolution} must be 2 to 512 voxels a side"
        )));
    }
    let volume = match kind {
        "fireball" => procedural::procedural(resolution, time),
        "explosion" => procedural::explosion(resolution, time),
        "ball" => Ok(procedural::ball(resolution, 0.5, 2500.0)),
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown procedural volume {other:?}: fireball, explosion or ball"
            )))
        }
    }
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let time = time.to_string();
    lgh_volume::export::write_raw_grids(&volume, &prefix, &[("kind", kind), ("time", &time)])
        .map_err(|e| RenderError::new_err(format!("{}: {e}", prefix.display())))
}
