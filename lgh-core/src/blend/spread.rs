//! Eq. (3)'s blended fall-off averaged over a coarse light's spread ([`CoarseSpread::Averaged`]).
//!
//! Eq. (3) weights a level-ℓ light by `B_ℓ(d)` and its fall-off `1/d²` at the distance `d` of its
//! illumination centre (eq. 2), as if every input light it stands for were there. Each input light
//! `j` is split among the levels by the trilinear weights `w_ij` of eq. (1), and the levels'
//! weights sum to one at every distance, so the sum over levels is exact for input light `j` only
//! if every level weighs it at its *own* distance `d_j`: `Σ_ℓ Σ_i w_ij B_ℓ(d_j) = 1`. At the centres'
//! distances the sum is only close to one where `B_ℓ` bends (at `r_{ℓ−1}`, `r_ℓ`, `2 r_ℓ`), and
//! the error is not random: the nearer input lights of a cluster have the larger `1/d_j²` and,
//! outside a cloud of lights, the larger finer-level weight, so eq. (3) is bright there. On a
//! uniform 32³ lattice of point lights (`h1` = 2 spacings, `tools/hierarchy/lattice_probes.py`)
//! it is +0.26% inside the lattice and +1.86% three to ten spacings outside it at α = 2, and no
//! level alone causes it.
//!
//! The exact contribution of light `i` of level ℓ is `Σ_j w_ij I_j B_ℓ(d_j)/d_j²`: the mean of
//! `B_ℓ(d)/d²` over the lights it stands for, weighted by intensity. Eq. (4) gives their spread, a
//! per-axis variance `σ²_ℓi`; [`CoarseSpread::Averaged`] takes the lights as an isotropic
//! distribution of that variance, `s² = tr(σ²_ℓi)/3`, with the radial density `∝ 1 − a²/R²` on the
//! ball of radius `R = √7 s` (smooth, and zero beyond `R`, so a light's weight falls to zero
//! continuously as its ball leaves the level's support: no light enters a query with a jump),
//! and weighs the light by
//!
//! `K_ℓ(d, s) = E[B_ℓ(‖x − p‖) / ‖x − p‖²]`, `p` drawn from that ball about the centre.
//!
//! (In a numpy model of the same lattice, a Gaussian of the same variance gives the same figures
//! to 0.05%, and a uniform ball, whose mass sits at its rim, is 0.5% dark outside.) With it the
//! lattice above is −0.12% inside, −0.04% across its box and +0.09% outside at α = 2, the points'
//! RMS error 0.12–0.13% against eq. (3)'s 0.53–1.88%; at α = 4 within 0.04% (RMS 0.03–0.04%
//! against 0.13–0.19%): `cargo test --release -p lgh-core --test spread -- --nocapture`.
//!
//! # The table
//!
//! In units of `r_ℓ`, `K_ℓ = k(ρ, σ) / r_ℓ²` with `ρ = d/r_ℓ` and `σ = s/r_ℓ`, and `k` has one shape
//! for the levels below the top (`B̂` rising from 0 at `ρ = ½` to 1 at 1 and falling to 0 at 2)
//! and one for the top level (rising, then 1). Both are tabulated at `ρ = i/32`, `σ = j/32`
//! (`σ ≤ 1`: a level-ℓ light's lights lie within `h_ℓ` of its vertex on each axis, so `s ≤ h_ℓ
//! = r_ℓ/α`; a larger `σ`, possible only at α < 1, is taken as 1) and read bilinearly; the middle
//! shape is zero beyond `ρ = 2 + √7 σ`, and the top shape beyond `ρ = 8` — where the ball lies
//! wholly where `B̂ = 1` — is the convergent series of the mean of `1/‖x − p‖²` over the ball,
//!
//! `k = (1/ρ²) Σ_n 15 (R/ρ)^2n / ((2n + 1)(2n + 3)(2n + 5))`, `R = √7 σ`
//!
//! (each shell of radius `a` gives `(1/ρ²) Σ_n (a/ρ)^2n / (2n + 1)`, and the density's even
//! moments are `E[a^2n] = 15 R^2n / ((2n + 3)(2n + 5))`). `tools/hierarchy/spread_table.py`
//! writes the table: each entry a one-dimensional integral over the shell radius of a shell's
//! mean, which is closed-form because `B̂` is piecewise linear; the test below recomputes every
//! entry from that formula in `f64`.
//!
//! The table's `1/d²` is not clamped at `h0`: for ℓ ≥ 1 the ramp is zero below `r_{ℓ−1} ≥ r_0 =
//! α h0`, so the clamp never acts where α ≥ 1. A light of no spread (one input light, or all at
//! one point) is weighed by eq. (3) exactly.
//!
//! The weight a query reports is `K_ℓ · max(d, h0)²`, so that a caller's `I · weight · g(d)` with
//! the point's fall-off `g(d) = 1/max(d, h0)²` is `I K_ℓ`; it may exceed 1 (beyond `r_ℓ` on the top
//! level the ball's mean of `1/d²` is above `1/d²`). A light's weight is non-zero from `r_{ℓ−1} −
//! R` to `2 r_ℓ + R`, so a query scans each level that much wider
//! ([`Blending::support`](crate::Blending::support)), with the level's largest `R`.

use glam::Vec3;

use super::spread_table::{MIDDLE, TOP};
use crate::light::spread_of;

/// How a coarse light (level ℓ ≥ 1) is weighted and its fall-off taken: at its illumination
/// centre, as eq. (3) is printed, or averaged over the spread of the lights it stands for (eq. 4;
/// the `blend::spread` module documentation). Level-0 lights are points either way.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::{CoarseSpread, GridSettings, LightingGridHierarchy, PointLight};
///
/// // A 16³ lattice of equal lights, one h0 apart, and points just outside one face.
/// let lights: Vec<PointLight> = (0..4096u32)
///     .map(|i| Vec3::new((i % 16) as f32, (i / 16 % 16) as f32, (i / 256) as f32))
///     .map(|p| PointLight::new(p, Vec3::ONE))
///     .collect();
/// let lgh = LightingGridHierarchy::build(&lights, &GridSettings { h1: Some(2.0), ..Default::default() })?;
/// let points = [Vec3::new(-6.0, 3.5, 3.5), Vec3::new(-4.0, 3.5, 9.5), Vec3::new(-3.0, 12.5, 4.5)];
/// let g = |d: f32| lgh_core::falloff(d, lgh.h0());
/// let exact: f32 = points.iter().flat_map(|&x| lights.iter().map(move |l| g(l.position.distance(x)))).sum();
/// let ratio = |spread| -> Result<f32, lgh_core::QueryError> {
///     let blending = lgh.blending_with(2.0, spread)?;
///     let mut sum = 0.0;
///     for &x in &points {
///         sum += lgh.query_sum(x, &blending, |s| s.intensity * g(s.distance))?.0.x;
///     }
///     Ok(sum / exact)
/// };
/// let (centre, averaged) = (ratio(CoarseSpread::Centre)?, ratio(CoarseSpread::Averaged)?);
/// assert!(centre > 1.01); // eq. (3) at the centres: bright outside a cloud
/// assert!((averaged - 1.0).abs() < 0.003);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CoarseSpread {
    /// Eq. (3) as printed: `B_ℓ(d)` and `1/d²` at the light's illumination centre.
    #[default]
    Centre,
    /// `B_ℓ(d)/d²` averaged over a ball of the light's variance (eq. 4).
    Averaged,
}

impl CoarseSpread {
    /// Both, the paper's first.
    pub const ALL: [CoarseSpread; 2] = [CoarseSpread::Centre, CoarseSpread::Averaged];

    /// The name on the command line and in file headers: `centre` or `averaged`.
    ///
    /// ```
    /// use lgh_core::CoarseSpread;
    ///
    /// assert_eq!(CoarseSpread::Averaged.name(), "averaged");
    /// assert_eq!(CoarseSpread::Centre.name(), "centre");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CoarseSpread::Centre => "centre",
            CoarseSpread::Averaged => "averaged",
        }
    }

    /// The weighting named `name` ([`name`](Self::name)), `None` for any other string.
    ///
    /// ```
    /// use lgh_core::CoarseSpread;
    ///
    /// assert_eq!(CoarseSpread::from_name("averaged"), Some(CoarseSpread::Averaged));
    /// assert_eq!(CoarseSpread::from_name("center"), None); // the name is British
    /// for c in CoarseSpread::ALL {
    ///     assert_eq!(CoarseSpread::from_name(c.name()), Some(c));
    /// }
    /// ```
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        CoarseSpread::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// `R / s`: the radius of the ball of density `∝ 1 − a²/R²` whose per-axis variance is `s²`.
pub(crate) const RADIUS_PER_SPREAD: f32 = 2.645_751_3; // √7

/// Table steps a unit of `ρ` and of `σ`.
const STEPS: f32 = 32.0;
/// The largest `σ` tabulated.
const SIGMA_MAX: f32 = 1.0;

/// The spread `s = √(tr σ²/3)` of a light of variance `variance`, in units of `r_ℓ` (`inv_r =
/// 1/r_ℓ`), at most [`SIGMA_MAX`]; 0 for a point, a negative rounding or a NaN.
#[inline(always)]
fn sigma(variance: Vec3, inv_r: f32) -> f32 {
    (spread_of(variance) * inv_r).min(SIGMA_MAX)
}

/// The table's `k(ρ, σ)`, bilinearly, for `ρ` below its last row (`x = ρ · STEPS`).
#[inline(always)]
fn lerp2<const C: usize>(t: &[[f32; C]], x: f32, sigma: f32) -> f32 {
    let i = x as usize;
    let fx = x - i as f32;
    let y = sigma * STEPS;
    let j = (y as usize).min(C - 2);
    let fy = y - j as f32;
    let (a, b) = (&t[i], &t[i + 1]);
    let lo = a[j] + (a[j + 1] - a[j]) * fy;
    let hi = b[j] + (b[j + 1] - b[j]) * fy;
    lo + (hi - lo) * fx
}

/// The top shape beyond the table: the ball's mean of `1/d²`, `(1/ρ²) Σ_n c_n (R/ρ)^2n` with
/// `c_n = 15/((2n + 1)(2n + 3)(2n + 5))` (module documentation). At `ρ ≥ 8`, `R ≤ √7`, so the
/// ratio `(R/ρ)² ≤ 0.11` and the six terms kept leave less than 1e-7.
#[inline(always)]
fn top_series(rho: f32, sigma: f32) -> f32 {
    const C: [f32; 6] = [
        1.0,
        1.0 / 7.0,
        15.0 / 315.0,
        15.0 / 693.0,
        15.0 / 1287.0,
        15.0 / 2145.0,
    ];
    let inv2 = 1.0 / (rho * rho);
    let x = RADIUS_PER_SPREAD * RADIUS_PER_SPREAD * sigma * sigma * inv2;
    let sum = C[0] + x * (C[1] + x * (C[2] + x * (C[3] + x * (C[4] + x * C[5]))));
    inv2 * sum
}

/// `k(ρ, σ)` of the top level or of one below it: zero where the ball of radius `R = √7 σ` does
/// not meet the ramp (below `ρ = ½ − R`, and beyond `2 + R` below the top), where the bilinear
/// table would leak a trace and the query does not look.
#[inline(always)]
pub(crate) fn k(top_level: bool, rho: f32, sigma: f32) -> f32 {
    let ball = RADIUS_PER_SPREAD * sigma;
    if rho + ball <= 0.5 || (!top_level && rho - ball >= 2.0) {
        0.0
    } else {
        let table: &[[f32; 33]] = if top_level { &TOP } else { &MIDDLE };
        let x = rho * STEPS;
        if x < (table.len() - 1) as f32 {
            lerp2(table, x, sigma)
        } else if top_level {
            top_series(rho, sigma)
        } else {
            0.0 // beyond 2 + √7 σ (and a NaN)
        }
    }
}

/// The averaged weight of one level's lights: `K_ℓ(d, s) · max(d, h0)²` (module documentation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Averaged {
    /// Eq. (3)'s `B_ℓ` of the level: a light of no spread (one input light, or all of them at
    /// one point) is weighed by it at its centre, exactly.
    pub ramp: super::Ramp,
    /// Whether the level is the top one (`B_ℓ` stays 1 beyond `r_ℓ`).
    pub top: bool,
    /// `1 / r_ℓ`.
    pub inv_r: f32,
    /// The clamp of the point's fall-off, `h0`.
    pub h0: f32,
}

impl Averaged {
    /// The weight of a light of variance `variance` whose centre is `d` away.
    #[inline(always)]
    pub fn weight(self, d: f32, variance: Vec3) -> f32 {
        let sigma = sigma(variance, self.inv_r);
        if sigma == 0.0 {
            return self.ramp.weight(d);
        }
        let k = k(self.top, d * self.inv_r, sigma);
        let c = if d > self.h0 { d } else { self.h0 };
        k * (self.inv_r * c) * (self.inv_r * c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    /// `∫_0^d B̂(t)/t dt`, piece by piece.
    fn antiderivative(top: bool, d: f64) -> f64 {
        let ln2 = core::f64::consts::LN_2;
        if d <= 0.5 {
            0.0
        } else if d <= 1.0 {
            2.0 * (d - 0.5) - (2.0 * d).ln()
        } else if top {
            1.0 - ln2 + d.ln()
        } else if d <= 2.0 {
            1.0 - ln2 + 2.0 * d.ln() - (d - 1.0)
        } else {
            ln2
        }
    }

    fn ramp(top: bool, d: f64) -> f64 {
        let rise = 2.0 * d - 1.0;
        let w = if top { rise } else { rise.min(2.0 - d) };
        w.clamp(0.0, 1.0)
    }

    /// The mean of `B̂(d)/d²` over the sphere of radius `a` about a point at distance `u`: `d` is
    /// uniform in `d²` on `[|u − a|, u + a]`.
    fn shell(top: bool, u: f64, a: f64) -> f64 {
        if a == 0.0 {
            return if u > 0.0 { ramp(top, u) / (u * u) } else { 0.0 };
        }
        if u == 0.0 {
            return ramp(top, a) / (a * a);
        }
        (antiderivative(top, u + a) - antiderivative(top, (u - a).abs())) / (2.0 * u * a)
    }

    /// `k(ρ, σ)` in f64 by composite Simpson over the shell radius, split where a shell's ends
    /// cross the ramp's bends — an independent quadrature of the same integral as the table's
    /// generator (which uses Gauss–Legendre).
    fn exact(top: bool, rho: f64, sigma: f64) -> f64 {
        if sigma == 0.0 {
            return shell(top, rho, 0.0);
        }
        let big_r = f64::from(RADIUS_PER_SPREAD) * sigma;
        let mut cuts = alloc::vec![0.0, big_r];
        let kinks: &[f64] = if top { &[0.5, 1.0] } else { &[0.5, 1.0, 2.0] };
        for &k in kinks {
            for a in [k - rho, rho - k, k + rho] {
                if a > 0.0 && a < big_r {
                    cuts.push(a);
                }
            }
        }
        if rho > 0.0 && rho < big_r {
            cuts.push(rho);
        }
        cuts.sort_by(f64::total_cmp);
        let (mut num, mut den) = (0.0, 0.0);
        for w in cuts.windows(2) {
            let n = 64;
            let hstep = (w[1] - w[0]) / n as f64;
            for i in 0..=n {
                let a = w[0] + i as f64 * hstep;
                let c = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                let density = a * a * (1.0 - (a / big_r).powi(2));
                num += c * hstep / 3.0 * density * shell(top, rho, a);
                den += c * hstep / 3.0 * density;
            }
        }
        num / den
    }

    /// Every entry of both tables against the integral, to f32's rounding and the quadratures'
    /// error (1e-6 of the largest value, 1/ρ² near ρ = ½, or 2e-6 relative).
    #[wasm_bindgen_test(unsupported = test)]
    fn the_table_is_the_integral() {
        for (top, rows) in [(false, &MIDDLE[..]), (true, &TOP[..])] {
            for (i, row) in rows.iter().enumerate() {
                for (j, &got) in row.iter().enumerate() {
                    let (rho, sigma) = (i as f64 / 32.0, j as f64 / 32.0);
                    let want = exact(top, rho, sigma);
                    let err = (f64::from(got) - want).abs();
                    assert!(
                        err <= 2e-6 * want.abs() + 1e-6,
                        "top {top} ρ {rho} σ {sigma}: table {got}, integral {want}"
                    );
                }
            }
        }
    }

    /// Beyond the table the top shape is the series; it meets the last row.
    #[wasm_bindgen_test(unsupported = test)]
    fn the_series_meets_the_table() {
        let last = TOP.len() - 1;
        for (j, &row) in TOP[last].iter().enumerate() {
            let sigma = j as f32 / 32.0;
            let series = top_series(last as f32 / 32.0, sigma);
            assert!(
                (row - series).abs() <= 1e-6 * row,
                "σ {sigma}: {row} vs {series}"
            );
        }
        // Far away the ball is a point: k → 1/ρ².
        assert!((k(true, 1e4, 0.5) * 1e8 - 1.0).abs() < 1e-6);
    }

    /// A point (σ = 0) is eq. (3) at its centre; the middle shape ends where its ball leaves
    /// `2 r_ℓ`; the weight is continuous across the table's rows and columns.
    #[wasm_bindgen_test(unsupported = test)]
    fn points_are_eq_3_and_the_edges_are_continuous() {
        for rho in [0.25f32, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0] {
            let b = ramp(false, f64::from(rho)) as f32;
            assert!((k(false, rho, 0.0) * rho * rho - b).abs() < 1e-6, "{rho}");
        }
        for sigma in [0.0f32, 0.1, 0.5, 1.0] {
            let end = 2.0 + RADIUS_PER_SPREAD * sigma;
            assert_eq!(k(false, end + 1e-6, sigma), 0.0, "σ {sigma}");
            assert!(
                k(false, end - 0.05, sigma) > 0.0 || sigma == 0.0,
                "σ {sigma}"
            );
        }
        let mut last = k(false, 0.0, 0.3);
        for i in 1..=4000 {
            let now = k(false, i as f32 / 1000.0, 0.3);
            assert!(
                (now - last).abs() < 0.01,
                "a jump at ρ = {}",
                i as f32 / 1000.0
            );
            last = now;
        }
    }

    /// The variance's spread: the trace's third, clamped at σ = 1, a NaN or a negative rounding 0.
    #[wasm_bindgen_test(unsupported = test)]
    fn sigma_of_a_variance() {
        assert_eq!(sigma(Vec3::new(3.0, 0.0, 0.0), 1.0), 1.0);
        assert_eq!(sigma(Vec3::splat(0.25), 2.0), 1.0);
        assert!((sigma(Vec3::splat(0.04), 2.0) - 0.4).abs() < 1e-6);
        assert_eq!(sigma(Vec3::splat(-1e-9), 1.0), 0.0);
        assert_eq!(sigma(Vec3::NAN, 1.0), 0.0);
    }
}
