//! Shadow rays eight abreast on x86-64 CPUs with AVX2: each lane marches one ray with exactly the
//! operations of [`ShadowGrid::march`] (no fused multiply-adds), so the results are the same bit
//! for bit; the eight neighbours of each lane's sample come in through gathered loads, which the
//! one-by-one march spends most of its instructions addressing.
//!
//! This and its cube-map counterpart, `deep::avx2`, are the crate's only `unsafe` code: the
//! gathers read through a raw pointer, and a function compiled for AVX2 may only run on a CPU
//! that has it. Both are guarded here: the CPU is checked (once, cached by `std`) before every
//! batch, and every gathered index is clamped into the grid whatever the ray, so a wrong
//! position can give a wrong density but never a read outside it.
#![allow(unsafe_code)]

use core::arch::x86_64::*;

use lgh_core::glam::Vec3;

use super::{transmittance, PaddedGrid, Ray, ShadowGrid, ROUND};

/// Rays marched together, one per lane of a 256-bit register.
pub(super) const LANES: usize = 8;

/// [`ShadowGrid::transmittances`] with AVX2, or `None` when this CPU lacks it or the grid is too
/// large for 32-bit gather offsets (`out` must be as long as `lights`).
pub(super) fn transmittances(
    grid: &ShadowGrid,
    x: Vec3,
    lights: &[Vec3],
    out: &mut [f32],
) -> Option<u64> {
    let fits =
        i32::try_from(grid.grid.data.len()).is_ok() && grid.grid.data.len() >= grid.grid.span;
    if !fits || !std::arch::is_x86_feature_detected!("avx2") || out.len() != lights.len() {
        return None;
    }
    // SAFETY: the CPU supports AVX2, checked just above.
    Some(unsafe { batches(grid, x, lights, out) })
}

/// Marches the rays eight at a time. Where the shading point and eight consecutive lights are all
/// inside the box (the usual case) the rays are also set up eight abreast; other rays are set up
/// one by one ([`ShadowGrid::ray`]) and gathered into eights; the last few go one by one.
#[target_feature(enable = "avx2")]
fn batches(grid: &ShadowGrid, x: Vec3, lights: &[Vec3], out: &mut [f32]) -> u64 {
    let mut samples = 0u64;
    let mut group = [(0usize, Ray::default()); LANES];
    let mut k = 0;
    let x_inside = grid.inside(x);
    for (c, chunk) in lights.chunks(LANES).enumerate() {
        let first = c * LANES;
        if let (true, Ok(chunk)) = (x_inside, <&[Vec3; LANES]>::try_from(chunk)) {
            if let Some(rays) = setup(grid, x, chunk) {
                samples += march8(grid, &rays, core::array::from_fn(|l| first + l), out);
                continue;
            }
        }
        for (j, &l) in chunk.iter().enumerate() {
            let Some(ray) = grid.ray(x, l) else {
                out[first + j] = 1.0;
                continue;
            };
            {
                group[k] = (first + j, ray);
                k += 1;
                if k == LANES {
                    let rays = Rays::gather(&group);
                    samples += march8(grid, &rays, group.map(|(i, _)| i), out);
                    k = 0;
                }
            }
        }
    }
    for (i, ray) in &group[..k] {
        let (t, n) = grid.march(ray);
        out[*i] = t;
        samples += u64::from(n);
    }
    samples
}

/// Eight rays set up for marching, a lane each: [`Ray`]'s fields as vectors.
struct Rays {
    p0: [__m256; 3],
    dp: [__m256; 3],
    n: __m256,
    kappa: __m256,
    max_sum: __m256,
}

impl Rays {
    /// Eight rays set up one by one.
    #[target_feature(enable = "avx2")]
    fn gather(rays: &[(usize, Ray); LANES]) -> Rays {
        Rays {
            p0: [
                lanes(rays, |r| r.p0.x),
                lanes(rays, |r| r.p0.y),
                lanes(rays, |r| r.p0.z),
            ],
            dp: [
                lanes(rays, |r| r.dp.x),
                lanes(rays, |r| r.dp.y),
                lanes(rays, |r| r.dp.z),
            ],
            // Sample counts are far below 2^24 (a box of at most 2^15 voxels a side, steps
            // ≥ 0.01 voxel), so they are exact as floats.
            n: lanes(rays, |r| r.n as f32),
            kappa: lanes(rays, |r| r.kappa),
            max_sum: lanes(rays, |r| r.max_sum),
        }
    }
}

/// [`ShadowGrid::ray`] from `x` (inside the box) to eight lights, eight abreast, with the same
/// operations in the same order; `None` unless every light is inside the box and at a distance
/// from `x`, the rays that need no clipping.
#[target_feature(enable = "avx2")]
fn setup(grid: &ShadowGrid, x: Vec3, lights: &[Vec3; LANES]) -> Option<Rays> {
    let axis = |a: usize| from_array(lights.map(|l| l[a]));
    let b = [axis(0), axis(1), axis(2)];
    let mut inside = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    for (a, &b) in b.iter().enumerate() {
        let lo = _mm256_cmp_ps::<_CMP_GE_OQ>(b, _mm256_set1_ps(grid.lo[a]));
        let hi = _mm256_cmp_ps::<_CMP_LE_OQ>(b, _mm256_set1_ps(grid.hi[a]));
        inside = _mm256_and_ps(inside, _mm256_and_ps(lo, hi));
    }
    if _mm256_movemask_ps(inside) != 0xff {
        return None;
    }
    let pa = (x - grid.grid.origin) * grid.grid.inv_voxel_size;
    let inv_voxel = _mm256_set1_ps(grid.grid.inv_voxel_size);
    let seg =
        [0, 1, 2].map(|a| _mm256_mul_ps(_mm256_sub_ps(b[a], _mm256_set1_ps(x[a])), inv_voxel));
    // glam's Vec3A::length: (x² + y²) + z², then the square root.
    let square = |v: __m256| _mm256_mul_ps(v, v);
    let len = _mm256_sqrt_ps(_mm256_add_ps(
        _mm256_add_ps(square(seg[0]), square(seg[1])),
        square(seg[2]),
    ));
    if _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(len, _mm256_setzero_ps())) != 0xff {
        return None;
    }
    let q = _mm256_mul_ps(len, _mm256_set1_ps(grid.inv_step_voxels));
    let n = _mm256_max_ps(
        _mm256_round_ps::<{ _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC }>(q),
        _mm256_set1_ps(1.0),
    );
    let inv_n = _mm256_div_ps(_mm256_set1_ps(1.0), n);
    let dp = seg.map(|s| _mm256_mul_ps(s, inv_n));
    let kappa = _mm256_mul_ps(_mm256_set1_ps(grid.kappa_voxel), _mm256_div_ps(len, n));
    let half = _mm256_set1_ps(0.5);
    Some(Rays {
        p0: [0, 1, 2].map(|a| _mm256_add_ps(_mm256_set1_ps(pa[a]), _mm256_mul_ps(half, dp[a]))),
        dp,
        n,
        kappa,
        max_sum: _mm256_div_ps(_mm256_set1_ps(grid.max_tau), kappa),
    })
}

/// One value of each ray, a lane each.
#[inline]
#[target_feature(enable = "avx2")]
fn lanes(rays: &[(usize, Ray); LANES], f: impl Fn(&Ray) -> f32) -> __m256 {
    from_array(rays.map(|(_, r)| f(&r)))
}

/// A vector of eight values, the first in lane 0.
#[inline]
#[target_feature(enable = "avx2")]
pub(super) fn from_array(v: [f32; LANES]) -> __m256 {
    _mm256_setr_ps(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7])
}

/// A vector's lanes.
#[inline]
#[target_feature(enable = "avx2")]
pub(super) fn to_array(v: __m256) -> [f32; LANES] {
    let mut a = [0.0f32; LANES];
    // SAFETY: `a` holds eight floats.
    unsafe { _mm256_storeu_ps(a.as_mut_ptr(), v) };
    a
}

/// `a + (b − a)·t`, as [`crate::grid::trilinear`] computes it.
#[inline]
#[target_feature(enable = "avx2")]
pub(super) fn lerp(a: __m256, b: __m256, t: __m256) -> __m256 {
    _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), t))
}

/// `floor(p)` as an integer and `p − floor(p)`, as [`ShadowGrid::sample`] computes them.
#[inline]
#[target_feature(enable = "avx2")]
fn floor(p: __m256) -> (__m256i, __m256) {
    let round = _mm256_set1_ps(ROUND);
    let r = _mm256_add_ps(_mm256_sub_ps(p, _mm256_set1_ps(0.5)), round);
    let w = _mm256_sub_ps(p, _mm256_sub_ps(r, round));
    let i = _mm256_sub_epi32(
        _mm256_castps_si256(r),
        _mm256_set1_epi32(ROUND.to_bits() as i32),
    );
    (i, w)
}

/// Index of voxel `(i, j, k)` in a grid of `nx × ny × …` voxels, clamped into `0..=max_base`
/// (wrapping in between), so whatever the voxel, reads from there up to `max_base` on stay put.
#[inline]
#[target_feature(enable = "avx2")]
fn clamped_base([i, j, k]: [__m256i; 3], nx: __m256i, ny: __m256i, max_base: __m256i) -> __m256i {
    let base = _mm256_add_epi32(
        _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(k, ny), j), nx),
        i,
    );
    _mm256_min_epi32(_mm256_max_epi32(base, _mm256_setzero_si256()), max_base)
}

/// What gathering trilinear samples of a [`PaddedGrid`] eight at a time needs.
pub(super) struct Gathers {
    /// The eight neighbours' offsets from a sample's base voxel, in `trilinear`'s order.
    offsets: [usize; 8],
    /// Bases from 0 to len − span keep every neighbour inside the grid.
    max_base: __m256i,
    nx: __m256i,
    ny: __m256i,
    data: *const f32,
}

impl Gathers {
    /// For `grid`, which must hold `span ≤ len < 2^31` values (checked by the callers).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn new(grid: &PaddedGrid) -> Self {
        let [nx, ny, _] = grid.dims;
        let (dj, dk) = (nx, nx * ny);
        Gathers {
            offsets: [0, 1, dj, dj + 1, dk, dk + 1, dk + dj, dk + dj + 1],
            max_base: _mm256_set1_epi32((grid.data.len() - grid.span) as i32),
            nx: _mm256_set1_epi32(nx as i32),
            ny: _mm256_set1_epi32(ny as i32),
            data: grid.data.as_ptr(),
        }
    }

    /// [`PaddedGrid::sample`] of eight points in padded voxel units, bit for bit (points outside
    /// the padded box read clamped garbage rather than nothing: mask them).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn sample(&self, [px, py, pz]: [__m256; 3]) -> __m256 {
        let (ix, wx) = floor(px);
        let (iy, wy) = floor(py);
        let (iz, wz) = floor(pz);
        let base = clamped_base([ix, iy, iz], self.nx, self.ny, self.max_base);
        // SAFETY: every base is in 0..=len − span and every offset below span, so each gathered
        // element is inside the grid's data, whose pointer this is.
        let c = self
            .offsets
            .map(|o| unsafe { _mm256_i32gather_ps::<4>(self.data.add(o), base) });
        let x00 = lerp(c[0], c[1], wx);
        let x10 = lerp(c[2], c[3], wx);
        let x01 = lerp(c[4], c[5], wx);
        let x11 = lerp(c[6], c[7], wx);
        lerp(lerp(x00, x10, wy), lerp(x01, x11, wy), wz)
    }
}

/// [`ShadowGrid::march`] of eight rays; writes ray `l`'s transmittance to `out[index[l]]` and
/// returns the samples taken.
#[target_feature(enable = "avx2")]
fn march8(grid: &ShadowGrid, rays: &Rays, index: [usize; LANES], out: &mut [f32]) -> u64 {
    let ([px, py, pz], [dx, dy, dz], n) = (rays.p0, rays.dp, rays.n);
    let last = _mm256_sub_ps(n, _mm256_set1_ps(1.0));
    let max_sum = rays.max_sum;
    let steps = to_array(n).into_iter().fold(0.0f32, f32::max) as u32;

    let g = Gathers::new(&grid.grid);
    let mut sum = _mm256_setzero_ps();
    let mut active = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    let mut hidden = _mm256_setzero_ps();
    let mut samples = 0u64;
    for i in 0..steps {
        // A lane past its end re-reads its last sample, masked out of the sum.
        let t = _mm256_min_ps(_mm256_set1_ps(i as f32), last);
        let density = g.sample([
            _mm256_add_ps(px, _mm256_mul_ps(dx, t)),
            _mm256_add_ps(py, _mm256_mul_ps(dy, t)),
            _mm256_add_ps(pz, _mm256_mul_ps(dz, t)),
        ]);
        sum = _mm256_blendv_ps(sum, _mm256_add_ps(sum, density), active);
        samples += u64::from((_mm256_movemask_ps(active) as u32).count_ones());
        let over = _mm256_and_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(sum, max_sum), active);
        hidden = _mm256_or_ps(hidden, over);
        let more = _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_set1_ps((i + 1) as f32), n);
        active = _mm256_andnot_ps(over, _mm256_and_ps(active, more));
        if _mm256_movemask_ps(active) == 0 {
            break;
        }
    }
    let (sums, kappa) = (to_array(sum), to_array(rays.kappa));
    let hidden = _mm256_movemask_ps(hidden);
    for (l, &i) in index.iter().enumerate() {
        out[i] = if hidden & (1 << l) != 0 {
            0.0
        } else {
            transmittance(kappa[l], sums[l])
        };
    }
    samples
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_anywhere_read_inside_the_grid() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        // SAFETY: the CPU has AVX2, checked above.
        unsafe { check_clamped_bases() }
    }

    /// Coordinates no ray setup makes (billions of voxels away, infinite, not a number) give
    /// bases in `0..=max_base`, and so reads inside the grid.
    #[target_feature(enable = "avx2")]
    fn check_clamped_bases() {
        let wild = [
            -1e9f32,
            1e9,
            f32::NAN,
            f32::INFINITY,
            -f32::INFINITY,
            3e7,
            -0.7,
            5.5,
        ];
        let (nx, ny, max_base) = (130, 131, 130 * 131 * 132 - (130 * 131 + 132));
        let v = from_array;
        let rotate = |r: usize| core::array::from_fn(|l| wild[(l + r) % LANES]);
        for r in 0..LANES {
            let p = [v(wild), v(rotate(r)), v(rotate(3 * r + 1))];
            let base = clamped_base(
                p.map(|p| floor(p).0),
                _mm256_set1_epi32(nx),
                _mm256_set1_epi32(ny),
                _mm256_set1_epi32(max_base),
            );
            let mut got = [0i32; LANES];
            // SAFETY: `got` holds eight 32-bit integers.
            unsafe { _mm256_storeu_si256(got.as_mut_ptr().cast(), base) };
            assert!(got.iter().all(|b| (0..=max_base).contains(b)), "{got:?}");
        }
    }
}
