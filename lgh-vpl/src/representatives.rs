//! Representative VPLs of the hierarchy's coarse lights: beyond the paper, an alternative to
//! its Gaussian shadow samples (Fig. 11d) for lights that stand for surfaces.
//!
//! A coarse light `i` of level `ℓ` aggregates the input lights within one cell of its grid
//! vertex `v`, each with its trilinear weight `w_j = Π_a (1 − |p_j,a − v_a| / h_ℓ)` (eqs. 1,
//! 2). The paper shades it as a volume light: `k` shadow samples at `p_ℓi + σ ⊙ g`, Gaussian
//! offsets with its variance (eq. 4). On surfaces that Gaussian misleads twice: its samples
//! fall inside walls and blocks, or behind the surface the VPLs lie on, so their shadow rays
//! say "hidden" for light that is seen; and one point has no cosine lobe, while the VPLs it
//! stands for each have one about their own normal.
//!
//! Here the `k` samples are VPLs the light stands for instead, drawn once per light from its
//! own weights `w_j ‖I_j‖` by systematic sampling (`k` evenly spaced points of the weights'
//! cumulative sum, offset by a number seeded by the light's level and index): every sample lies
//! on a surface, in front of it, with its normal. Shading a sample is shading that VPL, in its
//! own colour, at the share `1/k` of the light's blended luminance `‖B_ℓ(d) I_ℓi‖`
//! ([`Indirect::shade_representatives`](crate::indirect::Indirect::shade_representatives)): a
//! Monte Carlo estimate of the light's VPLs with `k` samples drawn in proportion to what they
//! carry, unbiased in every channel. The draws are fixed per light, so the estimate is
//! deterministic and does not change from pixel to pixel or frame to frame while the VPLs stay.
//! At most [`MAX_PER_LIGHT`] per light; the hierarchy must splat every level from the input
//! lights (`LevelSource::InputLights`, the default) and prune none, as the weights recomputed
//! here assume.

use lgh_core::glam::DVec3;
use lgh_core::random::SplitMix64;
use lgh_core::{GridLight, LightingGridHierarchy};
use rayon::prelude::*;

use crate::facing::Facing;
use crate::vpl::Vpl;

/// How many representatives each coarse light gets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Allocation {
    /// `k` for every light (at most [`MAX_PER_LIGHT`]).
    Uniform(u32),
    /// In proportion to the light's luminance against its level's mean, `k_i = round(mean ·
    /// ‖I_i‖ / mean_ℓ ‖I‖)`, held to `1..=max`: the samples go where the light is, since a
    /// light's error from `k` samples scales as its contribution over `√k` (and the optimal
    /// `k_i`, for a fixed total, as its contribution). Fixed per light, like the draws.
    ByIntensity {
        /// The mean `k` the rule aims at.
        mean: f32,
        /// The most one light gets.
        max: u32,
    },
    /// `K` for every light (the largest power of two not above it, at most 64), in nested order: the first `2^m` of
    /// them are themselves a systematic sample of the light's weights with `2^m` strata (the
    /// strata taken in bit-reversed order from a rotation seeded by the light), so a shading
    /// point may use any power-of-two prefix ([`Coarse::Adaptive`](crate::indirect::Coarse)).
    Nested(u32),
}

impl Allocation {
    /// Representatives of a light of luminance `lum` on a level of mean luminance `mean_lum`.
    #[must_use]
    fn count(self, lum: f32, mean_lum: f64) -> usize {
        match self {
            Allocation::Uniform(k) => k.clamp(1, MAX_PER_LIGHT) as usize,
            // The largest power of two not above k (and 64).
            Allocation::Nested(k) => 1usize << (31 - k.clamp(1, MAX_PER_LIGHT).leading_zeros()),
            Allocation::ByIntensity { mean, max } => {
                let k = (f64::from(mean) * f64::from(lum) / mean_lum + 0.5).floor();
                k.clamp(1.0, f64::from(max.clamp(1, MAX_PER_LIGHT))) as usize
            }
        }
    }
}

/// The most representatives one light gets, whatever the allocation.
pub const MAX_PER_LIGHT: u32 = 64;

/// Representative input lights for every light of levels ≥ 1 of a hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Representatives {
    /// How they were drawn.
    allocation: Allocation,
    /// Level `ℓ ≥ 1` at `ℓ − 1`.
    levels: Vec<LevelReps>,
}

/// One level's representatives: those of light `i` are `reps[starts[i]..starts[i + 1]]`,
/// indices into the slice the hierarchy was built from.
#[derive(Clone, Debug, PartialEq)]
struct LevelReps {
    starts: Vec<u32>,
    reps: Vec<u32>,
    /// Light `i`'s [`extent`](Representatives::extent).
    extents: Vec<f32>,
    /// The largest of them.
    max_extent: f32,
    /// Light `i`'s [`Facing`] ([`Facing::ANY`] for each if built without the VPLs).
    facings: Vec<Facing>,
}

/// One light's draw ([`draw`]).
struct LightDraw {
    reps: Vec<u32>,
    extent: f32,
    facing: Facing,
}

impl Representatives {
    /// Draws `k ≥ 1` representatives for every light of levels ≥ 1 of `lgh` (module docs), in
    /// parallel; the result does not depend on the thread count. Same as
    /// [`build_with`](Self::build_with) and [`Allocation::Uniform`].
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_vpl::representatives::Representatives;
    ///
    /// // 64 lights on a 4 × 4 × 4 lattice.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let reps = Representatives::build(&lgh, 4);
    /// for level in 1..=lgh.max_level() {
    ///     for (i, light) in lgh.level(level).iter().enumerate() {
    ///         let r = reps.of(level, i as u32);
    ///         // A dark vertex (which queries never report) has none.
    ///         assert_eq!(r.len(), if light.luminance > 0.0 { 4 } else { 0 });
    ///         // Each lies within one cell of the light's grid vertex, as its weights say.
    ///         let v = lgh.origin() + Vec3::from(lgh.vertex(level, i as u32).unwrap().map(|c| c as f32)) * lgh.h(level);
    ///         for &j in r {
    ///             assert!((lights[j as usize].position - v).abs().max_element() < lgh.h(level));
    ///         }
    ///     }
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn build(lgh: &LightingGridHierarchy, k: u32) -> Self {
        Self::build_with(lgh, Allocation::Uniform(k))
    }

    /// Draws representatives for every light of levels ≥ 1 of `lgh`, as many as `allocation`
    /// says.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_vpl::representatives::{Allocation, Representatives};
    ///
    /// // A row of lights, each 1.5 times brighter than the last.
    /// let lights: Vec<PointLight> = (0..40)
    ///     .map(|i| PointLight::new(Vec3::new(i as f32, 0.0, 0.0), Vec3::splat(1.5f32.powi(i))))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let reps = Representatives::build_with(&lgh, Allocation::ByIntensity { mean: 2.0, max: 16 });
    /// let lit = lgh.level(1).iter().enumerate().filter(|(_, l)| l.luminance > 0.0);
    /// let counts: Vec<usize> = lit.map(|(i, _)| reps.of(1, i as u32).len()).collect();
    /// // The dimmest lights get one, the brightest the most allowed.
    /// assert_eq!(counts.iter().copied().min(), Some(1));
    /// assert_eq!(counts.iter().copied().max(), Some(16));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn build_with(lgh: &LightingGridHierarchy, allocation: Allocation) -> Self {
        Self::build_stratified(lgh, allocation, &[])
    }

    /// Draws representatives for every light of levels ≥ 1 of `lgh`, as many as `allocation`
    /// says, stratified: the systematic sample runs over a light's input lights ordered by
    /// `strata[j]` (input light `j`'s stratum; 0 past the slice's end) first, so `k` draws
    /// give each stratum `k` times its share of the weight to within one — and with
    /// [`Allocation::Nested`], so does every power-of-two prefix. Each draw still picks input
    /// light `j` with probability `w_j ‖I_j‖ / Σ w ‖I‖`, so the estimate stays unbiased; what
    /// strata of like VPLs (the axis their lobe points along, [`Vpl::orientation`]) remove is
    /// the chance that a few draws all land on, say, the floor of a cell that also holds a
    /// wall, whose lobes face elsewhere.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_vpl::representatives::{Allocation, Representatives};
    ///
    /// // A floor (stratum 0) and a wall (stratum 1) meeting along x = 0.
    /// let lights: Vec<PointLight> = (0..400u32)
    ///     .map(|i| match i % 2 {
    ///         0 => Vec3::new((i / 2 % 10) as f32 * 0.1, 0.0, (i / 20) as f32 * 0.1),
    ///         _ => Vec3::new(0.0, (i / 2 % 10) as f32 * 0.1, (i / 20) as f32 * 0.1),
    ///     })
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let strata: Vec<u8> = (0..400).map(|i| (i % 2) as u8).collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let reps = Representatives::build_stratified(&lgh, Allocation::Nested(8), &strata);
    /// // Every lit coarse light has its 8, in nested order; `stratified_prefixes_…` in this
    /// // module's tests checks each prefix's share of every stratum.
    /// for level in 1..=lgh.max_level() {
    ///     for (i, light) in lgh.level(level).iter().enumerate() {
    ///         let n = reps.of(level, i as u32).len();
    ///         assert_eq!(n, if light.luminance > 0.0 { 8 } else { 0 });
    ///     }
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// [`Vpl::orientation`]: crate::vpl::Vpl::orientation
    #[must_use]
    pub fn build_stratified(
        lgh: &LightingGridHierarchy,
        allocation: Allocation,
        strata: &[u8],
    ) -> Self {
        Self::build_inner(lgh, allocation, strata, &[])
    }

    /// Draws representatives for every light of levels ≥ 1 of `lgh`, built over `vpls` (in
    /// order, as [`point_lights`](crate::indirect::point_lights) gives them), as many as
    /// `allocation` says: stratified by the VPLs' [`orientation`](Vpl::orientation)
    /// ([`build_stratified`](Self::build_stratified)), and with each light's [`Facing`],
    /// by which the adaptive shading leaves out the lights that face away from a point.
    /// (Those drawn otherwise rule nothing out: [`Facing::ANY`].)
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy};
    /// use lgh_vpl::facing::Facing;
    /// use lgh_vpl::indirect::point_lights;
    /// use lgh_vpl::representatives::{Allocation, Representatives};
    /// use lgh_vpl::vpl::Vpl;
    ///
    /// // A flat floor of VPLs facing up: every light's faces point up, none leans.
    /// let vpls: Vec<Vpl> = (0..400)
    ///     .map(|i| Vpl { position: Vec3::new((i % 20) as f32, 0.0, (i / 20) as f32) * 0.1,
    ///                    normal: Vec3::Y, geometric: Vec3::Y, power: Vec3::ONE,
    ///                    albedo: Vec3::ONE, bounce: 1 })
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&point_lights(&vpls), &GridSettings::default())?;
    /// let reps = Representatives::build_for(&lgh, Allocation::Nested(8), &vpls);
    /// let lit = |l: u8, i: u32| !reps.of(l, i).is_empty();
    /// for level in 1..=lgh.max_level() {
    ///     for i in (0..lgh.level(level).len() as u32).filter(|&i| lit(level, i)) {
    ///         let f = reps.facing(level, i);
    ///         assert_eq!((f.axis, f.spread, f.tilt), (Vec3::Y, 0.0, 0.0));
    ///         // Beneath the floor, every light faces away.
    ///         let centre = lgh.level(level).position(i as usize);
    ///         let below = centre - Vec3::Y;
    ///         assert!(f.faces_away(below, 1.0, reps.extent(level, i)));
    ///     }
    /// }
    /// let unsummarised = Representatives::build_with(&lgh, Allocation::Nested(8));
    /// assert_eq!(unsummarised.facing(1, 0), Facing::ANY);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn build_for(lgh: &LightingGridHierarchy, allocation: Allocation, vpls: &[Vpl]) -> Self {
        let strata: Vec<u8> = vpls.iter().map(Vpl::orientation).collect();
        Self::build_inner(lgh, allocation, &strata, vpls)
    }

    /// [`build_stratified`](Self::build_stratified), with each light's [`Facing`] over `vpls`
    /// if there are any.
    fn build_inner(
        lgh: &LightingGridHierarchy,
        allocation: Allocation,
        strata: &[u8],
        vpls: &[Vpl],
    ) -> Self {
        let levels = (1..=lgh.max_level())
            .map(|level| {
                let lights = lgh.level(level);
                let (sum, lit) = lights
                    .iter()
                    .filter(|l| l.luminance > 0.0)
                    .fold((0.0f64, 0usize), |(s, n), l| {
                        (s + f64::from(l.luminance), n + 1)
                    });
                let mean_lum = sum / lit.max(1) as f64;
                let per_light: Vec<LightDraw> = (0..lights.len() as u32)
                    .into_par_iter()
                    .map(|i| {
                        let k = allocation.count(lights.get(i as usize).luminance, mean_lum);
                        let drawn = draw(lgh, level, i, k, strata, vpls);
                        match allocation {
                            Allocation::Nested(_) => LightDraw {
                                reps: nest(drawn.reps, level, i),
                                ..drawn
                            },
                            _ => drawn,
                        }
                    })
                    .collect();
                let mut starts = Vec::with_capacity(per_light.len() + 1);
                starts.push(0u32);
                let mut reps = Vec::new();
                let mut extents = Vec::with_capacity(per_light.len());
                let mut facings = Vec::with_capacity(per_light.len());
                for d in per_light {
                    reps.extend(d.reps);
                    starts.push(reps.len() as u32);
                    extents.push(d.extent);
                    facings.push(d.facing);
                }
                let max_extent = extents.iter().copied().fold(0.0, f32::max);
                LevelReps {
                    starts,
                    reps,
                    extents,
                    max_extent,
                    facings,
                }
            })
            .collect();
        Representatives { allocation, levels }
    }

    /// The representatives of light `index` of `level ≥ 1`: indices into the slice the
    /// hierarchy was built from (empty for level 0, out of range, or a light without weight).
    #[must_use]
    pub fn of(&self, level: u8, index: u32) -> &[u32] {
        let Some(l) = self.level(level) else {
            return &[];
        };
        let i = index as usize;
        match (l.starts.get(i), l.starts.get(i + 1)) {
            (Some(&s), Some(&e)) => &l.reps[s as usize..e as usize],
            _ => &[],
        }
    }

    /// Hints to the cache that [`of`](Self::of) will soon read light `index` of `level`'s
    /// entry ([`crate::prefetch`]).
    #[inline(always)]
    pub(crate) fn hint(&self, level: u8, index: u32) {
        if let Some(start) = self.level(level).and_then(|l| l.starts.get(index as usize)) {
            crate::prefetch::prefetch(start);
        }
    }

    /// How far from light `index` of `level ≥ 1`'s centre the farthest of the input lights it
    /// stands for lies (those with a weight and some light; a hair over, for rounding): the
    /// distance at which it may still give light through one of them. 0 for a light without
    /// any, for level 0 and out of range.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_vpl::representatives::Representatives;
    ///
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let reps = Representatives::build(&lgh, 4);
    /// for level in 1..=lgh.max_level() {
    ///     let level_lights = lgh.level(level);
    ///     for i in 0..level_lights.len() as u32 {
    ///         let (centre, extent) = (level_lights.position(i as usize), reps.extent(level, i));
    ///         // Every representative lies within it, and it is within the cube's 2√3 h_ℓ.
    ///         for &j in reps.of(level, i) {
    ///             assert!((lights[j as usize].position - centre).length() <= extent);
    ///         }
    ///         assert!(extent <= 2.0 * 3f32.sqrt() * lgh.h(level) * 1.001);
    ///         assert!(extent <= reps.max_extent(level));
    ///     }
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    #[inline]
    pub fn extent(&self, level: u8, index: u32) -> f32 {
        self.level(level)
            .and_then(|l| l.extents.get(index as usize))
            .copied()
            .unwrap_or(0.0)
    }

    /// Where light `index` of `level ≥ 1`'s VPLs face ([`Facing`]): [`Facing::ANY`] where
    /// the representatives were drawn without the VPLs
    /// ([`build_for`](Self::build_for) draws them with), for level 0 and out of range.
    #[must_use]
    #[inline]
    pub fn facing(&self, level: u8, index: u32) -> Facing {
        self.level(level)
            .and_then(|l| l.facings.get(index as usize))
            .copied()
            .unwrap_or(Facing::ANY)
    }

    /// The largest [`extent`](Self::extent) of `level`'s lights (0 for level 0 and above the
    /// top): what [`LightingGridHierarchy::query_reaching`] must reach beyond the level's
    /// support to find every light that can give light.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_vpl::representatives::Representatives;
    ///
    /// let lights: Vec<PointLight> = (0..40)
    ///     .map(|i| PointLight::new(Vec3::new(i as f32 * 0.3, 0.0, 0.0), Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let reps = Representatives::build(&lgh, 2);
    /// assert_eq!(reps.max_extent(0), 0.0);
    /// // On a line, a light's input lights are within h_ℓ of its vertex along it.
    /// assert!(reps.max_extent(1) > 0.0 && reps.max_extent(1) <= 2.0 * lgh.h(1) * 1.001);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn max_extent(&self, level: u8) -> f32 {
        self.level(level).map_or(0.0, |l| l.max_extent)
    }

    /// Every light of `level`'s [`extent`](Self::extent), by index (empty for level 0 and
    /// above the top): what [`LightingGridHierarchy::query_reaching`] takes.
    #[must_use]
    pub fn extents(&self, level: u8) -> &[f32] {
        self.level(level).map_or(&[], |l| &l.extents)
    }

    /// Level `ℓ ≥ 1`'s.
    fn level(&self, level: u8) -> Option<&LevelReps> {
        self.levels.get((level as usize).checked_sub(1)?)
    }

    /// True if drawn with [`Allocation::Nested`]: every power-of-two prefix of a light's is a
    /// sample of it too.
    #[must_use]
    pub fn is_nested(&self) -> bool {
        matches!(self.allocation, Allocation::Nested(_))
    }

    /// Representatives drawn in all.
    #[must_use]
    pub fn len(&self) -> usize {
        self.levels.iter().map(|l| l.reps.len()).sum()
    }

    /// True if no light has a representative.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Calls `f(input, w, light)` for every input `light` that light `i` of `level ≥ 1`
/// aggregates, with its trilinear weight `w > 0` (eqs. 1, 2: `Π_a (1 − |p_a − v_a| / h_ℓ)` about the light's
/// grid vertex `v`), `input` its index in the slice the hierarchy was built from. The order is
/// fixed for a given hierarchy.
pub(crate) fn contributors(
    lgh: &LightingGridHierarchy,
    level: u8,
    i: u32,
    mut f: impl FnMut(usize, f64, &GridLight),
) {
    let Some(c) = lgh.vertex(level, i) else {
        return;
    };
    let h = f64::from(lgh.h(level));
    let vertex = lgh.origin().as_dvec3() + DVec3::new(c[0].into(), c[1].into(), c[2].into()) * h;
    let level0 = lgh.level(0);
    let reach = (3f64.sqrt() * h * (1.0 + 1e-6)) as f32;
    // The query cannot fail: the vertex is finite for every light the hierarchy holds.
    let _ = lgh.lights_within(0, vertex.as_vec3(), reach, |j, _| {
        let light = level0.get(j as usize);
        let w = (1.0 - (light.position.as_dvec3() - vertex).abs() / h).max(DVec3::ZERO);
        let w = w.x * w.y * w.z;
        if w > 0.0 {
            if let Some(input) = lgh.input_index(j) {
                f(input, w, &light);
            }
        }
    });
}

/// `k` input lights of light `i` of `level` by systematic sampling of their weights
/// `w_j ‖I_j‖`, taken in the order of their `strata` (then in [`contributors`]' order); with
/// the light's [`extent`](Representatives::extent) and, over `vpls` (the input lights' VPLs,
/// if given), its [`Facing`].
fn draw(
    lgh: &LightingGridHierarchy,
    level: u8,
    i: u32,
    k: usize,
    strata: &[u8],
    vpls: &[Vpl],
) -> LightDraw {
    let mut cands: Vec<(u32, f64)> = Vec::new();
    let centre = lgh.level(level).position(i as usize);
    let mut extent = 0.0f32;
    contributors(lgh, level, i, |input, w, light| {
        if light.luminance > 0.0 {
            cands.push((input as u32, w * f64::from(light.luminance)));
            extent = extent.max((light.position - centre).length());
        }
    });
    // A hair over: distances from a point are rounded too.
    let extent = extent * (1.0 + 1e-5);
    if !strata.is_empty() {
        // Stable: within a stratum, the contributors' fixed order.
        cands.sort_by_key(|c| strata.get(c.0 as usize).copied().unwrap_or(0));
    }
    let total: f64 = cands.iter().map(|c| c.1).sum();
    if total <= 0.0 || !total.is_finite() {
        return LightDraw {
            reps: Vec::new(),
            extent: 0.0,
            facing: Facing::ANY,
        };
    }
    // Every VPL or none (none without them): a summary of some of them could rule out light.
    let facing = if !vpls.is_empty() && cands.iter().all(|&(j, _)| (j as usize) < vpls.len()) {
        Facing::of(cands.iter().map(|&(j, w)| (&vpls[j as usize], w)))
    } else {
        Facing::ANY
    };
    let mut rng = SplitMix64(SplitMix64::mix((u64::from(level) << 32) | u64::from(i)));
    let offset = f64::from(rng.next_f32());
    let mut out = Vec::with_capacity(k);
    let (mut c, mut acc) = (0, cands[0].1);
    for s in 0..k {
        let target = (s as f64 + offset) / k as f64 * total;
        while acc < target && c + 1 < cands.len() {
            c += 1;
            acc += cands[c].1;
        }
        out.push(cands[c].0);
    }
    LightDraw {
        reps: out,
        extent,
        facing,
    }
}

/// `drawn` (a systematic sample, `2^n` strata in order) reordered so that every power-of-two
/// prefix is a systematic sample too: position `j` takes stratum `(bitrev(j) + r) mod 2^n`, `r`
/// seeded by the light (so a one-sample prefix is any stratum, not always the first).
fn nest(drawn: Vec<u32>, level: u8, i: u32) -> Vec<u32> {
    let n = drawn.len();
    if n <= 1 {
        return drawn;
    }
    let bits = n.trailing_zeros();
    let mut rng = SplitMix64(SplitMix64::mix(
        (u64::from(level) << 32) | u64::from(i) | (1 << 40),
    ));
    let r = (rng.next_f32() * n as f32) as usize % n;
    (0..n)
        .map(|j| {
            let rev = (j as u32).reverse_bits() >> (32 - bits);
            drawn[(rev as usize + r) % n]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::glam::Vec3;
    use lgh_core::{GridSettings, PointLight};

    /// Clumped lights of varied brightness (a fixed pseudo-random set).
    fn lights() -> Vec<PointLight> {
        let mut rng = SplitMix64(7);
        (0..3000)
            .map(|_| {
                let p = Vec3::new(rng.next_f32(), rng.next_f32() * 0.5, rng.next_f32()) * 10.0;
                let p = if rng.next_f32() < 0.5 { p * 0.2 } else { p };
                PointLight::new(p, Vec3::new(1.0, 0.5, 0.2) * (0.1 + 4.0 * rng.next_f32()))
            })
            .collect()
    }

    /// Stratified draws (three strata at random over the clumped lights): every power-of-two
    /// prefix of every light's nested draws holds each stratum's share of its weights to within
    /// one pick — systematic sampling over the weights laid end to end by stratum puts `m`
    /// evenly spaced points on them, and a stratum of share `s` is an interval holding `m s`
    /// of them up to one. The same draws in the contributors' own order do not (the strata
    /// interleave), and each pick still follows the weights.
    #[test]
    fn stratified_prefixes_give_each_stratum_its_share() {
        let lights = lights();
        let strata: Vec<u8> = (0..lights.len() as u64)
            .map(|j| (SplitMix64::mix(j) % 3) as u8)
            .collect();
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        // The (light, power-of-two prefix, stratum) whose count of picks is not within one of
        // the prefix's length × the stratum's share of the light's weight.
        let misses = |reps: &Representatives| {
            let mut misses = 0;
            for level in 1..=lgh.max_level() {
                for i in 0..lgh.level(level).len() as u32 {
                    let r = reps.of(level, i);
                    let mut share = [0f64; 3];
                    contributors(&lgh, level, i, |input, w, light| {
                        share[strata[input] as usize] += w * f64::from(light.luminance);
                    });
                    let total: f64 = share.iter().sum();
                    let mut m = 1;
                    while m <= r.len() {
                        for (s, part) in share.iter().enumerate() {
                            let got = r[..m].iter().filter(|&&j| strata[j as usize] == s as u8);
                            let want = m as f64 * part / total;
                            misses += usize::from((got.count() as f64 - want).abs() > 1.0 + 1e-9);
                        }
                        m *= 2;
                    }
                }
            }
            misses
        };
        let stratified = Representatives::build_stratified(&lgh, Allocation::Nested(16), &strata);
        assert_eq!(misses(&stratified), 0);
        // Drawn over the contributors' own order, the strata interleave and prefixes miss.
        assert!(misses(&Representatives::build_with(&lgh, Allocation::Nested(16))) > 0);
        // Each pick still follows the weights (the stratification reorders, it does not bias).
        for i in (0..lgh.level(1).len() as u32).step_by(37) {
            let picks = stratified.of(1, i);
            assert!(picks.is_empty() || follows_weights(&lgh, &lights, 1, i, picks));
        }
    }

    /// Checks that `picks` draws each of `lights` `m p_j` times to within one, `p_j = w_j ‖I_j‖
    /// / Σ w ‖I‖` with the trilinear weights of light `i` of `level` recomputed here from its
    /// vertex and `h_ℓ`. False (and `picks` empty) for a light without weight.
    fn follows_weights(
        lgh: &LightingGridHierarchy,
        lights: &[PointLight],
        level: u8,
        i: u32,
        picks: &[u32],
    ) -> bool {
        let h = f64::from(lgh.h(level));
        let c = lgh.vertex(level, i).unwrap();
        let v = lgh.origin().as_dvec3() + DVec3::new(c[0].into(), c[1].into(), c[2].into()) * h;
        let weight = |l: &PointLight| {
            let w = (1.0 - (l.position.as_dvec3() - v).abs() / h).max(DVec3::ZERO);
            w.x * w.y * w.z * f64::from(lgh_core::luminance(l.intensity))
        };
        let total: f64 = lights.iter().map(weight).sum();
        if total == 0.0 {
            assert!(picks.is_empty());
            return false;
        }
        let m = picks.len() as f64;
        for (j, l) in lights.iter().enumerate() {
            let n = picks.iter().filter(|&&p| p as usize == j).count() as f64;
            let expected = m * weight(l) / total;
            assert!(
                (n - expected).abs() <= 1.0 + 1e-6,
                "level {level} light {i}, {m} picks: input {j} drawn {n} times, expected {expected}"
            );
        }
        true
    }

    /// Systematic sampling gives each input light `j` of a coarse light `k p_j` picks up to
    /// one ([`follows_weights`]) — the representatives follow the light's own weights (eqs. 1,
    /// 2), on every level — and so does every power-of-two prefix of the nested draws; neither
    /// depends on the thread count.
    #[test]
    fn representatives_follow_the_trilinear_weights() {
        let lights = lights();
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        let k = MAX_PER_LIGHT;
        let reps = Representatives::build(&lgh, k);
        let nested = Representatives::build_with(&lgh, Allocation::Nested(16));
        let (mut checked, mut prefixes) = (0, 0);
        for level in 1..=lgh.max_level() {
            for i in (0..lgh.level(level).len() as u32).step_by(37) {
                let picks = reps.of(level, i);
                if follows_weights(&lgh, &lights, level, i, picks) {
                    assert_eq!(picks.len(), k as usize);
                    checked += 1;
                }
                let all = nested.of(level, i);
                for m in [2usize, 4, 8, 16] {
                    if follows_weights(&lgh, &lights, level, i, all.get(..m).unwrap_or(&[])) {
                        prefixes += 1;
                    }
                }
            }
        }
        assert!(checked > 20, "{checked}");
        assert!(prefixes > 40, "{prefixes}");
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        assert_eq!(one.install(|| Representatives::build(&lgh, k)), reps);
        let again = one.install(|| Representatives::build_with(&lgh, Allocation::Nested(16)));
        assert_eq!(again, nested);
        assert!(reps.of(0, 0).is_empty());
        assert!(reps.of(1, u32::MAX / 2).is_empty());
    }
}
