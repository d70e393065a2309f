//! Shadow rays eight abreast on x86-64 CPUs with AVX2: each lane marches one ray with exactly the
//! operations of [`ShadowGrid::march`] (no fused multiply-adds), so the results are the same bit
//! for bit; the eight neighbours of each lane's sample come in through gathered loads, which the
//! one-by-one march spends most of its instructions addressing.
//!
//! This is the crate's only `unsafe` code: the gathers read through a raw pointer, and a function
//! compiled for AVX2 may only run on a CPU that has it. Both are guarded here: the CPU is checked
//! (once, cached by `std`) before every batch, and every gathered index is clamped into the grid
//! whatever the ray, so a wrong position can give a wrong density but never a read outside it.
#![allow(unsafe_code)]

use core::arch::x86_64::*;

use lgh_core::glam::Vec3;

use super::deep::{CubeMaps, Depths, Fit, Tracer, INV_QUANT, MAX_DEPTHS, TAU_MAX};
use super::lookup::{Slot, EXP2, NO_MAP};
use super::prefilter::Mix;
use super::{transmittance, PaddedGrid, Ray, ShadowGrid, ROUND};

/// Rays marched together, one per lane of a 256-bit register.
const LANES: usize = 8;

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
fn from_array(v: [f32; LANES]) -> __m256 {
    _mm256_setr_ps(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7])
}

/// A vector's lanes.
#[inline]
#[target_feature(enable = "avx2")]
fn to_array(v: __m256) -> [f32; LANES] {
    let mut a = [0.0f32; LANES];
    // SAFETY: `a` holds eight floats.
    unsafe { _mm256_storeu_ps(a.as_mut_ptr(), v) };
    a
}

/// `a + (b − a)·t`, as [`crate::grid::trilinear`] computes it.
#[inline]
#[target_feature(enable = "avx2")]
fn lerp(a: __m256, b: __m256, t: __m256) -> __m256 {
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
struct Gathers {
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
    fn new(grid: &PaddedGrid) -> Self {
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
    fn sample(&self, [px, py, pz]: [__m256; 3]) -> __m256 {
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

/// [`CubeMaps::transmittances`] with AVX2, eight lights abreast: `false` (and nothing written)
/// when this CPU lacks AVX2 or the maps are too large for 32-bit gather offsets. Each lane does
/// exactly the operations of `lookup::quantised_depth` and `lookup::exp_neg`, so the results
/// are the same bit for bit; the four texels of each lane come in through gathered loads.
pub(super) fn cube_transmittances(
    maps: &CubeMaps,
    x: Vec3,
    centres: &[Vec3],
    ids: &[(u8, u32)],
    out: &mut [f32],
) -> bool {
    let (texels, depths) = (maps.texels(), maps.depths_per_texel());
    // Offsets are gathered in units of two bytes (one depth): every index must fit an i32.
    let fits = texels.len() >= 2 && texels.len() < i32::MAX as usize - 1;
    if !fits
        || !std::arch::is_x86_feature_detected!("avx2")
        || out.len() != centres.len()
        || ids.len() != centres.len()
    {
        return false;
    }
    let n = centres.len();
    let whole = n - n % LANES;
    // Groups of chunks: every chunk of a group is located and its texels' cache lines are
    // requested, then the group's texels are gathered. The lookups of a shading point read
    // lines scattered over the maps; requested together, their fetches overlap.
    const GROUP: usize = 8;
    let mut located = [None; GROUP];
    for group in (0..whole).step_by(LANES * GROUP) {
        let end = (group + LANES * GROUP).min(whole);
        for (g, first) in (group..end).step_by(LANES).enumerate() {
            let mut c = [[0.0f32; LANES]; 3];
            let mut slots = [NO_MAP; LANES];
            let mut inv_spacing = [0.0f32; LANES];
            for l in 0..LANES {
                let p = centres[first + l];
                c[0][l] = p.x;
                c[1][l] = p.y;
                c[2][l] = p.z;
                let (level, index) = ids[first + l];
                (slots[l], inv_spacing[l]) = maps.slot(level, index);
            }
            // SAFETY: the CPU supports AVX2, checked above.
            located[g] = Some(unsafe { locate8(texels, depths, x, &c, &slots, &inv_spacing) });
        }
        for (g, first) in (group..end).step_by(LANES).enumerate() {
            let at = located[g].take().expect("located above");
            // SAFETY: the CPU supports AVX2, checked above; `at` was located in `texels`.
            let v = unsafe { finish8(texels, &at) };
            out[first..first + LANES].copy_from_slice(&v);
        }
    }
    for i in whole..n {
        let (level, index) = ids[i];
        out[i] = maps.transmittance(x, level, index, centres[i]);
    }
    true
}

/// Eight lookups located: the two-byte index of each lane's first texel pair, the offsets to
/// its neighbours, the interpolation weights and which lanes are valid (see [`locate8`]).
#[derive(Clone, Copy)]
struct Located8 {
    base: __m256i,
    side4: __m256i,
    four: __m256i,
    tx: __m256,
    ty: __m256,
    f: __m256,
    k0: __m256,
    valid: __m256,
}

/// The first half of eight lookups of `lookup::quantised_depth`: where each lane's texels are,
/// lane by lane the same operations in the same order; their cache lines are requested.
#[target_feature(enable = "avx2")]
fn locate8(
    texels: &[u16],
    depths: usize,
    x: Vec3,
    c: &[[f32; LANES]; 3],
    slots: &[Slot; LANES],
    inv_spacing: &[f32; LANES],
) -> Located8 {
    let ld = |a: &[f32; LANES]| unsafe { _mm256_loadu_ps(a.as_ptr()) };
    let zero = _mm256_setzero_ps();
    let one = _mm256_set1_ps(1.0);
    let vx = _mm256_sub_ps(_mm256_set1_ps(x.x), ld(&c[0]));
    let vy = _mm256_sub_ps(_mm256_set1_ps(x.y), ld(&c[1]));
    let vz = _mm256_sub_ps(_mm256_set1_ps(x.z), ld(&c[2]));
    let d = _mm256_sqrt_ps(_mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(vx, vx), _mm256_mul_ps(vy, vy)),
        _mm256_mul_ps(vz, vz),
    ));
    let offsets: [i32; LANES] = core::array::from_fn(|l| slots[l].offset as i32);
    let cells_u: [i32; LANES] = core::array::from_fn(|l| slots[l].cells as i32);
    let has_map: [i32; LANES] = core::array::from_fn(|l| -i32::from(slots[l] != NO_MAP));
    let li = |a: &[i32; LANES]| unsafe { _mm256_loadu_si256(a.as_ptr().cast()) };
    // Valid lanes: a map, d finite and > 0 (d < ∞ and d > 0 are both false for NaN).
    let valid = _mm256_and_ps(
        _mm256_castsi256_ps(li(&has_map)),
        _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(d, zero),
            _mm256_cmp_ps::<_CMP_LT_OQ>(d, _mm256_set1_ps(f32::INFINITY)),
        ),
    );
    let abs = |v: __m256| _mm256_andnot_ps(_mm256_set1_ps(-0.0), v);
    let (ax, ay, az) = (abs(vx), abs(vy), abs(vz));
    let x_major = _mm256_and_ps(
        _mm256_cmp_ps::<_CMP_GE_OQ>(ax, ay),
        _mm256_cmp_ps::<_CMP_GE_OQ>(ax, az),
    );
    let y_major = _mm256_andnot_ps(x_major, _mm256_cmp_ps::<_CMP_GE_OQ>(ay, az));
    // blendv(a, b, m): b where m, else a. z-major by default, then y, then x.
    let pick = |xv: __m256, yv: __m256, zv: __m256| {
        _mm256_blendv_ps(_mm256_blendv_ps(zv, yv, y_major), xv, x_major)
    };
    let major = pick(vx, vy, vz);
    let u = pick(vy, vz, vx);
    let w = pick(vz, vx, vy);
    let axis = _mm256_castps_si256(pick(
        _mm256_castsi256_ps(_mm256_set1_epi32(0)),
        _mm256_castsi256_ps(_mm256_set1_epi32(1)),
        _mm256_castsi256_ps(_mm256_set1_epi32(2)),
    ));
    let negative = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(major, zero));
    // 2·axis + (major < 0): the mask is −1 where negative.
    let face = _mm256_sub_epi32(_mm256_add_epi32(axis, axis), negative);
    let inv = _mm256_div_ps(one, abs(major));
    let cells_i = li(&cells_u);
    let cells = _mm256_cvtepi32_ps(cells_i);
    let half = _mm256_mul_ps(_mm256_set1_ps(0.5), cells);
    let gx = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(u, inv), one), half);
    let gy = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(w, inv), one), half);
    let max = _mm256_sub_ps(cells, one);
    // max(0) then min(max), as the scalar code: the same result for every non-NaN g.
    let clampi = |g: __m256| _mm256_min_ps(_mm256_max_ps(g, zero), max);
    let cxi = _mm256_cvttps_epi32(clampi(gx));
    let cyi = _mm256_cvttps_epi32(clampi(gy));
    let unit = |t: __m256| _mm256_min_ps(_mm256_max_ps(t, zero), one);
    let tx = unit(_mm256_sub_ps(gx, _mm256_cvtepi32_ps(cxi)));
    let ty = unit(_mm256_sub_ps(gy, _mm256_cvtepi32_ps(cyi)));
    let side = _mm256_add_epi32(cells_i, _mm256_set1_epi32(1));
    let first = _mm256_add_epi32(
        li(&offsets),
        _mm256_add_epi32(
            _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(face, side), cyi), side),
            cxi,
        ),
    );
    let q = _mm256_min_ps(
        _mm256_mul_ps(d, ld(inv_spacing)),
        _mm256_set1_ps(depths as f32),
    );
    let k = _mm256_min_epi32(_mm256_cvttps_epi32(q), _mm256_set1_epi32(depths as i32 - 1));
    let f = unit(_mm256_sub_ps(q, _mm256_cvtepi32_ps(k)));
    let kk = _mm256_max_epi32(
        _mm256_sub_epi32(k, _mm256_set1_epi32(1)),
        _mm256_setzero_si256(),
    );
    let k0 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(k, _mm256_setzero_si256()));
    // Index of the pair (kk, kk + 1) of each corner, in two-byte units; invalid lanes read
    // texel 0 (in bounds: there are at least two texels) and are discarded below.
    let vi = _mm256_castps_si256(valid);
    let per_texel = _mm256_set1_epi32(depths as i32);
    let base = _mm256_and_si256(
        _mm256_add_epi32(_mm256_mullo_epi32(first, per_texel), kk),
        vi,
    );
    let side4 = _mm256_and_si256(_mm256_mullo_epi32(side, per_texel), vi);
    let four = _mm256_and_si256(per_texel, vi);
    // Request each lane's two texel rows (cy and cy + 1): a prefetch is a hint that never
    // faults, and every index is inside `texels` anyway.
    let mut rows = [[0i32; LANES]; 2];
    // SAFETY: `rows` holds sixteen i32.
    unsafe {
        _mm256_storeu_si256(rows[0].as_mut_ptr().cast(), base);
        _mm256_storeu_si256(rows[1].as_mut_ptr().cast(), _mm256_add_epi32(base, side4));
    }
    let bytes = texels.as_ptr().cast::<i8>();
    for &i in rows.iter().flatten() {
        _mm_prefetch::<_MM_HINT_T0>(bytes.wrapping_add(2 * i as usize));
    }
    Located8 {
        base,
        side4,
        four,
        tx,
        ty,
        f,
        k0,
        valid,
    }
}

/// The second half of eight lookups: the texels gathered and interpolated, then `exp_neg`.
#[target_feature(enable = "avx2")]
fn finish8(texels: &[u16], at: &Located8) -> [f32; LANES] {
    let Located8 {
        base,
        side4,
        four,
        tx,
        ty,
        f,
        k0,
        valid,
    } = *at;
    let zero = _mm256_setzero_ps();
    let one = _mm256_set1_ps(1.0);
    let ptr = texels.as_ptr().cast::<i32>();
    // SAFETY: every valid lane's four texels lie in its map (cx, cy ≤ R − 1, face ≤ 5), inside
    // `texels`; a 4-byte read at a two-byte index i = texel·n + kk (kk ≤ n − 2, n ≥ 2) reads
    // depths kk and kk + 1 of that texel, inside; invalid lanes read index 0 (masked to 0).
    let gather = |i: __m256i| unsafe { _mm256_i32gather_epi32::<2>(ptr, i) };
    let pair = |g: __m256i| {
        let a = _mm256_cvtepi32_ps(_mm256_and_si256(g, _mm256_set1_epi32(0xffff)));
        let b = _mm256_cvtepi32_ps(_mm256_srli_epi32::<16>(g));
        (_mm256_blendv_ps(a, zero, k0), _mm256_blendv_ps(b, a, k0))
    };
    let (l00, h00) = pair(gather(base));
    let (l10, h10) = pair(gather(_mm256_add_epi32(base, four)));
    let (l01, h01) = pair(gather(_mm256_add_epi32(base, side4)));
    let (l11, h11) = pair(gather(_mm256_add_epi32(
        _mm256_add_epi32(base, side4),
        four,
    )));
    let lerp =
        |a: __m256, b: __m256, t: __m256| _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), t));
    let lo = lerp(lerp(l00, l10, tx), lerp(l01, l11, tx), ty);
    let hi = lerp(lerp(h00, h10, tx), lerp(h01, h11, tx), ty);
    let tau = _mm256_mul_ps(lerp(lo, hi, f), _mm256_set1_ps(INV_QUANT));
    let e = exp_neg8(tau);
    let v = _mm256_blendv_ps(one, e, valid);
    let mut out = [0.0f32; LANES];
    // SAFETY: `out` holds eight floats.
    unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v) };
    out
}

/// `lookup::exp_neg` of eight values, bit for bit.
#[inline]
#[target_feature(enable = "avx2")]
fn exp_neg8(y: __m256) -> __m256 {
    let z = _mm256_mul_ps(
        _mm256_sub_ps(_mm256_setzero_ps(), y),
        _mm256_set1_ps(core::f32::consts::LOG2_E),
    );
    let n = _mm256_cvttps_epi32(z);
    let f = _mm256_sub_ps(z, _mm256_cvtepi32_ps(n));
    let mut p = _mm256_set1_ps(EXP2[5]);
    for c in [EXP2[4], EXP2[3], EXP2[2], EXP2[1], EXP2[0]] {
        p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(c));
    }
    _mm256_castsi256_ps(_mm256_add_epi32(
        _mm256_castps_si256(p),
        _mm256_slli_epi32::<23>(n),
    ))
}

/// Eight texel rays of one light (`dirs`, unit) traced abreast: `Tracer::trace` lane by lane,
/// the same operations in the same order, so the depths are the same bit for bit (the sample
/// counts may differ: lanes jump over empty space together, only where all of them can). The
/// rays share the light's step schedule, so each step's distance, filter width and pyramid
/// levels are the same for all eight; only the positions differ. `None` without AVX2 or when a
/// pyramid level is too large for 32-bit gather offsets.
pub(super) fn trace8(
    tracer: &Tracer<'_>,
    p: Vec3,
    dirs: &[Vec3; LANES],
    s: f32,
    r: f32,
    reach: f32,
) -> Option<[([f32; MAX_DEPTHS], u32); LANES]> {
    let pyramid = tracer.pyramid;
    let fits = (0..pyramid.levels()).all(|m| {
        let g = pyramid.grid(m);
        i32::try_from(g.data.len()).is_ok() && g.data.len() >= g.span
    });
    if !fits || !std::arch::is_x86_feature_detected!("avx2") {
        return None;
    }
    // SAFETY: the CPU supports AVX2, checked above; every level fits 32-bit offsets.
    Some(unsafe { trace8_avx2(tracer, p, dirs, s, r, reach) })
}

/// Eight f64 accumulators of `deep::Fit` (lanes 0–3 and 4–7).
#[derive(Clone, Copy)]
struct Acc8([__m256d; 2]);

impl Acc8 {
    #[inline]
    #[target_feature(enable = "avx2")]
    fn zero() -> Self {
        Acc8([_mm256_setzero_pd(); 2])
    }

    /// `self += (w·a)·b` lane by lane, `a` the same for every lane, `b` per lane.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn add(&mut self, w: &[__m256d; 2], a: f64, b: &[__m256d; 2]) {
        let a = _mm256_set1_pd(a);
        for ((s, w), b) in self.0.iter_mut().zip(w).zip(b) {
            *s = _mm256_add_pd(*s, _mm256_mul_pd(_mm256_mul_pd(*w, a), *b));
        }
    }

    #[inline]
    #[target_feature(enable = "avx2")]
    fn lanes(&self) -> [f64; LANES] {
        let mut out = [0.0f64; LANES];
        // SAFETY: `out` holds eight f64.
        unsafe {
            _mm256_storeu_pd(out.as_mut_ptr(), self.0[0]);
            _mm256_storeu_pd(out.as_mut_ptr().add(4), self.0[1]);
        }
        out
    }
}

/// Eight f32 lanes as two halves of f64.
#[inline]
#[target_feature(enable = "avx2")]
fn widen(v: __m256) -> [__m256d; 2] {
    [
        _mm256_cvtps_pd(_mm256_castps256_ps128(v)),
        _mm256_cvtps_pd(_mm256_extractf128_ps::<1>(v)),
    ]
}

#[target_feature(enable = "avx2")]
fn trace8_avx2(
    tracer: &Tracer<'_>,
    p: Vec3,
    dirs: &[Vec3; LANES],
    s: f32,
    r: f32,
    reach: f32,
) -> [([f32; MAX_DEPTHS], u32); LANES] {
    let depths = tracer.n;
    let spacing = reach / depths as f32;
    let p_inside = tracer.inside(p);
    let pyramid = tracer.pyramid;
    let dir = [
        from_array(dirs.map(|d| d.x)),
        from_array(dirs.map(|d| d.y)),
        from_array(dirs.map(|d| d.z)),
    ];
    let origin = [p.x, p.y, p.z].map(|c| _mm256_set1_ps(c));
    let (lo, hi) = (tracer.lo, tracer.hi);
    let fitted = tracer.depths == Depths::Fitted;
    let zero = _mm256_setzero_ps();
    let mut samples = [0u32; LANES];
    let mut tau = zero;
    let mut at = [zero; MAX_DEPTHS];
    let (mut diag, mut upper, mut rhs) = (
        [Acc8::zero(); MAX_DEPTHS],
        [Acc8::zero(); MAX_DEPTHS - 1],
        [Acc8::zero(); MAX_DEPTHS],
    );
    let mut look_again = 0.0f32;
    let mut live = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    for (k, at_k) in at.iter_mut().enumerate().take(depths) {
        if _mm256_movemask_ps(live) != 0 {
            let (a, n, dt) = tracer.schedule(k, spacing, s, r);
            let mut i = 0;
            while i < n {
                let d = a + (i as f32 + 0.5) * dt;
                let dv = _mm256_set1_ps(d);
                // x = p + dir·d, as Vec3's `p + dir * d`.
                let x = [0, 1, 2].map(|c| _mm256_add_ps(origin[c], _mm256_mul_ps(dir[c], dv)));
                let mut inside = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
                for c in 0..3 {
                    inside = _mm256_and_ps(
                        inside,
                        _mm256_and_ps(
                            _mm256_cmp_ps::<_CMP_GE_OQ>(x[c], _mm256_set1_ps(lo[c])),
                            _mm256_cmp_ps::<_CMP_LE_OQ>(x[c], _mm256_set1_ps(hi[c])),
                        ),
                    );
                }
                if p_inside {
                    live = _mm256_and_ps(live, inside); // a convex box is not entered again
                }
                let active = _mm256_and_ps(live, inside);
                let active_bits = _mm256_movemask_ps(active);
                if _mm256_movemask_ps(live) == 0 {
                    break;
                }
                if active_bits == 0 {
                    i += 1;
                    continue;
                }
                let width = tracer.width(d, s, r);
                if tracer.skip_empty && d >= look_again {
                    // The lanes jump together, as far as the least clear of them allows.
                    let xs = x.map(|v| to_array(v));
                    let mut margin = f32::INFINITY;
                    for l in (0..LANES).filter(|l| active_bits & (1 << l) != 0) {
                        let xl = Vec3::new(xs[0][l], xs[1][l], xs[2][l]);
                        margin =
                            margin.min(tracer.empty.clearance(xl) - 3.0 * width.max(tracer.h0));
                    }
                    if margin >= 0.0 {
                        i += (margin / dt) as u32 + 1;
                        continue;
                    }
                    look_again = d + 2.0 * tracer.empty.block();
                }
                let at_level = |m: usize| {
                    let g = pyramid.grid(m);
                    // PaddedGrid::local: (x − origin) · 1/h, component by component.
                    let local = [0, 1, 2].map(|c| {
                        _mm256_mul_ps(
                            _mm256_sub_ps(x[c], _mm256_set1_ps(g.origin[c])),
                            _mm256_set1_ps(g.inv_voxel_size),
                        )
                    });
                    Gathers::new(g).sample(local)
                };
                let rho = match pyramid.mix(width) {
                    Mix::One(m) => at_level(m),
                    Mix::Two(m, t) => {
                        let a = at_level(m);
                        lerp(a, at_level(m + 1), _mm256_set1_ps(t))
                    }
                };
                let rho = _mm256_and_ps(rho, active);
                for (l, c) in samples.iter_mut().enumerate() {
                    *c += u32::from(active_bits & (1 << l) != 0);
                }
                let dtau = _mm256_mul_ps(
                    _mm256_mul_ps(_mm256_set1_ps(tracer.kappa), rho),
                    _mm256_set1_ps(dt),
                );
                if fitted {
                    let sampled = _mm256_and_ps(active, _mm256_cmp_ps::<_CMP_GT_OQ>(rho, zero));
                    if _mm256_movemask_ps(sampled) != 0 {
                        let mid = _mm256_add_ps(tau, _mm256_mul_ps(_mm256_set1_ps(0.5), dtau));
                        let e = exp_neg8(_mm256_min_ps(
                            _mm256_mul_ps(_mm256_set1_ps(2.0), mid),
                            _mm256_set1_ps(80.0),
                        ));
                        let w = _mm256_mul_ps(_mm256_mul_ps(rho, e), _mm256_set1_ps(dt));
                        // Lanes not sampled add (0·a)·b = 0: their sums do not change.
                        let (w, mid) = (widen(_mm256_and_ps(w, sampled)), widen(mid));
                        // deep::Fit::add with the step's q, the same for all lanes.
                        let q = d / spacing;
                        let fk = (q as usize).min(depths - 1);
                        let t = f64::from(q - fk as f32).clamp(0.0, 1.0);
                        let (t_all, u_all) = ([_mm256_set1_pd(t); 2], [_mm256_set1_pd(1.0 - t); 2]);
                        diag[fk].add(&w, t, &t_all);
                        rhs[fk].add(&w, t, &mid);
                        if fk > 0 {
                            diag[fk - 1].add(&w, 1.0 - t, &u_all);
                            rhs[fk - 1].add(&w, 1.0 - t, &mid);
                            upper[fk - 1].add(&w, 1.0 - t, &t_all);
                        }
                    }
                }
                tau = _mm256_blendv_ps(tau, _mm256_add_ps(tau, dtau), active);
                i += 1;
                let over = _mm256_and_ps(
                    active,
                    _mm256_cmp_ps::<_CMP_GT_OQ>(tau, _mm256_set1_ps(TAU_MAX)),
                );
                live = _mm256_andnot_ps(over, live);
            }
        }
        *at_k = tau;
    }
    // Only the first `depths` entries are in use: convert and copy those alone.
    let mut out = [([0.0f32; MAX_DEPTHS], 0u32); LANES];
    for (k, v) in at.iter().enumerate().take(depths) {
        for (o, x) in out.iter_mut().zip(to_array(*v)) {
            o.0[k] = x;
        }
    }
    for (o, &n) in out.iter_mut().zip(&samples) {
        o.1 = n;
    }
    if fitted {
        let mut fits = [Fit::new(depths); LANES];
        for k in 0..depths {
            let (d, r) = (diag[k].lanes(), rhs[k].lanes());
            let u = if k + 1 < depths {
                upper[k].lanes()
            } else {
                [0.0; LANES]
            };
            for (l, fit) in fits.iter_mut().enumerate() {
                (fit.diag[k], fit.rhs[k]) = (d[l], r[l]);
                if k + 1 < depths {
                    fit.upper[k] = u[l];
                }
            }
        }
        for (o, fit) in out.iter_mut().zip(fits) {
            o.0 = fit.solve(&o.0[..depths], 1e-6 * spacing);
        }
    }
    out
}
