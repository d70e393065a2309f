//! Level 0's unshadowed light split by distance into a near part, summed at every march
//! sample, and a far part, interpolated from the lighting cache's vertices
//! (`lighting_cache`, "Level 0 as a ratio").
//!
//! With level 0 kept as a ratio, a sample multiplies level 0's unshadowed light
//! `U(x) = Σ_j B_0(d_j) I_j g(d_j)` (eq. 1 with `V = 1`, `d_j = ‖x − p_j‖`) by the shadowing
//! its vertices interpolate. Summed exactly, `U` costs every level-0 light within `r_1 = α h_1`
//! of the sample — about 270 at α = 2 inside the fire, each a voxel light — and that sum was
//! most of what the ratio form cost over level 0 cached as light. Only the lights close to the
//! sample make `U` vary within a voxel: the voxel light's near field `g` peaks at its own
//! voxel (`7.7/h²`, `lgh_core::near_field`), and it is that peak, interpolated between the
//! voxel centres, that made level 0 cached as light flicker. So a partition of unity in the
//! distance, `w(d) + (1 − w(d)) = 1`, with
//!
//! `w(d) = 1` for `d ≤ a`, falling linearly to 0 at `b = 3a`,
//!
//! splits `U = U_near + U_far`, `U_near(x) = Σ_j w(d_j) B_0 I_j g` and
//! `U_far(x) = Σ_j (1 − w(d_j)) B_0 I_j g`. The near part — a few lights — is summed at every
//! sample; the far part holds no light nearer than `a`, varies over the distance to its
//! lights, and is computed at the vertices with the rest of the cache and interpolated
//! trilinearly. At a vertex the two parts add up to its exact `U_v`.
//!
//! **The reach** `b` is [`NEAR_REACH`] voxels by default. A model of the fire (lights on the
//! voxel centres of a ball with a smooth, noisy or sparse intensity, α = 2, vertices on the
//! voxel centres) gives the relative RMS error of `U` over points in the ball, and the near
//! lights a sample sums (of about 270 in reach of `r_1` in dense fire):
//!
//! | `a`–`b` (voxels) | smooth | noisy | sparse | near lights (dense) |
//! |---|---|---|---|---|
//! | 0.5–1.5 | 0.97% | 1.3% | 2.2% | 12.8 |
//! | 0.67–2 | | | 1.6% | |
//! | 1–3 | 0.46% | 0.55% | 0.89% | 95 |
//! | level 0 interpolated whole (cached as light) | 2.6% | 4.3% | 8.8% | 0 |
//!
//! (A smoothstep ramp instead of the linear one, or an inner radius other than `b/3`, changed
//! the sparse case's error by less than a tenth.) The error is the interpolation's, a linear
//! function of the lights' intensities, so it follows the fire from frame to frame: flicker.
//! `lgh bench flicker --cache-level 0` on the dev fire (frames 50–56, 32×20; its flames are
//! the sparse case) against the uncached render's 0.0001025: level 0 as light +39%, the near
//! part of 1.5 voxels +19%, 2.25 voxels +5.0%, 3 voxels −1.6%, level 0 summed whole −11%. The
//! default is 3 voxels, comfortably within a tenth. On the Fig. 8-class frame at 1280×720
//! (dense fire, 436,211 lights) the render's CPU-seconds were 114.0 at 3 voxels, 111.3 at 1.5
//! (one after the other) and 124.3 summed whole (an earlier run; this machine's speed varied
//! by a tenth between runs). The near part's query scans only the cells that meet its smaller
//! ball ([`lgh_core::LghBackend::within`]).
//!
//! The far part's lights are shaded with the [`escape`](lgh_core::near_field::escape) of their
//! light through the smoke at the point, which a vertex takes at its own extinction and the
//! cache interpolates; `a` stays above 0.3 voxels, within which the escape falls below 1 and
//! varies fastest with the extinction (a point's own voxel light, shielded by its smoke), so
//! that part is always summed at the sample. The distances here are to the lights' voxel
//! centres, while a voxel light's near field is centred at its cell's emission centroid, up to
//! 0.71 voxels from its centre (`crate::voxel_light`, "The near field's centre"): at the
//! default reach a far-part light's near field is centred 0.29 voxels or more from the point;
//! at the shortest reach it may be centred at the point itself.

use crate::error::{check_setting, RenderError};

/// The default reach `b` of level 0's near part, in voxels (module docs).
pub const NEAR_REACH: f32 = 3.0;

/// The shortest reach: its inner radius `b/3` must stay beyond 0.3 voxels, where a voxel light
/// is shielded by the smoke at the point (module docs).
pub const MIN_NEAR_REACH: f32 = 0.9;

/// The partition of level 0's lights into a near and a far part (module docs): `w(d) = 1` to
/// `a = b/3`, linear to 0 at the reach `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearPart {
    /// `b`, world units.
    reach: f32,
    /// `1 / (b − a)`.
    inv_ramp: f32,
}

impl NearPart {
    /// The near part of `reach` voxels of side `voxel_size`; a reach below [`MIN_NEAR_REACH`]
    /// voxels (or not finite) is an error.
    ///
    /// ```
    /// use lgh_volume::near_part::NearPart;
    ///
    /// let part = NearPart::new(1.5, 0.5)?; // 1.5 voxels of 0.5: 0.75 world units
    /// assert_eq!(part.reach(), 0.75);
    /// assert_eq!((part.weight(0.2), part.weight(0.5), part.weight(0.75)), (1.0, 0.5, 0.0));
    /// assert_eq!(
    ///     NearPart::new(0.5, 0.5).unwrap_err().to_string(),
    ///     "lighting cache: level 0's near reach 0.5 must be at least 0.9 voxels"
    /// );
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn new(reach: f32, voxel_size: f32) -> Result<Self, RenderError> {
        check_setting(
            reach.is_finite() && reach >= MIN_NEAR_REACH,
            "lighting cache: level 0's near reach",
            reach,
            "must be at least 0.9 voxels",
        )?;
        let b = reach * voxel_size;
        Ok(NearPart {
            reach: b,
            inv_ramp: 1.0 / (b - b / 3.0),
        })
    }

    /// `b`: no light farther than this from a sample is in its near part (world units).
    #[must_use]
    pub fn reach(&self) -> f32 {
        self.reach
    }

    /// `w(d)`: the share of a light at distance `d` in the near part (`1 − w(d)` in the far).
    #[inline]
    #[must_use]
    pub fn weight(&self, d: f32) -> f32 {
        ((self.reach - d) * self.inv_ramp).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weight_falls_continuously_from_a_third_of_the_reach_to_the_reach() {
        let part = NearPart::new(3.0, 1.0).unwrap();
        let mut last = 1.0;
        for i in 0..=400 {
            let d = i as f32 * 0.01;
            let w = part.weight(d);
            assert!((0.0..=1.0).contains(&w));
            assert!(
                w <= last && last - w <= 0.01 / 2.0 + 1e-6,
                "at {d}: {last} to {w}"
            );
            if d <= 1.0 {
                assert_eq!(w, 1.0);
            }
            if d >= 3.0 {
                assert_eq!(w, 0.0);
            }
            last = w;
        }
        assert!(NearPart::new(f32::INFINITY, 1.0).is_err());
        assert!(NearPart::new(f32::NAN, 1.0).is_err());
    }
}
