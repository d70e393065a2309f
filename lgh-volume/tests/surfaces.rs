//! Opaque surfaces in the volume render (issue 15, "the explosion in a box"): a surface point
//! reflects `(ρ/π) cos θ I g(d)` from each light, through the smoke's shadows and the surfaces'
//! own, and the smoke in front of it is marched as before.

use lgh_volume::lgh_core::glam::Vec3;
use lgh_volume::lgh_core::{BruteForce, PointLight};
use lgh_volume::medium::{Medium, Volume};
use lgh_volume::render::{Camera, Framing, MarchSettings, Marcher, Up};
use lgh_volume::surfaces::Ground;
use lgh_volume::{DenseGrid, Lights, Shadows};

/// A 16³ box over `[-1, 1]³` of uniform `density` (no emission).
fn fog(density: f32) -> Volume {
    let h = 2.0 / 16.0;
    let mut d = DenseGrid::zeros([16; 3], h, Vec3::splat(-1.0 + 0.5 * h));
    d.data.fill(density);
    let t = DenseGrid::zeros([16; 3], h, Vec3::splat(-1.0 + 0.5 * h));
    Volume::new(d, t)
}

/// The radiance of the one pixel looking straight down at the ground's `(0, −1, 0)` from
/// `(0, 3, 0)`, lit by one unit light at `light`, with the ground or without it.
fn render(volume: &Volume, light: Vec3, shadows: Shadows, with_ground: bool) -> Vec3 {
    let medium = Medium::new(1.0, 1.0, 0.0, 1000.0).unwrap();
    let lights = Lights::new(
        BruteForce::new(&[PointLight::new(light, Vec3::ONE)]).unwrap(),
        0.01,
    );
    let ground = Ground::new(Up::Y, -1.0, Vec3::splat(0.5)).unwrap();
    let settings = MarchSettings {
        shadows,
        ..Default::default()
    };
    let camera = Camera::look_at(
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::Z,
        1.0,
        1,
        1,
    )
    .unwrap();
    let mut marcher = Marcher::new(volume, &medium, &settings).unwrap();
    if with_ground {
        marcher = marcher.with_surfaces(&ground);
    }
    let (image, stats) = marcher.render(&lights, &camera, &()).unwrap();
    assert_eq!(stats.surface_points, u64::from(with_ground));
    image.pixels[0]
}

fn pixel(volume: &Volume, light: Vec3, shadows: Shadows) -> Vec3 {
    render(volume, light, shadows, true)
}

/// Exact but for the shading point's lift off the surface (a thousandth of a voxel, 1.25e-4
/// here), which shortens `d` by that much: 1.7e-4 of `1/d²` at `d = 1.5`; 5e-4 covers it.
#[test]
fn a_ground_point_reflects_the_lambertian_share_of_a_light() {
    let clear = fog(0.0);
    // A light 1.5 above the point, straight up: (ρ/π) I / d².
    let l = pixel(&clear, Vec3::new(0.0, 0.5, 0.0), Shadows::None);
    let exact = 0.5 / std::f32::consts::PI / 2.25;
    assert!((l.x - exact).abs() <= 5e-4 * exact, "{l} against {exact}");
    // Off to the side at 45°: cos θ = 1/√2 at d = √2 · 1.5 (the ground at y = −1).
    let l = pixel(&clear, Vec3::new(1.5, 0.5, 0.0), Shadows::None);
    let exact = 0.5 / std::f32::consts::PI * std::f32::consts::FRAC_1_SQRT_2 / 4.5;
    assert!((l.x - exact).abs() <= 5e-4 * exact, "{l} against {exact}");
    // Below the ground: no light.
    assert_eq!(
        pixel(&clear, Vec3::new(0.0, -2.0, 0.0), Shadows::None),
        Vec3::ZERO
    );
}

#[test]
fn smoke_in_front_of_and_above_the_ground_dims_it_by_beer_lambert() {
    // The fog fills y in [−1, 1] with σ_t = 2: the light at (0, 0.5, 0) reaches the ground
    // through 1.5 of it, and the camera sees the ground through 2 of it. The fog's own single
    // scattering is the same with the ground or without it (the ground does not shadow the
    // smoke), so the ground's share is the difference of the two renders.
    let thick = fog(1.0);
    let lit = pixel(&thick, Vec3::new(0.0, 0.5, 0.0), Shadows::RayMarch);
    let unlit_ground = render(&thick, Vec3::new(0.0, 0.5, 0.0), Shadows::RayMarch, false);
    let ground = lit.x - unlit_ground.x;
    let exact = 0.5 / std::f32::consts::PI / 2.25 * (-2.0f32 * 1.5).exp() * (-2.0f32 * 2.0).exp();
    // The march's one-voxel steps sample the box's faces at voxel centres: 2% covers it.
    assert!(
        (ground - exact).abs() <= 0.02 * exact,
        "{ground} against {exact}"
    );
}
