//! lgh-gpu as an engine drives it: lights already in GPU buffers (`GpuBuilder::rebuild_from`),
//! and the query and the gather recorded into the engine's own command encoder on its own
//! G-buffer (`GpuHierarchy::record_shade`, `record_gather`) — the same bits as the calls that
//! upload and read back.

mod common;

use common::{g_buffer, gpu};
use lgh_core::testsets::clumped_lights;
use lgh_gpu::{dispatch, GatherSample, GpuBuilder, GpuError, GpuGrid};
use wgpu::util::DeviceExt;

fn buffer(device: &wgpu::Device, contents: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents,
        usage,
    })
}

#[test]
fn an_engines_buffers_give_the_bits_of_the_calls_that_copy() {
    let Some(gpu) = gpu() else { return };
    let device = gpu.device();
    let lights = clumped_lights(1500, 21);
    let grid = GpuGrid::fitting(&lights).unwrap();
    let mut on_cpu_data = GpuBuilder::new(gpu, grid, 2.0).unwrap();
    on_cpu_data.rebuild(&lights).unwrap();
    // The lights as an engine's compute pass would leave them: [f32; 4] each.
    let positions: Vec<[f32; 4]> = lights
        .iter()
        .map(|l| l.position.extend(1.0).into())
        .collect();
    let intensities: Vec<[f32; 4]> = lights
        .iter()
        .map(|l| l.intensity.extend(0.0).into())
        .collect();
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let p = buffer(device, bytemuck::cast_slice(&positions), usage);
    let i = buffer(device, bytemuck::cast_slice(&intensities), usage);
    let mut on_gpu_data = GpuBuilder::new(gpu, grid, 2.0).unwrap();
    on_gpu_data
        .rebuild_from(&p, &i, lights.len() as u32)
        .unwrap();
    for level in 0..=grid.max_level() {
        assert_eq!(
            on_gpu_data.read_level(level).unwrap(),
            on_cpu_data.read_level(level).unwrap(),
            "level {level}"
        );
    }
    assert!(matches!(
        on_gpu_data.rebuild_from(&p, &i, lights.len() as u32 + 1),
        Err(GpuError::BufferTooSmall { .. })
    ));

    // The query and the gather into the engine's encoder, on its G-buffer.
    let hierarchy = on_gpu_data.hierarchy();
    let points = g_buffer(&lights, 300, 22);
    let n = points.len() as u32;
    let g = buffer(
        device,
        bytemuck::cast_slice(&points),
        wgpu::BufferUsages::STORAGE,
    );
    let out = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let radiance = buffer(device, &vec![0u8; points.len() * 16], out);
    let (k, seed) = (3, 5);
    let samples = buffer(device, &vec![0u8; points.len() * 32 * k as usize], out);
    let mut encoder = device.create_command_encoder(&Default::default());
    hierarchy
        .record_shade(&mut encoder, &g, &radiance, n)
        .unwrap();
    hierarchy
        .record_gather(&mut encoder, &g, &samples, n, (k, seed))
        .unwrap();
    let rgba: Vec<[f32; 4]> = dispatch::read(gpu, encoder, &radiance).unwrap();
    let shaded: Vec<[f32; 3]> = rgba.iter().map(|c| [c[0], c[1], c[2]]).collect();
    assert_eq!(shaded, hierarchy.shade(&points).unwrap());
    let encoder = device.create_command_encoder(&Default::default());
    let drawn: Vec<GatherSample> = dispatch::read(gpu, encoder, &samples).unwrap();
    assert_eq!(drawn, hierarchy.gather(&points, k, seed).unwrap());
    // Too small a buffer is refused before anything is recorded.
    let mut encoder = device.create_command_encoder(&Default::default());
    assert!(matches!(
        hierarchy.record_shade(&mut encoder, &g, &radiance, n + 1),
        Err(GpuError::BufferTooSmall { .. })
    ));
    assert!(matches!(
        hierarchy.record_gather(&mut encoder, &g, &samples, n, (0, 1)),
        Err(GpuError::InvalidK { k: 0, .. })
    ));
}

/// An engine's device made with wgpu's default limits — WebGPU's: 8 storage buffers a kernel —
/// runs every kernel: each binds only what it uses. The same bits as on the tests' device (the
/// adapter's own limits).
#[test]
fn a_device_with_webgpus_default_limits_runs_every_kernel() {
    let Some(gpu) = gpu() else { return };
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::PRIMARY,
        flags: wgpu::InstanceFlags::empty(),
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = pollster::block_on(instance.request_adapter(&Default::default())).unwrap();
    let descriptor = wgpu::DeviceDescriptor {
        required_limits: wgpu::Limits::default(),
        ..Default::default()
    };
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor)).unwrap();
    assert_eq!(device.limits().max_storage_buffers_per_shader_stage, 8);
    let engine = lgh_gpu::Gpu::from_device(device, queue, adapter.get_info());
    let lights = clumped_lights(1200, 23);
    let grid = GpuGrid::fitting(&lights).unwrap();
    let points = g_buffer(&lights, 200, 24);
    let run = |gpu: &lgh_gpu::Gpu| {
        let mut b = GpuBuilder::new(gpu, grid, 2.0).unwrap();
        b.rebuild(&lights).unwrap();
        let h = b.hierarchy();
        (h.shade(&points).unwrap(), h.gather(&points, 2, 9).unwrap())
    };
    assert_eq!(run(&engine), run(gpu));
}
