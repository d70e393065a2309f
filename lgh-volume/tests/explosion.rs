//! The explosion renderer end to end: the lighting grid hierarchy against brute force over every
//! light (the exact answer of the same light model) on a procedural volume and a real Blender
//! frame, and a 7-frame sequence of the real cache rendered bit-identically on 1 and 2 threads.

use lgh_tests::{fire_frame, scatter_errors};
use std::path::PathBuf;

use lgh_image::Image;
use lgh_volume::cache::{self, GridNames, Placement};
use lgh_volume::medium::{framing_bounds, EmissionModel, Medium, Volume};
use lgh_volume::procedural;
use lgh_volume::render::{Camera, Framing, MarchSettings, Shadows, Up};
use lgh_volume::{ExplosionLights, FrameRender, Method};

/// Renders `volume` with brute force and with the hierarchy at α = 1, 2, 4; returns the
/// scattered light's relative RMSE at each α, and the same channel by channel at α = 2.
fn errors_by_alpha(volume: &Volume, medium: &Medium, camera: &Camera, shadows: Shadows) -> Errors {
    let lights = ExplosionLights::new(&[volume], medium).unwrap();
    let s = MarchSettings {
        shadows,
        ..Default::default()
    };
    let render = |method| {
        FrameRender::new(&lights, method, volume, medium, &s, &())
            .and_then(|f| f.render(camera, &()))
            .unwrap()
            .0
    };
    let emission = render(Method::Emission);
    let brute = render(Method::Brute);
    let scattered: f64 = brute
        .pixels
        .iter()
        .zip(&emission.pixels)
        .map(|(b, e)| f64::from(lgh_core::luminance(*b - *e)))
        .sum();
    assert!(scattered > 0.0, "the test needs scattered light");
    let errors: Vec<(f64, [Option<f64>; 3])> = [1.0, 2.0, 4.0]
        .iter()
        .map(|&alpha| {
            let img = render(Method::Lgh { alpha });
            scatter_errors(&img, &brute, &emission)
        })
        .collect();
    Errors {
        luminance: errors.iter().map(|e| e.0).collect(),
        channels: errors[1].1,
    }
}

/// The scattered light's errors against brute force ([`errors_by_alpha`]).
struct Errors {
    /// Relative RMSE of luminance at α = 1, 2, 4.
    luminance: Vec<f64>,
    /// Each channel's at α = 2.
    channels: [Option<f64>; 3],
}

/// The bound at α = 2, from the core's measured point-probe error on the 1M-light explosion set
/// (`docs/benchmarks.md`, `lgh bench core`): relative RMSE 6.9%, 1.3% and 0.19% at α = 1, 2, 4.
///
/// Without shadows a pixel's scattered light is a transmittance-weighted mean of point values of
/// the very model the probes measure, and by Jensen's inequality the mean's error is at most the
/// points' RMS error; another light set than the probes' may err differently, for which we allow
/// a factor of 2: 2.6%. Shadows add an error the probes do not have (a cluster is shadowed as a
/// point at its illumination centre), for which we allow a factor of 4: 5.2%.
fn bound(shadows: Shadows) -> f64 {
    match shadows {
        Shadows::None => 2.0 * 0.013,
        Shadows::RayMarch => 4.0 * 0.013,
        // The hierarchy's lights through their cube maps against brute force ray-marched: the
        // maps' own error (≤ 2% against ray-marched shadows of the same lights, the target of
        // shadow::deep's tests) on top.
        Shadows::CubeMap => 4.0 * 0.013 + 0.02,
        // Coarse lights as volume lights through the prefiltered density: a cluster's shadow
        // is still not its lights' shadows, allowed as for ray-marched points.
        Shadows::RayMarchVolumes | Shadows::Volumes => 4.0 * 0.013,
    }
}

/// Checks the α = 2 error against [`bound`] (each channel's against 1.5× it), and that the
/// error shrinks as α grows.
fn check(errors: &Errors, shadows: Shadows, what: &str) {
    let (channels, errors) = (errors.channels, &errors.luminance);
    eprintln!(
        "{what}: scattered-light relative RMSE at α = 1, 2, 4: {errors:?}; R, G, B at α = 2: \
         {channels:?}"
    );
    let b = bound(shadows);
    assert!(errors[1] < b, "{what}: α = 2 error {} ≥ {b}", errors[1]);
    assert!(
        errors[0] > errors[1] && errors[1] > errors[2],
        "{what}: error must shrink with α: {errors:?}"
    );
    // Each channel too, within 1.5× the bound: the hierarchy's lights are placed by their
    // luminance, so a channel whose light sits elsewhere than the luminance's errs more
    // (issue 54's target for lgh against Cycles: each channel within 1.5× the luminance's).
    for (c, e) in channels.iter().enumerate() {
        let e = e.unwrap_or_else(|| panic!("{what}: channel {c} has no scattered light"));
        assert!(
            e < 1.5 * b,
            "{what}: channel {c}'s α = 2 error {e} ≥ 1.5 × {b}"
        );
    }
}

#[test]
fn lgh_matches_brute_force_on_a_procedural_explosion() {
    let v = procedural(40, 0.5).unwrap();
    let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let (lo, hi) = v.active_bounds().unwrap();
    let cam = Camera::frame(lo, hi, 24, 14).unwrap();
    let shadows = Shadows::RayMarch;
    let errors = errors_by_alpha(&v, &m, &cam, shadows);
    check(&errors, shadows, "procedural 40³, shadows");
    // Coarse lights as volume lights (the cube maps' model, marched): brute force's lights are
    // all points, so this is the error of the hierarchy with the prefilter.
    let shadows = Shadows::RayMarchVolumes;
    let errors = errors_by_alpha(&v, &m, &cam, shadows);
    check(&errors, shadows, "procedural 40³, volume-light shadows");
    // The same model in cone steps, `lgh explosion`'s default.
    let shadows = Shadows::Volumes;
    let errors = errors_by_alpha(&v, &m, &cam, shadows);
    check(
        &errors,
        shadows,
        "procedural 40³, volume-light shadows in cone steps",
    );
}

#[test]
fn lgh_matches_brute_force_on_a_real_frame() {
    let Some(path) = fire_frame(56) else { return };
    let v = cache::load(&[path], &GridNames::default(), Placement::BlenderDomain)
        .unwrap()
        .remove(0);
    // Blender's emission; smoke 200× denser than Blender's default so that scattering is a
    // sizeable part of the image (at density 1 it is 10⁻⁴ of the emission).
    let m = Medium::new(100.0, 100.0, 1.0, 800.0)
        .unwrap()
        .with_temperature_scale(1000.0)
        .unwrap()
        .with_model(EmissionModel::Blender);
    let (lo, hi) = v.active_bounds().unwrap();
    let cam = Camera::frame_up(lo, hi, 16, 10, Up::Z).unwrap();
    let shadows = Shadows::None;
    let errors = errors_by_alpha(&v, &m, &cam, shadows);
    check(&errors, shadows, "fire frame 0056, no shadows");
}

#[test]
fn a_sequence_of_the_real_cache_is_deterministic() {
    let paths: Vec<PathBuf> = match (50..=56).map(fire_frame).collect::<Option<Vec<_>>>() {
        Some(p) => p,
        None => return,
    };
    let volumes = cache::load(&paths, &GridNames::default(), Placement::BlenderDomain).unwrap();
    // One grid for all frames: the adaptive domain's offsets put them on the full domain.
    assert!(volumes
        .windows(2)
        .all(|w| w[0].density.dims == w[1].density.dims
            && w[0].density.origin == w[1].density.origin));
    let m = Medium::new(50.0, 50.0, 1.0, 800.0)
        .unwrap()
        .with_temperature_scale(1000.0)
        .unwrap()
        .with_model(EmissionModel::Blender);
    let refs: Vec<&Volume> = volumes.iter().collect();
    let (lo, hi) = framing_bounds(&refs).unwrap();
    let cam = Camera::frame_up(lo, hi, 12, 8, Up::Z).unwrap();
    let s = MarchSettings {
        shadows: Shadows::RayMarch,
        step_voxels: 2.0,
        ..Default::default()
    };
    let render_all = |threads: usize| -> Vec<Image> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut lights = ExplosionLights::new(&refs, &m).unwrap();
            volumes
                .iter()
                .map(|v| {
                    lights.set_frame(v, &m).unwrap();
                    let lgh = Method::Lgh { alpha: 2.0 };
                    FrameRender::new(&lights, lgh, v, &m, &s, &())
                        .and_then(|f| f.render(&cam, &()))
                        .unwrap()
                        .0
                })
                .collect()
        })
    };
    let one = render_all(1);
    let two = render_all(2);
    for (i, (a, b)) in one.iter().zip(&two).enumerate() {
        assert!(
            a.pixels == b.pixels,
            "frame {} differs between 1 and 2 threads",
            50 + i
        );
        assert!(
            a.pixels.iter().any(|p| p.max_element() > 0.0),
            "frame {} is black",
            50 + i
        );
    }
    // The fire grows: more light in the last frame than in the first.
    let total = |img: &Image| {
        img.pixels
            .iter()
            .map(|p| f64::from(p.element_sum()))
            .sum::<f64>()
    };
    assert!(total(&one[6]) > total(&one[0]));
}

#[test]
fn a_streamed_sequence_renders_as_one_loaded_at_once() {
    let paths: Vec<PathBuf> = match (50..=56).map(fire_frame).collect::<Option<Vec<_>>>() {
        Some(p) => p,
        None => return,
    };
    let names = GridNames::default();
    let m = Medium::new(50.0, 50.0, 1.0, 800.0)
        .unwrap()
        .with_temperature_scale(1000.0)
        .unwrap()
        .with_model(EmissionModel::Blender);
    // All frames in memory.
    let volumes = cache::load(&paths, &names, Placement::BlenderDomain).unwrap();
    let refs: Vec<&Volume> = volumes.iter().collect();
    let mut at_once = ExplosionLights::new(&refs, &m).unwrap();
    // One frame at a time, each read from its file when needed.
    let (seq, last) =
        cache::Sequence::open_with_last(&paths, &names, Placement::BlenderDomain).unwrap();
    assert!(
        last == volumes[6],
        "the last frame read while opening differs"
    );
    assert_eq!(seq.len(), 7);
    assert_eq!(seq.bounds(), volumes[0].density.bounds());
    let mut streamed =
        ExplosionLights::from_frames((0..seq.len()).map(|i| seq.frame(i)), &m).unwrap();
    assert_eq!(streamed.lights().len(), at_once.lights().len());
    assert_eq!(streamed.lit(), 0, "dark until a frame is set");

    let (lo, hi) = framing_bounds(&refs).unwrap();
    let cam = Camera::frame_up(lo, hi, 10, 6, Up::Z).unwrap();
    let s = MarchSettings {
        step_voxels: 2.0,
        ..Default::default()
    };
    for i in [0, 3, 6] {
        let v = seq.frame(i).unwrap();
        assert!(v == volumes[i], "frame {i} read alone differs");
        streamed.set_frame(&v, &m).unwrap();
        at_once.set_frame(&volumes[i], &m).unwrap();
        // The same lights directly, and then through a render.
        assert!(streamed.lights() == at_once.lights(), "frame {i}'s lights");
        let render = |lights, v| {
            FrameRender::new(lights, Method::Lgh { alpha: 2.0 }, v, &m, &s, &())
                .and_then(|f| f.render(&cam, &()))
                .unwrap()
                .0
        };
        let (a, b) = (render(&streamed, &v), render(&at_once, &volumes[i]));
        assert!(a.pixels == b.pixels, "frame {i}");
    }
    // A frame that cannot be read is an error, from the sequence and through the lights.
    assert!(seq.frame(7).is_err());
    assert!(ExplosionLights::from_frames((0..8).map(|i| seq.frame(i)), &m).is_err());
}

/// A Blender domain's temperature made from the flame (`EmissionValues::BlenderFlame`) is, voxel
/// for voxel, Cycles' `ignition + flame × (max − ignition)` where the flame exceeds 0.01 and 0
/// elsewhere, of the flame grid as written, on the same grid.
#[test]
fn a_domains_temperature_is_made_of_its_flame_voxel_for_voxel() {
    use lgh_volume::cache::EmissionValues;
    let Some(path) = fire_frame(56) else { return };
    let read = |emission_values| {
        let names = GridNames {
            emission: "flame".into(),
            flame: None,
            emission_values,
            ..GridNames::default()
        };
        cache::load(
            std::slice::from_ref(&path),
            &names,
            Placement::BlenderDomain,
        )
        .unwrap()
        .remove(0)
    };
    let (ignition, max_temperature) = (1.2_f32, 2.8_f32);
    let flame = read(EmissionValues::AsWritten).temperature;
    let made = read(EmissionValues::BlenderFlame {
        ignition,
        max_temperature,
    })
    .temperature;
    assert_eq!((made.dims, made.origin), (flame.dims, flame.origin));
    let (mut cut, mut hot) = (0, 0);
    for (&f, &t) in flame.data.iter().zip(&made.data) {
        if f > 0.01 {
            assert_eq!(t, ignition + f * (max_temperature - ignition));
            hot += 1;
        } else {
            assert_eq!(t, 0.0);
            cut += usize::from(f > 0.0);
        }
    }
    eprintln!("{hot} hot voxels, {cut} cut by 0.01");
    // The cut matters on this frame: faint flame is no temperature.
    assert!(hot > 1000 && cut > 100, "{hot} hot voxels, {cut} cut");
}
