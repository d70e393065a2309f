//! A stable radix sort of `(key, value)` pairs of `u32` on the GPU (`sort.wgsl`): 8 bits a
//! pass, each pass a count of every tile's digits, a scan of the counts ([`Scan`]) and a
//! scatter in a fixed order, so the same pairs give the same bits on every run. The build
//! sorts its lights by level-1 cell with it (paper Sec. 5: the GPU build sorts its lights).

use crate::dispatch::{self, Uniforms};
use crate::layout::SortPass as Pass;
use crate::scan::{self, Scan};

/// Pairs a workgroup sorts into place (`sort.wgsl`'s `TILE`).
pub const TILE: u32 = 256;
const RADIX: u32 = 256;

/// The sort's kernels and its buffers for up to `capacity` pairs: the pairs are sorted from
/// `keys`/`values` back into them (an even number of passes through a second pair of buffers).
#[derive(Debug)]
pub struct RadixSort {
    count: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    capacity: u32,
    /// The keys and values sorted, in and out.
    pub keys: wgpu::Buffer,
    /// See `keys`.
    pub values: wgpu::Buffer,
    keys_b: wgpu::Buffer,
    values_b: wgpu::Buffer,
    histogram: wgpu::Buffer,
}

impl RadixSort {
    /// The kernels, and buffers for `capacity` pairs.
    #[must_use]
    pub fn new(device: &wgpu::Device, capacity: u32) -> RadixSort {
        let layout = dispatch::layout(device, "lgh-gpu sort", 16, 5);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lgh-gpu sort.wgsl"),
            source: wgpu::ShaderSource::Wgsl(crate::kernels::SORT.source().into()),
        });
        let pipeline = |entry| dispatch::pipeline(device, &layout, &module, entry);
        let n = u64::from(capacity.max(1)) * 4;
        let tiles = capacity.div_ceil(TILE).max(1);
        let histogram_len = RADIX * tiles + 1;
        let buffer = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        RadixSort {
            count: pipeline("count_digits"),
            scatter: pipeline("scatter_digits"),
            keys: buffer("lgh-gpu sort keys", n),
            values: buffer("lgh-gpu sort values", n),
            keys_b: buffer("lgh-gpu sort keys, second", n),
            values_b: buffer("lgh-gpu sort values, second", n),
            histogram: buffer(
                "lgh-gpu sort histogram",
                u64::from(histogram_len + Scan::scratch(histogram_len)) * 4,
            ),
            capacity,
            layout,
        }
    }

    /// The pairs it has room for.
    #[must_use]
    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// Records the sort of the first `count` pairs by their keys' low `bits` bits (stable:
    /// pairs with equal keys keep their order) into `pass`.
    pub fn record(
        &self,
        device: &wgpu::Device,
        pass: &mut wgpu::ComputePass<'_>,
        scan: &Scan,
        count: u32,
        bits: u32,
    ) {
        let tiles = count.div_ceil(TILE).max(1);
        // An even number of passes, so the pairs end where they began.
        let passes = bits.div_ceil(8).max(1).next_multiple_of(2);
        let steps: Vec<Pass> = (0..passes)
            .map(|p| Pass {
                count,
                shift: (8 * p).min(31),
                tiles,
                _pad: 0,
            })
            .collect();
        let uniforms = Uniforms::new(device, &steps);
        let mut scratch = RADIX * tiles + 1;
        let mut scan_steps = Vec::new();
        Scan::plan(0, RADIX * tiles + 1, &mut scratch, &mut scan_steps);
        let scan_only: Vec<scan::Step> = scan_steps.iter().map(|s| s.1).collect();
        let scan_uniforms = Uniforms::new(device, &scan_only);
        let scan_bind = scan.bind(device, &scan_uniforms, &self.histogram);
        let bind = |from: [&wgpu::Buffer; 2], to: [&wgpu::Buffer; 2]| {
            dispatch::bind(
                device,
                &self.layout,
                &uniforms,
                &[from[0], from[1], to[0], to[1], &self.histogram],
            )
        };
        let forth = bind([&self.keys, &self.values], [&self.keys_b, &self.values_b]);
        let back = bind([&self.keys_b, &self.values_b], [&self.keys, &self.values]);
        let limits = device.limits();
        let (x, y) = dispatch::groups(tiles, &limits);
        for p in 0..passes {
            let group = if p % 2 == 0 { &forth } else { &back };
            let offset = [uniforms.offset(p)];
            pass.set_pipeline(&self.count);
            pass.set_bind_group(0, group, &offset);
            pass.dispatch_workgroups(x, y, 1);
            scan.record(pass, &scan_bind, &scan_uniforms, 0, &scan_steps, &limits);
            pass.set_pipeline(&self.scatter);
            pass.set_bind_group(0, group, &offset);
            pass.dispatch_workgroups(x, y, 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Gpu;

    /// The sort against the CPU's stable sort, keys with many ties, one to many tiles.
    #[test]
    fn the_sort_is_stable_and_sorted() {
        let gpu = match Gpu::new() {
            Ok(gpu) => gpu,
            Err(e) => return lgh_tests::Piece::Gpu.missing(&e.to_string()),
        };
        let device = gpu.device();
        let scan = Scan::new(device);
        for (count, bits) in [(1u32, 8u32), (300, 5), (5000, 15), (70_000, 24)] {
            let keys: Vec<u32> = (0..count)
                .map(|i| (i.wrapping_mul(2_654_435_761) >> 7) & ((1 << bits) - 1) & !0x3)
                .collect();
            let values: Vec<u32> = (0..count).collect();
            let sort = RadixSort::new(device, count);
            gpu.queue()
                .write_buffer(&sort.keys, 0, bytemuck::cast_slice(&keys));
            gpu.queue()
                .write_buffer(&sort.values, 0, bytemuck::cast_slice(&values));
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                sort.record(device, &mut pass, &scan, count, bits);
            }
            let got: Vec<u32> = dispatch::read(&gpu, encoder, &sort.values).unwrap();
            let mut want: Vec<u32> = values.clone();
            want.sort_by_key(|&i| keys[i as usize]);
            assert_eq!(
                &got[..count as usize],
                &want[..],
                "{count} pairs, {bits} bits"
            );
        }
    }
}
