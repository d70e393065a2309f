//! Determinism across thread counts: the same lights give bit-identical levels and query results
//! whether the hierarchy is built on 1, 2 or 3 rayon threads (lgh-core's `rayon` feature is on here).

use lgh_core::glam::Vec3;
use lgh_core::{testsets, GridSettings, LevelSource, LightingGridHierarchy, PointLight};

fn build_on(
    threads: usize,
    lights: &[PointLight],
    settings: &GridSettings,
) -> LightingGridHierarchy {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| LightingGridHierarchy::build(lights, settings).unwrap())
}

fn check(lights: &[PointLight], settings: GridSettings) {
    let reference = build_on(1, lights, &settings);
    let (lo, hi) = lgh_core::bounds(lights);
    let points = testsets::query_points(lo, hi, 300, 3);
    for threads in [2, 3] {
        let other = build_on(threads, lights, &settings);
        assert_eq!(reference.max_level(), other.max_level());
        for l in 0..=reference.max_level() {
            assert!(
                reference.level(l) == other.level(l),
                "level {l} differs on {threads} threads"
            );
        }
        for alpha in [1.0f32, 3.0] {
            let b = reference.blending(alpha).unwrap();
            for &x in &points {
                let f = |s: &lgh_core::LightSample| {
                    s.intensity * lgh_core::falloff(s.distance, reference.h0())
                };
                let (a, na) = reference.query_sum(x, &b, f).unwrap();
                let (c, nc) = other.query_sum(x, &b, f).unwrap();
                assert_eq!(
                    (a.to_array().map(f32::to_bits), na),
                    (c.to_array().map(f32::to_bits), nc)
                );
            }
        }
    }
}

#[test]
fn explosion_lights_are_bit_identical_on_any_thread_count() {
    let res = 40;
    let settings = GridSettings {
        h1: Some(2.0 / res as f32),
        origin: Some(Vec3::splat(0.5 / res as f32)),
        ..Default::default()
    };
    let lights = testsets::explosion_shell(res);
    check(&lights, settings);
    check(
        &lights,
        GridSettings {
            source: LevelSource::PreviousLevel,
            ..settings
        },
    );
}

#[test]
fn scattered_lights_are_bit_identical_on_any_thread_count() {
    check(&testsets::uniform_cube(20_000, 11), GridSettings::default());
    check(
        &testsets::light_strings(4096),
        GridSettings {
            prune_below: 0.5,
            ..Default::default()
        },
    );
}

#[test]
fn rebuild_on_any_thread_count_matches() {
    let lights = testsets::uniform_cube(5_000, 2);
    let brighter: Vec<Vec3> = lights
        .iter()
        .map(|l| l.intensity * Vec3::new(2.0, 0.5, 1.0))
        .collect();
    let mut results = Vec::new();
    for threads in [1, 2] {
        let mut h = build_on(threads, &lights, &GridSettings::default());
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| h.update_intensities(&brighter).unwrap());
        results.push(h);
    }
    for l in 0..=results[0].max_level() {
        assert!(results[0].level(l) == results[1].level(l));
    }
}
