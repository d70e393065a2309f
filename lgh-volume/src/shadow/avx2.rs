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

use super::padded::{self, PaddedGrid};
use super::{transmittance, Ray, ShadowGrid, ROUND};

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
    if !fits(&grid.grid)
        || !std::arch::is_x86_feature_detected!("avx2")
        || out.len() != lights.len()
    {
        return None;
    }
    // SAFETY: the CPU supports AVX2, checked just above.
    Some(unsafe { batches(grid, x, lights, out) })
}

/// Whether eight-abreast lookups can read `grid`: it holds values, fewer than 2^31 of them
/// (32-bit gather offsets).
pub(super) fn fits(grid: &PaddedGrid) -> bool {
    !grid.is_empty() && i32::try_from(grid.data.len()).is_ok()
}

/// Marches the rays eight at a time, in order of length (the lanes of a batch march until its
/// longest ray ends, so rays of like length together keep them busy; each lane's result does
/// not depend on its batch). Where the shading point and eight lights are all inside the box
/// (the usual case) the rays are also set up eight abreast; other rays are set up one by one
/// ([`ShadowGrid::ray`]) and gathered into eights; the last few go one by one.
#[target_feature(enable = "avx2")]
fn batches(grid: &ShadowGrid, x: Vec3, lights: &[Vec3], out: &mut [f32]) -> u64 {
    BY_LENGTH.with(|order| {
        let mut order = order.borrow_mut();
        let (positions, index) = order.sort(grid, x, lights);
        ordered_batches(grid, x, positions, index, out)
    })
}

std::thread_local! {
    /// Each thread's reordering of its lights ([`ByLength`]).
    static BY_LENGTH: core::cell::RefCell<ByLength> = core::cell::RefCell::default();
}

/// Lights put in order of their rays' step counts by a counting sort (a vertex of the lighting
/// cache has hundreds of lights, whose rays run from a few steps to the box's width).
#[derive(Default)]
struct ByLength {
    positions: Vec<Vec3>,
    index: Vec<usize>,
    keys: Vec<u8>,
}

impl ByLength {
    /// Rays of up to this many steps get a bucket each; longer ones share the last.
    const BUCKETS: usize = 64;

    /// `lights` from shortest to longest ray from `x` (at most [`Self::BUCKETS`] steps apart),
    /// and each one's index in `lights`. Fewer than two batches are left as they are.
    fn sort(&mut self, grid: &ShadowGrid, x: Vec3, lights: &[Vec3]) -> (&[Vec3], &[usize]) {
        self.positions.clear();
        self.index.clear();
        if lights.len() <= LANES {
            self.positions.extend_from_slice(lights);
            self.index.extend(0..lights.len());
            return (&self.positions, &self.index);
        }
        let scale = grid.grid.inv_voxel_size * grid.inv_step_voxels;
        self.keys.clear();
        self.keys.extend(lights.iter().map(|&l| {
            let steps = (l - x).length() * scale;
            // NaN and beyond the last bucket: the last bucket.
            if steps < (Self::BUCKETS - 1) as f32 {
                steps as u8
            } else {
                (Self::BUCKETS - 1) as u8
            }
        }));
        // Each bucket's next slot.
        let mut next = [0usize; Self::BUCKETS + 1];
        for &k in &self.keys {
            next[usize::from(k) + 1] += 1;
        }
        for b in 1..=Self::BUCKETS {
            next[b] += next[b - 1];
        }
        self.positions.resize(lights.len(), Vec3::ZERO);
        self.index.resize(lights.len(), 0);
        for (i, (&k, &l)) in self.keys.iter().zip(lights).enumerate() {
            let slot = &mut next[usize::from(k)];
            self.positions[*slot] = l;
            self.index[*slot] = i;
            *slot += 1;
        }
        (&self.positions, &self.index)
    }
}

/// [`batches`] over `lights` in the order given, light `k`'s transmittance written to
/// `out[index[k]]`.
#[target_feature(enable = "avx2")]
fn ordered_batches(
    grid: &ShadowGrid,
    x: Vec3,
    lights: &[Vec3],
    index: &[usize],
    out: &mut [f32],
) -> u64 {
    let mut samples = 0u64;
    let mut group = [(0usize, Ray::default()); LANES];
    let mut k = 0;
    let x_inside = grid.inside(x);
    for (c, chunk) in lights.chunks(LANES).enumerate() {
        let first = c * LANES;
        if let (true, Ok(chunk)) = (x_inside, <&[Vec3; LANES]>::try_from(chunk)) {
            if let Some(rays) = setup(grid, x, chunk) {
                samples += march8(grid, &rays, core::array::from_fn(|l| index[first + l]), out);
                continue;
            }
        }
        for (j, &l) in chunk.iter().enumerate() {
            let Some(ray) = grid.ray(x, l) else {
                out[index[first + j]] = 1.0;
                continue;
            };
            {
                group[k] = (index[first + j], ray);
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

/// Index of the first value of cell `(i, j, k)` in a [`PaddedGrid`]'s bricks, each index
/// clamped into `0..=last` first (as `PaddedGrid::first` clamps), so whatever the cell, its
/// eight values are inside the grid.
#[inline]
#[target_feature(enable = "avx2")]
fn first_value(cell: [__m256i; 3], last: [__m256i; 3], bricks: [__m256i; 2]) -> __m256i {
    let zero = _mm256_setzero_si256();
    let [i, j, k] = [0, 1, 2].map(|a| _mm256_min_epi32(_mm256_max_epi32(cell[a], zero), last[a]));
    let brick_of = |c: __m256i| _mm256_srli_epi32::<{ padded::BRICK_BITS as i32 }>(c);
    let within = |c: __m256i| _mm256_and_si256(c, _mm256_set1_epi32(padded::BRICK as i32 - 1));
    let brick = _mm256_add_epi32(
        _mm256_mullo_epi32(
            _mm256_add_epi32(_mm256_mullo_epi32(brick_of(k), bricks[1]), brick_of(j)),
            bricks[0],
        ),
        brick_of(i),
    );
    let side = _mm256_set1_epi32(padded::SIDE as i32);
    let offset = _mm256_add_epi32(
        _mm256_mullo_epi32(
            _mm256_add_epi32(_mm256_mullo_epi32(within(k), side), within(j)),
            side,
        ),
        within(i),
    );
    _mm256_add_epi32(
        _mm256_mullo_epi32(brick, _mm256_set1_epi32(padded::BRICK_VALUES as i32)),
        offset,
    )
}

/// What gathering trilinear samples of a [`PaddedGrid`] eight at a time needs.
pub(super) struct Gathers {
    /// The last cell per axis.
    last: [__m256i; 3],
    /// Bricks along x and y.
    bricks: [__m256i; 2],
    data: *const f32,
}

impl Gathers {
    /// For `grid`, which must be non-empty and hold fewer than 2^31 values (checked by the
    /// callers, [`fits`]).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn new(grid: &PaddedGrid) -> Self {
        let (last, bricks) = grid.layout();
        let v = |n: usize| _mm256_set1_epi32(n as i32);
        Gathers {
            last: last.map(v),
            bricks: [v(bricks[0]), v(bricks[1])],
            data: grid.data.as_ptr(),
        }
    }

    /// [`PaddedGrid::sample`] of eight points in padded voxel units, bit for bit (points outside
    /// the padded box read their nearest cell's values, clamped, rather than nothing: mask them).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn sample(&self, [px, py, pz]: [__m256; 3]) -> __m256 {
        let (ix, wx) = floor(px);
        let (iy, wy) = floor(py);
        let (iz, wz) = floor(pz);
        let base = first_value([ix, iy, iz], self.last, self.bricks);
        // Each of the cell's four x-rows is a pair of neighbouring values, gathered as one
        // 64-bit element: half the elements of gathering the eight corners one by one, which
        // is what a lookup costs (a gather's time grows with its elements).
        let [x00, x10, x01, x11] = [0, 2, 4, 6].map(|c| {
            let row = padded::CORNERS[c];
            // SAFETY: every base is the first value of a cell of the grid, whose eight values
            // lie at the corners' offsets inside the grid's data, whose pointer this is; a row's
            // two values are its corners `c` and `c + 1`, one apart.
            let (a, b) = unsafe { self.pairs(row, base) };
            lerp(a, b, wx)
        });
        lerp(lerp(x00, x10, wy), lerp(x01, x11, wy), wz)
    }

    /// The values at `base + offset` and `base + offset + 1` of each lane, gathered in pairs.
    ///
    /// # Safety
    /// Both must be inside the grid's data for every lane.
    #[inline]
    #[target_feature(enable = "avx2")]
    unsafe fn pairs(&self, offset: usize, base: __m256i) -> (__m256, __m256) {
        let at = self.data.add(offset).cast::<f64>();
        // Lanes 0–3 and 4–7: [a0 b0 a1 b1 | a2 b2 a3 b3] and [a4 b4 a5 b5 | a6 b6 a7 b7].
        let lo = _mm256_castpd_ps(_mm256_i32gather_pd::<4>(at, _mm256_castsi256_si128(base)));
        let hi = _mm256_castpd_ps(_mm256_i32gather_pd::<4>(
            at,
            _mm256_extracti128_si256::<1>(base),
        ));
        // [a0 a1 a4 a5 | a2 a3 a6 a7], then the middle quarters swapped.
        let order = |v: __m256| {
            _mm256_castpd_ps(_mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_castps_pd(v)))
        };
        (
            order(_mm256_shuffle_ps::<0b10_00_10_00>(lo, hi)),
            order(_mm256_shuffle_ps::<0b11_01_11_01>(lo, hi)),
        )
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

    /// The reordering is a permutation from fewest to most whole steps, keeps lists of one
    /// batch as they are, and puts a NaN position (no ray) last rather than panicking.
    #[test]
    fn lights_are_ordered_by_their_rays_steps() {
        let v = crate::medium::Volume::new(
            crate::grid::DenseGrid::zeros([40, 8, 8], 1.0, Vec3::ZERO),
            crate::grid::DenseGrid::zeros([40, 8, 8], 1.0, Vec3::ZERO),
        );
        let m = crate::medium::Medium::new(1.0, 1.0, 0.0, 0.0).unwrap();
        let grid = ShadowGrid::new(&v, &m, 2.0, 1e-3);
        let x = Vec3::new(0.0, 4.0, 4.0);
        let mut lights: Vec<Vec3> = [17.0f32, 3.0, 39.0, 9.0, 1.0, 25.0, 5.0, 33.0, 11.0, 0.5]
            .iter()
            .map(|&d| x + Vec3::X * d)
            .collect();
        lights.push(Vec3::NAN);
        let mut order = ByLength::default();
        let (positions, index) = order.sort(&grid, x, &lights);
        // Whole steps (the buckets; within one the order is the input's).
        let steps: Vec<f32> = positions
            .iter()
            .map(|p| ((p.x - x.x) / 2.0).floor())
            .collect();
        assert!(steps[..10].windows(2).all(|w| w[0] <= w[1]), "{steps:?}");
        assert!(positions[10].is_nan());
        let mut seen = index.to_vec();
        seen.sort_unstable();
        assert_eq!(seen, (0..lights.len()).collect::<Vec<_>>());
        for (p, &i) in positions.iter().zip(index) {
            assert!(p == &lights[i] || (p.is_nan() && lights[i].is_nan()));
        }
        let few = &lights[..LANES];
        let (positions, index) = order.sort(&grid, x, few);
        assert_eq!(
            (positions, index),
            (few, &(0..LANES).collect::<Vec<_>>()[..])
        );
    }

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
    /// first values whose cell lies inside the grid, and so reads inside it.
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
        let density = crate::grid::DenseGrid::zeros([128, 129, 130], 1.0, Vec3::ZERO);
        let grid = PaddedGrid::new(&density);
        let g = Gathers::new(&grid);
        let most = (grid.data.len() - 1 - padded::CORNERS[7]) as i32;
        let v = from_array;
        let rotate = |r: usize| core::array::from_fn(|l| wild[(l + r) % LANES]);
        for r in 0..LANES {
            let p = [v(wild), v(rotate(r)), v(rotate(3 * r + 1))];
            let base = first_value(p.map(|p| floor(p).0), g.last, g.bricks);
            let mut got = [0i32; LANES];
            // SAFETY: `got` holds eight 32-bit integers.
            unsafe { _mm256_storeu_si256(got.as_mut_ptr().cast(), base) };
            assert!(got.iter().all(|b| (0..=most).contains(b)), "{got:?}");
        }
    }
}
