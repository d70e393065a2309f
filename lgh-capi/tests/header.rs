//! `include/lgh.h` is generated from `src/lib.rs` by cbindgen (settings: `cbindgen.toml`) and
//! committed, so that a C or C++ user needs no Rust tool to build against the library. This test
//! regenerates it and fails where the committed header is stale; `LGH_BLESS=1 cargo test -p
//! lgh-capi --test header` writes the fresh one.

use std::path::Path;

#[test]
fn the_committed_header_is_what_cbindgen_generates() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).unwrap();
    let mut fresh = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen reads src/lib.rs")
        .write(&mut fresh);
    let path = crate_dir.join("include/lgh.h");
    if std::env::var_os("LGH_BLESS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "include/lgh.h is stale: regenerate it with `LGH_BLESS=1 cargo test -p lgh-capi --test header` and commit it"
    );
}
