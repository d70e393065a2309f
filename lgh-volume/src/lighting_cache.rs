//! A lighting cache for the hierarchy's coarse levels: their light computed once per frame at
//! the vertices of a sparse grid over the smoke and interpolated at every march sample, where
//! the finer levels are still shaded exactly.
//!
//! **Why it may be cached.** Eq. (1)'s sum splits by level,
//! `L(x) = Σ_{ℓ<ℓ_c} Σ_i V g B_ℓ I + Σ_{ℓ≥ℓ_c} Σ_i V g B_ℓ I`. A level-ℓ light lights only points
//! beyond `r_{ℓ−1}` of it (eq. 3's blending is zero nearer), and `B_ℓ`, `g` and the unshadowed
//! sum vary over `h_ℓ`, not over a voxel: the hierarchy makes the coarse part smooth by
//! construction. Its shadows `V` do vary at the voxel scale near the shading point, where the
//! smoke does — so the vertices sit on the voxel centres by default
//! (the lattice the density itself is interpolated on) or closer, where the smoke is so dense
//! that a voxel's optical depth passes 1, and coarser levels on coarser grids where the smoke is
//! thin ([`CacheSpacing`]).
//!
//! **How it is interpolated.** Trilinear interpolation of `L` leaks light into smoke: across a
//! voxel of dense soot the light falls like `e^{−σ_t d}`, and a chord of an exponential lies above
//! it. Two things the cache knows make the interpolation follow the shadow instead:
//! 1. *The shadow's gradient.* Moving the receiver by `δ` along light `j`'s direction of travel
//!    `ω_j` adds `σ_t δ·ω_j` of optical depth (for a light far compared with `|δ|`), so
//!    `∇L ≈ −σ_t F` with `F = Σ_j L_j ω_j` the flux vector ([`Lights::incident_flux`]). Each
//!    vertex keeps `d = F / lum(L)` (the mean direction of travel, `|d| ≤ 1`), and each of the
//!    eight corners around a sample `x` extrapolates its light to it as
//!    `L̂_v = L_v e^{−σ̄ (x − v)·d_v}`, `σ̄` the mean of `σ_t` at `v` and at `x`: exact for light
//!    from one direction through smoke of constant `σ_t`.
//! 2. *Geometric blending.* The corners' estimates are blended with the trilinear weights `w_v`
//!    in the logarithm, `exp(Σ_v w_v ln(L̂_v + ε)) − ε`, exact for light that varies
//!    exponentially along the cell; `ε` is a thousandth of the linear blend `Σ_v w_v L̂_v` (the
//!    march's own cut-off: a corner a thousand times darker than the sample does not darken it
//!    further), which keeps a black corner from blacking out its cell and keeps the result
//!    continuous in `x` across cells.
//!
//! A grid that holds level 0 (the scattering depths' cache of every level,
//! [`LightingCacheSettings::scattered_depths`]) blends the extrapolated corners linearly
//! instead. Level 0's voxel lights give each voxel a share of its own light, `I_v · 7.7/h²`
//! at its centre (`lgh_core::near_field`), so that light varies from voxel to voxel with the
//! density and the geometric mean of such corners falls below their mean (AM–GM): on a 20³
//! ball of smoke, depth 2 two voxels apart lost 22% of its power blended geometrically, 0.2%
//! linearly (0.5% at depth 3).
//!
//! **Level 0 on the scattering depths' grid.** Depths ≥ 2 of multiple scattering take their
//! fluence from a grid of every level, vertices up to four voxels apart
//! ([`LightingCacheSettings::scattered_depths`]). Interpolated whole, level 0's light loses
//! what follows the density from voxel to voxel: a voxel's own light and its neighbours' are
//! `h³ σ_s Φ/4π` of their own smoke, and the light a voxel scatters is its fluence times its
//! smoke, so the pass's power is `Σ ρ_x Φ_x` where the grid gives `Σ ρ_x ⟨Φ⟩_x` — the
//! covariance of the two is lost (on the smoky64 fire, Blender's Quick Smoke at 64 cells, the
//! second depth's power on the grid was 0.93 of its power at every voxel, all of it lost
//! between the vertices). So that grid keeps level 0's *far* light ([`Level0Form::FarLight`]):
//! each light's term weighted by one minus [`crate::near_part`]'s partition of unity in the
//! distance, and each voxel sums the near part — the lights within
//! [`SCATTERED_NEAR_REACH`] voxels, with their shadows — itself.
//!
//! **Level 0 too, for large images, as a ratio.** Level 0's light varies from voxel to voxel,
//! and within a voxel by its own light's near field, which no grid on the voxel centres
//! follows: interpolated as light ([`Level0Form::Light`]), it adds flicker (`lgh bench flicker
//! --cache-level 0 --cache-level0 light`: +39% on the dev fire, +12% on the procedural
//! sequence, against −11% and −4% from level 1 up), the interpolation's error following the
//! fire's intensities from frame to frame. What varies slowly across a voxel is its
//! *shadows*. So a grid that holds level 0 ([`Level0Form::Ratio`], the default) keeps at each
//! vertex — on the voxel centres, one per voxel light, on a grid of its own — level 0's
//! shadowed light `S_v = Σ_j I_j g_j V_j` and unshadowed light `U_v = Σ_j I_j g_j`, and a sample
//! multiplies level 0's unshadowed light `U(x)`, summed exactly there, by
//! `Σ_v w_v Ŝ_v / Σ_v w_v U_v`: a mean of level 0's
//! transmittances weighted by their light, `Ŝ_v` extrapolated along the shadow's gradient as
//! below (a channel whose light is negative at a corner — Blender's blackbody below about
//! 1900 K — is no such mean, and takes the luminance's ratio instead). The near field stays exact, and the shadow rays — most of level 0's cost at a
//! sample — are cast at the vertices only. Without shadows the ratio is exactly 1 and the
//! image that of level 0 shaded at every sample. Flicker from level 0 up: −11% on the dev fire
//! and +0.6% on the procedural sequence against the uncached render (−11% and −4% from level
//! 1), with level 0's unshadowed light summed whole; with its near part (below) −1.6% and
//! −1.4%. Against the exact image: the Fig. 8-class frame at 320×180 1.55% (levels ≥ 1: 1.55%,
//! level 0 as light 1.54%); the demo at 640×360 1.69% (1.70%, 1.72%).
//!
//! A vertex costs about twice what a sample's level 0 costs (a vertex at a voxel centre has
//! every hot neighbour in reach), and the vertices do not grow with the image while the
//! samples do: [`auto_first_level`] caches level 0 where a camera ray's footprint at the smoke
//! is small enough that the samples outnumber the vertices. Summed whole at every sample,
//! level 0's unshadowed light was the ratio form's price: on the Fig. 8-class frame at
//! 1280×720 (with the demo's ground) the render took 189.5 CPU-s against 131.6 with level 0 as
//! light (one run after the other). So only its *near part* is summed at a sample — the lights
//! within [`NEAR_REACH`] voxels, through a partition of unity in the distance — and its far
//! part, which holds no light's near field, is kept at the ratio grid's vertices and
//! interpolated with the ratio ([`crate::near_part`], `--cache-near`, where its reach is
//! measured against flicker and speed). Multiple scattering's merged lights, one a smoky voxel, made the
//! whole sum far dearer (236 lights a sample on the same frame at depth 4: the render 385
//! CPU-s as a ratio), so [`Level0Form::Auto`], the default, keeps their level 0 as light.
//!
//! At a vertex the cache returns the vertex's exact value. On the demo's explosion (320×180,
//! levels ≥ 1 cached, 2-voxel shadow steps) against the uncached render: trilinear 3.06%
//! relative RMSE, geometric 2.51%, transport-corrected 2.03%, both 1.82% (`docs/shadows.md`).
//!
//! **Sparse and filled on demand.** Bricks of [`BRICK`]³ vertices are computed the first time a
//! march sample needs one of their vertices, so only the smoke the camera's rays reach is paid
//! for, and the cost does not grow with the image's pixels. A vertex's value depends on its
//! position, the lights and their visibility only, so the cache — and every image made with it
//! — is the same whatever the thread count and the order in which bricks are filled. (Two
//! threads may fill the same brick at once; both compute the same values and one is kept.)

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

use lgh_core::glam::{BVec3, Vec3};
use lgh_core::{LghBackend, LightingGridHierarchy, QueryError, ISOTROPIC_PHASE};

use crate::method::FrameBackend;

use crate::error::{check_setting, RenderError};
use crate::grid::DenseGrid;
use crate::lighting::{LightScratch, Lights};
use crate::medium::Medium;
use crate::near_part::{NearPart, NEAR_REACH};
use crate::shadow::Visibility;
use crate::stats::RenderStats;

/// Vertices per side of a brick, the unit the cache is filled in.
pub const BRICK: usize = 2;

/// Whether the coarse levels' light is cached (`--lighting-cache`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CacheMode {
    /// Every light shaded at every march sample.
    #[default]
    None,
    /// Levels from [`LightingCacheSettings::first_level`] up cached at the vertices of a grid,
    /// the finer levels shaded per sample.
    Coarse,
}

impl CacheMode {
    /// The name on the command line (`none`, `coarse`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CacheMode::None => "none",
            CacheMode::Coarse => "coarse",
        }
    }
}

/// The distance between the cache's vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CacheSpacing {
    /// The distance across which the densest smoke (the 99th percentile of the density over
    /// the voxels with smoke) has this optical depth, and for each level at most half its grid
    /// spacing `h_ℓ` (its blending ramp and fall-off vary over `h_ℓ`: a voxel for level 1, the
    /// explosions' `h_1` being two, two for level 2, …) but not below a voxel on that account
    /// (level 0, whose lights are the voxels, sits on their centres; so would any level of a
    /// hierarchy whose `h_1` is under two voxels), or the next shorter of `1/k` or `k`
    /// voxels (on the density's lattice), between [`MIN_SPACING`] and [`MAX_SPACING`] voxels.
    /// Levels that get the same spacing share a grid. Without the
    /// second bound the dev fire's thin smoke got 4-voxel cells and flickered 4.5× as much as
    /// the uncached render; at one voxel, 8% less. The interpolation's error follows the optical depth of a cell,
    /// not its size in voxels: the demo's explosion at 128³ has 0.95 a voxel and errs by 1.8%
    /// at voxel spacing, at 64³ 1.9 a voxel and 5.3%, at 64³ with half-voxel spacing 1.9%.
    OpticalDepth(f32),
    /// A fixed distance, in voxels (1: the voxel centres).
    Voxels(f32),
}

/// The closest the vertices of an automatic spacing come, in voxels.
pub const MIN_SPACING: f32 = 0.25;
/// The reach, in voxels, of the near part that the scattering depths' grid sums at every voxel
/// ([`LightingCacheSettings::scattered_depths`], [`Level0Form::FarLight`]).
pub const SCATTERED_NEAR_REACH: f32 = 1.0;

/// The farthest apart the vertices of an automatic spacing are, in voxels.
pub const MAX_SPACING: f32 = 4.0;

/// How the lighting cache is laid out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightingCacheSettings {
    /// Cached or not.
    pub mode: CacheMode,
    /// Distance between the cache's vertices.
    pub spacing: CacheSpacing,
    /// The first level cached: levels below it are shaded at every sample.
    pub first_level: u8,
    /// How a grid that holds level 0 keeps it: its shadows as a ratio or its light (by default
    /// as a ratio for the emission's lights, as light for multiple scattering's merged lights).
    pub level0: Level0Form,
    /// With level 0 kept as a ratio, the reach in voxels of its near part, summed at every
    /// sample; the far part is interpolated from the vertices ([`crate::near_part`];
    /// [`NEAR_REACH`] by default). `None`: every level-0 light at every sample.
    pub near_reach: Option<f32>,
    /// Multiple scattering's depths ≥ 2 compute their fluence at the vertices of a grid this
    /// many voxels apart, every level cached, and interpolate it to the voxels
    /// ([`scattered_depths`](Self::scattered_depths)); 1: at every voxel, as depth 1 does; 0
    /// (the default): chosen from the smoke's extent
    /// ([`scattered_spacing_on`](Self::scattered_spacing_on)).
    pub scattered_spacing: u8,
    /// How the render takes in multiple scattering's light: the paper's merged lights at every
    /// march sample, or a grid of its in-scattered radiance at the voxels
    /// ([`crate::scattered_light`]).
    pub scattered_light: ScatteredLight,
}

/// How a cache that holds level 0 keeps it (`--cache-level0`; module docs, "Level 0 as a
/// ratio").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Level0Form {
    /// [`Ratio`](Self::Ratio) for the emission's voxel lights in the camera's march,
    /// [`Light`](Self::Light) for multiple scattering's merged lights — one a smoky voxel,
    /// their level 0 summed at every sample would cost more than the rest of the render (the
    /// Fig. 8-class frame at depth 4, 1280×720: 236 lights a sample; the render 385 CPU-s as a
    /// ratio) — and for the scattering pass, whose samples are the voxel centres: the
    /// vertices, where light is exact. [`crate::FrameRender`] resolves it; a cache made
    /// directly takes it as a ratio.
    #[default]
    Auto,
    /// Its shadows only: the vertices keep level 0's shadowed light `S_v` and unshadowed light
    /// `U_v`, and a sample multiplies level 0's unshadowed light `U(x)`, summed exactly, by
    /// their interpolated ratio `Σ w_v S_v / Σ w_v U_v`. The near field stays exact; the
    /// shadow rays, most of level 0's cost a sample, are cast at the vertices only.
    Ratio,
    /// Its light, interpolated linearly, where every sample would otherwise sum level 0.
    Light,
    /// The light of its far part interpolated linearly, its near part — the lights within
    /// [`near_reach`](LightingCacheSettings::near_reach) — summed with their shadows at every
    /// sample ([`crate::near_part`]'s split): what the scattering depths' grid keeps. A voxel's
    /// own light and its neighbours' follow the voxel's density and extinction, which no grid
    /// between the voxels follows: interpolated whole, the smoky64 fire's depth 2 lost 7% of
    /// its power on a grid four voxels apart (module docs, "Level 0 on the scattering depths'
    /// grid"). Without a near reach it is [`Light`](Self::Light).
    FarLight,
}

impl Level0Form {
    /// The name on the command line (`auto`, `ratio`, `light`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Level0Form::Auto => "auto",
            Level0Form::Ratio => "ratio",
            Level0Form::Light => "light",
            Level0Form::FarLight => "far-light",
        }
    }

    /// The form for a cache of `lights`: [`Auto`](Self::Auto) resolved (a ratio for the
    /// emission's lights, light for the merged lights), the others as they are.
    ///
    /// ```
    /// use lgh_volume::lighting_cache::{Level0Form, RenderedLights};
    ///
    /// assert_eq!(Level0Form::Auto.for_lights(RenderedLights::Emission), Level0Form::Ratio);
    /// assert_eq!(Level0Form::Auto.for_lights(RenderedLights::Merged), Level0Form::Light);
    /// assert_eq!(Level0Form::Ratio.for_lights(RenderedLights::Merged), Level0Form::Ratio);
    /// ```
    #[must_use]
    pub fn for_lights(self, lights: RenderedLights) -> Self {
        match (self, lights) {
            (Level0Form::Auto, RenderedLights::Merged) => Level0Form::Light,
            (Level0Form::Auto, RenderedLights::Emission) => Level0Form::Ratio,
            (form, _) => form,
        }
    }
}

/// The lights a lighting cache is made for, which decide [`Level0Form::Auto`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderedLights {
    /// The emission's voxel lights, one a hot voxel (paper Sec. 6.1): few enough for level 0
    /// to be summed at every sample, so its shadows are cached as a ratio.
    Emission,
    /// Multiple scattering's merged lights, one a smoky voxel (Sec. 5), or the scattering
    /// pass's own, whose samples are the voxel centres: level 0's light is cached.
    Merged,
}

/// How a render with multiple scattering takes in the scattered light (`--scattered-light`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ScatteredLight {
    /// The paper's Sec. 5: one light per voxel, its emission and every scattered depth merged,
    /// shaded at every march sample (the default: the image the pass's lights make).
    #[default]
    Merged,
    /// With the lighting cache, and shadows that do not belong to a light set (ray-marched or
    /// none): the scattered depths' in-scattered radiance computed at the voxels by one more
    /// fluence pass and interpolated at every sample, which shades the emission lights only
    /// ([`crate::scattered_light`]); surfaces are lit by the merged lights. Faster (the
    /// Fig. 8-class frame at depth 4: 442 core-seconds in all against 664), but smooth between
    /// voxel centres where the merged lights are not: 4.0% from their image with the same
    /// passes (mean −1.1%).
    Grid,
}

impl ScatteredLight {
    /// The name on the command line (`merged`, `grid`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ScatteredLight::Merged => "merged",
            ScatteredLight::Grid => "grid",
        }
    }
}

/// The largest footprint of a camera ray at the volume's centre, in voxels (a pixel's, or a
/// sub-pixel's with several rays a pixel), at which [`auto_first_level`] caches level 0. Measured
/// on the Fig. 8-class frame (`docs/shadows.md`; 2 threads, level 0 then sharing level 1's
/// grid), the render's CPU-seconds with level 0 shaded at every sample against cached: 2.19
/// voxels a ray (320×180, separate runs) 70.4 against 77.0, 1.09 (640×360, one after the other)
/// 99.2 against 102.4, 0.55 (1280×720, one after the other) 267.4 against 147.1. Three quarters
/// of a voxel sits between the break-even and the clear gain.
pub const LEVEL0_CACHE_FOOTPRINT: f32 = 0.75;

/// The first level a lighting cache should hold for a camera whose rays are `footprint` voxels
/// apart at the volume (a sub-pixel's footprint: [`crate::render::pixel_footprint`] over the
/// rays a pixel side): 0 at most [`LEVEL0_CACHE_FOOTPRINT`], where the march's samples outnumber
/// level 0's vertices, 1 otherwise (module docs). A `--cache-level auto`.
///
/// ```
/// use lgh_volume::lighting_cache::auto_first_level;
///
/// assert_eq!(auto_first_level(0.55), 0); // the Fig. 8-class frame at 1280×720
/// assert_eq!(auto_first_level(1.09), 1); // at 640×360
/// assert_eq!(auto_first_level(f32::NAN), 1);
/// ```
#[must_use]
pub fn auto_first_level(footprint: f32) -> u8 {
    if footprint <= LEVEL0_CACHE_FOOTPRINT {
        0
    } else {
        1
    }
}

/// The default [`LightingCacheSettings::scattered_spacing`]: 0, automatic
/// ([`scattered_spacing_on`](LightingCacheSettings::scattered_spacing_on)).
pub const SCATTERED_SPACING: u8 = 0;

/// The fewest cells of the scattering depths' grid across the smoke's narrowest extent that an
/// automatic spacing leaves. Measured with voxel lights (`lgh_core::near_field`), depth 4
/// against every voxel: the 24³ ball of the path-tracer test (`tests/tests/scattering.rs`,
/// smoke 19 voxels across) four voxels apart (4.7 cells) +6.5%, two apart (9.5 cells) +0.5%;
/// the Fig. 8-class frame (`docs/shadows.md`, over 200 voxels across) four apart against two
/// apart: depths 2–4's power +0.8%, +0.6%, +0.1%, the image 1.5%, at half the pass's time
/// (depths 2–4 8–12 s each against 58–66 s). Against Cycles 3.4.1's converged image
/// (`docs/cycles.md`, "The scattering depths' grid a step finer on the small volumes"): the 64³
/// fires and the fireball, 35 voxels across, four apart (8.75 cells) leave 0.5–0.6% of
/// structure against every voxel, two apart (17.5 cells) 0.16%; 9 is the least minimum that
/// takes them to two, and leaves the 24³ ball (20 voxels in its box of smoke, 10 cells two apart)
/// where it was.
pub const MIN_SCATTERED_CELLS: f32 = 9.0;

impl Default for LightingCacheSettings {
    /// No cache; when on, cells of optical depth 1 across the densest smoke, levels ≥ 1,
    /// scattering depths ≥ 2 on a grid whose spacing follows the smoke's extent, the scattered
    /// light merged.
    fn default() -> Self {
        LightingCacheSettings {
            mode: CacheMode::None,
            spacing: CacheSpacing::OpticalDepth(1.0),
            first_level: 1,
            level0: Level0Form::Auto,
            near_reach: Some(NEAR_REACH),
            scattered_spacing: SCATTERED_SPACING,
            scattered_light: ScatteredLight::Merged,
        }
    }
}

impl LightingCacheSettings {
    /// The coarse cache with the default layout (cells of optical depth 1 across the densest
    /// smoke, levels ≥ 1).
    ///
    /// ```
    /// use lgh_volume::lighting_cache::{CacheMode, CacheSpacing, LightingCacheSettings};
    ///
    /// let cache = LightingCacheSettings::coarse();
    /// assert_eq!(cache.mode, CacheMode::Coarse);
    /// assert_eq!((cache.spacing, cache.first_level), (CacheSpacing::OpticalDepth(1.0), 1));
    /// ```
    #[must_use]
    pub fn coarse() -> Self {
        LightingCacheSettings {
            mode: CacheMode::Coarse,
            ..Default::default()
        }
    }

    /// The cache a multiple-scattering depth ≥ 2 computes its fluence through, if any: every
    /// level at the vertices of a grid [`scattered_spacing`](Self::scattered_spacing) voxels
    /// apart, on the voxel centres. Depth `k ≥ 2`'s lights are light that has scattered
    /// already: spread over all the smoke, their fluence varies over the smoke's scale and
    /// its shadows, which the cache's interpolation follows (module docs), not over a single
    /// hot voxel's near field as the emission's does (depth 1 keeps every voxel) — but for
    /// level 0's near part, which follows the voxels' smoke: the grid keeps level 0's far
    /// light ([`Level0Form::FarLight`]) and each voxel sums the lights within
    /// [`SCATTERED_NEAR_REACH`] voxels (module docs, "Level 0 on the scattering depths'
    /// grid"). None without a cache (the exact pass, every voxel) or with a spacing of 1.
    ///
    /// ```
    /// use lgh_volume::lighting_cache::{CacheSpacing, Level0Form, LightingCacheSettings};
    /// use lgh_volume::procedural;
    ///
    /// let density = procedural::ball(64, 0.7, 3000.0).density; // smoke 51 voxels across
    /// let later = LightingCacheSettings::coarse().scattered_depths(&density).unwrap();
    /// assert_eq!((later.spacing, later.first_level), (CacheSpacing::Voxels(4.0), 0));
    /// assert_eq!(later.level0, Level0Form::FarLight);
    /// assert!(LightingCacheSettings::default().scattered_depths(&density).is_none()); // no cache
    /// let every = LightingCacheSettings { scattered_spacing: 1, ..LightingCacheSettings::coarse() };
    /// assert!(every.scattered_depths(&density).is_none());
    /// ```
    #[must_use]
    pub fn scattered_depths(&self, density: &DenseGrid) -> Option<Self> {
        let spacing = self.scattered_spacing_on(density);
        (self.mode == CacheMode::Coarse && spacing > 1).then_some(LightingCacheSettings {
            spacing: CacheSpacing::Voxels(f32::from(spacing)),
            first_level: 0,
            level0: Level0Form::FarLight,
            near_reach: Some(SCATTERED_NEAR_REACH),
            ..*self
        })
    }

    /// The spacing, in voxels, of the scattering depths' grid over `density`:
    /// [`scattered_spacing`](Self::scattered_spacing), or where it is 0 (automatic, the default)
    /// the coarsest of 4, 2 and 1 voxels that leaves [`MIN_SCATTERED_CELLS`] cells across the
    /// smoke's narrowest extent (its box of voxels with density).
    ///
    /// ```
    /// use lgh_volume::lighting_cache::LightingCacheSettings;
    /// use lgh_volume::procedural;
    ///
    /// let auto = LightingCacheSettings::coarse();
    /// let small = procedural::ball(24, 0.7, 3000.0).density; // 19 voxels across
    /// assert_eq!(auto.scattered_spacing_on(&small), 2);
    /// let fire64 = procedural::ball(42, 0.7, 3000.0).density; // 34 across, near the 64³ fires' 35
    /// assert_eq!(auto.scattered_spacing_on(&fire64), 2); // 8.5 cells at 4
    /// let large = procedural::ball(64, 0.7, 3000.0).density;
    /// assert_eq!(auto.scattered_spacing_on(&large), 4);
    /// let fixed = LightingCacheSettings { scattered_spacing: 3, ..auto };
    /// assert_eq!(fixed.scattered_spacing_on(&small), 3);
    /// ```
    #[must_use]
    pub fn scattered_spacing_on(&self, density: &DenseGrid) -> u8 {
        if self.scattered_spacing != 0 {
            return self.scattered_spacing;
        }
        let Some((lo, hi)) = density.active_bounds() else {
            return 1;
        };
        let across = ((hi - lo) / density.voxel_size).min_element();
        [4u8, 2]
            .into_iter()
            .find(|&s| across / f32::from(s) >= MIN_SCATTERED_CELLS)
            .unwrap_or(1)
    }

    /// Whether the scattered light enters the render as a grid ([`ScatteredLight::Grid`] with
    /// the cache on; the caller also needs shadows that every light set shares).
    ///
    /// ```
    /// use lgh_volume::lighting_cache::{LightingCacheSettings, ScatteredLight};
    ///
    /// assert!(!LightingCacheSettings::coarse().scattered_grid()); // merged by default
    /// let grid = LightingCacheSettings { scattered_light: ScatteredLight::Grid, ..LightingCacheSettings::coarse() };
    /// assert!(grid.scattered_grid());
    /// let uncached = LightingCacheSettings { scattered_light: ScatteredLight::Grid, ..Default::default() };
    /// assert!(!uncached.scattered_grid()); // no cache: merged lights
    /// ```
    #[must_use]
    pub fn scattered_grid(&self) -> bool {
        self.mode == CacheMode::Coarse && self.scattered_light == ScatteredLight::Grid
    }

    /// Checks the layout before any work: a fixed spacing of 0.25 to 16 voxels, an optical
    /// depth a cell of 0.01 to 100, a first level of at most 21 (a level above the hierarchy's
    /// top caches nothing), scattered depths 1 to 8 voxels apart (or 0: automatic), a near
    /// reach of at least [`MIN_NEAR_REACH`](crate::near_part::MIN_NEAR_REACH) voxels.
    ///
    /// ```
    /// use lgh_volume::lighting_cache::{CacheSpacing, LightingCacheSettings};
    ///
    /// let zero = LightingCacheSettings { spacing: CacheSpacing::Voxels(0.0), ..LightingCacheSettings::coarse() };
    /// assert_eq!(
    ///     zero.check().unwrap_err().to_string(),
    ///     "lighting cache: spacing 0 must be 0.25 to 16 voxels"
    /// );
    /// let far = LightingCacheSettings { scattered_spacing: 9, ..LightingCacheSettings::coarse() };
    /// assert_eq!(
    ///     far.check().unwrap_err().to_string(),
    ///     "lighting cache: spacing of the scattered depths 9 must be 1 to 8 voxels (0: automatic)"
    /// );
    /// ```
    pub fn check(&self) -> Result<(), RenderError> {
        match self.spacing {
            CacheSpacing::Voxels(v) => check_setting(
                (0.25..=16.0).contains(&v),
                "lighting cache: spacing",
                v,
                "must be 0.25 to 16 voxels",
            )?,
            CacheSpacing::OpticalDepth(t) => check_setting(
                (0.01..=100.0).contains(&t),
                "lighting cache: optical depth a cell",
                t,
                "must be 0.01 to 100",
            )?,
        };
        check_setting(
            self.first_level <= lgh_core::MAX_LEVEL,
            "lighting cache: first level",
            f32::from(self.first_level),
            "must be 0 to 21",
        )?;
        check_setting(
            (0..=8).contains(&self.scattered_spacing),
            "lighting cache: spacing of the scattered depths",
            f32::from(self.scattered_spacing),
            "must be 1 to 8 voxels (0: automatic)",
        )?;
        if let Some(reach) = self.near_reach {
            NearPart::new(reach, 1.0)?;
        }
        Ok(())
    }
}

/// What filling a cache cost, summed over the bricks filled so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CacheStats {
    /// Vertices computed.
    pub vertices: u64,
    /// Seconds spent computing them, summed over threads (CPU-seconds).
    pub cpu_seconds: f64,
    /// Lights evaluated at them.
    pub lights_evaluated: u64,
    /// Density samples their shadows took.
    pub shadow_samples: u64,
}

/// The coarse levels' incident light `Σ_{ℓ≥ℓ_c} Σ_i V g B_ℓ I` at the vertices of grids over a
/// volume's box — one grid per run of levels that share a spacing — filled brick by brick on
/// demand (see the module docs).
#[derive(Debug)]
pub struct LightingCache {
    settings: LightingCacheSettings,
    /// The grids, finest (lowest levels) first.
    tiers: Vec<Lattice>,
    /// `σ_t` per unit density.
    kappa: f32,
    /// Level 0's near part, where a grid keeps level 0 as a ratio (`None`: all of it summed
    /// at every sample).
    near: Option<NearPart>,
    vertices: AtomicU64,
    nanos: AtomicU64,
    lights_evaluated: AtomicU64,
    shadow_samples: AtomicU64,
}

/// One grid of the cache: the levels it holds and its vertices.
#[derive(Debug)]
struct Lattice {
    /// The levels, `first..=last`.
    first: u8,
    last: u8,
    /// What it keeps of level 0, if it holds level 0: its light ([`Level0Form::Light`]), its
    /// vertices' shadowed and unshadowed light, which [`LightingCache::lookup`] reads as a
    /// ratio ([`Level0Form::Ratio`]), or its far part's light ([`Level0Form::FarLight`]).
    level0: Option<Level0Form>,
    /// World position of vertex (0, 0, 0): the first voxel centre.
    origin: Vec3,
    /// The spacing in voxels, in world units, and its inverse.
    voxels: f32,
    spacing: f32,
    inv_spacing: f32,
    /// Vertices per axis.
    dims: [usize; 3],
    /// Bricks per axis.
    bricks: [usize; 3],
    /// Each brick's [`BRICK`]³ values once filled, x fastest.
    filled: Vec<OnceLock<Brick>>,
}

/// A filled brick's vertices, x fastest.
#[derive(Debug)]
struct Brick {
    vertices: Box<[Vertex]>,
    /// On a ratio grid, level 0's unshadowed light at each vertex (empty elsewhere).
    level0: Box<[Level0Vertex]>,
}

impl Lattice {
    /// An empty grid of levels `first..=last` over `density`'s box, `voxels` voxels apart.
    fn new(
        density: &DenseGrid,
        voxels: f32,
        first: u8,
        last: u8,
        level0: Option<Level0Form>,
    ) -> Self {
        let spacing = density.voxel_size * voxels;
        let dims = density.dims.map(|n| {
            let span = n.saturating_sub(1) as f32 / voxels;
            span.ceil() as usize + 1
        });
        let bricks = dims.map(|n| n.div_ceil(BRICK));
        let count = bricks.iter().product();
        Lattice {
            first,
            last,
            level0,
            origin: density.centre(0, 0, 0),
            voxels,
            spacing,
            inv_spacing: 1.0 / spacing,
            dims,
            bricks,
            filled: (0..count).map(|_| OnceLock::new()).collect(),
        }
    }

    /// Whether it keeps level 0 as a ratio.
    fn ratio(&self) -> bool {
        self.level0 == Some(Level0Form::Ratio)
    }

    /// World position of vertex `v`.
    fn vertex(&self, v: [usize; 3]) -> Vec3 {
        self.origin + Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32) * self.spacing
    }
}

impl LightingCache {
    /// An empty cache over `density`'s box in `medium` with `settings` (checked), for the
    /// levels of `hierarchy` from the settings' first up: each level's spacing is the
    /// settings' (by optical depth, at most half the level's `h_ℓ`), and the levels that share
    /// one share a grid of vertices from the first voxel centre to (at least) the last.
    ///
    /// ```
    /// use lgh_volume::lighting_cache::{CacheSpacing, LightingCache, LightingCacheSettings};
    /// use lgh_volume::{explosion, ExplosionLights, Medium};
    ///
    /// let volume = explosion(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let lights = ExplosionLights::new(&[&volume], &medium)?;
    /// let voxels = LightingCacheSettings { spacing: CacheSpacing::Voxels(1.0), ..LightingCacheSettings::coarse() };
    /// let cache = LightingCache::new(&volume.density, &medium, lights.hierarchy(), &voxels)?;
    /// assert_eq!(cache.dims(), [32; 3]);
    /// assert_eq!(cache.stats().vertices, 0); // nothing computed before it is sampled
    /// // By optical depth: this coarse explosion's soot is 3.8 deep a voxel, so a quarter voxel
    /// // for every level.
    /// let auto = LightingCacheSettings::coarse();
    /// let auto = LightingCache::new(&volume.density, &medium, lights.hierarchy(), &auto)?;
    /// assert_eq!(auto.spacing_voxels(), 0.25);
    /// assert_eq!(auto.tiers().len(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(
        density: &DenseGrid,
        medium: &Medium,
        hierarchy: &LightingGridHierarchy,
        settings: &LightingCacheSettings,
    ) -> Result<Self, RenderError> {
        settings.check()?;
        let kappa = medium.extinction(1.0);
        let (h, h1) = (density.voxel_size, hierarchy.h1());
        let by_depth = match settings.spacing {
            CacheSpacing::Voxels(_) => None,
            CacheSpacing::OpticalDepth(t) => {
                let depth = kappa * dense_smoke(density) * h;
                Some(if depth > 0.0 { t / depth } else { MAX_SPACING })
            }
        };
        // Each level's spacing: fixed, or by optical depth and at most half its h_ℓ (its B_ℓ
        // and fall-off vary over h_ℓ = 2^ℓ h1 / 2) but not below a voxel on that account: level
        // 0's lights are the voxels themselves, and its vertices on their centres (module docs).
        let spacing = |level: u8| match (settings.spacing, by_depth) {
            (CacheSpacing::Voxels(v), _) => v,
            (_, depth) => {
                let h_level = 0.5 * h1 * 2f32.powi(i32::from(level));
                aligned(
                    depth
                        .unwrap_or(MAX_SPACING)
                        .min((0.5 * h_level / h).max(1.0)),
                )
            }
        };
        let mut tiers: Vec<Lattice> = Vec::new();
        let top = hierarchy.max_level().max(settings.first_level);
        for level in settings.first_level..=top {
            let voxels = spacing(level);
            match tiers.last_mut() {
                // Level 0 keeps a grid of its own: blended linearly (its near field), while
                // the coarse levels blend in the logarithm (module docs).
                Some(t) if t.voxels == voxels && t.first > 0 => t.last = level,
                _ => {
                    // A far part needs a near part to sum at the samples.
                    let form = match settings.level0.for_lights(RenderedLights::Emission) {
                        Level0Form::FarLight if settings.near_reach.is_none() => Level0Form::Light,
                        form => form,
                    };
                    let level0 = (level == 0).then_some(form);
                    tiers.push(Lattice::new(density, voxels, level, level, level0));
                }
            }
        }
        if let Some(t) = tiers.last_mut() {
            t.last = u8::MAX; // whatever lies above, as the backend's levels do
        }
        let near = settings
            .near_reach
            .map(|r| NearPart::new(r, h))
            .transpose()?;
        Ok(LightingCache {
            settings: *settings,
            tiers,
            kappa,
            near,
            vertices: AtomicU64::new(0),
            nanos: AtomicU64::new(0),
            lights_evaluated: AtomicU64::new(0),
            shadow_samples: AtomicU64::new(0),
        })
    }

    /// Vertices per axis of the finest grid.
    #[must_use]
    pub fn dims(&self) -> [usize; 3] {
        self.tiers[0].dims
    }

    /// The finest grid's spacing, in voxels (chosen by optical depth, or as set).
    #[must_use]
    pub fn spacing_voxels(&self) -> f32 {
        self.tiers[0].voxels
    }

    /// Each grid's first level and spacing in voxels, finest first (one grid with a fixed
    /// spacing; by optical depth, coarser levels may get coarser grids).
    #[must_use]
    pub fn tiers(&self) -> Vec<(u8, f32)> {
        self.tiers.iter().map(|t| (t.first, t.voxels)).collect()
    }

    /// The layout.
    #[must_use]
    pub fn settings(&self) -> &LightingCacheSettings {
        &self.settings
    }

    /// What filling the cache has cost so far.
    #[must_use]
    pub fn stats(&self) -> CacheStats {
        CacheStats {
            vertices: self.vertices.load(Ordering::Relaxed),
            cpu_seconds: self.nanos.load(Ordering::Relaxed) as f64 * 1e-9,
            lights_evaluated: self.lights_evaluated.load(Ordering::Relaxed),
            shadow_samples: self.shadow_samples.load(Ordering::Relaxed),
        }
    }

    /// What the cache holds at `x`, where the extinction is `sigma_t`: the light of the grids
    /// that keep light, and level 0's shadowing where a grid keeps it as a ratio. On each grid,
    /// the eight vertices around `x` (the nearest face of the grid beyond its outermost
    /// vertices) interpolated as the module docs say, their bricks filled with `coarse`'s
    /// lights of the grid's levels and `visibility` first if they are not yet (`density` gives
    /// the vertices' extinction).
    pub(crate) fn lookup(
        &self,
        x: Vec3,
        sigma_t: f32,
        coarse: &Lights<LghBackend<'_>>,
        visibility: &Visibility,
        density: &DenseGrid,
    ) -> Result<Cached, QueryError> {
        QueryError::check_point(x)?;
        let mut cached = Cached::default();
        for tier in &self.tiers {
            let source = Source::of(tier, coarse, visibility, density);
            let corners = self.corners(tier, x, &source)?;
            if tier.ratio() {
                cached.shadowing = ratio(&corners, sigma_t);
                cached.far = corners
                    .iter()
                    .map(|c| c.level0.far * c.weight)
                    .sum::<Vec3>();
                continue;
            }
            // A grid that holds level 0 holds the voxel lights' near field: blended linearly.
            let blend = if tier.first == 0 {
                Blend::Linear
            } else {
                Blend::Geometric
            };
            cached.light += interpolate(&corners, sigma_t, blend);
        }
        Ok(cached)
    }

    /// How the grid that holds level 0 holds it, as resolved for the frame's lights
    /// ([`Level0Form::Auto`] never; a far light without a near part is kept as
    /// [`Level0Form::Light`]); `None` where the cache starts above level 0.
    #[must_use]
    pub fn level0(&self) -> Option<Level0Form> {
        self.tiers.iter().find_map(|t| t.level0)
    }

    /// Whether level 0 is kept as a ratio ([`Level0Form::Ratio`]): then the cache's light
    /// leaves it out, and its shadowing multiplies level 0's unshadowed light, summed at the
    /// sample.
    #[must_use]
    pub fn level0_ratio(&self) -> bool {
        self.tiers.iter().any(Lattice::ratio)
    }

    /// Whether level 0's far part is kept as light ([`Level0Form::FarLight`]): then its near
    /// part is summed at every sample, with its shadows.
    #[must_use]
    pub fn level0_far_light(&self) -> bool {
        self.tiers
            .iter()
            .any(|t| t.level0 == Some(Level0Form::FarLight))
    }

    /// The eight vertices of grid `tier` around `x` (the nearest face of the grid beyond its
    /// outermost vertices), with their offsets to `x` and trilinear weights, their bricks
    /// filled from `source` first where they are not yet.
    fn corners(
        &self,
        tier: &Lattice,
        x: Vec3,
        source: &Source<'_, '_>,
    ) -> Result<[Corner; 8], QueryError> {
        let u = (x - tier.origin) * tier.inv_spacing;
        let mut base = [0usize; 3];
        let mut w = [0.0f32; 3];
        for a in 0..3 {
            let top = tier.dims[a].saturating_sub(1) as f32;
            let c = u[a].clamp(0.0, top);
            let i = (c as usize).min(tier.dims[a].saturating_sub(2));
            base[a] = i;
            w[a] = (c - i as f32).clamp(0.0, 1.0);
        }
        let mut corners = [Corner::default(); 8];
        for (n, corner) in corners.iter_mut().enumerate() {
            let d = [n & 1, (n >> 1) & 1, n >> 2];
            let weight: f32 = (0..3)
                .map(|a| if d[a] == 1 { w[a] } else { 1.0 - w[a] })
                .product();
            if weight > 0.0 {
                let v = core::array::from_fn(|a| (base[a] + d[a]).min(tier.dims[a] - 1));
                let (vertex, level0) = self.value(tier, v, source)?;
                *corner = Corner {
                    vertex,
                    level0,
                    offset: x - tier.vertex(v),
                    weight,
                };
            }
        }
        Ok(corners)
    }

    /// Vertex `v` of grid `tier` and its level-0 values (zero but on a ratio grid), its brick
    /// filled from `source` first if need be.
    fn value(
        &self,
        tier: &Lattice,
        v: [usize; 3],
        source: &Source<'_, '_>,
    ) -> Result<(Vertex, Level0Vertex), QueryError> {
        let b = v.map(|i| i / BRICK);
        let index = (b[2] * tier.bricks[1] + b[1]) * tier.bricks[0] + b[0];
        let cell = &tier.filled[index];
        let values = match cell.get() {
            Some(values) => values,
            None => {
                let (values, count, stats) = self.fill(tier, b, source)?;
                // Another thread may have set the same values first: then this work is counted
                // in the seconds only.
                if cell.set(values).is_ok() {
                    self.vertices.fetch_add(count, Ordering::Relaxed);
                    self.lights_evaluated
                        .fetch_add(stats.lights_evaluated, Ordering::Relaxed);
                    self.shadow_samples
                        .fetch_add(stats.shadow_samples, Ordering::Relaxed);
                }
                cell.get().expect("set above")
            }
        };
        let [i, j, k] = v.map(|i| i % BRICK);
        let at = (k * BRICK + j) * BRICK + i;
        let level0 = values.level0.get(at).copied().unwrap_or_default();
        Ok((values.vertices[at], level0))
    }

    /// Computes brick `b` of grid `tier` from `source` (its vertices outside the grid stay
    /// zero); also returns how many it computed and their work counts.
    fn fill(
        &self,
        tier: &Lattice,
        b: [usize; 3],
        source: &Source<'_, '_>,
    ) -> Result<(Brick, u64, RenderStats), QueryError> {
        let Source {
            lights,
            visibility,
            density,
        } = source;
        let t = Instant::now();
        const N: usize = BRICK * BRICK * BRICK;
        let mut values = vec![Vertex::default(); N].into_boxed_slice();
        let mut level0 = vec![Level0Vertex::default(); if tier.ratio() { N } else { 0 }];
        // On a ratio grid, the far part of level 0's unshadowed light; on a grid of level 0's
        // far light, that light (`near_part`).
        let far_light = tier.level0 == Some(Level0Form::FarLight);
        let far = (self.near)
            .filter(|_| tier.ratio() || far_light)
            .map(|part| move |d: f32| 1.0 - part.weight(d));
        let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
        let mut count = 0u64;
        for k in 0..BRICK {
            for j in 0..BRICK {
                for i in 0..BRICK {
                    let v = [b[0] * BRICK + i, b[1] * BRICK + j, b[2] * BRICK + k];
                    if (0..3).any(|a| v[a] >= tier.dims[a]) {
                        continue;
                    }
                    let x = tier.vertex(v);
                    let sigma_t = self.kappa * density.sample(x);
                    let split = lights.incident_flux(
                        x,
                        sigma_t,
                        visibility,
                        far,
                        &mut scratch,
                        &mut stats,
                    )?;
                    let lum = lgh_core::luminance(split.light);
                    let at = (k * BRICK + j) * BRICK + i;
                    if let Some(v) = level0.get_mut(at) {
                        *v = Level0Vertex {
                            unshadowed: split.unshadowed,
                            far: split.far, // 0 without a near part
                        };
                    }
                    values[at] = Vertex {
                        light: if far_light {
                            split.far_light
                        } else {
                            split.light
                        },
                        direction: if lum > 0.0 {
                            split.flux / lum
                        } else {
                            Vec3::ZERO
                        },
                        sigma_t,
                    };
                    count += 1;
                }
            }
        }
        self.nanos
            .fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
        let brick = Brick {
            vertices: values,
            level0: level0.into_boxed_slice(),
        };
        Ok((brick, count, stats))
    }
}

/// The largest spacing of at most `voxels` voxels that keeps the vertices on the voxel
/// centres' lattice — `1/k` or `k` voxels — between [`MIN_SPACING`] and [`MAX_SPACING`]: off
/// the density's own lattice the interpolation errs more (the demo's explosion: 2.17% at 1.058
/// voxels against 1.82% at 1).
#[must_use]
fn aligned(voxels: f32) -> f32 {
    let v = voxels.clamp(MIN_SPACING, MAX_SPACING);
    if v >= 1.0 {
        v.floor()
    } else {
        1.0 / (1.0 / v).ceil()
    }
}

/// The 99th percentile of `density` over its voxels with smoke (0 without smoke): the densest
/// smoke, give or take a few outlying voxels.
#[must_use]
fn dense_smoke(density: &DenseGrid) -> f32 {
    let mut smoke: Vec<f32> = density.data.iter().copied().filter(|&d| d > 0.0).collect();
    if smoke.is_empty() {
        return 0.0;
    }
    let k = (smoke.len() - 1) * 99 / 100;
    *smoke.select_nth_unstable_by(k, f32::total_cmp).1
}

/// What a grid's vertices are computed from: the lights of its levels, their visibility, and
/// the density (for the vertices' extinction).
struct Source<'s, 'l> {
    lights: Lights<LghBackend<'l>>,
    visibility: &'s Visibility,
    density: &'s DenseGrid,
}

impl<'s, 'l> Source<'s, 'l> {
    /// Grid `tier`'s levels of `lights`, with `visibility` and `density`.
    fn of(
        tier: &Lattice,
        lights: &Lights<LghBackend<'l>>,
        visibility: &'s Visibility,
        density: &'s DenseGrid,
    ) -> Self {
        Source {
            lights: lights.with_backend(lights.backend.with_levels(tier.first..=tier.last)),
            visibility,
            density,
        }
    }
}

/// What the cache gives at a point ([`LightingCache::lookup`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Cached {
    /// The light of the grids that keep light.
    pub(crate) light: Vec3,
    /// Level 0's shadowing, per channel: the ratio `Σ_v w_v Ŝ_v / Σ_v w_v U_v` of its shadowed
    /// light `S_v` (extrapolated along its shadow's gradient as the module docs say, `Ŝ_v`)
    /// and its unshadowed light `U_v` at the eight vertices around the point with their
    /// trilinear weights `w_v`, a channel none of them has light in taking the ratio of their
    /// luminances ([`ratio`]). `None` without a ratio grid, or where no vertex around the point
    /// has level-0 light: then the point needs level 0 exactly.
    pub(crate) shadowing: Option<Vec3>,
    /// On a ratio grid with a near part, the far part of level 0's unshadowed light,
    /// `Σ_v w_v U_far,v` (`near_part`; 0 otherwise).
    pub(crate) far: Vec3,
}

/// What the cache holds at a vertex.
#[derive(Clone, Copy, Debug, Default)]
struct Vertex {
    /// The coarse levels' incident light `L` (on a ratio grid, level 0's shadowed light `S`).
    light: Vec3,
    /// Its flux vector over its luminance, `F / lum(L)`: the mean direction the light travels,
    /// of length at most 1 (see [`Lights::incident_flux`]).
    direction: Vec3,
    /// The extinction `σ_t` there.
    sigma_t: f32,
}

/// What a ratio grid also holds at a vertex: level 0's unshadowed light.
#[derive(Clone, Copy, Debug, Default)]
struct Level0Vertex {
    /// All of it, `U_v`.
    unshadowed: Vec3,
    /// Its far part `U_far,v` (`near_part`; 0 without a near part).
    far: Vec3,
}

/// One of the eight vertices around a sample: its values, the offset `x − v` from it to the
/// sample, and its trilinear weight (0 for a corner that does not count).
#[derive(Clone, Copy, Debug, Default)]
struct Corner {
    vertex: Vertex,
    /// Zero but on a ratio grid.
    level0: Level0Vertex,
    offset: Vec3,
    weight: f32,
}

/// How the corners' estimates are blended (module docs, step 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Blend {
    /// In the logarithm, with a floor of a thousandth of the linear blend: the coarse levels.
    Geometric,
    /// With the trilinear weights: a grid that holds level 0.
    Linear,
}

/// Corner `c`'s light extrapolated to a sample of extinction `sigma_t` along its shadow's
/// gradient, `L_v e^{−σ̄ (x − v)·d_v}` (module docs, step 1).
#[must_use]
fn extrapolated(c: &Corner, sigma_t: f32) -> Vec3 {
    // ln of the largest factor the extrapolation may apply (e^±30): far beyond any physical
    // σ̄ |δ| of a cell, it only keeps the exponential finite.
    const MAX_EXPONENT: f32 = 30.0;
    let sigma = 0.5 * (c.vertex.sigma_t + sigma_t);
    let exponent = -sigma * c.offset.dot(c.vertex.direction);
    c.vertex.light * exponent.clamp(-MAX_EXPONENT, MAX_EXPONENT).exp()
}

/// The light at a sample of extinction `sigma_t` from the `corners` around it: each corner's
/// light extrapolated along its shadow's gradient, then blended as `blend` says (see the
/// module docs).
#[must_use]
fn interpolate(corners: &[Corner; 8], sigma_t: f32, blend: Blend) -> Vec3 {
    let mut estimates = [Vec3::ZERO; 8];
    let mut linear = Vec3::ZERO;
    for (e, c) in estimates.iter_mut().zip(corners) {
        if c.weight > 0.0 {
            *e = extrapolated(c, sigma_t);
            linear += *e * c.weight;
        }
    }
    if blend == Blend::Linear {
        return linear;
    }
    let floor = linear * 1e-3;
    let mut log = Vec3::ZERO;
    // Channels where a corner's light is negative (Blender's blackbody below about 1900 K: a cool
    // flame's light has a blue below 0) have no logarithm: they take the linear blend.
    let mut negative = BVec3::FALSE;
    for (e, c) in estimates.iter().zip(corners) {
        if c.weight > 0.0 {
            log += Vec3::from((*e + floor).to_array().map(f32::ln)) * c.weight;
            negative |= e.cmplt(Vec3::ZERO);
        }
    }
    let out = Vec3::from(log.to_array().map(f32::exp)) - floor;
    // Where every corner is black, so is the sample (ln 0 = −∞, e^−∞ = 0, 0 − 0 = 0 — or NaN
    // from −∞ · 0 weights, which this rules out).
    let geometric = Vec3::select(linear.cmpgt(Vec3::ZERO), out.max(Vec3::ZERO), Vec3::ZERO);
    Vec3::select(negative, linear, geometric)
}

/// Level 0's shadowing at a sample of extinction `sigma_t` from the `corners` of a ratio grid
/// around it, as [`Cached::shadowing`] says.
#[must_use]
fn ratio(corners: &[Corner; 8], sigma_t: f32) -> Option<Vec3> {
    let (mut shadowed, mut unshadowed) = (Vec3::ZERO, Vec3::ZERO);
    // Channels where a corner's light is negative (Blender's blackbody below about 1900 K):
    // their sums mix both signs and may nearly cancel, so their quotient means nothing; they
    // take the luminance's shadowing, as a channel without light does.
    let mut mixed = BVec3::FALSE;
    for c in corners.iter().filter(|c| c.weight > 0.0) {
        let (s, u) = (extrapolated(c, sigma_t), c.level0.unshadowed);
        shadowed += s * c.weight;
        unshadowed += u * c.weight;
        mixed |= s.cmplt(Vec3::ZERO) | u.cmplt(Vec3::ZERO);
    }
    let grey = lgh_core::luminance(unshadowed);
    if grey <= 0.0 {
        return None;
    }
    let grey = lgh_core::luminance(shadowed) / grey;
    let r = Vec3::select(
        unshadowed.cmpgt(Vec3::ZERO) & !mixed,
        shadowed / unshadowed,
        Vec3::splat(grey),
    );
    Some(r)
}

/// A frame's lights split for a cache: the finest levels shaded per point, the coarse ones
/// through the cache.
pub(crate) struct CachedLights<'l> {
    pub(crate) cache: &'l LightingCache,
    pub(crate) density: &'l DenseGrid,
    /// Levels below the cache's first, shaded at every sample (none when it caches every
    /// level); with level 0 kept as a ratio, level 0, unshadowed.
    pub(crate) fine: Option<Lights<LghBackend<'l>>>,
    /// With the cache's near part ([`NearPart`]), the lights within its reach, summed per
    /// point with its weight (made once here, not at every point): level 0's, unshadowed, on a
    /// ratio grid; every level's, shadowed, on a grid of level 0's far light.
    near: Option<(NearPart, Lights<LghBackend<'l>>)>,
    /// The cached levels, what the cache is filled with.
    pub(crate) coarse: Lights<LghBackend<'l>>,
}

impl<'l> CachedLights<'l> {
    /// `lights` split at `cache`'s first level (`density` gives the vertices' extinction).
    pub(crate) fn new(
        cache: &'l LightingCache,
        density: &'l DenseGrid,
        lights: &Lights<LghBackend<'l>>,
    ) -> Self {
        let first = cache.settings.first_level;
        let split = |levels| lights.with_backend(lights.backend.with_levels(levels));
        let fine = if cache.level0_ratio() {
            Some(split(0..=0))
        } else {
            first.checked_sub(1).map(|last| split(0..=last))
        };
        let within = |part: NearPart, l: &Lights<LghBackend<'l>>| {
            (part, l.with_backend(l.backend.within(part.reach())))
        };
        let near = if cache.level0_far_light() {
            cache.near.map(|part| within(part, lights))
        } else {
            cache
                .near
                .zip(fine.as_ref())
                .map(|(part, fine)| within(part, fine))
        };
        CachedLights {
            cache,
            density,
            fine,
            near,
            coarse: split(first..=u8::MAX),
        }
    }

    /// A frame's `lights` split at `cache`'s first level, if there is a cache and the lights
    /// are the hierarchy's (`None` otherwise: shade them per point).
    pub(crate) fn of(
        cache: Option<&'l LightingCache>,
        density: &'l DenseGrid,
        lights: &Lights<FrameBackend<'l>>,
    ) -> Option<Self> {
        match (cache, &lights.backend) {
            (Some(cache), FrameBackend::Lgh(b)) => {
                Some(CachedLights::new(cache, density, &lights.with_backend(*b)))
            }
            _ => None,
        }
    }

    /// The light in-scattered at `x`, where the extinction is `sigma_t`
    /// ([`Lights::in_scattered`]): the fine levels exactly, the coarse ones from the cache.
    pub(crate) fn in_scattered(
        &self,
        x: Vec3,
        scale: f32,
        sigma_t: f32,
        visibility: &Visibility,
        scratch: &mut LightScratch,
        stats: &mut RenderStats,
    ) -> Result<Vec3, QueryError> {
        let (coarse, density) = (&self.coarse, self.density);
        let cached = self.cache.lookup(x, sigma_t, coarse, visibility, density)?;
        let fine = match (&self.fine, cached.shadowing) {
            (Some(fine), Some(r)) => {
                let none = &Visibility::None;
                let unshadowed = match &self.near {
                    // The near part summed, the far part interpolated (`near_part`).
                    Some((part, near)) => {
                        let w = |d| part.weight(d);
                        let near = near.unshadowed_part(x, scale, sigma_t, w, scratch, stats)?;
                        near + cached.far * (ISOTROPIC_PHASE * scale)
                    }
                    None => fine.in_scattered(x, scale, sigma_t, none, scratch, stats)?,
                };
                unshadowed * r
            }
            (Some(fine), None) => {
                fine.in_scattered(x, scale, sigma_t, visibility, scratch, stats)?
            }
            (None, _) => match &self.near {
                // Level 0's far light cached: its near part summed, shadowed (`near_part`).
                Some((part, near)) if self.cache.level0_far_light() => {
                    let w = |d| part.weight(d);
                    near.in_scattered_part(x, sigma_t, visibility, w, scratch, stats)? * scale
                }
                _ => Vec3::ZERO,
            },
        };
        let coarse = cached.light;
        Ok(fine + coarse * (ISOTROPIC_PHASE * scale))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eight corners of the unit cell at `origin` around `x`, each vertex's values from
    /// `vertex(corner position)`.
    fn cell(x: Vec3, origin: Vec3, vertex: impl Fn(Vec3) -> Vertex) -> [Corner; 8] {
        cell_of_ratios(x, origin, |p| (vertex(p), Level0Vertex::default()))
    }

    /// [`cell`] of a ratio grid: each vertex's values and level-0 values from `vertex`.
    fn cell_of_ratios(
        x: Vec3,
        origin: Vec3,
        vertex: impl Fn(Vec3) -> (Vertex, Level0Vertex),
    ) -> [Corner; 8] {
        let f = x - origin;
        core::array::from_fn(|n| {
            let d = Vec3::new((n & 1) as f32, ((n >> 1) & 1) as f32, (n >> 2) as f32);
            let weight = (0..3)
                .map(|a| if d[a] == 1.0 { f[a] } else { 1.0 - f[a] })
                .product();
            let v = origin + d;
            let (vertex, level0) = vertex(v);
            Corner {
                vertex,
                level0,
                offset: x - v,
                weight,
            }
        })
    }

    /// Light travelling along `omega` (unit) through smoke of constant extinction `sigma`:
    /// `L0 e^{−σ p·ω}` at `p`, its direction `ω`.
    fn beam(l0: Vec3, omega: Vec3, sigma: f32) -> impl Fn(Vec3) -> Vertex {
        move |p| Vertex {
            light: l0 * (-sigma * p.dot(omega)).exp(),
            direction: omega,
            sigma_t: sigma,
        }
    }

    #[test]
    fn level0s_ratio_is_the_shadowing_weighted_by_the_unshadowed_light() {
        // Every vertex shadowed by the same factor per channel (its light from no one
        // direction: no extrapolation): that factor, wherever the sample lies in the cell.
        let r = Vec3::new(0.5, 0.25, 0.125);
        let shadowed = |dark_blue: bool| {
            move |p: Vec3| {
                let mut u = Vec3::new(1.0, 2.0, 3.0) + p * 7.0;
                if dark_blue {
                    u.z = 0.0;
                }
                let vertex = Vertex {
                    light: u * r,
                    direction: Vec3::ZERO,
                    sigma_t: 2.0,
                };
                let level0 = Level0Vertex {
                    unshadowed: u,
                    far: Vec3::ZERO,
                };
                (vertex, level0)
            }
        };
        let mut rng = lgh_core::random::SplitMix64(5);
        for _ in 0..50 {
            let x = rng.next_in(Vec3::ZERO, Vec3::ONE);
            let got = ratio(&cell_of_ratios(x, Vec3::ZERO, shadowed(false)), 2.0).unwrap();
            assert!((got - r).abs().max_element() < 1e-6, "{x}: {got}");
            // A channel with no light at any corner takes the luminance's ratio.
            let corners = cell_of_ratios(x, Vec3::ZERO, shadowed(true));
            let got = ratio(&corners, 2.0).unwrap();
            let mean = |f: fn(&Corner) -> Vec3| {
                let sum = corners.iter().map(|c| f(c) * c.weight).sum::<Vec3>();
                lgh_core::luminance(sum)
            };
            let grey = mean(|c| c.vertex.light) / mean(|c| c.level0.unshadowed);
            assert!(
                (got.z - grey).abs() < 1e-3 * grey,
                "{x}: {got} against {grey}"
            );
            assert!((got.truncate() - r.truncate()).abs().max_element() < 1e-6);
        }
        // Where no corner has level-0 light: none, so the sample shades level 0 exactly.
        let dark = |_: Vec3| Vertex::default();
        assert_eq!(ratio(&cell(Vec3::splat(0.5), Vec3::ZERO, dark), 1.0), None);
    }

    #[test]
    fn a_vertex_gives_its_own_value() {
        let beam = beam(Vec3::new(1.0, 0.5, 0.2), Vec3::X, 3.0);
        for n in 0..8 {
            let v = Vec3::new((n & 1) as f32, ((n >> 1) & 1) as f32, (n >> 2) as f32);
            let got = interpolate(&cell(v, Vec3::ZERO, &beam), 3.0, Blend::Geometric);
            let want = beam(v).light;
            assert!(
                (got - want).abs().max_element() <= 1e-6 * want.max_element(),
                "{v}"
            );
        }
    }

    #[test]
    fn light_from_one_direction_through_uniform_smoke_is_exact() {
        // σ = 4 per cell: the light falls by e^−4 across the cell, where a trilinear blend of the
        // corners errs by up to (1 + e^−4)/2 / e^−2 = 3.8× at the centre. The extrapolation along
        // the gradient is exact and so is the blend: rounding only.
        let omega = Vec3::new(0.6, -0.48, 0.64);
        let sigma = 4.0;
        let beam = beam(Vec3::new(2.0, 1.0, 0.5), omega, sigma);
        let mut rng = lgh_core::random::SplitMix64(3);
        for _ in 0..200 {
            let x = rng.next_in(Vec3::ZERO, Vec3::ONE);
            let got = interpolate(&cell(x, Vec3::ZERO, &beam), sigma, Blend::Geometric);
            let want = beam(x).light;
            let err = ((got - want) / want).abs().max_element();
            assert!(err < 1e-5, "{x}: {got} against {want}");
        }
    }

    #[test]
    fn without_a_gradient_the_blend_is_geometric_and_keeps_a_black_corner_from_blacking_out() {
        let lit = |l: f32| {
            move |p: Vec3| Vertex {
                light: Vec3::splat(if p.x > 0.5 { l } else { 0.0 }),
                direction: Vec3::ZERO,
                sigma_t: 0.0,
            }
        };
        // Half the corners black, at the centre: the linear blend is 0.5, the geometric blend
        // of (1 + ε, ε) with ε = 0.0005 is √(1.0005 · 0.0005) − ε ≈ 0.0219.
        let got = interpolate(
            &cell(Vec3::splat(0.5), Vec3::ZERO, lit(1.0)),
            0.0,
            Blend::Geometric,
        );
        let want = (1.0005f32 * 0.0005).sqrt() - 0.0005;
        assert!((got.x - want).abs() < 1e-5, "{got}");
        // Every corner black: black, not NaN.
        let got = interpolate(
            &cell(Vec3::splat(0.3), Vec3::ZERO, lit(0.0)),
            0.0,
            Blend::Geometric,
        );
        assert_eq!(got, Vec3::ZERO);
        // Scaling the light scales the result (the floor is relative).
        let a = interpolate(
            &cell(Vec3::splat(0.7), Vec3::ZERO, lit(1.0)),
            0.0,
            Blend::Geometric,
        );
        let b = interpolate(
            &cell(Vec3::splat(0.7), Vec3::ZERO, lit(8.0)),
            0.0,
            Blend::Geometric,
        );
        assert!((b - 8.0 * a).abs().max_element() < 1e-5 * b.x, "{a} {b}");
    }

    /// A channel negative at a corner (a cool flame's blue, Blender's blackbody) is blended
    /// linearly, as the logarithm cannot; the other channels keep the geometric blend's bits.
    #[test]
    fn a_negative_channel_is_blended_linearly() {
        let light = |p: Vec3| Vertex {
            light: Vec3::new(1.0 + p.x, 0.5 + p.y, if p.z > 0.5 { 0.2 } else { -0.1 }),
            direction: Vec3::ZERO,
            sigma_t: 0.0,
        };
        let positive = |p: Vec3| Vertex {
            light: light(p).light.with_z(1.0),
            ..light(p)
        };
        let x = Vec3::new(0.3, 0.6, 0.25);
        let got = interpolate(&cell(x, Vec3::ZERO, light), 0.0, Blend::Geometric);
        let linear = interpolate(&cell(x, Vec3::ZERO, light), 0.0, Blend::Linear);
        let geometric = interpolate(&cell(x, Vec3::ZERO, positive), 0.0, Blend::Geometric);
        assert_eq!(got.z, linear.z);
        assert!(
            (linear.z - (0.25 * 0.2 - 0.75 * 0.1)).abs() < 1e-6,
            "{linear}"
        );
        assert_eq!((got.x, got.y), (geometric.x, geometric.y));
        assert_ne!(got.x, linear.x);
    }

    #[test]
    fn the_light_is_continuous_across_a_cell_face() {
        // Arbitrary values at the vertices of two cells sharing the face x = 1; on either side
        // of it, each cell's interpolation tends to the same value.
        let vertex = |p: Vec3| {
            let h = (p.x * 7.0 + p.y * 13.0 + p.z * 29.0).sin().abs();
            Vertex {
                light: Vec3::new(h, h * h, 0.1 + h),
                direction: Vec3::new(p.y - 0.5, 0.3, -p.z).normalize() * 0.8,
                sigma_t: 2.0 + p.x,
            }
        };
        for (y, z) in [(0.2f32, 0.7f32), (0.9, 0.1), (0.5, 0.5)] {
            let eps = 1e-4;
            let left = interpolate(
                &cell(Vec3::new(1.0 - eps, y, z), Vec3::ZERO, vertex),
                2.5,
                Blend::Geometric,
            );
            let right = interpolate(
                &cell(Vec3::new(1.0 + eps, y, z), Vec3::X, vertex),
                2.5,
                Blend::Geometric,
            );
            let jump = (left - right).abs().max_element() / left.max_element();
            assert!(jump < 1e-3, "({y}, {z}): {left} | {right}");
        }
    }
}
