//! # lgh-vpl — virtual-point-light global illumination on meshes (not implemented yet)
//!
//! This crate will hold OBJ scenes, a triangle BVH, VPL generation and surface shading through any
//! [`lgh_core`] backend (paper Sec. 6.4, Fig. 13; DESIGN.md "lgh-vpl"). It is an empty placeholder
//! today: nothing here works yet, and nothing pretends to.

#![forbid(unsafe_code)]

pub use lgh_core;
