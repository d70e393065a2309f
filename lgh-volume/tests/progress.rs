//! A frame's progress as a caller hears it: the scatter shares count the rows of every render
//! they make, and an adaptive render's refinement, whose steps are pixels, does not add to them.

use lgh_core::glam::Vec3;
use lgh_volume::progress::Recorder;
use lgh_volume::render::{Camera, Framing, MarchSettings, PixelRefinement};
use lgh_volume::{procedural, ExplosionLights, FrameRender, Medium, Method, Phase};

#[test]
fn scatter_shares_of_adaptive_renders_count_rows_alone() {
    let volume = procedural::ball(12, 0.5, 2500.0);
    let medium = Medium::new(4.0, 3.0, 1e-3, 500.0).unwrap();
    let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
    let settings = MarchSettings {
        scatter_depth: 1,
        pixel_samples: 2,
        pixel_refinement: PixelRefinement::Adaptive { tolerance: 0.0 },
        ..Default::default()
    };
    let frame =
        FrameRender::new(&emission, Method::Brute, &volume, &medium, &settings, &()).unwrap();
    let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 16, 12).unwrap();
    // The render itself refines (tolerance 0 refines every pixel that varies).
    let recorder = Recorder::default();
    let (_, stats) = frame.render(&camera, &recorder).unwrap();
    assert!(stats.refined_pixels > 0);
    // The shares' renders refine too; their one phase hears exactly its rows.
    let recorder = Recorder::default();
    frame.scatter_shares(&camera, &recorder).unwrap().unwrap();
    let phases = recorder.heard();
    assert_eq!(phases.len(), 1, "{phases:?}");
    assert_eq!(phases[0].phase, Phase::ScatterShares);
    assert_eq!(phases[0].steps, phases[0].total, "{phases:?}");
}
