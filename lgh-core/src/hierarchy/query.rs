//! The radius query of the lighting grid hierarchy (paper Sec. 3, eq. 3): every light whose
//! blending weight `B_ℓ` is non-zero at a point, with its weighted intensity.

use core::ops::RangeInclusive;

use glam::Vec3;

use super::LightingGridHierarchy;
use crate::blend::{Blending, CoarseSpread, LevelWeight, MAX_LEVEL};
use crate::bricks::Ball;
use crate::error::QueryError;
use crate::light::{Contribution, Hit, Inner, LevelLights};
use crate::many_lights::{LightSample, Lobe};

/// Every level: what the unrestricted queries pass.
const ALL_LEVELS: RangeInclusive<u8> = 0..=u8::MAX;

impl LightingGridHierarchy {
    /// Blending parameters for this hierarchy and the paper's α (`r_ℓ = α h_ℓ`).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight, QueryError};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::ONE, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let blending = lgh.blending(2.0)?;
    /// assert_eq!(blending.radius(1), 2.0 * lgh.h1()); // r_1 = α h_1
    /// assert!(matches!(lgh.blending(-1.0), Err(QueryError::InvalidAlpha { .. })));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn blending(&self, alpha: f32) -> Result<Blending, QueryError> {
        Blending::new(alpha, self.h1(), self.max_level())
    }

    /// The blending at `alpha` with each coarse light weighted as `spread` says
    /// ([`CoarseSpread`]): for [`CoarseSpread::Averaged`], each level's support widened by its
    /// lights' largest spread. Make it again after [`update_intensities`](Self::update_intensities):
    /// the spreads follow the intensities.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{CoarseSpread, GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> =
    ///     (0..64).map(|i| PointLight::new(Vec3::new(i as f32, 0.0, 0.0), Vec3::ONE)).collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let centre = lgh.blending_with(2.0, CoarseSpread::Centre)?;
    /// assert_eq!(centre, lgh.blending(2.0)?);
    /// let averaged = lgh.blending_with(2.0, CoarseSpread::Averaged)?;
    /// assert!(averaged.support(1).1 > centre.support(1).1); // level 1 reaches further
    /// assert_eq!(averaged.support(0), centre.support(0)); // level 0's lights are points
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn blending_with(&self, alpha: f32, spread: CoarseSpread) -> Result<Blending, QueryError> {
        let blending = self.blending(alpha)?;
        Ok(match spread {
            CoarseSpread::Centre => blending,
            CoarseSpread::Averaged => blending.with_spreads(&self.spreads()),
        })
    }

    /// Per level ℓ ≥ 1, the largest spread `√(tr σ²/3)` (eq. 4) of its lights (0 at level 0),
    /// kept by each level since it was built.
    fn spreads(&self) -> [f32; MAX_LEVEL as usize + 1] {
        let mut out = [0.0f32; MAX_LEVEL as usize + 1];
        for (l, s) in out.iter_mut().enumerate().skip(1) {
            *s = self.level(l as u8).max_spread();
        }
        out
    }

    /// Calls `f(index, distance)` for every light of `level` whose position lies within `radius`
    /// of `x` and that queries report (see [`is_active`](Self::is_active)), using the level's
    /// index (no allocation). Useful for shadow precomputation and tests.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let x = Vec3::ONE;
    /// let mut near = Vec::new();
    /// lgh.lights_within(0, x, 1.0, |i, d| near.push((i, d)))?;
    /// assert_eq!(near.len(), 7); // the light at x and its 6 neighbours
    /// assert!(near.iter().all(|&(i, d)| d <= 1.0 && d == (lgh.level(0).position(i as usize) - x).length()));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn lights_within(
        &self,
        level: u8,
        x: Vec3,
        radius: f32,
        mut f: impl FnMut(u32, f32),
    ) -> Result<(), QueryError> {
        QueryError::check_point(x)?;
        if self.is_empty() || level > self.max_level() || radius.is_nan() || radius < 0.0 {
            return Ok(());
        }
        let lights = self.level(level);
        let r2 = radius * radius;
        let mut hit = |i: usize, d: f32| -> Option<()> {
            f(i as u32, d);
            Some(())
        };
        let report = |s: usize, e: usize| {
            lights.scan(s, e, x, Inner::None, r2, &mut hit);
        };
        self.for_each_range_within(level, x, radius, report);
        Ok(())
    }

    /// Like [`for_each_range`](Self::for_each_range), but the whole level at once at the top
    /// level or for an unbounded `radius`.
    #[inline]
    fn for_each_range_within(
        &self,
        level: u8,
        x: Vec3,
        radius: f32,
        mut f: impl FnMut(usize, usize),
    ) {
        if level == self.max_level() || !radius.is_finite() {
            f(0, self.level(level).len());
        } else {
            self.for_each_range(level, x, radius, f);
        }
    }

    /// Calls `f(start, end)` with ranges of light indices of `level` (< ℓ_max) that together hold
    /// every light whose position lies within `radius` of `x` (and possibly others).
    #[inline]
    fn for_each_range(&self, level: u8, x: Vec3, radius: f32, mut f: impl FnMut(usize, usize)) {
        // A hair wider than asked (relative, and 1e-4 of a cell absolute), so rounding of positions
        // and of the f64 culling never drops a light at the edge.
        let reach = |h: f64| radius as f64 * (1.0 + 1e-6) / h + 1e-4;
        if level == 0 {
            // Level-1 cells hold the level-0 lights; the cells of a brick and their lights are
            // contiguous.
            let ball = Ball {
                centre: self.local(x, 1),
                radius: reach(self.placement.h1),
                lo_pad: 0.0,
                hi_pad: 4.0,
            };
            self.cells0.for_each_brick_near(&ball, |first, n| {
                let s = self.cells0_starts[first as usize] as usize;
                let e = self.cells0_starts[(first + n) as usize] as usize;
                f(s, e)
            });
        } else {
            // A vertex's illumination centre lies within h_ℓ of it (pads −1 and 4).
            let ball = Ball {
                centre: self.local(x, level),
                radius: reach(self.h64(level)),
                lo_pad: -1.0,
                hi_pad: 4.0,
            };
            self.levels[level as usize - 1]
                .topo
                .index
                .for_each_brick_near(&ball, |first, n| f(first as usize, (first + n) as usize));
        }
    }

    /// Level-ℓ coordinates of `x` (world position relative to the origin, in units of `h_ℓ`).
    #[inline]
    fn local(&self, x: Vec3, level: u8) -> [f64; 3] {
        let inv = 1.0 / self.h64(level);
        let o = self.placement.origin;
        [
            (x.x as f64 - o[0]) * inv,
            (x.y as f64 - o[1]) * inv,
            (x.z as f64 - o[2]) * inv,
        ]
    }

    /// The lighting query of eq. (3): calls `f` once for every light (of any level) that contributes
    /// at `x`, i.e. whose blending weight `B_ℓ(d)` is non-zero at its distance `d = ‖x − p_ℓi‖`, with
    /// the weighted intensity `B_ℓ(d) I_ℓi`. Returns the number of calls.
    ///
    /// Visibility `V`, fall-off `g` (see [`falloff`](crate::falloff)), BRDF or phase function are the
    /// caller's. The query allocates nothing; the order of calls is fixed for a given hierarchy, α
    /// and `x`, so sums over them are deterministic.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let blending = lgh.blending(2.0)?;
    /// let mut calls = 0;
    /// let n = lgh.query(Vec3::new(10.0, 1.5, 1.5), &blending, |light| {
    ///     assert!(light.weight > 0.0 && light.weight <= 1.0);
    ///     calls += 1;
    /// })?;
    /// assert_eq!(n, calls);
    /// // Far from the lights only coarse levels are gathered: fewer calls than lights.
    /// assert!(calls > 0 && calls < 64);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query<F: FnMut(&LightSample)>(
        &self,
        x: Vec3,
        blending: &Blending,
        mut f: F,
    ) -> Result<u32, QueryError> {
        self.gather(x, blending, ALL_LEVELS, f32::INFINITY, |s| f(s))
            .map(|((), n)| n)
    }

    /// Like [`query`](Self::query), but sums what `f` returns for each light (radiance, say) and
    /// returns the sum with the number of lights. Prefer this to accumulating into a captured
    /// variable: the running sum stays in registers instead of memory.
    ///
    /// With a large α every light is within `r_0` of the point, so only level 0 contributes, at full
    /// weight: the sum is brute force's.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{
    ///     falloff, BruteForce, GridSettings, LightSample, LightingGridHierarchy, PointLight,
    /// };
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let x = Vec3::new(1.2, 5.0, 0.7);
    /// let shade = |s: &LightSample| s.intensity * falloff(s.distance, lgh.h0());
    /// let (sum, n) = lgh.query_sum(x, &lgh.blending(1000.0)?, shade)?;
    /// assert_eq!(n, 64);
    /// let exact = BruteForce::new(&lights)?.falloff_sum(x, lgh.h0())?;
    /// assert!(((sum - exact) / exact).abs().max_element() < 1e-5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn query_sum<F: FnMut(&LightSample) -> Vec3>(
        &self,
        x: Vec3,
        blending: &Blending,
        f: F,
    ) -> Result<(Vec3, u32), QueryError> {
        self.gather(x, blending, ALL_LEVELS, f32::INFINITY, f)
    }

    /// [`query`](Self::query) restricted to the lights of the levels in `levels`: the same
    /// lights with the same weights, in the same order, as the full query reports for those
    /// levels. A lighting cache splits eq. (3)'s sum this way: the finest level per point, the
    /// coarse levels interpolated (lgh-volume's `lighting_cache`).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let (blending, x) = (lgh.blending(2.0)?, Vec3::new(1.5, 1.5, 2.5));
    /// let mut all = Vec::new();
    /// lgh.query(x, &blending, |s| all.push((s.level, s.index)))?;
    /// let mut split = Vec::new();
    /// lgh.query_levels(x, &blending, 0..=0, |s| split.push((s.level, s.index)))?;
    /// assert!(split.iter().all(|&(level, _)| level == 0));
    /// lgh.query_levels(x, &blending, 1..=u8::MAX, |s| split.push((s.level, s.index)))?;
    /// assert_eq!(split, all);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query_levels<F: FnMut(&LightSample)>(
        &self,
        x: Vec3,
        blending: &Blending,
        levels: RangeInclusive<u8>,
        mut f: F,
    ) -> Result<u32, QueryError> {
        self.gather(x, blending, levels, f32::INFINITY, |s| f(s))
            .map(|((), n)| n)
    }

    /// `Ok` if `blending` is for this hierarchy's levels (its `h1` and top level), else
    /// [`QueryError::BlendingMismatch`].
    #[inline]
    pub(super) fn check_blending(&self, blending: &Blending) -> Result<(), QueryError> {
        if blending.h1() != self.h1() || blending.max_level() != self.max_level() {
            return Err(QueryError::BlendingMismatch);
        }
        Ok(())
    }

    /// The query of the levels in `levels`, of the lights within `reach` of `x` only (∞: every
    /// light whose weight is non-zero): `f` is called for each, and what it returns summed.
    #[inline]
    pub(super) fn gather<R: Contribution, F: FnMut(&LightSample) -> R>(
        &self,
        x: Vec3,
        blending: &Blending,
        levels: RangeInclusive<u8>,
        reach: f32,
        mut f: F,
    ) -> Result<(R, u32), QueryError> {
        QueryError::check_point(x)?;
        self.check_blending(blending)?;
        if self.level0.is_empty() {
            return Ok((R::ZERO, 0));
        }
        let wanted = |l: u8| levels.contains(&l);
        let top = self.max_level();
        let mut sum = R::ZERO;
        let mut count = 0u32;
        // Scans lights[start..end] of `level` and adds what they contribute.
        let mut scan = |level: u8,
                        lights: &LevelLights,
                        start: usize,
                        end: usize,
                        inner: Inner,
                        outer2: f32| {
            let mut hits = LevelHits {
                f: &mut f,
                weight: blending.level_weight(level),
                level,
                lights,
            };
            let (r, n) = lights.scan(start, end, x, inner, outer2, &mut hits);
            sum = sum.add(r);
            count += n;
        };

        // Level 0: lights in the level-1 cells that meet the ball of radius r_1 = α h_1. The cells of
        // a brick are contiguous, and so are their lights.
        let reach2 = reach * reach;
        if top == 0 {
            if wanted(0) {
                scan(0, &self.level0, 0, self.level0.len(), Inner::None, reach2);
            }
            return Ok((sum, count));
        }
        if wanted(0) {
            let outer = blending.support(0).1.min(reach);
            let outer2 = outer * outer;
            self.for_each_range(0, x, outer, |s, e| {
                scan(0, &self.level0, s, e, Inner::None, outer2)
            });
        }

        // Levels 0 < ℓ < ℓ_max: lights within 2 r_ℓ of x; a centre lies within h_ℓ of its vertex.
        for l in (1..top).filter(|&l| wanted(l)) {
            let level = &self.levels[l as usize - 1];
            let (inner, outer) = blending.support(l);
            let outer = outer.min(reach);
            let (inner_edge, outer2) = (Inner::Radius2(inner * inner), outer * outer);
            self.for_each_range(l, x, outer, |s, e| {
                scan(l, &level.lights, s, e, inner_edge, outer2)
            });
        }

        // The top level has no outer cutoff: every light beyond r_{ℓmax−1}.
        if !wanted(top) {
            return Ok((sum, count));
        }
        let (inner, _) = blending.support(top);
        let level = &self.levels[top as usize - 1];
        scan(
            top,
            &level.lights,
            0,
            level.lights.len(),
            Inner::Radius2(inner * inner),
            reach2,
        );
        Ok((sum, count))
    }
}

/// A coarse light [`LightingGridHierarchy::query_reaching`] finds: its level and index, its
/// centre's distance from the point and `B_ℓ` there (0 outside the level's support). Its
/// position, intensity and luminance are [`LightingGridHierarchy::level`]'s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reaching {
    /// Its level ℓ ≥ 1.
    pub level: u8,
    /// Its index within the level.
    pub index: u32,
    /// `d = ‖x − p_ℓi‖`.
    pub distance: f32,
    /// `B_ℓ(d)`.
    pub weight: f32,
}

impl LightingGridHierarchy {
    /// The coarse lights (levels ≥ 1) that can give `x` light when each input light `j` a
    /// coarse light stands for is blended at its *own* distance, `B_ℓ(‖x − p_j‖)`, instead of
    /// at the light's centre as in eq. (3). Beyond the paper.
    ///
    /// `extents(ℓ)` gives level ℓ's lights' extents — light `i`'s, `e_i`, at least the
    /// distance from its centre to the farthest input light it stands for — and the largest
    /// of them (a light past the slice's end counts as the largest). A light is reported when
    /// some point within `e_i` of its centre lies inside its level's support
    /// `(r_{ℓ−1}, 2 r_ℓ)`: `d + e_i > r_{ℓ−1}` and `d − e_i < 2 r_ℓ`. So no light any of whose
    /// input lights has a non-zero weight at its own distance is left out; since the weights
    /// of all levels sum to one at every distance, level 0 from
    /// [`query_levels`](Self::query_levels) and these lights together account for every
    /// input light exactly once (lgh-vpl's per-representative blending). (`2√3 h_ℓ` bounds
    /// any light's extent: its centre and its input lights lie in the cube of half-width
    /// `h_ℓ` about its vertex, eqs. 1, 2.) The blending's [`CoarseSpread`] does not enter:
    /// blending each input light at its own distance is what
    /// [`CoarseSpread::Averaged`] approximates, so the support is eq. (3)'s and each weight
    /// `B_ℓ(d)` at the light's centre.
    ///
    /// Returns the number of calls; the order is fixed, as in [`query`](Self::query).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> = (0..512u32)
    ///     .map(|i| Vec3::new((i % 8) as f32, (i / 8 % 8) as f32, (i / 64) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let (blending, x) = (lgh.blending(2.0)?, Vec3::new(3.2, 9.0, 4.1));
    /// let mut centred = Vec::new();
    /// lgh.query_levels(x, &blending, 1..=u8::MAX, |s| centred.push((s.level, s.index)))?;
    /// // Every light as wide as any can be.
    /// let widest = |level| (2.0 * 3f32.sqrt() * lgh.h(level), &[][..]);
    /// let mut reaching = Vec::new();
    /// lgh.query_reaching(x, &blending, widest, |r| {
    ///     let d = (lgh.level(r.level).position(r.index as usize) - x).length();
    ///     assert!((r.distance - d).abs() <= 1e-5 * d);
    ///     assert_eq!(r.weight, blending.weight(r.level, r.distance));
    ///     reaching.push((r.level, r.index));
    /// })?;
    /// // Every light eq. (3) gathers, and more near the supports' edges.
    /// assert!(centred.iter().all(|l| reaching.contains(l)));
    /// assert!(reaching.len() > centred.len());
    /// // The coarse lights' spread does not enter: the same lights, the same weights.
    /// let averaged = lgh.blending_with(2.0, lgh_core::CoarseSpread::Averaged)?;
    /// let mut same = Vec::new();
    /// lgh.query_reaching(x, &averaged, widest, |r| same.push((r.level, r.index)))?;
    /// assert_eq!(same, reaching);
    /// // Lights of no extent (each a single point at its centre): eq. (3)'s own.
    /// let points = |_| (0.0, &[][..]);
    /// let mut exact = Vec::new();
    /// lgh.query_reaching(x, &blending, points, |r| exact.push((r.level, r.index)))?;
    /// assert_eq!(exact, centred);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query_reaching<'e, F: FnMut(Reaching)>(
        &self,
        x: Vec3,
        blending: &Blending,
        extents: impl Fn(u8) -> (f32, &'e [f32]),
        mut f: F,
    ) -> Result<u32, QueryError> {
        QueryError::check_point(x)?;
        self.check_blending(blending)?;
        let top = self.max_level();
        let mut count = 0u32;
        for l in 1..=top {
            let lights = &self.levels[l as usize - 1].lights;
            let (inner, outer) = blending.ramp_support(l);
            let (widest, each) = extents(l);
            let widest = widest.max(0.0);
            let (scan_inner, scan_outer) = (inner - widest, outer + widest);
            let inner_edge = if scan_inner > 0.0 {
                Inner::Radius2(scan_inner * scan_inner)
            } else {
                Inner::None
            };
            let ramp = blending.ramp(l);
            let mut hit = |index: usize, d: f32| -> Option<()> {
                let e = each.get(index).copied().unwrap_or(widest);
                if d + e <= inner || d - e >= outer {
                    return None;
                }
                count += 1;
                f(Reaching {
                    level: l,
                    index: index as u32,
                    distance: d,
                    weight: ramp.weight(d),
                });
                Some(())
            };
            let outer2 = scan_outer * scan_outer;
            self.for_each_range_within(l, x, scan_outer, |s, e| {
                lights.scan(s, e, x, inner_edge, outer2, &mut hit);
            });
        }
        Ok(count)
    }
}

/// Hands one level's contributing lights to the caller's closure.
struct LevelHits<'a, F> {
    f: &'a mut F,
    weight: LevelWeight,
    level: u8,
    lights: &'a LevelLights,
}

impl<R: Contribution, F: FnMut(&LightSample) -> R> Hit for LevelHits<'_, F> {
    type Out = R;

    /// Reports light `index` at distance `d` unless its weight is zero. (Dark and pruned lights
    /// never get here: their scanned positions are NaN.)
    #[inline(always)]
    fn hit(&mut self, index: usize, d: f32) -> Option<R> {
        let l = self.lights;
        let w = self.weight.weight(d, || l.variance(index));
        if w <= 0.0 {
            return None;
        }
        Some((self.f)(&LightSample {
            level: self.level,
            index: index as u32,
            position: l.position(index),
            intensity: l.intensity(index) * w,
            variance: l.variance(index),
            size: l.size(index),
            distance: d,
            weight: w,
            lobe: Lobe::All,
        }))
    }
}
