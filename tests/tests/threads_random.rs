//! Determinism across thread counts on random inputs: random small scenes give bit-identical
//! output on 1, 2, 3 and 8 rayon threads. `determinism.rs` and `renders.rs` check this on a few
//! fixed scenes; here proptest draws the scenes:
//!
//! - volumes: a random density and temperature grid of 8 to 16 voxels a side, rendered by
//!   `FrameRender` through the hierarchy at 12×8 with ray-marched or cube-map shadows, with or
//!   without the lighting cache, with or without a depth of multiple scattering;
//! - surfaces: 1 to 3 point lamps in a room with a random box, their VPLs traced and rendered by
//!   `GiScene` through `GiMethod::Lgh` at 12×8, with a random coarse shading, α, shadow rays and
//!   direct light (the VPLs' own bits compared as well as the image's);
//! - light sets: random `PointLight`s built into a `LightingGridHierarchy` (in parallel: the
//!   `rayon` feature is on here) with random settings, its levels and its sums at random points.
//!
//! Determinism is a feature: the same input gives the same output, bit for bit, whatever the
//! machine's core count — no flicker from one render of a frame to the next, and a farm can
//! split a sequence over machines of any size. Values are compared by their bits (`to_bits`),
//! so `-0.0` against `0.0` or two NaNs count as what they are. Few cases and tiny images keep
//! the file fast in a debug build.

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_core::{GridSettings, LevelSource, LightingGridHierarchy, Material, PointLight};
use lgh_tests::{image_bits, on};
use lgh_volume::lighting_cache::LightingCacheSettings;
use lgh_volume::render::{Camera, Framing, MarchSettings};
use lgh_volume::{DenseGrid, ExplosionLights, FrameRender, Medium, Method, Shadows, Volume};
use lgh_vpl::gi::{Aggregation, CoarseShading, DirectLight, GiMethod, GiScene, GiSettings};
use lgh_vpl::primary::PrimaryLight;
use lgh_vpl::vpl::VplSettings;
use lgh_vpl::Mesh;
use proptest::prelude::*;
use rayon::prelude::*;

/// The thread counts compared with the one-thread reference.
const THREADS: [usize; 3] = [2, 3, 8];

/// The bits of `v`'s components.
fn vec_bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// `run` on 1 thread, then on each of [`THREADS`]: the same bits every time. `lit` says whether
/// the reference has light in it (else the comparison would not bite).
fn same_bits(
    what: &str,
    lit: impl Fn(&[u32]) -> bool,
    run: impl Fn() -> Vec<u32> + Sync,
) -> Result<(), TestCaseError> {
    let reference = on(1, &run);
    prop_assert!(lit(&reference), "{}: the test needs light", what);
    for threads in THREADS {
        let other = on(threads, &run);
        prop_assert!(
            other == reference,
            "{}: bits differ on {} threads",
            what,
            threads
        );
    }
    Ok(())
}

/// Whether some value, read as an `f32`, is positive.
fn any_positive(bits: &[u32]) -> bool {
    bits.iter().any(|&b| f32::from_bits(b) > 0.0)
}

/// A random volume of `dims` voxels centred on the origin, its longest side 2: smoke and heat
/// as random values under a smooth bump about the centre (so they thin out to the edges), the
/// voxel nearest the centre always hot.
fn random_volume(dims: [usize; 3], seed: u64) -> Volume {
    let h = 2.0 / *dims.iter().max().unwrap() as f32;
    let extent = Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32) - 1.0;
    let origin = -0.5 * h * extent;
    let mut density = DenseGrid::zeros(dims, h, origin);
    let mut temperature = density.clone();
    let mut rng = SplitMix64(seed);
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let idx = density.index(i, j, k);
                let r = density.centre(i, j, k).length();
                let bump = (1.0 - r).max(0.0);
                density.data[idx] = bump * rng.next_f32() * 2.0;
                temperature.data[idx] = bump * rng.next_f32() * 3500.0;
            }
        }
    }
    let centre = density.index(dims[0] / 2, dims[1] / 2, dims[2] / 2);
    temperature.data[centre] = 3000.0;
    Volume::new(density, temperature)
}

/// The march settings of `variant` (0 to 5): ray-marched or cube-map shadows, each with and
/// without the lighting cache, and one depth of multiple scattering with ray-marched shadows
/// or with cube maps and the cache.
fn march(variant: usize) -> MarchSettings {
    use Shadows::{CubeMap, RayMarch};
    let (shadows, cached, scatter_depth) = [
        (RayMarch, false, 0),
        (CubeMap, false, 0),
        (RayMarch, true, 0),
        (CubeMap, true, 0),
        (RayMarch, false, 1),
        (CubeMap, true, 1),
    ][variant];
    MarchSettings {
        shadows,
        scatter_depth,
        lighting_cache: if cached {
            LightingCacheSettings::coarse()
        } else {
            LightingCacheSettings::default()
        },
        ..MarchSettings::default()
    }
}

/// The room: a floor and a back wall, a box of `material` on the floor, centred at `at` with
/// half-sides `half`.
fn room(at: Vec3, half: Vec3, material: Material) -> Mesh {
    let grey = Material::Lambert {
        albedo: Vec3::splat(0.7),
    };
    let v = Vec3::new;
    let floor = [
        v(-1., 0., 1.),
        v(1., 0., 1.),
        v(1., 0., -1.),
        v(-1., 0., -1.),
    ];
    let wall = [
        v(-1., 0., -1.),
        v(1., 0., -1.),
        v(1., 2., -1.),
        v(-1., 2., -1.),
    ];
    let mut mesh = Mesh::quad(floor, grey).unwrap();
    mesh.append(Mesh::quad(wall, grey).unwrap()).unwrap();
    let lo = (at - half).max(v(-1.0, 0.0, -1.0));
    mesh.append(Mesh::cuboid(lo, at + half, material).unwrap())
        .unwrap();
    mesh
}

/// The coarse shadings a case picks from: `lgh gi`'s adaptive default, the paper's Gaussian
/// samples (over one hierarchy and over the normal buckets), and representatives drawn by
/// intensity and uniformly.
fn coarse(choice: usize) -> CoarseShading {
    match choice {
        0 => CoarseShading::adaptive(),
        1 => CoarseShading::gaussian(),
        2 => CoarseShading::gaussian()
            .with_aggregation(Aggregation::Buckets)
            .unwrap(),
        3 => CoarseShading::by_intensity(),
        _ => CoarseShading::uniform(),
    }
}

/// A random lamp above the box: position (in the room, higher than the box's top), intensity.
fn lamp_strategy() -> impl Strategy<Value = PrimaryLight> {
    ((-0.8f32..0.8, 0.6f32..1.8, -0.8f32..0.8), 0.5f32..3.0).prop_map(|((x, y, z), i)| {
        PrimaryLight::Point {
            position: Vec3::new(x, y, z),
            intensity: Vec3::new(i, 0.8 * i, 0.6 * i),
        }
    })
}

/// Random lights: `1..max` of them, spread over a box of side up to 8 or, half the time,
/// clustered about a few centres; intensities 0 to 10 (grey), one in eight of them off.
fn lights_strategy(max: usize) -> impl Strategy<Value = Vec<PointLight>> {
    let light = (
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        prop_oneof![1 => Just(Vec3::ZERO), 7 => (0.0f32..10.0).prop_map(Vec3::splat)],
        0usize..4,
    );
    (
        prop::collection::vec(light, 1..max),
        0.05f32..4.0,
        any::<bool>(),
    )
        .prop_map(|(v, extent, clustered)| {
            let centres = [
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(-1.0, 2.0, 0.5),
                Vec3::splat(3.0),
            ];
            v.into_iter()
                .map(|((x, y, z), intensity, c)| {
                    let spread = if clustered { 0.1 * extent } else { extent };
                    let at = if clustered { centres[c] } else { Vec3::ZERO };
                    PointLight::new(at + spread * Vec3::new(x, y, z), intensity)
                })
                .collect()
        })
}

/// The bits of a hierarchy built from `lights` with `settings` (on the current pool): every
/// level's lights and, at each of `points`, the sum of eq. (3) at `alpha` and its count of
/// lights, the points queried in parallel.
fn hierarchy_bits(
    lights: &[PointLight],
    settings: &GridSettings,
    alpha: f32,
    points: &[Vec3],
) -> Vec<u32> {
    let lgh = LightingGridHierarchy::build(lights, settings).unwrap();
    let mut out = Vec::new();
    for l in 0..=lgh.max_level() {
        for light in lgh.level(l).iter() {
            out.extend(vec_bits(light.position));
            out.extend(vec_bits(light.intensity));
        }
    }
    let b = lgh.blending(alpha).unwrap();
    let sums: Vec<([u32; 3], u32)> = points
        .par_iter()
        .map(|&x| {
            let f =
                |s: &lgh_core::LightSample| s.intensity * lgh_core::falloff(s.distance, lgh.h0());
            let (sum, n) = lgh.query_sum(x, &b, f).unwrap();
            (vec_bits(sum), n)
        })
        .collect();
    for (sum, n) in sums {
        out.extend(sum);
        out.push(n);
    }
    out
}

// A volume case takes about 1 s in a debug build (its four renders), a VPL or light-set case
// about 0.1 s: 8 and 16 cases, the file 9 to 19 s on two cores.
proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    /// A random volume, rendered through the hierarchy by `FrameRender` at 12×8 with one of
    /// [`march`]'s settings: its image, and with scattering its merged lights' intensities.
    #[test]
    fn random_volumes_render_the_same_on_any_thread_count(
        dims in [8usize..=16, 8usize..=16, 8usize..=16],
        seed in any::<u64>(),
        variant in 0usize..6,
        alpha in 1.0f32..4.0,
    ) {
        let volume = random_volume(dims, seed);
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
        let (lo, hi) = volume.density.bounds();
        let camera = Camera::frame(lo, hi, 12, 8).unwrap();
        let settings = march(variant);
        let method = Method::Lgh { alpha };
        same_bits(&format!("volume, {settings:?}"), any_positive, || {
            let frame = FrameRender::new(&lights, method, &volume, &medium, &settings, &())
                .unwrap();
            let (image, _) = frame.render(&camera, &()).unwrap();
            let mut bits: Vec<u32> = image_bits(&image).concat();
            bits.extend(frame.lights().lights().iter().flat_map(|l| vec_bits(l.intensity)));
            bits
        })?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Random lamps in a room with a random box: VPLs traced from them and rendered through
    /// the hierarchy by `GiScene` at 12×8, the VPLs' bits with the image's and the shadow
    /// rays' count.
    #[test]
    fn random_vpl_sets_render_the_same_on_any_thread_count(
        lamps in prop::collection::vec(lamp_strategy(), 1..=3),
        (at, half) in ((-0.6f32..0.6, 0.1f32..0.3, -0.6f32..0.4), (0.05f32..0.2, 0.05f32..0.2, 0.05f32..0.2)),
        glossy in any::<bool>(),
        (count, bounces, seed) in (64usize..600, 1u32..=3, any::<u64>()),
        (shading, alpha, shadows, direct) in (0usize..5, 1.5f32..6.0, any::<bool>(), any::<bool>()),
    ) {
        let material = if glossy {
            Material::Phong { kd: Vec3::splat(0.4), ks: Vec3::splat(0.4), exponent: 20.0 }
        } else {
            Material::Lambert { albedo: Vec3::new(0.8, 0.5, 0.3) }
        };
        let mesh = room(Vec3::from(at), Vec3::from(half), material);
        let settings = GiSettings {
            vpls: VplSettings { count, max_bounces: bounces, seed },
            coarse: coarse(shading),
            shadows,
            direct: if direct { DirectLight::default() } else { DirectLight::Off },
            ..GiSettings::default()
        };
        let v = Vec3::new;
        let camera = lgh_vpl::Camera::new(v(0.0, 1.0, 3.0), v(0.0, 0.6, 0.0), Vec3::Y, 50.0, 12, 8)
            .unwrap();
        same_bits(&format!("VPLs, {settings:?}, alpha {alpha}"), any_positive, || {
            let scene = GiScene::prepare(mesh.clone(), lamps.clone(), &settings).unwrap();
            let r = scene.render(GiMethod::Lgh { alpha }, &camera, &()).unwrap();
            let mut bits: Vec<u32> = image_bits(&r.rendered.image).concat();
            bits.extend([r.shadow_rays, r.bounded_points].map(|n| n as u32));
            for vpl in scene.vpls() {
                bits.extend(vec_bits(vpl.position));
                bits.extend(vec_bits(vpl.power));
            }
            bits
        })?;
    }

    /// Random lights into the hierarchy with random settings: its levels and its sums at 64
    /// random points around them.
    #[test]
    fn random_light_sets_build_the_same_on_any_thread_count(
        lights in lights_strategy(3000),
        h1 in prop_oneof![Just(None), (0.1f32..2.0).prop_map(Some)],
        previous in any::<bool>(),
        prune_below in prop_oneof![Just(0.0f32), 0.0f32..2.0],
        alpha in 0.5f32..6.0,
        seed in any::<u64>(),
    ) {
        let settings = GridSettings {
            h1,
            source: if previous { LevelSource::PreviousLevel } else { LevelSource::InputLights },
            prune_below,
            ..GridSettings::default()
        };
        let (lo, hi) = lgh_core::bounds(&lights);
        let points = lgh_core::testsets::query_points(lo, hi, 64, seed);
        let lit = |bits: &[u32]| !bits.is_empty();
        same_bits(&format!("{} lights, {settings:?}", lights.len()), lit, || {
            hierarchy_bits(&lights, &settings, alpha, &points)
        })?;
    }
}
