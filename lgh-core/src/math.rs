//! Scalar maths that works with and without `std`.
//!
//! With the `std` feature the hardware instruction behind `f32::sqrt` is used; without it, `libm`.
//! Both are correctly rounded, so results are bit-identical either way.

/// Square root.
#[inline(always)]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrtf(x)
    }
}

/// Square root of an `f64`.
#[inline(always)]
pub fn sqrt64(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrt(x)
    }
}

/// Ceiling of an `f64` (exact, see [`floor64`]).
#[inline(always)]
pub fn ceil64(x: f64) -> f64 {
    -floor64(-x)
}

/// `2^level / 2`: the spacing `h_ℓ` of level ℓ in units of `h_1` (`h_0 = h_1 / 2`), exactly.
#[inline(always)]
pub fn level_scale(level: u8) -> f64 {
    (1u64 << level) as f64 * 0.5
}

/// Floor of an `f64` (exact for every input; NaN stays NaN).
///
/// Without SSE4.1, `f64::floor` is a library call; grid coordinates are computed per light per
/// level, so this uses truncation instead where it is exact (`|x| < 2^52`).
#[inline(always)]
pub fn floor64(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        let t = x as i64 as f64;
        if t == x {
            x // keeps −0.0
        } else if t > x {
            t - 1.0
        } else {
            t
        }
    } else {
        libm::floor(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    #[wasm_bindgen_test(unsupported = test)]
    fn floor_matches_libm() {
        for x in [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999,
            -2.999,
            1e15 + 0.5,
            -1e15 - 0.5,
            1e300,
            -1e300,
            4503599627370497.0,
        ] {
            assert_eq!(floor64(x).to_bits(), libm::floor(x).to_bits(), "{x}");
        }
        assert!(floor64(f64::NAN).is_nan());
        assert_eq!(ceil64(2.5), 3.0);
        assert_eq!(ceil64(-2.5), -2.0);
        assert_eq!(ceil64(4.0), 4.0);
        assert_eq!(level_scale(0), 0.5);
        assert_eq!(level_scale(1), 1.0);
        assert_eq!(level_scale(21), 1048576.0);
    }
}
