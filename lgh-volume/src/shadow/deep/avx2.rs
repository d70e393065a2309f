//! Deep-shadow cube maps eight abreast on x86-64 CPUs with AVX2: the lookups of
//! [`CubeMaps::transmittances`], eight lights at a time, and the texel rays of one light traced
//! eight at a time. Each lane does exactly the operations of the one-by-one code, so the results
//! are the same bit for bit.
//!
//! With `shadow::avx2` (the ray-marched shadows, whose gathers and lane helpers this uses), this
//! is the crate's only `unsafe` code. Each `unsafe` block says why it is sound: the CPU is
//! checked for AVX2 before every batch, and every gather reads inside the maps or the grid.
#![allow(unsafe_code)]

use core::arch::x86_64::*;

use lgh_core::glam::Vec3;

use super::knots::TAU;
use super::{CubeMaps, Depths, Fit, Knots, Tracer, INV_QUANT, MAX_DEPTHS, TAU_MAX};
use crate::shadow::avx2::{fits, from_array, lerp, to_array, Gathers, LANES};
use crate::shadow::lookup::{Slot, EXP2, NO_MAP};
use crate::shadow::prefilter::{DensityPyramid, Mix};

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
    if maps.adaptive() {
        // Knots are read two a gather: an odd count is left to the one-by-one code. Invalid
        // lanes read the knots of texel 0, which must be there.
        if depths % 2 != 0 || texels.len() < depths {
            return false;
        }
        for first in (0..whole).step_by(LANES) {
            let (c, slots, scale) = chunk(maps, &centres[first..], &ids[first..]);
            // SAFETY: the CPU supports AVX2, checked above.
            let v = unsafe { knots8(texels, depths, x, &c, &slots, &scale) };
            out[first..first + LANES].copy_from_slice(&v);
        }
    } else {
        // Groups of chunks: every chunk of a group is located and its texels' cache lines are
        // requested, then the group's texels are gathered. The lookups of a shading point read
        // lines scattered over the maps; requested together, their fetches overlap.
        const GROUP: usize = 8;
        let mut located = [None; GROUP];
        for group in (0..whole).step_by(LANES * GROUP) {
            let end = (group + LANES * GROUP).min(whole);
            for (g, first) in (group..end).step_by(LANES).enumerate() {
                let (c, slots, inv_spacing) = chunk(maps, &centres[first..], &ids[first..]);
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
    }
    for i in whole..n {
        let (level, index) = ids[i];
        out[i] = maps.transmittance(x, level, index, centres[i]);
    }
    true
}

/// The first eight lights of `centres` and `ids`, a lane each: their centres (x, y, z lanes),
/// their maps and their maps' depth scale ([`CubeMaps::slot`]).
fn chunk(
    maps: &CubeMaps,
    centres: &[Vec3],
    ids: &[(u8, u32)],
) -> ([[f32; LANES]; 3], [Slot; LANES], [f32; LANES]) {
    let mut c = [[0.0f32; LANES]; 3];
    let mut slots = [NO_MAP; LANES];
    let mut scale = [0.0f32; LANES];
    for l in 0..LANES {
        let p = centres[l];
        (c[0][l], c[1][l], c[2][l]) = (p.x, p.y, p.z);
        let (level, index) = ids[l];
        (slots[l], scale[l]) = maps.slot(level, index);
    }
    (c, slots, scale)
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

/// Eight lookups' texels: lane by lane `lookup::locate` (the distance, the map's first texel
/// of the footprint, the bilinear weights) with the same operations in the same order, and
/// which lanes are valid (a map, `d` finite and > 0).
#[derive(Clone, Copy)]
struct Footprint8 {
    d: __m256,
    first: __m256i,
    side: __m256i,
    tx: __m256,
    ty: __m256,
    valid: __m256,
}

/// [`Footprint8`] of the lights centred at `c` (x, y, z lanes) with maps `slots`, seen from `x`.
#[inline]
#[target_feature(enable = "avx2")]
fn footprint8(x: Vec3, c: &[[f32; LANES]; 3], slots: &[Slot; LANES]) -> Footprint8 {
    // SAFETY: AVX2 is enabled on this function, whose callers checked the CPU for it; `a` is
    // eight f32, 32 bytes, exactly what the load reads, and `loadu` needs no alignment.
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
    // SAFETY: AVX2 is enabled on this function, whose callers checked the CPU for it; `a` is
    // eight i32, 32 bytes, exactly what the load reads, and `loadu` needs no alignment.
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
    Footprint8 {
        d,
        first,
        side,
        tx,
        ty,
        valid,
    }
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
    // SAFETY: AVX2 is enabled on this function, whose callers checked the CPU for it; `a` is
    // eight f32, 32 bytes, exactly what the load reads, and `loadu` needs no alignment.
    let ld = |a: &[f32; LANES]| unsafe { _mm256_loadu_ps(a.as_ptr()) };
    let Footprint8 {
        d,
        first,
        side,
        tx,
        ty,
        valid,
    } = footprint8(x, c, slots);
    let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
    let unit = |t: __m256| _mm256_min_ps(_mm256_max_ps(t, zero), one);
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

/// Eight lookups of `knots::transmittance` (adaptive knots, `n` a texel, `n` even), lane by
/// lane the same operations in the same order: each corner texel's knots gathered two at a
/// time, walked to the two around the distance, `τ` interpolated; the corners blended
/// bilinearly, then `exp_neg`. Invalid lanes read texel 0 and give 1.
#[target_feature(enable = "avx2")]
fn knots8(
    texels: &[u16],
    n: usize,
    x: Vec3,
    c: &[[f32; LANES]; 3],
    slots: &[Slot; LANES],
    scale: &[f32; LANES],
) -> [f32; LANES] {
    let at = footprint8(x, c, slots);
    // SAFETY: `scale` holds eight floats.
    let q = _mm256_mul_ps(at.d, unsafe { _mm256_loadu_ps(scale.as_ptr()) });
    let vi = _mm256_castps_si256(at.valid);
    let per_texel = _mm256_set1_epi32(n as i32);
    let ptr = texels.as_ptr().cast::<i32>();
    let tau_of = TAU.as_ptr();
    let depth = |texel: __m256i| {
        // Two-byte index of the texel's first knot (0 for invalid lanes).
        let base = _mm256_and_si256(_mm256_mullo_epi32(texel, per_texel), vi);
        let (mut q0, mut t0) = (_mm256_setzero_ps(), _mm256_setzero_ps());
        let mut found = _mm256_setzero_ps();
        let mut out = _mm256_setzero_ps();
        for pair in (0..n).step_by(2) {
            // SAFETY: a valid lane's texel lies in its map, inside `texels`, and a four-byte
            // read at its knot `pair` (even, pair + 1 < n) reads knots pair and pair + 1 of it;
            // invalid lanes read knots 0 and 1 of texel 0.
            let g = unsafe {
                _mm256_i32gather_epi32::<2>(
                    ptr,
                    _mm256_add_epi32(base, _mm256_set1_epi32(pair as i32)),
                )
            };
            for k in [
                _mm256_and_si256(g, _mm256_set1_epi32(0xffff)),
                _mm256_srli_epi32::<16>(g),
            ] {
                let q1 = _mm256_cvtepi32_ps(_mm256_srli_epi32::<8>(k));
                let v1 = _mm256_and_si256(k, _mm256_set1_epi32(0xff));
                // SAFETY: v1 < 256, the table's length.
                let t1 = unsafe { _mm256_i32gather_ps::<4>(tau_of, v1) };
                let here = _mm256_andnot_ps(found, _mm256_cmp_ps::<_CMP_LT_OQ>(q, q1));
                let t = _mm256_add_ps(
                    t0,
                    _mm256_mul_ps(
                        _mm256_sub_ps(t1, t0),
                        _mm256_div_ps(_mm256_sub_ps(q, q0), _mm256_sub_ps(q1, q0)),
                    ),
                );
                out = _mm256_blendv_ps(out, t, here);
                found = _mm256_or_ps(found, here);
                (q0, t0) = (q1, t1);
            }
        }
        // Beyond the last knot: its value.
        _mm256_blendv_ps(t0, out, found)
    };
    let one = _mm256_set1_epi32(1);
    let (first, side) = (at.first, at.side);
    let t00 = depth(first);
    let t10 = depth(_mm256_add_epi32(first, one));
    let t01 = depth(_mm256_add_epi32(first, side));
    let t11 = depth(_mm256_add_epi32(_mm256_add_epi32(first, side), one));
    let tau = lerp(lerp(t00, t10, at.tx), lerp(t01, t11, at.tx), at.ty);
    let v = _mm256_blendv_ps(_mm256_set1_ps(1.0), exp_neg8(tau), at.valid);
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
/// levels are the same for all eight; only the positions differ. With `knots`, each lane's
/// steps are also handed to its adaptive knots, as `Tracer::trace_knots` does. `None` without
/// AVX2 or when a pyramid level is too large for 32-bit gather offsets.
pub(super) fn trace8(
    tracer: &Tracer<'_>,
    p: Vec3,
    dirs: &[Vec3; LANES],
    s: f32,
    r: f32,
    reach: f32,
    knots: Option<&mut [Knots; LANES]>,
) -> Option<[([f32; MAX_DEPTHS], u32); LANES]> {
    let pyramid = tracer.pyramid;
    let fits = (0..pyramid.levels()).all(|m| fits(pyramid.grid(m)));
    if !fits || !std::arch::is_x86_feature_detected!("avx2") {
        return None;
    }
    // SAFETY: the CPU supports AVX2, checked above; every level fits 32-bit offsets.
    Some(unsafe { trace8_avx2(tracer, p, dirs, (s, r, reach), knots) })
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

/// The normal equations of eight lanes' `deep::Fit`s, summed in f64 step by step, with the
/// light's knot spacing and depth count that place each step among the depths.
struct Fit8 {
    diag: [Acc8; MAX_DEPTHS],
    upper: [Acc8; MAX_DEPTHS - 1],
    rhs: [Acc8; MAX_DEPTHS],
    spacing: f32,
    depths: usize,
}

impl Fit8 {
    #[inline]
    #[target_feature(enable = "avx2")]
    fn new(spacing: f32, depths: usize) -> Self {
        let (diag, upper, rhs) = (
            [Acc8::zero(); MAX_DEPTHS],
            [Acc8::zero(); MAX_DEPTHS - 1],
            [Acc8::zero(); MAX_DEPTHS],
        );
        Fit8 {
            diag,
            upper,
            rhs,
            spacing,
            depths,
        }
    }

    /// One step at distance `d` (length `dt`) of the `active` lanes: density `rho`, optical
    /// depth `tau` before it and `dtau` across it, added as `deep::Fit::add` adds it, lane by
    /// lane.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn step(&mut self, rho: __m256, tau: __m256, dtau: __m256, active: __m256, d: f32, dt: f32) {
        let zero = _mm256_setzero_ps();
        let (diag, upper, rhs) = (&mut self.diag, &mut self.upper, &mut self.rhs);
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
            let q = d / self.spacing;
            let fk = (q as usize).min(self.depths - 1);
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

    /// Each lane's fitted depths in `out`, solved from its sums as `deep::Fit::solve` does.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn solve(&self, out: &mut [([f32; MAX_DEPTHS], u32); LANES]) {
        let (depths, spacing) = (self.depths, self.spacing);
        let (diag, upper, rhs) = (&self.diag, &self.upper, &self.rhs);
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
}

/// The lanes of the positions `x` (x, y, z lanes) inside the box `lo..=hi`: all bits set where
/// inside.
#[inline]
#[target_feature(enable = "avx2")]
fn inside8(x: &[__m256; 3], lo: Vec3, hi: Vec3) -> __m256 {
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
    inside
}

/// How far the lanes of `active_bits` at the positions `x` can jump together over empty space:
/// the least clearance among them, less three filter widths (`width`, at least `h0`); negative
/// where one of them cannot.
#[inline]
#[target_feature(enable = "avx2")]
fn margin8(tracer: &Tracer<'_>, x: &[__m256; 3], active_bits: i32, width: f32) -> f32 {
    let xs = x.map(|v| to_array(v));
    let mut margin = f32::INFINITY;
    for l in (0..LANES).filter(|l| active_bits & (1 << l) != 0) {
        let xl = Vec3::new(xs[0][l], xs[1][l], xs[2][l]);
        margin = margin.min(tracer.empty.clearance(xl) - 3.0 * width.max(tracer.h0));
    }
    margin
}

/// The prefiltered density at the positions `x` for the filter width `width`: one level of the
/// pyramid or two blended, as `Tracer::trace` samples it.
#[inline]
#[target_feature(enable = "avx2")]
fn density8(pyramid: &DensityPyramid, x: &[__m256; 3], width: f32) -> __m256 {
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
    match pyramid.mix(width) {
        Mix::One(m) => at_level(m),
        Mix::Two(m, t) => {
            let a = at_level(m);
            lerp(a, at_level(m + 1), _mm256_set1_ps(t))
        }
    }
}

/// `Knots::step` lane by lane for the step at distance `d` (length `dt`), optical depth `tau`
/// before it and `dtau` across it, as `Tracer::trace_knots` calls it (inactive lanes have
/// `dtau` = 0 and are left out).
#[inline]
#[target_feature(enable = "avx2")]
fn step_knots8(knots: &mut [Knots; LANES], tau: __m256, dtau: __m256, d: f32, dt: f32) {
    let (t0, dt0) = (to_array(tau), to_array(dtau));
    let (d0, d1) = (d - 0.5 * dt, d + 0.5 * dt);
    for (l, k) in knots.iter_mut().enumerate() {
        if dt0[l] > 0.0 {
            k.step(d0, t0[l], d1, t0[l] + dt0[l]);
        }
    }
}

/// The lanes' results: the optical depths `at` (their first `depths`), or with `fit` the
/// depths fitted to the steps, and each lane's sample count.
#[inline]
#[target_feature(enable = "avx2")]
fn results8(
    at: &[__m256; MAX_DEPTHS],
    depths: usize,
    samples: &[u32; LANES],
    fit: Option<&Fit8>,
) -> [([f32; MAX_DEPTHS], u32); LANES] {
    // Only the first `depths` entries are in use: convert and copy those alone.
    let mut out = [([0.0f32; MAX_DEPTHS], 0u32); LANES];
    for (k, v) in at.iter().enumerate().take(depths) {
        for (o, x) in out.iter_mut().zip(to_array(*v)) {
            o.0[k] = x;
        }
    }
    for (o, &n) in out.iter_mut().zip(samples) {
        o.1 = n;
    }
    if let Some(fit) = fit {
        fit.solve(&mut out);
    }
    out
}

/// [`trace8`] on a CPU with AVX2, every pyramid level within 32-bit gather offsets.
#[target_feature(enable = "avx2")]
fn trace8_avx2(
    tracer: &Tracer<'_>,
    p: Vec3,
    dirs: &[Vec3; LANES],
    (s, r, reach): (f32, f32, f32),
    mut knots: Option<&mut [Knots; LANES]>,
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
    let mut fit = Fit8::new(spacing, depths);
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
                let inside = inside8(&x, lo, hi);
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
                    let margin = margin8(tracer, &x, active_bits, width);
                    if margin >= 0.0 {
                        i += (margin / dt) as u32 + 1;
                        continue;
                    }
                    look_again = d + 2.0 * tracer.empty.block();
                }
                let rho = density8(pyramid, &x, width);
                let rho = _mm256_and_ps(rho, active);
                for (l, c) in samples.iter_mut().enumerate() {
                    *c += u32::from(active_bits & (1 << l) != 0);
                }
                let dtau = _mm256_mul_ps(
                    _mm256_mul_ps(_mm256_set1_ps(tracer.kappa), rho),
                    _mm256_set1_ps(dt),
                );
                if fitted {
                    fit.step(rho, tau, dtau, active, d, dt);
                }
                if let Some(knots) = knots.as_deref_mut() {
                    step_knots8(knots, tau, dtau, d, dt);
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
    results8(&at, depths, &samples, fitted.then_some(&fit))
}
