//! Blender's colours channel by channel (issue 54): a uniform slab at one temperature each,
//! rendered by lgh with Blender's emission and by Cycles (`tools/cycles/slabs.py`, whose
//! measurements are committed beside it), compared in red, green and blue — where luminance
//! hid a blue 10% off on a fire.
//!
//! The slab: 48³ voxels over [−1, 1]³, density 0.25 with σ_t = 4 · density, albedo 0 (emission
//! and absorption alone: nothing scattered, so the render is exact up to the march and Cycles
//! converges fast), temperature 1 times T, seen from (0, −4, 0) at 16×16; the colour is the
//! mean of the central 4×4 pixels, whose rays cross the whole slab.

use std::sync::Mutex;

use lgh_core::glam::Vec3;
use lgh_image::Image;
use lgh_volume::medium::{EmissionInterpolation, EmissionModel, Medium, Volume};
use lgh_volume::render::{Camera, Framing, MarchSettings};
use lgh_volume::{DenseGrid, ExplosionLights, FrameRender, Method};

/// Cycles 5.2.3's slabs (`slabs.py --bpy python3.13 --spp 1024`), whose voxel placement lgh
/// follows (OpenVDB's: a voxel's value at its centre).
const CYCLES_52: &str = include_str!("../../tools/cycles/slabs-5.2.json");
/// Cycles 3.4.1's (`slabs.py --spp 1024`): the same colours in a slab about 1.5% dimmer,
/// Blender 3.x drawing the voxels over cells a half voxel off (tools/cycles/README.md).
const CYCLES_34: &str = include_str!("../../tools/cycles/slabs-3.4.json");
/// The same slabs with the temperature in alternate layers of T and 3T across the view
/// (`slabs.py --pattern alternating`): each ray crosses both, where the two interpolations of
/// the emission differ by about 1.5×.
const ALTERNATING_52: &str = include_str!("../../tools/cycles/slabs-alternating-5.2.json");
const ALTERNATING_34: &str = include_str!("../../tools/cycles/slabs-alternating-3.4.json");

/// The temperature's layout across the slab.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Pattern {
    Uniform,
    /// 3 in the layers of even y (Blender's world: the layers that `slabs.py` writes at odd z in
    /// lgh's +Y-up one, turned to +Z up), 1 in the others.
    Alternating,
}

const N: usize = 48;
const SIZE: usize = 16;

/// The slab at `kelvin`, rendered as `lgh explosion --density-scale 4 --albedo 0
/// --temperature-scale T --emission-interpolation I` renders it; the mean of its central 4×4
/// pixels.
fn lgh_slab(kelvin: f32, pattern: Pattern, interpolation: EmissionInterpolation) -> Vec3 {
    let h = 2.0 / (N - 1) as f32;
    let mut density = DenseGrid::zeros([N; 3], h, Vec3::splat(-1.0));
    density.data.fill(0.25);
    let mut temperature = density.clone();
    for k in 0..N {
        for j in 0..N {
            for i in 0..N {
                let hot = pattern == Pattern::Alternating && j % 2 == 0;
                temperature.data[density.index(i, j, k)] = if hot { 3.0 } else { 1.0 };
            }
        }
    }
    let volume = Volume::new(density, temperature);
    let medium = Medium::new(4.0, 0.0, 1.0, 0.0)
        .unwrap()
        .with_temperature_scale(kelvin)
        .unwrap()
        .with_model(EmissionModel::Blender)
        .with_interpolation(interpolation);
    let camera = Camera::look_at(
        Vec3::new(0.0, -4.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        40.0,
        SIZE,
        SIZE,
    )
    .unwrap();
    let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
    let settings = MarchSettings::default();
    let image: Image =
        FrameRender::new(&lights, Method::Emission, &volume, &medium, &settings, &())
            .and_then(|f| f.render(&camera, &()))
            .unwrap()
            .0;
    let c = SIZE / 2;
    let mut sum = Vec3::ZERO;
    for y in c - 2..c + 2 {
        for x in c - 2..c + 2 {
            sum += image.get(x, y);
        }
    }
    sum / 16.0
}

/// [`lgh_slab`], each slab rendered once for all the tests (the renders are deterministic, so
/// two threads that render one slab at once agree).
fn slab(kelvin: f32, pattern: Pattern, interpolation: EmissionInterpolation) -> Vec3 {
    type Key = (u32, Pattern, EmissionInterpolation);
    static RENDERED: Mutex<Vec<(Key, Vec3)>> = Mutex::new(Vec::new());
    let key = (kelvin.to_bits(), pattern, interpolation);
    let done = |r: &Vec<(Key, Vec3)>| r.iter().find(|r| r.0 == key).map(|r| r.1);
    if let Some(c) = done(&RENDERED.lock().unwrap()) {
        return c;
    }
    let c = lgh_slab(kelvin, pattern, interpolation);
    RENDERED.lock().unwrap().push((key, c));
    c
}

/// The uniform slab (either interpolation: they agree on a uniform temperature).
fn uniform(kelvin: f32) -> Vec3 {
    slab(kelvin, Pattern::Uniform, EmissionInterpolation::Temperature)
}

/// Cycles' slabs from `json`: (kelvin, colour).
fn cycles(json: &str) -> Vec<(f32, Vec3)> {
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    v["slabs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let c: Vec<f32> = s["cycles"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap() as f32)
                .collect();
            (
                s["kelvin"].as_f64().unwrap() as f32,
                Vec3::new(c[0], c[1], c[2]),
            )
        })
        .collect()
}

/// Each channel of `got` within `share` of `want`'s brightest channel.
fn within(got: Vec3, want: Vec3, share: f32, what: &str) {
    let bound = share * want.abs().max_element();
    let off = (got - want).abs().max_element();
    assert!(
        off <= bound,
        "{what}: lgh {got} against Cycles {want} (off {off}, bound {bound})"
    );
}

/// The test: 1000 to 6500 K, each channel within 0.5% of the brightest channel of
/// Cycles 5.2.3's slab. The blue of the slabs below 2000 K is negative in Cycles, and must be
/// in lgh: a clamped blue (as before) errs there by 2% of the red, four times the bound.
#[test]
fn slabs_match_cycles_channel_by_channel() {
    let slabs = cycles(CYCLES_52);
    assert_eq!(slabs.len(), 7);
    for (kelvin, want) in slabs {
        let got = uniform(kelvin);
        eprintln!("{kelvin} K: lgh {got}, Cycles 5.2.3 {want}");
        within(got, want, 0.005, &format!("{kelvin} K"));
        if kelvin < 1900.0 {
            assert!(
                want.z < 0.0 && got.z < 0.0,
                "{kelvin} K: a negative blue, as Cycles"
            );
        }
    }
}

/// Blender 3.4.1's colours are 5.2.3's: each slab's colour over its luminance (which takes
/// out 3.x's dimmer slab) within 0.5% of the brightest channel of lgh's.
#[test]
fn slabs_colours_match_cycles_3_4() {
    for (kelvin, want) in cycles(CYCLES_34) {
        let got = uniform(kelvin);
        let unit = |c: Vec3| c / lgh_core::luminance(c);
        within(unit(got), unit(want), 0.005, &format!("{kelvin} K (3.4.1)"));
    }
}

/// Which interpolation each Blender draws, on the alternating slabs from 1000 K (layers of
/// 1000 and 3000 K) to 3000 K (3000 and 9000 K): Cycles 5.2.3 draws `attributes` (each voxel's
/// emission interpolated: 4.x and later sample each grid stochastically) within 0.5% of the
/// brightest channel (measured ≤ 0.35%), and is 20–47% away from `temperature`; Cycles 3.4.1
/// draws `temperature` (the emission of the interpolated temperature) within 5% (measured
/// 2.9–4.8%: its slabs are 1.5% brighter here than 3.4.1's, as the uniform ones, and the rest
/// grows with the blue of the hottest layers) and is 15–97% away from `attributes`. So lgh's default (`temperature`)
/// is Blender 3.x's, and `--emission-interpolation attributes` Blender 4.x's and 5.x's.
#[test]
fn each_blender_draws_its_own_interpolation() {
    use EmissionInterpolation::{Attributes, Temperature};
    let render = |kelvin, interpolation| slab(kelvin, Pattern::Alternating, interpolation);
    for (json, own, other, bound, blender) in [
        (ALTERNATING_52, Attributes, Temperature, 0.005, "5.2.3"),
        (ALTERNATING_34, Temperature, Attributes, 0.05, "3.4.1"),
    ] {
        // 6500 K (layers of 19,500 K) left out: Cycles 5.2.3 there is far from either model
        // (+72% and +152% in red), a temperature no fire reaches; 3.4.1 stays within 2%.
        for (kelvin, want) in cycles(json).into_iter().filter(|s| s.0 <= 3000.0) {
            let what = format!("{kelvin} K, Blender {blender}");
            within(render(kelvin, own), want, bound, &what);
            let far = render(kelvin, other);
            let off = (far - want).abs().max_element() / want.abs().max_element();
            assert!(
                off > 0.1,
                "{what}: the other interpolation is only {off} away"
            );
        }
    }
}
