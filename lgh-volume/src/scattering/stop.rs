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

/// The fall a depth `r = P_n/P_{n−1}` between the last two scattered depths of `powers`
/// (depth 0, the emission lights', first; the emission's own fall to depth 1 is not the
/// transport's), if there are two and `0 ≤ r < 1`: a depth of negative power (a colour whose
/// luminance sums below 0) or light that does not fall makes no geometric series.
fn last_fall(powers: &[f64]) -> Option<f64> {
    let [_, .., before, last] = powers else {
        return None;
    };
    let r = last / before;
    (*before > 0.0 && (0.0..1.0).contains(&r)).then_some(r)
}

/// The factor `r/(1 − r)` by which the depths beyond the last of `powers` (depth 0, the
/// emission lights', first), a geometric series of ratio `r = P_n/P_{n−1}`, exceed depth `n`
/// ([`ScatterTail::Geometric`](crate::scattering::ScatterTail::Geometric)), the fall taken
/// at most `max_fall` (in `[0, 1]`; 0 below, 1 leaves it as it is); `None` with fewer than two
/// scattered depths or a fall outside `[0, 1)` (light that does not fall converges to
/// nothing). A pass whose rule has not settled the fall (it reached its most depths, or
/// [`stop_after`] stopped it, without [`tail_settled`]) bounds it by the medium's albedo
/// ([`Medium::albedo`](crate::Medium::albedo)), the most of a depth's light the next can hold
/// in the exact transport; a settled one passes 1.
///
/// ```
/// use lgh_volume::scattering::geometric_tail;
///
/// // 1 + 1/2 + 1/4 + … beyond depth 2's quarter: another quarter.
/// assert_eq!(geometric_tail(&[2.0, 0.5, 0.25], 1.0), Some(1.0));
/// // A fall of 0.9 not confirmed, in smoke of albedo 0.5: at most 0.5/(1 − 0.5).
/// assert_eq!(geometric_tail(&[2.0, 1.0, 0.9], 0.5), Some(1.0));
/// assert_eq!(geometric_tail(&[1.0, 0.5], 1.0), None); // the emission's fall is not the smoke's
/// assert_eq!(geometric_tail(&[1.0, 0.5, 0.5], 1.0), None);
/// assert_eq!(geometric_tail(&[1.0, 0.5, -0.1], 1.0), None);
/// ```
#[must_use]
pub fn geometric_tail(powers: &[f64], max_fall: f64) -> Option<f64> {
    last_fall(powers).map(|r| {
        let r = r.min(max_fall).max(0.0);
        r / (1.0 - r)
    })
}

/// Whether a pass with a geometric tail
/// ([`ScatterTail::Geometric`](crate::scattering::ScatterTail::Geometric)) stops after the
/// depths whose powers are `powers` (depth 0 first), the last two scattered depths' shapes
/// differing by `shape_change` ([`shape_change`]). The tail's error is the change of its power
/// `T = P_n r/(1 − r)` from the fall before to the last fall, plus `T` times the shape's last
/// change: the tail takes depth `n`'s shape, where the depths beyond it keep moving towards the
/// densest smoke. The pass stops when that error is below `share` of all the light so far.
/// Needs three scattered depths (two falls between them).
///
/// ```
/// use lgh_volume::scattering::tail_settled;
///
/// let steady = [1.0, 0.6, 0.36, 0.216]; // falls 0.6, 0.6: the tail's power known
/// assert!(tail_settled(&steady, 0.0, 0.001));
/// assert!(!tail_settled(&steady, 0.05, 0.001)); // its shape still moving by 5% a depth
/// let drifting = [1.0, 0.6, 0.3, 0.21]; // falls 0.5, 0.7
/// assert!(!tail_settled(&drifting, 0.0, 0.01));
/// assert!(!tail_settled(&[1.0, 0.6, 0.36], 0.0, 0.5)); // one fall: nothing to check it with
/// ```
#[must_use]
pub fn tail_settled(powers: &[f64], shape_change: f64, share: f32) -> bool {
    let n = powers.len();
    if n < 4 {
        return false;
    }
    let (Some(r), Some(before)) = (last_fall(powers), last_fall(&powers[..n - 1])) else {
        return false;
    };
    let last = powers[n - 1];
    let tail = |r: f64| last * r / (1.0 - r);
    let error = (tail(r) - tail(before)).abs() + tail(r) * shape_change;
    error < f64::from(share) * powers.iter().sum::<f64>()
}

/// How far apart two depths' shapes are: half the sum over the voxels of the difference of
/// their luminances, each as a share of its depth's (the total variation distance of the two
/// distributions of light over the voxels; 0 for one depth a multiple of the other, 1 for
/// depths on no common voxel).
///
/// ```
/// use lgh_volume::lgh_core::glam::Vec3;
/// use lgh_volume::scattering::shape_change;
///
/// let a = [Vec3::ONE, Vec3::ONE];
/// assert_eq!(shape_change(&a, &[Vec3::splat(0.5), Vec3::splat(0.5)]), 0.0);
/// assert!((shape_change(&a, &[Vec3::ONE, Vec3::ZERO]) - 0.5).abs() < 1e-12);
/// ```
#[must_use]
pub fn shape_change(a: &[Vec3], b: &[Vec3]) -> f64 {
    let lum = |v: &Vec3| f64::from(lgh_core::luminance(*v));
    let (pa, pb) = (
        a.iter().map(lum).sum::<f64>(),
        b.iter().map(lum).sum::<f64>(),
    );
    if pa <= 0.0 || pb <= 0.0 {
        return 1.0;
    }
    0.5 * a
        .iter()
        .zip(b)
        .map(|(x, y)| (lum(x) / pa - lum(y) / pb).abs())
        .sum::<f64>()
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
    use crate::settings::{MarchSettings, ScatterTail};
    use crate::shadow::Shadows;

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
            scatter_tail: ScatterTail::Dropped,
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

    #[test]
    fn the_geometric_tail_is_the_full_pass_where_dropping_it_is_not() {
        // The exact answer of the same model: the pass to 16 depths, every one computed. On a
        // ball of smoke that scatters most of what it takes (albedo 0.83, the light falling
        // about 0.47 a depth) the pass stopped by the rule at 0.2% with its tail holds the
        // full pass's merged light to within that share where, the tail dropped, it loses
        // several times as much; and each voxel's light too (the tail's shape is the last
        // depth's: the rule weighs its change).
        let volume = blob(16);
        let medium = Medium::new(0.6, 3.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let lgh = Method::Lgh { alpha: 2.0 };
        let with = |scatter_stop, scatter_tail| MarchSettings {
            scatter_stop,
            scatter_tail,
            ..Default::default()
        };
        let full = pass(
            &emission,
            16,
            lgh,
            &volume,
            &medium,
            &with(0.0, ScatterTail::Dropped),
        );
        let tail = pass(
            &emission,
            16,
            lgh,
            &volume,
            &medium,
            &with(0.002, ScatterTail::Geometric),
        );
        let dropped = pass(
            &emission,
            16,
            lgh,
            &volume,
            &medium,
            &with(0.002, ScatterTail::Dropped),
        );
        let merged = |s: &crate::scattering::Scattered| {
            s.lights()
                .lights()
                .iter()
                .map(|l| l.intensity)
                .collect::<Vec<_>>()
        };
        let (exact, tailed, cut) = (merged(&full), merged(&tail), merged(&dropped));
        let total = power(&exact);
        let off = |v: &[Vec3]| (power(v) / total - 1.0).abs();
        // The voxels' light off the full pass's, relative to its sum (L1 over the voxels).
        let spread = |v: &[Vec3]| {
            v.iter()
                .zip(&exact)
                .map(|(a, b)| f64::from(lgh_core::luminance(*a - *b)).abs())
                .sum::<f64>()
                / total
        };
        println!(
            "depths {} / {} / 16; power off {:.2e} / {:.2e}; voxels off {:.2e} / {:.2e}; factor {:?}",
            tail.depths().len(),
            dropped.depths().len(),
            off(&tailed),
            off(&cut),
            spread(&tailed),
            spread(&cut),
            tail.tail()
        );
        assert!(tail.tail().is_some() && tail.depths().len() < 16);
        assert!(off(&tailed) < 0.002, "{}", off(&tailed));
        assert!(
            off(&cut) > 2.0 * off(&tailed),
            "{} {}",
            off(&cut),
            off(&tailed)
        );
        assert!(
            spread(&tailed) < spread(&cut),
            "{} {}",
            spread(&tailed),
            spread(&cut)
        );
        // The merged lights are the computed depths plus the last one times the factor.
        let k = tail.depths().len();
        let f = tail.tail().unwrap() as f32;
        for (s, m) in tailed.iter().enumerate() {
            let sum = (0..=k).fold(Vec3::ZERO, |a, d| a + tail.intensities(d).unwrap()[s]);
            let want = sum + tail.intensities(k).unwrap()[s] * f;
            assert!((*m - want).abs().max_element() <= 1e-5 * want.abs().max_element().max(1e-6));
        }
    }

    #[test]
    fn a_tail_the_rule_has_not_settled_takes_a_fall_no_steeper_than_the_albedo() {
        // A pass cut at its most depths (2) under a stopping share too small to stop it has
        // one fall, which nothing confirms: its tail takes the fall at most the medium's albedo.
        // Without shadows the model does not conserve energy (every voxel sees every other
        // unhidden), so the fall passes the albedo there and the bound is what decides; with
        // ray-marched shadows it falls below the albedo and the fall is taken as it is.
        let volume = blob(12);
        let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0).unwrap();
        let albedo = f64::from(medium.albedo());
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let lgh = Method::Lgh { alpha: 2.0 };
        let fall = |shadows| {
            let settings = MarchSettings {
                shadows,
                scatter_stop: 1e-6,
                ..Default::default()
            };
            let s = pass(&emission, 2, lgh, &volume, &medium, &settings);
            assert_eq!(s.depths().len(), 2);
            let mut powers = vec![power(&emission_intensities(&emission))];
            powers.extend(s.depths().iter().map(|d| d.power));
            let r = powers[2] / powers[1];
            println!(
                "{shadows:?}: fall {r:.4}, albedo {albedo}, tail {:?}",
                s.tail()
            );
            (r, s.tail().expect("one fall below 1"))
        };
        let (r, tail) = fall(Shadows::None);
        assert!(r > albedo && r < 1.0, "{r}");
        assert_eq!(tail, albedo / (1.0 - albedo));
        let (r, tail) = fall(Shadows::RayMarch);
        assert!(r < albedo, "{r}");
        assert_eq!(tail, r / (1.0 - r));
        // Where the rule has settled the fall, it is taken as it is, above the albedo too.
        let settling = MarchSettings {
            shadows: Shadows::None,
            scatter_stop: 0.01,
            ..Default::default()
        };
        let s = pass(&emission, 16, lgh, &volume, &medium, &settling);
        let mut powers = vec![power(&emission_intensities(&emission))];
        powers.extend(s.depths().iter().map(|d| d.power));
        let n = powers.len() - 1;
        let (r, before) = (powers[n] / powers[n - 1], powers[n - 1] / powers[n - 2]);
        println!("settled after {n} depths: falls {before:.4}, {r:.4}");
        assert!(n < 16 && r > albedo, "{powers:?}");
        assert_eq!(s.tail(), Some(r / (1.0 - r)));
    }
}
