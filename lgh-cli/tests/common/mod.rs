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

/// `lgh args`, which must succeed (the panic shows its stderr).
pub fn lgh_ok(args: &[&str]) -> Output {
    let o = lgh(args);
    assert!(
        o.status.success(),
        "lgh {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// The JSON `lgh args` prints on stdout; it must succeed.
pub fn lgh_json(args: &[&str]) -> serde_json::Value {
    let o = lgh_ok(args);
    serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("lgh {args:?}: not JSON on stdout: {e}"))
}

/// `lgh args` run in `dir` fails with one line of error that contains `names`; its output,
/// for the exit code.
pub fn assert_refused(dir: &Path, args: &[&str], names: &str) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_lgh"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(!o.status.success(), "{args:?}");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(names), "{args:?}: {err} should name {names}");
    o
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
