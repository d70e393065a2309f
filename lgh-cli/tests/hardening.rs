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
