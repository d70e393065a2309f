//! Criterion benchmarks of lgh-gpu, each to its results on the CPU side (wall time, readback or
//! fence included): the query (`GpuHierarchy::shade_timed`) against lgh-core's query on every
//! core on the same hierarchy and points; the GPU build, intensity update and gather. `cargo
//! bench -p lgh-gpu`. `lgh bench gpu` measures the kernels alone (timestamp queries), the CPU
//! path and their agreement, as JSON. Without a GPU adapter it says so and measures nothing.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use lgh_core::glam::Vec3;
use lgh_core::{testsets, GridSettings, LightingGridHierarchy};
use lgh_gpu::{Gpu, GpuBuilder, GpuGrid, GpuHierarchy, ShadingPoint};
use rayon::prelude::*;

/// The explosion set at 64³ (about 130K lights) and a 256 × 256 grid of points below it.
fn scene() -> (LightingGridHierarchy, Vec<ShadingPoint>) {
    let lights = testsets::explosion_shell(64);
    let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).expect("a build");
    let points = (0..256 * 256)
        .map(|i| {
            let (u, v) = ((i % 256) as f32 / 255.0, (i / 256) as f32 / 255.0);
            ShadingPoint::new(Vec3::new(u, -0.2, v), Vec3::Y, Vec3::splat(0.8))
        })
        .collect();
    (lgh, points)
}

fn shade(c: &mut Criterion) {
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("lgh-gpu bench: nothing measured: {e}");
            return;
        }
    };
    let (lgh, points) = scene();
    let on_gpu = GpuHierarchy::upload(&gpu, &lgh, 2.0).expect("an upload");
    let blending = lgh.blending(2.0).expect("α = 2");
    let mut g = c.benchmark_group("shade_explosion_64_256x256");
    g.sample_size(10);
    g.throughput(Throughput::Elements(points.len() as u64));
    g.bench_function("gpu", |b| {
        b.iter(|| black_box(on_gpu.shade_timed(&points).expect("a query")))
    });
    g.bench_function("cpu_all_cores", |b| {
        b.iter(|| {
            let sums: Vec<Vec3> = points
                .par_iter()
                .map(|p| lgh_gpu::reference::shade(&lgh, &blending, p).expect("a point"))
                .collect();
            black_box(sums)
        })
    });
    g.finish();
}

/// The build, the update and the gather on the GPU, on the same explosion set.
fn build(c: &mut Criterion) {
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("lgh-gpu bench: nothing measured: {e}");
            return;
        }
    };
    let lights = testsets::explosion_shell(64);
    let (_, points) = scene();
    let mut builder =
        GpuBuilder::new(&gpu, GpuGrid::fitting(&lights).expect("a grid"), 2.0).expect("a builder");
    let brighter: Vec<Vec3> = lights.iter().map(|l| l.intensity * 1.5).collect();
    let mut g = c.benchmark_group("gpu_explosion_64");
    g.sample_size(10);
    g.throughput(Throughput::Elements(lights.len() as u64));
    g.bench_function("rebuild", |b| {
        b.iter(|| black_box(builder.rebuild(&lights).expect("a build")))
    });
    g.bench_function("update_intensities", |b| {
        b.iter(|| black_box(builder.update_intensities(&brighter).expect("an update")))
    });
    let hierarchy = builder.hierarchy();
    g.throughput(Throughput::Elements(points.len() as u64));
    g.bench_function("gather_k4_256x256", |b| {
        b.iter(|| black_box(hierarchy.gather_timed(&points, 4, 1).expect("a gather")))
    });
    g.finish();
}

criterion_group!(benches, shade, build);
criterion_main!(benches);
