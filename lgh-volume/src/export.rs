//! A volume's grids as raw little-endian `f32` files beside a JSON description: what
//! `tools/cycles/write_vdb.py` turns into the OpenVDB file that Blender Cycles and `lgh explosion`
//! both read (the Cycles comparison, `tools/cycles/README.md`).
//!
//! `PREFIX.json` holds `dims`, `voxel_size`, `origin` (the centre of voxel (0, 0, 0), as in
//! [`DenseGrid`]), `up` (`"y"`: the procedural volumes' world), `grids` and whatever the caller
//! adds; `PREFIX.density.f32` and `PREFIX.temperature.f32` hold the values, x fastest, then y,
//! then z.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::grid::DenseGrid;
use crate::medium::Volume;

/// Writes `volume`'s density and temperature grids as `PREFIX.density.f32` and
/// `PREFIX.temperature.f32` and their description as `PREFIX.json`, with the string fields
/// `extra` added to it (e.g. the volume's kind). Its flame and colour grids are not written.
/// Errors (`InvalidInput`, nothing written) where the two grids do not share one layout.
///
/// ```
/// use lgh_volume::export::write_raw_grids;
///
/// let dir = tempfile::tempdir()?;
/// let prefix = dir.path().join("ball");
/// let ball = lgh_volume::procedural::ball(8, 0.5, 2500.0);
/// write_raw_grids(&ball, &prefix, &[("kind", "ball")])?;
/// let meta: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.path().join("ball.json"))?)?;
/// assert_eq!((meta["dims"][0].as_u64(), meta["kind"].as_str()), (Some(8), Some("ball")));
/// assert_eq!(std::fs::metadata(dir.path().join("ball.density.f32"))?.len(), 8 * 8 * 8 * 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_raw_grids(
    volume: &Volume,
    prefix: &Path,
    extra: &[(&str, &str)],
) -> std::io::Result<()> {
    let d = &volume.density;
    if !d.same_layout(&volume.temperature) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the density and temperature grids differ in layout: one JSON cannot describe both",
        ));
    }
    let [nx, ny, nz] = d.dims;
    let o = d.origin;
    let mut fields = vec![
        format!("\"dims\": [{nx}, {ny}, {nz}]"),
        // Rust prints an f32 as the shortest decimal that reads back to it.
        format!("\"voxel_size\": {:?}", d.voxel_size),
        format!("\"origin\": [{:?}, {:?}, {:?}]", o.x, o.y, o.z),
        "\"up\": \"y\"".to_string(),
        "\"grids\": [\"density\", \"temperature\"]".to_string(),
    ];
    fields.extend(
        extra
            .iter()
            .map(|(k, v)| format!("{}: {}", string(k), string(v))),
    );
    let with = |suffix: &str| {
        let mut p: PathBuf = prefix.into();
        p.as_mut_os_string().push(suffix);
        p
    };
    std::fs::write(
        with(".json"),
        format!("{{\n  {}\n}}\n", fields.join(",\n  ")),
    )?;
    write_raw(&with(".density.f32"), &volume.density)?;
    write_raw(&with(".temperature.f32"), &volume.temperature)
}

/// `s` as a JSON string.
fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' | '\\' => {
                out.push('\\');
                out.push(c);
            }
            c if u32::from(c) < 0x20 => out.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn write_raw(path: &Path, grid: &DenseGrid) -> std::io::Result<()> {
    let mut bytes = Vec::with_capacity(grid.data.len() * 4);
    for v in &grid.data {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::File::create(path)?.write_all(&bytes)
}
