//! What the end-to-end tests of the `lgh` binary share.

#![allow(dead_code)] // each test crate uses its own part of it

use std::path::Path;
use std::process::{Command, Output};

/// `lgh args`, run to completion.
pub fn lgh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lgh"))
        .args(args)
        .output()
        .expect("run lgh")
}

/// `lgh args` run in `dir` fails with one line of error that contains `names`.
pub fn assert_refused(dir: &Path, args: &[&str], names: &str) {
    let o = Command::new(env!("CARGO_BIN_EXE_lgh"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(!o.status.success(), "{args:?}");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(names), "{args:?}: {err} should name {names}");
}

/// `lgh demo` at 32³ voxels, `width × height`, quiet, written to `out`, with `extra` arguments.
pub fn small_demo(out: &Path, (width, height): (usize, usize), extra: &[&str]) -> Output {
    let (w, h) = (width.to_string(), height.to_string());
    let mut args = vec![
        "demo",
        "--resolution",
        "32",
        "--width",
        &w,
        "--height",
        &h,
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    lgh(&args)
}

/// The pixels of an EXR as bits, for comparisons that must be exact.
pub fn exr_bits(path: &Path) -> Vec<[u32; 3]> {
    lgh_image::read_exr(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}
