//! The buffers' element types and the kernels' uniforms: the contract for an engine not on
//! wgpu that dispatches the same kernels (`generated/`). Each is `#[repr(C)]` with the offsets
//! of its WGSL struct (a `vec3<f32>` is 16-byte aligned there, so each is padded to 16 bytes),
//! and mirrored in C by `generated/lgh_gpu.h` (cbindgen; `tests/header.rs` keeps it current).

use bytemuck::{Pod, Zeroable};
use lgh_core::glam::Vec3;

/// A light of one level: its centre `p_ℓi` (eq. 2) and RGB intensity `I_ℓi` (eq. 1). 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// Centre.
    pub position: [f32; 3],
    /// Padding (WGSL's `vec3` alignment).
    pub _pad0: f32,
    /// RGB radiant intensity (W/sr).
    pub intensity: [f32; 3],
    /// Padding.
    pub _pad1: f32,
}

/// A shading point of a G-buffer: position, unit normal and Lambertian albedo. 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ShadingPoint {
    /// Position.
    pub position: [f32; 3],
    /// Padding.
    pub _pad0: f32,
    /// Unit normal: light from behind it does not count.
    pub normal: [f32; 3],
    /// Padding.
    pub _pad1: f32,
    /// RGB albedo `ρ`: the outgoing radiance is `ρ/π · Σ B·I·g(d)·max(0, n·ω)`.
    pub albedo: [f32; 3],
    /// Padding.
    pub _pad2: f32,
}

impl ShadingPoint {
    /// A shading point at `position` with unit `normal` and `albedo`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_gpu::ShadingPoint;
    ///
    /// let p = ShadingPoint::new(Vec3::ZERO, Vec3::Z, Vec3::splat(0.5));
    /// assert_eq!(p.normal, [0.0, 0.0, 1.0]);
    /// assert_eq!(core::mem::size_of::<ShadingPoint>(), 48);
    /// ```
    #[must_use]
    pub fn new(position: Vec3, normal: Vec3, albedo: Vec3) -> Self {
        ShadingPoint {
            position: position.to_array(),
            normal: normal.to_array(),
            albedo: albedo.to_array(),
            ..Default::default()
        }
    }
}

/// How a level's cells are numbered in its starts ([`LevelGrid::order`]) and where the starts
/// are ([`LevelGrid::bank`]).
pub mod cell_order {
    /// Row by row: cell `(x, y, z)` is `(z·dims.y + y)·dims.x + x` (cells sorted on the CPU).
    pub const ROWS: u32 = 0;
    /// By the Morton code of `(x, y, z)` (the hierarchy built on the GPU, `build.wgsl`).
    pub const MORTON: u32 = 1;
    /// The starts are in the cell starts' buffer (binding 2).
    pub const IN_STARTS: u32 = 0;
    /// The starts are the GPU build's vertex numbering (binding 7): a level's cells are blocks
    /// of 2³ vertices, so `stride` 8.
    pub const IN_SLOTS: u32 = 1;
}

/// One level as the query reads it: its cells (a dense grid over the level's lights' box, each
/// cell a range of the level's lights sorted by cell), its lights, and its blending. 80 bytes.
/// `dims` all zero: no cells, every light is scanned (the top level, which has a few).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LevelGrid {
    /// The low corner of the cells.
    pub origin: [f32; 3],
    /// A cell's side.
    pub cell: f32,
    /// Cells along x, y, z.
    pub dims: [u32; 3],
    /// Where the level's cell starts begin in the starts buffer.
    pub first_cell: u32,
    /// Where the level's lights begin in the lights buffer.
    pub first_light: u32,
    /// How many lights it has.
    pub light_count: u32,
    /// A light counts only if its squared distance is above this (`r_{ℓ−1}²`; −1 for level 0)…
    pub inner2: f32,
    /// …and at most this (`(2 r_ℓ)²`; the largest float for the top level).
    pub outer2: f32,
    /// `B_ℓ(d) = clamp(min(a d + c1, c2 − b d), 0, 1)` as `[a, c1, b, c2]` (eq. 3).
    pub ramp: [f32; 4],
    /// How far a light may lie outside its cell: 0 where lights are sorted by their position,
    /// `h_ℓ` where a vertex's light is filed under its vertex (its centre is within a cell of it).
    pub margin: f32,
    /// Cell `c`'s lights are `starts[first_cell + stride·c] .. starts[first_cell + stride·(c+1)]`
    /// (relative to `first_light`).
    pub stride: u32,
    /// How cells are numbered: [`cell_order::ROWS`] or [`cell_order::MORTON`].
    pub order: u32,
    /// Which buffer holds the cell starts: [`cell_order::IN_STARTS`] or [`cell_order::IN_SLOTS`].
    pub bank: u32,
}

/// The walk's parameters (`walk.wgsl`'s `Params`, a uniform): the query's and the gather's.
/// 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct WalkParams {
    /// Levels, 0 to the top.
    pub levels: u32,
    /// Shading points.
    pub points: u32,
    /// The fall-off's clamp `h0`: `g(d) = 1 / max(d, h0)²`.
    pub h0: f32,
    /// The lights from this index on are in the second lights buffer (binding 6): one binding
    /// holds at most the device's `max_storage_buffer_binding_size`.
    pub split: u32,
    /// The gather's draws per point (`gather.wgsl`; 0 for the shade).
    pub k: u32,
    /// The gather's seed.
    pub seed: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

/// One light the gather drew for a shading point (`gather.wgsl`'s `Sample`). 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GatherSample {
    /// The light's centre: where the shadow ray goes.
    pub position: [f32; 3],
    /// Padding.
    pub _pad0: f32,
    /// The RGB radiance it stands for when unshadowed: `ρ/π · term · W / w / K`.
    pub weight: [f32; 3],
    /// Padding.
    pub _pad1: f32,
}

/// A build dispatch's uniform (`build.wgsl`'s `Step`), at a dynamic offset. 64 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BuildStep {
    /// The grid's origin (the low corner of level-1 cell 0).
    pub origin: [f32; 3],
    /// The level-1 spacing.
    pub h1: f32,
    /// Input lights.
    pub n: u32,
    /// Morton bits a side.
    pub bits: u32,
    /// This dispatch's level ℓ.
    pub level: u32,
    /// The top level.
    pub top: u32,
    /// The largest level-1 cell coordinate of a light.
    pub max_cell: u32,
    /// Where level ℓ's vertex slots begin in the slots buffer.
    pub slot_offset: u32,
    /// Where level ℓ's lights begin in the level lights buffer.
    pub light_base: u32,
    /// Level ℓ's weak-light threshold (0 on the top level).
    pub threshold: f32,
    /// Items of the dispatch (lights, cells, vertex slots or vertices).
    pub count: u32,
    /// Workgroups each vertex's sums are split over (the coarse levels' splat).
    pub parts: u32,
    /// Where level ℓ's vertices begin in the list of vertex slots.
    pub list_offset: u32,
    /// Padding.
    pub _pad: u32,
}

/// An input light in the build's sorted order (`build.wgsl`'s `Sorted`). 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SortedLight {
    /// Its place in its level-1 cell, in cell units.
    pub frac: [f32; 3],
    /// Its luminance.
    pub luminance: f32,
    /// Its RGB intensity.
    pub intensity: [f32; 3],
    /// Its level-1 cell, 10 bits an axis (x lowest).
    pub cell: u32,
}

/// A scan dispatch's uniform (`scan.wgsl`'s `Step`). 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct ScanStep {
    /// Where the values begin in the buffer.
    pub offset: u32,
    /// How many.
    pub count: u32,
    /// Where the blocks' sums are written (or read back, scanned).
    pub sums: u32,
    /// Padding.
    pub _pad: u32,
}

/// A radix sort pass's uniform (`sort.wgsl`'s `Pass`). 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct SortPass {
    /// Pairs.
    pub count: u32,
    /// The digit's shift.
    pub shift: u32,
    /// Tiles of 256 pairs.
    pub tiles: u32,
    /// Padding.
    pub _pad: u32,
}
