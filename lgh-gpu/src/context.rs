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
        pollster::block_on(Self::new_async())
    }

    /// [`new`](Self::new) without blocking: in a browser (wasm32), the browser's WebGPU, where
    /// nothing may block.
    pub async fn new_async() -> Result<Gpu, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            flags: wgpu::InstanceFlags::empty(),
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = instance
            .request_adapter(&options)
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        // Timestamps where the adapter has them (`lgh bench gpu` times the kernels with them).
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("lgh-gpu"),
            required_limits: adapter.limits(),
            required_features: adapter.features()
                & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES),
            ..Default::default()
        };
        let (device, queue) = adapter
            .request_device(&descriptor)
            .await
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
        pollster::block_on(self.read_back_async(staging))
    }

    /// [`read_back`](Self::read_back) without blocking: natively the device is polled until
    /// the mapping is done; in a browser the mapping completes on the page's event loop while
    /// this waits.
    pub(crate) async fn read_back_async<T: bytemuck::Pod>(
        &self,
        staging: &wgpu::Buffer,
    ) -> Result<Vec<T>, GpuError> {
        let slice = staging.slice(..);
        let mapped = Mapped::default();
        let done = mapped.clone();
        slice.map_async(wgpu::MapMode::Read, move |r| done.finish(r));
        self.device()
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        mapped
            .await
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

/// A buffer mapping's outcome, awaited: set by `map_async`'s callback, which wakes the task.
#[derive(Clone, Default)]
struct Mapped(std::sync::Arc<std::sync::Mutex<MappedState>>);

#[derive(Default)]
struct MappedState {
    outcome: Option<Result<(), wgpu::BufferAsyncError>>,
    waker: Option<std::task::Waker>,
}

impl Mapped {
    fn finish(&self, outcome: Result<(), wgpu::BufferAsyncError>) {
        let mut state = self.0.lock().unwrap_or_else(|e| e.into_inner());
        state.outcome = Some(outcome);
        if let Some(waker) = state.waker.take() {
            waker.wake();
        }
    }
}

impl std::future::Future for Mapped {
    type Output = Result<(), wgpu::BufferAsyncError>;

    fn poll(
        self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<Self::Output> {
        let mut state = self.0.lock().unwrap_or_else(|e| e.into_inner());
        match state.outcome.take() {
            Some(outcome) => std::task::Poll::Ready(outcome),
            None => {
                state.waker = Some(cx.waker().clone());
                std::task::Poll::Pending
            }
        }
    }
}
