//! An exclusive prefix sum of `u32`s in place on the GPU (`scan.wgsl`): blocks of 1024 scanned
//! in workgroup memory, their sums scanned the same way (recursively), then added back. Integer
//! additions in a fixed tree, so the same bits on every run: the build's counting sort and
//! vertex numbering rest on it (paper Sec. 5's "compacted by a prefix scan").

use crate::dispatch::{self, Uniforms};
pub use crate::layout::ScanStep as Step;

/// Values a workgroup scans (`scan.wgsl`'s `BLOCK`).
pub const BLOCK: u32 = 1024;

/// What one dispatch of a scan does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// Each block scanned, its total written to `sums`.
    Blocks,
    /// Each block raised by its scanned sum.
    AddSums,
}

/// The scan's two kernels.
#[derive(Debug)]
pub struct Scan {
    blocks: wgpu::ComputePipeline,
    add: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl Scan {
    /// The kernels, compiled for `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Scan {
        let layout = dispatch::layout(device, "lgh-gpu scan", 16, 1);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lgh-gpu scan.wgsl"),
            source: wgpu::ShaderSource::Wgsl(crate::kernels::SCAN.source().into()),
        });
        let pipeline = |entry| dispatch::pipeline(device, &layout, &module, entry);
        Scan {
            blocks: pipeline("scan_blocks"),
            add: pipeline("add_sums"),
            layout,
        }
    }

    /// Appends the dispatches that scan `count` values at `offset` to `out`, taking room for
    /// the blocks' sums from `scratch` on (and moving it past what they take).
    pub fn plan(offset: u32, count: u32, scratch: &mut u32, out: &mut Vec<(Pass, Step)>) {
        let blocks = count.div_ceil(BLOCK).max(1);
        let sums = *scratch;
        *scratch += blocks;
        let step = Step {
            offset,
            count,
            sums,
            _pad: 0,
        };
        out.push((Pass::Blocks, step));
        if blocks > 1 {
            Self::plan(sums, blocks, scratch, out);
            out.push((Pass::AddSums, step));
        }
    }

    /// The scratch a scan of `count` values takes.
    #[must_use]
    pub fn scratch(count: u32) -> u32 {
        let mut scratch = 0;
        Self::plan(0, count, &mut scratch, &mut Vec::new());
        scratch
    }

    /// The bind group of `data` with the steps' uniforms.
    #[must_use]
    pub fn bind(
        &self,
        device: &wgpu::Device,
        uniforms: &Uniforms,
        data: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        dispatch::bind(device, &self.layout, uniforms, &[data])
    }

    /// Records `steps` (whose uniforms are `first..` of the bind group's) into `pass`.
    pub fn record(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        bind_group: &wgpu::BindGroup,
        uniforms: &Uniforms,
        first: u32,
        steps: &[(Pass, Step)],
        limits: &wgpu::Limits,
    ) {
        for (i, (kind, step)) in steps.iter().enumerate() {
            let pipeline = match kind {
                Pass::Blocks => &self.blocks,
                Pass::AddSums => &self.add,
            };
            let groups = step.count.div_ceil(BLOCK).max(1);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[uniforms.offset(first + i as u32)]);
            let (x, y) = dispatch::groups(groups, limits);
            pass.dispatch_workgroups(x, y, 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Gpu;
    use wgpu::util::DeviceExt;

    /// The scan against the CPU's prefix sum, one to three levels of blocks deep.
    #[test]
    fn the_scan_is_the_prefix_sum() {
        let gpu = match Gpu::new() {
            Ok(gpu) => gpu,
            Err(e) => return lgh_tests::Piece::Gpu.missing(&e.to_string()),
        };
        let device = gpu.device();
        let scan = Scan::new(device);
        for count in [1u32, 255, 1024, 1025, 70_001, 2_100_000] {
            let values: Vec<u32> = (0..count)
                .map(|i| i.wrapping_mul(2_654_435_761) >> 28)
                .collect();
            let offset = 5;
            let mut scratch = offset + count;
            let mut steps = Vec::new();
            Scan::plan(offset, count, &mut scratch, &mut steps);
            let mut data = vec![7u32; scratch as usize];
            data[offset as usize..(offset + count) as usize].copy_from_slice(&values);
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: bytemuck::cast_slice(&data),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            });
            let steps_only: Vec<Step> = steps.iter().map(|s| s.1).collect();
            let uniforms = Uniforms::new(device, &steps_only);
            let bind = scan.bind(device, &uniforms, &buffer);
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                scan.record(&mut pass, &bind, &uniforms, 0, &steps, &device.limits());
            }
            let out: Vec<u32> = dispatch::read(&gpu, encoder, &buffer).unwrap();
            let mut sum = 0u32;
            for i in 0..count as usize {
                assert_eq!(out[offset as usize + i], sum, "count {count}, value {i}");
                sum += values[i];
            }
            assert_eq!(
                &out[..offset as usize],
                &[7; 5],
                "values before the offset kept"
            );
        }
    }
}
