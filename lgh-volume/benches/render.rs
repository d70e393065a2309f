//! Criterion benches of the explosion renderer: the same small image of the procedural explosion
//! (40³, 32×18, ray-marched shadows) through the lighting grid hierarchy at α = 1, 2, 4, through
//! brute force over every light, and path-traced (single scattering, 16 paths per pixel); and the
//! per-frame light update of a sequence; and shadow rays alone, through the demo's 128³ volume.
//! `lgh bench explosion` measures the large scenes and the errors; these are the quick,
//! statistically careful timings.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lgh_volume::explosion::{procedural, Medium};
use lgh_volume::lgh_core::glam::Vec3;
use lgh_volume::lgh_core::testsets::SplitMix64;
use lgh_volume::pathtrace::{self, PathSettings};
use lgh_volume::render::{Camera, MarchSettings};
use lgh_volume::scene::{Backend, ExplosionLights};
use lgh_volume::shadow::ShadowGrid;

fn renders(c: &mut Criterion) {
    let volume = procedural(40, 0.5).unwrap();
    let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
    let (lo, hi) = volume.active_bounds().unwrap();
    let camera = Camera::frame(lo, hi, 32, 18).unwrap();
    let march = MarchSettings::default();
    let mut g = c.benchmark_group("explosion_40_render_32x18");
    g.sample_size(10);
    for alpha in [1.0f32, 2.0, 4.0] {
        g.bench_with_input(BenchmarkId::new("lgh", alpha), &alpha, |b, &alpha| {
            b.iter(|| {
                lights
                    .render(
                        Backend::Lgh { alpha },
                        &volume,
                        &medium,
                        &camera,
                        &march,
                        &|_| {},
                    )
                    .unwrap()
            })
        });
    }
    g.bench_function("brute", |b| {
        b.iter(|| {
            lights
                .render(Backend::Brute, &volume, &medium, &camera, &march, &|_| {})
                .unwrap()
        })
    });
    let pt = PathSettings {
        spp: 16,
        max_scatter: 1,
        ..Default::default()
    };
    g.bench_function("pathtrace_16spp", |b| {
        b.iter(|| pathtrace::render(&volume, &medium, &camera, &pt, &|_| {}).unwrap())
    });
    g.finish();

    let next = procedural(40, 0.55).unwrap();
    let mut seq = ExplosionLights::new(&[&volume, &next], &medium).unwrap();
    c.bench_function("explosion_40_set_frame", |b| {
        b.iter(|| seq.set_frame(&next, &medium).unwrap())
    });
}

/// 10,000 shadow rays between random points of the demo's volume (procedural 128³, its medium),
/// 4, 16 and 64 voxels long, marched in 2-voxel steps (the demo's) and cut off at 10⁻³.
fn shadow_rays(c: &mut Criterion) {
    let volume = procedural(128, 0.5).unwrap();
    let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let grid = ShadowGrid::new(&volume, &medium, 2.0, 1e-3);
    let (lo, hi) = volume.density.bounds();
    let h = volume.density.voxel_size;
    let mut g = c.benchmark_group("shadow_rays_128_x10000");
    for voxels in [4.0f32, 16.0, 64.0] {
        let mut rng = SplitMix64(7);
        let rays: Vec<(Vec3, Vec3)> = (0..10_000)
            .map(|_| {
                let a = rng.next_in(lo, hi);
                let d = rng.next_in(-Vec3::ONE, Vec3::ONE).normalize_or_zero();
                (a, (a + d * voxels * h).clamp(lo, hi))
            })
            .collect();
        g.bench_with_input(BenchmarkId::new("voxels", voxels), &rays, |b, rays| {
            b.iter(|| {
                rays.iter()
                    .map(|&(a, b)| grid.transmittance(a, b).0)
                    .sum::<f32>()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, renders, shadow_rays);
criterion_main!(benches);
