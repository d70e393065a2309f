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
    explosion_of_size(vdb, out, ("16", "12"), extra)
}

/// `lgh explosion` of `vdb` without shadows at `width`×`height`, quiet, to `out`, with `extra`
/// arguments.
fn explosion_of_size(
    vdb: &Path,
    out: &Path,
    (width, height): (&str, &str),
    extra: &[&str],
) -> Output {
    let mut args = vec![
        "explosion",
        "--vdb",
        vdb.to_str().unwrap(),
        "--shadows",
        "none",
        "--width",
        width,
        "--height",
        height,
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
    // Brute force sums every light at every step of every pixel's march (about 3 minutes
    // at 16×12 in a debug build): a NaN light would reach any of its pixels, so 4×3 of them.
    for (backend, size) in [("lgh", ("16", "12")), ("brute", ("4", "3"))] {
        let out = dir.path().join(format!("{backend}.exr"));
        let o = explosion_of_size(
            &f56,
            &out,
            size,
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

/// Polls `done` every 20 ms until it holds (true) or a minute has passed (false): the guard
/// against a hang, far past any normal time. How fast `lgh` is, is not asserted (tests assert
/// correctness, ARCHITECTURE.md "Measuring").
#[cfg(unix)]
fn within_a_minute(mut done: impl FnMut() -> bool) -> bool {
    (0..3000).any(|_| {
        done() || {
            std::thread::sleep(std::time::Duration::from_millis(20));
            false
        }
    })
}

/// Starts `lgh args` in `dir`, waits until `ready()` holds while it still runs, sends it
/// `signal` (`INT` or `TERM`) and waits for it to exit: its exit code. Either wait fails as hung
/// after a minute ([`within_a_minute`]), and kills `lgh`.
#[cfg(unix)]
fn interrupt(dir: &Path, args: &[&str], ready: impl FnMut() -> bool, signal: &str) -> i32 {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lgh"))
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    fn hung(child: &mut std::process::Child, what: &str) -> ! {
        let _ = child.kill();
        let _ = child.wait();
        panic!("hung: {what} after a minute");
    }
    if !within_a_minute(ready) {
        hung(&mut child, "not ready");
    }
    assert!(
        child.try_wait().unwrap().is_none(),
        "lgh finished before the signal: give it more work"
    );
    // The shell's own `kill`: no package needed.
    let kill = Command::new("sh")
        .args([
            "-c",
            "kill -s \"$0\" \"$1\"",
            signal,
            &child.id().to_string(),
        ])
        .status()
        .unwrap();
    assert!(kill.success());
    let mut status = None;
    if !within_a_minute(|| {
        status = child.try_wait().unwrap();
        status.is_some()
    }) {
        hung(&mut child, &format!("still running after SIG{signal}"));
    }
    status.unwrap().code().expect("exited, not killed")
}

/// Files in `dir` whose name starts with `.lgh-`: temporary files of atomic writes.
fn temporary_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".lgh-"))
        .collect()
}

/// SIGINT during a render: `lgh` stops with exit code 130 before the image is finished, and
/// writes nothing (no output, no temporary file).
#[cfg(unix)]
#[test]
fn sigint_stops_a_render_at_once_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "demo",
        "--resolution",
        "96",
        "--width",
        "640",
        "--height",
        "360",
        "--quiet",
        "--out",
        "demo.exr",
    ];
    // Ready once the render has had a second to start (it writes nothing before it ends).
    let ready = || {
        std::thread::sleep(std::time::Duration::from_secs(1));
        true
    };
    assert_eq!(interrupt(dir.path(), &args, ready, "INT"), 130);
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
}

/// SIGTERM in the middle of a sequence: exit code 143, every finished frame kept whole (its EXR
/// readable, its PNG beside it), no temporary file, and the frames after it not begun.
#[cfg(unix)]
#[test]
fn sigterm_keeps_every_finished_frame_of_a_sequence() {
    let Some(f56) = lgh_tests::fire_frame(56) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "explosion",
        "--vdb",
        f56.to_str().unwrap(),
        "--frames",
        "50..56",
        "--width",
        "96",
        "--height",
        "64",
        "--quiet",
        "--out",
        "fire.exr",
    ];
    let first_png = dir.path().join("fire_0050.png");
    assert_eq!(
        interrupt(dir.path(), &args, || first_png.exists(), "TERM"),
        143
    );
    assert_eq!(temporary_files(dir.path()), Vec::<String>::new());
    let mut finished = 0;
    for f in 50..=56 {
        let exr = dir.path().join(format!("fire_{f:04}.exr"));
        let png = exr.with_extension("png");
        assert_eq!(
            exr.exists(),
            png.exists(),
            "frame {f}: EXR and PNG go together"
        );
        if exr.exists() {
            let img = lgh_image::read_exr(&exr).unwrap();
            assert_eq!((img.width, img.height), (96, 64));
            finished += 1;
        }
    }
    assert!((1..7).contains(&finished), "{finished} frames finished");
}

/// A tmpfs of `kib` KiB mounted on a fresh folder, unmounted when dropped; `None` (after saying
/// SKIPPED) where this process may not mount (not root, no CAP_SYS_ADMIN).
#[cfg(target_os = "linux")]
struct Scratch {
    dir: tempfile::TempDir,
}

#[cfg(target_os = "linux")]
impl Scratch {
    fn mount(kib: u32) -> Option<Scratch> {
        let dir = tempfile::tempdir().unwrap();
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={kib}k"), "tmpfs"])
            .arg(dir.path())
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            lgh_tests::Piece::Tmpfs.missing("cannot mount a tmpfs here");
            return None;
        }
        Some(Scratch { dir })
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Remounts it read-only.
    fn read_only(&self) {
        let s = Command::new("mount")
            .args(["-o", "remount,ro"])
            .arg(self.path())
            .status()
            .unwrap();
        assert!(s.success());
    }
}

#[cfg(target_os = "linux")]
impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

/// `lgh demo` into `dir`, over a previous `demo.exr` and `demo.png`: it fails with one line
/// naming the file and the system's reason, and the previous files are untouched, with no
/// temporary file beside them.
#[cfg(target_os = "linux")]
fn assert_refused_whole(dir: &Path, previous: &[u8], reason: &str) {
    let out = dir.join("demo.exr");
    let o = common::small_demo(&out, (64, 36), &[]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(reason), "{err}");
    for f in ["demo.exr", "demo.png"] {
        assert_eq!(std::fs::read(dir.join(f)).unwrap(), previous, "{f}");
    }
    assert_eq!(temporary_files(dir), Vec::<String>::new());
}

/// A full disk while writing: a clear error, the previous files of that name untouched.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_keeps_the_previous_output() {
    let Some(disk) = Scratch::mount(48) else {
        return;
    };
    let previous = b"the previous frame".repeat(100);
    for f in ["demo.exr", "demo.png"] {
        std::fs::write(disk.path().join(f), &previous).unwrap();
    }
    // The image needs more than the space left (64×36 floats, compressed, plus the PNG).
    std::fs::write(disk.path().join("filler"), vec![7u8; 40 << 10]).unwrap();
    assert_refused_whole(disk.path(), &previous, "No space left on device");
}

/// A read-only output folder: a clear error, the previous files untouched.
#[cfg(target_os = "linux")]
#[test]
fn a_read_only_folder_keeps_the_previous_output() {
    let Some(disk) = Scratch::mount(256) else {
        return;
    };
    let previous = b"the previous frame".to_vec();
    for f in ["demo.exr", "demo.png"] {
        std::fs::write(disk.path().join(f), &previous).unwrap();
    }
    disk.read_only();
    assert_refused_whole(
        disk.path(),
        &previous,
        "Read-only file system (os error 30)\n",
    );
}

/// Two processes rendering to the same name at once: the EXR left is one of them whole (it
/// reads back, with one process's header), never a mix, and no temporary file is left.
#[test]
fn two_writers_of_one_name_leave_one_whole_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo.exr");
    let run = |alpha: &'static str| {
        let out = out.clone();
        std::thread::spawn(move || common::small_demo(&out, (64, 36), &["--alpha", alpha]))
    };
    for _ in 0..3 {
        let (a, b) = (run("1"), run("4"));
        for o in [a.join().unwrap(), b.join().unwrap()] {
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        let img = lgh_image::read_exr(&out).unwrap();
        assert_eq!((img.width, img.height), (64, 36));
        let attrs = lgh_image::read_exr_attributes(&out).unwrap();
        let alpha = attrs.iter().find(|(k, _)| k == "lgh:alpha").unwrap();
        assert!(alpha.1 == "1" || alpha.1 == "4", "{alpha:?}");
        assert_eq!(temporary_files(dir.path()), Vec::<String>::new());
    }
}
