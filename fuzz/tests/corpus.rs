//! Replays the saved fuzz corpus (`fuzz/corpus/TARGET/*`): every input that coverage-guided
//! fuzzing kept, and every crash it found once, still returns without a panic, within a time
//! limit of its own. Deterministic, so it runs in CI; the fuzzing itself is `fuzz/README.md`'s.

use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

/// How long one input may take before the test calls it a hang: 60 s. Not a speed check (tests
/// assert correctness, ARCHITECTURE.md "Measuring"; the parsers' speed is the fuzzer's to
/// watch): the hangs fuzzing found (`hang-*`) ran without end or for seconds and gigabytes, and
/// every saved input now returns in milliseconds in a debug build, so only a hang come back can
/// reach this limit. The standard test harness has no timeout of its own: without this, a
/// regressed hang would stall CI instead of failing it.
const HANG: Duration = Duration::from_secs(60);

#[test]
fn every_saved_input_returns() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus");
    for (name, target) in lgh_fuzz::TARGETS {
        let dir = root.join(name);
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file())
            .collect();
        files.sort();
        assert!(!files.is_empty(), "{}: no saved inputs", dir.display());
        for f in &files {
            let data = std::fs::read(f).unwrap();
            // A panic names the file: a regression of a crash fuzzing once found. The input
            // runs on a thread of its own so that a hang fails the test, naming the file,
            // instead of stalling it (a hung thread is left behind; the test fails at once).
            let (done, finished) = mpsc::channel();
            std::thread::spawn(move || {
                let returned = std::panic::catch_unwind(|| target(&data)).is_ok();
                let _ = done.send(returned);
            });
            match finished.recv_timeout(HANG) {
                Ok(returned) => assert!(returned, "{} panicked", f.display()),
                Err(_) => panic!("{} did not return within {HANG:?}: a hang", f.display()),
            }
        }
        println!("{name}: {} inputs", files.len());
    }
}
