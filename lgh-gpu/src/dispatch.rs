//! What every multi-kernel pass of the crate does the same way: a bind group layout of one
//! uniform (each dispatch its own, at a dynamic offset) and storage buffers, pipelines on it,
//! dispatch sizes beyond one dimension's limit, and reading a buffer back.

use wgpu::util::DeviceExt;

use crate::context::Gpu;
use crate::error::GpuError;

/// Each dispatch's uniform of one pass, `stride` bytes apart in one buffer (the device's uniform
/// offset alignment), bound at a dynamic offset.
#[derive(Debug)]
pub struct Uniforms {
    buffer: wgpu::Buffer,
    stride: u32,
    size: u64,
}

impl Uniforms {
    /// The uniforms `values`, in this order.
    #[must_use]
    pub fn new<T: bytemuck::Pod>(device: &wgpu::Device, values: &[T]) -> Uniforms {
        let align = device.limits().min_uniform_buffer_offset_alignment;
        let size = size_of::<T>() as u32;
        let stride = size.div_ceil(align) * align;
        let mut bytes = vec![0u8; (stride as usize * values.len()).max(stride as usize)];
        for (i, v) in values.iter().enumerate() {
            let at = i * stride as usize;
            bytes[at..at + size as usize].copy_from_slice(bytemuck::bytes_of(v));
        }
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("lgh-gpu uniforms"),
            contents: &bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        Uniforms {
            buffer,
            stride,
            size: size as u64,
        }
    }

    /// The dynamic offset of uniform `i`.
    #[must_use]
    pub fn offset(&self, i: u32) -> u32 {
        i * self.stride
    }
}

/// A layout of a uniform of `uniform_size` bytes at a dynamic offset (binding 0) and
/// `storage` read-write storage buffers (bindings 1..).
#[must_use]
pub fn layout(
    device: &wgpu::Device,
    label: &str,
    uniform_size: u64,
    storage: u32,
) -> wgpu::BindGroupLayout {
    let bindings: Vec<u32> = (1..=storage).collect();
    layout_of(device, label, uniform_size, &bindings)
}

/// [`layout`] with read-write storage buffers at the given `bindings` only: each kernel binds
/// no more than it uses (WebGPU allows 8 storage buffers a kernel by default).
#[must_use]
pub fn layout_of(
    device: &wgpu::Device,
    label: &str,
    uniform_size: u64,
    bindings: &[u32],
) -> wgpu::BindGroupLayout {
    let mut entries = vec![wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(uniform_size),
        },
        count: None,
    }];
    entries.extend(bindings.iter().map(|&binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// The pipeline of `entry` in `module` on `layout`.
#[must_use]
pub fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// The bind group of `uniforms` (binding 0) and `storage` (bindings 1..).
#[must_use]
pub fn bind(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniforms: &Uniforms,
    storage: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let numbered: Vec<(u32, &wgpu::Buffer)> = (1..).zip(storage.iter().copied()).collect();
    bind_of(device, layout, uniforms, &numbered)
}

/// [`bind`] with each storage buffer at its binding.
#[must_use]
pub fn bind_of(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniforms: &Uniforms,
    storage: &[(u32, &wgpu::Buffer)],
) -> wgpu::BindGroup {
    let mut entries = vec![wgpu::BindGroupEntry {
        binding: 0,
        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &uniforms.buffer,
            offset: 0,
            size: wgpu::BufferSize::new(uniforms.size),
        }),
    }];
    entries.extend(storage.iter().map(|&(binding, b)| wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }));
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

/// `n` workgroups as (x, y), x at most the device's per-dimension limit: the kernels number
/// their workgroup `wg.x + wg.y · groups.x`.
#[must_use]
pub fn groups(n: u32, limits: &wgpu::Limits) -> (u32, u32) {
    let most = limits.max_compute_workgroups_per_dimension.max(1);
    let x = n.clamp(1, most);
    (x, n.div_ceil(x).max(1))
}

/// Submits `encoder` with a copy of `buffer` to a readback buffer, and reads it.
pub fn read<T: bytemuck::Pod>(
    gpu: &Gpu,
    mut encoder: wgpu::CommandEncoder,
    buffer: &wgpu::Buffer,
) -> Result<Vec<T>, GpuError> {
    let staging = gpu.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("lgh-gpu readback"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    gpu.queue().submit([encoder.finish()]);
    gpu.read_back(&staging)
}
