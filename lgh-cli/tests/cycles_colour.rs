//! The Cycles comparison's scenes channel by channel (issue 54): `lgh explosion` renders the
//! procedural fireball and explosion and the dev fire as `tools/cycles/compare.py` renders them,
//! and each channel's mean is held to a converged Cycles render's — Blender 3.4.1 with lgh's
//! defaults, 5.2.3 with `--emission-interpolation attributes` — whose means
//! `tools/cycles/colour.py` committed (`tools/cycles/colour-3.4.json`, `colour-5.2.json`).
//!
//! Luminance hid a blue 10% off on a fire; these hold red, green and blue each. A release test
//! (`cargo test --release -p lgh-cli --test cycles_colour -- --ignored`, run by `.ci/run`): it
//! renders 128² images of volumes of up to 128³ voxels. The procedural volumes go through the
//! comparison's own VDB writer (`tools/cycles/write_vdb.py`, the official library); the dev
//! fire is read from the shared data and skipped without it.

use std::path::{Path, PathBuf};
use std::process::Command;

use lgh_core::glam::DVec3;
use serde_json::Value;

/// `lgh explosion`'s arguments for `scene`, as compare.py's (the medium σ_t = 4 · density,
/// albedo 0.7, 128², the scene's camera and temperature scale) with `setting`'s.
fn render(vdb: &Path, scene: &str, setting: &str, out: &Path) -> DVec3 {
    let (camera, temperature_scale) = match scene {
        "fire56" => ("0.53,-2.16,0.455,0.53,0.34,0.455,40", "1000"),
        _ => ("0,-4,0,0,0,0,40", "1"),
    };
    let mut args = vec![
        "explosion",
        "--vdb",
        vdb.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--camera",
        camera,
        "--width",
        "128",
        "--height",
        "128",
        "--density-scale",
        "4",
        "--albedo",
        "0.7",
        "--temperature-scale",
        temperature_scale,
        "--no-domain-offset",
        "--quiet",
    ];
    if setting == "attributes" {
        args.extend(["--emission-interpolation", "attributes"]);
    }
    let o = Command::new(env!("CARGO_BIN_EXE_lgh"))
        .args(&args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let image = lgh_image::read_exr(out).unwrap();
    let sum = image
        .pixels
        .iter()
        .fold(DVec3::ZERO, |a, p| a + p.as_dvec3());
    sum / image.pixels.len() as f64
}

/// The procedural `kind` (`fireball` at 64³ or `explosion` at 128³, t = 0.5 s) as compare.py
/// writes it: raw grids, then write_vdb.py. `None` without the official library (said).
fn procedural_vdb(dir: &Path, kind: &str) -> Option<PathBuf> {
    if !lgh_tests::openvdb() {
        return None;
    }
    let volume = match kind {
        "fireball" => lgh_volume::procedural::procedural(64, 0.5).unwrap(),
        _ => lgh_volume::procedural::explosion(128, 0.5).unwrap(),
    };
    let prefix = dir.join(kind);
    lgh_volume::export::write_raw_grids(&volume, &prefix, &[("kind", kind)]).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/cycles/write_vdb.py");
    let o = Command::new("/usr/bin/python3")
        .arg(script)
        .arg(&prefix)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    Some(prefix.with_extension("vdb"))
}

/// Cycles' channel means of `scene` in `json`, where `setting` was compared.
fn cycles_means(json: &str, scene: &str, setting: &str) -> DVec3 {
    let v: Value = serde_json::from_str(json).unwrap();
    let m = &v["scenes"][scene][format!("{setting}/after")]["reference_mean_rgb"];
    DVec3::new(
        m[0].as_f64().unwrap(),
        m[1].as_f64().unwrap(),
        m[2].as_f64().unwrap(),
    )
}

/// Each channel's mean within `share` of Cycles' mean of it; a channel whose mean is below 5% of
/// the brightest (the procedural volumes' blue, negative in Cycles: their cool smoke takes blue
/// from the image) within `share` of 5% of the brightest. With the blackbody clamped at 0, as
/// before, that blue erred by 1.3% of the red: 26 times this bound at 1%.
fn check(got: DVec3, want: DVec3, share: f64, what: &str) {
    let top = want.max_element();
    for c in 0..3 {
        let bound = share * want[c].abs().max(0.05 * top);
        let off = got[c] - want[c];
        assert!(
            off.abs() <= bound,
            "{what}, channel {c}: lgh {got} against Cycles {want} (off {off:.3e}, bound {bound:.3e})"
        );
    }
}

/// The target: 1% a channel. Measured at 343f861: the explosion −0.5% and −0.9% in red
/// and green (3.4.1), −0.4% and −0.8% (5.2.3), the closest to the bound; at the former stopping
/// share of 1% its green was −1.3% (docs/cycles.md, "Colour, channel by channel").
const SHARE: f64 = 0.01;

#[test]
#[ignore = "release: cargo test --release -p lgh-cli --test cycles_colour -- --ignored"]
fn the_comparisons_scenes_match_cycles_channel_by_channel() {
    let dir = tempfile::tempdir().unwrap();
    let references = [
        (
            include_str!("../../tools/cycles/colour-3.4.json"),
            "default",
            "3.4.1",
        ),
        (
            include_str!("../../tools/cycles/colour-5.2.json"),
            "attributes",
            "5.2.3",
        ),
    ];
    let mut scenes: Vec<(&str, PathBuf)> = Vec::new();
    for (scene, kind) in [("fireball64", "fireball"), ("explosion128", "explosion")] {
        if let Some(vdb) = procedural_vdb(dir.path(), kind) {
            scenes.push((scene, vdb));
        }
    }
    if let Some(frame) = lgh_tests::fire_frame(56) {
        scenes.push(("fire56", frame));
    }
    for (scene, vdb) in &scenes {
        for (json, setting, blender) in references {
            let out = dir.path().join(format!("{scene}-{setting}.exr"));
            let got = render(vdb, scene, setting, &out);
            let want = cycles_means(json, scene, setting);
            eprintln!("{scene} ({setting}): lgh {got}, Cycles {blender} {want}");
            check(
                got,
                want,
                SHARE,
                &format!("{scene} against Cycles {blender}"),
            );
        }
    }
}
