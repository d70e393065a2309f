//! Timing a compute pass on the GPU with timestamp queries (where the adapter has them):
//! `lgh bench gpu` reports the kernel's own time, not the upload or the readback.

use crate::context::Gpu;
use crate::error::GpuError;

/// Two timestamps around a compute pass, resolved and read back after it.
#[derive(Debug)]
pub struct PassTimer {
    query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
}

impl PassTimer {
    /// A timer for one pass, if the device was given `Features::TIMESTAMP_QUERY` ([`Gpu::new`]
    /// asks for it where the adapter has it).
    #[must_use]
    pub fn new(gpu: &Gpu) -> Option<PassTimer> {
        let device = gpu.device();
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let query_set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("lgh-gpu pass timer"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lgh-gpu timestamps"),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(PassTimer {
            query_set,
            resolve: buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            staging: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
        })
    }

    /// The pass's timestamp writes: at its beginning and its end.
    #[must_use]
    pub fn writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    /// Records the resolve of the two timestamps, after the pass.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.query_set, 0..2, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, 16);
    }

    /// The pass's milliseconds, once the commands were submitted.
    pub fn milliseconds(&self, gpu: &Gpu) -> Result<f64, GpuError> {
        pollster::block_on(self.milliseconds_async(gpu))
    }

    /// [`milliseconds`](Self::milliseconds) without blocking.
    pub async fn milliseconds_async(&self, gpu: &Gpu) -> Result<f64, GpuError> {
        let ticks: Vec<u64> = gpu.read_back_async(&self.staging).await?;
        let period = f64::from(gpu.queue().get_timestamp_period());
        Ok(ticks[1].saturating_sub(ticks[0]) as f64 * period * 1e-6)
    }
}

/// How long a GPU call took ([`GpuHierarchy::shade_timed`](crate::GpuHierarchy::shade_timed),
/// [`GpuBuilder::rebuild`](crate::GpuBuilder::rebuild), …).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuTiming {
    /// The kernel's milliseconds by timestamp queries; `None` where the device has none.
    pub kernel_ms: Option<f64>,
    /// Milliseconds from the first submission to the results read back (a fence; NaN in a
    /// browser, which has no clock for it).
    pub wall_ms: f64,
}

/// Timestamps around spans of dispatches inside a pass (where the adapter has
/// `TIMESTAMP_QUERY_INSIDE_PASSES`): where a build's time goes, kernel by kernel
/// ([`GpuBuilder::profile`](crate::GpuBuilder::profile)).
#[derive(Debug)]
pub struct SpanTimer {
    query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    labels: Vec<String>,
    capacity: u32,
}

impl SpanTimer {
    /// A timer for up to `spans` spans, if the device has timestamps inside passes.
    #[must_use]
    pub fn new(gpu: &Gpu, spans: u32) -> Option<SpanTimer> {
        let device = gpu.device();
        let wanted =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
        if !device.features().contains(wanted) {
            return None;
        }
        let count = 2 * spans;
        let query_set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("lgh-gpu span timer"),
            ty: wgpu::QueryType::Timestamp,
            count,
        });
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lgh-gpu span timestamps"),
                size: u64::from(count) * 8,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(SpanTimer {
            query_set,
            resolve: buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            staging: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
            labels: Vec::new(),
            capacity: spans,
        })
    }

    /// Times what `record` records into `pass` as `label` (untimed past the capacity).
    pub fn span(
        &mut self,
        pass: &mut wgpu::ComputePass<'_>,
        label: String,
        record: impl FnOnce(&mut wgpu::ComputePass<'_>),
    ) {
        let i = self.labels.len() as u32;
        if i >= self.capacity {
            return record(pass);
        }
        pass.write_timestamp(&self.query_set, 2 * i);
        record(pass);
        pass.write_timestamp(&self.query_set, 2 * i + 1);
        self.labels.push(label);
    }

    /// Records the resolve of the spans' timestamps, after the pass.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let n = 2 * self.labels.len() as u32;
        if n > 0 {
            encoder.resolve_query_set(&self.query_set, 0..n, &self.resolve, 0);
            encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, u64::from(n) * 8);
        }
    }

    /// Each span's label and milliseconds, once the commands were submitted.
    pub fn milliseconds(self, gpu: &Gpu) -> Result<Vec<(String, f64)>, GpuError> {
        if self.labels.is_empty() {
            return Ok(Vec::new());
        }
        let ticks: Vec<u64> = gpu.read_back(&self.staging)?;
        let period = f64::from(gpu.queue().get_timestamp_period());
        Ok(self
            .labels
            .into_iter()
            .enumerate()
            .map(|(i, l)| {
                let ms = ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * period * 1e-6;
                (l, ms)
            })
            .collect())
    }
}

/// Wall time from its start: `std::time::Instant` natively; in a browser (wasm32, which has no
/// `Instant`) it reads NaN.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stopwatch {
    #[cfg(not(target_arch = "wasm32"))]
    start: std::time::Instant,
}

impl Stopwatch {
    pub(crate) fn start() -> Stopwatch {
        Stopwatch {
            #[cfg(not(target_arch = "wasm32"))]
            start: std::time::Instant::now(),
        }
    }

    /// Milliseconds since the start (NaN in a browser).
    pub(crate) fn ms(&self) -> f64 {
        #[cfg(not(target_arch = "wasm32"))]
        return self.start.elapsed().as_secs_f64() * 1e3;
        #[cfg(target_arch = "wasm32")]
        return f64::NAN;
    }
}
