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

use lgh_volume::export::write_raw_grids;
use lgh_volume::procedural;

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
    let time = time.to_string();
    write_raw_grids(
        &volume,
        std::path::Path::new(out),
        &[("kind", kind), ("time", &time)],
    )?;
    eprintln!(
        "wrote {out}.json and its two grids ({:?} voxels)",
        volume.density.dims
    );
    Ok(())
}
