//! `lgh-fuzz-afl TARGET`: one of lgh-fuzz's targets under AFL++, in persistent mode.
//!
//! ```text
//! cargo afl build --release
//! cargo afl fuzz -i seeds/vdb -o out/vdb -E 1000000 target/release/lgh-fuzz-afl vdb
//! ```

fn main() {
    let name = std::env::args().nth(1).unwrap_or_default();
    let Some(target) = lgh_fuzz::target(&name) else {
        let names: Vec<_> = lgh_fuzz::TARGETS.iter().map(|(n, _)| *n).collect();
        eprintln!("usage: lgh-fuzz-afl TARGET (one of {})", names.join(", "));
        std::process::exit(2);
    };
    afl::fuzz!(|data: &[u8]| {
        target(data);
    });
}
