//! One cube-map lookup, written once so that the AVX2 version (module `avx2`) can do exactly the
//! same operations eight lights abreast and agree bit for bit: no branch whose two sides round
//! differently, no fused multiply-add, and an `e^{−τ}` of our own (libm's differs from any
//! vector version) accurate to 3·10⁻⁷.

use lgh_core::glam::Vec3;

use super::cube;

/// The largest optical depth a texel stores (`V = e^{−16} ≈ 1.1·10⁻⁷`).
pub const TAU_MAX: f32 = 16.0;

/// Where a light's map is: its first texel in the maps' one texel array, and its cells per
/// face side; `offset == u32::MAX` for a light without a map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Slot {
    pub offset: u32,
    pub cells: u32,
}

/// A light without a map (dark, or pruned: queries never return it).
pub(super) const NO_MAP: Slot = Slot {
    offset: u32::MAX,
    cells: 0,
};

/// `2^f` for `f ∈ (−1, 0]`: a degree-5 polynomial fitted to the relative error (≤ 2.6·10⁻⁷ in
/// f32 Horner evaluation), coefficients rounded to f32.
pub(super) const EXP2: [f32; 6] = [
    0.999_999_94,
    0.693_142_2,
    0.240_171_6,
    0.055_278_14,
    0.009_186_881,
    0.000_938_118_84,
];

/// `e^{−y}` for `y ∈ [0, 80]`: `2^z`, `z = −y log2 e`, split into `n = trunc(z)` and
/// `f = z − n ∈ (−1, 0]`; `2^f` by [`EXP2`], `2^n` added to the exponent bits.
#[inline(always)]
#[must_use]
pub(super) fn exp_neg(y: f32) -> f32 {
    let z = -y * core::f32::consts::LOG2_E;
    let n = z as i32;
    let f = z - n as f32;
    let mut p = EXP2[5];
    p = p * f + EXP2[4];
    p = p * f + EXP2[3];
    p = p * f + EXP2[2];
    p = p * f + EXP2[1];
    p = p * f + EXP2[0];
    f32::from_bits(p.to_bits().wrapping_add((n << 23) as u32))
}

/// `a + (b − a) t`.
#[inline(always)]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// The quantised optical depth at `x` of the light centred at `c` whose map is `slot` in
/// `texels` (`n` depths a texel), with `inv_spacing` = n / its reach, or `None` when the light
/// is unshadowed there (no map, `x` on the light or not finite). See
/// `CubeMaps::transmittance` for the interpolation.
#[inline(always)]
#[must_use]
pub(super) fn quantised_depth(
    texels: &[u16],
    n: usize,
    slot: Slot,
    inv_spacing: f32,
    x: Vec3,
    c: Vec3,
) -> Option<f32> {
    let (at, d) = locate(slot, x, c)?;
    // The two depths around the distance: knots 0 (τ = 0 at the light), 1..=n stored.
    let q = (d * inv_spacing).min(n as f32);
    let k = (q as u32).min(n as u32 - 1);
    let f = (q - k as f32).clamp(0.0, 1.0);
    let kk = k.saturating_sub(1) as usize;
    let lo = cube::bilinear(&at, slot.cells, |t| {
        if k == 0 {
            0.0
        } else {
            f32::from(texels[t * n + kk])
        }
    });
    let hi = cube::bilinear(&at, slot.cells, |t| {
        f32::from(texels[t * n + kk + usize::from(k > 0)])
    });
    Some(lerp(lo, hi, f))
}

/// The texels around the direction from `c` to `x` in the map `slot` (`cube::footprint`'s face
/// and weights, offset to the map) and the distance, or `None` when the light is unshadowed
/// there (no map, `x` on the light or not finite).
#[inline(always)]
pub(super) fn locate(slot: Slot, x: Vec3, c: Vec3) -> Option<(cube::Footprint, f32)> {
    let (vx, vy, vz) = (x.x - c.x, x.y - c.y, x.z - c.z);
    let d = (vx * vx + vy * vy + vz * vz).sqrt();
    if slot == NO_MAP || !d.is_finite() || d <= 0.0 {
        return None;
    }
    let at = cube::footprint(Vec3::new(vx, vy, vz), slot.cells);
    let at = cube::Footprint {
        first: slot.offset as usize + at.first,
        ..at
    };
    Some((at, d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_neg_is_the_exponential_to_a_few_ulps_of_its_argument() {
        // The polynomial errs by ≤ 2.6e-7; rounding z = −y log2 e errs by ≤ |z| 2⁻²⁴, which
        // moves 2^z by ln 2 |z| 2⁻²⁴ relatively (9.5e-7 at τ = TAU_MAX = 16); a few ulps more
        // for the Horner steps.
        for i in 0..=160_000 {
            let y = i as f32 * 1e-4; // 0 to TAU_MAX
            let want = (-f64::from(y)).exp();
            let z = f64::from(y) * std::f64::consts::LOG2_E;
            let bound = 2.6e-7 + std::f64::consts::LN_2 * z * 2f64.powi(-24) + 2.4e-7;
            let err = (f64::from(exp_neg(y)) / want - 1.0).abs();
            assert!(err < bound, "{y}: {err} ≥ {bound}");
        }
    }
}
