//! The GPU: a `wgpu::Device` and its `Queue` — the caller's, or a headless one of our own — and
//! what adapter they run on.

use crate::error::GpuError;

/// A device and queue to run the kernels on, with its adapter's description.
#[derive(Clone, Debug)]
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: wgpu::AdapterInfo,
}

impl Gpu {
    /// A headless device of our own on the first Vulkan, Metal or DX12 adapter, preferring a
    /// discrete GPU (Mesa's software Vulkan, lavapipe, where there is no GPU). With the
    /// adapter's own limits, so large hierarchies fit where the device allows.
    ///
    /// Errors with [`GpuError::NoAdapter`] (saying how to install lavapipe) where there is none.
    pub fn new() -> Result<Gpu, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            flags: wgpu::InstanceFlags::empty(),
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = pollster::block_on(instance.request_adapter(&options))
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        // Timestamps where the adapter has them (`lgh bench gpu` times the kernels with them).
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("lgh-gpu"),
            required_limits: adapter.limits(),
            required_features: adapter.features()
                & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))
            .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Gpu {
            device,
            queue,
            adapter: adapter.get_info(),
        })
    }

    /// The caller's device and queue (an engine's), with its adapter's description.
    #[must_use]
    pub fn from_device(
        device: wgpu::Device,
        queue: wgpu::Queue,
        adapter: wgpu::AdapterInfo,
    ) -> Gpu {
        Gpu {
            device,
            queue,
            adapter,
        }
    }

    /// The device.
    #[must_use]
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue.
    #[must_use]
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// The adapter: its name, backend and kind (`DeviceType::Cpu` for lavapipe).
    #[must_use]
    pub fn adapter(&self) -> &wgpu::AdapterInfo {
        &self.adapter
    }

    /// The contents of a `MAP_READ` buffer once the GPU is done with it.
    pub(crate) fn read_back<T: bytemuck::Pod>(
        &self,
        staging: &wgpu::Buffer,
    ) -> Result<Vec<T>, GpuError> {
        let slice = staging.slice(..);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = sender.send(r);
        });
        self.device()
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        receiver
            .recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let values = {
            let view = slice
                .get_mapped_range()
                .map_err(|e| GpuError::Readback(e.to_string()))?;
            bytemuck::cast_slice::<u8, T>(&view).to_vec()
        };
        staging.unmap();
        Ok(values)
    }
}
