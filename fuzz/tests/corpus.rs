//! Replays the saved fuzz corpus (`fuzz/corpus/TARGET/*`): every input that coverage-guided
//! fuzzing kept, and every crash it found once, still returns without a panic. Deterministic, so
//! it runs in CI; the fuzzing itself is `fuzz/README.md`'s.

use std::path::Path;

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
            // A panic names the file: a regression of a crash fuzzing once found. The hangs
            // fuzzing found (`hang-*`) took 3 to 8 s and 1.6 to 3 GB each in a debug build and
            // now take milliseconds; how long an input takes is not asserted here (tests assert
            // correctness, ARCHITECTURE.md "Measuring"): a real hang is the test harness's
            // timeout, and the speed of the parsers is the fuzzer's to watch (`fuzz/README.md`).
            let done = std::panic::catch_unwind(|| target(&data));
            assert!(done.is_ok(), "{} panicked", f.display());
        }
        println!("{name}: {} inputs", files.len());
    }
}
