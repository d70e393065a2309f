//! The emission marched apart from the light (`MarchSettings::emission_samples`) in a whole
//! frame: with the scattered light as a grid of in-scattered radiance and with a surface in
//! view, what finer emission rays change is the emission's filter alone.

use lgh_volume::lgh_core::glam::Vec3;
use lgh_volume::lighting_cache::{LightingCacheSettings, ScatteredLight};
use lgh_volume::render::{Camera, Framing, MarchSettings, Up};
use lgh_volume::surfaces::Ground;
use lgh_volume::{procedural, ExplosionLights, FrameRender, Medium, Method};

#[test]
fn finer_emission_rays_change_the_emission_alone_with_a_scattered_grid_and_a_surface() {
    // A pixel with `e` emission rays a side is the box filter of `e × e` rays of emission plus
    // that of `n × n` rays of everything else, so `image(n, e) − image(n, n)` is the emission's
    // `e × e` filter less its `n × n` one: the same whatever lights the smoke and the ground.
    // Here, single scattering against two scattered depths as a grid (the march adds the grid's
    // radiance at every sample, the ground is shaded with the merged lights): the two
    // differences agree to the rounding of sums of larger terms (1e-5 of the brightest pixel).
    let volume = procedural(32, 0.5).unwrap();
    let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
    let (lo, hi) = volume.active_bounds().unwrap();
    let ground = Ground::new(Up::Z, lo.z - 0.05, Vec3::splat(0.5)).unwrap();
    let camera = Camera::look_at(
        Vec3::new(0.0, -3.0, 0.4),
        (lo + hi) * 0.5 - Vec3::Z * 0.4,
        Vec3::Z,
        50.0,
        24,
        18,
    )
    .unwrap();
    let grid = LightingCacheSettings {
        scattered_light: ScatteredLight::Grid,
        ..LightingCacheSettings::coarse()
    };
    let render = |depth: usize, e: usize| {
        let settings = MarchSettings {
            scatter_depth: depth,
            lighting_cache: grid,
            emission_samples: e,
            ..Default::default()
        };
        assert_eq!(
            settings.scattered_grid(Method::Lgh { alpha: 2.0 }),
            depth > 0
        );
        let frame = FrameRender::new(
            &lights,
            Method::Lgh { alpha: 2.0 },
            &volume,
            &medium,
            &settings,
            &(),
        )
        .unwrap()
        .with_surfaces(&ground);
        let (image, stats) = frame.render(&camera, &()).unwrap();
        assert!(stats.surface_points > 0, "the ground is in view");
        image.pixels
    };
    let (single, single_fine) = (render(0, 1), render(0, 3));
    let (scattered, scattered_fine) = (render(2, 1), render(2, 3));
    let brightest = scattered
        .iter()
        .chain(&single)
        .map(|p| p.max_element())
        .fold(0.0f32, f32::max);
    let (mut lit_apart, mut filtered) = (0.0f32, 0.0f32);
    for i in 0..single.len() {
        let a = single_fine[i] - single[i];
        let b = scattered_fine[i] - scattered[i];
        assert!(
            (a - b).abs().max_element() <= 1e-5 * brightest,
            "pixel {i}: {a} with single scattering, {b} with the grid"
        );
        lit_apart = lit_apart.max((scattered[i] - single[i]).abs().max_element());
        filtered = filtered.max(a.abs().max_element());
    }
    // Both differ where the test looks: the scattered light moves pixels, the finer emission
    // rays move them too.
    assert!(lit_apart > 1e-3 * brightest && filtered > 1e-3 * brightest);
}
