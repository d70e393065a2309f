//! Criterion benches of the explosion renderer: the same small image of the procedural explosion
//! (40³, 32×18, ray-marched shadows) through the lighting grid hierarchy at α = 1, 2, 4, through
//! brute force over every light, and path-traced (single scattering, 16 paths per pixel); and the
//! per-frame light update of a sequence. `lgh bench explosion` measures the large scenes and the
//! errors; these are the quick, statistically careful timings.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lgh_volume::explosion::{procedural, Medium};
use lgh_volume::pathtrace::{self, PathSettings};
use lgh_volume::render::{Camera, MarchSettings};
use lgh_volume::scene::{Backend, ExplosionLights};

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

criterion_group!(benches, renders);
criterion_main!(benches);
