//! Cross-crate integration tests live in `tests/tests/`. This library is what the test suites of
//! every crate share: where the real data of `../shared/data` is, and how a test skips without it.

use std::path::{Path, PathBuf};

/// The shared data folder: `$LGH_SHARED_DATA`, else `../shared/data` beside the checkout.
pub fn shared_data() -> PathBuf {
    std::env::var_os("LGH_SHARED_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../shared/data")
                .to_path_buf()
        })
}

/// The folder of the dev Blender fire cache's `.vdb` frames.
pub fn fire_dir() -> PathBuf {
    shared_data().join("volumes/blender_fire_pesichra/data")
}

/// Frame `n` (50..=56) of the dev fire cache, or `None` after saying `SKIPPED` on stderr when
/// the data is absent.
pub fn fire_frame(n: u32) -> Option<PathBuf> {
    let p = fire_dir().join(format!("fluid_data_{n:04}.vdb"));
    if p.exists() {
        Some(p)
    } else {
        eprintln!("SKIPPED: {} is not here", p.display());
        None
    }
}

/// Relative RMSE (luminance, ARCHITECTURE.md "Measuring") of the *scattered* light: `a` and `r`
/// minus the emission-only image `e`. The emission is computed identically by both renders, so
/// leaving it in would only dilute the error of what the lights approximate.
pub fn scatter_rel_rmse(a: &lgh_image::Image, r: &lgh_image::Image, e: &lgh_image::Image) -> f64 {
    let sub = |x: &lgh_image::Image| lgh_image::Image {
        pixels: x
            .pixels
            .iter()
            .zip(&e.pixels)
            .map(|(p, q)| *p - *q)
            .collect(),
        ..x.clone()
    };
    lgh_image::compare(&sub(a), &sub(r))
        .expect("images of one size")
        .rel_rmse
}

/// The README's library examples (lgh-core, lgh-volume, lgh-vpl), compiled and run as doctests
/// here, where every crate of the workspace is a dependency of the doctests.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
struct ReadmeDoctests;

/// A piece of the system that some tests need and `cargo` does not install: a browser, a rustup
/// target, a C++ compiler, a Python module, a scheduler. Outside CI a test without it says
/// `SKIPPED: <what is missing> (<the install command>)` on stderr and passes; with its
/// `LGH_REQUIRE_<PIECE>` variable set (`.ci/run` sets every one, after installing them) it fails,
/// so a missing install step can never pass as green.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Piece {
    /// Chromium and chromedriver: the web page's browser test (`web/tests/browser.rs`).
    Browser,
    /// The `wasm32-unknown-unknown` rustup target: the web page's module, built by its browser
    /// test.
    WasmTarget,
    /// `make` and a C++ compiler: the C API's C and C++ examples (`lgh-capi/tests/example.rs`).
    Cxx,
    /// Debian's `python3-openvdb` and `vdb_print`: the official OpenVDB library, the VDB
    /// reader's oracle (`lgh-volume/tests/vdb_oracle.rs`).
    OpenVdb,
    /// Slurm and munge, run as root: the farm test's scheduler (`lgh-cli/tests/slurm.rs`).
    Slurm,
}

impl Piece {
    /// Every piece, in the order the README lists them.
    pub const ALL: [Piece; 5] = [
        Piece::Browser,
        Piece::WasmTarget,
        Piece::Cxx,
        Piece::OpenVdb,
        Piece::Slurm,
    ];

    /// The variable that makes the piece required: `LGH_REQUIRE_BROWSER`, …
    ///
    /// ```
    /// assert_eq!(lgh_tests::Piece::Slurm.variable(), "LGH_REQUIRE_SLURM");
    /// ```
    #[must_use]
    pub fn variable(self) -> &'static str {
        match self {
            Piece::Browser => "LGH_REQUIRE_BROWSER",
            Piece::WasmTarget => "LGH_REQUIRE_WASM",
            Piece::Cxx => "LGH_REQUIRE_CXX",
            Piece::OpenVdb => "LGH_REQUIRE_OPENVDB",
            Piece::Slurm => "LGH_REQUIRE_SLURM",
        }
    }

    /// The command that installs the piece on Debian (as `.ci/run` does).
    ///
    /// ```
    /// assert!(lgh_tests::Piece::Cxx.install().contains("g++"));
    /// ```
    #[must_use]
    pub fn install(self) -> &'static str {
        match self {
            Piece::Browser => "apt-get install chromium chromium-driver",
            Piece::WasmTarget => "rustup target add wasm32-unknown-unknown",
            Piece::Cxx => "apt-get install make g++",
            Piece::OpenVdb => "apt-get install python3-openvdb libopenvdb-tools",
            Piece::Slurm => "apt-get install slurm-wlm munge, and run the tests as root",
        }
    }

    /// Whether this run requires the piece (its variable is set and not empty).
    #[must_use]
    pub fn required(self) -> bool {
        std::env::var_os(self.variable()).is_some_and(|v| !v.is_empty())
    }

    /// Says `SKIPPED: <missing> (<install>)` on stderr, or panics with the same words when the
    /// piece is required. A test calls it where the piece is missing, then returns.
    ///
    /// ```
    /// # std::env::remove_var("LGH_REQUIRE_CXX");
    /// lgh_tests::Piece::Cxx.missing("no c++ on the PATH"); // says SKIPPED and returns
    /// ```
    pub fn missing(self, missing: &str) {
        let line = format!("{missing} ({})", self.install());
        if self.required() {
            panic!("{} is set but {line}", self.variable());
        }
        eprintln!("SKIPPED: {line}");
    }
}

/// Whether `program` runs (`program args` exits, whatever its status).
#[must_use]
pub fn runs(program: &str, args: &[&str]) -> bool {
    std::process::Command::new(program)
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok()
}

/// The examples of `docs/library.md` (the library in more depth), run as doctests as the
/// README's are.
#[cfg(doctest)]
#[doc = include_str!("../../docs/library.md")]
struct LibraryDoctests;
