//! Criterion benches of the explosion renderer: the same small image of the procedural explosion
//! (40³, 32×18, ray-marched shadows) through the lighting grid hierarchy at α = 1, 2, 4, through
//! brute force over every light, and path-traced (single scattering, 16 paths per pixel); and the
//! per-frame light update of a sequence; and shadow rays alone, one by one and together, through
//! the demo's 128³ volume; and the deep-shadow cube maps (paper Sec. 4) of the demo's explosion
//! at 64³: traced, and looked up for the lights a render asks about, against ray-marched shadow
//! rays to the same lights, as points, as volume lights in uniform steps (the maps' reference)
//! and as volume lights in cone steps (`--shadows volumes`).
//! `lgh bench explosion` measures the large scenes and the errors; these are the quick,
//! statistically careful timings.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lgh_volume::lgh_core::glam::Vec3;
use lgh_volume::lgh_core::random::SplitMix64;
use lgh_volume::pathtrace::{self, PathSettings};
use lgh_volume::render::{Camera, Framing, MarchSettings};
use lgh_volume::shadow::{
    Casters, CubeMapSettings, CubeMaps, ShadowGrid, ShadowQuery, Visibility, VolumeRays,
};
use lgh_volume::{explosion, procedural, ExplosionLights, FrameRender, Medium, Method};

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
                let lgh = Method::Lgh { alpha };
                FrameRender::new(&lights, lgh, &volume, &medium, &march, &())
                    .and_then(|f| f.render(&camera, &()))
                    .unwrap()
            })
        });
    }
    g.bench_function("brute", |b| {
        b.iter(|| {
            FrameRender::new(&lights, Method::Brute, &volume, &medium, &march, &())
                .and_then(|f| f.render(&camera, &()))
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

/// Shadow rays through the demo's volume (procedural 128³, its medium) in 2-voxel steps (the
/// demo's), cut off at 10⁻³: from each of 100 random points of the box to 96 random points
/// within 4, 16 or 64 voxels of it (clamped into the box), one by one with `transmittance` and
/// together with `transmittances` (eight abreast where the CPU has AVX2).
fn shadow_rays(c: &mut Criterion) {
    let volume = procedural(128, 0.5).unwrap();
    let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let grid = ShadowGrid::new(&volume, &medium, 2.0, 1e-3);
    let (lo, hi) = volume.density.bounds();
    let h = volume.density.voxel_size;
    let mut g = c.benchmark_group("shadow_rays_128_100x96");
    for voxels in [4.0f32, 16.0, 64.0] {
        let mut rng = SplitMix64(7);
        let r = Vec3::splat(voxels * h);
        let sets: Vec<(Vec3, Vec<Vec3>)> = (0..100)
            .map(|_| {
                let x = rng.next_in(lo, hi);
                let lights = (0..96)
                    .map(|_| rng.next_in(x - r, x + r).clamp(lo, hi))
                    .collect();
                (x, lights)
            })
            .collect();
        g.bench_with_input(BenchmarkId::new("one_by_one", voxels), &sets, |b, sets| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for (x, lights) in sets {
                    sum += lights
                        .iter()
                        .map(|&l| grid.transmittance(*x, l).0)
                        .sum::<f32>();
                }
                sum
            })
        });
        let mut out = Vec::new();
        g.bench_with_input(BenchmarkId::new("together", voxels), &sets, |b, sets| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for (x, lights) in sets {
                    grid.transmittances(*x, lights, &mut out);
                    sum += out.iter().sum::<f32>();
                }
                sum
            })
        });
    }
    g.finish();
}

/// A shading point and its lights: centres and (level, index).
type Query = (Vec3, Vec<Vec3>, Vec<(u8, u32)>);

/// The cube maps of the demo's explosion at 64³ (its medium, α = 2, texel rays in 2-voxel steps
/// as `lgh demo`'s): tracing them all, and the visibility of the lights the hierarchy returns at
/// 200 random points of the smoke's box, through the maps and through shadow rays (2-voxel
/// steps, cut off at 10⁻³) — the two ways a render can ask the same question.
fn cube_maps(c: &mut Criterion) {
    let volume = explosion(64, 0.5).unwrap();
    let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
    let lgh = lights.hierarchy();
    let blending = lgh.blending(2.0).unwrap();
    let settings = CubeMapSettings {
        step_voxels: 2.0,
        ..Default::default()
    };
    let mut g = c.benchmark_group("cube_maps_64");
    g.sample_size(10);
    g.bench_function("trace", |b| {
        b.iter(|| {
            CubeMaps::build(
                Casters::new(lgh, &blending),
                &volume,
                &medium,
                &settings,
                &|_| {},
            )
            .unwrap()
        })
    });
    let maps = CubeMaps::build(
        Casters::new(lgh, &blending),
        &volume,
        &medium,
        &settings,
        &|_| {},
    )
    .unwrap();
    let grid = ShadowGrid::new(&volume, &medium, 2.0, 1e-3);
    let (lo, hi) = volume.active_bounds().unwrap();
    let mut rng = SplitMix64(3);
    // Each point's lights as the hierarchy returns them: centres, (level, index).
    let queries: Vec<Query> = (0..200)
        .map(|_| {
            let x = rng.next_in(lo, hi);
            let (mut centres, mut ids) = (Vec::new(), Vec::new());
            lgh.query(x, &blending, |l| {
                centres.push(l.position);
                ids.push((l.level, l.index));
            })
            .unwrap();
            (x, centres, ids)
        })
        .collect();
    let lookups: usize = queries.iter().map(|q| q.1.len()).sum();
    eprintln!("cube_maps_64: {lookups} lights at 200 points");
    let mut out = Vec::new();
    g.bench_function("lookups_200_points", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for (x, centres, ids) in &queries {
                maps.transmittances(*x, centres, ids, &mut out);
                sum += out.iter().sum::<f32>();
            }
            sum
        })
    });
    g.bench_function("shadow_rays_200_points", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for (x, centres, _) in &queries {
                grid.transmittances(*x, centres, &mut out);
                sum += out.iter().sum::<f32>();
            }
            sum
        })
    });
    // Coarse lights as volume lights (eq. 6), ray-marched in the maps' step: uniform steps
    // (the maps' reference) and cone steps with the plain rest eight abreast (`volumes`).
    let rays = VolumeRays::new(Casters::new(lgh, &blending), &volume, &medium, 2.0, 1e-3);
    g.bench_function("volume_rays_200_points", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for (x, centres, ids) in &queries {
                rays.transmittances(*x, centres, ids, &mut out);
                sum += out.iter().sum::<f32>();
            }
            sum
        })
    });
    let volumes = Visibility::Volumes {
        points: ShadowGrid::new(&volume, &medium, 2.0, 1e-3),
        rays: rays.clone(),
    };
    let shadow_queries: Vec<(Vec3, ShadowQuery)> = queries
        .iter()
        .map(|(x, _, _)| {
            let mut q = ShadowQuery::default();
            lgh.query(*x, &blending, |l| q.push(l)).unwrap();
            (*x, q)
        })
        .collect();
    g.bench_function("volumes_200_points", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for (x, q) in &shadow_queries {
                volumes.transmittances(*x, q, &mut out);
                sum += out.iter().sum::<f32>();
            }
            sum
        })
    });
    g.finish();
}

criterion_group!(benches, renders, shadow_rays, cube_maps);
criterion_main!(benches);
