//! The hierarchy built on the GPU (`build.wgsl`, paper Sec. 3 and 5): from a buffer of lights,
//! every level by eqs. (1), (2), (4) and (5), deterministically (no float atomics: each sum is
//! gathered in a fixed order), in two submissions:
//!
//! 1. **Topology.** Each light counted in its level-1 cell, the counts scanned into the cells'
//!    starts, the lights sorted by cell, ties by index (a stable radix sort); each level's
//!    vertex slots marked where a light lies in one of the vertex's eight cells, and scanned into
//!    the vertices' numbers. The levels' vertex counts are read back (a few bytes) to place each
//!    level's lights.
//! 2. **Splat.** The lights gathered in the sorted order, then each vertex's light splatted from
//!    the input lights of its eight cells — one invocation a vertex on the fine levels; on the
//!    coarse ones, whose vertices gather many lights, each vertex's sums split over many
//!    workgroups (each adding its lanes' sums in a fixed tree), then the parts added in order.
//!
//! [`GpuBuilder::update_intensities`] (same positions, new intensities: the animated fire)
//! runs the splat alone; [`GpuBuilder::rebuild`] (lights that move, any count) both.

use std::sync::Arc;

use bytemuck::Pod;
use lgh_core::glam::Vec3;
use lgh_core::{Blending, BuildError, Channels, PointLight};

use crate::context::Gpu;
use crate::dispatch::{self, Uniforms};
use crate::error::GpuError;
use crate::grid::GpuGrid;
use crate::hierarchy::{blended, check_size, GpuHierarchy, QueryBuffers, QueryKernels};
use crate::layout::{cell_order, BuildStep as Step, GpuLight, LevelGrid, SortedLight};
use crate::scan::{self, Scan};
use crate::sort::RadixSort;
use crate::timing::{GpuTiming, PassTimer, SpanTimer};

/// Threads of a workgroup of `build.wgsl` (its `WORKGROUP`).
const WORKGROUP: u32 = 64;

/// Bytes of an input light's position or intensity: `[f32; 4]`, xyz and one unused.
const INPUT_BYTES: u64 = 16;

/// The most workgroups a level's splat takes: its vertices times their parts.
const PARTS_IN_ALL: u32 = 1 << 18;

/// The build's entry points: [`kernels::BUILD`](crate::kernels::BUILD)'s, then
/// [`kernels::MARK`](crate::kernels::MARK)'s, in their order.
#[derive(Clone, Copy, Debug)]
enum Kernel {
    Locate,
    CopyCounts,
    GatherSorted,
    Splat,
    MomentParts,
    FinishMoments,
    SizeParts,
    FinishVertices,
    ListVertices,
    ClearSlots,
    MarkCorners,
}

impl Kernel {
    /// Every kernel, in order.
    const ALL: [Kernel; 11] = [
        Kernel::Locate,
        Kernel::CopyCounts,
        Kernel::GatherSorted,
        Kernel::Splat,
        Kernel::MomentParts,
        Kernel::FinishMoments,
        Kernel::SizeParts,
        Kernel::FinishVertices,
        Kernel::ListVertices,
        Kernel::ClearSlots,
        Kernel::MarkCorners,
    ];

    /// The storage buffers the kernel binds (`build.wgsl`'s and `mark.wgsl`'s binding
    /// numbers): 1 positions, 2 intensities, 3 counts, 4 starts, 5 order, 6 sorted, 7 slots,
    /// 8 level lights, 9 extras, 10 keys, 11 partials, 12 vertex slots. At most 6, within
    /// WebGPU's default of 8 a kernel.
    fn bindings(self) -> &'static [u32] {
        match self {
            Kernel::Locate => &[1, 3, 5, 10],
            Kernel::CopyCounts => &[3, 4],
            Kernel::GatherSorted => &[1, 2, 5, 6, 8, 9],
            Kernel::Splat => &[4, 6, 8, 9, 12],
            Kernel::MomentParts | Kernel::SizeParts => &[4, 6, 11, 12],
            Kernel::FinishMoments => &[11, 12],
            Kernel::FinishVertices => &[8, 9, 11, 12],
            Kernel::ListVertices => &[7, 12],
            Kernel::ClearSlots => &[7],
            Kernel::MarkCorners => &[7, 10],
        }
    }
}

/// A light of a level as the GPU built it, read back ([`GpuBuilder::read_level`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuiltLight {
    /// Its grid vertex (levels ≥ 1), or the input light's index (level 0, as `[i, 0, 0]`).
    pub vertex: [u32; 3],
    /// Its centre (eq. 2).
    pub position: Vec3,
    /// Its RGB intensity (eq. 1); 0 where it is weaker than the threshold.
    pub intensity: Vec3,
    /// Its per-axis variance (eq. 4).
    pub variance: Vec3,
    /// Its size (eq. 5).
    pub size: f32,
}

/// The lights' buffers, for up to `capacity` lights: their order by cell is the sort's values;
/// each level's vertices listed by slot, at most [`list_len`] of them in all.
#[derive(Debug)]
struct LightBuffers {
    capacity: u32,
    positions: wgpu::Buffer,
    intensities: wgpu::Buffer,
    sort: RadixSort,
    sorted: wgpu::Buffer,
    vertex_slots: wgpu::Buffer,
}

/// The levels' lights' buffers (the query's lights and their variances and sizes), for up to
/// `capacity` lights of all levels together.
#[derive(Debug)]
struct OutBuffers {
    capacity: u32,
    lights: wgpu::Buffer,
    extras: wgpu::Buffer,
}

/// A hierarchy built, updated and rebuilt on the GPU, for queries at one α. Its buffers stay on
/// the GPU between frames and only grow.
///
/// ```no_run
/// use lgh_core::glam::Vec3;
/// use lgh_core::PointLight;
/// use lgh_gpu::{Gpu, GpuBuilder, GpuGrid, ShadingPoint};
///
/// let lights: Vec<PointLight> = (0..1000)
///     .map(|i| PointLight::new(Vec3::new(i as f32 * 0.01, 0.0, 1.0), Vec3::ONE))
///     .collect();
/// let gpu = Gpu::new()?;
/// let mut builder = GpuBuilder::new(&gpu, GpuGrid::fitting(&lights)?, 2.0)?;
/// builder.rebuild(&lights)?; // positions and intensities
/// builder.update_intensities(&vec![Vec3::splat(2.0); 1000])?; // the next frame
/// let floor = ShadingPoint::new(Vec3::ZERO, Vec3::Z, Vec3::splat(0.8));
/// let radiance = builder.hierarchy().shade(&[floor])?;
/// assert!(radiance[0][0] > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct GpuBuilder {
    gpu: Gpu,
    grid: GpuGrid,
    alpha: f32,
    prune_below: f32,
    blending: Blending,
    /// Each kernel's layout and pipeline, in [`Kernel`]'s order.
    layouts: Vec<wgpu::BindGroupLayout>,
    pipelines: Vec<wgpu::ComputePipeline>,
    scan: Scan,
    query: Arc<QueryKernels>,
    counts: wgpu::Buffer,
    starts: wgpu::Buffer,
    slots: wgpu::Buffer,
    /// Where each level ℓ ≥ 1's vertex slots begin in `slots` (index ℓ − 1).
    slot_offsets: Vec<u32>,
    /// Where the scans' block sums go in `slots`.
    slot_scratch: u32,
    level_buffer: wgpu::Buffer,
    /// The coarse levels' partial sums (`build.wgsl`'s `partials`).
    partials: wgpu::Buffer,
    lights: LightBuffers,
    out: OutBuffers,
    /// The lights of the last build.
    n: u32,
    /// Each level's grid as the query reads it.
    levels: Vec<LevelGrid>,
    /// Whether builds time each kernel, and the last build's times.
    profiling: bool,
    profile: std::sync::Mutex<Vec<(String, f64)>>,
}

impl GpuBuilder {
    /// A builder on `gpu` for lights within `grid`'s box, queried at `alpha` (the paper's α).
    /// Nothing is built until [`rebuild`](Self::rebuild).
    ///
    /// Errors if α is refused (lgh-core's [`Blending`]) or the grid's buffers exceed the
    /// device's binding size.
    pub fn new(gpu: &Gpu, grid: GpuGrid, alpha: f32) -> Result<GpuBuilder, GpuError> {
        let blending = Blending::new(alpha, grid.h1, grid.max_level())?;
        let device = gpu.device();
        let limit = device.limits().max_storage_buffer_binding_size;
        let cells = grid.side().pow(3);
        let starts_len = cells + 1 + Scan::scratch(cells + 1);
        let mut slot_offsets = Vec::new();
        let mut at = 0u32;
        for level in 1..=grid.max_level() {
            slot_offsets.push(at);
            at += slots_a_side(&grid, level).pow(3) + 1;
        }
        let slot_scratch = at;
        let scratch: u32 = (1..=grid.max_level())
            .map(|l| Scan::scratch(slots_a_side(&grid, l).pow(3) + 1))
            .sum();
        let slots_len = at + scratch;
        for (what, len) in [
            ("the cell counts", cells),
            ("the cell starts", starts_len),
            ("the vertex slots", slots_len),
        ] {
            check_size(what, len as usize * 4, limit)?;
        }
        let zeroed = |label: &str, len: u32, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: u64::from(len.max(1)) * 4,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let layouts: Vec<wgpu::BindGroupLayout> = Kernel::ALL
            .iter()
            .map(|k| {
                let label = format!("lgh-gpu build: {k:?}");
                dispatch::layout_of(device, &label, size_of::<Step>() as u64, k.bindings())
            })
            .collect();
        // The build's entry points, then the marking's: the order of [`Kernel`].
        let entries: Vec<(wgpu::ShaderModule, &str)> =
            [crate::kernels::BUILD, crate::kernels::MARK]
                .into_iter()
                .flat_map(|kernel| {
                    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                        label: Some(kernel.name),
                        source: wgpu::ShaderSource::Wgsl(kernel.source().into()),
                    });
                    kernel.entries.iter().map(move |&e| (module.clone(), e))
                })
                .collect();
        let pipelines = entries
            .iter()
            .zip(&layouts)
            .map(|((module, entry), layout)| dispatch::pipeline(device, layout, module, entry))
            .collect();
        let levels = grid.max_level() as u64 + 1;
        let level_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lgh-gpu levels"),
            size: levels * size_of::<LevelGrid>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let copy = wgpu::BufferUsages::COPY_SRC;
        let partials = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lgh-gpu partial sums"),
            size: u64::from(PARTS_IN_ALL) * 80,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        Ok(GpuBuilder {
            partials,
            gpu: gpu.clone(),
            grid,
            alpha,
            prune_below: 0.0,
            blending,
            scan: Scan::new(device),
            query: Arc::new(QueryKernels::new(device)),
            counts: zeroed("lgh-gpu cell counts", cells, wgpu::BufferUsages::empty()),
            starts: zeroed("lgh-gpu cell starts", starts_len, copy),
            slots: zeroed("lgh-gpu vertex slots", slots_len, copy),
            slot_offsets,
            slot_scratch,
            level_buffer,
            lights: light_buffers(device, &grid, 0),
            out: out_buffers(device, 0),
            n: 0,
            levels: Vec::new(),
            profiling: false,
            profile: Default::default(),
            layouts,
            pipelines,
        })
    }

    /// The builder with lgh-core's weak-light threshold `prune_below`
    /// ([`GridSettings::prune_below`](lgh_core::GridSettings::prune_below)): a light of a level
    /// below the top whose luminance is below it adds nothing. Errors unless finite and ≥ 0.
    pub fn with_prune_below(mut self, prune_below: f32) -> Result<GpuBuilder, GpuError> {
        if !(prune_below.is_finite() && prune_below >= 0.0) {
            return Err(BuildError::InvalidThreshold {
                threshold: prune_below,
            }
            .into());
        }
        self.prune_below = prune_below;
        Ok(self)
    }

    /// The builder timing each kernel of its builds (where the adapter has timestamps inside
    /// passes), for [`profile`](Self::profile). Off by default: the timestamps cost a little.
    #[must_use]
    pub fn with_profiling(mut self, on: bool) -> GpuBuilder {
        self.profiling = on;
        self
    }

    /// Where the last build's or update's GPU time went: each kernel (or group of them) and
    /// its milliseconds, in order; empty unless [`with_profiling`](Self::with_profiling) and
    /// the adapter has timestamps inside passes.
    #[must_use]
    pub fn profile(&self) -> Vec<(String, f64)> {
        self.profile.lock().map(|p| p.clone()).unwrap_or_default()
    }

    fn spans(&self) -> Option<SpanTimer> {
        if self.profiling {
            SpanTimer::new(&self.gpu, 128)
        } else {
            None
        }
    }

    /// Keeps `spans`' times as the profile (after the topology's, unless `fresh`).
    fn keep_profile(&self, spans: Option<SpanTimer>, fresh: bool) -> Result<(), GpuError> {
        let Some(spans) = spans else { return Ok(()) };
        let times = spans.milliseconds(&self.gpu)?;
        if let Ok(mut profile) = self.profile.lock() {
            if fresh {
                profile.clear();
            }
            profile.extend(times);
        }
        Ok(())
    }

    /// Its grid.
    #[must_use]
    pub fn grid(&self) -> &GpuGrid {
        &self.grid
    }

    /// The lights of the last build.
    #[must_use]
    pub fn len(&self) -> usize {
        self.n as usize
    }

    /// True before any light was built.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Builds the hierarchy of `lights` (any count, any positions: lights that moved), both
    /// submissions. Lights outside the grid's box are clamped into its boundary cells (as
    /// lgh-core clamps to its grid), so points far outside the box may miss them.
    ///
    /// Errors on a non-finite position, a non-finite intensity or one with a negative luminance
    /// (lgh-core's [`BuildError`]s; a negative channel alone is taken, as lgh-core's), or where the levels' lights exceed the device's binding size.
    pub fn rebuild(&mut self, lights: &[PointLight]) -> Result<GpuTiming, GpuError> {
        for (index, l) in lights.iter().enumerate() {
            if !l.position.is_finite() {
                return Err(BuildError::NonFinitePosition { index }.into());
            }
            check_intensity(index, l.intensity)?;
        }
        let n = u32::try_from(lights.len()).map_err(|_| BuildError::TooManyLights {
            count: lights.len(),
        })?;
        self.make_room(n);
        let positions: Vec<[f32; 4]> = lights
            .iter()
            .map(|l| l.position.extend(1.0).into())
            .collect();
        let intensities: Vec<[f32; 4]> = lights
            .iter()
            .map(|l| l.intensity.extend(0.0).into())
            .collect();
        let queue = self.gpu.queue();
        queue.write_buffer(&self.lights.positions, 0, bytemuck::cast_slice(&positions));
        queue.write_buffer(
            &self.lights.intensities,
            0,
            bytemuck::cast_slice(&intensities),
        );
        self.build_uploaded()
    }

    /// [`rebuild`](Self::rebuild) from `n` lights already on the GPU — an engine whose lights a
    /// compute pass made: positions and intensities as `[f32; 4]` each (xyz; the fourth is
    /// ignored) in the caller's buffers (`COPY_SRC` usage), copied into the builder's. Nothing
    /// checks them on the CPU: a non-finite position or a negative luminance makes a hierarchy
    /// as wrong as its input.
    ///
    /// Errors where a buffer holds fewer than `n` lights ([`GpuError::BufferTooSmall`]).
    pub fn rebuild_from(
        &mut self,
        positions: &wgpu::Buffer,
        intensities: &wgpu::Buffer,
        n: u32,
    ) -> Result<GpuTiming, GpuError> {
        let needed = u64::from(n) * INPUT_BYTES;
        for (what, buffer) in [("positions", positions), ("intensities", intensities)] {
            if buffer.size() < needed {
                let bytes = buffer.size();
                return Err(GpuError::BufferTooSmall {
                    what,
                    bytes,
                    needed,
                });
            }
        }
        self.make_room(n);
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        if needed > 0 {
            encoder.copy_buffer_to_buffer(positions, 0, &self.lights.positions, 0, needed);
            encoder.copy_buffer_to_buffer(intensities, 0, &self.lights.intensities, 0, needed);
        }
        self.gpu.queue().submit([encoder.finish()]);
        self.build_uploaded()
    }

    /// Room for `n` lights (the lights' buffers grown where they must), and `n` the count.
    fn make_room(&mut self, n: u32) {
        if n > self.lights.capacity {
            self.lights = light_buffers(self.gpu.device(), &self.grid, n);
        }
        self.n = n;
    }

    /// Both submissions of a build of the lights in the builder's input buffers.
    fn build_uploaded(&mut self) -> Result<GpuTiming, GpuError> {
        let start = crate::timing::Stopwatch::start();
        let (vertices, topology_ms) = self.topology()?;
        self.place_levels(&vertices)?;
        let splat_ms = self.splat(false)?;
        Ok(GpuTiming {
            kernel_ms: topology_ms.zip(splat_ms).map(|(a, b)| a + b),
            wall_ms: start.ms(),
        })
    }

    /// New intensities for the lights of the last [`rebuild`](Self::rebuild), same positions:
    /// the splat alone, the topology kept. Gives the same bits as a rebuild with them.
    ///
    /// Errors unless `intensities` has one per light, each finite with a luminance ≥ 0.
    pub fn update_intensities(&mut self, intensities: &[Vec3]) -> Result<GpuTiming, GpuError> {
        if intensities.len() != self.n as usize {
            return Err(BuildError::LengthMismatch {
                expected: self.n as usize,
                got: intensities.len(),
            }
            .into());
        }
        for (index, &i) in intensities.iter().enumerate() {
            check_intensity(index, i)?;
        }
        let rgb: Vec<[f32; 4]> = intensities.iter().map(|i| i.extend(0.0).into()).collect();
        let start = crate::timing::Stopwatch::start();
        self.gpu
            .queue()
            .write_buffer(&self.lights.intensities, 0, bytemuck::cast_slice(&rgb));
        let kernel_ms = self.splat(true)?;
        Ok(GpuTiming {
            kernel_ms,
            wall_ms: start.ms(),
        })
    }

    /// The hierarchy as the query reads it (its buffers shared with the builder: a later
    /// rebuild or update shows in it, unless the buffers had to grow).
    #[must_use]
    pub fn hierarchy(&self) -> GpuHierarchy {
        GpuHierarchy {
            gpu: self.gpu.clone(),
            levels: self.levels.clone(),
            h0: self.grid.h(0),
            alpha: self.alpha,
            buffers: QueryBuffers {
                levels: self.level_buffer.clone(),
                starts: self.starts.clone(),
                slots: self.slots.clone(),
                lights: self.out.lights.clone(),
                lights_hi: self.out.lights.clone(),
                split: u32::MAX,
            },
            kernels: self.query.clone(),
        }
    }

    /// Level `level`'s lights as built, read back from the GPU (the tests compare them with
    /// lgh-core's build on [`GpuGrid::settings`]): level 0 in the sorted order, each level
    /// above by vertex.
    pub fn read_level(&self, level: u8) -> Result<Vec<BuiltLight>, GpuError> {
        let Some(grid) = self.levels.get(level as usize) else {
            return Ok(Vec::new());
        };
        let lights: Vec<GpuLight> = self.read(&self.out.lights)?;
        let extras: Vec<[f32; 4]> = self.read(&self.out.extras)?;
        let first = grid.first_light as usize;
        let keys: Vec<[u32; 3]> = if level == 0 {
            let order: Vec<u32> = self.read(&self.lights.sort.values)?;
            order[..self.n as usize]
                .iter()
                .map(|&i| [i, 0, 0])
                .collect()
        } else {
            let slots: Vec<u32> = self.read(&self.slots)?;
            let offset = self.slot_offsets[level as usize - 1] as usize;
            let count = slots_a_side(&self.grid, level).pow(3) as usize;
            (0..count)
                .filter(|&m| slots[offset + m + 1] > slots[offset + m])
                .map(|m| demorton(m as u32))
                .collect()
        };
        Ok(keys
            .into_iter()
            .enumerate()
            .map(|(k, vertex)| {
                let (l, e) = (lights[first + k], extras[first + k]);
                BuiltLight {
                    vertex,
                    position: l.position.into(),
                    intensity: l.intensity.into(),
                    variance: Vec3::new(e[0], e[1], e[2]),
                    size: e[3],
                }
            })
            .collect())
    }

    fn read<T: Pod>(&self, buffer: &wgpu::Buffer) -> Result<Vec<T>, GpuError> {
        let encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        dispatch::read(&self.gpu, encoder, buffer)
    }

    /// The uniform of a dispatch at `level` over `count` items.
    fn step(&self, level: u8, count: u32) -> Step {
        let g = &self.grid;
        let top = g.max_level();
        Step {
            origin: g.origin.to_array(),
            h1: g.h1,
            n: self.n,
            bits: u32::from(g.bits),
            level: u32::from(level),
            top: u32::from(top),
            max_cell: g.max_cell(),
            slot_offset: if level > 0 {
                self.slot_offsets[level as usize - 1]
            } else {
                0
            },
            light_base: self.levels.get(level as usize).map_or(0, |l| l.first_light),
            threshold: if level == top { 0.0 } else { self.prune_below },
            count,
            parts: 1,
            list_offset: list_offset(g, level.max(1), self.n),
            _pad: 0,
        }
    }

    /// Each kernel's bind group of `uniforms` and the buffers it binds, in [`Kernel`]'s order.
    fn bind(&self, uniforms: &Uniforms) -> Vec<wgpu::BindGroup> {
        let l = &self.lights;
        let buffers = [
            &l.positions,
            &l.intensities,
            &self.counts,
            &self.starts,
            &l.sort.values,
            &l.sorted,
            &self.slots,
            &self.out.lights,
            &self.out.extras,
            &l.sort.keys,
            &self.partials,
            &l.vertex_slots,
        ];
        Kernel::ALL
            .iter()
            .zip(&self.layouts)
            .map(|(k, layout)| {
                let storage: Vec<(u32, &wgpu::Buffer)> = k
                    .bindings()
                    .iter()
                    .map(|&b| (b, buffers[b as usize - 1]))
                    .collect();
                dispatch::bind_of(self.gpu.device(), layout, uniforms, &storage)
            })
            .collect()
    }

    /// Records `kernel` over `items` (one invocation each; one workgroup each for the parts'
    /// kernels) with uniform `index`.
    fn record(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        binds: &[wgpu::BindGroup],
        uniforms: &Uniforms,
        (kernel, index, items): (Kernel, u32, u32),
    ) {
        let groups = match kernel {
            Kernel::MomentParts
            | Kernel::SizeParts
            | Kernel::FinishMoments
            | Kernel::FinishVertices => items,
            _ => items.div_ceil(WORKGROUP),
        };
        pass.set_pipeline(&self.pipelines[kernel as usize]);
        pass.set_bind_group(0, &binds[kernel as usize], &[uniforms.offset(index)]);
        let (x, y) = dispatch::groups(groups, &self.gpu.device().limits());
        pass.dispatch_workgroups(x, y, 1);
    }

    /// Submission 1: the counting sort and each level's vertex numbering; returns each level
    /// ℓ ≥ 1's vertex count.
    fn topology(&self) -> Result<(Vec<u32>, Option<f64>), GpuError> {
        let device = self.gpu.device();
        let g = &self.grid;
        let cells = g.side().pow(3);
        let mut steps = Vec::new();
        let n = self.n;
        steps.push(self.step(0, cells));
        // The scans: the cell starts, then each level's slots.
        let mut starts_scan = Vec::new();
        let mut scratch = cells + 1;
        Scan::plan(0, cells + 1, &mut scratch, &mut starts_scan);
        let mut slot_scans = Vec::new();
        let mut scratch = self.slot_scratch;
        for level in 1..=g.max_level() {
            let count = slots_a_side(g, level).pow(3);
            steps.push(self.step(level, count));
            let mut one = Vec::new();
            Scan::plan(
                self.slot_offsets[level as usize - 1],
                count + 1,
                &mut scratch,
                &mut one,
            );
            slot_scans.push(one);
        }
        let uniforms = Uniforms::new(device, &steps);
        let all_scans: Vec<scan::Step> = starts_scan
            .iter()
            .chain(slot_scans.iter().flatten())
            .map(|s| s.1)
            .collect();
        let scan_uniforms = Uniforms::new(device, &all_scans);
        let bind = self.bind(&uniforms);
        let bind_starts = self.scan.bind(device, &scan_uniforms, &self.starts);
        let bind_slots = self.scan.bind(device, &scan_uniforms, &self.slots);
        let levels = g.max_level() as u64;
        let totals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lgh-gpu vertex counts"),
            size: levels * 4,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let record = |pass: &mut wgpu::ComputePass<'_>, spans: &mut Option<SpanTimer>| {
            let limits = device.limits();
            timed(spans, pass, "locate", |p| {
                self.record(p, &bind, &uniforms, (Kernel::Locate, 0, n));
                self.record(p, &bind, &uniforms, (Kernel::CopyCounts, 0, cells));
            });
            timed(spans, pass, "scan the cells' counts", |p| {
                self.scan
                    .record(p, &bind_starts, &scan_uniforms, 0, &starts_scan, &limits);
            });
            let key_bits = 3 * u32::from(g.bits);
            timed(spans, pass, "sort the lights by cell", |p| {
                self.lights.sort.record(device, p, &self.scan, n, key_bits);
            });
            let mut first = starts_scan.len() as u32;
            for (k, one) in slot_scans.iter().enumerate() {
                let (index, count) = (k as u32 + 1, steps[k + 1].count);
                let label = format!("level {}: number the vertices", k + 1);
                timed(spans, pass, &label, |p| {
                    self.record(p, &bind, &uniforms, (Kernel::ClearSlots, index, count + 1));
                    self.record(p, &bind, &uniforms, (Kernel::MarkCorners, index, n));
                    self.scan
                        .record(p, &bind_slots, &scan_uniforms, first, one, &limits);
                    self.record(p, &bind, &uniforms, (Kernel::ListVertices, index, count));
                });
                first += one.len() as u32;
            }
        };
        // Each level's vertex count: the last entry of its scanned slots.
        let copy_totals = |encoder: &mut wgpu::CommandEncoder| {
            for level in 1..=g.max_level() {
                let at = self.slot_offsets[level as usize - 1] + slots_a_side(g, level).pow(3);
                let to = u64::from(level - 1) * 4;
                encoder.copy_buffer_to_buffer(&self.slots, u64::from(at) * 4, &totals, to, 4);
            }
        };
        let ms = self.run_pass("lgh-gpu build: topology", true, record, copy_totals)?;
        let vertices: Vec<u32> = self.gpu.read_back(&totals)?;
        Ok((vertices, ms))
    }

    /// Records one compute pass (`record` fills it, timing its spans where profiling), then
    /// `after`, submits them and waits: the pass's milliseconds where the adapter has
    /// timestamps. The spans' times become the profile (`fresh`) or are added to it.
    fn run_pass(
        &self,
        label: &str,
        fresh: bool,
        record: impl FnOnce(&mut wgpu::ComputePass<'_>, &mut Option<SpanTimer>),
        after: impl FnOnce(&mut wgpu::CommandEncoder),
    ) -> Result<Option<f64>, GpuError> {
        let timer = PassTimer::new(&self.gpu);
        let mut spans = self.spans();
        let mut encoder = self
            .gpu
            .device()
            .create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: timer.as_ref().map(PassTimer::writes),
            });
            record(&mut pass, &mut spans);
        }
        after(&mut encoder);
        if let Some(t) = &timer {
            t.resolve(&mut encoder);
        }
        if let Some(s) = &spans {
            s.resolve(&mut encoder);
        }
        self.gpu.queue().submit([encoder.finish()]);
        let ms = match timer {
            Some(t) => Some(t.milliseconds(&self.gpu)?),
            None => {
                self.gpu
                    .device()
                    .poll(wgpu::PollType::wait_indefinitely())
                    .map_err(|e| GpuError::Readback(e.to_string()))?;
                None
            }
        };
        self.keep_profile(spans, fresh)?;
        Ok(ms)
    }

    /// Each level's place in the lights and its grid as the query reads it; the lights'
    /// buffers grown where they must.
    fn place_levels(&mut self, vertices: &[u32]) -> Result<(), GpuError> {
        let g = self.grid;
        let top = g.max_level();
        let mut levels = Vec::new();
        let mut first = 0u64;
        for level in 0..=top {
            let count = if level == 0 {
                self.n
            } else {
                vertices[level as usize - 1]
            };
            let base = blended(&self.blending, level, top);
            let grid = if level == 0 {
                LevelGrid {
                    origin: g.origin.to_array(),
                    cell: g.h1,
                    dims: [g.side(); 3],
                    stride: 1,
                    order: cell_order::MORTON,
                    bank: cell_order::IN_STARTS,
                    ..base
                }
            } else if level == top {
                LevelGrid { ..base }
            } else {
                // Blocks of 2³ vertices: slot 8·Morton(block) begins a block's vertices.
                let h = g.h(level);
                LevelGrid {
                    origin: g.origin.to_array(),
                    cell: 2.0 * h,
                    dims: [slots_a_side(&g, level) / 2; 3],
                    first_cell: self.slot_offsets[level as usize - 1],
                    margin: h,
                    stride: 8,
                    order: cell_order::MORTON,
                    bank: cell_order::IN_SLOTS,
                    ..base
                }
            };
            levels.push(LevelGrid {
                first_light: first as u32,
                light_count: count,
                ..grid
            });
            first += u64::from(count);
        }
        let limit = self.gpu.device().limits().max_storage_buffer_binding_size;
        check_size(
            "the levels' lights",
            first as usize * size_of::<GpuLight>(),
            limit,
        )?;
        let total = first.max(1) as u32;
        if total > self.out.capacity {
            // Grown with room, so that a few more lights next frame do not reallocate.
            self.out = out_buffers(self.gpu.device(), total + total / 8);
        }
        self.gpu
            .queue()
            .write_buffer(&self.level_buffer, 0, bytemuck::cast_slice(&levels));
        self.levels = levels;
        Ok(())
    }

    /// Submission 2: the lights in the sorted order, then every level's splat (its profile
    /// `fresh`, or after the topology's).
    fn splat(&self, fresh: bool) -> Result<Option<f64>, GpuError> {
        let device = self.gpu.device();
        let g = &self.grid;
        let mut steps = vec![self.step(0, self.n)];
        let mut plan = vec![(Kernel::GatherSorted, 0, self.n)];
        for level in 1..=g.max_level() {
            let index = steps.len() as u32;
            let vertices = self.levels[level as usize].light_count;
            if let Some(parts) = parts(vertices, self.n) {
                plan.extend([
                    (Kernel::MomentParts, index, vertices * parts),
                    (Kernel::FinishMoments, index, vertices),
                    (Kernel::SizeParts, index, vertices * parts),
                    (Kernel::FinishVertices, index, vertices),
                ]);
                steps.push(Step {
                    parts,
                    ..self.step(level, vertices)
                });
            } else {
                plan.push((Kernel::Splat, index, vertices));
                steps.push(self.step(level, vertices));
            }
        }
        let uniforms = Uniforms::new(device, &steps);
        let bind = self.bind(&uniforms);
        let record = |pass: &mut wgpu::ComputePass<'_>, spans: &mut Option<SpanTimer>| {
            for &p in &plan {
                let label = format!("level {}: {:?}", steps[p.1 as usize].level, p.0);
                timed(spans, pass, &label, |pass| {
                    self.record(pass, &bind, &uniforms, p);
                });
            }
        };
        self.run_pass("lgh-gpu build: splat", fresh, record, |_| {})
    }
}

/// The workgroups each of a level's `vertices` splits its sums over, where they gather many of
/// the `n` lights (each light counts at eight vertices): one per 1024 of four times their mean,
/// at most [`PARTS_IN_ALL`] for the level and 1024 a vertex; `None` where one invocation a
/// vertex does (few lights a vertex).
fn parts(vertices: u32, n: u32) -> Option<u32> {
    let mean = 8 * u64::from(n) / u64::from(vertices.max(1));
    if mean < 32 {
        return None;
    }
    let parts = (4 * mean).div_ceil(1024).min(1024) as u32;
    Some(parts.min(PARTS_IN_ALL / vertices.max(1)).max(1))
}

/// Records `record` into `pass`, timed as `label` where there is a span timer.
fn timed(
    spans: &mut Option<SpanTimer>,
    pass: &mut wgpu::ComputePass<'_>,
    label: &str,
    record: impl FnOnce(&mut wgpu::ComputePass<'_>),
) {
    match spans {
        Some(t) => t.span(pass, label.to_string(), record),
        None => record(pass),
    }
}

/// Where level ℓ's vertices begin in the list of vertex slots for `n` lights: each level ≥ 1
/// before it takes at most one entry a slot and eight a light (a light's cell has eight
/// corners).
fn list_offset(grid: &GpuGrid, level: u8, n: u32) -> u32 {
    (1..level)
        .map(|l| slots_a_side(grid, l).pow(3).min(n.saturating_mul(8)))
        .fold(0u32, u32::saturating_add)
}

/// Level ℓ's vertex slots a side: `2^(bits − ℓ + 1)`.
fn slots_a_side(grid: &GpuGrid, level: u8) -> u32 {
    1 << (grid.bits - (level - 1))
}

fn demorton(m: u32) -> [u32; 3] {
    let compact = |v: u32| (0..10).fold(0, |acc, b| acc | ((v >> (3 * b)) & 1) << b);
    [compact(m), compact(m >> 1), compact(m >> 2)]
}

fn check_intensity(index: usize, i: Vec3) -> Result<(), GpuError> {
    Ok(lgh_core::validate_intensity(
        index,
        i,
        Channels::OutOfGamut,
    )?)
}

fn storage(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

fn light_buffers(device: &wgpu::Device, grid: &GpuGrid, capacity: u32) -> LightBuffers {
    let n = u64::from(capacity);
    let listed = list_offset(grid, grid.max_level() + 1, capacity);
    LightBuffers {
        capacity,
        vertex_slots: storage(
            device,
            "lgh-gpu vertex slots by number",
            u64::from(listed) * 4,
        ),
        positions: storage(device, "lgh-gpu input positions", n * INPUT_BYTES),
        intensities: storage(device, "lgh-gpu input intensities", n * INPUT_BYTES),
        sort: RadixSort::new(device, capacity),
        sorted: storage(
            device,
            "lgh-gpu sorted lights",
            n * size_of::<SortedLight>() as u64,
        ),
    }
}

fn out_buffers(device: &wgpu::Device, capacity: u32) -> OutBuffers {
    let n = u64::from(capacity);
    OutBuffers {
        capacity,
        lights: storage(
            device,
            "lgh-gpu level lights",
            n * size_of::<GpuLight>() as u64,
        ),
        extras: storage(device, "lgh-gpu level variances and sizes", n * 16),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demorton_inverts_the_morton_code() {
        let c = [5u32, 200, 77];
        let spread = |v: u32| (0..10).fold(0, |acc, b| acc | ((v >> b) & 1) << (3 * b));
        let m = spread(c[0]) | spread(c[1]) << 1 | spread(c[2]) << 2;
        assert_eq!(demorton(m), c);
    }
}
