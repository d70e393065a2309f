//! The Lighting Grid Hierarchy (Yuksel & Yuksel 2017) on the GPU, in wgpu compute shaders
//! written in WGSL: Vulkan, Metal and DX12 natively. It runs in the caller's `wgpu::Device` and
//! `Queue` ([`Gpu::from_device`], so it embeds in any wgpu engine) or in a headless device of its
//! own ([`Gpu::new`]); its buffers stay on the GPU between frames.
//!
//! What it does today: a hierarchy built by [`lgh_core`] is uploaded ([`GpuHierarchy::upload`]:
//! each level's lights sorted into cells the size of the level's reach) and queried at a buffer of
//! shading points — position, normal, albedo: a G-buffer — for eq. (1)'s blended sum with a
//! Lambertian response, unshadowed ([`GpuHierarchy::shade`], `shade.wgsl`). The build, the
//! intensity update, the rebuild of moving lights and the gather of lights for shadow rays on
//! the GPU are not there yet.
//!
//! | module | what it holds |
//! |---|---|
//! | [`context`] | [`Gpu`]: the device and queue, the caller's or a headless one, and which adapter it is |
//! | [`layout`] | the buffers' element types, `#[repr(C)]` and mirrored in the WGSL: a contract for engines not on wgpu |
//! | [`cells`] | a level's lights sorted into a dense grid of cells, with each cell's range (built on the CPU) |
//! | [`hierarchy`] | [`GpuHierarchy`]: a hierarchy's levels on the GPU for one α, and its query ([`shade`](GpuHierarchy::shade)) |
//! | [`reference`](mod@reference) | the same query on the CPU through lgh-core, the tests' and benches' reference |
//! | [`timing`] | a compute pass timed by timestamp queries, where the adapter has them |
//! | [`error`] | [`GpuError`] |
//!
//! For engines not on wgpu (Unreal, Godot, Unity, an in-house RHI), each kernel is committed in
//! `lgh-gpu/generated/` as naga translated it — SPIR-V, HLSL 6.0, GLSL 4.30, MSL 2.4 — and kept
//! current by `tests/translations.rs`: such an engine dispatches the same kernel on buffers laid
//! out as [`layout`] says.
//!
//! ```no_run
//! use lgh_core::glam::Vec3;
//! use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
//! use lgh_gpu::{Gpu, GpuHierarchy, ShadingPoint};
//!
//! let lights: Vec<PointLight> = (0..1000)
//!     .map(|i| PointLight::new(Vec3::new(i as f32 * 0.01, 0.0, 1.0), Vec3::ONE))
//!     .collect();
//! let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
//! let gpu = Gpu::new()?; // a headless device: any Vulkan, Metal or DX12 adapter
//! let on_gpu = GpuHierarchy::upload(&gpu, &lgh, 2.0)?; // the paper's α = 2
//! let floor = ShadingPoint::new(Vec3::ZERO, Vec3::Z, Vec3::splat(0.8));
//! let radiance = on_gpu.shade(&[floor])?; // outgoing radiance, RGB
//! assert!(radiance[0][0] > 0.0);
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
