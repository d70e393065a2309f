//! Error metrics of an approximation `A` against a reference `R`, on luminance — the paper's
//! `‖I‖` of eq. (2), Rec. 709 weights — as ARCHITECTURE.md at the repository root describes under
//! "Measuring". Sums are in `f64`, sequential, so they are deterministic.

use glam::Vec3;

use crate::light::luminance;

/// Error statistics of `approx` against `reference`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ErrorStats {
    /// `sqrt(mean((A − R)²)) / mean(R)`.
    pub rel_rmse: f64,
    /// `max |A − R| / R` over samples with `R > 0`.
    pub max_rel: f64,
    /// `max |A − R|`.
    pub max_abs: f64,
    /// `mean |A − R|`.
    pub mean_abs: f64,
    /// `mean(R)`.
    pub mean_reference: f64,
}

impl ErrorStats {
    /// Compares two equally long sequences of RGB values by their luminance.
    /// Returns `None` if the lengths differ or the sequences are empty.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::metrics::ErrorStats;
    ///
    /// let reference = [Vec3::ONE, Vec3::splat(2.0), Vec3::splat(3.0)];
    /// let approx = reference.map(|v| v * 1.1); // 10 % too bright everywhere
    /// let stats = ErrorStats::compare(&approx, &reference).unwrap();
    /// assert!((stats.max_rel - 0.1).abs() < 1e-6);
    /// assert!((stats.mean_reference - 2.0).abs() < 1e-6);
    /// assert_eq!(ErrorStats::compare(&reference, &reference).unwrap().max_abs, 0.0);
    /// assert!(ErrorStats::compare(&approx[..2], &reference).is_none()); // lengths differ
    /// ```
    #[must_use]
    pub fn compare(approx: &[Vec3], reference: &[Vec3]) -> Option<Self> {
        Self::compare_luminance(
            approx.iter().map(|&v| luminance(v) as f64),
            reference.iter().map(|&v| luminance(v) as f64),
        )
    }

    /// Compares two sequences of scalar values (already luminance).
    #[must_use]
    pub fn compare_luminance(
        approx: impl ExactSizeIterator<Item = f64>,
        reference: impl ExactSizeIterator<Item = f64>,
    ) -> Option<Self> {
        if approx.len() != reference.len() || approx.len() == 0 {
            return None;
        }
        let n = approx.len() as f64;
        let mut s = ErrorStats::default();
        let mut sq = 0.0;
        for (a, r) in approx.zip(reference) {
            let e = (a - r).abs();
            sq += e * e;
            s.mean_abs += e;
            s.mean_reference += r;
            s.max_abs = s.max_abs.max(e);
            if r > 0.0 {
                s.max_rel = s.max_rel.max(e / r);
            }
        }
        s.mean_abs /= n;
        s.mean_reference /= n;
        s.rel_rmse = libm::sqrt(sq / n) / s.mean_reference;
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    #[wasm_bindgen_test(unsupported = test)]
    fn known_values() {
        let r = [1.0, 3.0];
        let a = [2.0, 3.0];
        let s = ErrorStats::compare_luminance(a.into_iter(), r.into_iter()).unwrap();
        assert_eq!(s.mean_reference, 2.0);
        assert!((s.rel_rmse - (0.5f64).sqrt() / 2.0).abs() < 1e-12);
        assert_eq!(s.max_rel, 1.0);
        assert_eq!(s.max_abs, 1.0);
        assert_eq!(s.mean_abs, 0.5);
        assert!(ErrorStats::compare(&[], &[]).is_none());
    }
}
