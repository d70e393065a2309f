//! Resource limits of the mesh reader as tested properties (issue 16), each in this binary of
//! its own so the process's peak resident memory (`VmHWM`) is the test's.

use lgh_vpl::{Mesh, MeshError, MAX_LINE_BYTES};

/// Peak resident memory of this process so far, in MiB (Linux's `VmHWM`).
fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let kib: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap();
    kib / 1024.0
}

/// An OBJ file of one 4 GiB line (a sparse file: no disk is used) is refused after its first
/// MiB, in bounded memory, with the line named (reading it whole would take 4 GiB; how long the
/// refusal takes is not asserted: tests assert correctness, ARCHITECTURE.md "Measuring").
#[cfg(target_os = "linux")]
#[test]
fn a_4_gib_line_is_refused_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.obj");
    let f = std::fs::File::create(&path).unwrap();
    f.set_len(4 << 30).unwrap();
    drop(f);
    let e = Mesh::load_obj(&path).unwrap_err();
    let peak = peak_rss_mib();
    println!("refused, peak RSS {peak:.1} MiB: {e}");
    assert!(
        matches!(&e, MeshError::Parse { message, .. }
            if message == &format!("line 1 is longer than {MAX_LINE_BYTES} bytes")),
        "{e}"
    );
    // 4 GiB read whole would be 4096 MiB; the limit reads 1 MiB of it.
    assert!(peak < 64.0, "peak RSS {peak:.1} MiB");
}
