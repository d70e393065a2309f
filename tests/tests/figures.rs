//! Every figure README.md and docs/*.md mark with `<!--fig:ID-->` is its entry's in
//! `docs/figures.json`, measured at a commit of this history, and no figure of the README
//! predates a change to the code it measures (`tools/figures check`; `lgh_tests::figures`).

use std::path::Path;

#[test]
fn the_published_figures_are_their_entries() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let problems = lgh_tests::figures::check(&root).unwrap();
    assert!(
        problems.is_empty(),
        "{}\n(`tools/figures refresh ID` measures a figure again)",
        problems.join("\n")
    );
}
