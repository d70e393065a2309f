//! Criterion benchmarks of lgh-core on the benchmark light sets of `lgh_core::testsets`.
//!
//! `cargo bench -p lgh-core` (add `--features rayon` for the parallel build). The `lgh bench core`
//! command measures the same things end to end, with accuracy, and prints JSON.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lgh_core::glam::Vec3;
use lgh_core::{falloff, testsets, BruteForce, GridSettings, LightingGridHierarchy, PointLight};

fn explosion() -> (Vec<PointLight>, GridSettings) {
    let res = 128;
    (
        testsets::explosion_shell(res),
        GridSettings {
            h1: Some(2.0 / res as f32),
            origin: Some(Vec3::splat(0.5 / res as f32)),
            ..Default::default()
        },
    )
}

fn bounds(lights: &[PointLight]) -> (Vec3, Vec3) {
    lights.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), l| (lo.min(l.position), hi.max(l.position)),
    )
}

fn build(c: &mut Criterion) {
    let (lights, settings) = explosion();
    let mut g = c.benchmark_group("build_explosion_128");
    g.sample_size(10);
    g.throughput(Throughput::Elements(lights.len() as u64));
    g.bench_function("from_input_lights", |b| {
        b.iter(|| LightingGridHierarchy::build(black_box(&lights), &settings).unwrap())
    });
    let mut lgh = LightingGridHierarchy::build(&lights, &settings).unwrap();
    let intensities: Vec<Vec3> = lights.iter().map(|l| l.intensity * 1.25).collect();
    g.bench_function("update_intensities", |b| {
        b.iter(|| lgh.update_intensities(black_box(&intensities)).unwrap())
    });
    g.finish();
}

fn query(c: &mut Criterion) {
    let (lights, settings) = explosion();
    let lgh = LightingGridHierarchy::build(&lights, &settings).unwrap();
    let (lo, hi) = bounds(&lights);
    let points = testsets::query_points(lo, hi, 1000, 42);
    let h0 = lgh.h0();
    let mut g = c.benchmark_group("query_explosion_128");
    g.sample_size(10);
    g.throughput(Throughput::Elements(points.len() as u64));
    for alpha in [1.0f32, 2.0, 4.0, 8.0] {
        let b = lgh.blending(alpha).unwrap();
        g.bench_with_input(BenchmarkId::new("lgh_alpha", alpha), &b, |bench, b| {
            bench.iter(|| {
                let mut total = Vec3::ZERO;
                for &x in &points {
                    total += lgh
                        .query_sum(x, b, |s| s.intensity * falloff(s.distance, h0))
                        .unwrap()
                        .0;
                }
                total
            })
        });
    }
    let brute = BruteForce::new(&lights).unwrap();
    let few = &points[..20];
    g.throughput(Throughput::Elements(few.len() as u64));
    g.bench_function("brute_force_vectorised", |bench| {
        bench.iter(|| {
            few.iter()
                .map(|&x| brute.falloff_sum(x, h0).unwrap())
                .fold(Vec3::ZERO, |a, b| a + b)
        })
    });
    g.finish();
}

criterion_group!(benches, build, query);
criterion_main!(benches);
