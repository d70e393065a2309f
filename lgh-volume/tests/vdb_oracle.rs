//! The VDB reader against the official OpenVDB library, on the real Blender fire cache in
//! `../shared/data/volumes` (not part of the repository).
//!
//! The oracle is `tests/oracle/vdb_stats.py` (Debian's python3-openvdb and libopenvdb-tools). When
//! the data is missing the tests say so and skip; when the oracle is missing (`/usr/bin/python3`
//! cannot import `pyopenvdb` and `numpy`, or there is no `vdb_print`) they say SKIPPED and pass,
//! unless `LGH_REQUIRE_OPENVDB` is set (`.ci/run` installs the oracle and sets it), where they
//! fail ([`lgh_tests::Piece`]). With the oracle there, any failure of its scripts fails the test.

use std::path::{Path, PathBuf};
use std::process::Command;

use lgh_volume::vdb;
use serde_json::Value;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// The dev fire's frames, or `None` after saying SKIPPED ([`lgh_tests::data`]).
fn fire_frames() -> Option<Vec<PathBuf>> {
    let dir = lgh_tests::data("volumes/blender_fire_pesichra/data")?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "vdb"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no .vdb frame in {}", dir.display());
    Some(files)
}

fn oracle(path: &Path) -> Result<Value, String> {
    let out = Command::new("/usr/bin/python3")
        .arg(workspace().join("tests/oracle/vdb_stats.py"))
        .arg(path)
        .output()
        .map_err(|e| format!("cannot run /usr/bin/python3: {e}"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    serde_json::from_slice(&out.stdout).map_err(|e| e.to_string())
}

/// A number from the oracle's JSON, where non-finite values are strings ("inf", "nan").
fn num(v: &Value) -> f64 {
    match v {
        Value::Number(n) => n.as_f64().unwrap(),
        Value::String(s) => s.parse().unwrap(),
        other => panic!("not a number: {other}"),
    }
}

/// Runs `script` (Python with pyopenvdb and numpy; it writes the file `sys.argv[1]`) for `path`:
/// a file written by the official library.
fn write_with_openvdb(script: &str, path: &Path) {
    let out = Command::new("/usr/bin/python3")
        .args(["-c", script, path.to_str().unwrap()])
        .output();
    let out = out.expect("/usr/bin/python3 ran a moment ago");
    assert!(
        out.status.success(),
        "the OpenVDB writer failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

#[test]
fn every_fire_frame_matches_the_official_library() {
    let Some(files) = fire_frames() else {
        return;
    };
    if !lgh_tests::openvdb() {
        return;
    }
    for path in &files {
        let ours = vdb::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(ours.format_version, 224);
        let theirs = oracle(path)
            .unwrap_or_else(|e| panic!("the OpenVDB oracle on {}: {e}", path.display()));
        let grids = theirs["grids"].as_array().unwrap();
        assert_eq!(grids.len(), ours.grids.len(), "{}", path.display());
        for t in grids {
            let name = t["name"].as_str().unwrap();
            let g = ours
                .grid(name)
                .unwrap_or_else(|| panic!("grid {name} missing"));
            let s = g.stats();
            let ctx = format!("{} / {name}", path.display());
            assert_eq!(t["value_type"].as_str(), Some(g.value_type.name()), "{ctx}");
            assert_eq!(t["active_voxels"].as_u64(), Some(s.active_voxels), "{ctx}");
            let (lo, hi) = s.bbox.unwrap();
            assert_eq!(t["bbox_min"], serde_json::json!(lo), "{ctx}");
            assert_eq!(t["bbox_max"], serde_json::json!(hi), "{ctx}");
            // Min and max are one stored value each (vector grids: one length, computed the same
            // way in f64), so they must agree exactly.
            assert!(
                same(num(&t["min"]), s.min),
                "{ctx}: min {} vs {}",
                t["min"],
                s.min
            );
            assert!(
                same(num(&t["max"]), s.max),
                "{ctx}: max {} vs {}",
                t["max"],
                s.max
            );
            if let Some(sum) = t.get("sum") {
                // Both sum the same f32 values in f64, possibly in another order: the difference
                // is bounded by N·ε₆₄·Σ|v| (N ≤ 300,000 voxels, so below 1e-10 relative).
                let (a, b) = (num(sum), s.sum);
                assert!(
                    same(a, b) || (a - b).abs() <= 1e-10 * a.abs().max(b.abs()),
                    "{ctx}: sum {a} vs {b}"
                );
                for (k, v) in t["voxel_size"].as_array().unwrap().iter().enumerate() {
                    assert!(
                        (num(v) - g.voxel_size[k]).abs() <= 1e-12 * num(v),
                        "{ctx}: voxel size"
                    );
                }
            }
        }
    }
}

#[test]
fn truncated_or_corrupted_files_are_errors_not_crashes() {
    let Some(files) = fire_frames() else {
        return;
    };
    let bytes = std::fs::read(&files[0]).unwrap();
    // Every truncation is an error.
    for i in 0..150 {
        let cut = (bytes.len() as u64 * i / 150) as usize;
        assert!(vdb::parse(&bytes[..cut]).is_err(), "cut at {cut}");
    }
    // Corrupted bytes: an error or a file, never a panic, hang or giant allocation.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..150 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let mut b = bytes.clone();
        let at = (state % b.len() as u64) as usize;
        b[at] ^= (state >> 32) as u8 | 1;
        let _ = vdb::parse(&b);
    }
}

/// `tools/cycles/write_vdb.py` (the Cycles comparison's writer, through the official library)
/// turns the raw grids of `examples/export_grids.rs` into a Z-up OpenVDB file: read back by our
/// reader, every voxel of the Y-up volume is at its turned place, `(x, y, z) -> (x, -z, y)`,
/// with its value (OpenVDB's placement: voxel `i`'s value at the transform of `i`).
#[test]
fn the_cycles_comparison_writer_round_trips_through_openvdb() {
    if !lgh_tests::openvdb() {
        return;
    }
    let v = lgh_volume::procedural::explosion(32, 0.5).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("x");
    let p = prefix.to_str().unwrap();
    let d = &v.density;
    let meta = serde_json::json!({
        "dims": d.dims, "voxel_size": d.voxel_size, "up": "y",
        "origin": [d.origin.x, d.origin.y, d.origin.z], "grids": ["density", "temperature"],
    });
    std::fs::write(format!("{p}.json"), meta.to_string()).unwrap();
    for (name, g) in [("density", &v.density), ("temperature", &v.temperature)] {
        let bytes: Vec<u8> = g.data.iter().flat_map(|x| x.to_le_bytes()).collect();
        std::fs::write(format!("{p}.{name}.f32"), bytes).unwrap();
    }
    let out = Command::new("/usr/bin/python3")
        .arg(workspace().join("tools/cycles/write_vdb.py"))
        .arg(p)
        .output();
    let out = out.expect("/usr/bin/python3 ran a moment ago");
    assert!(
        out.status.success(),
        "tools/cycles/write_vdb.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let file = vdb::read(&prefix.with_extension("vdb")).unwrap();
    for (name, ours) in [("density", &v.density), ("temperature", &v.temperature)] {
        let g = file.grid(name).unwrap();
        let (lo, hi) = g.active_bbox().unwrap();
        let back = lgh_volume::DenseGrid::from_vdb(g, lo, hi).unwrap();
        assert!((back.voxel_size - ours.voxel_size).abs() < 1e-7);
        let mut checked = 0;
        for k in 0..ours.dims[2] {
            for j in 0..ours.dims[1] {
                for i in 0..ours.dims[0] {
                    let want = ours.get(i, j, k);
                    let c = ours.centre(i, j, k);
                    // At a voxel centre the trilinear lookup is the voxel's value.
                    let got = back.sample(lgh_volume::lgh_core::glam::Vec3::new(c.x, -c.z, c.y));
                    assert!(
                        (got - want).abs() <= 1e-5 * want.abs().max(1.0),
                        "{name} ({i}, {j}, {k}): {got} vs {want}"
                    );
                    checked += usize::from(want != 0.0);
                }
            }
        }
        assert!(checked > 500, "{name}: only {checked} voxels hold a value");
    }
}

/// An RGB emission as Houdini writes it: a vec3s `emission` grid beside a float `density`,
/// written by the official library. Read as it is: each channel at its voxel, the temperature
/// grid each voxel's largest channel; a flame grid named with it is refused, saying why.
#[test]
fn a_vec3_emission_grid_is_read_as_rgb() {
    if !lgh_tests::openvdb() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rgb_0001.vdb");
    let script = r#"
import sys
import numpy as np
import pyopenvdb as vdb
n = 6
density = np.zeros((n, n, n), dtype=np.float32)
emission = np.zeros((n, n, n, 3), dtype=np.float32)
for i in range(n):
    for j in range(n):
        for k in range(n):
            density[i, j, k] = 0.1 + 0.01 * (i + n * j)
            if 1 <= i <= 4 and 1 <= j <= 4 and 1 <= k <= 4:
                emission[i, j, k] = (i + 0.5, 0.25 * j, 0.125 * k)
d = vdb.FloatGrid(); d.copyFromArray(density, tolerance=0.0); d.name = "density"
e = vdb.Vec3SGrid(); e.copyFromArray(emission, tolerance=(0.0, 0.0, 0.0)); e.name = "emission"
f = vdb.FloatGrid(); f.copyFromArray(density, tolerance=0.0); f.name = "flame"
for g in (d, e, f):
    g.transform = vdb.createLinearTransform(voxelSize=0.25)
vdb.write(sys.argv[1], grids=[d, e, f])
"#;
    write_with_openvdb(script, &path);
    let names = lgh_volume::cache::GridNames {
        emission: "emission".into(),
        ..Default::default()
    };
    let placement = lgh_volume::cache::Placement::AsWritten;
    let frames = lgh_volume::cache::load(std::slice::from_ref(&path), &names, placement).unwrap();
    let v = &frames[0];
    let colour = v.colour.as_deref().expect("an RGB emission");
    // Blender's `flame` is in the file and found by default, but it scales a blackbody: unused.
    assert!(v.flame.is_none());
    let d = &v.density;
    assert_eq!(
        d.dims, [8; 3],
        "6³ active voxels and a voxel of background around them"
    );
    let mut lit = 0;
    for k in 0..d.dims[2] {
        for j in 0..d.dims[1] {
            for i in 0..d.dims[0] {
                // The dense box starts a voxel of background before the first active voxel,
                // index (0, 0, 0) here ([`lgh_volume::cache::BACKGROUND_MARGIN`]).
                let p = d.centre(i, j, k) / 0.25;
                let [a, b, c] = [p.x, p.y, p.z].map(|x| x.round() as i32);
                let want = if (1..=4).contains(&a) && (1..=4).contains(&b) && (1..=4).contains(&c) {
                    [a as f32 + 0.5, 0.25 * b as f32, 0.125 * c as f32]
                } else {
                    [0.0; 3]
                };
                let got = [0, 1, 2].map(|ch| colour[ch].get(i, j, k));
                assert_eq!(got, want, "voxel ({a}, {b}, {c})");
                assert_eq!(
                    v.temperature.get(i, j, k),
                    want[0].max(want[1]).max(want[2])
                );
                lit += usize::from(want[0] > 0.0);
            }
        }
    }
    assert_eq!(lit, 64);
    let named = lgh_volume::cache::GridNames {
        flame: Some("flame".into()),
        flame_required: true,
        ..names.clone()
    };
    let err = lgh_volume::cache::load(std::slice::from_ref(&path), &named, placement).unwrap_err();
    assert!(err.to_string().contains("RGB (vec3) emission"), "{err}");
    // Nor is an RGB emission a flame to make a temperature of.
    let made = lgh_volume::cache::GridNames {
        emission_values: lgh_volume::cache::EmissionValues::BlenderFlame {
            ignition: 1.5,
            max_temperature: 3.0,
        },
        ..names
    };
    let err = lgh_volume::cache::load(&[path], &made, placement).unwrap_err();
    assert!(err.to_string().contains("no flame to read"), "{err}");
}

/// Outside its active voxels an OpenVDB grid is its background (zero), and a trilinear lookup
/// (OpenVDB's `BoxSampler`, Cycles' through NanoVDB) falls from the last active voxel's value to
/// zero over the next voxel. A block of emitting voxels that fills its active box, as flames at
/// a domain's wall do, must read so: a voxel of background around the box
/// ([`lgh_volume::cache::BACKGROUND_MARGIN`]), not the outermost values held to their faces.
#[test]
fn outside_the_active_voxels_the_field_falls_to_the_background() {
    if !lgh_tests::openvdb() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("block_0001.vdb");
    let script = r#"
import sys
import numpy as np
import pyopenvdb as vdb
block = np.full((4, 4, 4), 2.0, dtype=np.float32)
grids = []
for name in ("density", "temperature"):
    g = vdb.FloatGrid(); g.copyFromArray(block, tolerance=0.0); g.name = name
    g.transform = vdb.createLinearTransform(voxelSize=0.5)
    grids.append(g)
vdb.write(sys.argv[1], grids=grids)
"#;
    write_with_openvdb(script, &path);
    let names = lgh_volume::cache::GridNames::default();
    let placement = lgh_volume::cache::Placement::AsWritten;
    let frames = lgh_volume::cache::load(&[path], &names, placement).unwrap();
    let t = &frames[0].temperature;
    assert_eq!(t.dims, [6; 3]);
    // Along x through the block's middle (index 1.5 on y and z): active voxels 0..=3 hold 2;
    // from the last centre (index 3) the value falls linearly to 0 at index 4, and stays 0.
    for (x, want) in [
        (0.0, 2.0),
        (3.0, 2.0),
        (3.25, 1.5),
        (3.5, 1.0),
        (3.75, 0.5),
        (4.0, 0.0),
        (4.4, 0.0),
        (-0.5, 1.0),
        (-1.0, 0.0),
    ] {
        let p = lgh_volume::lgh_core::glam::Vec3::new(x, 1.5, 1.5) * 0.5;
        let got = t.sample(p);
        assert!(
            (got - want).abs() < 1e-5,
            "index {x}: {got}, OpenVDB's trilinear {want}"
        );
    }
}
