//! Deep-shadow cube maps (paper Sec. 4) against ray-marched shadows of the same lights: whole
//! renders of the procedural explosion through the hierarchy at the paper's α = 2, differing only
//! in how each light's visibility is found — shadow rays to points (`Shadows::RayMarch`), and the
//! maps' own model marched without the maps (`Shadows::RayMarchVolumes`, which isolates their
//! discretisation).

use lgh_image::Image;
use lgh_volume::cache::{self, GridNames, Placement};
use lgh_volume::medium::{EmissionModel, Medium, Volume};
use lgh_volume::procedural;
use lgh_volume::render::{Camera, Framing, MarchSettings, Shadows, Up};
use lgh_volume::shadow::{CoarseShadows, CubeMapSettings, Depths};
use lgh_volume::{ExplosionLights, FrameRender, Method, Variants};

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
    render_with(
        lights,
        Method::Lgh { alpha: 2.0 },
        v,
        &medium(),
        camera,
        &settings,
    )
}

/// The same lights with their coarse lights' shadows as points (the paper's flickering
/// variant of Fig. 9), not volume lights through the prefiltered density.
fn points(lights: &ExplosionLights) -> ExplosionLights {
    let points = Variants {
        coarse_shadows: CoarseShadows::Points,
        ..Variants::default()
    };
    lights.clone().with_variants(points).unwrap()
}

/// `lights` through `method` on `v` in `m` with `settings`, seen by `camera`.
fn render_with(
    lights: &ExplosionLights,
    method: Method,
    v: &Volume,
    m: &Medium,
    camera: &Camera,
    settings: &MarchSettings,
) -> Image {
    FrameRender::new(lights, method, v, m, settings, &())
        .and_then(|f| f.render(camera, &()))
        .unwrap()
        .0
}

/// Relative RMSE of the whole image and of the scattered light alone (the image minus the
/// emission-only render `e`, which both share exactly).
fn errors(a: &Image, r: &Image, e: &Image) -> (f64, f64) {
    (
        lgh_image::compare(a, r).unwrap().rel_rmse,
        lgh_tests::scatter_rel_rmse(a, r, e),
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
    let none = MarchSettings::default();
    let emission = render_with(&lights, Method::Emission, &v, &m, &camera, &none);
    let reference = render(
        &v,
        &lights,
        &camera,
        Shadows::RayMarch,
        CubeMapSettings::default(),
    );
    let variants = [
        (
            "adaptive knots, volume lights (default)",
            true,
            Depths::Adaptive,
        ),
        ("fitted depths, volume lights", true, Depths::Fitted),
        ("fitted depths, point lights", false, Depths::Fitted),
        (
            "sampled depths, point lights (the paper's storage)",
            false,
            Depths::Sampled,
        ),
    ];
    // The maps' own model ray-marched (coarse lights as volume lights through the prefilter):
    // against it, what remains is the maps' discretisation alone.
    let same_model = render(
        &v,
        &lights,
        &camera,
        Shadows::RayMarchVolumes,
        CubeMapSettings::default(),
    );
    let mut whole_errors = Vec::new();
    let points = points(&lights);
    for (name, prefilter, depths) in variants {
        let cube = CubeMapSettings {
            depths,
            ..Default::default()
        };
        let shadowed = if prefilter { &lights } else { &points };
        let img = render(&v, shadowed, &camera, Shadows::CubeMap, cube);
        if prefilter {
            let (whole, scattered) = errors(&img, &same_model, &emission);
            eprintln!(
                "{name}, against the same model ray-marched: relative RMSE {whole:.5} (whole \
                 image), {scattered:.5} (scattered light)"
            );
            assert!(whole < WHOLE_IMAGE, "{name}: {whole}");
        }
        let (whole, scattered) = errors(&img, &reference, &emission);
        eprintln!(
            "{name}: relative RMSE {whole:.5} (whole image), {scattered:.5} (scattered light)"
        );
        whole_errors.push(whole);
    }
    // The knots and the fitted depths meet the target, the fit with and without the prefilter.
    assert!(whole_errors[0] < WHOLE_IMAGE, "{whole_errors:?}");
    assert!(whole_errors[1] < WHOLE_IMAGE, "{whole_errors:?}");
    assert!(whole_errors[2] < WHOLE_IMAGE, "{whole_errors:?}");
    // The paper's sampled depths do not (measured 2.6%): the chord between two depths leaks
    // light through a smoke shell between them (shadow::deep, "What is stored"). That is why
    // the fit replaced them; the test keeps the reason measurable.
    assert!(whole_errors[3] > 2.0 * whole_errors[2], "{whole_errors:?}");
}

/// The demo's explosion (`procedural::explosion` 128³, `lgh demo`'s scene): its dense soot rim is
/// where the paper's four depths fail (the rise of τ across the rim lies between depths 8 and 16
/// voxels apart at levels 3 and 4; `docs/shadows.md`). Against the maps' own model marched, four
/// fixed depths miss the 2% target by far and twelve meet it: the error is the depths' spacing,
/// and it goes where the spacing goes. Four adaptive knots, in the memory of four depths, place
/// the rise where it is and meet it too.
#[test]
fn on_the_demo_four_knots_and_twelve_depths_meet_the_target_and_four_depths_do_not() {
    let v = lgh_volume::procedural::explosion(128, 0.5).unwrap();
    let m = medium();
    let lights = ExplosionLights::new(&[&v], &m).unwrap();
    let (lo, hi) = lgh_volume::medium::framing_bounds(&[&v]).unwrap();
    let camera = Camera::frame(lo, hi, 64, 36).unwrap();
    let render = |shadows, (depths, depth_count)| {
        let settings = MarchSettings {
            shadows,
            cube_maps: CubeMapSettings {
                depths,
                depth_count,
                ..Default::default()
            },
            ..Default::default()
        };
        render_with(
            &lights,
            Method::Lgh { alpha: 2.0 },
            &v,
            &m,
            &camera,
            &settings,
        )
    };
    let same_model = render(Shadows::RayMarchVolumes, (Depths::Fitted, 4));
    let error = |storage: (Depths, usize)| {
        let e = lgh_image::compare(&render(Shadows::CubeMap, storage), &same_model)
            .unwrap()
            .rel_rmse;
        eprintln!("the demo, {storage:?}: relative RMSE {e:.5} against the same model marched");
        e
    };
    let four = error((Depths::Fitted, 4));
    let twelve = error((Depths::Fitted, 12));
    let knots = error((Depths::Adaptive, 4));
    assert!(twelve < WHOLE_IMAGE, "{twelve}");
    assert!(knots < WHOLE_IMAGE, "{knots}");
    assert!(four > 2.0 * WHOLE_IMAGE, "{four}");
}

/// Temporal flicker (ARCHITECTURE.md "Measuring") of `a` against the reference `r`.
fn flicker(a: &[Image], r: &[Image]) -> f64 {
    lgh_image::flicker(a, r).expect("sequences of one size with a lit reference")
}

/// The flicker of each variant against brute force with ray-marched shadows (the exact answer
/// of the point-light model), and of the cube maps against their own model ray-marched.
#[derive(Debug)]
struct Flicker {
    /// The hierarchy at α = 2, ray-marched shadows to points.
    marched: f64,
    /// The hierarchy at α = 2, deep-shadow cube maps (coarse lights as volume lights).
    maps: f64,
    /// The cube maps' model marched without maps: volume lights, ray-marched.
    model: f64,
}

/// The hierarchy at α = 2 over `frames` with ray-marched shadows, with cube maps, with the cube
/// maps' model ray-marched (volume lights, no maps) and with cube maps of coarse lights as
/// points: the flicker of each against brute force with ray-marched shadows. Also printed: the
/// flicker of the cube maps against their own model.
fn flicker_of_variants(frames: &[Volume], m: &Medium, camera: &Camera) -> Flicker {
    let refs: Vec<&Volume> = frames.iter().collect();
    let mut volumes = ExplosionLights::new(&refs, m).unwrap();
    let mut points = points(&volumes);
    let march = MarchSettings::with_shadows;
    let lgh = Method::Lgh { alpha: 2.0 };
    let variants = [
        ("lgh, ray-marched shadows", lgh, Shadows::RayMarch, false),
        ("lgh, cube maps", lgh, Shadows::CubeMap, false),
        (
            "lgh, ray-marched volume lights (the cube maps' model)",
            lgh,
            Shadows::RayMarchVolumes,
            false,
        ),
        (
            "lgh, cube maps, coarse lights as points",
            lgh,
            Shadows::CubeMap,
            true,
        ),
        (
            "brute force, ray-marched (reference)",
            Method::Brute,
            Shadows::RayMarch,
            false,
        ),
    ];
    let mut images: Vec<Vec<Image>> = vec![Vec::new(); variants.len()];
    for f in frames {
        volumes.set_frame(f, m).unwrap();
        points.set_frame(f, m).unwrap();
        for (k, &(_, method, shadows, as_points)) in variants.iter().enumerate() {
            let lights = if as_points { &points } else { &volumes };
            let img = render_with(lights, method, f, m, camera, &march(shadows));
            images[k].push(img);
        }
    }
    let reference = variants.len() - 1;
    let f = [0, 1, 2, 3].map(|k| flicker(&images[k], &images[reference]));
    for (k, (name, ..)) in variants.iter().take(reference).enumerate() {
        eprintln!("{name}: flicker {:.6}", f[k]);
    }
    // What the maps add to their own model's flicker: the same sequence with the same-model
    // renders as the reference.
    let own = flicker(&images[1], &images[2]);
    eprintln!("cube maps against their model ray-marched: flicker {own:.6}");
    Flicker {
        marched: f[0],
        maps: f[1],
        model: f[2],
    }
}

/// The bound: the cube maps flicker at most 10% more than the exact answer of their own
/// model, the volume lights ray-marched without maps (`Shadows::RayMarchVolumes`): what the
/// maps' discretisation adds.
fn maps_within_the_flicker_bound(f: &Flicker) {
    assert!(
        f.maps <= 1.1 * f.model,
        "cube maps {} against their model ray-marched {}",
        f.maps,
        f.model
    );
}

/// On the procedural sequence, the cube maps flicker at most 1.1× ray-marched shadows to points
/// too. Measured in release: point shadows 0.000758, the maps' model 0.000662, the maps 0.000695
/// (1.05× their model, 0.92× point shadows).
/// `cargo test --release -p lgh-volume --test cube_maps -- --ignored --nocapture`.
#[test]
#[ignore = "slow in a debug build (brute force on every frame); .ci/run runs it in release"]
fn flicker_of_cube_map_shadows_on_a_procedural_sequence() {
    let m = medium();
    let frames: Vec<Volume> = (0..7)
        .map(|i| procedural(48, 0.5 + i as f32 / 25.0).unwrap())
        .collect();
    let refs: Vec<&Volume> = frames.iter().collect();
    let bounds = lgh_volume::medium::framing_bounds(&refs).unwrap();
    let camera = Camera::frame(bounds.0, bounds.1, 48, 27).unwrap();
    let f = flicker_of_variants(&frames, &m, &camera);
    maps_within_the_flicker_bound(&f);
    assert!(f.maps <= 1.1 * f.marched, "{f:?}");
}

/// The same on the dev Blender fire's frames 50–56 (skipped without `../shared/data`), with
/// Blender's emission and smoke 200× denser than Blender's default (tests/explosion.rs), so
/// that the shadows matter.
///
/// Here the cube maps' *model* — coarse lights as volume lights, each shadowed as a whole —
/// flickers more than point lights with ray-marched shadows: measured in release, ray-marched
/// point shadows 0.000199, the model ray-marched 0.000265 (1.33×), the cube maps 0.000278
/// (1.05× their model; 0.000021 against it). The maps are held to 1.1× their model (the
/// approximation against the exact answer of the same model), and the model to 1.6× the
/// point lights' (1.2× the measured 1.33×: a change of the volume lights' model that made it
/// flicker more would fail it).
#[test]
#[ignore = "slow in a debug build (brute force on every frame); .ci/run runs it in release"]
fn flicker_of_cube_map_shadows_on_the_real_fire() {
    let Some(paths) = (50..=56)
        .map(lgh_tests::fire_frame)
        .collect::<Option<Vec<_>>>()
    else {
        return;
    };
    let frames = cache::load(&paths, &GridNames::default(), Placement::BlenderDomain).unwrap();
    let m = fire_medium();
    let refs: Vec<&Volume> = frames.iter().collect();
    let (lo, hi) = lgh_volume::medium::framing_bounds(&refs).unwrap();
    let camera = Camera::frame_up(lo, hi, 32, 20, Up::Z).unwrap();
    let f = flicker_of_variants(&frames, &m, &camera);
    maps_within_the_flicker_bound(&f);
    assert!(f.model <= 1.6 * f.marched, "{f:?}");
}

/// Blender's emission with smoke 200× denser than its default (as tests/explosion.rs).
fn fire_medium() -> Medium {
    Medium::new(100.0, 100.0, 1.0, 800.0)
        .unwrap()
        .with_temperature_scale(1000.0)
        .unwrap()
        .with_model(EmissionModel::Blender)
}

#[test]
fn cube_map_shadows_match_ray_marched_shadows_on_a_real_frame() {
    let Some(path) = lgh_tests::fire_frame(56) else {
        return;
    };
    let v = cache::load(&[path], &GridNames::default(), Placement::BlenderDomain)
        .unwrap()
        .remove(0);
    let m = fire_medium();
    let lights = ExplosionLights::new(&[&v], &m).unwrap();
    let (lo, hi) = v.active_bounds().unwrap();
    let camera = Camera::frame_up(lo, hi, 32, 20, Up::Z).unwrap();
    let settings = |shadows| MarchSettings {
        shadows,
        ..Default::default()
    };
    let render = |shadows| {
        let lgh = Method::Lgh { alpha: 2.0 };
        render_with(&lights, lgh, &v, &m, &camera, &settings(shadows))
    };
    let (cube, marched) = (render(Shadows::CubeMap), render(Shadows::RayMarch));
    let whole = lgh_image::compare(&cube, &marched).unwrap().rel_rmse;
    eprintln!("fire frame 0056: cube maps against ray-marched shadows, relative RMSE {whole:.5}");
    assert!(whole < WHOLE_IMAGE, "{whole}");
    let same_model = render(Shadows::RayMarchVolumes);
    let own = lgh_image::compare(&cube, &same_model).unwrap().rel_rmse;
    eprintln!("fire frame 0056: cube maps against their model ray-marched, relative RMSE {own:.5}");
    assert!(own < WHOLE_IMAGE, "{own}");
}
