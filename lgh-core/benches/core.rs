//! Criterion benchmarks of lgh-core on the benchmark light sets of `lgh_core::testsets`.
//!
//! `cargo bench -p lgh-core` (add `--features rayon` for the parallel build). The `lgh bench core`
//! command measures the same things end to end, with accuracy, and prints JSON.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lgh_core::glam::Vec3;
use lgh_core::spectrum::{blackbody_rgb, BlackbodyTable};
use lgh_core::{
    bounds, falloff, testsets, BruteForce, GridSettings, LightingGridHierarchy, PointLight,
};

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

/// The level-0 radius query (lights within r_1 = α h_1 of a point): our bricked index with an
/// 8-lane scan against kiddo's immutable k-d tree, the kind of index the paper's implementation
/// used. Both visit the same lights and sum their distances.
fn level0_index(c: &mut Criterion) {
    let (lights, settings) = explosion();
    let lgh = LightingGridHierarchy::build(&lights, &settings).unwrap();
    let level0 = lgh.level(0);
    let positions: Vec<[f32; 3]> = (0..level0.len())
        .map(|i| level0.position(i).to_array())
        .collect();
    let tree: kiddo::ImmutableKdTree<f32, 3> = kiddo::ImmutableKdTree::new_from_slice(&positions);
    let (lo, hi) = bounds(&lights);
    let points = testsets::query_points(lo, hi, 1000, 7);
    let mut g = c.benchmark_group("level0_radius_query_explosion_128");
    g.sample_size(10);
    g.throughput(Throughput::Elements(points.len() as u64));
    for alpha in [1.0f32, 2.0, 4.0] {
        let r = alpha * lgh.h1();
        g.bench_with_input(BenchmarkId::new("bricks", alpha), &r, |b, &r| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for &x in &points {
                    lgh.lights_within(0, x, r, |_, d| sum += d).unwrap();
                }
                sum
            })
        });
        g.bench_with_input(BenchmarkId::new("kiddo", alpha), &r, |b, &r| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for &x in &points {
                    for n in tree.within_unsorted::<kiddo::SquaredEuclidean>(&x.to_array(), r * r) {
                        sum += n.distance.sqrt();
                    }
                }
                sum
            })
        });
    }
    g.finish();
}

/// The blackbody table every medium of lgh-volume shares (500 K to 12,000 K by 1 K, built once a
/// process), against its entries computed one integral at a time (the colour-matching functions
/// again at every entry), as the table was built before it computed them once.
fn blackbody(c: &mut Criterion) {
    let mut g = c.benchmark_group("blackbody_table_500_12000_by_1");
    g.sample_size(10);
    g.throughput(Throughput::Elements(11_502));
    g.bench_function("table", |b| {
        b.iter(|| BlackbodyTable::new(black_box(500.0), 12_000.0, 1.0).unwrap())
    });
    g.bench_function("integral_per_entry", |b| {
        b.iter(|| {
            (0..11_502)
                .map(|i| blackbody_rgb(black_box(500.0) + i as f32))
                .collect::<Vec<Vec3>>()
        })
    });
    g.finish();
}

criterion_group!(benches, build, query, level0_index, blackbody);
criterion_main!(benches);
