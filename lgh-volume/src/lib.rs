//! # lgh-volume — self-illuminating explosions (not implemented yet)
//!
//! This crate will hold voxel grids and OpenVDB import, explosion lights, the volume ray marcher,
//! deep-shadow cube maps, multiple scattering and the path-traced reference (paper Secs. 4–6,
//! DESIGN.md "lgh-volume"). It is an empty placeholder today: nothing here works yet, and nothing
//! pretends to. The lighting itself lives in [`lgh_core`].

#![forbid(unsafe_code)]

pub use lgh_core;

pub mod vdb;
