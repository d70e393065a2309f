//! `lgh inspect FILE.vdb`: what `vdb_print` prints and more, per grid.

use std::path::PathBuf;

use lgh_volume::vdb;
use serde_json::{json, Value};

/// Arguments of `lgh inspect`.
#[derive(Debug, clap::Args)]
pub struct InspectArgs {
    /// The OpenVDB file.
    pub file: PathBuf,
    /// Print JSON: {"grids": [{"name", "value_type", "voxel_size", "active_voxels", "bbox_min",
    /// "bbox_max", "min", "max", "sum"}, …]} (vector grids: statistics of the vector length;
    /// non-finite numbers are null).
    #[arg(long)]
    pub json: bool,
}

fn number(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

/// What `lgh inspect --json` prints of the OpenVDB file `path`: `{"grids": [...]}` (see
/// [`InspectArgs::json`]). A missing file is a [`MissingFile`](crate::files::MissingFile).
pub fn report(path: &std::path::Path) -> Result<Value, crate::Error> {
    crate::files::check_file(path)?;
    let file = vdb::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(json!({ "grids": grids_json(&file, &stats(&file)) }))
}

/// Each grid's statistics.
fn stats(file: &vdb::VdbFile) -> Vec<vdb::GridStats> {
    file.grids.iter().map(|g| g.stats()).collect()
}

/// The `grids` of [`report`].
fn grids_json(file: &vdb::VdbFile, stats: &[vdb::GridStats]) -> Vec<Value> {
    file.grids
        .iter()
        .zip(stats)
        .map(|(g, s)| {
            let (lo, hi) = s
                .bbox
                .map_or((Value::Null, Value::Null), |(a, b)| (json!(a), json!(b)));
            json!({
                "name": g.name,
                "value_type": g.value_type.name(),
                "voxel_size": g.voxel_size,
                "active_voxels": s.active_voxels,
                "bbox_min": lo,
                "bbox_max": hi,
                "min": number(s.min),
                "max": number(s.max),
                "sum": number(s.sum),
            })
        })
        .collect()
}

/// Runs `lgh inspect`.
pub fn run(args: &InspectArgs) -> Result<(), crate::Error> {
    let file = vdb::read(&args.file).map_err(|e| format!("{}: {e}", args.file.display()))?;
    let stats = stats(&file);
    let grids = grids_json(&file, &stats);
    if args.json {
        say!("{}", json!({ "grids": grids }));
        return Ok(());
    }
    say!(
        "{}: OpenVDB file format {}, library {}.{}, {} grids",
        args.file.display(),
        file.format_version,
        file.library_version.0,
        file.library_version.1,
        file.grids.len()
    );
    for (g, s) in file.grids.iter().zip(&stats) {
        let bbox = s.bbox.map_or("empty".to_string(), |(a, b)| {
            format!("({},{},{})->({},{},{})", a[0], a[1], a[2], b[0], b[1], b[2])
        });
        say!(
            "  {:<20} {:<6}{} voxel {:.6} {:>28} {:>10} active  min {:<12.6e} max {:<12.6e} sum {:.6e}{}",
            g.name,
            g.value_type.name(),
            if g.half_float { " (half)" } else { "       " },
            g.voxel_size[0],
            bbox,
            s.active_voxels,
            s.min,
            s.max,
            s.sum,
            if g.value_type.components() == 3 { "  (of |v|)" } else { "" },
        );
    }
    Ok(())
}
