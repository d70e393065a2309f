//! The pilot of a pass's first depth under a skipping share (`--scatter-depth auto`): depth 1's
//! power predicted from a sample of the voxels, and the whole pass (paper Sec. 5) skipped when
//! the smoke scatters too little of the emitted light to matter.

/// Voxels the pilot of a pass's first depth samples, at most
/// ([`Scattered::skipped`](super::Scattered::skipped)).
pub const PILOT_VOXELS: usize = 4096;

/// The pilot of a pass's first depth under a skipping share
/// ([`MarchSettings::scatter_skip`](crate::render::MarchSettings::scatter_skip),
/// `--scatter-depth auto`): before
/// the depth-1 fluence is computed at every smoky voxel, it is computed at every `m`-th of
/// them (in index order, `m` the smallest that keeps the sample to [`PILOT_VOXELS`]), and the
/// depth's power is predicted as the sample's times `n / sample`. Depth 1 — and so every depth —
/// is skipped when that prediction is below `share` of the emission lights' power: the rule of
/// [`stop_after`](super::stop_after) for the first depth, which has no depth before it to
/// predict from. Where the smoke scatters nothing (albedo 0) the prediction is exactly 0; where
/// it scatters almost nothing (thin smoke around a flame) the pass, its lights and their cost in
/// the render are saved, and the image is the single-scattering one, bit for bit.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pilot {
    pub(super) share: f32,
    /// The emission lights' power (depth 0).
    pub(super) emitted: f64,
}

impl Pilot {
    /// The sample: every `m`-th of `voxels`.
    pub(super) fn sample(self, voxels: &[usize]) -> Vec<usize> {
        let m = voxels.len().div_ceil(PILOT_VOXELS).max(1);
        voxels.iter().step_by(m).copied().collect()
    }

    /// The power below which the depth is skipped.
    pub(super) fn bar(self) -> f64 {
        f64::from(self.share) * self.emitted
    }
}

#[cfg(test)]
mod tests {
    use lgh_core::glam::Vec3;

    use crate::lights::ExplosionLights;
    use crate::medium::Medium;
    use crate::method::Method;
    use crate::render::{Camera, Framing};
    use crate::scattering::tests::{bits, blob};
    use crate::scattering::Scattered;
    use crate::settings::MarchSettings;

    #[test]
    fn the_pilot_skips_a_pass_that_cannot_matter_and_predicts_its_power() {
        // The ball at 32³: 8,744 smoky voxels, so the pilot samples every 3rd (2,915).
        let volume = blob(32);
        let lgh = Method::Lgh { alpha: 2.0 };
        let frame = |medium: &Medium, depth, stop, skip| {
            let emission = ExplosionLights::new(&[&volume], medium).unwrap();
            let settings = MarchSettings {
                scatter_depth: depth,
                scatter_stop: stop,
                scatter_skip: skip,
                ..Default::default()
            };
            let render = crate::FrameRender::new(&emission, lgh, &volume, medium, &settings, &());
            let render = render.unwrap();
            let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 24, 24).unwrap();
            let image = render.render(&camera, &()).unwrap().0;
            let skipped = render.scattered().and_then(Scattered::skipped).copied();
            let power = render
                .scattered()
                .and_then(|s| s.depths().first().map(|d| d.power));
            (bits(&image.pixels), skipped, power)
        };
        // Thin, nearly black smoke: depth 1 would add well under 1% of the emitted light.
        let thin = Medium::new(1.0, 0.02, 1e-4, 1000.0).unwrap();
        let (image, skipped, _) = frame(&thin, 16, 0.01, 0.01);
        let skipped = skipped.expect("the pilot skips the pass");
        assert!(skipped.predicted > 0.0 && skipped.predicted < 0.01 * skipped.emitted);
        assert_eq!((skipped.sampled, skipped.voxels), (2915, 8744));
        // The image is the single-scattering one, bit for bit.
        let (single, none, _) = frame(&thin, 0, 0.0, 0.0);
        assert!(none.is_none());
        assert_eq!(image, single);
        // The skipping share alone decides: without it the stopping share computes depth 1, and
        // a share that the prediction passes keeps the pass.
        let (_, none, power) = frame(&thin, 16, 0.01, 0.0);
        assert!(none.is_none() && power.is_some());
        let (_, none, _) = frame(&thin, 16, 0.01, 0.1 * skipped.share() as f32);
        assert!(none.is_none());
        // The prediction against the depth computed at every voxel, from a systematic sample of
        // a third of them. 2%: a uniformly random sample of 2,915 voxels whose powers spread
        // with a coefficient of variation of 1 errs by 1/√2915 = 1.85% (one standard
        // deviation); a systematic sample of a smooth field does better (measured: 0.26%).
        let (_, _, exact) = frame(&thin, 1, 0.0, 0.0);
        let (_, by_pilot, _) = frame(&thin, 16, 0.999, 0.999);
        let (exact, predicted) = (exact.unwrap(), by_pilot.unwrap().predicted);
        assert!(
            (predicted / exact - 1.0).abs() < 0.02,
            "{predicted} against {exact}"
        );
        // Smoke that scatters goes on, and its first depth is the full pass's, bit for bit.
        let grey = Medium::new(1.0, 4.0, 1e-4, 1000.0).unwrap();
        let (_, skipped, auto) = frame(&grey, 16, 0.01, 0.01);
        let (_, _, full) = frame(&grey, 1, 0.0, 0.0);
        assert!(skipped.is_none());
        assert_eq!(auto.map(f64::to_bits), full.map(f64::to_bits));
    }
}
