//! The workspace's shape, checked as code (ARCHITECTURE.md, "Crates"): inside each crate the
//! modules import one another without a circle, and none takes a name from its crate root's
//! re-exports (a module low in the crate names the module that defines what it uses); no clippy
//! allowance for long parameter lists (values that travel together are a struct); no library crate
//! depends on `clap` or enables lgh-core's `testsets` outside its dev-dependencies; no file
//! cites a document that is not in the repository.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The workspace root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The library crates, whose structure is checked.
const CRATES: [&str; 10] = [
    "lgh-core",
    "lgh-image",
    "lgh-volume",
    "lgh-vpl",
    "lgh-ply",
    "lgh-cli",
    "lgh-capi",
    "lgh-gpu",
    "web",
    "lgh-py",
];

/// Every `.rs` file below `dir`, outside build folders (lgh-py, its own workspace, builds into
/// `lgh-py/target`).
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "target") {
                    stack.push(p);
                }
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// A source file's module path inside its crate (`shadow::deep`; the crate root is "").
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|l| l == "mod") {
        parts.pop();
    }
    if parts == ["lib"] || parts == ["main"] {
        parts.clear();
    }
    parts.join("::")
}

/// The code of a file outside comments and its unit tests.
fn code(text: &str) -> String {
    let body = text.split("#[cfg(test)]\nmod tests").next().unwrap_or("");
    body.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths named after `crate::` in `code` (or after `super::`, resolved from `module`):
/// `crate::a::b::X`, and each item of `crate::a::{X, b::Y}` or `crate::{X, a::Y}`, as full
/// paths without `crate::`.
fn crate_paths(code: &str, module: &str) -> Vec<String> {
    let mut out = crate_paths_after(code, "crate::", "");
    // `super::` in module `a::b` names `a::`; the crate root's children have no `super`.
    let parent = module.rsplit_once("::").map_or("", |(p, _)| p);
    if !module.is_empty() {
        let prefix = if parent.is_empty() {
            String::new()
        } else {
            format!("{parent}::")
        };
        out.extend(crate_paths_after(code, "super::", &prefix));
    }
    out
}

/// The paths after each `marker` in `code`, with `prefix` put before them.
fn crate_paths_after(code: &str, marker: &str, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find(marker) {
        let preceded = rest[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':');
        let tail = &rest[at + marker.len()..];
        let end = tail
            .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
            .unwrap_or(tail.len());
        if preceded {
            // `super::super::` or `a::crate::`: not this marker's own path.
            rest = &tail[end..];
            continue;
        }
        let path = format!("{prefix}{}", tail[..end].trim_end_matches(':'));
        let path = path.trim_end_matches(':').to_string();
        let group = tail[..end].is_empty() || tail[..end].ends_with("::");
        if tail[end..].starts_with('{') && group {
            let close = tail[end..].find('}').map_or(tail.len(), |c| end + c);
            for item in tail[end + 1..close].split(',') {
                let item = item.trim().split("::").next().unwrap_or("").trim();
                if !item.is_empty() {
                    out.push(if path.is_empty() {
                        item.to_string()
                    } else {
                        format!("{path}::{item}")
                    });
                }
            }
        } else {
            out.push(path);
        }
        rest = &tail[end..];
    }
    out
}

/// The longest module of `modules` that `path` starts with ("" for the crate root).
fn target(modules: &BTreeSet<String>, path: &str) -> String {
    let parts: Vec<&str> = path.split("::").collect();
    (1..=parts.len())
        .rev()
        .map(|i| parts[..i].join("::"))
        .find(|m| modules.contains(m))
        .unwrap_or_default()
}

/// A crate's module graph: module → the modules it imports (neither an ancestor nor a
/// descendant), and the imports it takes from the crate root's re-exports.
fn graph(krate: &str) -> (BTreeMap<String, BTreeSet<String>>, Vec<String>) {
    let src = root().join(krate).join("src");
    let files = rust_files(&src);
    let modules: BTreeSet<String> = files.iter().map(|f| module_of(&src, f)).collect();
    let mut edges = BTreeMap::new();
    let mut via_root = Vec::new();
    for f in &files {
        let m = module_of(&src, f);
        let mut out = BTreeSet::new();
        for p in crate_paths(&code(&std::fs::read_to_string(f).unwrap()), &m) {
            let t = target(&modules, &p);
            let item = p.split("::").next().unwrap_or("");
            if t.is_empty() {
                let capital = item.chars().next().is_some_and(char::is_uppercase);
                // The CLI's one error type lives at its root by design.
                if capital && !m.is_empty() && !(krate == "lgh-cli" && item == "Error") {
                    via_root.push(format!("{krate}: {m} takes crate::{p}"));
                }
                continue;
            }
            let related =
                t == m || m.starts_with(&format!("{t}::")) || t.starts_with(&format!("{m}::"));
            if !related {
                out.insert(t);
            }
        }
        edges.insert(m, out);
    }
    (edges, via_root)
}

/// The circles of a graph: its strongly connected components of more than one module.
fn circles(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    // Two modules are in one circle when each reaches the other.
    let reach = |from: &str| {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.to_string()];
        while let Some(v) = stack.pop() {
            for w in edges.get(&v).into_iter().flatten() {
                if seen.insert(w.clone()) {
                    stack.push(w.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<String>> =
        edges.keys().map(|m| (m, reach(m))).collect();
    let mut out: Vec<Vec<String>> = Vec::new();
    for m in edges.keys() {
        let circle: Vec<String> = edges
            .keys()
            .filter(|n| *n != m && reached[m].contains(*n) && reached[n].contains(m))
            .cloned()
            .collect();
        if !circle.is_empty() && !out.iter().any(|c| c.contains(m)) {
            out.push(std::iter::once(m.clone()).chain(circle).collect());
        }
    }
    out
}

#[test]
fn the_circle_finder_finds_a_circle() {
    let edges: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec!["a"]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(circles(&edges), vec![vec!["a", "b", "c"]]);
    let code = "use crate::grid::{DenseGrid, MAX};\nuse crate::{Camera, mesh::Mesh};\n\
                let x = crate::a::b(1);\nuse super::prefilter::Pyramid;";
    let paths = crate_paths(code, "shadow::deep");
    assert_eq!(
        paths,
        [
            "grid::DenseGrid",
            "grid::MAX",
            "Camera",
            "mesh",
            "a::b",
            "shadow::prefilter::Pyramid"
        ]
    );
}

#[test]
fn no_crate_has_an_import_circle_or_imports_through_its_root() {
    let mut problems = Vec::new();
    for krate in CRATES {
        let (edges, via_root) = graph(krate);
        for c in circles(&edges) {
            problems.push(format!("{krate}: import circle {}", c.join(" ↔ ")));
        }
        problems.extend(via_root);
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Every `.rs` file of the workspace's crates (tests and benches included) and `.md` file.
fn workspace_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    for dir in CRATES.iter().chain(&["tests", "fuzz"]) {
        files.extend(rust_files(&root().join(dir)));
    }
    let md = |d: &Path| {
        std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "md"))
            .collect::<Vec<_>>()
    };
    files.extend(md(&root()));
    files.extend(md(&root().join("docs")));
    files
}

#[test]
fn no_allowance_for_long_parameter_lists_and_no_citation_of_a_missing_document() {
    let allowance = ["too_many", "arguments"].join("_");
    let missing = ["DESIGN", ".md"].concat();
    let mut problems = Vec::new();
    for f in workspace_files() {
        let text = std::fs::read_to_string(&f).unwrap();
        if text.contains(&allowance) {
            problems.push(format!("{}: allows {allowance}", f.display()));
        }
        if text.contains(&missing) {
            problems.push(format!("{}: cites {missing}", f.display()));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn library_crates_know_nothing_of_the_command_line_or_the_test_sets() {
    for krate in [
        "lgh-core",
        "lgh-image",
        "lgh-volume",
        "lgh-vpl",
        "lgh-ply",
        "lgh-capi",
        "lgh-gpu",
        "web",
    ] {
        let manifest = std::fs::read_to_string(root().join(krate).join("Cargo.toml")).unwrap();
        let normal = manifest
            .split("[dev-dependencies]")
            .next()
            .unwrap_or_default();
        let deps: Vec<&str> = normal
            .lines()
            .filter(|l| !l.trim_start().starts_with('#'))
            .collect();
        assert!(
            !deps.iter().any(|l| l.trim_start().starts_with("clap")),
            "{krate} depends on clap"
        );
        assert!(
            !deps
                .iter()
                .any(|l| l.contains("lgh-core") && l.contains("testsets")),
            "{krate} enables lgh-core's testsets outside its dev-dependencies"
        );
    }
}

/// The public modules a crate root declares (`pub mod name;` or `pub mod name {`), but for
/// those hidden from its documentation (`#[doc(hidden)]` on the line before).
fn public_modules(lib: &str) -> Vec<String> {
    let code = code(lib);
    let lines: Vec<&str> = code.lines().map(str::trim).collect();
    lines
        .iter()
        .enumerate()
        .filter(|&(i, _)| i == 0 || lines[i - 1] != "#[doc(hidden)]")
        .filter_map(|(_, l)| l.strip_prefix("pub mod "))
        .map(|rest| {
            rest.trim_end_matches(|c: char| c == ';' || c == '{' || c.is_whitespace())
                .to_string()
        })
        .collect()
}

/// The crate root's own documentation: its leading `//!` lines.
fn crate_doc(lib: &str) -> String {
    lib.lines()
        .take_while(|l| l.starts_with("//!") || l.trim().is_empty())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn public_modules_are_found_in_the_module_map() {
    assert_eq!(
        public_modules("//! doc\npub mod a;\nmod b;\npub mod c {\n}\n#[doc(hidden)]\npub mod d;\n"),
        ["a", "c"]
    );
    let mut problems = Vec::new();
    for krate in CRATES {
        let src = root().join(krate).join("src");
        let lib = ["lib.rs", "main.rs"]
            .iter()
            .map(|f| src.join(f))
            .find(|p| p.exists())
            .unwrap();
        let text = std::fs::read_to_string(&lib).unwrap();
        let doc = crate_doc(&text);
        for m in public_modules(&text) {
            // A link `[`m`]`, `[m](mod@m)` or a mention `` `m` `` in the crate's top doc.
            let named = [format!("[`{m}`]"), format!("(mod@{m})"), format!("`{m}`")]
                .iter()
                .any(|n| doc.contains(n.as_str()));
            if !named {
                problems.push(format!(
                    "{krate}: pub mod {m} is not in the crate's module map"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_readme_stays_short() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= 300,
        "README.md has {lines} lines: at most 300 (studies and figures go to docs/)"
    );
}

/// The functions of `text` (outside its unit tests) longer than `most` lines, as
/// `(name, first line, lines)`: from the line of `fn name` to the line of its closing brace at
/// the same indentation.
fn long_functions(text: &str, most: usize) -> Vec<(String, usize, usize)> {
    let body = text.split("#[cfg(test)]\nmod tests").next().unwrap_or("");
    let lines: Vec<&str> = body.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        let indent = &line[..line.len() - trimmed.len()];
        let Some(at) = trimmed.find("fn ") else {
            continue;
        };
        let head = &trimmed[..at];
        let words_before = head.split_whitespace().all(|w| {
            [
                "pub",
                "pub(crate)",
                "pub(super)",
                "const",
                "unsafe",
                "async",
            ]
            .contains(&w)
                || w == "extern"
                // The ABI of `extern "C" fn`.
                || (w.len() > 1 && w.starts_with('"') && w.ends_with('"'))
        });
        if !words_before || trimmed.starts_with("//") {
            continue;
        }
        // A declaration without a body (a trait's required method) ends with `;` before any `{`.
        let opens = lines[i..]
            .iter()
            .position(|l| l.trim_end().ends_with('{') || l.trim_end().ends_with(';'));
        if opens.is_none_or(|k| lines[i + k].trim_end().ends_with(';')) {
            continue;
        }
        let close = format!("{indent}}}");
        let end = lines[i..]
            .iter()
            .position(|l| l.trim_end() == close)
            .map(|k| i + k);
        if let Some(end) = end {
            let n = end - i + 1;
            if n > most {
                let name = trimmed[at + 3..]
                    .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .next()
                    .unwrap_or("")
                    .to_string();
                out.push((name, i + 1, n));
            }
        }
    }
    out
}

#[test]
fn no_function_in_library_code_is_over_120_lines() {
    let short = "fn a() {\n    1;\n}\n";
    let long = format!("pub fn b() {{\n{}}}\n", "    x();\n".repeat(130));
    assert!(long_functions(short, 120).is_empty());
    let c_abi = format!(
        "pub unsafe extern \"C\" fn c() {{\n{}}}\n",
        "    x();\n".repeat(130)
    );
    assert_eq!(long_functions(&c_abi, 120), [("c".to_string(), 1, 132)]);
    assert_eq!(long_functions(&long, 120), [("b".to_string(), 1, 132)]);
    let mut problems = Vec::new();
    for krate in CRATES {
        for f in rust_files(&root().join(krate).join("src")) {
            let text = std::fs::read_to_string(&f).unwrap();
            for (name, line, n) in long_functions(&text, 120) {
                problems.push(format!("{}:{line}: fn {name} is {n} lines", f.display()));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "cut these at their seams (at most 120 lines a function):\n{}",
        problems.join("\n")
    );
}

#[test]
fn ci_requires_every_piece_a_test_can_skip_and_no_test_reads_ci() {
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let exported = |name: &str| {
        let export = format!("export {name}=1");
        ci.lines().any(|l| l.trim_start().starts_with(&export))
    };
    assert!(
        exported(lgh_tests::REQUIRE_ALL),
        ".ci/run does not `export {}=1`: a missing piece would pass as SKIPPED",
        lgh_tests::REQUIRE_ALL
    );
    for piece in lgh_tests::Piece::ALL {
        // `.ci/run` names every piece, and says why a piece it does not require is not.
        assert!(
            ci.contains(piece.variable()),
            ".ci/run does not name {piece:?}"
        );
        assert!(
            !piece.by_nature() || !exported(piece.variable()),
            "{piece:?} may be missing by nature on a CI machine"
        );
    }
    // Every LGH_REQUIRE_ variable the tests read is one of the pieces, and no test asks
    // whether it runs in CI: what CI requires, it says with LGH_REQUIRE_*.
    let mut known: Vec<&str> = lgh_tests::Piece::ALL.iter().map(|p| p.variable()).collect();
    known.push(lgh_tests::REQUIRE_ALL);
    let reads_ci = ["var(\"CI\")", "var_os(\"CI\")"];
    let mut problems = Vec::new();
    for f in workspace_files() {
        let text = std::fs::read_to_string(&f).unwrap();
        for (at, _) in text.match_indices("LGH_REQUIRE_") {
            let name: String = text[at..]
                .chars()
                .take_while(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || *c == '_')
                .collect();
            if name.len() > "LGH_REQUIRE_".len() && !known.contains(&name.as_str()) {
                problems.push(format!("{}: {name} is not a lgh_tests::Piece", f.display()));
            }
        }
        if reads_ci.iter().any(|r| text.contains(r)) {
            problems.push(format!("{}: reads CI", f.display()));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The package of a `.rs` file: the name in the `Cargo.toml` of the nearest folder above it.
fn package_of(file: &Path) -> String {
    let manifest = file
        .ancestors()
        .map(|d| d.join("Cargo.toml"))
        .find(|m| m.is_file())
        .unwrap();
    let text = std::fs::read_to_string(manifest).unwrap();
    let line = text.lines().find(|l| l.starts_with("name = ")).unwrap();
    line["name = ".len()..].trim_matches('"').to_string()
}

/// An `#[ignore]`d test is one CI would never run: `.ci/run` runs each file that has one with
/// `--ignored` (in release, where they take minutes and not hours).
#[test]
fn ci_runs_every_ignored_test() {
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let mut problems = Vec::new();
    for f in workspace_files() {
        let text = std::fs::read_to_string(&f).unwrap();
        let ignores = text.lines().any(|l| l.trim_start().starts_with("#[ignore"));
        if f.extension().is_some_and(|x| x == "md") || !ignores {
            continue;
        }
        let in_tests = f.parent().is_some_and(|d| d.ends_with("tests"));
        let Some(name) = f.file_stem().and_then(|s| s.to_str()).filter(|_| in_tests) else {
            problems.push(format!("{}: an ignored test outside tests/", f.display()));
            continue;
        };
        let run = format!("-p {} --test {name} -- --ignored", package_of(&f));
        if !ci.lines().any(|l| l.contains(&run)) {
            problems.push(format!("{}: .ci/run has no `{run}`", f.display()));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// A crate that is its own workspace (lgh-py: PyO3's build needs a Python, so maturin builds
/// it) is out of reach of the workspace's `cargo fmt --all` and `cargo clippy --workspace`:
/// `.ci/run` lints it by its manifest, and runs the Python package's tests.
#[test]
fn ci_lints_every_crate_outside_the_workspace() {
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let mut problems = Vec::new();
    for krate in CRATES {
        let manifest = std::fs::read_to_string(root().join(krate).join("Cargo.toml")).unwrap();
        if !manifest.lines().any(|l| l.trim() == "[workspace]") {
            continue;
        }
        for lint in [
            format!("cargo fmt --manifest-path {krate}/Cargo.toml -- --check"),
            format!("cargo clippy --manifest-path {krate}/Cargo.toml --all-targets -- -D warnings"),
        ] {
            if !ci.contains(&lint) {
                problems.push(format!(".ci/run has no `{lint}`"));
            }
        }
    }
    if !ci.contains("-m pytest -q lgh-py/tests") {
        problems.push(".ci/run does not run lgh-py's pytest suite".to_string());
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// `(name, version)` of every package in a `Cargo.lock`.
fn locked(path: &Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = Vec::new();
    let mut name = None;
    for line in text.lines() {
        if let Some(n) = line.strip_prefix("name = ") {
            name = Some(n.trim_matches('"').to_string());
        } else if let (Some(v), Some(n)) = (line.strip_prefix("version = "), name.take()) {
            out.push((n, v.trim_matches('"').to_string()));
        }
    }
    out
}

/// The part of a version that Cargo keeps compatible: the major, or `0.minor`.
fn semver_line(version: &str) -> String {
    let mut parts = version.split('.');
    match (parts.next(), parts.next()) {
        (Some("0"), Some(minor)) => format!("0.{minor}"),
        (Some(major), _) => major.to_string(),
        _ => version.to_string(),
    }
}

/// lgh-py, its own workspace, has its own `Cargo.lock`; the Python package is held to the
/// command's images bit for bit, so it must build the shared crates from the same sources: every
/// package it locks that the root also locks in the same compatible line, at the same version
/// (start from the root's lockfile: `cp Cargo.lock lgh-py/ && cargo build --manifest-path
/// lgh-py/Cargo.toml`).
#[test]
fn the_python_package_locks_the_roots_versions() {
    let root_lock = locked(&root().join("Cargo.lock"));
    let mut problems = Vec::new();
    for (name, version) in locked(&root().join("lgh-py/Cargo.lock")) {
        let line = semver_line(&version);
        for (_, other) in root_lock
            .iter()
            .filter(|(n, v)| *n == name && semver_line(v) == line)
        {
            if *other != version {
                problems.push(format!("{name}: lgh-py locks {version}, the root {other}"));
            }
        }
    }
    assert_eq!(semver_line("0.34.2"), "0.34");
    assert_eq!(semver_line("2.1.3"), "2");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
