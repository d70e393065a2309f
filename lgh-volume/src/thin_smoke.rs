//! Shadows that cannot matter: smoke so thin that no shadow ray through it loses more than a
//! few percent, where the lights' shadows are skipped by a stated bound.
//!
//! A shadow ray's transmittance is `e^{−τ}`, `τ = ∫ σ_t ds` along it (paper eq. 1's `V`). In a
//! frame whose extinction is at most `σ_max` (the densest voxel: trilinear interpolation and
//! the prefilter of eq. 6 only average), every segment inside the density grid's box — and a
//! shadow ray reads density nowhere else — has `τ ≤ τ_max = σ_max · D`, `D` the box's diagonal.
//! Rendering with no shadows (`V = 1`) then changes nothing of the emission or of its
//! absorption along camera rays, and makes the in-scattered light brighter:
//! - **at every point**, the light in-scattered after `k` flights is at most `e^{kτ_max}`
//!   times too bright ([`ThinSmoke::point_bound`], single scattering's `e^{τ_max} − 1`);
//! - **in power**, unshadowed, a flight of light scatters at most `α τ_max` of its power
//!   (`∫ σ_s ds = α ∫ σ_t ds`), and shadows would have removed at most `1 − e^{−kτ_max}` of the
//!   light scattered `k` times, so skipping them adds at most
//!   `Σ_{k=1}^{K} (α τ_max)^k (1 − e^{−k τ_max})` of the emitted power
//!   ([`ThinSmoke::power_bound`], `K` = [`MAX_SCATTER_DEPTH`] + 1, every depth a pass may add).
//!
//! `lgh explosion --shadow-skip` renders a frame without shadows where the power bound is
//! below its share (1% by default, the share `--scatter-skip` leaves out): on the dev fire's
//! thin smoke (frame 56, `τ_max` = 0.089) the bound is 0.53%, and the render took 1.9 CPU-s
//! instead of 6.9, 0.004% from the shadowed image (docs/cycles.md, "Shadows of thin smoke").

use crate::medium::{Medium, Volume};
use crate::settings::MAX_SCATTER_DEPTH;

/// What skipping a frame's shadows can change (module docs): its smoke's largest optical depth
/// along any segment, and the bounds that follow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinSmoke {
    /// `τ_max`: the densest voxel's extinction times the diagonal of the density grid's box.
    pub optical_depth: f32,
    /// At every point, the most by which single scattering's in-scattered light is too bright
    /// without shadows, relative to it: `e^{τ_max} − 1`.
    pub point_bound: f64,
    /// The most light, as a share of the emitted power, that skipping the shadows adds to the
    /// frame's scattered light at any scattering depth.
    pub power_bound: f64,
}

impl ThinSmoke {
    /// The bounds for `volume` in `medium`.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::thin_smoke::ThinSmoke;
    /// use lgh_volume::{DenseGrid, Medium, Volume};
    ///
    /// // A 10-voxel cube of side 1 whose densest voxel is 0.05: σ_max = 4 · 0.05 = 0.2 and the
    /// // diagonal √3, so τ_max = 0.35.
    /// let mut density = DenseGrid::zeros([10, 10, 10], 0.1, Vec3::ZERO);
    /// density.data[555] = 0.05;
    /// let volume = Volume::new(density.clone(), density);
    /// let medium = Medium::new(1.2, 2.8, 1.0, 1000.0)?; // σ_t = 4 ρ, albedo 0.7
    /// let thin = ThinSmoke::of(&volume, &medium);
    /// assert!((thin.optical_depth - 0.2 * 3f32.sqrt()).abs() < 1e-5);
    /// assert!((thin.point_bound - (0.2f64 * 3f64.sqrt()).exp_m1()).abs() < 1e-6);
    /// // Σ_k (α τ)^k (1 − e^{−kτ}) over the 17 flights of 16 depths: single scattering's
    /// // term first, each deeper one smaller.
    /// let t = f64::from(thin.optical_depth);
    /// let want: f64 = (1..=17).map(|k| (0.7 * t).powi(k) * -(-f64::from(k) * t).exp_m1()).sum();
    /// assert!((thin.power_bound - want).abs() < 1e-6 * want); // the albedo is an f32
    /// assert!(thin.power_bound > 0.7 * t * -(-t).exp_m1());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn of(volume: &Volume, medium: &Medium) -> ThinSmoke {
        let densest = volume.density.data.iter().fold(0.0f32, |m, &d| m.max(d));
        let (lo, hi) = volume.density.bounds();
        let tau = medium.extinction(densest) * (hi - lo).length();
        let t = f64::from(tau);
        let albedo = if medium.extinction(1.0) > 0.0 {
            f64::from(medium.scattering / medium.extinction(1.0))
        } else {
            0.0
        };
        let power_bound = (1..=MAX_SCATTER_DEPTH + 1)
            .map(|k| (albedo * t).powi(k as i32) * -(-(k as f64) * t).exp_m1())
            .sum();
        ThinSmoke {
            optical_depth: tau,
            point_bound: t.exp_m1(),
            power_bound,
        }
    }

    /// Whether the shadows may be skipped under `share` (the most light they may add, as a
    /// share of the emitted power; 0 never skips).
    ///
    /// ```
    /// use lgh_volume::thin_smoke::ThinSmoke;
    ///
    /// let thin = ThinSmoke { optical_depth: 0.089, point_bound: 0.093, power_bound: 0.0053 };
    /// assert!(thin.skips(0.01));
    /// assert!(!thin.skips(0.005));
    /// assert!(!thin.skips(0.0));
    /// ```
    #[must_use]
    pub fn skips(&self, share: f32) -> bool {
        share > 0.0 && self.power_bound <= f64::from(share)
    }
}

#[cfg(test)]
mod tests {
    use lgh_core::glam::Vec3;

    use super::*;
    use crate::lights::ExplosionLights;
    use crate::method::Method;
    use crate::render::{Camera, Framing, MarchSettings};
    use crate::shadow::Shadows;

    /// Luminance.
    fn lum(v: Vec3) -> f64 {
        f64::from(lgh_core::luminance(v))
    }

    #[test]
    fn unshadowed_thin_smoke_is_within_the_point_bound_of_the_shadowed_render() {
        // A soft ball of fire in thin smoke: every light exact (brute force), shadows
        // ray-marched or none. Pixel by pixel, the unshadowed image exceeds the shadowed one by
        // at most `point_bound` times the shadowed in-scattered light (the shadowed image less
        // the emission alone), and by something: the smoke does cast shadows.
        let mut volume = crate::procedural::ball(20, 0.6, 2500.0);
        volume.density.data.iter_mut().for_each(|d| *d *= 0.03);
        let medium = Medium::new(2.0, 0.8, 1e-4, 1000.0).unwrap();
        let thin = ThinSmoke::of(&volume, &medium);
        assert!(
            thin.optical_depth > 0.05 && thin.optical_depth < 1.0,
            "{thin:?}"
        );
        let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
        let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 16, 16).unwrap();
        let render = |method, shadows| {
            let settings = MarchSettings {
                shadows,
                ..Default::default()
            };
            let frame =
                crate::FrameRender::new(&lights, method, &volume, &medium, &settings, &()).unwrap();
            frame.render(&camera, &()).unwrap().0.pixels
        };
        let shadowed = render(Method::Brute, Shadows::RayMarch);
        let unshadowed = render(Method::Brute, Shadows::None);
        let emitted = render(Method::Emission, Shadows::RayMarch);
        let mut largest = 0.0f64;
        for i in 0..shadowed.len() {
            let scattered = lum(shadowed[i]) - lum(emitted[i]);
            let added = lum(unshadowed[i]) - lum(shadowed[i]);
            let slack = 1e-5 * lum(shadowed[i]) + 1e-12;
            assert!(
                added >= -slack,
                "pixel {i}: shadows brightened it by {added}"
            );
            assert!(
                added <= thin.point_bound * scattered + slack,
                "pixel {i}: {added} added, bound {} of {scattered}",
                thin.point_bound
            );
            largest = largest.max(added / scattered.max(1e-12));
        }
        assert!(
            largest > 0.01 * thin.point_bound,
            "no pixel lost light to shadows"
        );
    }

    #[test]
    fn the_bounds_grow_with_the_smoke_and_vanish_without_it() {
        let volume = crate::procedural::ball(12, 0.6, 2500.0);
        let thin = |sigma: f32, albedo: f32| {
            let medium = Medium::new(sigma * (1.0 - albedo), sigma * albedo, 1e-4, 1000.0).unwrap();
            ThinSmoke::of(&volume, &medium)
        };
        let (a, b) = (thin(0.5, 0.7), thin(1.0, 0.7));
        assert!(b.optical_depth > a.optical_depth && b.power_bound > a.power_bound);
        assert!(b.point_bound > a.point_bound);
        // No scattering: nothing to shadow, whatever the absorption.
        assert_eq!(thin(1.0, 0.0).power_bound, 0.0);
        assert!(thin(1.0, 0.0).skips(0.01));
        // Dense smoke: never skipped at the default share.
        assert!(!thin(50.0, 0.7).skips(0.01));
    }
}
