//! # lgh-volume — self-illuminating explosions (in progress)
//!
//! This crate will hold voxel grids, explosion lights, the volume ray marcher, deep-shadow cube
//! maps, multiple scattering and the path-traced reference (paper Secs. 4–6, DESIGN.md
//! "lgh-volume"). Today it has one working part: [`vdb`], a pure-Rust reader of OpenVDB files as
//! Blender and Houdini write them, checked against the official library on a real Blender fire
//! cache. Nothing else here works yet, and nothing pretends to. The lighting itself lives in
//! [`lgh_core`].
//!
//! ```no_run
//! let file = lgh_volume::vdb::read(std::path::Path::new("fluid_data_0056.vdb"))?;
//! for grid in &file.grids {
//!     let stats = grid.stats();
//!     println!("{} {}: {} active voxels", grid.name, grid.value_type.name(), stats.active_voxels);
//! }
//! # Ok::<(), lgh_volume::vdb::VdbError>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub use lgh_core;

pub mod cache;
pub mod explosion;
pub mod grid;
pub mod pathtrace;
pub mod render;
pub mod scene;
pub mod vdb;

pub use grid::DenseGrid;
