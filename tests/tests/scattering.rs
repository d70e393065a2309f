//! Multiple scattering (paper Sec. 5, `lgh_volume::scattering`) against the physical truth: the
//! unbiased path tracer on the same grids (ARCHITECTURE.md, "References" (b)).
//!
//! The marcher's lights are a model of the continuous medium (one point light `I = j h³` or
//! `h³ σ_s/(4π) Φ` per voxel centre, fall-off clamped at `h`), so the marcher and the path tracer
//! differ even with one scattering event. That offset is measured on its own — depth 0 (single
//! scattering) against the path tracer with `max_scatter = 1` — so that it is not mistaken for
//! an error of the scattering pass; the pass is then measured at depth `n` against the path
//! tracer with `max_scatter = n + 1`, and on the scattered light alone (the image minus the
//! single-scattering image, on both sides).

use lgh_core::glam::Vec3;
use lgh_core::metrics::ErrorStats;
use lgh_image::Image;
use lgh_tests::mean_luminance;
use lgh_volume::lighting_cache::{LightingCacheSettings, ScatteredLight};
use lgh_volume::pathtrace::{self, PathSettings};
use lgh_volume::render::{Camera, Framing, MarchSettings};
use lgh_volume::{ExplosionLights, FrameRender, Medium, Method, Shadows, Volume};

/// A ball of smoke (density 1 at the centre falling linearly to 0 at radius 0.8) around a large
/// hot core (3000 K at the centre, above 1000 K inside radius 0.47: the path tracer, which has no
/// light model, finds a large emitter quickly), `n³` voxels over `[-1, 1]³`.
fn blob(n: usize) -> Volume {
    lgh_volume::procedural::ball(n, 0.7, 3000.0)
}

fn minus(a: &Image, b: &Image) -> Vec<Vec3> {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .map(|(x, y)| *x - *y)
        .collect()
}

fn rel_rmse(a: &[Vec3], r: &[Vec3]) -> f64 {
    ErrorStats::compare(a, r).unwrap().rel_rmse
}

#[test]
#[ignore = "slow (minutes in a debug build): measures the scattering pass against the path tracer; \
            run with `cargo test --release -p lgh-tests --test scattering -- --ignored --nocapture`"]
fn multiple_scattering_approaches_the_path_tracer() {
    // Albedo 0.9 and an optical depth of about 3 across the ball: the scattered light is a
    // large part of the image (asserted below, ≥ 20 %).
    let n = 4;
    let volume = blob(24);
    let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
    let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
    let camera = Camera::frame(Vec3::splat(-0.85), Vec3::splat(0.85), 40, 30).unwrap();
    let none = &|_: usize| {};
    let spp: u32 = std::env::var("LGH_SCATTER_SPP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2048);
    let truth_seeded = |max_scatter: u32, seed: u64| {
        let settings = PathSettings {
            spp,
            max_scatter,
            seed,
            ..Default::default()
        };
        let t = std::time::Instant::now();
        let (image, variance) =
            pathtrace::render_with_variance(&volume, &medium, &camera, &settings, none).unwrap();
        // The noise of the reference, as a relative RMSE: sqrt(mean variance of the mean) / mean.
        let var: f64 = variance
            .pixels
            .iter()
            .map(|&v| f64::from(lgh_core::luminance(v)))
            .sum::<f64>()
            / variance.pixels.len() as f64;
        let noise = var.max(0.0).sqrt() / mean_luminance(&image);
        eprintln!(
            "path tracer max_scatter {max_scatter}: {spp} spp in {:.1} s, noise {:.4} (relative RMSE of the mean)",
            t.elapsed().as_secs_f64(),
            noise
        );
        (image, noise)
    };
    let truth = |max_scatter: u32| truth_seeded(max_scatter, 3);
    let (pt1, noise1) = truth(1);
    // The noise floor as measured, not as estimated: two independent path-traced images differ
    // by √2 times the noise of one (if the variance estimate above holds; fireflies break it).
    let (other, _) = truth_seeded(1, 4);
    eprintln!(
        "path tracer(1) against itself with another seed: relRMSE {:.4} (√2 × estimate {:.4})",
        rel_rmse(&other.pixels, &pt1.pixels),
        std::f64::consts::SQRT_2 * noise1
    );
    let (ptn, noisen) = truth(n as u32 + 1);
    let scattered_share = 1.0 - mean_luminance(&pt1) / mean_luminance(&ptn);
    eprintln!(
        "scattering beyond the first event: {:.1} % of the path-traced image",
        100.0 * scattered_share
    );
    assert!(scattered_share >= 0.2, "{scattered_share}");

    let lgh = Method::Lgh { alpha: 2.0 };
    let cached = |scattered_light| LightingCacheSettings {
        scattered_light,
        ..LightingCacheSettings::coarse()
    };
    for (method, shadows, lighting_cache) in [
        (
            Method::Brute,
            Shadows::RayMarch,
            LightingCacheSettings::default(),
        ),
        (lgh, Shadows::CubeMap, LightingCacheSettings::default()),
        (lgh, Shadows::RayMarch, LightingCacheSettings::default()),
        (lgh, Shadows::RayMarch, cached(ScatteredLight::Merged)),
        (lgh, Shadows::RayMarch, cached(ScatteredLight::Grid)),
    ] {
        let march = MarchSettings {
            shadows,
            lighting_cache,
            ..Default::default()
        };
        let t = std::time::Instant::now();
        let single = FrameRender::new(&emission, method, &volume, &medium, &march, &())
            .and_then(|f| f.render(&camera, &()))
            .unwrap()
            .0;
        let t_single = t.elapsed().as_secs_f64();
        let march = MarchSettings {
            scatter_depth: n,
            ..march
        };
        let frame = FrameRender::new(&emission, method, &volume, &medium, &march, &()).unwrap();
        let t_pass = frame.seconds().scattering;
        let multi = frame.render(&camera, &()).unwrap().0;
        let offset = rel_rmse(&single.pixels, &pt1.pixels);
        let error = rel_rmse(&multi.pixels, &ptn.pixels);
        let without_pass = rel_rmse(&single.pixels, &ptn.pixels);
        let increment = rel_rmse(&minus(&multi, &single), &minus(&ptn, &pt1));
        let mean_ratio = mean_luminance(&multi) / mean_luminance(&ptn);
        let single_ratio = mean_luminance(&single) / mean_luminance(&pt1);
        // Channel by channel too (reported: the path tracer's noise is measured on luminance).
        let rgb = lgh_image::compare_rgb(&multi, &ptn).unwrap();
        eprintln!(
            "{method:?} {shadows:?}: depth {n} vs path tracer, red, green, blue: relRMSE {:?}, \
             mean ratio {:?}",
            rgb.rel_rmse, rgb.mean_ratio
        );
        eprintln!(
            "{method:?} {shadows:?} {:?}: single scattering vs path tracer(1): relRMSE {offset:.4} \
             (noise {noise1:.4}), mean ratio {single_ratio:.4}; depth {n} vs path tracer({}): relRMSE {error:.4} (noise {noisen:.4}), \
             mean ratio {mean_ratio:.4}; without the pass {without_pass:.4}; scattered light alone \
             (depth {n} − depth 0 vs PT({}) − PT(1)): relRMSE {increment:.4}; render {t_single:.1} s, \
             pass {t_pass:.1} s",
            lighting_cache.scattered_grid(),
            n + 1,
            n + 1
        );
        // The pass must move the image towards the truth: much closer than single scattering
        // is to the same reference (which misses ≥ 20 % of the light).
        assert!(
            error < without_pass,
            "{method:?}: {error} vs {without_pass}"
        );
        // Issue 29's target: depth 4 within 3% of the path tracer's mean (the paper's point
        // lights held 0.82), plus three standard errors of the reference's mean (its pixels'
        // noise over √pixels: 2.4% at the default 2048 spp, 0.4% at 65536).
        let mean_noise = noisen / (ptn.pixels.len() as f64).sqrt();
        assert!(
            (mean_ratio - 1.0).abs() <= 0.03 + 3.0 * mean_noise,
            "{method:?} {shadows:?}: mean ratio {mean_ratio} (noise of the mean {mean_noise})"
        );
    }
}
