//! Tone mapping: linear radiance to 8-bit sRGB for display, through Reinhard's curve or a
//! filmic one ([`ToneCurve`], [`tonemap_with`]), at an exposure chosen from the image's
//! brightest pixels ([`auto_exposure`]).

use lgh_core::glam::Vec3;
use lgh_core::luminance;

use crate::image::Image;

/// An exposure for [`tonemap`] that puts the 99th percentile of the non-black pixels' luminance
/// at 4 (tone-mapped to 80% of white), so a few blazing pixels do not darken the whole image;
/// 1 for a black image.
#[must_use]
pub fn auto_exposure(image: &Image) -> f32 {
    let mut l: Vec<f32> = image
        .pixels
        .iter()
        .map(|&p| luminance(p))
        .filter(|&l| l > 0.0 && l.is_finite())
        .collect();
    if l.is_empty() {
        return 1.0;
    }
    let k = (l.len() - 1) * 99 / 100;
    let (_, p99, _) = l.select_nth_unstable_by(k, f32::total_cmp);
    4.0 / *p99
}

/// How [`tonemap_with`] compresses linear radiance (after the exposure) into display values
/// `0..=1`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ToneCurve {
    /// `v / (1 + L)` on luminance `L`: keeps every hue, never reaches white, flattens bright
    /// highlights (a luminance of 4 shows at 80%, 8 at 89%).
    #[default]
    Reinhard,
    /// [`filmic`] on each channel: a toe that deepens the shadows, a long shoulder that keeps
    /// the highlights apart and reaches white at [`FILMIC_WHITE`]; saturated colours desaturate
    /// towards white as they brighten, as film does with fire.
    Filmic,
}

/// The linear value that [`filmic`] maps to white (1).
pub const FILMIC_WHITE: f32 = 11.2;

/// The filmic shape before normalisation: a ratio of quadratics (J. Hable's form of a film
/// response: toe, near-linear middle, shoulder), `0` at `0`, strictly increasing for `x ≥ 0`.
fn filmic_shape(x: f32) -> f32 {
    // Shoulder strength, linear strength, linear angle, toe strength, toe numerator and
    // denominator.
    const SHOULDER: f32 = 0.15;
    const LINEAR: f32 = 0.5;
    const ANGLE: f32 = 0.1;
    const TOE: f32 = 0.2;
    const TOE_NUM: f32 = 0.02;
    const TOE_DEN: f32 = 0.3;
    (x * (SHOULDER * x + ANGLE * LINEAR) + TOE * TOE_NUM)
        / (x * (SHOULDER * x + LINEAR) + TOE * TOE_DEN)
        - TOE_NUM / TOE_DEN
}

/// The filmic tone curve of [`ToneCurve::Filmic`], linear `x ≥ 0` to a linear display value in
/// `0..=1`: `0 → 0`, increasing, `1` from [`FILMIC_WHITE`] on (negative and NaN input give 0).
/// Its middle is steeper than Reinhard's over the highlights a 99th-percentile exposure puts at
/// 2 to 8 ([`auto_exposure`]), so a fireball's core keeps its detail.
///
/// ```
/// use lgh_image::{filmic, FILMIC_WHITE};
///
/// assert_eq!(filmic(0.0), 0.0);
/// assert!(filmic(0.5) < filmic(1.0) && filmic(1.0) < filmic(4.0));
/// assert_eq!(filmic(FILMIC_WHITE), 1.0);
/// assert_eq!(filmic(1e6), 1.0);
/// ```
#[must_use]
pub fn filmic(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    (filmic_shape(x.min(FILMIC_WHITE)) / filmic_shape(FILMIC_WHITE)).min(1.0)
}

/// Linear to sRGB-encoded 8 bits, after multiplying by `exposure` and the Reinhard curve on
/// luminance (which keeps hue while compressing highlights): [`tonemap_with`] and
/// [`ToneCurve::Reinhard`].
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::tonemap;
///
/// assert_eq!(tonemap(Vec3::ZERO, 1.0), [0, 0, 0]);
/// // Grey stays grey; brighter is lighter but never clips to white.
/// let [r, g, b] = tonemap(Vec3::splat(0.5), 1.0);
/// assert!(r == g && g == b);
/// let [bright, ..] = tonemap(Vec3::splat(100.0), 1.0);
/// assert!(r < bright && bright < 255);
/// ```
#[must_use]
pub fn tonemap(v: Vec3, exposure: f32) -> [u8; 3] {
    tonemap_with(v, exposure, ToneCurve::Reinhard)
}

/// Linear to sRGB-encoded 8 bits: multiplies by `exposure`, compresses with `curve`, encodes
/// with the sRGB transfer function. Negative values are black.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{tonemap_with, ToneCurve};
///
/// let fire = Vec3::new(8.0, 3.0, 0.5);
/// let [r, g, b] = tonemap_with(fire, 1.0, ToneCurve::Filmic);
/// assert!(r > g && g > b);
/// // Exposure is a factor on the radiance, before the curve.
/// assert_eq!(tonemap_with(fire, 2.0, ToneCurve::Filmic), tonemap_with(fire * 2.0, 1.0, ToneCurve::Filmic));
/// // Filmic reaches white; Reinhard never does.
/// assert_eq!(tonemap_with(Vec3::splat(50.0), 1.0, ToneCurve::Filmic), [255; 3]);
/// assert!(tonemap_with(Vec3::splat(50.0), 1.0, ToneCurve::Reinhard)[0] < 255);
/// ```
#[must_use]
pub fn tonemap_with(v: Vec3, exposure: f32, curve: ToneCurve) -> [u8; 3] {
    let v = (v * exposure).max(Vec3::ZERO);
    let v = match curve {
        ToneCurve::Reinhard => {
            let l = luminance(v);
            if l > 0.0 {
                v * (1.0 / (1.0 + l))
            } else {
                v
            }
        }
        ToneCurve::Filmic => Vec3::new(filmic(v.x), filmic(v.y), filmic(v.z)),
    };
    let encode = |c: f32| (linear_to_srgb(c.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8;
    [encode(v.x), encode(v.y), encode(v.z)]
}

/// The sRGB transfer function (IEC 61966-2-1): linear light in `[0, 1]` to its encoded value.
///
/// ```
/// use lgh_image::{linear_to_srgb, srgb_to_linear};
///
/// assert_eq!(linear_to_srgb(0.0), 0.0);
/// assert!((linear_to_srgb(0.214_041_14) - 0.5).abs() < 1e-6);
/// assert!((srgb_to_linear(linear_to_srgb(0.3)) - 0.3).abs() < 1e-6);
/// ```
#[must_use]
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1): an encoded value in `[0, 1]` to
/// linear light (how 8-bit texture colours become reflectances).
///
/// ```
/// use lgh_image::srgb_to_linear;
///
/// assert_eq!(srgb_to_linear(1.0), 1.0);
/// assert!((srgb_to_linear(0.5) - 0.214_041_14).abs() < 1e-6);
/// ```
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_exposure_maps_the_99th_percentile_to_4() {
        let mut img = Image::new(100, 1);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            *p = Vec3::splat(i as f32);
        }
        // 99 non-black pixels of luminance 1..=99; the 99th percentile (index 97) is 98.
        assert!((auto_exposure(&img) - 4.0 / 98.0).abs() < 1e-6);
        assert_eq!(auto_exposure(&Image::new(3, 3)), 1.0);
    }

    #[test]
    fn tonemap_is_monotone_and_black_stays_black() {
        assert_eq!(tonemap(Vec3::ZERO, 1.0), [0, 0, 0]);
        let a = tonemap(Vec3::splat(0.2), 1.0);
        let b = tonemap(Vec3::splat(2.0), 1.0);
        assert!(a[0] < b[0] && b[0] < 255);
    }

    #[test]
    fn filmic_curve_is_monotone_from_black_to_white() {
        assert_eq!(filmic(0.0), 0.0);
        assert_eq!(filmic(-1.0), 0.0);
        assert_eq!(filmic(f32::NAN), 0.0);
        // Strictly increasing up to the white point, then exactly white.
        let mut last = 0.0;
        for i in 1..=11_200 {
            let y = filmic(i as f32 * 1e-3);
            assert!(y > last, "not increasing at {}", i as f32 * 1e-3);
            assert!(y <= 1.0);
            last = y;
        }
        assert_eq!(filmic(FILMIC_WHITE), 1.0);
        assert_eq!(filmic(f32::INFINITY), 1.0);
    }

    #[test]
    fn filmic_keeps_highlights_apart_and_scales_with_exposure() {
        // The highlights an automatic exposure puts at luminance 2 to 8: more distinct 8-bit
        // greys with the filmic curve than with Reinhard's.
        let levels = |curve| {
            let mut codes: Vec<u8> = (0..=600)
                .map(|i| tonemap_with(Vec3::splat(2.0 + i as f32 * 0.01), 1.0, curve)[0])
                .collect();
            codes.dedup();
            codes.len()
        };
        let (filmic_levels, reinhard_levels) =
            (levels(ToneCurve::Filmic), levels(ToneCurve::Reinhard));
        assert!(
            filmic_levels > reinhard_levels + 20,
            "{filmic_levels} vs {reinhard_levels}"
        );
        // Exposure multiplies the radiance before the curve.
        for v in [Vec3::new(0.3, 0.1, 0.02), Vec3::new(6.0, 2.5, 0.4)] {
            for e in [0.25f32, 1.0, 3.0] {
                let scaled = tonemap_with(v * e, 1.0, ToneCurve::Filmic);
                assert_eq!(tonemap_with(v, e, ToneCurve::Filmic), scaled);
            }
        }
        // Negative radiance is black; the old entry point is Reinhard.
        assert_eq!(
            tonemap_with(Vec3::splat(-2.0), 1.0, ToneCurve::Filmic),
            [0; 3]
        );
        assert_eq!(
            tonemap(Vec3::splat(0.7), 1.3),
            tonemap_with(Vec3::splat(0.7), 1.3, ToneCurve::Reinhard)
        );
    }
}
