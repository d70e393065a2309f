//! Where a pass stops (paper Sec. 5 computes a fixed number of depths; `--scatter-depth auto`
//! stops early): each depth's power, and the rule that stops after the depth whose successor
//! would add too little of the light.

use lgh_core::glam::Vec3;

/// Whether a scattering pass stops after the depths whose powers are `powers` (depth 0, the
/// emission lights', first): when the next depth's power, predicted from the last two, is below
/// `share` of all the light so far. Each depth scatters the one before through the same smoke,
/// so the power falls by a nearly steady factor `r` a depth and the next is about
/// `P_k · (P_k / P_{k−1})`. The rule weighs that next depth alone: all the depths left out hold
/// about `P_{k+1} / (1 − r)`, so with `r` = 0.66 (the demo's explosion) a share of 1% leaves out
/// about 3% of the light, with `r` = 0.8 about 5%.
///
/// ```
/// use lgh_volume::scattering::stop_after;
///
/// let halving = [1.0, 0.5, 0.25]; // the next about 0.125, 7% of the 1.75 so far
/// assert!(stop_after(&halving, 0.1));
/// assert!(!stop_after(&halving, 0.05));
/// assert!(!stop_after(&[1.0], 0.5)); // no depth yet: nothing to predict from
/// assert!(stop_after(&[1.0, 0.0], 0.01)); // nothing scattered: nothing more will be
/// ```
#[must_use]
pub fn stop_after(powers: &[f64], share: f32) -> bool {
    let [.., before, last] = powers else {
        return false;
    };
    let next = if *before > 0.0 {
        last * (last / before)
    } else {
        0.0
    };
    next < f64::from(share) * powers.iter().sum::<f64>()
}

/// The luminance of the summed intensities, in f64 (a depth's power,
/// [`DepthReport::power`](super::DepthReport::power)).
pub(super) fn power(intensities: &[Vec3]) -> f64 {
    let total = intensities.iter().fold([0.0f64; 3], |a, i| {
        [0, 1, 2].map(|c| a[c] + f64::from(i[c]))
    });
    lgh_core::LUMINANCE_WEIGHTS
        .to_array()
        .iter()
        .zip(total)
        .map(|(&w, t)| f64::from(w) * t)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::ExplosionLights;
    use crate::medium::Medium;
    use crate::method::Method;
    use crate::scattering::merge::emission_intensities;
    use crate::scattering::tests::{bits, blob, pass};
    use crate::settings::MarchSettings;

    #[test]
    fn the_pass_stops_where_the_next_depth_would_add_too_little() {
        // A pass of up to 8 depths that stops by the rule computes the same first depths as the
        // full pass, bit for bit, and stops at the first depth after which the rule holds.
        let volume = blob(12);
        let medium = Medium::new(1.0, 4.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let lgh = Method::Lgh { alpha: 2.0 };
        let full = pass(
            &emission,
            8,
            lgh,
            &volume,
            &medium,
            &MarchSettings::default(),
        );
        let share = 0.05;
        let stopping = MarchSettings {
            scatter_stop: share,
            ..Default::default()
        };
        let stopped = pass(&emission, 8, lgh, &volume, &medium, &stopping);
        let n = stopped.depths().len();
        assert!((1..8).contains(&n), "{n} depths");
        let mut powers = vec![power(&emission_intensities(&emission))];
        powers.extend(full.depths().iter().map(|d| d.power));
        for k in 1..=n {
            assert_eq!(
                bits(stopped.intensities(k).unwrap()),
                bits(full.intensities(k).unwrap())
            );
            assert_eq!(
                stop_after(&powers[..=k], share),
                k == n,
                "depth {k}: {powers:?}"
            );
        }
        // What it left out is near what the rule predicted: the next depth within a factor 2.
        let (predicted, actual) = (powers[n] * powers[n] / powers[n - 1], powers[n + 1]);
        assert!(
            actual < 2.0 * predicted && predicted < 2.0 * actual,
            "{powers:?}"
        );
        let bad = MarchSettings {
            scatter_stop: 1.0,
            ..stopping
        };
        assert!(bad.check().is_err());

        // With the scattered light as a grid, the pass stops at the same depth and computes one
        // more for the grid alone.
        use crate::lighting_cache::{LightingCacheSettings, ScatteredLight};
        let grid = MarchSettings {
            lighting_cache: LightingCacheSettings {
                scattered_light: ScatteredLight::Grid,
                ..LightingCacheSettings::coarse()
            },
            ..stopping
        };
        let gridded = pass(&emission, 8, lgh, &volume, &medium, &grid);
        let (_, report) = gridded.radiance().expect("a grid");
        let m = gridded.depths().len();
        assert!((1..8).contains(&m), "{m} depths");
        assert_eq!(report.depth, m + 1);
    }
}
