//! A hierarchy's levels on the GPU for one α, and its query: eq. (1)'s blended sum at a buffer of
//! shading points with a Lambertian response, unshadowed (`shade.wgsl`).

use std::sync::Arc;

use lgh_core::glam::Vec3;
use lgh_core::{Blending, LightingGridHierarchy};
use wgpu::util::DeviceExt;

use crate::cells::Cells;
use crate::context::Gpu;
use crate::dispatch;
use crate::error::GpuError;
use crate::layout::{cell_order, GpuLight, LevelGrid, ShadingPoint, WalkParams};
use crate::timing::{GpuTiming, PassTimer};

/// The most cells of one level's dense grid (64 MiB of cell starts).
pub const MAX_CELLS: u64 = 1 << 24;

/// Threads of a workgroup of `walk.wgsl` (its `WORKGROUP`).
const WORKGROUP: u32 = 64;

/// A [`LightingGridHierarchy`] uploaded for the query at one α: each level's lights that the CPU
/// query reports ([`LightingGridHierarchy::is_active`]), sorted into cells of half the level's
/// reach, and each level's blending `B_ℓ` (eq. 3). The buffers stay on the GPU.
#[derive(Debug)]
pub struct GpuHierarchy {
    pub(crate) gpu: Gpu,
    pub(crate) levels: Vec<LevelGrid>,
    pub(crate) h0: f32,
    pub(crate) alpha: f32,
    pub(crate) buffers: QueryBuffers,
    pub(crate) kernels: Arc<QueryKernels>,
}

/// The buffers the query reads (`walk.wgsl`'s bindings).
#[derive(Clone, Debug)]
pub(crate) struct QueryBuffers {
    /// The levels (binding 1).
    pub levels: wgpu::Buffer,
    /// Cell starts of the levels sorted on the CPU and of the GPU build's level 0 (binding 2).
    pub starts: wgpu::Buffer,
    /// The GPU build's vertex numbering, whose blocks are the cells of levels ≥ 1 (binding 7).
    pub slots: wgpu::Buffer,
    /// The lights (binding 3)…
    pub lights: wgpu::Buffer,
    /// …and those from `split` on (binding 6; a one-light placeholder where all fit in the first).
    pub lights_hi: wgpu::Buffer,
    pub split: u32,
}

/// The kernels that walk the hierarchy, compiled once for a device.
#[derive(Debug)]
pub(crate) struct QueryKernels {
    shade: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
    gather: (wgpu::ComputePipeline, wgpu::BindGroupLayout),
}

impl QueryKernels {
    pub fn new(device: &wgpu::Device) -> QueryKernels {
        let compile = |kernel: crate::kernels::Kernel| {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(kernel.name),
                source: wgpu::ShaderSource::Wgsl(kernel.source().into()),
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(kernel.name),
                layout: None,
                module: &module,
                entry_point: Some(kernel.entries[0]),
                compilation_options: Default::default(),
                cache: None,
            });
            let layout = pipeline.get_bind_group_layout(0);
            (pipeline, layout)
        };
        QueryKernels {
            shade: compile(crate::kernels::SHADE),
            gather: compile(crate::kernels::GATHER),
        }
    }
}

/// Which kernel walks the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Walk {
    Shade,
    Gather,
}

/// `[a, c1, b, c2]` of `B_ℓ(d) = clamp(min(a d + c1, c2 − b d), 0, 1)`, the same floats as
/// lgh-core's: `1/r_ℓ = (1/r_0) / 2^ℓ`, exact.
fn ramp(blending: &Blending, level: u8) -> [f32; 4] {
    let inv = |l: u8| (1.0 / blending.radius(0)) / (1u64 << l) as f32;
    let top = blending.max_level();
    let (a, c1) = if level > 0 {
        (inv(level - 1), -1.0)
    } else {
        (0.0, 1.0)
    };
    let (b, c2) = if level < top {
        (inv(level), 2.0)
    } else {
        (0.0, 1.0)
    };
    [a, c1, b, c2]
}

/// Level `level`'s blending as the query reads it: its support (squared) and ramp.
pub(crate) fn blended(blending: &Blending, level: u8, top: u8) -> LevelGrid {
    let (inner, outer) = blending.support(level);
    LevelGrid {
        inner2: if level == 0 { -1.0 } else { inner * inner },
        outer2: if level == top {
            f32::MAX
        } else {
            outer * outer
        },
        ramp: ramp(blending, level),
        ..Default::default()
    }
}

/// The level's grid, its cell starts and its lights in cell order.
fn level_grid(
    lgh: &LightingGridHierarchy,
    blending: &Blending,
    level: u8,
) -> Result<(LevelGrid, Vec<u32>, Vec<GpuLight>), GpuError> {
    let top = lgh.max_level();
    let lights: Vec<_> = lgh
        .level(level)
        .iter()
        .filter(|l| lgh.is_active(level, l))
        .collect();
    let (_, outer) = blending.support(level);
    let cells = if level == top {
        Cells {
            origin: Vec3::ZERO,
            cell: 0.0,
            dims: [0; 3],
            starts: Vec::new(),
            order: (0..lights.len() as u32).collect(),
        }
    } else {
        let positions: Vec<Vec3> = lights.iter().map(|l| l.position).collect();
        Cells::sort(&positions, outer * 0.5, MAX_CELLS, level)?
    };
    let gpu_lights = cells
        .order
        .iter()
        .map(|&i| GpuLight {
            position: lights[i as usize].position.to_array(),
            intensity: lights[i as usize].intensity.to_array(),
            ..Default::default()
        })
        .collect();
    let grid = LevelGrid {
        origin: cells.origin.to_array(),
        cell: cells.cell,
        dims: cells.dims,
        light_count: lights.len() as u32,
        stride: 1,
        order: cell_order::ROWS,
        bank: cell_order::IN_STARTS,
        ..blended(blending, level, top)
    };
    Ok((grid, cells.starts, gpu_lights))
}

impl GpuHierarchy {
    /// Uploads `lgh` for queries at `alpha` (the paper's α; lgh-core's [`Blending`]).
    ///
    /// Errors if α is refused, if a level's lights are too spread out for its dense cells
    /// ([`MAX_CELLS`]), or if a buffer exceeds the device's binding size.
    pub fn upload(
        gpu: &Gpu,
        lgh: &LightingGridHierarchy,
        alpha: f32,
    ) -> Result<GpuHierarchy, GpuError> {
        let limit = gpu.device().limits().max_storage_buffer_binding_size;
        Self::upload_within(gpu, lgh, alpha, limit)
    }

    /// [`upload`](Self::upload) with the lights split over two bindings of at most `limit`
    /// bytes each.
    fn upload_within(
        gpu: &Gpu,
        lgh: &LightingGridHierarchy,
        alpha: f32,
        limit: u64,
    ) -> Result<GpuHierarchy, GpuError> {
        let blending = lgh.blending(alpha)?;
        let (mut levels, mut starts, mut lights) = (Vec::new(), Vec::new(), Vec::new());
        if !lgh.is_empty() {
            for level in 0..=lgh.max_level() {
                let (mut grid, level_starts, level_lights) = level_grid(lgh, &blending, level)?;
                grid.first_cell = starts.len() as u32;
                grid.first_light = lights.len() as u32;
                starts.extend(level_starts);
                lights.extend(level_lights);
                levels.push(grid);
            }
        }
        // WGSL has no empty arrays: one zeroed element where a buffer would be empty.
        starts.push(0);
        if lights.is_empty() {
            lights.push(GpuLight::default());
        }
        // Two bindings of lights, the second from `split` on, where one would be too large.
        let split = (limit / size_of::<GpuLight>() as u64).min(u32::MAX as u64) as usize;
        check_size(
            "the lights",
            lights.len() * size_of::<GpuLight>(),
            2 * limit,
        )?;
        let hi = if lights.len() > split {
            lights.split_off(split)
        } else {
            vec![GpuLight::default()]
        };
        check_size("the cells", starts.len() * size_of::<u32>(), limit)?;
        let device = gpu.device();
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let mut level_bytes = bytemuck::cast_slice::<LevelGrid, u8>(&levels).to_vec();
        if levels.is_empty() {
            level_bytes = bytemuck::bytes_of(&LevelGrid::default()).to_vec();
        }
        let buffers = QueryBuffers {
            levels: storage("lgh-gpu levels", &level_bytes),
            starts: storage("lgh-gpu cell starts", bytemuck::cast_slice(&starts)),
            slots: storage("lgh-gpu slots (none)", &[0; 4]),
            lights: storage("lgh-gpu lights", bytemuck::cast_slice(&lights)),
            lights_hi: storage("lgh-gpu lights, second", bytemuck::cast_slice(&hi)),
            split: split as u32,
        };
        Ok(GpuHierarchy {
            gpu: gpu.clone(),
            h0: lgh.h0(),
            alpha,
            levels,
            buffers,
            kernels: Arc::new(QueryKernels::new(device)),
        })
    }

    /// The α it was uploaded for.
    #[must_use]
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// Its levels as the query reads them.
    #[must_use]
    pub fn levels(&self) -> &[LevelGrid] {
        &self.levels
    }

    /// The outgoing radiance at each shading point, RGB: `ρ/π · Σ_ℓ Σ_i B_ℓ(d)·g(d)·I_ℓi·max(0,
    /// n·ω)` over the lights lgh-core's query reports there (eq. 1 with eq. 3's blending,
    /// `g(d) = 1/max(d, h0)²`, unshadowed): what `LightingGridHierarchy::query_sum` sums with
    /// that response, up to the order of the sum. Runs on the GPU and waits for it.
    ///
    /// Errors on a non-finite point ([`GpuError::InvalidPoint`]) or a failed readback.
    pub fn shade(&self, points: &[ShadingPoint]) -> Result<Vec<[f32; 3]>, GpuError> {
        self.shade_timed(points).map(|(radiance, _)| radiance)
    }

    /// [`shade`](Self::shade), with how long it took: the kernel's own time by timestamp
    /// queries where the device has them, and the wall time from the submission to the results
    /// read back.
    pub fn shade_timed(
        &self,
        points: &[ShadingPoint],
    ) -> Result<(Vec<[f32; 3]>, GpuTiming), GpuError> {
        let (rgba, timing) = self.walk::<[f32; 4]>(Walk::Shade, points, 1, 0)?;
        let radiance = rgba.into_iter().map(|c| [c[0], c[1], c[2]]).collect();
        Ok((radiance, timing))
    }

    /// [`shade`](Self::shade) without blocking: in a browser (wasm32), where the results come
    /// back on the page's event loop.
    pub async fn shade_async(&self, points: &[ShadingPoint]) -> Result<Vec<[f32; 3]>, GpuError> {
        let (rgba, _) = self
            .walk_async::<[f32; 4]>(Walk::Shade, points, 1, 0)
            .await?;
        Ok(rgba.into_iter().map(|c| [c[0], c[1], c[2]]).collect())
    }

    /// Runs `walk` at `points`, `per_point` outputs of `T` each, and reads them back.
    pub(crate) fn walk<T: bytemuck::Pod>(
        &self,
        walk: Walk,
        points: &[ShadingPoint],
        per_point: u32,
        seed: u32,
    ) -> Result<(Vec<T>, GpuTiming), GpuError> {
        pollster::block_on(self.walk_async(walk, points, per_point, seed))
    }

    /// [`walk`](Self::walk) without blocking.
    pub(crate) async fn walk_async<T: bytemuck::Pod>(
        &self,
        walk: Walk,
        points: &[ShadingPoint],
        per_point: u32,
        seed: u32,
    ) -> Result<(Vec<T>, GpuTiming), GpuError> {
        if let Some(index) = points.iter().position(|p| {
            let all = [p.position, p.normal, p.albedo];
            !all.iter().flatten().all(|v| v.is_finite())
        }) {
            return Err(GpuError::InvalidPoint { index });
        }
        if points.is_empty() {
            let timing = GpuTiming {
                kernel_ms: None,
                wall_ms: 0.0,
            };
            return Ok((Vec::new(), timing));
        }
        let device = self.gpu.device();
        let limit = device.limits().max_storage_buffer_binding_size;
        check_size("the shading points", size_of_val(points), limit)?;
        let out_bytes = (points.len() * per_point as usize * size_of::<T>()) as u64;
        check_size("the results", out_bytes as usize, limit)?;
        let point_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("lgh-gpu points"),
            contents: bytemuck::cast_slice(points),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let buffer = |label: &str, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: out_bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        let out = buffer(
            "lgh-gpu results",
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let staging = buffer(
            "lgh-gpu readback",
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        let timer = PassTimer::new(&self.gpu);
        let mut encoder = device.create_command_encoder(&Default::default());
        let count = points.len() as u32;
        self.record_walk(
            &mut encoder,
            walk,
            (&point_buffer, &out, count),
            per_point,
            seed,
            timer.as_ref(),
        );
        encoder.copy_buffer_to_buffer(&out, 0, &staging, 0, out_bytes);
        if let Some(t) = &timer {
            t.resolve(&mut encoder);
        }
        let start = crate::timing::Stopwatch::start();
        self.gpu.queue().submit([encoder.finish()]);
        let values: Vec<T> = self.gpu.read_back_async(&staging).await?;
        let wall_ms = start.ms();
        let kernel_ms = match timer {
            Some(t) => Some(t.milliseconds_async(&self.gpu).await?),
            None => None,
        };
        Ok((values, GpuTiming { kernel_ms, wall_ms }))
    }

    /// Records the query into the caller's `encoder` — `count` shading points of `points`
    /// ([`ShadingPoint`]s, 48 bytes each, `STORAGE` usage) to `radiance` (`[f32; 4]` each: RGB
    /// and 0; `STORAGE`) — and reads nothing back: how an engine runs it every frame on its own
    /// G-buffer. [`shade`](Self::shade) is this, with the upload and the readback.
    ///
    /// Errors where a buffer is smaller than `count` of its elements
    /// ([`GpuError::BufferTooSmall`]) or larger than a binding may be.
    pub fn record_shade(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        points: &wgpu::Buffer,
        radiance: &wgpu::Buffer,
        count: u32,
    ) -> Result<(), GpuError> {
        self.check_buffers((points, radiance, count), 16)?;
        self.record_walk(encoder, Walk::Shade, (points, radiance, count), 1, 0, None);
        Ok(())
    }

    /// Errors unless `points` holds `count` shading points and `out` `count` results of
    /// `per_point` bytes, each within a binding's size.
    pub(crate) fn check_buffers(
        &self,
        (points, out, count): (&wgpu::Buffer, &wgpu::Buffer, u32),
        per_point: u64,
    ) -> Result<(), GpuError> {
        let limit = self.gpu.device().limits().max_storage_buffer_binding_size;
        let n = u64::from(count);
        for (what, buffer, needed) in [
            (
                "the shading points",
                points,
                n * size_of::<ShadingPoint>() as u64,
            ),
            ("the results", out, n * per_point),
        ] {
            if buffer.size() < needed {
                return Err(GpuError::BufferTooSmall {
                    what,
                    bytes: buffer.size(),
                    needed,
                });
            }
            check_size(what, needed as usize, limit)?;
        }
        Ok(())
    }

    /// Records `walk` over `count` points of `points` into `out`, `per_point` results a point
    /// (the gather's K), timed by `timer` where given.
    pub(crate) fn record_walk(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        walk: Walk,
        (points, out, count): (&wgpu::Buffer, &wgpu::Buffer, u32),
        per_point: u32,
        seed: u32,
        timer: Option<&PassTimer>,
    ) {
        let device = self.gpu.device();
        let (pipeline, layout) = match walk {
            Walk::Shade => &self.kernels.shade,
            Walk::Gather => &self.kernels.gather,
        };
        let params = WalkParams {
            levels: self.levels.len() as u32,
            points: count,
            h0: self.h0,
            split: self.buffers.split,
            k: per_point,
            seed,
            _pad: [0; 2],
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("lgh-gpu params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let b = &self.buffers;
        let buffers = [
            &uniform,
            &b.levels,
            &b.starts,
            &b.lights,
            points,
            out,
            &b.lights_hi,
            &b.slots,
        ];
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lgh-gpu walk"),
            layout,
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("lgh-gpu walk"),
            timestamp_writes: timer.map(PassTimer::writes),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        let (x, y) = dispatch::groups(count.div_ceil(WORKGROUP), &device.limits());
        pass.dispatch_workgroups(x, y, 1);
    }
}

pub(crate) fn check_size(what: &'static str, bytes: usize, limit: u64) -> Result<(), GpuError> {
    let bytes = bytes as u64;
    if bytes > limit {
        return Err(GpuError::TooLarge { what, bytes, limit });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::{GridSettings, PointLight};

    /// Lights split over two bindings give the same bits as in one.
    #[test]
    fn lights_split_over_two_bindings_give_the_same_bits() {
        let gpu = match Gpu::new() {
            Ok(gpu) => gpu,
            Err(e) => return lgh_tests::Piece::Gpu.missing(&e.to_string()),
        };
        let lights: Vec<PointLight> = lgh_core::testsets::clumped_lights(500, 8);
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        let points: Vec<ShadingPoint> = (0..200)
            .map(|i| {
                let p = Vec3::new(i as f32 * 0.05, 1.0, (i % 7) as f32);
                ShadingPoint::new(p, Vec3::Y, Vec3::splat(0.7))
            })
            .collect();
        let whole = GpuHierarchy::upload(&gpu, &lgh, 2.0).unwrap();
        let total = whole.levels.iter().map(|l| l.light_count).sum::<u32>();
        // A binding of three fifths of the lights: the second holds the rest.
        let most = (total as u64 * 3 / 5 + 1) * size_of::<GpuLight>() as u64;
        let split = GpuHierarchy::upload_within(&gpu, &lgh, 2.0, most).unwrap();
        assert!(
            split.buffers.split < total,
            "{} of {total}",
            split.buffers.split
        );
        assert_eq!(split.shade(&points).unwrap(), whole.shade(&points).unwrap());
        let too_small = GpuHierarchy::upload_within(&gpu, &lgh, 2.0, 64);
        assert!(matches!(too_small, Err(GpuError::TooLarge { .. })));
    }
}
