//! # lgh-core — the Lighting Grid Hierarchy
//!
//! Lighting with very many point lights after Yuksel & Yuksel, *Lighting Grid Hierarchy for
//! Self-illuminating Explosions* (SIGGRAPH 2017), Sec. 3. The input lights `S0` are splatted with
//! trilinear weights onto a hierarchy of sparse grids (level ℓ has spacing `h_ℓ = 2^(ℓ−1) h_1`);
//! every grid vertex becomes a light with an intensity (eq. 1), an illumination centre (eq. 2), a
//! per-axis variance (eq. 4) and a size (eq. 5). A shading point gathers fine levels nearby and
//! coarse levels far away, blended by the partition-of-unity functions `B_ℓ` (eq. 3) so nothing
//! jumps — the paper's cure for flicker.
//!
//! The crate is `no_std` + `alloc`. A query allocates nothing and never panics; build and query are
//! deterministic (bit-identical for any thread count and any input order). Visibility, BRDF and
//! phase function stay with the caller, who receives each contributing light in a closure.
//!
//! ```
//! use glam::Vec3;
//! use lgh_core::{falloff, GridSettings, LightingGridHierarchy, PointLight};
//!
//! // Four lights; let the hierarchy choose h1 (paper Sec. 6.4) and ℓ_max.
//! let lights = [
//!     PointLight::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.5, 0.2)),
//!     PointLight::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 0.5, 0.2)),
//!     PointLight::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.2, 0.5, 1.0)),
//!     PointLight::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.2, 0.5, 1.0)),
//! ];
//! let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
//! let blending = lgh.blending(2.0)?; // the paper's α = 2
//!
//! // Unshadowed irradiance-like sum L(x) = Σ B_ℓ(d) I g(d) at a point.
//! let x = Vec3::new(3.0, 2.0, 1.0);
//! let mut sum = Vec3::ZERO;
//! lgh.query(x, &blending, |light| {
//!     // A renderer would multiply by visibility and BRDF / phase function here.
//!     sum += light.intensity * falloff(light.distance, lgh.h0());
//! })?;
//! assert!(sum.x > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Backends: every many-lights method implements [`ManyLights`] and is re-exported here —
//! [`LghBackend`], [`BruteForce`], [`OctreeBackend`] (over a [`LightOctree`]),
//! [`LightcutsBackend`] (over a [`LightTree`]) and [`WardBackend`]; their modules keep the same
//! paths too (`lgh_core::octree::OctreeBackend`, …).
//!
//! Modules beside the hierarchy (whose types are at the root): [`lightcuts`] (Walter et al.'s
//! light tree and cuts, the paper's baseline), [`octree`] (Paquette et al.'s light octree and
//! its error bounds), [`ward`] (Ward's adaptive shadow testing), [`reflection`] (the Phong
//! model of Paquette's eq. 1), [`near_field`] (what a voxel light gives close to it),
//! [`spectrum`] (blackbody colour), [`metrics`] (error metrics of an approximation against a
//! reference) and [`morton`] (Morton codes of grid coordinates, the hierarchy's order).
//!
//! Features: `std` (default), `rayon` (parallel build; the result is bit-identical to a serial one)
//! and `testsets` (off by default: the light sets and query points of the module `testsets`, for
//! tests and benchmarks only; production randomness is in [`random`], and the lights of published
//! test scenes that production code renders are in [`scenes`]).

#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

// `cargo test -p lgh-core --target wasm32-unknown-unknown` runs the tests in a browser
// (docs/embedding.md, "In a browser").
#[cfg(test)]
wasm_bindgen_test::wasm_bindgen_test_configure!(run_in_browser);

mod blend;
#[cfg(test)]
mod bounded_tests;
mod bricks;
mod brute;
mod error;
mod grid;
mod hierarchy;
mod level;
mod light;
pub mod lightcuts;
mod many_lights;
mod math;
pub mod metrics;
pub mod morton;
pub mod near_field;
pub mod octree;
mod radix;
pub mod random;
mod ranked;
pub mod reflection;
pub mod scenes;
pub mod spectrum;
#[cfg(any(test, feature = "testsets"))]
pub mod testsets;
pub mod ward;

pub use blend::{check_alpha, falloff, Blending, CoarseSpread, MAX_LEVEL};
pub use brute::BruteForce;
pub use error::{BuildError, QueryError, MAX_LIGHTS};
pub use glam;
pub use grid::{bounds, Clustering, GridSettings, LevelSource, LightPosition};
pub use hierarchy::{LghBackend, LightingGridHierarchy, Reaching};
pub use light::{
    luminance, validate_intensity, Channels, GridLight, LevelLights, PointLight, LUMINANCE_WEIGHTS,
};
pub use lightcuts::{LightTree, LightcutsBackend, LightcutsSettings, Representative};
pub use many_lights::{
    probe, Illumination, LightSample, Lobe, ManyLights, Material, Shader, ShadingPoint,
    ISOTROPIC_PHASE,
};
pub use near_field::NearField;
pub use octree::{LightOctree, OctreeBackend, OctreeSettings};
pub use ward::WardBackend;
