//! Prefiltered density for the shadows of volume lights (paper Sec. 4, eq. 6).
//!
//! A coarse light `i ∈ S_ℓ` stands for many lights of `S0` spread around its illumination centre
//! (its size `s_ℓi`, eq. 5). Treated as a point, its shadow is sharp and jumps when the centre moves
//! a little between frames — the flicker the paper warns of. Instead the paper traces its shadow
//! map through the density filtered with the pyramidal (tent) filter — the filter of the trilinear
//! splat — whose width shrinks linearly along the ray,
//!
//! `δ(d) = (1 − d/r_ℓ) s_ℓi + (d/r_ℓ) h_0` for `d ≤ r_ℓ`, the plain density beyond,
//!
//! so that near the light the smoke is blurred over the light's extent and at `r_ℓ`, where the
//! blending function peaks, it is the density itself.
//!
//! [`DensityPyramid`] precomputes the filtered density at widths `w_m = 2^m h` (level 0 is the
//! density itself: trilinear interpolation of the voxels *is* the tent of half-width `h` over
//! them). Level `m ≥ 1` holds the tent of half-width `w_m` evaluated directly from the voxels, on
//! a grid of spacing `w_m / 2` (fine enough that its own trilinear interpolation adds little), so
//! every level equals the direct convolution at its samples. A lookup at width `δ` interpolates
//! trilinearly in the point and linearly in the width between the two levels around `δ`: the
//! filtered density is continuous in both, so a light whose size changes a little between frames
//! changes its shadow a little.

use lgh_core::glam::Vec3;
use rayon::prelude::*;

use super::PaddedGrid;
use crate::grid::DenseGrid;

/// The density filtered at widths `h, 2h, 4h, …` (see the module docs).
#[derive(Clone, Debug)]
pub struct DensityPyramid {
    /// Level `m` has tent half-width `2^m h` and sample spacing `max(2^(m−1), 1) h`; level 0 is
    /// the density. Padded for clamp-free lookups.
    levels: Vec<PaddedGrid>,
    /// Each level's (unpadded) dimensions.
    dims: Vec<[usize; 3]>,
    /// `1 / h`, `h` the voxel size.
    inv_h: f32,
}

impl DensityPyramid {
    /// The pyramid of `density` up to the first level whose width reaches `max_width` (world
    /// units), or whose grid has collapsed to a few samples along every axis.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::shadow::DensityPyramid;
    /// use lgh_volume::DenseGrid;
    ///
    /// let mut density = DenseGrid::zeros([16; 3], 0.1, Vec3::ZERO);
    /// density.data.fill(2.0);
    /// let pyramid = DensityPyramid::new(&density, 0.8);
    /// assert_eq!(pyramid.levels(), 4); // widths 0.1, 0.2, 0.4, 0.8
    /// // A constant stays constant at any width.
    /// let p = Vec3::new(0.7, 0.3, 1.1);
    /// assert!((pyramid.sample(p, 0.55) - 2.0).abs() < 1e-5);
    /// ```
    #[must_use]
    pub fn new(density: &DenseGrid, max_width: f32) -> Self {
        let h = density.voxel_size;
        let mut levels = vec![PaddedGrid::new(density)];
        let mut dims = vec![density.dims];
        // Level m (width 2^m h) is added while level m − 1 is narrower than asked for and has
        // not collapsed to a few samples along every axis.
        for m in 1..24u32 {
            let collapsed = dims.last().is_some_and(|d| d.iter().all(|&n| n <= 2));
            if collapsed || h * (1u64 << (m - 1)) as f32 >= max_width {
                break;
            }
            let width = 1usize << m;
            let level = tent_filtered(density, width, width / 2);
            dims.push(level.dims);
            levels.push(PaddedGrid::new(&level));
        }
        DensityPyramid {
            levels,
            dims,
            inv_h: 1.0 / h,
        }
    }

    /// The pyramid the lights of `hierarchy` need: up to the widest light's size `s_ℓi` (the
    /// widest filter of eq. 6) for coarse lights as volumes, the density alone for points.
    #[must_use]
    pub fn for_hierarchy(
        density: &DenseGrid,
        hierarchy: &lgh_core::LightingGridHierarchy,
        coarse: super::CoarseShadows,
    ) -> Self {
        let widest = if coarse == super::CoarseShadows::Volumes {
            (0..=hierarchy.max_level())
                .flat_map(|l| hierarchy.level(l).iter().map(|g| g.size))
                .fold(0.0f32, f32::max)
        } else {
            0.0
        };
        DensityPyramid::new(density, widest)
    }

    /// Number of levels (level 0 is the density itself).
    #[must_use]
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// Samples per axis of level `m` (the density's for level 0).
    #[must_use]
    pub fn dims(&self, m: usize) -> Option<[usize; 3]> {
        self.dims.get(m).copied()
    }

    /// The value of level `m` (tent of half-width `2^m h`) at `p`.
    #[inline(always)]
    fn at(&self, m: usize, p: Vec3) -> f32 {
        let g = &self.levels[m];
        g.sample(g.local(p))
    }

    /// The density filtered with the tent of half-width `width` (world units) at `p`, for `p`
    /// inside the density's box: the plain (trilinear) density for `width ≤ h`, linear in the
    /// width between the levels around it, the top level's beyond it.
    #[inline]
    #[must_use]
    pub fn sample(&self, p: Vec3, width: f32) -> f32 {
        match self.mix(width) {
            Mix::One(m) => self.at(m, p),
            Mix::Two(m, t) => {
                let a = self.at(m, p);
                a + (self.at(m + 1, p) - a) * t
            }
        }
    }

    /// [`sample`](Self::sample) from the one level whose width is nearer `width` (in linear
    /// scale: level `m` below `1.5 · 2^m h`): one lookup instead of two, the filter's width
    /// rounded to a power of two of the voxel's.
    #[inline]
    #[must_use]
    pub fn sample_nearest(&self, p: Vec3, width: f32) -> f32 {
        match self.mix(width) {
            Mix::One(m) => self.at(m, p),
            Mix::Two(m, t) => self.at(if t < 0.5 { m } else { m + 1 }, p),
        }
    }

    /// Which levels a lookup at `width` reads, and how much of the coarser one.
    #[inline]
    pub(super) fn mix(&self, width: f32) -> Mix {
        let ratio = width * self.inv_h;
        // A NaN width reads the plain density too.
        if ratio.is_nan() || ratio <= 1.0 {
            return Mix::One(0);
        }
        // ratio = 2^m (1 + t): m is its binary exponent, t its mantissa's fraction, both exact
        // (ratio > 1 is a normal float).
        let bits = ratio.to_bits();
        let m = ((bits >> 23) as usize).saturating_sub(127);
        let top = self.levels.len() - 1;
        if m >= top {
            return Mix::One(top);
        }
        Mix::Two(m, f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000) - 1.0)
    }

    /// Level `m`, padded (for module `avx2`).
    pub(super) fn grid(&self, m: usize) -> &PaddedGrid {
        &self.levels[m]
    }
}

/// The levels a lookup reads: one, or two with the weight of the second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Mix {
    One(usize),
    Two(usize, f32),
}

/// The tent of half-width `width` voxels over `density`'s voxels, sampled every `spacing` voxels
/// from voxel `(0, 0, 0)`'s centre, as a grid of its own (same origin). Separable: one pass per
/// axis, each renormalised by the weights inside the grid, so a constant stays constant up to the
/// grid's faces (the smoke beyond the grid is taken to continue as at its border, which for real
/// caches — empty at their borders — makes no difference).
fn tent_filtered(density: &DenseGrid, width: usize, spacing: usize) -> DenseGrid {
    let mut dims = density.dims;
    let mut data = density.data.clone();
    for axis in 0..3 {
        let (out, out_dims) = filter_axis(&data, dims, axis, width, spacing);
        data = out;
        dims = out_dims;
    }
    DenseGrid {
        dims,
        voxel_size: density.voxel_size * spacing as f32,
        origin: density.origin,
        data,
    }
}

/// One axis of [`tent_filtered`]: output sample `o` along `axis` sits at input voxel `o·spacing`
/// and is the tent-weighted mean of the input voxels within `width` of it.
fn filter_axis(
    data: &[f32],
    dims: [usize; 3],
    axis: usize,
    width: usize,
    spacing: usize,
) -> (Vec<f32>, [usize; 3]) {
    let n = dims[axis];
    // Samples from voxel 0's centre to at least the grid's far face (n − ½ voxels), so that a
    // lookup anywhere in the density's box interpolates between samples.
    let m = if n == 0 {
        0
    } else {
        (n - 1).div_ceil(spacing) + 1
    };
    let mut out_dims = dims;
    out_dims[axis] = m;
    // The tent's weights, the same for every output sample: 1 − |k|/width for |k| < width.
    let weights: Vec<f32> = (0..width).map(|k| 1.0 - k as f32 / width as f32).collect();
    let stride = [1, dims[0], dims[0] * dims[1]][axis];
    let mut out = vec![0.0f32; out_dims.iter().product()];
    // Every output sample is independent (its sum runs over its line in a fixed order), so they
    // are computed in parallel with the same bits on any thread count.
    let [ox, oy, _] = out_dims;
    out.par_iter_mut().enumerate().for_each(|(idx, value)| {
        let mut at = [idx % ox, (idx / ox) % oy, idx / (ox * oy)];
        let c = at[axis] * spacing;
        at[axis] = 0;
        let inb = at[0] + at[1] * dims[0] + at[2] * dims[0] * dims[1];
        let lo = c.saturating_sub(width - 1);
        let hi = (c + width - 1).min(n - 1);
        let (mut sum, mut wsum) = (0.0f32, 0.0f32);
        for i in lo..=hi {
            let w = weights[c.abs_diff(i)];
            sum += w * data[inb + i * stride];
            wsum += w;
        }
        *value = sum / wsum;
    });
    (out, out_dims)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of `dims` voxels of size 0.1 with value `f(i, j, k)`.
    fn grid(dims: [usize; 3], f: impl Fn(usize, usize, usize) -> f32) -> DenseGrid {
        let mut g = DenseGrid::zeros(dims, 0.1, Vec3::new(-1.0, 0.5, 2.0));
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let idx = g.index(i, j, k);
                    g.data[idx] = f(i, j, k);
                }
            }
        }
        g
    }

    /// The tent of half-width `width` voxels centred on voxel `c`, summed directly in 3-D over
    /// every voxel (renormalised by the weights inside the grid).
    fn direct(g: &DenseGrid, c: [usize; 3], width: usize) -> f64 {
        let tent = |a: usize, b: usize| (1.0 - a.abs_diff(b) as f64 / width as f64).max(0.0);
        let (mut s, mut w) = (0.0f64, 0.0f64);
        for k in 0..g.dims[2] {
            for j in 0..g.dims[1] {
                for i in 0..g.dims[0] {
                    let t = tent(i, c[0]) * tent(j, c[1]) * tent(k, c[2]);
                    s += t * f64::from(g.get(i, j, k));
                    w += t;
                }
            }
        }
        s / w
    }

    #[test]
    fn each_level_is_the_direct_tent_convolution_at_its_samples() {
        let mut rng = lgh_core::random::SplitMix64(3);
        let values: Vec<f32> = (0..19 * 13 * 11).map(|_| rng.next_f32() * 4.0).collect();
        let g = grid([19, 13, 11], |i, j, k| values[(k * 13 + j) * 19 + i]);
        let p = DensityPyramid::new(&g, 0.8);
        assert_eq!(p.levels(), 4);
        let (lo, hi) = g.bounds();
        let mut checked = 0;
        for m in 1..p.levels() {
            let spacing = (1usize << m) / 2;
            let [nx, ny, nz] = p.dims(m).unwrap();
            for k in 0..nz {
                for j in 0..ny {
                    for i in 0..nx {
                        let x = g.origin
                            + Vec3::new(i as f32, j as f32, k as f32) * 0.1 * spacing as f32;
                        if !(x.cmplt(hi).all() && x.cmpge(lo).all()) {
                            continue; // samples beyond the far face, kept for interpolation only
                        }
                        let want = direct(&g, [i * spacing, j * spacing, k * spacing], 1 << m);
                        // The lookup at the level's width and sample position returns the
                        // sample: f32 sums of at most 15 terms per axis, a few ulps of values ≤ 4.
                        let got = f64::from(p.sample(x, 0.1 * (1 << m) as f32));
                        assert!((got - want).abs() < 2e-5, "level {m} ({i},{j},{k})");
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 19 * 13 * 11, "{checked}");
    }

    #[test]
    fn a_constant_stays_constant_and_narrow_widths_are_the_plain_density() {
        let c = grid([9, 17, 6], |_, _, _| 1.75);
        let p = DensityPyramid::new(&c, 3.0);
        let (lo, hi) = c.bounds();
        let mut rng = lgh_core::random::SplitMix64(8);
        for _ in 0..500 {
            let x = rng.next_in(lo, hi);
            let w = rng.next_f32() * 4.0;
            assert!((p.sample(x, w) - 1.75).abs() < 1e-5);
        }
        let mut r2 = lgh_core::random::SplitMix64(9);
        let v = grid([9, 17, 6], |i, j, k| ((i * 3 + j * 5 + k * 7) % 4) as f32);
        let q = DensityPyramid::new(&v, 1.0);
        for _ in 0..500 {
            let x = r2.next_in(lo, hi);
            let w = r2.next_f32() * 0.1;
            // The same trilinear interpolation, up to the rounding of its weights (values ≤ 3).
            let want = v.sample_voxel((x - v.origin) / v.voxel_size);
            assert!((q.sample(x, w) - want).abs() < 4e-6, "{x} {w}");
        }
    }

    #[test]
    fn the_lookup_is_continuous_in_the_width_and_between_samples_close_to_the_convolution() {
        // A smooth field: between the levels' samples and widths the lookup is within the
        // linear-interpolation error of the exact convolution. Per axis f = a·sin(k·x + φ): a
        // level's values are a tent-filtered sinusoid of amplitude ≤ a, whose trilinear
        // interpolation at spacing s errs by ≤ s²k²a/8; the tent of width w scales it by about
        // sinc²(kw/2) ≈ 1 − k²w²/12, whose second derivative in w is ≈ k²/6, so interpolating
        // linearly between widths Δw apart errs by ≤ Δw²k²a/48. Spacings up to 2 voxels and
        // width steps up to 2 (widths 1 to 4), k = 0.3, amplitudes 1 + 1 + 0.5:
        let k = 0.3f32;
        let tolerance = 2.5 * (4.0 * k * k / 8.0 + 4.0 * k * k / 48.0);
        let f = |i: usize, j: usize, l: usize| {
            (k * i as f32).sin() + (k * j as f32).cos() + 0.5 * (k * l as f32).sin() + 3.0
        };
        let g = grid([40, 40, 40], f);
        let p = DensityPyramid::new(&g, 0.4);
        // The exact tent-filtered value of the separable field at voxel coordinates u, width w
        // (voxels): the discrete tent of the sampled sinusoids, summed directly.
        let conv = |u: Vec3, w: f32| {
            let axis = |x: f32, g: &dyn Fn(f32) -> f32| {
                let (mut s, mut ws) = (0.0f32, 0.0f32);
                for n in (x - w).floor() as i32..=(x + w).ceil() as i32 {
                    let t = (1.0 - (n as f32 - x).abs() / w).max(0.0);
                    s += t * g(n as f32);
                    ws += t;
                }
                s / ws
            };
            axis(u.x, &|n| (k * n).sin())
                + axis(u.y, &|n| (k * n).cos())
                + 0.5 * axis(u.z, &|n| (k * n).sin())
                + 3.0
        };
        let mut rng = lgh_core::random::SplitMix64(1);
        let mut worst = 0.0f32;
        for step in 0..400 {
            // Interior points (away from the renormalised faces), widths 1 to 4 voxels.
            let u = rng.next_in(Vec3::splat(10.0), Vec3::splat(30.0));
            let w = 1.0 + 3.0 * (step as f32 / 400.0);
            let got = p.sample(g.origin + u * g.voxel_size, w * g.voxel_size);
            worst = worst.max((got - conv(u, w)).abs());
            // Continuity in the width: a change of 10⁻³ voxel changes the value by at most the
            // steepest slope between levels (≤ 2.5 per voxel of width) times it.
            let near = p.sample(g.origin + u * g.voxel_size, (w + 1e-3) * g.voxel_size);
            assert!((near - got).abs() < 2.5e-3 + 1e-5, "w {w}: {got} vs {near}");
        }
        assert!(worst < tolerance, "{worst} ≥ {tolerance}");
    }
}
