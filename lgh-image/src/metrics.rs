//! Image comparisons on luminance (ARCHITECTURE.md, "Measuring"): relative RMSE and absolute
//! errors ([`compare`]), the same channel by channel with the ratio of the channels' means
//! ([`compare_rgb`]: a colour off in one channel hides in the luminance), the flicker of a sequence ([`flicker`]), the error an 8-bit display
//! shows (Paquette et al. §5.1, [`error_8bit`]) and a false-colour map of the error
//! ([`difference_png`]).

use std::path::Path;

use lgh_core::glam::Vec3;
use lgh_core::luminance;
use lgh_core::metrics::ErrorStats;

use crate::error::ImageError;
use crate::image::Image;
use crate::png_file::write_png_rgb8;

/// Compares `a` against the reference `r` on luminance (ARCHITECTURE.md, "Measuring": relative RMSE,
/// max and mean absolute error). `None` if their sizes differ or they are empty.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{compare, Image};
///
/// let mut r = Image::new(2, 2);
/// r.pixels.fill(Vec3::ONE);
/// let mut a = r.clone();
/// a.set(1, 0, Vec3::splat(3.0));
/// // One pixel of four off by 2: RMSE sqrt(4 / 4) = 1 over a mean of 1.
/// let s = compare(&a, &r).unwrap();
/// assert!((s.rel_rmse - 1.0).abs() < 1e-6);
/// assert!((s.max_abs - 2.0).abs() < 1e-6 && (s.mean_abs - 0.5).abs() < 1e-6);
/// assert!(compare(&a, &Image::new(4, 1)).is_none());
/// ```
#[must_use]
pub fn compare(a: &Image, r: &Image) -> Option<ErrorStats> {
    if (a.width, a.height) != (r.width, r.height) {
        return None;
    }
    ErrorStats::compare(&a.pixels, &r.pixels)
}

/// An image against a reference channel by channel ([`compare_rgb`]): red, green and blue each
/// compared on its own, where luminance would hide a colour off in one channel (a fire's blue
/// 10% high moves its luminance by under 1%).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelStats {
    /// Each channel's RMSE over the reference's mean of that channel; `None` for a channel
    /// whose reference mean is not above 0.
    pub rel_rmse: [Option<f64>; 3],
    /// Each channel's mean over the reference's mean of it; `None` as above.
    pub mean_ratio: [Option<f64>; 3],
    /// The image's mean of each channel.
    pub mean: [f64; 3],
    /// The reference's mean of each channel (a channel's mean may be negative: Cycles' cool
    /// flames take blue from an image).
    pub mean_reference: [f64; 3],
}

/// Compares `a` against the reference `r` channel by channel ([`ChannelStats`]). `None` if
/// their sizes differ or they are empty.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{compare_rgb, Image};
///
/// let mut r = Image::new(2, 1);
/// r.pixels.fill(Vec3::new(1.0, 0.5, 0.0));
/// let mut a = r.clone();
/// a.pixels[0].z = 0.1; // blue where the reference has none
/// a.pixels[1].y = 0.6;
/// let s = compare_rgb(&a, &r).unwrap();
/// assert_eq!(s.mean_ratio[0], Some(1.0));
/// assert!((s.mean_ratio[1].unwrap() - 1.1).abs() < 1e-6); // mean 0.55 against 0.5
/// // One pixel of two off by 0.1: RMSE √(0.01 / 2) over a mean of 0.5.
/// assert!((s.rel_rmse[1].unwrap() - 0.005f64.sqrt() / 0.5).abs() < 1e-6);
/// assert_eq!((s.rel_rmse[2], s.mean_ratio[2]), (None, None)); // a black channel
/// ```
#[must_use]
pub fn compare_rgb(a: &Image, r: &Image) -> Option<ChannelStats> {
    if (a.width, a.height) != (r.width, r.height) || r.pixels.is_empty() {
        return None;
    }
    let mut out = ChannelStats {
        rel_rmse: [None; 3],
        mean_ratio: [None; 3],
        mean: [0.0; 3],
        mean_reference: [0.0; 3],
    };
    let n = r.pixels.len() as f64;
    for c in 0..3 {
        let channel =
            |i: &Image| -> Vec<f64> { i.pixels.iter().map(|p| f64::from(p[c])).collect() };
        let (ca, cr) = (channel(a), channel(r));
        let stats = ErrorStats::compare_luminance(ca.iter().copied(), cr.iter().copied())?;
        let mean = stats.mean_reference;
        out.mean_reference[c] = mean;
        out.mean[c] = ca.iter().sum::<f64>() / n;
        if mean > 0.0 {
            out.rel_rmse[c] = Some(stats.rel_rmse);
            out.mean_ratio[c] = Some(out.mean[c] / mean);
        }
    }
    Some(out)
}

/// Per-pixel errors of an image against a reference ([`point_errors`]), over the pixels the
/// reference lights: each pixel's luminance difference over the reference's luminance, held at
/// 1% of the reference's mean at least (so that a near-black pixel's error is not divided by
/// nearly nothing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointErrors {
    /// The largest.
    pub max: f64,
    /// The 99th percentile: the smallest bound that at most 1% of the pixels exceed.
    pub p99: f64,
    /// The fraction of the pixels over the bound asked for.
    pub over: f64,
}

/// The [`PointErrors`] of `a` against the reference `r`, `over` counted against `bound`
/// (0.1: 10%). `None` if their sizes differ; all zero if `r` lights no pixel.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{point_errors, Image};
///
/// let mut r = Image::new(4, 1);
/// r.pixels.fill(Vec3::ONE);
/// let mut a = r.clone();
/// a.set(0, 0, Vec3::splat(1.2));
/// // One pixel of four 20% off, the others exact.
/// let e = point_errors(&a, &r, 0.1).unwrap();
/// assert!((e.max - 0.2).abs() < 1e-6 && (e.over - 0.25).abs() < 1e-12);
/// // A near-black pixel is held to 1% of the mean (0.0075): 0.0005 against 0.0001 errs by
/// // 0.0004 / 0.0075 = 5%, not 400%.
/// r.set(3, 0, Vec3::splat(1e-4));
/// a.set(3, 0, Vec3::splat(5e-4));
/// let e = point_errors(&a, &r, 0.1).unwrap();
/// assert!((e.over - 0.25).abs() < 1e-12);
/// assert!(point_errors(&a, &Image::new(2, 2), 0.1).is_none());
/// ```
#[must_use]
pub fn point_errors(a: &Image, r: &Image, bound: f64) -> Option<PointErrors> {
    if (a.width, a.height) != (r.width, r.height) {
        return None;
    }
    let lum = |p: Vec3| f64::from(luminance(p));
    let lit: Vec<(f64, f64)> = a
        .pixels
        .iter()
        .zip(&r.pixels)
        .map(|(&a, &b)| (lum(a), lum(b)))
        .filter(|&(_, b)| b > 0.0)
        .collect();
    if lit.is_empty() {
        return Some(PointErrors {
            max: 0.0,
            p99: 0.0,
            over: 0.0,
        });
    }
    let mean = lit.iter().map(|p| p.1).sum::<f64>() / lit.len() as f64;
    let mut errors: Vec<f64> = lit
        .iter()
        .map(|&(a, b)| (a - b).abs() / b.max(0.01 * mean))
        .collect();
    errors.sort_by(f64::total_cmp);
    let n = errors.len();
    // The smallest error with at most 1% of the pixels above it.
    let p99 = errors[n - 1 - n / 100];
    Some(PointErrors {
        max: errors[n - 1],
        p99,
        over: errors.iter().filter(|&&e| e > bound).count() as f64 / n as f64,
    })
}

/// Temporal flicker of the sequence `a` against the reference sequence `r` (ARCHITECTURE.md,
/// "Measuring"): `mean_t mean_px |(A_t − R_t) − (A_{t−1} − R_{t−1})| / mean |R|` on luminance,
/// the change of the error from one frame to the next, so a constant bias does not flicker.
/// `None` with fewer than two frames, sequences or frames of different sizes, or a black
/// reference.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{flicker, Image};
///
/// let frame = |v: f32| Image { width: 2, height: 1, pixels: vec![Vec3::splat(v); 2] };
/// let r = [frame(1.0), frame(1.0), frame(1.0)];
/// // A constant bias: no flicker.
/// assert_eq!(flicker(&[frame(1.5), frame(1.5), frame(1.5)], &r), Some(0.0));
/// // An error that alternates by ±0.5: it changes by 1 every frame, over a mean of 1.
/// let f = flicker(&[frame(1.5), frame(0.5), frame(1.5)], &r).unwrap();
/// assert!((f - 1.0).abs() < 1e-6);
/// assert_eq!(flicker(&r[..1], &r[..1]), None);
/// ```
#[must_use]
pub fn flicker(a: &[Image], r: &[Image]) -> Option<f64> {
    let same = |x: &Image, y: &Image| (x.width, x.height) == (y.width, y.height);
    if a.len() != r.len() || a.len() < 2 || a.iter().chain(r).any(|i| !same(i, &r[0])) {
        return None;
    }
    let lum = |p: Vec3| f64::from(lgh_core::luminance(p));
    let pixels = r[0].pixels.len();
    let mean_r = r
        .iter()
        .flat_map(|i| i.pixels.iter())
        .map(|&p| lum(p).abs())
        .sum::<f64>()
        / (pixels * r.len()) as f64;
    if mean_r.is_nan() || mean_r <= 0.0 || pixels == 0 {
        return None;
    }
    let mut sum = 0.0;
    for t in 1..a.len() {
        let s: f64 = (0..pixels)
            .map(|i| {
                let e1 = lum(a[t].pixels[i]) - lum(r[t].pixels[i]);
                let e0 = lum(a[t - 1].pixels[i]) - lum(r[t - 1].pixels[i]);
                (e1 - e0).abs()
            })
            .sum();
        sum += s / pixels as f64;
    }
    Some(sum / (a.len() - 1) as f64 / mean_r)
}

/// The error of an image as an 8-bit display would show it (Paquette et al. §5.1): every channel
/// quantised linearly, `round(255 · clamp(v, 0, 1))`, no gamma — the scale on which their
/// threshold of 2.55 and their observed errors of (1, 1, 1) are stated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Error8Bit {
    /// The largest difference of any channel of any pixel, in levels of 255.
    pub max: u8,
    /// The mean difference over all channels of all pixels.
    pub mean: f64,
}

/// `v` quantised to 8 bits as [`Error8Bit`] does it.
#[must_use]
pub fn quantize_8bit(v: f32) -> u8 {
    // NaN goes to 0 (`as` saturates and maps NaN to 0).
    (255.0 * v.clamp(0.0, 1.0)).round() as u8
}

/// [`Error8Bit`] of `a` against `r`; `None` if their sizes differ or they are empty.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{error_8bit, Error8Bit, Image};
///
/// let r = Image::new(2, 1);
/// let mut a = r.clone();
/// // 2/255 in red is two levels; 10 is clamped to 1, so 255 levels in blue.
/// a.set(0, 0, Vec3::new(2.0 / 255.0, 0.0, 10.0));
/// assert_eq!(error_8bit(&a, &r), Some(Error8Bit { max: 255, mean: 257.0 / 6.0 }));
/// assert_eq!(error_8bit(&a, &Image::new(1, 2)), None);
/// ```
#[must_use]
pub fn error_8bit(a: &Image, r: &Image) -> Option<Error8Bit> {
    if (a.width, a.height) != (r.width, r.height) || a.pixels.is_empty() {
        return None;
    }
    let (mut max, mut sum) = (0u8, 0u64);
    for (p, q) in a.pixels.iter().zip(&r.pixels) {
        for c in 0..3 {
            let e = quantize_8bit(p[c]).abs_diff(quantize_8bit(q[c]));
            max = max.max(e);
            sum += u64::from(e);
        }
    }
    Some(Error8Bit {
        max,
        mean: sum as f64 / (3 * a.pixels.len()) as f64,
    })
}

/// A false-colour map of `|a − r|` on luminance: black for no error, through blue, green and
/// yellow to red at `max_error` and above. Written atomically.
///
/// Errors: [`ImageError::SizeMismatch`] if `a` and `r` differ in size, [`ImageError::EncodePng`],
/// and those of [`write_atomic`](crate::write_atomic).
pub fn difference_png(path: &Path, a: &Image, r: &Image, max_error: f32) -> Result<(), ImageError> {
    if (a.width, a.height) != (r.width, r.height) {
        return Err(ImageError::SizeMismatch {
            image: (a.width, a.height),
            reference: (r.width, r.height),
        });
    }
    let ramp = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
    ];
    let rgb: Vec<u8> = a
        .pixels
        .iter()
        .zip(&r.pixels)
        .flat_map(|(&x, &y)| {
            let e = (luminance(x) - luminance(y)).abs();
            let t = if max_error > 0.0 {
                (e / max_error).clamp(0.0, 1.0)
            } else {
                0.0
            } * 4.0;
            let i = (t as usize).min(3);
            let c = ramp[i].lerp(ramp[i + 1], t - i as f32);
            [0, 1, 2].map(|k| (c[k] * 255.0 + 0.5) as u8)
        })
        .collect();
    write_png_rgb8(path, a.width, a.height, &rgb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::gradient;

    #[test]
    fn error_8bit_quantises_linearly_and_clamps() {
        let mut a = Image::new(2, 1);
        let mut r = Image::new(2, 1);
        // 0.5 → 128 (127.5 rounds away from zero), 0.5 + 1.4/255 → 129: one level apart.
        a.set(0, 0, Vec3::new(0.5, 0.0, 2.0));
        r.set(0, 0, Vec3::new(0.5 + 1.4 / 255.0, 0.0, 7.0));
        // Below zero and NaN both count as 0; 3/255 apart → 3 levels.
        a.set(1, 0, Vec3::new(-1.0, f32::NAN, 3.0 / 255.0));
        r.set(1, 0, Vec3::new(0.0, 0.0, 0.0));
        let e = error_8bit(&a, &r).unwrap();
        assert_eq!(e.max, 3);
        assert!((e.mean - 4.0 / 6.0).abs() < 1e-12);
        assert_eq!(error_8bit(&a, &Image::new(1, 2)), None);
    }

    #[test]
    fn comparison_metrics() {
        let r = gradient();
        let mut a = r.clone();
        assert_eq!(compare(&a, &r).unwrap().rel_rmse, 0.0);
        a.pixels[5] += Vec3::ONE;
        let s = compare(&a, &r).unwrap();
        assert!((s.max_abs - 1.0).abs() < 1e-6);
        assert!(compare(&Image::new(3, 3), &r).is_none());
        let dir = tempfile::tempdir().unwrap();
        difference_png(&dir.path().join("d.png"), &a, &r, 1.0).unwrap();
    }
}
