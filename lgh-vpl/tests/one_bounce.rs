//! The VPL model against an independent estimate (issue 14): one-bounce indirect light in the
//! Cornell box, path traced ([`lgh_vpl::reference::one_bounce`]) and gathered from first-bounce
//! VPLs by brute force, with and without the `max(d, h0)` clamp. What the clamp drops and what
//! the finite VPL count leaves are measured here, so the model's own bias is stated, not hidden.
//!
//! Needs `../shared/data/meshes/cornellbox_original`; says SKIPPED without it.

use lgh_core::glam::Vec3;
use lgh_core::{BruteForce, GridSettings, LightSample, LightingGridHierarchy, ShadingPoint};
use lgh_image::Image;
use lgh_vpl::direct::{Direct, DirectSettings};
use lgh_vpl::indirect::{point_lights, Indirect, IndirectSettings};
use lgh_vpl::primary::area_lights;
use lgh_vpl::reference::one_bounce;
use lgh_vpl::vpl::{trace, VplSettings};
use lgh_vpl::{render_with_shader, Camera, Mesh, Scene};

fn env(name: &str, default: u32) -> u32 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn mean(image: &Image) -> f64 {
    image
        .pixels
        .iter()
        .map(|p| p.element_sum() as f64)
        .sum::<f64>()
        / image.pixels.len() as f64
}

fn rel_rmse(a: &Image, r: &Image) -> f64 {
    lgh_image::compare(a, r).unwrap().rel_rmse
}

/// Path-traced one bounce (`LGH_PT_STRATA²` paths per pixel, default 24² = 576) against brute
/// force over `LGH_VPLS` first-bounce VPLs (default 20,000), on `LGH_PX²` pixels (default 16²)
/// of the Cornell box.
///
/// Asserted, with the bounds' reasons:
/// - unclamped VPLs and the path tracer agree on the image mean within 3%: both are unbiased
///   estimates of the same integral. Measured at the defaults: −1.2% (the other VPL seed
///   −1.1%); at 32², 4096 paths and 100K VPLs: −0.5% (−0.3%), per-pixel rel. RMSE 7.6%
///   against the path tracer, 2.8% seed against seed — the path tracer's noise dominates the
///   per-pixel figure (paths that see the ceiling beside the lamp), its mean is what resolves
///   the model's bias;
/// - the clamp at the hierarchy's `h0` (0.8–1.6% of the box) drops under 1% of the image mean,
///   as `docs/gi.md` says (measured: 0.00–0.01%).
#[test]
fn first_bounce_vpls_agree_with_path_tracing_and_the_clamp_is_measured() {
    let Some(obj) = lgh_tests::cornell_box() else {
        return;
    };
    let scene = Scene::new(Mesh::load_obj(&obj).unwrap());
    let lights = area_lights(scene.mesh());
    let px = env("LGH_PX", 16) as usize;
    let camera = Camera::new(
        Vec3::new(0.0, 1.0, 3.9),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        39.0,
        px,
        px,
    )
    .unwrap();
    let epsilon = 1e-4;
    let direct = Direct::new(
        &scene,
        &lights,
        DirectSettings {
            area_strata: 2,
            epsilon,
        },
    );
    let traced = one_bounce(
        &scene,
        &camera,
        &direct,
        env("LGH_PT_STRATA", 24),
        epsilon,
        |_| {},
    )
    .unwrap();

    let vpls_of = |seed| {
        let settings = VplSettings {
            count: env("LGH_VPLS", 20_000) as usize,
            max_bounces: 1,
            seed,
        };
        trace(&scene, &lights, &settings).unwrap().vpls
    };
    let gather = |vpls: &[lgh_vpl::vpl::Vpl], h0: f32| {
        let point = point_lights(vpls);
        let settings = IndirectSettings {
            h0,
            gaussian_samples: 0,
            epsilon,
            shadows: true,
            lobe_error: None,
            point_error: None,
        };
        let shader = Indirect::new(&scene, vpls, settings);
        let brute = BruteForce::new(&point).unwrap();
        // Each of brute force's samples is its VPL (index for index), shaded with its lobe.
        let shade = |p: &ShadingPoint, s: &LightSample| shader.shade(p, s, Some(s.index as usize));
        render_with_shader(&scene, &camera, &brute, shade, |_| {})
            .unwrap()
            .image
    };
    let vpls = vpls_of(1);
    // The clamp lgh gi uses: the hierarchy's h0 over these VPLs.
    let h0 = LightingGridHierarchy::build(&point_lights(&vpls), &GridSettings::default())
        .unwrap()
        .h0();
    let clamped = gather(&vpls, h0);
    let unclamped = gather(&vpls, 1e-6);
    let other_seed = gather(&vpls_of(2), 1e-6);

    let pt = mean(&traced.image);
    let (mc, mu, mo) = (mean(&clamped), mean(&unclamped), mean(&other_seed));
    println!(
        "h0 {h0:.4}; means: path traced {pt:.5}, unclamped VPLs {mu:.5} ({:+.2}%), other seed {mo:.5} ({:+.2}%), clamped {mc:.5} (clamp drops {:.2}%)",
        100.0 * (mu / pt - 1.0),
        100.0 * (mo / pt - 1.0),
        100.0 * (1.0 - mc / mu),
    );
    println!(
        "rel. RMSE against the path tracer: unclamped {:.4}, other seed {:.4}, clamped {:.4}; seed against seed {:.4}",
        rel_rmse(&unclamped, &traced.image),
        rel_rmse(&other_seed, &traced.image),
        rel_rmse(&clamped, &traced.image),
        rel_rmse(&other_seed, &unclamped),
    );
    assert!((mu / pt - 1.0).abs() < 0.03, "{mu} against {pt}");
    // What `docs/gi.md` states: the clamp at h0 drops under 1% of the light here.
    assert!(
        1.0 - mc / mu < 0.01,
        "the clamp drops {}%",
        100.0 * (1.0 - mc / mu)
    );
}
