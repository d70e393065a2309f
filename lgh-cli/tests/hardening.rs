//! The `lgh` binary under the conditions of a shared render farm: files other users must read,
//! interrupted renders, full disks and read-only folders (issue 16).

mod common;

use std::path::Path;
use std::process::{Command, Output};

/// `lgh args` run by `sh` under `umask`, as a farm's job wrapper would start it.
#[cfg(unix)]
fn lgh_under_umask(umask: &str, args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!("umask {umask} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_lgh"))
        .args(args)
        .output()
        .expect("run lgh through sh")
}

#[cfg(unix)]
fn mode(p: &Path) -> u32 {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).unwrap().permissions().mode() & 0o777
}

/// Written images get `0o666 & !umask`, as a plain `create` would, not the temporary file's
/// private 0600: under umask 022 the compositor's user can read the frames.
#[cfg(unix)]
#[test]
fn outputs_get_the_permissions_the_umask_asks_for() {
    let dir = tempfile::tempdir().unwrap();
    for (umask, want) in [("022", 0o644), ("027", 0o640), ("077", 0o600)] {
        let out = dir.path().join(format!("demo-{umask}.exr"));
        let o = lgh_under_umask(
            umask,
            &[
                "demo",
                "--resolution",
                "32",
                "--width",
                "8",
                "--height",
                "6",
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(mode(&out), want, "EXR under umask {umask}");
        assert_eq!(
            mode(&out.with_extension("png")),
            want,
            "PNG under umask {umask}"
        );
    }
}

/// `lgh explosion` of `vdb` without shadows at 16×12, quiet, to `out`, with `extra` arguments.
fn small_explosion(vdb: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "explosion",
        "--vdb",
        vdb.to_str().unwrap(),
        "--shadows",
        "none",
        "--width",
        "16",
        "--height",
        "12",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    common::lgh(&args)
}

/// The report of issue 16: `--min-temperature 100` on the real fire wrote NaN pixels (a cold
/// blackbody's colour normalised by a luminance that underflows), on the hierarchy and on brute
/// force alike. Now both render a finite image, with more lights than at the default 800 K.
#[test]
fn cold_voxels_render_finite_images() {
    let Some(f56) = lgh_tests::fire_frame(56) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    for backend in ["lgh", "brute"] {
        let out = dir.path().join(format!("{backend}.exr"));
        let o = small_explosion(
            &f56,
            &out,
            &["--min-temperature", "100", "--backend", backend],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let img = lgh_image::read_exr(&out).unwrap();
        assert_eq!(lgh_image::first_non_finite(&img), None, "{backend}");
        assert!(
            img.pixels.iter().any(|p| p.max_element() > 0.0),
            "{backend}"
        );
    }
}

/// Writes `img` as a float EXR with the `exr` crate directly: lgh's own writer refuses images
/// with non-finite pixels, and these tests need such files as input.
fn write_raw_exr(path: &Path, img: &lgh_image::Image) {
    exr::prelude::write_rgb_file(path, img.width, img.height, |x, y| {
        let p = img.get(x, y);
        (p.x, p.y, p.z)
    })
    .unwrap();
}

/// `lgh compare` never prints `NaN%`: a NaN in either image is an error naming the pixel, and a
/// black reference leaves the relative error undefined, said in words (and `null` in JSON).
#[test]
fn compare_says_why_an_error_cannot_be_relative() {
    use lgh_core::glam::Vec3;
    let dir = tempfile::tempdir().unwrap();
    let path = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let mut lit = lgh_image::Image::new(4, 3);
    lit.pixels.fill(Vec3::splat(0.5));
    let mut nan = lit.clone();
    nan.set(1, 2, Vec3::new(f32::NAN, 0.0, 0.0));
    write_raw_exr(Path::new(&path("lit.exr")), &lit);
    write_raw_exr(Path::new(&path("nan.exr")), &nan);
    write_raw_exr(Path::new(&path("black.exr")), &lgh_image::Image::new(4, 3));

    for (a, r) in [("nan.exr", "lit.exr"), ("lit.exr", "nan.exr")] {
        let o = common::lgh(&["compare", &path(a), &path(r)]);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&format!(
                "{}: pixel (1, 2) is [NaN, 0, 0], not finite",
                path("nan.exr")
            )),
            "{err}"
        );
    }

    let o = common::lgh(&["compare", &path("lit.exr"), &path("black.exr")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("relative RMSE undefined") && !text.contains("NaN"),
        "{text}"
    );
    let o = common::lgh(&["compare", "--json", &path("lit.exr"), &path("black.exr")]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["rel_rmse"].is_null(), "{v}");
    assert!(v["max_abs"].as_f64().unwrap() > 0.0, "{v}");
}

/// A run without a single light is an error that says why in one line (which grid, which
/// flag), before any work and with nothing written; `--allow-dark` renders it anyway, with the
/// reason as a warning. (A plume's zero `flame` grid is checked on synthetic volumes in
/// `dark.rs`: the dev data holds no plume.)
#[test]
fn a_run_without_lights_says_why() {
    let Some(f56) = lgh_tests::fire_frame(56) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cold.exr");
    let cold = ["--min-temperature", "5000"];
    let o = small_explosion(&f56, &out, &cold);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("'temperature' grid holds 2.99")
            && err.contains("not above --min-temperature 5000")
            && err.contains("--allow-dark"),
        "{err}"
    );
    assert!(!out.exists() && !out.with_extension("png").exists());

    let o = small_explosion(&f56, &out, &[cold[0], cold[1], "--allow-dark"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.starts_with("lgh: warning: no light in any of the 1 frame(s)"),
        "{err}"
    );
    let img = lgh_image::read_exr(&out).unwrap();
    assert!(img.pixels.iter().all(|p| *p == lgh_core::glam::Vec3::ZERO));
}
