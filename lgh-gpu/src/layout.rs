//! The buffers' element types. Each is `#[repr(C)]` with the offsets of its WGSL struct in
//! `shade.wgsl` (a `vec3<f32>` is 16-byte aligned there, so each is padded to 16 bytes): an
//! engine not on wgpu that dispatches the same kernels fills its buffers with these layouts.

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

/// One level as the query reads it: its cells (a dense grid over the level's lights' box, each
/// cell a range of the level's lights sorted by cell), its lights, and its blending. 64 bytes.
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
    /// Where the level's `dims.x·dims.y·dims.z + 1` cell starts begin in the starts buffer.
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
}

/// The query's parameters (a uniform). 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Params {
    /// Levels, 0 to the top.
    pub levels: u32,
    /// Shading points.
    pub points: u32,
    /// The fall-off's clamp `h0`: `g(d) = 1 / max(d, h0)²`.
    pub h0: f32,
    /// The lights from this index on are in the second lights buffer (binding 6): one binding
    /// holds at most the device's `max_storage_buffer_binding_size`.
    pub split: u32,
}
