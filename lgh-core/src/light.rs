//! Point lights, the input set `S0` of the paper.

use alloc::vec::Vec;
use glam::Vec3;

use crate::error::{BuildError, MAX_LIGHTS};

/// Rec. 709 luminance weights: `‖I‖` in the paper (eq. 2) is the luminance of an RGB intensity.
pub const LUMINANCE_WEIGHTS: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Luminance `‖I‖` of an RGB triple (Rec. 709 weights).
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::luminance;
///
/// assert_eq!(luminance(Vec3::X), 0.2126);
/// assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6); // the weights sum to 1
/// ```
#[inline]
#[must_use]
pub fn luminance(rgb: Vec3) -> f32 {
    rgb.dot(LUMINANCE_WEIGHTS)
}

/// An input point light `j ∈ S0`: position `p0_j` and RGB radiant intensity `I0_j` (W/sr).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct PointLight {
    /// Position `p0_j`.
    pub position: Vec3,
    /// RGB radiant intensity `I0_j` in W/sr: every channel finite, the luminance ≥ 0. A channel
    /// may be negative — a colour outside Rec. 709's gamut, as Blender's blackbody below about
    /// 1900 K — for the hierarchy, brute force and Ward's method;
    /// the light octree and Lightcuts take non-negative channels only ([`Channels`]).
    pub intensity: Vec3,
}

impl PointLight {
    /// A light at `position` with RGB intensity `intensity`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::PointLight;
    ///
    /// let light = PointLight::new(Vec3::new(1.0, 2.0, 3.0), Vec3::splat(0.5));
    /// assert_eq!(light.position.y, 2.0);
    /// assert_eq!(light.intensity, Vec3::splat(0.5));
    /// ```
    #[must_use]
    pub const fn new(position: Vec3, intensity: Vec3) -> Self {
        PointLight {
            position,
            intensity,
        }
    }
}

/// Which RGB intensities a backend takes ([`validate_intensity`]).
///
/// The hierarchy and brute force are linear in each light's intensity, so a colour outside Rec.
/// 709's gamut — a negative channel, as Blender's blackbody gives below about 1900 K and Cycles
/// keeps in its volumes' emission — adds exactly what it should wherever the luminance that
/// weighs the lights (eq. 2's `‖I‖`) stays non-negative; Ward's method, over brute force's
/// lights, ranks them by their largest channel in magnitude. A light of luminance 0 adds nothing
/// in the hierarchy (eq. 2 weighs it by 0) whatever its channels. The light octree's error
/// bounds and Lightcuts' representative ratios are bounds on non-negative channels, so those two
/// refuse them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channels {
    /// Finite channels whose luminance is ≥ 0; a channel may be negative (the hierarchy, brute
    /// force and so Ward's method, the GPU build).
    OutOfGamut,
    /// Finite channels, each ≥ 0 (the light octree, Lightcuts).
    NonNegative,
}

/// The one validation of a light set, shared by every backend (the hierarchy, brute force — and so
/// Ward's method —, the light octree and Lightcuts): at most [`MAX_LIGHTS`] lights
/// ([`check_count`]), finite positions, intensities as `channels` says; the first offending
/// light, in order, is reported.
pub(crate) fn validate_lights(lights: &[PointLight], channels: Channels) -> Result<(), BuildError> {
    check_count(lights.len())?;
    for (index, l) in lights.iter().enumerate() {
        if !l.position.is_finite() {
            return Err(BuildError::NonFinitePosition { index });
        }
        validate_intensity(index, l.intensity, channels)?;
    }
    Ok(())
}

/// [`BuildError::TooManyLights`] if `count` exceeds [`MAX_LIGHTS`].
pub(crate) fn check_count(count: usize) -> Result<(), BuildError> {
    if count > MAX_LIGHTS {
        return Err(BuildError::TooManyLights { count });
    }
    Ok(())
}

/// Checks light `index`'s intensity `i`: [`BuildError::InvalidIntensity`] where a channel is NaN
/// or infinite or the luminance is negative, and [`BuildError::NegativeChannel`] where
/// `channels` is [`Channels::NonNegative`] and a channel is below 0.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::{validate_intensity, BuildError, Channels};
///
/// let blackbody_1500k = Vec3::new(3.264, 0.434, -0.064); // Cycles' colour: blue below 0
/// assert_eq!(validate_intensity(0, blackbody_1500k, Channels::OutOfGamut), Ok(()));
/// assert_eq!(
///     validate_intensity(0, blackbody_1500k, Channels::NonNegative),
///     Err(BuildError::NegativeChannel { index: 0 })
/// );
/// let dark = Vec3::new(0.1, -1.0, 0.0); // negative luminance
/// assert_eq!(
///     validate_intensity(7, dark, Channels::OutOfGamut),
///     Err(BuildError::InvalidIntensity { index: 7 })
/// );
/// ```
pub fn validate_intensity(index: usize, i: Vec3, channels: Channels) -> Result<(), BuildError> {
    if !i.is_finite() || luminance(i) < 0.0 {
        return Err(BuildError::InvalidIntensity { index });
    }
    if channels == Channels::NonNegative && i.min_element() < 0.0 {
        return Err(BuildError::NegativeChannel { index });
    }
    Ok(())
}

/// A light of the hierarchy: a level-ℓ light `i ∈ S_ℓ` (a grid vertex) or, at level 0, an input light.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct GridLight {
    /// Illumination centre `p_ℓi` (eq. 2); the light's position for shading.
    pub position: Vec3,
    /// Total intensity `I_ℓi = Σ_j w_ij I0_j` (eq. 1).
    pub intensity: Vec3,
    /// Per-axis variance `σ²_ℓi` of the represented light positions (eq. 4); zero at level 0.
    pub variance: Vec3,
    /// Size `s_ℓi`: the weighted mean distance of the represented lights from the centre (eq. 5).
    pub size: f32,
    /// `‖I_ℓi‖`, the luminance of `intensity` (used for weak-light pruning).
    pub luminance: f32,
}

/// A light is reported by queries if it is not dark and not weaker than the weak-light threshold.
#[inline]
pub(crate) fn is_reported(luminance: f32, threshold: f32) -> bool {
    luminance > 0.0 && luminance >= threshold
}

/// Lanes of the distance scan.
const LANES: usize = 8;

/// Which lights a [`LevelLights`] holds, so what it stores of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LevelKind {
    /// Level 0: the input point lights `S0`, whose variance and size are zero (not stored).
    Input,
    /// A level ℓ ≥ 1 of grid lights, each with its variance (eq. 4) and size (eq. 5).
    Grid,
}

/// The inner edge of the shell a [`LevelLights::scan`] reports: the lights at or within it are
/// left out. A level's blending weight `B_ℓ` is zero at and inside `r_{ℓ−1}` (eq. 3), so the query
/// of level ℓ ≥ 1 passes `Radius2(r_{ℓ−1}²)`; level 0 has no inner radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Inner {
    /// No inner radius: every distance is beyond it (the ball `d² ≤ outer²`).
    None,
    /// The squared inner radius: a light is reported only where `d² > r²`.
    Radius2(f32),
}

impl Inner {
    /// A bound every reported squared distance exceeds, for the scan's one comparison per lane:
    /// the squared radius, or for [`Inner::None`] −1, which every squared distance exceeds (a sum
    /// of squares is ≥ 0 or NaN, and a NaN one fails the outer test as well), so `None` drops
    /// nothing, exactly as no inner test at all.
    #[inline(always)]
    fn below2(self) -> f32 {
        match self {
            Inner::None => -1.0,
            Inner::Radius2(r2) => r2,
        }
    }
}

/// What a query's closure returns per light: summed by value so it can live in registers.
pub(crate) trait Contribution: Copy {
    /// The empty sum.
    const ZERO: Self;
    /// `self + other`.
    fn add(self, other: Self) -> Self;
}

impl Contribution for () {
    const ZERO: Self = ();
    #[inline(always)]
    fn add(self, _: Self) -> Self {}
}

impl Contribution for Vec3 {
    const ZERO: Self = Vec3::ZERO;
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        self + other
    }
}

/// Receives the lights a [`LevelLights::scan`] finds (a trait rather than a closure so the hot
/// path can be forced inline) and returns what each contributes, if anything.
pub(crate) trait Hit {
    /// What a light contributes.
    type Out: Contribution;
    /// Light `index` lies at distance `d`.
    fn hit(&mut self, index: usize, d: f32) -> Option<Self::Out>;
}

impl<R: Contribution, F: FnMut(usize, f32) -> Option<R>> Hit for F {
    type Out = R;
    #[inline(always)]
    fn hit(&mut self, index: usize, d: f32) -> Option<R> {
        self(index, d)
    }
}

/// The lights of one level, stored as structure-of-arrays: the radius query scans positions eight
/// at a time and touches intensities, variances and sizes only for lights that contribute.
/// Level 0 stores no variance or size (they are zero).
#[derive(Clone, Debug, Default)]
pub struct LevelLights {
    /// Positions as the radius query sees them: NaN for lights it must not report (dark, or weaker
    /// than `threshold`), so the distance test drops them at no cost. Padded with LANES − 1 NaNs.
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    /// The lights' actual positions.
    position: Vec<Vec3>,
    /// Weak-light threshold of this level (0: only dark lights are skipped).
    threshold: f32,
    luminance: Vec<f32>,
    intensity: Vec<Vec3>,
    variance: Vec<Vec3>,
    size: Vec<f32>,
    /// The largest `tr σ²/3` (eq. 4) of the level's lights, dark ones included (0 at level 0):
    /// the square of the spread [`crate::CoarseSpread::Averaged`] widens the level's support
    /// by, kept here so that a blending is made without a pass over the lights (the square
    /// root, being monotone, is taken once, in [`max_spread`](Self::max_spread)).
    max_spread_squared: f32,
}

/// Bit-for-bit equality (so NaN padding compares equal and −0.0 differs from 0.0): "the same
/// hierarchy" in the determinism guarantees means this.
impl PartialEq for LevelLights {
    fn eq(&self, other: &Self) -> bool {
        fn bits(v: &[f32]) -> impl Iterator<Item = u32> + '_ {
            v.iter().map(|f| f.to_bits())
        }
        fn bits3(v: &[Vec3]) -> impl Iterator<Item = u32> + '_ {
            v.iter().flat_map(|f| f.to_array()).map(|f| f.to_bits())
        }
        self.threshold.to_bits() == other.threshold.to_bits()
            && bits(&self.x).eq(bits(&other.x))
            && bits(&self.y).eq(bits(&other.y))
            && bits(&self.z).eq(bits(&other.z))
            && bits3(&self.position).eq(bits3(&other.position))
            && bits(&self.luminance).eq(bits(&other.luminance))
            && bits(&self.size).eq(bits(&other.size))
            && bits3(&self.intensity).eq(bits3(&other.intensity))
            && bits3(&self.variance).eq(bits3(&other.variance))
    }
}

/// The square of a light's spread, `s² = tr σ²/3`: the variance, per axis, of an isotropic
/// cloud with the variance `σ²` of eq. (4) ([`crate::CoarseSpread::Averaged`]'s ball); 0 for
/// a point, a negative rounding or a dark light's NaN.
#[inline]
fn spread_squared(variance: Vec3) -> f32 {
    ((variance.x + variance.y + variance.z) * (1.0 / 3.0)).max(0.0)
}

/// A light's spread `s = √(tr σ²/3)`, the standard deviation per axis of
/// [`spread_squared`]'s cloud.
#[inline]
#[must_use]
pub(crate) fn spread_of(variance: Vec3) -> f32 {
    crate::math::sqrt(spread_squared(variance))
}

impl LevelLights {
    /// No lights.
    pub const EMPTY: LevelLights = LevelLights {
        x: Vec::new(),
        y: Vec::new(),
        z: Vec::new(),
        position: Vec::new(),
        threshold: 0.0,
        luminance: Vec::new(),
        intensity: Vec::new(),
        variance: Vec::new(),
        size: Vec::new(),
        max_spread_squared: 0.0,
    };

    /// Stores `lights` of a level of kind `kind`; for [`LevelKind::Input`] variance and size are
    /// dropped (they must be zero). Queries will report only lights with luminance > 0 and
    /// ≥ `threshold`.
    pub(crate) fn from_lights(
        lights: impl ExactSizeIterator<Item = GridLight>,
        kind: LevelKind,
        threshold: f32,
    ) -> Self {
        let points = kind == LevelKind::Input;
        let n = lights.len();
        let mut out = LevelLights {
            x: Vec::with_capacity(n + LANES),
            y: Vec::with_capacity(n + LANES),
            z: Vec::with_capacity(n + LANES),
            position: Vec::with_capacity(n),
            threshold,
            luminance: Vec::with_capacity(n),
            intensity: Vec::with_capacity(n),
            variance: Vec::with_capacity(if points { 0 } else { n }),
            size: Vec::with_capacity(if points { 0 } else { n }),
            max_spread_squared: 0.0,
        };
        for l in lights {
            let p = out.scanned(l.position, l.luminance);
            out.x.push(p.x);
            out.y.push(p.y);
            out.z.push(p.z);
            out.position.push(l.position);
            out.luminance.push(l.luminance);
            out.intensity.push(l.intensity);
            if !points {
                out.variance.push(l.variance);
                out.size.push(l.size);
                // A dark light's NaN variance counts as no spread.
                out.max_spread_squared = out.max_spread_squared.max(spread_squared(l.variance));
            }
        }
        for _ in 1..LANES {
            out.x.push(f32::NAN);
            out.y.push(f32::NAN);
            out.z.push(f32::NAN);
        }
        out
    }

    /// The position the radius query scans for a light at `p` with luminance `lum`.
    #[inline]
    fn scanned(&self, p: Vec3, lum: f32) -> Vec3 {
        if is_reported(lum, self.threshold) {
            p
        } else {
            Vec3::NAN
        }
    }

    /// Number of lights.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// assert_eq!(level0.len(), 2);
    /// assert!(lgh.level(1).len() >= 8); // every corner of an occupied cell
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// True if the level has no lights.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// assert!(!level0.is_empty());
    /// assert!(lgh.level(lgh.max_level() + 1).is_empty());
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Light `i`. Panics if `i >= len()`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// let light = level0.get(0);
    /// assert_eq!((light.variance, light.size), (Vec3::ZERO, 0.0)); // input lights are points
    /// assert_eq!(light.position, level0.position(0));
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn get(&self, i: usize) -> GridLight {
        GridLight {
            position: self.position(i),
            intensity: self.intensity[i],
            variance: self.variance.get(i).copied().unwrap_or(Vec3::ZERO),
            size: self.size.get(i).copied().unwrap_or(0.0),
            luminance: self.luminance[i],
        }
    }

    /// Position (illumination centre) of light `i`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// let mut positions: Vec<Vec3> = (0..level0.len()).map(|i| level0.position(i)).collect();
    /// positions.sort_by(|a, b| a.y.total_cmp(&b.y));
    /// assert_eq!(positions, [Vec3::ZERO, Vec3::Y]);
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn position(&self, i: usize) -> Vec3 {
        self.position[i]
    }

    /// True if queries report light `i`: it is not dark and not weaker than the level's
    /// weak-light threshold.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// // The dark light is never reported.
    /// let reported: Vec<bool> = (0..2).map(|i| level0.is_reported(i)).collect();
    /// assert_eq!(reported.iter().filter(|&&r| r).count(), 1);
    /// assert!((0..2).all(|i| level0.is_reported(i) == (level0.intensity(i) != Vec3::ZERO)));
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn is_reported(&self, i: usize) -> bool {
        is_reported(self.luminance[i], self.threshold)
    }

    /// Luminance `‖I‖` of light `i`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{luminance, GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// assert!((0..2).all(|i| level0.luminance(i) == luminance(level0.intensity(i))));
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn luminance(&self, i: usize) -> f32 {
        self.luminance[i]
    }

    /// Intensity of light `i`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// let total: Vec3 = (0..level0.len()).map(|i| level0.intensity(i)).sum();
    /// assert_eq!(total, Vec3::X);
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn intensity(&self, i: usize) -> Vec3 {
        self.intensity[i]
    }

    /// All lights, in index order.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::X), PointLight::new(Vec3::Y, Vec3::ZERO)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = lgh.level(0);
    /// assert_eq!(level0.iter().len(), 2);
    /// assert!(level0.iter().enumerate().all(|(i, l)| l == level0.get(i)));
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn iter(&self) -> impl ExactSizeIterator<Item = GridLight> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// All intensities, in index order.
    pub(crate) fn intensities(&self) -> &[Vec3] {
        &self.intensity
    }

    /// All luminances, in index order.
    pub(crate) fn luminances(&self) -> &[f32] {
        &self.luminance
    }

    /// Sets the weak-light threshold: the lights weaker than it are no longer reported.
    pub(crate) fn set_threshold(&mut self, threshold: f32) {
        self.threshold = threshold;
        for i in 0..self.len() {
            let p = self.scanned(self.position[i], self.luminance[i]);
            (self.x[i], self.y[i], self.z[i]) = (p.x, p.y, p.z);
        }
    }

    /// Replaces the intensity (and luminance) of light `i`.
    pub(crate) fn set_intensity(&mut self, i: usize, intensity: Vec3) {
        self.intensity[i] = intensity;
        self.luminance[i] = luminance(intensity);
        let p = self.scanned(self.position[i], self.luminance[i]);
        (self.x[i], self.y[i], self.z[i]) = (p.x, p.y, p.z);
    }

    /// Calls `hit.hit(i, d)` for every light `i` in `start..end` whose distance `d` from `x` lies
    /// beyond `inner` (see [`Inner`]) with `d² ≤ outer2`, in increasing `i`, and returns the sum
    /// and number of the contributions it reports. Distances are computed eight lanes at a time.
    #[inline(always)]
    pub(crate) fn scan<H: Hit>(
        &self,
        start: usize,
        end: usize,
        x: Vec3,
        inner: Inner,
        outer2: f32,
        hit: &mut H,
    ) -> (H::Out, u32) {
        let inner2 = inner.below2();
        let mut sum = H::Out::ZERO;
        let mut count = 0u32;
        // Whole chunks of LANES from `start`; the position arrays carry LANES − 1 NaN entries of
        // padding, so the last chunk may read past `end` (those lanes are masked off).
        let mut i = start;
        while i < end {
            let (cx, cy, cz) = (
                &self.x[i..i + LANES],
                &self.y[i..i + LANES],
                &self.z[i..i + LANES],
            );
            let mut d2 = [0.0f32; LANES];
            let mut mask = 0u32;
            for k in 0..LANES {
                let (dx, dy, dz) = (cx[k] - x.x, cy[k] - x.y, cz[k] - x.z);
                d2[k] = dx * dx + dy * dy + dz * dz;
                mask |= ((d2[k] > inner2) as u32 & (d2[k] <= outer2) as u32) << k;
            }
            if end - i < LANES {
                mask &= (1u32 << (end - i)) - 1;
            }
            if mask != 0 {
                // Square roots of the whole chunk at once (one vector instruction per 4 lanes).
                for v in d2.iter_mut() {
                    *v = crate::math::sqrt(*v);
                }
            }
            while mask != 0 {
                let k = mask.trailing_zeros() as usize;
                if let Some(r) = hit.hit(i + k, d2[k]) {
                    sum = sum.add(r);
                    count += 1;
                }
                mask &= mask - 1;
            }
            i += LANES;
        }
        (sum, count)
    }

    /// Variance of light `i` (zero at level 0).
    #[inline]
    pub(crate) fn variance(&self, i: usize) -> Vec3 {
        self.variance.get(i).copied().unwrap_or(Vec3::ZERO)
    }

    /// The largest spread `√(tr σ²/3)` (eq. 4) of the level's lights (0 at level 0).
    #[inline]
    pub(crate) fn max_spread(&self) -> f32 {
        crate::math::sqrt(self.max_spread_squared)
    }

    /// Size of light `i` (zero at level 0).
    #[inline]
    pub(crate) fn size(&self, i: usize) -> f32 {
        self.size.get(i).copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    #[wasm_bindgen_test(unsupported = test)]
    fn luminance_weights_sum_to_one() {
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
        assert_eq!(luminance(Vec3::ZERO), 0.0);
    }

    /// The count check every backend's validation starts with (a slice of more than
    /// `MAX_LIGHTS` lights cannot be allocated in a test, so the check is tested on the length).
    #[wasm_bindgen_test(unsupported = test)]
    fn more_than_max_lights_are_rejected() {
        assert_eq!(check_count(0), Ok(()));
        assert_eq!(check_count(MAX_LIGHTS), Ok(()));
        assert_eq!(
            check_count(MAX_LIGHTS + 1),
            Err(BuildError::TooManyLights {
                count: MAX_LIGHTS + 1
            })
        );
        assert_eq!(
            check_count(usize::MAX),
            Err(BuildError::TooManyLights { count: usize::MAX })
        );
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn the_first_bad_light_is_reported() {
        let good = PointLight::new(Vec3::ZERO, Vec3::ONE);
        let nan = PointLight::new(Vec3::new(0.0, f32::NAN, 0.0), Vec3::ONE);
        let negative = PointLight::new(Vec3::ZERO, Vec3::new(1.0, -1.0, 0.0));
        let infinite = PointLight::new(Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0));
        let out_of_gamut = PointLight::new(Vec3::ZERO, Vec3::new(5.41, -0.2, -0.08));
        for channels in [Channels::OutOfGamut, Channels::NonNegative] {
            assert_eq!(validate_lights(&[], channels), Ok(()));
            assert_eq!(validate_lights(&[good, good], channels), Ok(()));
            assert_eq!(
                validate_lights(&[good, negative, nan], channels),
                Err(BuildError::InvalidIntensity { index: 1 })
            );
            assert_eq!(
                validate_lights(&[good, nan, negative], channels),
                Err(BuildError::NonFinitePosition { index: 1 })
            );
            assert_eq!(
                validate_lights(&[good, good, infinite], channels),
                Err(BuildError::InvalidIntensity { index: 2 })
            );
        }
        assert_eq!(
            validate_lights(&[good, out_of_gamut], Channels::OutOfGamut),
            Ok(())
        );
        assert_eq!(
            validate_lights(&[good, out_of_gamut], Channels::NonNegative),
            Err(BuildError::NegativeChannel { index: 1 })
        );
    }
}
