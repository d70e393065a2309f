//! Deep-shadow cube maps (paper Sec. 4) against ray-marched shadows of the same lights: whole
//! renders of the procedural explosion through the hierarchy at the paper's α = 2, differing only
//! in how each light's visibility is found.

use lgh_image::Image;
use lgh_volume::medium::{Medium, Volume};
use lgh_volume::procedural;
use lgh_volume::render::{Camera, Framing, MarchSettings, Shadows};
use lgh_volume::shadow::{CubeMapSettings, Depths};
use lgh_volume::{ExplosionLights, Method};

/// The demo's medium (`lgh demo`): albedo 0.75, glowing above 1000 K.
fn medium() -> Medium {
    Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap()
}

/// The LGH render at α = 2 with `shadows` and cube-map settings `cube`.
fn render(
    v: &Volume,
    lights: &ExplosionLights,
    camera: &Camera,
    shadows: Shadows,
    cube: CubeMapSettings,
) -> Image {
    let settings = MarchSettings {
        shadows,
        cube_maps: cube,
        ..Default::default()
    };
    lights
        .render(Method::Lgh, 2.0, v, &medium(), camera, &settings, &|_| {})
        .unwrap()
        .0
}

/// Relative RMSE of the whole image and of the scattered light alone (the image minus the
/// emission-only render `e`, which both share exactly).
fn errors(a: &Image, r: &Image, e: &Image) -> (f64, f64) {
    let sub = |x: &Image| Image {
        pixels: x
            .pixels
            .iter()
            .zip(&e.pixels)
            .map(|(p, q)| *p - *q)
            .collect(),
        ..x.clone()
    };
    (
        lgh_image::compare(a, r).unwrap().rel_rmse,
        lgh_image::compare(&sub(a), &sub(r)).unwrap().rel_rmse,
    )
}

/// The target for the whole image: 2%. Where it comes from: a level-0 map has texels one
/// voxel apart at `r_0` and depths `r_0/2` (one voxel at α = 2) apart, the resolution of the
/// density itself, so its error is that of moving a shadow by a fraction of a voxel; coarser
/// levels light from farther, through smoke filtered wider. The volume lights' prefilter adds a
/// deliberate difference (a cluster's shadow is not a point's), measured separately below.
const WHOLE_IMAGE: f64 = 0.02;

#[test]
fn cube_map_shadows_match_ray_marched_shadows_of_the_same_lights() {
    let v = procedural(64, 0.5).unwrap();
    let m = medium();
    let lights = ExplosionLights::new(&[&v], &m).unwrap();
    let (lo, hi) = v.active_bounds().unwrap();
    let camera = Camera::frame(lo, hi, 64, 36).unwrap();
    let none = &|_: usize| {};
    let emission = lgh_volume::render::render::<lgh_core::BruteForce>(
        &v,
        &m,
        None,
        &camera,
        &MarchSettings::default(),
        none,
    )
    .unwrap()
    .0;
    let reference = render(
        &v,
        &lights,
        &camera,
        Shadows::RayMarch,
        CubeMapSettings::default(),
    );
    let variants = [
        (
            "fitted depths, volume lights (default)",
            true,
            Depths::Fitted,
        ),
        ("fitted depths, point lights", false, Depths::Fitted),
        (
            "sampled depths, point lights (the paper's storage)",
            false,
            Depths::Sampled,
        ),
    ];
    let mut whole_errors = Vec::new();
    for (name, prefilter, depths) in variants {
        let cube = CubeMapSettings {
            prefilter,
            depths,
            ..Default::default()
        };
        let img = render(&v, &lights, &camera, Shadows::CubeMap, cube);
        let (whole, scattered) = errors(&img, &reference, &emission);
        eprintln!(
            "{name}: relative RMSE {whole:.5} (whole image), {scattered:.5} (scattered light)"
        );
        whole_errors.push(whole);
    }
    // The fitted depths meet the target with and without the prefilter.
    assert!(whole_errors[0] < WHOLE_IMAGE, "{whole_errors:?}");
    assert!(whole_errors[1] < WHOLE_IMAGE, "{whole_errors:?}");
    // The paper's sampled depths do not (measured 2.6%): the chord between two depths leaks
    // light through a smoke shell between them (shadow::deep, "What is stored"). That is why
    // the fit is the default; the test keeps the reason measurable.
    assert!(whole_errors[2] > 2.0 * whole_errors[1], "{whole_errors:?}");
}
