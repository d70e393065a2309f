//! Cross-crate integration tests live in `tests/tests/`. This library is what the test suites of
//! every crate share: where the real data of `../shared/data` is, and how a test skips without it;
//! and [`figures`], the published figures of `docs/figures.json` (`tools/figures`).

pub mod figures;

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

/// `relative` inside the shared data folder ([`shared_data`]), or `None` after
/// [`Piece::Data`]'s [`missing`](Piece::missing) (a failure with `LGH_REQUIRE_DATA` or
/// `LGH_REQUIRE_ALL` set) when it is not there.
///
/// ```
/// # std::env::remove_var("LGH_REQUIRE_DATA");
/// # std::env::remove_var("LGH_REQUIRE_ALL");
/// assert_eq!(lgh_tests::data("no/such/file.obj"), None); // says SKIPPED
/// ```
pub fn data(relative: impl AsRef<Path>) -> Option<PathBuf> {
    let p = shared_data().join(relative);
    if p.exists() {
        Some(p)
    } else {
        Piece::Data.missing(&format!("{} is not here", p.display()));
        None
    }
}

/// Frame `n` (50..=56) of the dev fire cache, or `None` after saying `SKIPPED` ([`data`]).
pub fn fire_frame(n: u32) -> Option<PathBuf> {
    data(format!(
        "volumes/blender_fire_pesichra/data/fluid_data_{n:04}.vdb"
    ))
}

/// The Cornell box's OBJ (its MTL beside it), or `None` after saying `SKIPPED` ([`data`]).
pub fn cornell_box() -> Option<PathBuf> {
    data("meshes/cornellbox_original/CornellBox-Original.obj")
}

/// Relative RMSE (luminance, ARCHITECTURE.md "Measuring") of the *scattered* light: `a` and `r`
/// minus the emission-only image `e`. The emission is computed identically by both renders, so
/// leaving it in would only dilute the error of what the lights approximate.
pub fn scatter_rel_rmse(a: &lgh_image::Image, r: &lgh_image::Image, e: &lgh_image::Image) -> f64 {
    scatter_errors(a, r, e).0
}

/// [`scatter_rel_rmse`] and the same channel by channel (each channel's RMSE over the
/// reference's mean of it, `lgh compare`'s `rel_rmse_rgb`; `None` for a channel the reference's
/// scattered light does not have).
pub fn scatter_errors(
    a: &lgh_image::Image,
    r: &lgh_image::Image,
    e: &lgh_image::Image,
) -> (f64, [Option<f64>; 3]) {
    let sub = |x: &lgh_image::Image| lgh_image::Image {
        pixels: x
            .pixels
            .iter()
            .zip(&e.pixels)
            .map(|(p, q)| *p - *q)
            .collect(),
        ..x.clone()
    };
    let (a, r) = (sub(a), sub(r));
    let luminance = lgh_image::compare(&a, &r).expect("images of one size");
    let channels = lgh_image::compare_rgb(&a, &r).expect("images of one size");
    (luminance.rel_rmse, channels.rel_rmse)
}

/// The README's library examples (lgh-core, lgh-volume, lgh-vpl), compiled and run as doctests
/// here, where every crate of the workspace is a dependency of the doctests.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
struct ReadmeDoctests;

/// A piece of the system that some tests need and `cargo` does not install: the shared data, a
/// browser, a rustup target, a C++ compiler, a Python module, a scheduler, a CPU feature. Outside
/// CI a test without it says `SKIPPED: <what is missing> (<how to get it>)` on stderr and passes;
/// with its `LGH_REQUIRE_<PIECE>` variable set, or `LGH_REQUIRE_ALL` (which `.ci/run` sets, after
/// installing them), it fails, so a missing install step can never pass as green. The pieces a
/// machine may lack by nature ([`by_nature`](Self::by_nature): AVX2, mounting a tmpfs) are
/// required by their own variable only.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Piece {
    /// The real data of `../shared/data` (or `$LGH_SHARED_DATA`): the dev fire, the Cornell box,
    /// Sponza ([`data`]).
    Data,
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
    /// Mounting a small tmpfs (root or `CAP_SYS_ADMIN`): the full-disk test
    /// (`lgh-cli/tests/hardening.rs`).
    Tmpfs,
    /// A CPU with AVX2: the eight-abreast kernels' tests against the one-by-one code
    /// (`lgh-volume/src/shadow/deep.rs`).
    Avx2,
    /// A GPU adapter for wgpu — Vulkan, Metal or DX12; without a GPU, Mesa's software Vulkan
    /// (lavapipe): lgh-gpu's tests (`lgh-gpu/tests/`).
    Gpu,
    /// Khronos' `spirv-val` and `glslangValidator`: the generated SPIR-V and GLSL of lgh-gpu's
    /// kernels validated by their own tools (`lgh-gpu/tests/translations.rs`).
    ShaderTools,
}

impl Piece {
    /// Every piece, in the order the README lists them.
    pub const ALL: [Piece; 10] = [
        Piece::Data,
        Piece::Browser,
        Piece::WasmTarget,
        Piece::Cxx,
        Piece::OpenVdb,
        Piece::Slurm,
        Piece::Tmpfs,
        Piece::Avx2,
        Piece::Gpu,
        Piece::ShaderTools,
    ];

    /// The piece's place in [`ALL`](Self::ALL): a match over every variant, so a new piece
    /// cannot compile without a place, and a test checks that [`ALL`](Self::ALL) holds it there.
    ///
    /// ```
    /// use lgh_tests::Piece;
    /// for (i, piece) in Piece::ALL.into_iter().enumerate() {
    ///     assert_eq!(piece.index(), i);
    /// }
    /// ```
    #[must_use]
    pub fn index(self) -> usize {
        match self {
            Piece::Data => 0,
            Piece::Browser => 1,
            Piece::WasmTarget => 2,
            Piece::Cxx => 3,
            Piece::OpenVdb => 4,
            Piece::Slurm => 5,
            Piece::Tmpfs => 6,
            Piece::Avx2 => 7,
            Piece::Gpu => 8,
            Piece::ShaderTools => 9,
        }
    }

    /// Whether a machine may lack the piece by its nature, whatever is installed (a CPU
    /// feature, a kernel's permission): `LGH_REQUIRE_ALL` does not require it.
    ///
    /// ```
    /// assert!(lgh_tests::Piece::Avx2.by_nature());
    /// assert!(!lgh_tests::Piece::Data.by_nature());
    /// ```
    #[must_use]
    pub fn by_nature(self) -> bool {
        matches!(self, Piece::Tmpfs | Piece::Avx2)
    }

    /// The variable that makes the piece required: `LGH_REQUIRE_BROWSER`, …
    ///
    /// ```
    /// assert_eq!(lgh_tests::Piece::Slurm.variable(), "LGH_REQUIRE_SLURM");
    /// ```
    #[must_use]
    pub fn variable(self) -> &'static str {
        match self {
            Piece::Data => "LGH_REQUIRE_DATA",
            Piece::Tmpfs => "LGH_REQUIRE_TMPFS",
            Piece::Avx2 => "LGH_REQUIRE_AVX2",
            Piece::Browser => "LGH_REQUIRE_BROWSER",
            Piece::WasmTarget => "LGH_REQUIRE_WASM",
            Piece::Cxx => "LGH_REQUIRE_CXX",
            Piece::OpenVdb => "LGH_REQUIRE_OPENVDB",
            Piece::Slurm => "LGH_REQUIRE_SLURM",
            Piece::Gpu => "LGH_REQUIRE_GPU",
            Piece::ShaderTools => "LGH_REQUIRE_SHADER_TOOLS",
        }
    }

    /// How to get the piece: the command that installs it on Debian (as `.ci/run` does), or
    /// what it takes.
    ///
    /// ```
    /// assert!(lgh_tests::Piece::Cxx.install().contains("g++"));
    /// ```
    #[must_use]
    pub fn install(self) -> &'static str {
        match self {
            Piece::Data => {
                "put the shared data beside the checkout as ../shared/data, or set LGH_SHARED_DATA"
            }
            Piece::Tmpfs => "run the tests as root, or with CAP_SYS_ADMIN",
            Piece::Avx2 => "a CPU with AVX2",
            Piece::Browser => "apt-get install chromium chromium-driver",
            Piece::WasmTarget => "rustup target add wasm32-unknown-unknown",
            Piece::Cxx => "apt-get install make g++",
            Piece::OpenVdb => "apt-get install python3-openvdb libopenvdb-tools",
            Piece::Slurm => "apt-get install slurm-wlm munge, and run the tests as root",
            Piece::Gpu => "a GPU with its Vulkan driver, or apt-get install mesa-vulkan-drivers",
            Piece::ShaderTools => "apt-get install spirv-tools glslang-tools",
        }
    }

    /// Whether this run requires the piece: its variable is set (and not empty), or
    /// [`REQUIRE_ALL`] is and the piece is not one a machine may lack by nature.
    #[must_use]
    pub fn required(self) -> bool {
        let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
        set(self.variable()) || (!self.by_nature() && set(REQUIRE_ALL))
    }

    /// Says `SKIPPED: <missing> (<install>)` on stderr, or panics with the same words when the
    /// piece is required. A test calls it where the piece is missing, then returns.
    ///
    /// ```
    /// # std::env::remove_var("LGH_REQUIRE_CXX");
    /// # std::env::remove_var("LGH_REQUIRE_ALL");
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

/// The variable that requires every piece but those a machine may lack by nature
/// ([`Piece::by_nature`]): `.ci/run` sets it.
pub const REQUIRE_ALL: &str = "LGH_REQUIRE_ALL";

/// Whether the official OpenVDB library is here: `/usr/bin/python3` imports `pyopenvdb` and
/// `numpy`, and `vdb_print` runs. Without it, [`Piece::OpenVdb`]'s
/// [`missing`](Piece::missing) has said so (a failure where it is required).
#[must_use]
pub fn openvdb() -> bool {
    let imports = std::process::Command::new("/usr/bin/python3")
        .args(["-c", "import pyopenvdb, numpy"])
        .output();
    let missing = match imports {
        Err(e) => format!("no /usr/bin/python3 ({e})"),
        Ok(o) if !o.status.success() => format!(
            "/usr/bin/python3 cannot import pyopenvdb and numpy: {}",
            // The exception, the traceback's last line.
            String::from_utf8_lossy(&o.stderr)
                .trim()
                .lines()
                .last()
                .unwrap_or("")
        ),
        Ok(_) if !runs("vdb_print", &["-version"]) => "no vdb_print".to_string(),
        Ok(_) => return true,
    };
    Piece::OpenVdb.missing(&missing);
    false
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

/// `f` run on a pool of `threads` rayon threads: the determinism tests compare what it returns
/// across thread counts.
pub fn on<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// An image's pixels as bits, so that `-0.0` against `0.0` or two NaNs count as what they are:
/// what the determinism tests compare.
#[must_use]
pub fn image_bits(image: &lgh_image::Image) -> Vec<[u32; 3]> {
    image
        .pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// An image's mean luminance, summed in f64: what the comparisons against the path tracer
/// compare.
#[must_use]
pub fn mean_luminance(image: &lgh_image::Image) -> f64 {
    image
        .pixels
        .iter()
        .map(|&p| f64::from(lgh_core::luminance(p)))
        .sum::<f64>()
        / image.pixels.len() as f64
}

/// `n` directions on a Fibonacci sphere, `[x, y, z]` unit vectors: a deterministic, even
/// quadrature of the sphere for the near-field tests.
///
/// ```
/// let d = lgh_tests::fibonacci_sphere(64);
/// assert_eq!(d.len(), 64);
/// let mean_z: f64 = d.iter().map(|w| w[2]).sum::<f64>() / 64.0;
/// assert!(mean_z.abs() < 1e-12 && d.iter().all(|w| (w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - 1.0).abs() < 1e-12));
/// ```
#[must_use]
pub fn fibonacci_sphere(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = (i as f64 + 0.5) * std::f64::consts::PI * (3.0 - 5f64.sqrt());
            [r * phi.cos(), r * phi.sin(), z]
        })
        .collect()
}

/// `∫_cube e^{−τ‖x − y‖} / ‖x − y‖² dy` over the unit cube centred at the origin, seen from `x`
/// (in the cube's side), in uniform smoke of `tau` optical depths a side: over the directions
/// `dirs` ([`fibonacci_sphere`]), each ray's chord `[t_in, t_out]` through the cube gives
/// `(e^{−τ t_in} − e^{−τ t_out}) / τ`. The exact fluence of a uniform emitting voxel — what
/// `lgh_core::near_field`'s kernel and escape stand for — `G(0) = 7.674` at the centre in clear
/// air. The directions must resolve the cube: 2,048 hold it within 1% up to about three sides
/// away; farther, few rays meet it.
///
/// ```
/// let dirs = lgh_tests::fibonacci_sphere(2048);
/// assert!((lgh_tests::cube_fluence([0.0; 3], &dirs, 0.0) / 7.674 - 1.0).abs() < 2e-3);
/// // Two sides away, near the inverse square (the cube's `1 + 1/(12 d²)` beyond it).
/// let near = lgh_tests::cube_fluence([0.0, 0.0, 2.0], &dirs, 0.0);
/// assert!((near * 4.0 - 1.0).abs() < 0.03, "{near}");
/// ```
#[must_use]
pub fn cube_fluence(x: [f64; 3], dirs: &[[f64; 3]], tau: f64) -> f64 {
    let mut sum = 0.0;
    for w in dirs {
        let (mut t_in, mut t_out) = (0.0f64, f64::INFINITY);
        for a in 0..3 {
            if w[a] == 0.0 {
                if x[a].abs() > 0.5 {
                    t_out = -1.0;
                }
                continue;
            }
            let (t1, t2) = ((-0.5 - x[a]) / w[a], (0.5 - x[a]) / w[a]);
            t_in = t_in.max(t1.min(t2));
            t_out = t_out.min(t1.max(t2));
        }
        if t_out > t_in {
            sum += if tau == 0.0 {
                t_out - t_in
            } else {
                ((-tau * t_in).exp() - (-tau * t_out).exp()) / tau
            };
        }
    }
    4.0 * std::f64::consts::PI * sum / dirs.len() as f64
}
