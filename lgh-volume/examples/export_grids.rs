//! Writes a procedural volume's grids as raw little-endian `f32` files plus a JSON description,
//! for `tools/cycles/write_vdb.py` to turn into an OpenVDB file that Blender Cycles and
//! `lgh explosion` both read (the Cycles comparison, `tools/cycles/README.md`).
//!
//! ```text
//! cargo run --release -p lgh-volume --example export_grids -- fireball|explosion|ball RES TIME OUT_PREFIX
//! ```
//!
//! Writes `OUT_PREFIX.json` (`dims`, `voxel_size`, `origin`: the centre of voxel (0, 0, 0), as
//! in [`DenseGrid`]; the world is +Y up, as the procedural volumes are) and
//! `OUT_PREFIX.density.f32`, `OUT_PREFIX.temperature.f32` (kelvin), x fastest, then y, then z.

use std::io::Write;

use lgh_volume::grid::DenseGrid;
use lgh_volume::procedural;

fn write_raw(path: &str, grid: &DenseGrid) -> std::io::Result<()> {
    let mut bytes = Vec::with_capacity(grid.data.len() * 4);
    for v in &grid.data {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::File::create(path)?.write_all(&bytes)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [kind, res, time, out] = args.as_slice() else {
        return Err("usage: export_grids fireball|explosion|ball RES TIME OUT_PREFIX".into());
    };
    let res: usize = res.parse()?;
    let time: f32 = time.parse()?;
    let volume = match kind.as_str() {
        // The older soft fireball (`procedural::procedural`) and the demo's explosion.
        "fireball" => procedural::procedural(res, time)?,
        "explosion" => procedural::explosion(res, time)?,
        // The scattering tests' ball (core radius 0.5, 2500 K); TIME is ignored.
        "ball" => procedural::ball(res, 0.5, 2500.0),
        other => return Err(format!("unknown volume {other:?}").into()),
    };
    let d = &volume.density;
    let meta = serde_json::json!({
        "kind": kind,
        "time": time,
        "dims": d.dims,
        "voxel_size": d.voxel_size,
        "origin": [d.origin.x, d.origin.y, d.origin.z],
        "up": "y",
        "grids": ["density", "temperature"],
    });
    std::fs::write(format!("{out}.json"), serde_json::to_string_pretty(&meta)?)?;
    write_raw(&format!("{out}.density.f32"), &volume.density)?;
    write_raw(&format!("{out}.temperature.f32"), &volume.temperature)?;
    eprintln!("wrote {out}.json and its two grids ({:?} voxels)", d.dims);
    Ok(())
}
