//! # lgh-volume — self-illuminating explosions
//!
//! A fire simulation in, images out (paper Secs. 3, 4, 6.1; DESIGN.md "lgh-volume"):
//!
//! - [`vdb`]: a pure-Rust reader of OpenVDB files as Blender and Houdini write them, checked
//!   against the official library; [`cache`] places a cache's frames on one grid (Blender's
//!   adaptive-domain offset) with Blender's grid names.
//! - [`explosion`]: the medium (absorption, isotropic scattering, blackbody emission with
//!   Planck's or Blender's model), one light per hot voxel (`I0 = j h³`), and the embedded
//!   procedural explosion.
//! - [`scene`]: a sequence's lights at fixed positions with per-frame intensities, through the
//!   lighting grid hierarchy or brute force.
//! - [`render`]: camera and ray marcher (emission + single scattering); [`shadow`]: the
//!   ray-marched shadow rays it shades with; [`pathtrace`]: the unbiased path-traced reference
//!   on the same grids.
//!
//! Deep-shadow cube maps and multiple scattering (Secs. 4, 5) are not written yet; shadows are
//! ray-marched (exact) or off. The lighting itself lives in [`lgh_core`].
//!
//! ```
//! use lgh_volume::explosion::{procedural, Medium};
//! use lgh_volume::render::{Camera, Framing, MarchSettings};
//! use lgh_volume::scene::{Backend, ExplosionLights};
//!
//! let volume = procedural(32, 0.5)?;
//! let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?; // κ_a, κ_s, k_e, T_min
//! let lights = ExplosionLights::new(&[&volume], &medium)?;
//! let (lo, hi) = volume.active_bounds().unwrap();
//! let camera = Camera::frame(lo, hi, 32, 18)?;
//! let (image, stats) = lights.render(
//!     Backend::Lgh { alpha: 2.0 },
//!     &volume,
//!     &medium,
//!     &camera,
//!     &MarchSettings::default(),
//!     &|_rows| {},
//! )?;
//! assert_eq!(image.pixels.len(), 32 * 18);
//! println!("{:.0} lights per shading point", stats.lights_per_point());
//! # Ok::<(), String>(())
//! ```

#![deny(unsafe_code)]
#![warn(missing_docs)]

pub use lgh_core;

pub mod cache;
pub mod explosion;
pub mod grid;
pub mod pathtrace;
pub mod render;
pub mod scene;
pub mod shadow;
pub mod vdb;

pub use grid::DenseGrid;
