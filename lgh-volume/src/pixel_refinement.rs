//! Adaptive pixel refinement ([`PixelRefinement::Adaptive`]): which pixels of an image first
//! sampled `n × n` rays a pixel take `2n × 2n` — those where neighbouring rays differ.
//!
//! A pixel is the box filter's integral of the radiance over it, taken by the midpoint rule
//! ([`MarchSettings::pixel_samples`](crate::render::MarchSettings::pixel_samples)). Where the
//! radiance is smooth over the pixel, a few rays have it; where a thin flame crosses it, the
//! few rays miss or over-count the flame and the pixel errs by about the flame's contrast. The
//! contrast is seen between neighbouring rays: on the image's grid of first rays (`n` times
//! finer than its pixels), two neighbours that differ by more than the tolerance refine the
//! pixels they lie in, on either side of a pixel's border too. The decision reads only the
//! first rays, so it is the same on any thread count, and a refined pixel is exactly the pixel
//! of the finer filter.
//!
//! [`PixelRefinement::Adaptive`]: crate::render::PixelRefinement::Adaptive

use lgh_core::glam::Vec3;
use lgh_core::luminance;

/// The pixels `[x, y]` (in row order) of a `width × height` image whose first rays say they
/// need more: `first` holds every pixel's `n × n` rays' radiance, pixel after pixel in row
/// order, each pixel's rays row after row. A pixel is refined when one of its rays and a
/// neighbouring ray (left, right, above or below on the grid of rays, in the pixel or the
/// next) differ in luminance by more than `tolerance` times the mean luminance of all the
/// rays; none is when that mean is not above zero.
///
/// ```
/// use lgh_volume::lgh_core::glam::Vec3;
/// use lgh_volume::render::pixels_to_refine;
///
/// // A 3 × 1 image, one ray a pixel: a bright middle pixel refines itself and both neighbours
/// // (each differs from it); a dark image refines nothing.
/// let first = [Vec3::ZERO, Vec3::ONE, Vec3::ZERO];
/// assert_eq!(pixels_to_refine(&first, 3, 1, 1, 0.5), vec![[0, 0], [1, 0], [2, 0]]);
/// assert!(pixels_to_refine(&[Vec3::ZERO; 3], 3, 1, 1, 0.5).is_empty());
/// // Two rays a side: the flame in the left half of pixel 0 refines it alone.
/// let mut first = [Vec3::ZERO; 8];
/// first[0] = Vec3::ONE;
/// first[2] = Vec3::ONE;
/// assert_eq!(pixels_to_refine(&first, 2, 1, 2, 0.5), vec![[0, 0]]);
/// ```
#[must_use]
pub fn pixels_to_refine(
    first: &[Vec3],
    width: usize,
    height: usize,
    n: usize,
    tolerance: f32,
) -> Vec<[usize; 2]> {
    let (fw, fh) = (width * n, height * n);
    assert_eq!(first.len(), fw * fh, "n × n rays for each pixel");
    // The ray at (fx, fy) of the grid of rays: its pixel, then its place in the pixel.
    let ray = |fx: usize, fy: usize| {
        let pixel = (fy / n) * width + fx / n;
        pixel * n * n + (fy % n) * n + fx % n
    };
    let lum: Vec<f32> = first.iter().map(|&r| luminance(r)).collect();
    let mean = lum.iter().map(|&l| f64::from(l)).sum::<f64>() / lum.len().max(1) as f64;
    if mean.is_nan() || mean <= 0.0 {
        return Vec::new();
    }
    let limit = f64::from(tolerance) * mean;
    let mut refine = vec![false; width * height];
    let mut differ = |a: (usize, usize), b: (usize, usize)| {
        let d = f64::from(lum[ray(a.0, a.1)]) - f64::from(lum[ray(b.0, b.1)]);
        if d.abs() > limit {
            refine[(a.1 / n) * width + a.0 / n] = true;
            refine[(b.1 / n) * width + b.0 / n] = true;
        }
    };
    for fy in 0..fh {
        for fx in 0..fw {
            if fx + 1 < fw {
                differ((fx, fy), (fx + 1, fy));
            }
            if fy + 1 < fh {
                differ((fx, fy), (fx, fy + 1));
            }
        }
    }
    (0..width * height)
        .filter(|&p| refine[p])
        .map(|p| [p % width, p / width])
        .collect()
}
