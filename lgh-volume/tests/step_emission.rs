//! The camera march's emission through dense smoke at its default step against the same march
//! at steps sixteen times shorter, which tends to the exact integral of the emission and its
//! absorption along each ray (`lgh_volume::step_emission`): no scattering, so the two differ only
//! by how a step integrates them.
//!
//! A ball of smoke whose one-voxel steps are about one optical depth at its centre, around a hot
//! core whose emission rises steeply along every ray that enters it: weighing a step's two
//! emission nodes alike (its far half counted as much as its near one) made the image's mean
//! 4.1% too bright here (measured with that rule); weighed by what the step's smoke lets through
//! from each, it is 0.6% below the fine march (the emission is not a line along a step: steep as
//! the blackbody in a temperature falling 360 K a voxel).

use lgh_core::glam::Vec3;
use lgh_tests::mean_luminance;
use lgh_volume::render::{Camera, Framing, MarchSettings};
use lgh_volume::{ExplosionLights, FrameRender, Medium, Method};

#[test]
fn a_flame_seen_through_its_own_smoke_at_one_voxel_steps_is_the_fine_marchs() {
    // 24³ voxels over [-1, 1]³ (h = 1/12), density 1 at the centre: κ_a = 12 makes a one-voxel
    // step there one optical depth, and the ball 9.6 across. No scattering: no lights.
    let volume = lgh_volume::procedural::ball(24, 0.7, 3000.0);
    let medium = Medium::new(12.0, 0.0, 1e-3, 500.0).unwrap();
    let camera = Camera::frame(Vec3::splat(-0.85), Vec3::splat(0.85), 24, 18).unwrap();
    let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
    let mean_at = |step_voxels: f32| {
        let settings = MarchSettings {
            pixel_samples: 2,
            step_voxels,
            ..Default::default()
        };
        let frame =
            FrameRender::new(&lights, Method::Emission, &volume, &medium, &settings, &()).unwrap();
        mean_luminance(&frame.render(&camera, &()).unwrap().0)
    };
    let (fine, finer) = (mean_at(1.0 / 16.0), mean_at(1.0 / 32.0));
    // The fine march has converged: halving its step moves it by far less than the bound below.
    assert!((fine / finer - 1.0).abs() < 5e-4, "{fine} vs {finer}");
    let ratio = mean_at(1.0) / fine;
    eprintln!("one-voxel steps / sixteenth-voxel steps: {ratio:.4}");
    // 1%: the linear emission's rule to within its error on this curve, far below the 4.1%.
    assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
}
