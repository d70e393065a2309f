//! # lgh-volume — self-illuminating explosions
//!
//! A fire simulation in, images out (paper Secs. 3, 4, 6.1; ARCHITECTURE.md at the repository
//! root, "lgh-volume", follows the data from a VDB file to an EXR):
//!
//! - [`vdb`]: a pure-Rust reader of OpenVDB files as Blender and Houdini write them, checked
//!   against the official library; [`cache`] places a cache's frames on one grid (Blender's
//!   adaptive-domain offset) with Blender's grid names; [`grid`]: the dense grids; [`export`]: a
//!   volume's grids as raw files for `tools/cycles/write_vdb.py`.
//! - [`medium`]: one frame's density and temperature ([`Volume`]) and how they absorb, scatter
//!   and emit ([`Medium`]: Planck's or Blender's emission; [`blender_blackbody`]: Cycles'
//!   blackbody colour as its volumes emit it, measured); [`procedural`](mod@procedural): the embedded
//!   explosions ([`explosion`], the demo's, and the older [`procedural`](fn@procedural)).
//! - [`lights`]: one light per emitting voxel cell (`I0 = j h³`), fixed positions over a sequence with
//!   per-frame intensities ([`voxel_light`]: what a voxel light emits, its cell's emission;
//!   [`voxel_smoke`]: the smoke in its voxel, through which its light escapes); [`method`]: the
//!   many-lights method that shades them ([`Method`]:
//!   the lighting grid hierarchy at α, brute force, Lightcuts, or emission alone).
//! - [`frame`]: [`FrameRender`], a frame made ready to render (scattering, method, shadows)
//!   in one value; [`progress`]: how long work reports its progress.
//! - [`shadow`]: the visibility of the lights ([`Shadows`] chosen, [`Visibility`] built: the
//!   paper's deep-shadow cube maps over prefiltered density (Sec. 4, eq. 6), ray-marched, or
//!   none; [`thin_smoke`]: the bound under which a frame's shadows may be skipped);
//!   [`lighting`]: the one per-point lighting function, [`Lights::incident`] (eq. 1
//!   with `V`); [`lighting_cache`]: the coarse levels' light computed once per frame at the
//!   vertices of a grid over the smoke and interpolated, level 0's near part summed at every
//!   sample ([`near_part`]).
//! - [`render`]: the ray marcher (emission + single scattering; [`step_emission`]: the emission
//!   a step gathers through its smoke) and the one pixel loop, which
//!   skips the empty bricks ([`occupancy`]) and composites opaque surfaces ([`surfaces`]: a
//!   ground, or a room);
//!   [`camera`]: the camera and its automatic framing; [`settings`]: what a render is asked to
//!   do; [`stats`]: a render's work counts;
//!   [`pathtrace`]: the unbiased path-traced reference on the same grids.
//! - [`scattering`]: multiple scattering (Sec. 5): scattered lights at every voxel with smoke,
//!   depth by depth, merged with the emission lights into one light per voxel, or taken as a
//!   grid of in-scattered radiance ([`scattered_light`]).
//! - [`error`]: [`ReadError`] for reading a volume, [`RenderError`] for lighting and rendering it.
//!
//! Deep-shadow cube maps (Sec. 4) plug into [`Visibility`], multiple scattering (Sec. 5) calls
//! [`Lights::incident`] at every voxel with smoke. The lighting itself lives in [`lgh_core`].
//!
//! One value renders a frame ([`FrameRender`]): the lights through a [`Method`], their
//! shadows, the volume and the medium, made ready once, then any camera:
//!
//! ```
//! use lgh_volume::render::{Camera, Framing, MarchSettings};
//! use lgh_volume::{procedural, ExplosionLights, FrameRender, Medium, Method, Shadows};
//!
//! let volume = procedural(32, 0.5)?;
//! let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?; // κ_a, κ_s, k_e, T_min
//! let lights = ExplosionLights::new(&[&volume], &medium)?;
//! let settings = MarchSettings { shadows: Shadows::CubeMap, ..Default::default() };
//! let alpha = 2.0; // the paper's α
//! let frame = FrameRender::new(&lights, Method::Lgh { alpha }, &volume, &medium, &settings, &())?;
//! let (lo, hi) = volume.active_bounds().unwrap();
//! let (image, stats) = frame.render(&Camera::frame(lo, hi, 32, 18)?, &())?;
//! assert_eq!(image.pixels.len(), 32 * 18);
//! println!("{:.0} lights per shading point", stats.lights_per_point());
//! # Ok::<(), lgh_volume::RenderError>(())
//! ```

#![deny(unsafe_code)]
#![warn(missing_docs)]

pub use lgh_core;

pub mod blender_blackbody;
pub mod cache;
pub mod camera;
pub mod error;
pub mod export;
pub mod frame;
pub mod grid;
pub mod lighting;
pub mod lighting_cache;
pub mod lights;
pub mod medium;
pub mod method;
pub mod near_part;
pub mod occupancy;
pub mod pathtrace;
mod pixel_refinement;
pub mod procedural;
pub mod progress;
pub mod render;
pub mod scattered_light;
pub mod scattering;
pub mod settings;
mod shading;
pub mod shadow;
pub mod stats;
pub mod step_emission;
pub mod surfaces;
pub mod thin_smoke;
pub mod vdb;
pub mod voxel_light;
pub mod voxel_smoke;

pub use error::{ReadError, RenderError};
pub use frame::{FrameRender, PrepareSeconds};
pub use grid::DenseGrid;
pub use lighting::Lights;
pub use lights::{ExplosionLights, Variants};
pub use medium::{EmissionModel, Medium, Volume, MAX_EMISSION};
pub use method::{FrameBackend, Method};
pub use procedural::{bouncing_balls, explosion, procedural, Explosion};
pub use progress::{Phase, Progress};
pub use shadow::{Shadows, Visibility};
