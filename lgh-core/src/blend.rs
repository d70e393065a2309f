//! Blending functions `B_ℓ` (eq. 3, Fig. 3) and the light fall-off `g`.
//!
//! With `r_ℓ = α h_ℓ` (so `r_ℓ = 2 r_{ℓ−1}` and `r_0 = α h_1 / 2`):
//! - `B_0(d) = 1` for `d ≤ r_0`, falling linearly to 0 at `r_1`;
//! - `B_ℓ` (0 < ℓ < ℓ_max) rises linearly from 0 at `r_{ℓ−1}` to 1 at `r_ℓ` and falls to 0 at `r_{ℓ+1}`;
//! - `B_ℓmax` rises from 0 at `r_{ℓmax−1}` to 1 at `r_ℓmax` and stays 1.
//!
//! Each piece is evaluated as `a = d / r_ℓ` with one reciprocal per level, the reciprocals being
//! exact powers-of-two multiples of `1 / r_0`. On the overlap `[r_ℓ, r_{ℓ+1}]` the two non-zero
//! weights are then `2 − a` and `a − 1` with `a ∈ [1, 2]`; both subtractions are exact (Sterbenz),
//! so `Σ_ℓ B_ℓ(d) = 1` holds exactly in floating point, not just approximately.

use glam::Vec3;

use crate::error::QueryError;

mod spread;
mod spread_table;

pub(crate) use spread::Averaged;
pub use spread::CoarseSpread;

/// The most levels above level 0 a hierarchy may have.
pub const MAX_LEVEL: u8 = 21;

/// Clamped inverse-square fall-off `g(d) = 1 / max(d, h0)²` (paper Sec. 6: distances are clamped to
/// `h0` to avoid the point-light singularity).
///
/// ```
/// use lgh_core::falloff;
///
/// assert_eq!(falloff(2.0, 0.5), 0.25); // 1 / d²
/// assert_eq!(falloff(0.1, 0.5), 4.0); // clamped at h0: 1 / h0²
/// ```
#[inline(always)]
#[must_use]
pub fn falloff(d: f32, h0: f32) -> f32 {
    let c = if d > h0 { d } else { h0 };
    1.0 / (c * c)
}

/// α and the influence radii `r_ℓ = α h_ℓ` of one hierarchy: everything a query needs to weight
/// levels. Make one with [`LightingGridHierarchy::blending`](crate::LightingGridHierarchy::blending)
/// (or [`Blending::new`]) once, and reuse it for every query.
///
/// The weights of all levels are a partition of unity (eq. 3), exactly:
///
/// ```
/// use lgh_core::Blending;
///
/// let blending = Blending::new(2.0, 0.5, 4)?; // α = 2, h1 = 0.5, ℓ_max = 4
/// assert_eq!(blending.radius(0), 0.5); // r_0 = α h_1 / 2
/// assert_eq!(blending.radius(2), 2.0); // r_2 = α h_2 = α · 2 h_1
/// for d in [0.0, 0.3, 0.77, 1.5, 2.9, 7.0, 100.0] {
///     let sum: f32 = (0..=4).map(|l| blending.weight(l, d)).sum();
///     assert_eq!(sum, 1.0);
/// }
/// # Ok::<(), lgh_core::QueryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blending {
    alpha: f32,
    h1: f32,
    max_level: u8,
    /// `r_ℓ` for ℓ = 0..=MAX_LEVEL.
    radius: [f32; MAX_LEVEL as usize + 1],
    /// Eq. (3)'s blending, or hard level switches (a flickering variant).
    switches: Switches,
    /// Where a coarse light's weight and fall-off are taken ([`CoarseSpread`]).
    spread: CoarseSpread,
    /// Per level, how far beyond eq. (3)'s support a light's weight reaches: the largest radius
    /// `R = √7 s` of the level's lights' balls with [`CoarseSpread::Averaged`], else 0.
    reach: [f32; MAX_LEVEL as usize + 1],
    /// Per level `(a, c1, b, c2)` with `B_ℓ(d) = clamp(min(a d + c1, c2 − b d), 0, 1)`: the rising and
    /// falling ramps, `a = 1 / r_{ℓ−1}`, `b = 1 / r_ℓ` (exact powers-of-two multiples of `1 / r_0`),
    /// or a constant 1 where a level has no ramp on that side.
    ramps: [[f32; 4]; MAX_LEVEL as usize + 1],
}

/// Checks the paper's α: a finite number above 0.
///
/// ```
/// use lgh_core::{check_alpha, QueryError};
///
/// assert_eq!(check_alpha(2.0), Ok(()));
/// assert_eq!(check_alpha(0.0), Err(QueryError::InvalidAlpha { alpha: 0.0 }));
/// assert!(check_alpha(f32::NAN).is_err());
/// ```
pub fn check_alpha(alpha: f32) -> Result<(), QueryError> {
    if alpha.is_finite() && alpha > 0.0 {
        Ok(())
    } else {
        Err(QueryError::InvalidAlpha { alpha })
    }
}

impl Blending {
    /// Blending for a hierarchy with level-1 spacing `h1` and top level `max_level`.
    pub fn new(alpha: f32, h1: f32, max_level: u8) -> Result<Self, QueryError> {
        check_alpha(alpha)?;
        if max_level > MAX_LEVEL {
            return Err(QueryError::InvalidAlpha { alpha });
        }
        let r0 = alpha * h1 * 0.5;
        let inv0 = 1.0 / r0;
        let mut radius = [0.0; MAX_LEVEL as usize + 1];
        let mut inv_radius = [0.0; MAX_LEVEL as usize + 1];
        let mut scale = 1.0f32;
        for l in 0..=MAX_LEVEL as usize {
            radius[l] = r0 * scale;
            inv_radius[l] = inv0 / scale;
            scale *= 2.0;
        }
        let mut ramps = [[0.0, 1.0, 0.0, 1.0]; MAX_LEVEL as usize + 1];
        for (l, ramp) in ramps.iter_mut().enumerate().take(max_level as usize + 1) {
            if l > 0 {
                ramp[0] = inv_radius[l - 1];
                ramp[1] = -1.0;
            }
            if l < max_level as usize {
                ramp[2] = inv_radius[l];
                ramp[3] = 2.0;
            }
        }
        // The outermost radius a query uses is 2 r_ℓmax; it (and 1/r_0) must be finite and non-zero.
        let outer = 2.0 * radius[max_level as usize];
        if !(r0 > 0.0 && outer.is_finite() && inv0.is_finite()) {
            return Err(QueryError::InvalidAlpha { alpha });
        }
        Ok(Blending {
            alpha,
            h1,
            max_level,
            radius,
            ramps,
            switches: Switches::Blended,
            spread: CoarseSpread::Centre,
            reach: [0.0; MAX_LEVEL as usize + 1],
        })
    }

    /// The same radii with each coarse light's weight and fall-off averaged over its spread
    /// ([`CoarseSpread::Averaged`]), for lights whose largest spread `s = √(tr σ²/3)` (eq. 4) at
    /// level ℓ is `spreads[ℓ]`: each level's support grows by that light's radius `√7 s`. Made by
    /// [`LightingGridHierarchy::blending_with`](crate::LightingGridHierarchy::blending_with).
    #[must_use]
    pub(crate) fn with_spreads(mut self, spreads: &[f32; MAX_LEVEL as usize + 1]) -> Self {
        self.switches = Switches::Blended;
        self.spread = CoarseSpread::Averaged;
        let levels = 1..=self.max_level as usize;
        for ((reach, &s), &r) in self.reach[levels.clone()]
            .iter_mut()
            .zip(&spreads[levels.clone()])
            .zip(&self.radius[levels])
        {
            // σ is clamped at 1 (spread.rs), so no light's ball is wider than √7 r_ℓ.
            let s = s.min(r);
            *reach = if s > 0.0 {
                s * spread::RADIUS_PER_SPREAD * (1.0 + 1e-5)
            } else {
                0.0
            };
        }
        self
    }

    /// How far beyond eq. (3)'s support a light of `level` may have a weight: with
    /// [`CoarseSpread::Averaged`], the largest radius `√7 s` of the level's lights' balls; 0 for
    /// [`CoarseSpread::Centre`], for level 0 and above `ℓ_max`.
    ///
    /// ```
    /// use lgh_core::Blending;
    ///
    /// assert_eq!(Blending::new(2.0, 1.0, 3)?.spread_reach(1), 0.0);
    /// # Ok::<(), lgh_core::QueryError>(())
    /// ```
    #[must_use]
    pub fn spread_reach(&self, level: u8) -> f32 {
        self.reach.get(level as usize).copied().unwrap_or(0.0)
    }

    /// Where a coarse light's weight and fall-off are taken: [`CoarseSpread::Centre`] unless made
    /// by [`LightingGridHierarchy::blending_with`](crate::LightingGridHierarchy::blending_with).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{CoarseSpread, GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> =
    ///     (0..8).map(|i| PointLight::new(Vec3::new(i as f32, 0.0, 0.0), Vec3::ONE)).collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// assert_eq!(lgh.blending(2.0)?.coarse_spread(), CoarseSpread::Centre);
    /// let averaged = lgh.blending_with(2.0, CoarseSpread::Averaged)?;
    /// assert_eq!(averaged.coarse_spread(), CoarseSpread::Averaged);
    /// // Hard switches take every light whole, at its centre.
    /// assert_eq!(averaged.with_hard_switches().coarse_spread(), CoarseSpread::Centre);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn coarse_spread(&self) -> CoarseSpread {
        self.spread
    }

    /// The same radii with *hard level switches* instead of the blending of eq. (3): each
    /// distance takes one level whole, the one whose `B_ℓ` is largest there (the finer one at
    /// the tie, `d = 1.5 r_ℓ`). One of the variants the paper names as flickering (Sec. 3.2: a
    /// light crossing a switch jumps between levels); an option only to measure that.
    ///
    /// ```
    /// use lgh_core::Blending;
    ///
    /// let hard = Blending::new(2.0, 0.5, 4)?.with_hard_switches();
    /// assert!(hard.hard_switches());
    /// for d in [0.0, 0.3, 0.77, 1.5, 2.9, 7.0, 100.0] {
    ///     let w: Vec<f32> = (0..=4).map(|l| hard.weight(l, d)).collect();
    ///     assert!(w.iter().all(|&x| x == 0.0 || x == 1.0));
    ///     assert_eq!(w.iter().sum::<f32>(), 1.0);
    /// }
    /// # Ok::<(), lgh_core::QueryError>(())
    /// ```
    #[must_use]
    pub fn with_hard_switches(mut self) -> Self {
        self.switches = Switches::Hard;
        self.spread = CoarseSpread::Centre;
        self.reach = [0.0; MAX_LEVEL as usize + 1];
        self
    }

    /// Whether the levels switch hard ([`with_hard_switches`](Self::with_hard_switches)).
    #[must_use]
    pub fn hard_switches(&self) -> bool {
        self.switches == Switches::Hard
    }

    /// The paper's α.
    #[must_use]
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// Level-1 spacing `h1` this blending was made for.
    #[must_use]
    pub fn h1(&self) -> f32 {
        self.h1
    }

    /// Top level `ℓ_max` this blending was made for.
    #[must_use]
    pub fn max_level(&self) -> u8 {
        self.max_level
    }

    /// Influence radius `r_ℓ = α h_ℓ` (with `h_0 = h_1 / 2`); infinite above [`MAX_LEVEL`].
    #[inline]
    #[must_use]
    pub fn radius(&self, level: u8) -> f32 {
        self.radius
            .get(level as usize)
            .copied()
            .unwrap_or(f32::INFINITY)
    }

    /// Distances `(inner, outer)` with a zero weight for every `d ≤ inner` and every `d ≥ outer`:
    /// eq. (3)'s `r_{ℓ−1}` and `2 r_ℓ` (0 for level 0, ∞ for the top level), widened by a relative
    /// 1e-6 so that rounding in [`weight`](Self::weight) can never put a non-zero weight outside;
    /// with [`CoarseSpread::Averaged`], widened on both sides by the level's largest ball radius
    /// `√7 s` too (the lights' balls reach that far beyond their centres). Levels above `ℓ_max`
    /// have no support.
    ///
    /// ```
    /// use lgh_core::Blending;
    ///
    /// let b = Blending::new(2.0, 1.0, 3)?; // r = 1, 2, 4, 8
    /// let (inner, outer) = b.support(1);
    /// assert!((inner - 1.0).abs() < 1e-5 && (outer - 4.0).abs() < 1e-5);
    /// assert_eq!(b.support(3).1, f32::INFINITY);
    /// # Ok::<(), lgh_core::QueryError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn support(&self, level: u8) -> (f32, f32) {
        let (inner, outer) = self.ramp_support(level);
        if level > self.max_level {
            return (inner, outer);
        }
        let reach = self.reach[level as usize];
        ((inner - reach).max(0.0), outer + reach)
    }

    /// Eq. (3)'s own support of `level`, `(r_{ℓ−1}, 2 r_ℓ)` widened by a relative 1e-6, whatever
    /// the coarse lights' spread: [`support`](Self::support) before the balls widen it.
    #[inline]
    #[must_use]
    pub(crate) fn ramp_support(&self, level: u8) -> (f32, f32) {
        if level > self.max_level {
            return (f32::INFINITY, f32::INFINITY);
        }
        let inner = if level == 0 {
            0.0
        } else {
            self.radius[level as usize - 1] * (1.0 - 1e-6)
        };
        let outer = if level == self.max_level {
            f32::INFINITY
        } else {
            2.0 * self.radius[level as usize] * (1.0 + 1e-6)
        };
        (inner, outer)
    }

    /// The blending weight `B_ℓ(d)` of level `level` at distance `d ≥ 0` (eq. 3, Fig. 3).
    /// Zero for levels above `ℓ_max`.
    #[inline(always)]
    #[must_use]
    pub fn weight(&self, level: u8, d: f32) -> f32 {
        self.ramp(level).weight(d)
    }

    /// The weight a light of level `level` with per-axis variance `variance` (eq. 4) gets with
    /// its centre `d` away: [`weight`](Self::weight) for [`CoarseSpread::Centre`] and for level 0;
    /// with [`CoarseSpread::Averaged`], `B_ℓ(d')/d'²` averaged over the light's ball, times
    /// `max(d, h0)²` (so that times the point's fall-off [`falloff`] it is that mean).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{falloff, CoarseSpread, GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> =
    ///     (0..64).map(|i| PointLight::new(Vec3::new(i as f32, 0.0, 0.0), Vec3::ONE)).collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let centre = lgh.blending(2.0)?;
    /// let averaged = lgh.blending_with(2.0, CoarseSpread::Averaged)?;
    /// let top = lgh.max_level();
    /// // A point is weighed at its centre either way...
    /// assert_eq!(averaged.weight_of(top, 1e3, Vec3::ZERO), centre.weight(top, 1e3));
    /// // ...and a spread light far from everything by its ball's mean of 1/d², above 1/d².
    /// let spread = Vec3::splat(lgh.h(top) * lgh.h(top) / 6.0);
    /// assert!(averaged.weight_of(top, 1e3, spread) > 1.0);
    /// assert_eq!(centre.weight_of(top, 1e3, spread), 1.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn weight_of(&self, level: u8, d: f32, variance: Vec3) -> f32 {
        self.level_weight(level).weight(d, || variance)
    }

    /// `B_ℓ` of one level, for evaluating many distances.
    #[inline(always)]
    pub(crate) fn ramp(&self, level: u8) -> Ramp {
        match self.ramps.get(level as usize) {
            Some(&r) if level <= self.max_level => Ramp(r, self.switches),
            _ => Ramp([0.0, -1.0, 0.0, -1.0], Switches::Blended), // always 0
        }
    }

    /// How one level's lights are weighted: by eq. (3)'s ramp, or averaged over their spread.
    #[inline(always)]
    pub(crate) fn level_weight(&self, level: u8) -> LevelWeight {
        match self.spread {
            CoarseSpread::Averaged if level >= 1 && level <= self.max_level => {
                let r = self.radius[level as usize];
                LevelWeight::Averaged(Averaged {
                    ramp: self.ramp(level),
                    top: level == self.max_level,
                    inv_r: 1.0 / r,
                    h0: self.h1 * 0.5,
                })
            }
            _ => LevelWeight::Ramp(self.ramp(level)),
        }
    }
}

/// How one level's lights are weighted ([`Blending::level_weight`]).
#[derive(Clone, Copy, Debug)]
pub(crate) enum LevelWeight {
    /// Eq. (3)'s `B_ℓ(d)` at the light's centre.
    Ramp(Ramp),
    /// `B_ℓ/d²` averaged over the light's ball, times `max(d, h0)²`.
    Averaged(Averaged),
}

impl LevelWeight {
    /// The weight of a light whose centre is `d` away; `variance` is asked for only when it is
    /// needed (level 0 stores none).
    #[inline(always)]
    pub fn weight(self, d: f32, variance: impl FnOnce() -> Vec3) -> f32 {
        match self {
            LevelWeight::Ramp(r) => r.weight(d),
            LevelWeight::Averaged(a) => a.weight(d, variance()),
        }
    }
}

/// `B_ℓ` of one level: `B_ℓ(d) = clamp(min(a d + c1, c2 − b d), 0, 1)` with `[a, c1, b, c2]`;
/// with hard switches ([`Blending::with_hard_switches`]), 1 where that is above ½ (or exactly ½
/// on its falling side) and 0 elsewhere.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ramp([f32; 4], Switches);

/// How a distance takes its levels: blended by eq. (3), or one level whole (the paper's
/// flickering variant, Sec. 3.2; [`Blending::with_hard_switches`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Switches {
    /// Eq. (3): the levels' weights overlap and sum to one.
    Blended,
    /// The level whose `B_ℓ` is largest takes the whole weight.
    Hard,
}

impl Ramp {
    /// `B_ℓ(d)`.
    #[inline(always)]
    pub fn weight(self, d: f32) -> f32 {
        let [a, c1, b, c2] = self.0;
        let (rise, fall) = (d * a + c1, c2 - d * b);
        let w = rise.min(fall).clamp(0.0, 1.0);
        if self.1 == Switches::Blended {
            return w;
        }
        // The two non-zero weights at any d are 2 − a' and a' − 1 of one a' = d / r_ℓ, so they
        // tie exactly at ½, where the falling one (the finer level) wins.
        if w > 0.5 || (w == 0.5 && fall <= rise) {
            1.0
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    proptest! {
        /// Partition of unity, exactly (see the module docs for why no tolerance is needed).
        #[wasm_bindgen_test(unsupported = test)]
        fn weights_sum_to_one(alpha in 0.01f32..64.0, h1 in 0.001f32..100.0, top in 0u8..=MAX_LEVEL,
                              d in 0.0f32..1e6) {
            let b = Blending::new(alpha, h1, top).unwrap();
            let sum: f32 = (0..=top).map(|l| b.weight(l, d)).sum();
            prop_assert_eq!(sum, 1.0);
        }

        /// Hard switches: every weight 0 or 1, exactly one level at each distance.
        #[wasm_bindgen_test(unsupported = test)]
        fn hard_switches_pick_one_level(alpha in 0.01f32..64.0, h1 in 0.001f32..100.0,
                                        top in 0u8..=MAX_LEVEL, d in 0.0f32..1e6) {
            let b = Blending::new(alpha, h1, top).unwrap().with_hard_switches();
            let w: alloc::vec::Vec<f32> = (0..=top).map(|l| b.weight(l, d)).collect();
            prop_assert!(w.iter().all(|&x| x == 0.0 || x == 1.0));
            prop_assert_eq!(w.iter().sum::<f32>(), 1.0);
            // The level taken is the one the smooth blending weighs most.
            let smooth = Blending::new(alpha, h1, top).unwrap();
            let taken = w.iter().position(|&x| x == 1.0).unwrap() as u8;
            for l in 0..=top {
                prop_assert!(smooth.weight(taken, d) >= smooth.weight(l, d));
            }
        }

        #[wasm_bindgen_test(unsupported = test)]
        fn weights_vanish_outside_support(alpha in 0.1f32..16.0, top in 1u8..8, d in 0.0f32..1e3) {
            let b = Blending::new(alpha, 1.0, top).unwrap();
            for l in 0..=top {
                let (inner, outer) = b.support(l);
                if d <= inner || d >= outer {
                    prop_assert_eq!(b.weight(l, d), 0.0);
                }
            }
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn shape_matches_figure_3() {
        let b = Blending::new(2.0, 1.0, 3).unwrap(); // r = 1, 2, 4, 8
        assert_eq!(b.radius(0), 1.0);
        assert_eq!(b.weight(0, 0.5), 1.0);
        assert_eq!(b.weight(0, 1.5), 0.5);
        assert_eq!(b.weight(1, 1.5), 0.5);
        assert_eq!(b.weight(1, 2.0), 1.0);
        assert_eq!(b.weight(1, 3.0), 0.5);
        assert_eq!(b.weight(3, 100.0), 1.0);
        assert_eq!(b.weight(3, 4.0), 0.0);
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn bad_alpha_is_an_error() {
        for a in [0.0, -1.0, f32::NAN, f32::INFINITY, 1e38] {
            assert!(Blending::new(a, 1.0, 20).is_err(), "{a}");
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn falloff_is_clamped() {
        assert_eq!(falloff(0.0, 0.5), 4.0);
        assert_eq!(falloff(2.0, 0.5), 0.25);
    }
}
