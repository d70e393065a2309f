//! The GPU query (`GpuHierarchy::shade`, `shade.wgsl`) against lgh-core's query on the CPU,
//! point by point: `query_sum` with the same Lambertian response,
//! `ρ/π · Σ B_ℓ(d)·I·g(d)·max(0, n·ω)`.
//!
//! **The tolerance, derived.** Both sides sum the same non-negative terms `t_k` (the lights the
//! CPU reports; the GPU's other candidates have `B = 0` and add exactly 0) in different orders.
//! A sum of `N` non-negative floats in any order is within `(N − 1)·u·Σ t_k` of the exact sum
//! (`u = 2⁻²⁴`), so two orders differ by at most `2(N − 1)·u·S`, `S = Σ t_k`. Each term is
//! computed with a few roundings on each side — `d` by a square root, `g` by a division, the
//! cosine by a dot product and a division, `B = min(a d + c1, c2 − b d)` whose absolute error is
//! a few `u` because `a d ≤ 2`, and four products — at most 16 `u` of the term with its weight
//! taken as 1. With `S₁` the sum of the terms with `B = 1`: `|gpu − cpu| ≤ (2N + 32)·u·S₁` per
//! channel. Measured differences are far below it (printed).
//!
//! Without a GPU adapter (and without Mesa's lavapipe) the tests say SKIPPED, unless
//! `LGH_REQUIRE_GPU` or `LGH_REQUIRE_ALL` is set (`lgh_tests::Piece::Gpu`).

use lgh_core::glam::Vec3;
mod common;

use common::{flicker, g_buffer, gpu};
use lgh_core::testsets::{clumped_lights, explosion_shell, uniform_cube};
use lgh_core::{falloff, GridSettings, LightingGridHierarchy, PointLight};
use lgh_gpu::reference::response;
use lgh_gpu::{Gpu, GpuError, GpuHierarchy, ShadingPoint};
use proptest::prelude::*;

const U: f64 = 1.0 / (1u64 << 24) as f64;

/// The CPU's answer at `p`, the bound on the GPU's difference per channel, and the lights
/// counted.
fn cpu(lgh: &LightingGridHierarchy, alpha: f32, p: &ShadingPoint) -> (Vec3, Vec3, u32) {
    let blending = lgh.blending(alpha).unwrap();
    let (x, n, albedo) = (
        Vec3::from(p.position),
        Vec3::from(p.normal),
        Vec3::from(p.albedo),
    );
    let mut unweighted = Vec3::ZERO;
    let (sum, count) = lgh
        .query_sum(x, &blending, |s| {
            let term = response(x, n, lgh.h0(), s);
            unweighted += term / s.weight;
            term
        })
        .unwrap();
    let scale = albedo / core::f32::consts::PI;
    let bound = unweighted * scale * ((2 * count as u64 + 32) as f64 * U) as f32;
    (sum * scale, bound, count)
}

/// Uploads `lgh` at `alpha`, shades `points` on the GPU and checks every point against the CPU
/// within the derived bound; returns the largest difference over its bound.
fn agrees(gpu: &Gpu, lgh: &LightingGridHierarchy, alpha: f32, points: &[ShadingPoint]) -> f64 {
    let on_gpu = GpuHierarchy::upload(gpu, lgh, alpha).unwrap();
    let got = on_gpu.shade(points).unwrap();
    let mut worst = 0.0f64;
    for (i, (p, g)) in points.iter().zip(&got).enumerate() {
        let (want, bound, count) = cpu(lgh, alpha, p);
        for c in 0..3 {
            let diff = (g[c] - want[c]).abs() as f64;
            assert!(
                diff <= bound[c] as f64,
                "α = {alpha}, point {i}, channel {c}: GPU {} against CPU {} ({count} lights): \
                 {diff:e} over the bound {:e}",
                g[c],
                want[c],
                bound[c]
            );
            if bound[c] > 0.0 {
                worst = worst.max(diff / bound[c] as f64);
            }
        }
    }
    worst
}

fn check_set(name: &str, lights: &[PointLight], settings: &GridSettings) {
    let Some(gpu) = gpu() else { return };
    let lgh = LightingGridHierarchy::build(lights, settings).unwrap();
    let points = g_buffer(lights, 2000, 7);
    for alpha in [1.0, 2.0, 4.0] {
        let worst = agrees(gpu, &lgh, alpha, &points);
        eprintln!("{name}, α = {alpha}: largest difference {worst:.3} of the bound");
    }
}

#[test]
fn agrees_with_the_cpu_on_uniform_lights() {
    check_set("uniform", &uniform_cube(3000, 1), &GridSettings::default());
}

#[test]
fn agrees_with_the_cpu_on_clumped_lights() {
    check_set(
        "clumped",
        &clumped_lights(3000, 2),
        &GridSettings::default(),
    );
}

#[test]
fn agrees_with_the_cpu_on_an_explosion() {
    check_set("explosion", &explosion_shell(24), &GridSettings::default());
}

/// Flickering lights (new intensities, `update_intensities`) and moving ones (a rebuild): each
/// frame uploaded and checked.
#[test]
fn agrees_with_the_cpu_on_flickering_and_moving_lights() {
    let Some(gpu) = gpu() else { return };
    let lights = clumped_lights(2000, 3);
    let points = g_buffer(&lights, 500, 9);
    let mut lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
    for frame in 1..4 {
        let flicker = flicker(&lights, frame);
        lgh.update_intensities(&flicker).unwrap();
        agrees(gpu, &lgh, 2.0, &points);
        let moved: Vec<PointLight> = lights
            .iter()
            .map(|l| PointLight::new(l.position + Vec3::splat(0.1 * frame as f32), l.intensity))
            .collect();
        let rebuilt = LightingGridHierarchy::build(&moved, &GridSettings::default()).unwrap();
        agrees(gpu, &rebuilt, 2.0, &points);
    }
}

/// The same inputs give the same bits, run after run.
#[test]
fn the_same_bits_every_run() {
    let Some(gpu) = gpu() else { return };
    let lights = clumped_lights(2000, 4);
    let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
    let points = g_buffer(&lights, 1000, 5);
    let on_gpu = GpuHierarchy::upload(gpu, &lgh, 2.0).unwrap();
    let first = on_gpu.shade(&points).unwrap();
    for _ in 0..3 {
        assert_eq!(on_gpu.shade(&points).unwrap(), first);
    }
}

#[test]
fn bad_points_are_refused_and_nothing_is_a_zero() {
    let Some(gpu) = gpu() else { return };
    let lights = uniform_cube(100, 5);
    let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
    let on_gpu = GpuHierarchy::upload(gpu, &lgh, 2.0).unwrap();
    let mut points = g_buffer(&lights, 10, 1);
    assert_eq!(on_gpu.shade(&[]).unwrap(), Vec::<[f32; 3]>::new());
    points[3].normal[1] = f32::NAN;
    assert_eq!(
        on_gpu.shade(&points),
        Err(GpuError::InvalidPoint { index: 3 })
    );
    assert!(matches!(
        GpuHierarchy::upload(gpu, &lgh, -1.0),
        Err(GpuError::Query(_))
    ));
    // No lights: every point dark.
    let empty = LightingGridHierarchy::build(&[], &GridSettings::default()).unwrap();
    let dark = GpuHierarchy::upload(gpu, &empty, 2.0).unwrap();
    assert!(dark
        .shade(&points[..3])
        .unwrap()
        .iter()
        .all(|c| *c == [0.0; 3]));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    /// Energy conservation, through the GPU: with α so large that every light is within `r_0`
    /// of every point (`B_0 = 1`), the blended sum is brute force's, within the summation bound.
    #[test]
    fn a_huge_alpha_gives_brute_force(seed in 0u64..1000, n in 1usize..300) {
        let Some(gpu) = gpu() else { return Ok(()) };
        let lights = uniform_cube(n, seed);
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        let points = g_buffer(&lights, 64, seed + 1);
        let on_gpu = GpuHierarchy::upload(gpu, &lgh, 1e4).unwrap();
        let got = on_gpu.shade(&points).unwrap();
        for (p, g) in points.iter().zip(&got) {
            let (x, nrm, albedo) =
                (Vec3::from(p.position), Vec3::from(p.normal), Vec3::from(p.albedo));
            let mut exact = Vec3::ZERO;
            for l in &lights {
                let v = l.position - x;
                let d = v.length();
                let cosine = if d > 0.0 { (nrm.dot(v) / d).max(0.0) } else { 0.0 };
                exact += l.intensity * falloff(d, lgh.h0()) * cosine;
            }
            let exact = exact * albedo / core::f32::consts::PI;
            let bound = (2 * n + 32) as f32 * U as f32;
            for c in 0..3 {
                prop_assert!((g[c] - exact[c]).abs() <= bound * exact[c] + 1e-30,
                             "{} against {}", g[c], exact[c]);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Partition of unity, through the GPU: a single light is every level's light at its own
    /// position (each level splats it onto its vertices with weights summing to one, eqs. 1-2),
    /// so at any distance the blended sum is the light's own `I·g(d)·cos·ρ/π`: the levels'
    /// weights `B_ℓ` and the vertices' weights both sum to one. Within the summation bound of
    /// the module docs (at most 8 terms a level, 22 levels).
    #[test]
    fn one_light_is_lit_as_itself_at_any_distance(
        seed in 0u64..1000,
        alpha in 0.5f32..8.0,
        distance in 0.01f32..100.0,
    ) {
        let Some(gpu) = gpu() else { return Ok(()) };
        let light = uniform_cube(1, seed)[0];
        // Levels 1 to 6 over a level-1 spacing of 0.1 (one light alone would need none).
        let settings = GridSettings {
            h1: Some(0.1),
            origin: Some(Vec3::splat(-1.0)),
            max_level: Some(6),
            ..Default::default()
        };
        let lgh = LightingGridHierarchy::build(&[light], &settings).unwrap();
        prop_assert_eq!(lgh.max_level(), 6);
        let normal = Vec3::new(0.3, 1.0, -0.2).normalize();
        let x = light.position - normal * distance;
        let point = ShadingPoint::new(x, normal, Vec3::splat(0.9));
        let got = GpuHierarchy::upload(gpu, &lgh, alpha).unwrap().shade(&[point]).unwrap()[0];
        let d = (light.position - x).length();
        let cosine = (normal.dot(light.position - x) / d).max(0.0);
        let want = light.intensity * falloff(d, lgh.h0()) * cosine * 0.9 / core::f32::consts::PI;
        let terms = 8 * (u32::from(lgh.max_level()) + 1);
        let bound = (2 * terms + 32) as f32 * U as f32;
        for c in 0..3 {
            prop_assert!((got[c] - want[c]).abs() <= bound * want[c] + 1e-30,
                         "{} against {} at d = {d}", got[c], want[c]);
        }
    }
}
