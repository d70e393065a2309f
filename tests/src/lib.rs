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
