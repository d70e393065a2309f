//! Resource limits as tested properties (issue 16): files that declare more than any machine
//! holds are each an error in bounded memory, measured as the peak resident memory of the
//! `lgh` process (`getrusage` of the children, through python3), never an out-of-memory kill.
//! How long a refusal takes is not asserted (tests assert correctness, ARCHITECTURE.md
//! "Measuring"); one that hangs is the test harness's timeout.

mod common;

use std::process::{Command, Output};

use lgh_volume::vdb::synthetic::{tiled_file, Storage};

/// `lgh args` and its peak resident memory in MiB.
fn lgh_peak_rss(args: &[&str]) -> (Output, f64) {
    let o = Command::new("python3")
        .arg("-c")
        .arg(
            "import resource, subprocess, sys\n\
             r = subprocess.run(sys.argv[1:], capture_output=True)\n\
             sys.stdout.buffer.write(r.stdout)\n\
             sys.stderr.buffer.write(r.stderr)\n\
             print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr)\n\
             sys.exit(r.returncode)",
        )
        .arg(env!("CARGO_BIN_EXE_lgh"))
        .args(args)
        .output()
        .expect("run python3");
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    let (text, last) = err
        .trim_end()
        .rsplit_once('\n')
        .unwrap_or(("", err.trim_end()));
    let kib: f64 = last.trim().parse().unwrap_or_else(|_| panic!("{err}"));
    let out = Output {
        stderr: text.as_bytes().to_vec(),
        ..o
    };
    (out, kib / 1024.0)
}

/// Asserts `lgh args` failed with one line containing `names`, under `mib` of peak resident
/// memory.
fn assert_refused_within(args: &[&str], names: &str, mib: f64) {
    let (o, peak) = lgh_peak_rss(args);
    let err = String::from_utf8_lossy(&o.stderr);
    println!("{}: peak RSS {peak:.1} MiB: {}", args[0], err.trim());
    assert!(!o.status.success(), "{args:?}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(names), "{err} should name {names}");
    assert!(peak < mib, "peak RSS {peak:.1} MiB");
}

/// A complete VDB file of 253 MB holding 10⁹ active tiles (30,518 nodes of 32³ tiles: one bit
/// each in a mask, and a compressed constant): kept, they would take 32 GB. `lgh inspect`
/// refuses the file as soon as it passes the reader's tile limit; its memory is the file's
/// bytes (read whole) and the 2²² tiles kept until then, 128 MiB.
#[test]
fn a_billion_tiles_are_refused_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tiles.vdb");
    std::fs::write(&path, tiled_file(Storage::Zip, &[], 30_518, 30_518)).unwrap();
    let p = path.to_str().unwrap();
    assert_refused_within(&["inspect", p], "more than 4194304 tiles", 640.0);
}

/// A VDB grid of two active root tiles at the ends of the index space: 2³² voxels a side,
/// 2⁹⁶ in its box. `lgh inspect` describes it; `lgh explosion` refuses to make it dense, at once.
#[test]
fn a_grid_of_2_96_voxels_is_refused_before_any_allocation() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.vdb");
    let ends = [[i32::MIN; 3], [i32::MAX - 4095; 3]];
    std::fs::write(&path, tiled_file(Storage::Zip, &ends, 0, 0)).unwrap();
    let p = path.to_str().unwrap();
    let o = common::lgh(&["inspect", p]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("137438953472 active"), "{text}");
    let out = dir.path().join("out.exr");
    let args = [
        "explosion",
        "--vdb",
        p,
        "--emission-grid",
        "density",
        "--flame-grid",
        "none",
        "--out",
        out.to_str().unwrap(),
    ];
    assert_refused_within(&args, "voxels", 64.0);
    assert!(!out.exists());
}

/// A PLY header announcing 10¹² vertices over a few bytes: refused before any allocation.
#[test]
fn a_ply_of_10_12_vertices_is_refused_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let lights = dir.path().join("lights.ply");
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n\
                  property float x\nproperty float y\nproperty float z\nproperty float r\n\
                  property float g\nproperty float b\nend_header\n";
    std::fs::write(&lights, [header.as_bytes(), &[0u8; 240]].concat()).unwrap();
    let out = dir.path().join("out.ply");
    let l = lights.to_str().unwrap();
    let args = [
        "probes",
        "--lights",
        l,
        "--points",
        l,
        "--out",
        out.to_str().unwrap(),
    ];
    assert_refused_within(&args, "lights.ply", 64.0);
    assert!(!out.exists());
}
