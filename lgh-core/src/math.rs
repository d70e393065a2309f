//! Scalar maths that works with and without `std`.
//!
//! With the `std` feature the hardware instructions behind `f32::sqrt` / `f32::floor` are used;
//! without it, `libm`. Both are correctly rounded for `sqrt`, so results are bit-identical.

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

/// Floor of an `f64`.
#[inline(always)]
pub fn floor64(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.floor()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::floor(x)
    }
}
