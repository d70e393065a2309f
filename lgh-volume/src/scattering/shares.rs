//! How an image splits by where its light comes from: the emission alone and what each depth's
//! lights add (paper Sec. 5's depths, measured on the image).

use lgh_core::glam::Vec3;
use lgh_image::Image;

/// How the image splits by where its light comes from: the luminance summed over an image's
/// pixels of the emission alone, and of what each depth's lights add (see
/// [`FrameRender::scatter_shares`](crate::FrameRender::scatter_shares)).
#[derive(Clone, Debug, PartialEq)]
pub struct Shares {
    /// `Σ_px ‖E‖`: the emission seen through the smoke, no scattering.
    pub emission: f64,
    /// `Σ_px ‖R_k − E‖` for `k = 0..=n`, `R_k` the image lit by depth `k`'s lights alone (depth
    /// 0: single scattering of the emission lights, their near field centred as the merged
    /// lights').
    pub depths: Vec<f64>,
    /// `Σ_px ‖R_tail − E‖`, `R_tail` the image lit by the geometric tail's lights alone
    /// ([`Scattered::tail_lights`](crate::scattering::Scattered::tail_lights)): the depths
    /// beyond `n`; `None` without a tail.
    pub tail: Option<f64>,
}

impl Shares {
    /// The shares of `emitted`, the emission alone, `depths[k]`, the image lit by depth `k`'s
    /// lights alone, and `tail`, by the geometric tail's (all the same size).
    pub(crate) fn of_images(emitted: &Image, depths: &[Image], tail: Option<&Image>) -> Shares {
        let luminance = |p: Vec3| f64::from(lgh_core::luminance(p));
        let added = |image: &Image| {
            image
                .pixels
                .iter()
                .zip(&emitted.pixels)
                .map(|(&r, &e)| luminance(r) - luminance(e))
                .sum()
        };
        Shares {
            emission: emitted.pixels.iter().map(|&p| luminance(p)).sum(),
            depths: depths.iter().map(added).collect(),
            tail: tail.map(added),
        }
    }

    /// Everything the image holds: the emission, the depths and the tail.
    ///
    /// ```
    /// use lgh_volume::scattering::Shares;
    ///
    /// let s = Shares { emission: 2.0, depths: vec![1.0, 0.5], tail: Some(0.5) };
    /// assert_eq!(s.total(), 4.0);
    /// ```
    #[must_use]
    pub fn total(&self) -> f64 {
        self.emission + self.depths.iter().sum::<f64>() + self.tail.unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use lgh_core::glam::Vec3;

    use crate::lights::ExplosionLights;
    use crate::medium::Medium;
    use crate::method::Method;
    use crate::render::{Camera, Framing};
    use crate::scattering::tests::blob;
    use crate::settings::MarchSettings;
    use crate::shadow::Shadows;

    #[test]
    fn the_shares_add_up_to_the_image_for_brute_force() {
        // The marcher is linear in the lights' intensities: without shadows (V = 1) and with
        // brute force, emission + Σ_k (R_k − E) (+ the tail's R_tail − E) is the merged image
        // up to rounding, for a pass of two depths and for one stopped by a share with its
        // geometric tail. Each pixel's scattered light is a sum of N non-negative terms per
        // step (N ≤ merged lights): relative error ≤ (N + 12) u of its value, for the merged
        // image and each of the m parts; their sum errs by at most (m + 1) (N + 12) u of the
        // total.
        let volume = blob(12);
        let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let unshadowed = MarchSettings {
            shadows: Shadows::None,
            ..Default::default()
        };
        for (scatter_depth, scatter_stop) in [(2, 0.0), (16, 0.01)] {
            let settings = MarchSettings {
                scatter_depth,
                scatter_stop,
                ..unshadowed
            };
            let frame =
                crate::FrameRender::new(&emission, Method::Brute, &volume, &medium, &settings, &())
                    .unwrap();
            let s = frame.scattered().unwrap();
            let camera = Camera::frame(Vec3::splat(-0.8), Vec3::splat(0.8), 16, 12).unwrap();
            let shares = frame.scatter_shares(&camera, &()).unwrap().unwrap();
            assert_eq!(shares.depths.len(), s.depths().len() + 1);
            assert_eq!(shares.tail.is_some(), scatter_stop > 0.0, "{shares:?}");
            let (image, _) = frame.render(&camera, &()).unwrap();
            let total: f64 = image
                .pixels
                .iter()
                .map(|&p| f64::from(lgh_core::luminance(p)))
                .sum();
            let parts = shares.total();
            let u = f64::from(f32::EPSILON) / 2.0;
            let n = s.lights().lights().len() as f64;
            let m = (shares.depths.len() + 2 + usize::from(shares.tail.is_some())) as f64;
            let bound = (m + 1.0) * (n + 12.0) * u;
            assert!(
                (parts - total).abs() <= bound * total,
                "{parts} vs {total} ({shares:?})"
            );
            // Every depth adds light. (Without shadows nothing bounds the ratio of one depth
            // to the last: unshadowed, the model does not conserve energy.)
            assert!(shares.depths.iter().all(|&d| d > 0.0), "{shares:?}");
            assert!(shares.tail.is_none_or(|t| t > 0.0), "{shares:?}");
        }
    }
}
