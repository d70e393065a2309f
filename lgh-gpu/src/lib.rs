//! The Lighting Grid Hierarchy (Yuksel & Yuksel 2017) on the GPU, in wgpu compute shaders
//! written in WGSL: Vulkan, Metal and DX12 natively. It runs in the caller's `wgpu::Device` and
//! `Queue` ([`Gpu::from_device`], so it embeds in any wgpu engine) or in a headless device of its
//! own ([`Gpu::new`]); its buffers stay on the GPU between frames.
//!
//! The whole per-frame path runs on the GPU, deterministically (no float atomics: the same
//! lights give the same bits on every run):
//!
//! - **build** ([`GpuBuilder::rebuild`], `build.wgsl`): from a buffer of lights, each level by
//!   the paper's eqs. (1), (2), (4) and (5) — the lights counted and sorted into level-1 cells
//!   (a stable radix sort, `sort.wgsl`, and prefix scans, `scan.wgsl`), each level's vertices
//!   numbered, each vertex's light gathered from the lights of its eight cells in a fixed order;
//!   the same levels as [`lgh_core`]'s build on the same placement ([`GpuGrid::settings`]) within
//!   a derived tolerance (`tests/build.rs`);
//! - **update** ([`GpuBuilder::update_intensities`]): same positions, new intensities, the
//!   topology kept — the same bits as a rebuild;
//! - **rebuild** of lights that move, any count from frame to frame;
//! - **query** ([`GpuHierarchy::shade`], `walk.wgsl` + `shade.wgsl`): eq. (1)'s blended sum at a
//!   buffer of shading points (position, normal, albedo: a G-buffer) with a Lambertian response,
//!   unshadowed;
//! - **gather** ([`GpuHierarchy::gather`], `gather.wgsl`): K lights a point drawn in proportion
//!   to their unshadowed light, weighted so that an engine's shadow rays to them give an
//!   unbiased estimate of the sum.
//!
//! An engine keeps its data on the GPU: [`GpuBuilder::rebuild_from`] builds from lights in its
//! buffers, [`GpuHierarchy::record_shade`] and [`GpuHierarchy::record_gather`] record into its
//! command encoder on its G-buffer, nothing read back. A hierarchy built by lgh-core can also be
//! uploaded ([`GpuHierarchy::upload`]); in a browser
//! (wasm32) wgpu runs on the browser's WebGPU ([`Gpu::new_async`],
//! [`GpuHierarchy::shade_async`]; `web/gpu`).
//!
//! | module | what it holds |
//! |---|---|
//! | [`context`] | [`Gpu`]: the device and queue, the caller's or a headless one, and which adapter it is |
//! | [`grid`] | [`GpuGrid`]: where the GPU's grids sit (origin, `h1`, Morton bits a side) |
//! | [`build`] | [`GpuBuilder`]: the build, update and rebuild on the GPU (`build.wgsl`) |
//! | [`sort`] | the stable radix sort of the lights by cell (`sort.wgsl`) |
//! | [`scan`] | the prefix sum (`scan.wgsl`) |
//! | [`hierarchy`] | [`GpuHierarchy`]: a hierarchy's levels on the GPU for one α, and its query ([`shade`](GpuHierarchy::shade)) |
//! | [`gather`] | the gather of lights for shadow rays ([`GpuHierarchy::gather`]) |
//! | [`cells`] | a level's lights sorted into cells on the CPU (the upload of an lgh-core hierarchy) |
//! | [`layout`] | every buffer's element and every kernel's uniform, `#[repr(C)]` and mirrored in the WGSL and in C |
//! | [`kernels`] | the WGSL sources and their entry points |
//! | [`dispatch`] | what every multi-kernel pass does alike: layouts, uniforms at dynamic offsets, readback |
//! | [`reference`](mod@reference) | the query on the CPU through lgh-core, the tests' and benches' reference |
//! | [`timing`] | passes and spans of dispatches timed by timestamp queries, where the adapter has them |
//! | [`error`] | [`GpuError`] |
//!
//! For engines not on wgpu (Unreal, Godot, Unity, an in-house RHI), each entry point is committed
//! in `lgh-gpu/generated/` as naga translated it — SPIR-V, HLSL 6.0, GLSL 4.30, MSL 2.4 — with
//! the layouts in C (`generated/lgh_gpu.h`), both kept current by tests: such an engine
//! dispatches the same kernels on buffers laid out as [`layout`] says.
//!
//! ```no_run
//! use lgh_core::glam::Vec3;
//! use lgh_core::{LightingGridHierarchy, PointLight};
//! use lgh_gpu::{Gpu, GpuBuilder, GpuGrid, GpuHierarchy, ShadingPoint};
//!
//! let lights: Vec<PointLight> = (0..1000)
//!     .map(|i| PointLight::new(Vec3::new(i as f32 * 0.01, 0.0, 1.0), Vec3::ONE))
//!     .collect();
//! let gpu = Gpu::new()?; // a headless device: any Vulkan, Metal or DX12 adapter
//! let mut builder = GpuBuilder::new(&gpu, GpuGrid::fitting(&lights)?, 2.0)?; // α = 2
//! builder.rebuild(&lights)?; // built on the GPU
//! let floor = ShadingPoint::new(Vec3::ZERO, Vec3::Z, Vec3::splat(0.8));
//! let radiance = builder.hierarchy().shade(&[floor])?; // outgoing radiance, RGB
//! assert!(radiance[0][0] > 0.0);
//! let draws = builder.hierarchy().gather(&[floor], 4, 0)?; // 4 lights for shadow rays
//! assert_eq!(draws.len(), 4);
//! // The same lights built by lgh-core on the CPU, uploaded: the same image within tolerance.
//! let lgh = LightingGridHierarchy::build(&lights, &builder.grid().settings())?;
//! let uploaded = GpuHierarchy::upload(&gpu, &lgh, 2.0)?.shade(&[floor])?;
//! assert!((uploaded[0][0] - radiance[0][0]).abs() < 1e-4 * radiance[0][0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod build;
pub mod cells;
pub mod context;
pub mod dispatch;
pub mod error;
pub mod gather;
pub mod grid;
pub mod hierarchy;
pub mod kernels;
pub mod layout;
pub mod reference;
pub mod scan;
pub mod sort;
pub mod timing;

pub use build::{BuiltLight, GpuBuilder};
pub use context::Gpu;
pub use error::GpuError;
pub use grid::GpuGrid;
pub use hierarchy::GpuHierarchy;
pub use layout::{GatherSample, GpuLight, LevelGrid, ShadingPoint};
pub use timing::GpuTiming;
