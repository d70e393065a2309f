//! What every render command shares: options for the ray marcher, the progress bar over rows,
//! and the outputs (a linear EXR with the settings in its header, a tone-mapped PNG beside it).

use std::path::{Path, PathBuf};
use std::time::Instant;

use lgh_image::Image;
use lgh_volume::lgh_core::{CoarseSpread, NearField};
use lgh_volume::lighting_cache::{
    CacheMode, CacheSpacing, Level0Form, LightingCache, LightingCacheSettings, ScatteredLight,
};
use lgh_volume::render::{Camera, MarchSettings, PixelRefinement, RenderStats};
use lgh_volume::scattering::{self, ScatterTail, Scattered, Shares};
use lgh_volume::shadow::{CoarseShadows, CubeMapSettings, Depths, LevelMaps};
use lgh_volume::{FrameRender, Shadows};

/// How lights are shadowed (`--shadows`): [`Shadows`]' choices by their command-line names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ShadowsArg {
    /// The paper's deep-shadow cube maps, precomputed per light of every level of the
    /// hierarchy (Sec. 4). Backends without a hierarchy (brute force) ray-march instead.
    #[value(name = "cubemap")]
    CubeMap,
    /// Transmittance ray-marched to every light (exact shadows).
    #[value(name = "raymarch")]
    RayMarch,
    /// The cube maps' own model without the maps, their same-model reference: transmittance
    /// ray-marched from every light's centre through the density prefiltered for it (eq. 6;
    /// coarse lights as volume lights). Slow. Backends without a hierarchy ray-march instead.
    #[value(name = "raymarch-volumes")]
    RayMarchVolumes,
    /// Ray-marched, each light as what it stands for: level-0 lights as points (as raymarch),
    /// coarse lights as the volume lights of eq. 6 in steps that widen with the prefilter —
    /// point shadows let more light through a coarse light's one ray than its lights' rays do.
    /// Backends without a hierarchy ray-march instead
    #[value(name = "volumes")]
    Volumes,
    /// No shadows.
    None,
}

impl From<ShadowsArg> for Shadows {
    fn from(s: ShadowsArg) -> Self {
        match s {
            ShadowsArg::CubeMap => Shadows::CubeMap,
            ShadowsArg::RayMarch => Shadows::RayMarch,
            ShadowsArg::RayMarchVolumes => Shadows::RayMarchVolumes,
            ShadowsArg::Volumes => Shadows::Volumes,
            ShadowsArg::None => Shadows::None,
        }
    }
}

/// The voxel lights' model (`--near-field`): [`NearField`]'s choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum NearFieldArg {
    /// Uniform emitting voxels (`lgh_core::near_field`).
    Voxel,
    /// The paper's clamped point lights.
    Clamp,
}

/// How coarse lights are weighted (`--coarse-spread`): [`CoarseSpread`]'s choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CoarseSpreadArg {
    /// Eq. (3) at each light's centre, as the paper prints it.
    Centre,
    /// Eq. (3)'s blended fall-off averaged over the spread of the voxels each stands for.
    Averaged,
}

impl From<CoarseSpreadArg> for CoarseSpread {
    fn from(c: CoarseSpreadArg) -> Self {
        match c {
            CoarseSpreadArg::Averaged => CoarseSpread::Averaged,
            CoarseSpreadArg::Centre => CoarseSpread::Centre,
        }
    }
}

impl From<NearFieldArg> for NearField {
    fn from(n: NearFieldArg) -> Self {
        match n {
            NearFieldArg::Voxel => NearField::Voxel,
            NearFieldArg::Clamp => NearField::Clamp,
        }
    }
}

/// Whether the coarse levels' light is cached (`--lighting-cache`): [`CacheMode`]'s choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CacheArg {
    /// Every light shaded at every march sample.
    None,
    /// The hierarchy's levels from --cache-level up computed once per frame at the vertices of a
    /// grid over the smoke (filled where the camera's rays need it) and interpolated
    /// trilinearly; the finer levels shaded at every sample. Surfaces keep per-point lighting.
    Coarse,
}

impl From<CacheArg> for CacheMode {
    fn from(c: CacheArg) -> Self {
        match c {
            CacheArg::None => CacheMode::None,
            CacheArg::Coarse => CacheMode::Coarse,
        }
    }
}

/// `--cache-spacing`: `auto` or a number of voxels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpacingArg {
    /// By optical depth (`--cache-depth`).
    Auto,
    /// Voxels apart.
    Voxels(f32),
}

/// `auto` (`None`) or a number of `unit`.
fn parse_auto<T: std::str::FromStr>(s: &str, unit: &str) -> Result<Option<T>, String> {
    parse_or_word(s, "auto", unit)
}

/// `word` (`None`) or a number of `unit`.
fn parse_or_word<T: std::str::FromStr>(
    s: &str,
    word: &str,
    unit: &str,
) -> Result<Option<T>, String> {
    if s == word {
        return Ok(None);
    }
    s.parse::<T>()
        .map(Some)
        .map_err(|_| format!("expected {word} or a number of {unit}, not '{s}'"))
}

/// `--pixel-tolerance`'s default: neighbouring rays that differ by more than 5% of the image's
/// mean luminance refine their pixels (docs/cycles.md, "Adaptive pixels").
pub const DEFAULT_PIXEL_TOLERANCE: f32 = 0.05;

/// The most rays a side `--pixel-samples adaptive` takes first: those whose refinement
/// ([`lgh_volume::render::REFINEMENT`] times as many) stays within
/// [`lgh_volume::render::MAX_PIXEL_SAMPLES`] (4, refined to 8).
const ADAPTIVE_FIRST_RAYS: usize =
    lgh_volume::render::MAX_PIXEL_SAMPLES / lgh_volume::render::REFINEMENT;

/// `--pixel-samples`: rays a pixel side, `auto` (from the image's and the voxels' sizes) or
/// `adaptive` (auto's, at most 4, refined twice as fine where neighbouring rays differ).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelSamplesArg {
    /// This many rays a side.
    Fixed(usize),
    /// [`lgh_volume::render::auto_pixel_samples`].
    Auto,
    /// [`Auto`](Self::Auto)'s rays, at most 4 a side, then
    /// [`lgh_volume::render::PixelRefinement::Adaptive`] at `--pixel-tolerance`.
    Adaptive,
}

/// `--emission-samples`: rays a pixel side for the emission alone, `auto` (from the image's and
/// the voxels' sizes), or as many as the pixel samples (what `lgh demo` takes unless told).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EmissionSamplesArg {
    /// This many rays a side (where at most the pixel samples, every ray marches both).
    Fixed(usize),
    /// [`lgh_volume::render::auto_emission_samples`].
    Auto,
    /// The pixel samples: every ray marches the emission and the light together.
    WithLight,
}

/// `auto` or a number of emission rays a pixel side.
fn parse_emission_samples(s: &str) -> Result<EmissionSamplesArg, String> {
    parse_auto(s, "rays a pixel side")
        .map(|n| n.map_or(EmissionSamplesArg::Auto, EmissionSamplesArg::Fixed))
}

/// `auto`, `adaptive` or a number of rays a pixel side.
fn parse_pixel_samples(s: &str) -> Result<PixelSamplesArg, String> {
    if s == "adaptive" {
        return Ok(PixelSamplesArg::Adaptive);
    }
    parse_auto(s, "rays a pixel side")
        .map(|n| n.map_or(PixelSamplesArg::Auto, PixelSamplesArg::Fixed))
        .map_err(|e| format!("{e} (or adaptive)"))
}

/// `--cache-level`: the lighting cache's first level, or `auto` (from the camera rays' footprint).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CacheLevelArg {
    /// This level.
    Fixed(u8),
    /// [`lgh_volume::lighting_cache::auto_first_level`].
    Auto,
}

/// `auto` or a level.
fn parse_cache_level(s: &str) -> Result<CacheLevelArg, String> {
    Ok(parse_auto(s, "levels")?.map_or(CacheLevelArg::Auto, CacheLevelArg::Fixed))
}

/// `--cache-near`: a reach in voxels, or `None` for `all`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearReachArg(pub Option<f32>);

/// `all` or a number of voxels (checked with the cache's settings).
fn parse_near_reach(s: &str) -> Result<NearReachArg, String> {
    parse_or_word(s, "all", "voxels").map(NearReachArg)
}

/// `auto` or a number of voxels.
fn parse_spacing(s: &str) -> Result<SpacingArg, String> {
    Ok(parse_auto(s, "voxels")?.map_or(SpacingArg::Auto, SpacingArg::Voxels))
}

/// The lighting cache's options, shared by the render commands and `lgh bench flicker`.
#[derive(Debug, Clone, clap::Args)]
pub struct CacheArgs {
    /// Lighting cache for the hierarchy's coarse levels: their in-scattered light computed once
    /// per frame at grid vertices over the smoke and interpolated along each vertex's shadow
    /// gradient, the finest level shaded at every sample (`none`: every light at every sample,
    /// the exact image). Other methods than the hierarchy shade every sample.
    #[arg(long, value_enum, default_value_t = CacheArg::Coarse)]
    pub lighting_cache: CacheArg,
    /// Distance between the lighting cache's vertices: `auto` (cells of --cache-depth optical
    /// depth across the densest smoke, 0.25 to 4 voxels) or voxels (0.25 to 16; 1: the voxel
    /// centres).
    #[arg(long, default_value = "auto", value_parser = parse_spacing)]
    pub cache_spacing: SpacingArg,
    /// With --cache-spacing auto: the optical depth across a cell of the densest smoke (the 99th
    /// percentile of its density); the interpolation's error grows with it.
    #[arg(long, default_value_t = 1.0)]
    pub cache_depth: f32,
    /// The first level of the hierarchy the lighting cache holds (finer levels are shaded at
    /// every sample), or `auto`: 0 where a camera ray's footprint at the volume's centre is at
    /// most 3/4 of a voxel (large images: the march's samples then outnumber level 0's
    /// vertices), 1 otherwise
    #[arg(long, default_value = "auto", value_parser = parse_cache_level)]
    pub cache_level: CacheLevelArg,
    /// Where the lighting cache holds level 0: `ratio` caches only its shadows (the ratio of
    /// shadowed to unshadowed light at the vertices, multiplying level 0's unshadowed light
    /// summed exactly at every sample: no added flicker), `light` its light, interpolated
    /// linearly (cheaper a sample, but it flickers), `far-light` its far part's light with the
    /// lights within --cache-near summed at every sample; `auto`: ratio for the emission's
    /// lights, light for multiple scattering's merged lights (one a smoky voxel: too many to
    /// sum at every sample)
    #[arg(long, value_enum, default_value_t = Level0Arg::Auto)]
    pub cache_level0: Level0Arg,
    /// With level 0 cached as a ratio or far light: the reach, in voxels (at least 0.9), of its
    /// near part, summed at every sample; beyond it level 0's unshadowed (or far) light is
    /// interpolated from the vertices, with a partition of unity between the parts from a
    /// third of the reach to it (`all`: every level-0 light summed at every sample). Shorter
    /// reaches are cheaper and flicker more
    #[arg(long, default_value = "3", value_parser = parse_near_reach)]
    pub cache_near: NearReachArg,
    /// With --scatter-depth and the lighting cache: scattering depths 2 and up compute their
    /// fluence on a grid this many voxels apart (1 to 8), every level cached, and interpolate it
    /// to the voxels (their light has scattered already and varies slowly); 1 computes it at
    /// every voxel, as depth 1 does; auto: 4, 2 or 1, at least 9 cells across the smoke
    #[arg(long, default_value = "auto", value_parser = parse_scatter_spacing)]
    pub scatter_spacing: u8,
    /// With --scatter-depth, the lighting cache and ray-marched shadows: how the render takes
    /// in the scattered light
    #[arg(long, value_enum, default_value_t = ScatteredLightArg::Merged)]
    pub scattered_light: ScatteredLightArg,
}

/// How the lighting cache holds level 0 (`--cache-level0`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Level0Arg {
    /// Ratio for the emission's lights, light for multiple scattering's merged lights
    Auto,
    /// Its shadows: the near field stays exact, shadow rays are cast at the vertices only
    Ratio,
    /// Its light, interpolated linearly between the voxel centres
    Light,
    /// The light of its far part interpolated, its near part (the lights within --cache-near)
    /// summed with their shadows at every sample: a voxel's own light follows its smoke
    FarLight,
}

impl From<Level0Arg> for Level0Form {
    fn from(a: Level0Arg) -> Self {
        match a {
            Level0Arg::Auto => Self::Auto,
            Level0Arg::Ratio => Self::Ratio,
            Level0Arg::Light => Self::Light,
            Level0Arg::FarLight => Self::FarLight,
        }
    }
}

/// What a scattering pass stopped by its rule does with the depths beyond its last.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ScatterTailArg {
    /// Left out (the stopping share bounds them)
    Dropped,
    /// Added as a geometric series of the last depth's lights
    #[default]
    Geometric,
}

impl From<ScatterTailArg> for ScatterTail {
    fn from(a: ScatterTailArg) -> Self {
        match a {
            ScatterTailArg::Dropped => Self::Dropped,
            ScatterTailArg::Geometric => Self::Geometric,
        }
    }
}

/// How a render with multiple scattering takes in the scattered light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ScatteredLightArg {
    /// The paper's merged lights (one a voxel: its emission and every scattered depth), shaded
    /// at every march sample
    Merged,
    /// The scattered depths' in-scattered radiance, computed at the voxels by one more fluence
    /// pass and interpolated at every sample, which then shades the emission lights only;
    /// surfaces are lit by the merged lights. Faster, but smooth between voxel centres where
    /// the merged lights are not
    Grid,
}

impl From<ScatteredLightArg> for ScatteredLight {
    fn from(a: ScatteredLightArg) -> Self {
        match a {
            ScatteredLightArg::Merged => Self::Merged,
            ScatteredLightArg::Grid => Self::Grid,
        }
    }
}

impl CacheArgs {
    /// The cache's first level for camera rays `footprint` voxels apart at the volume:
    /// `--cache-level`, `auto` resolved by [`lgh_volume::lighting_cache::auto_first_level`].
    pub fn first_level(&self, footprint: f32) -> u8 {
        match self.cache_level {
            CacheLevelArg::Fixed(level) => level,
            CacheLevelArg::Auto => lgh_volume::lighting_cache::auto_first_level(footprint),
        }
    }

    /// The cache's settings (checked with the march's).
    pub fn settings(&self) -> LightingCacheSettings {
        LightingCacheSettings {
            mode: self.lighting_cache.into(),
            spacing: match self.cache_spacing {
                SpacingArg::Voxels(voxels) => CacheSpacing::Voxels(voxels),
                SpacingArg::Auto => CacheSpacing::OpticalDepth(self.cache_depth),
            },
            // `auto` is resolved with the camera (`MarchArgs::for_camera`); without one, 1.
            first_level: self.first_level(f32::INFINITY),
            level0: self.cache_level0.into(),
            near_reach: self.cache_near.0,
            scattered_spacing: self.scatter_spacing,
            scattered_light: self.scattered_light.into(),
        }
    }
}

/// The ray marcher's options, shared by the render commands.
#[derive(Debug, Clone, clap::Args)]
pub struct MarchArgs {
    /// Weak-light pruning (paper Sec. 6): the hierarchy skips, below its top level, the lights
    /// dimmer than this fraction of the frame's brightest light (their energy still reaches the
    /// coarser levels): faster, at a small change of the image
    #[arg(long, default_value_t = 0.0)]
    pub prune: f32,
    /// Shadows of the lights: shadow rays marched to every light (with the lighting cache, the
    /// default, marched from its vertices for the levels it holds) — coarse lights as the volume
    /// lights they stand for (`volumes`) or as points (`raymarch`) —, the paper's precomputed
    /// deep-shadow cube maps, or none. Brute force has no hierarchy to make cube maps for: it
    /// ray-marches [default: volumes for lgh explosion, raymarch for lgh demo (the Table 1
    /// reference)]
    #[arg(long, value_enum)]
    pub shadows: Option<ShadowsArg>,
    /// Memory the cube maps may take, in GB (maps that would need more are refused before any
    /// work) [default: 8 GiB, or 3/4 of the available memory if less]
    #[arg(long)]
    pub shadow_memory: Option<f64>,
    /// Cube maps store optical depth sampled at fixed distances (`--shadow-depths`, 4 by
    /// default), as the paper does, instead of adaptive knots
    #[arg(long)]
    pub sampled_depths: bool,
    /// Cube-map texels store the least-squares fit of the optical depth at n fixed distances
    /// D/n ... D, 2 to 16 (the paper's layout with n = 4; 2 bytes each), instead of adaptive
    /// knots
    #[arg(long, value_name = "N")]
    pub shadow_depths: Option<usize>,
    /// Knots a cube-map texel stores, 2 to 16: the transmittance at K distances placed per texel
    /// where it changes (adaptive deep shadow maps; 2 bytes each, so the default 4 take the
    /// memory of the paper's four depths)
    #[arg(long, value_name = "K", conflicts_with_all = ["sampled_depths", "shadow_depths"])]
    pub shadow_knots: Option<usize>,
    /// Cube maps trace coarse lights as points through the plain density instead of as volume
    /// lights through the prefiltered density (eq. 6): the flickering variant of the paper.
    #[arg(long)]
    pub point_shadows: bool,
    /// The voxel lights' near field: `voxel` makes each level-0 light the uniform emitting
    /// voxel it stands for (its intensity what its cell emits, its fall-off the voxel's mean of
    /// 1/r² at points in the smoke, 7.7/h² at its centre, centred where its cell emits — the
    /// luminance centroid of the cell's emission — and its light escaping through the voxel's
    /// own smoke); `clamp` keeps the paper's point lights (the emission at the voxel's centre,
    /// fall-off 1/max(d, h)²)
    #[arg(long, value_enum, default_value_t = NearFieldArg::Voxel)]
    pub near_field: NearFieldArg,
    /// How coarse lights (levels ≥ 1) are weighted: `centre` takes eq. (3) at each light's
    /// centre as the paper prints it (up to 2% bright outside a cloud of lights at α 2);
    /// `averaged` takes eq. (3)'s blended fall-off averaged over the spread of the voxels each
    /// stands for (eq. 4's variance), the exact sum over those voxels to about 0.1% on a uniform
    /// cloud at α 2, at 1.3–1.6× the render's time on two baked fires (fire128, smoky128)
    #[arg(long, value_enum, default_value_t = CoarseSpreadArg::Centre)]
    pub coarse_spread: CoarseSpreadArg,
    /// Step along camera rays, in voxels (smaller is more accurate and slower).
    #[arg(long, default_value_t = 1.0)]
    pub step: f32,
    /// Step along shadow rays, in voxels (smaller is more accurate and slower) [default: 1, or 2
    /// for lgh demo]
    #[arg(long)]
    pub shadow_step: Option<f32>,
    /// Camera rays per side of a pixel, 1 to 8: N×N rays through the centres of N×N sub-pixels,
    /// averaged — a one-pixel box filter (Cycles' "Box" filter, width 1), without noise; 1 is
    /// the pixel's centre. The render costs about N² times as much; the passes before it do not
    /// change (the emission takes --emission-samples' rays where they are more). `auto`: the fewest (at most 4) for which a sub-pixel covers at most 3/4 of a
    /// voxel at the volume's centre (1 where the image resolves the voxels) [default: auto for
    /// lgh explosion, 1 for lgh demo]
    /// `adaptive`: auto's rays (at most 4 a side), then twice as fine a side (4 × 4 for 2 × 2)
    /// in the pixels where two neighbouring rays differ in luminance by more than
    /// --pixel-tolerance of the image's mean — thin flames filtered as the finer box filter
    /// would, at its cost only where the image varies; deterministic, no noise.
    #[arg(long, value_name = "N", value_parser = parse_pixel_samples)]
    pub pixel_samples: Option<PixelSamplesArg>,
    /// Camera rays per side of a pixel for the emission alone, 1 to 8: where more than
    /// --pixel-samples, each pixel's emission (and what the smoke absorbs of it) is the box
    /// filter of N×N rays that read no light, and the light the smoke scatters that of
    /// --pixel-samples' rays — a thin flame's emission varies far below a voxel, the scattered
    /// light as the smoke does, and an emission ray costs a fraction of one that shades the
    /// smoke. `auto`: the fewest for which an emission sub-pixel covers at most a quarter of a
    /// voxel at the volume's centre, at least --pixel-samples; with --pixel-samples adaptive,
    /// which refines both together, --pixel-samples' [default: auto for lgh explosion,
    /// --pixel-samples' for lgh demo]
    #[arg(long, value_name = "N", value_parser = parse_emission_samples)]
    pub emission_samples: Option<EmissionSamplesArg>,
    /// With --pixel-samples adaptive: the luminance difference between neighbouring rays
    /// that refines their pixels, as a share of the image's mean luminance (smaller refines
    /// more pixels: slower, closer to the finer filter)
    #[arg(long, value_name = "SHARE", default_value_t = DEFAULT_PIXEL_TOLERANCE, allow_negative_numbers = true)]
    pub pixel_tolerance: f32,
    #[command(flatten)]
    pub cache: CacheArgs,
}

impl MarchArgs {
    /// The rays a pixel side for `camera` looking at a volume centred at `centre` with voxels
    /// of `voxel_size`: `--pixel-samples`, or `default` where it was not given; `auto`
    /// resolved by [`lgh_volume::render::auto_pixel_samples`].
    pub fn pixel_samples_for(
        &self,
        default: PixelSamplesArg,
        camera: &lgh_volume::render::Camera,
        centre: lgh_volume::lgh_core::glam::Vec3,
        voxel_size: f32,
    ) -> (usize, PixelRefinement) {
        let auto = || lgh_volume::render::auto_pixel_samples(camera, centre, voxel_size);
        match self.pixel_samples.unwrap_or(default) {
            PixelSamplesArg::Fixed(n) => (n, PixelRefinement::Uniform),
            PixelSamplesArg::Auto => (auto(), PixelRefinement::Uniform),
            PixelSamplesArg::Adaptive => (
                auto().min(ADAPTIVE_FIRST_RAYS),
                PixelRefinement::Adaptive {
                    tolerance: self.pixel_tolerance,
                },
            ),
        }
    }

    /// `settings` with what depends on the camera resolved for `camera` looking at a volume
    /// centred at `centre` with voxels of `voxel_size`: the rays a pixel side
    /// ([`pixel_samples_for`](Self::pixel_samples_for), `defaults.0` where `--pixel-samples`
    /// was not given), the emission's (`--emission-samples`, else `defaults.1`; with adaptive
    /// pixels the pixel samples) and `--cache-level auto`
    /// ([`lgh_volume::lighting_cache::auto_first_level`] of a sub-pixel's footprint).
    pub fn for_camera(
        &self,
        settings: MarchSettings,
        defaults: (PixelSamplesArg, EmissionSamplesArg),
        camera: &lgh_volume::render::Camera,
        centre: lgh_volume::lgh_core::glam::Vec3,
        voxel_size: f32,
    ) -> MarchSettings {
        let (pixel_default, emission_default) = defaults;
        let (pixel_samples, pixel_refinement) =
            self.pixel_samples_for(pixel_default, camera, centre, voxel_size);
        let emission_samples = match (pixel_refinement, self.emission_samples) {
            // Refused with an explicit count before any work (`settings`).
            (PixelRefinement::Adaptive { .. }, _) => pixel_samples,
            (PixelRefinement::Uniform, given) => match given.unwrap_or(emission_default) {
                EmissionSamplesArg::Fixed(e) => e,
                EmissionSamplesArg::Auto => lgh_volume::render::auto_emission_samples(
                    camera,
                    centre,
                    voxel_size,
                    pixel_samples,
                ),
                EmissionSamplesArg::WithLight => pixel_samples,
            },
        };
        let footprint =
            lgh_volume::render::pixel_footprint(camera, centre, voxel_size) / pixel_samples as f32;
        MarchSettings {
            pixel_samples,
            pixel_refinement,
            emission_samples,
            lighting_cache: LightingCacheSettings {
                first_level: self.cache.first_level(footprint),
                ..settings.lighting_cache
            },
            ..settings
        }
    }

    /// How coarse lights cast shadows (`--point-shadows`), a variant of the lights.
    pub fn coarse_shadows(&self) -> CoarseShadows {
        if self.point_shadows {
            CoarseShadows::Points
        } else {
            CoarseShadows::Volumes
        }
    }

    /// The marcher's settings with `scatter`'s depth, checked ([`MarchSettings::check`]);
    /// `defaults` (shadows, shadow step) apply without `--shadows` and `--shadow-step`.
    pub fn settings(
        &self,
        defaults: (Shadows, f32),
        scatter: &ScatterArgs,
    ) -> Result<MarchSettings, crate::Error> {
        let (default_shadows, default_shadow_step) = defaults;
        scatter.check()?;
        let budget = match self.shadow_memory {
            Some(gb) if gb.is_finite() && gb > 0.0 && gb <= 1e6 => (gb * 1e9) as u64,
            Some(gb) => {
                return Err(format!("--shadow-memory {gb} must be a positive number of GB").into())
            }
            None => default_shadow_memory(),
        };
        if !(0.0..1.0).contains(&self.prune) {
            return Err(format!(
                "--prune {} must be a fraction of the brightest light in [0, 1)",
                self.prune
            )
            .into());
        }
        let pixel_samples = match self.pixel_samples {
            Some(PixelSamplesArg::Fixed(n)) => n,
            // Resolved with the camera (`pixel_samples_for`).
            _ => 1,
        };
        if !(1..=lgh_volume::render::MAX_PIXEL_SAMPLES).contains(&pixel_samples) {
            return Err(format!(
                "--pixel-samples {pixel_samples} must be 1 to {} (camera rays a pixel side) or auto",
                lgh_volume::render::MAX_PIXEL_SAMPLES
            )
            .into());
        }
        match (self.emission_samples, self.pixel_samples) {
            (Some(EmissionSamplesArg::Fixed(e)), _)
                if !(1..=lgh_volume::render::MAX_PIXEL_SAMPLES).contains(&e) =>
            {
                return Err(format!(
                    "--emission-samples {e} must be 1 to {} (emission rays a pixel side) or auto",
                    lgh_volume::render::MAX_PIXEL_SAMPLES
                )
                .into());
            }
            (Some(EmissionSamplesArg::Fixed(e)), Some(PixelSamplesArg::Adaptive)) if e > 1 => {
                return Err(format!(
                    "--emission-samples {e} needs uniform pixels: --pixel-samples adaptive \
                     refines the emission with the light (auto or 1 take its rays)"
                )
                .into());
            }
            _ => {}
        }
        if !(self.pixel_tolerance.is_finite() && self.pixel_tolerance >= 0.0) {
            return Err(format!(
                "--pixel-tolerance {} must be a share of the image's mean luminance, at least 0",
                self.pixel_tolerance
            )
            .into());
        }
        let shadow_step = self.shadow_step.unwrap_or(default_shadow_step);
        let settings = MarchSettings {
            shadows: self.shadows.map_or(default_shadows, Into::into),
            scatter_depth: scatter.depth(),
            scatter_stop: scatter.stop(),
            scatter_skip: scatter.skip(),
            scatter_tail: scatter.scatter_tail.into(),
            step_voxels: self.step,
            shadow_step_voxels: shadow_step,
            cube_maps: CubeMapSettings {
                // The texel rays step as the shadow rays do where the prefilter allows no more.
                step_voxels: shadow_step,
                depths: if self.sampled_depths {
                    Depths::Sampled
                } else if self.shadow_depths.is_some() {
                    Depths::Fitted
                } else {
                    Depths::Adaptive
                },
                depth_count: self.shadow_knots.or(self.shadow_depths).unwrap_or(4),
                memory_budget: budget,
            },
            lighting_cache: self.cache.settings(),
            pixel_samples,
            ..Default::default()
        };
        settings.check()?;
        Ok(settings)
    }
}

/// `--scatter-depth`: a number of depths, or `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthArg {
    /// This many depths (fewer with --scatter-stop).
    Fixed(usize),
    /// Up to 16 depths, stopping by --scatter-stop (0.2% unless given), or none by
    /// --scatter-skip (1% unless given).
    Auto,
}

impl Default for DepthArg {
    fn default() -> Self {
        DepthArg::Fixed(0)
    }
}

/// `auto` (0) or a number of voxels.
fn parse_scatter_spacing(s: &str) -> Result<u8, String> {
    Ok(parse_auto(s, "voxels")?.unwrap_or(lgh_volume::lighting_cache::SCATTERED_SPACING))
}

/// `auto` or a number of depths.
fn parse_depth(s: &str) -> Result<DepthArg, String> {
    Ok(parse_auto(s, "depths")?.map_or(DepthArg::Auto, DepthArg::Fixed))
}

/// The share of the light so far below which `--scatter-depth auto` stops adding depths: the
/// next depth's. The depths it leaves out hold about `1/(1 − r)` times that (`r` the fall a
/// depth: 0.66 in the demo's explosion, about 0.8 in the thickest smoke), so 0.2% leaves out
/// about 0.6–1% of the light. At 1% the procedural explosion's scattered light came out 2.5%
/// low and its green 1.3% below Cycles' (docs/cycles.md, "Colour, channel by channel").
pub const AUTO_SCATTER_STOP: f32 = 0.002;

/// The share of the emitted light below which `--scatter-depth auto` skips the scattering pass:
/// depth 1's, predicted by a pilot sample of the voxels. In smoke that scatters this little the
/// first depth is nearly all the scattered light (the next is a share of it as small), so 1%
/// leaves out about 1%; the pass it saves costs the dev fire a third of its time.
pub const AUTO_SCATTER_SKIP: f32 = 0.01;

/// Multiple scattering (paper Sec. 5), shared by the render commands.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ScatterArgs {
    /// Depths of scattered light (paper Sec. 5): 0 is single scattering; n adds lights for
    /// light scattered 1..=n times, so paths of up to n + 1 scattering events (the paper's
    /// Fig. 7 uses 4). At most 16. `auto`: up to 16, stopping when the next depth would add
    /// less than --scatter-stop of the light (0.2% unless given), and none at all when a sample
    /// of the voxels predicts that the first would add less than --scatter-skip of the emitted
    /// light (1% unless given: smoke that scatters almost nothing) [default: auto for lgh
    /// explosion's marcher (0 with --backend pathtrace), 0 for lgh demo]
    #[arg(long, value_parser = parse_depth)]
    pub scatter_depth: Option<DepthArg>,
    /// Stop adding scattering depths when the next one, predicted from the last two (the light
    /// falls by a nearly steady factor a depth), would add less than this share of the lights'
    /// power so far (0: every depth asked for) [default: 0.002 with --scatter-depth auto, else 0]
    #[arg(long)]
    pub scatter_stop: Option<f32>,
    /// Skip the whole scattering pass when a sample of the smoky voxels predicts that its first
    /// depth would add less than this share of the emitted light (0: never skip) [default: 0.01
    /// with --scatter-depth auto, else 0]
    #[arg(long)]
    pub scatter_skip: Option<f32>,
    /// With a stopping share (--scatter-depth auto): the depths beyond the last, added as a
    /// geometric series of the last depth's lights by its fall from the depth before
    /// (`geometric`, which stops once that series, by the last fall and by the one before,
    /// differs by less than --scatter-stop of the light so far) or left out (`dropped`)
    #[arg(long, value_enum, default_value_t = ScatterTailArg::Geometric)]
    pub scatter_tail: ScatterTailArg,
    /// Also report each depth's share of the image (renders the emission, each depth's
    /// lights and the geometric tail's alone: n + 2 more renders, one more with a tail).
    #[arg(long)]
    pub scatter_shares: bool,
}

impl ScatterArgs {
    /// These arguments with `depth` where --scatter-depth was not given: a command's default.
    #[must_use]
    pub fn or_depth(&self, depth: DepthArg) -> ScatterArgs {
        ScatterArgs {
            scatter_depth: Some(self.scatter_depth.unwrap_or(depth)),
            ..self.clone()
        }
    }

    /// --scatter-depth, or 0 where it was not given ([`or_depth`](Self::or_depth) sets
    /// another default).
    fn depth_arg(&self) -> DepthArg {
        self.scatter_depth.unwrap_or_default()
    }

    /// The most depths the pass computes.
    pub fn depth(&self) -> usize {
        match self.depth_arg() {
            DepthArg::Fixed(n) => n,
            DepthArg::Auto => scattering::MAX_SCATTER_DEPTH,
        }
    }

    /// The stopping share: --scatter-stop, or 0.2% with --scatter-depth auto, or none (0).
    pub fn stop(&self) -> f32 {
        self.scatter_stop
            .unwrap_or(self.auto_default(AUTO_SCATTER_STOP))
    }

    /// The skipping share: --scatter-skip, or 1% with --scatter-depth auto, or none (0).
    pub fn skip(&self) -> f32 {
        self.scatter_skip
            .unwrap_or(self.auto_default(AUTO_SCATTER_SKIP))
    }

    /// `share` with --scatter-depth auto, else 0.
    fn auto_default(&self, share: f32) -> f32 {
        if self.depth_arg() == DepthArg::Auto {
            share
        } else {
            0.0
        }
    }

    /// Checks the depth and the stopping share before any work.
    pub fn check(&self) -> Result<(), crate::Error> {
        let depth = self.depth();
        scattering::check_depth(depth).map_err(|_| {
            format!(
                "--scatter-depth {depth} must be 0 to {} or auto",
                scattering::MAX_SCATTER_DEPTH
            )
        })?;
        for (flag, share) in [
            ("--scatter-stop", self.stop()),
            ("--scatter-skip", self.skip()),
        ] {
            if !(0.0..1.0).contains(&share) {
                return Err(format!("{flag} {share} must be a share in [0, 1)").into());
            }
        }
        if self.scatter_shares && depth == 0 {
            return Err("--scatter-shares needs --scatter-depth 1 or more".into());
        }
        Ok(())
    }
}

/// EXR header entries of a frame made ready: its shadows (with cube maps their bytes, depths
/// and precompute seconds), then its scattering (the depth, and with a pass its seconds per
/// depth, its lights and, if measured, each depth's share of the image).
pub fn frame_header(frame: &FrameRender, shares: Option<&Shares>) -> Vec<(&'static str, String)> {
    let mut out = vec![
        ("near_field", frame.lights().near_field().name().to_string()),
        (
            "coarse_spread",
            frame.lights().coarse_spread().name().to_string(),
        ),
        ("shadows", frame.visibility().shadows().name().to_string()),
    ];
    let n = frame.settings().pixel_samples;
    if n > 1 {
        // The box filter's rays a pixel's side (`--pixel-samples`); absent: pixel centres.
        out.push(("pixel_samples", n.to_string()));
    }
    let e = frame.settings().emission_samples;
    if e > n {
        // The emission's rays a pixel side, marched apart (`--emission-samples`); absent:
        // the emission is marched with the light.
        out.push(("emission_samples", e.to_string()));
    }
    if let PixelRefinement::Adaptive { tolerance } = frame.settings().pixel_refinement {
        // Refined pixels take twice as many a side (`--pixel-samples adaptive`).
        out.push(("pixel_refinement", "adaptive".to_string()));
        out.push(("pixel_tolerance", tolerance.to_string()));
    }
    if let Some(m) = frame.cube_maps() {
        out.push(("shadow_bytes", m.bytes().to_string()));
        out.push(("shadow_depths", m.depths_per_texel().to_string()));
        out.push(("shadow_storage", m.storage().name().to_string()));
        let seconds = frame.seconds().shadows;
        out.push(("shadow_precompute_seconds", format!("{seconds:.3}")));
    }
    if let Some(c) = frame.lighting_cache() {
        let stats = c.stats();
        out.push(("lighting_cache", c.settings().mode.name().to_string()));
        out.push(("lighting_cache_spacing", c.spacing_voxels().to_string()));
        out.push(("lighting_cache_level", c.settings().first_level.to_string()));
        if let Some(form) = c.level0() {
            out.push(("lighting_cache_level0", form.name().to_string()));
            if form != Level0Form::Light {
                out.push(("lighting_cache_level0_near", near_reach(c)));
            }
        }
        out.push(("lighting_cache_vertices", stats.vertices.to_string()));
        out.push(("lighting_cache_tiers", tiers(c)));
    }
    match frame.scattered() {
        Some(s) => out.extend(scatter_header(frame, s, shares)),
        None => out.push(("scatter_depth", "0".to_string())),
    }
    out
}

/// EXR header entries of a frame's scattering pass: the rule that stopped it, its depths'
/// powers and seconds, its lights, how the render used them and, if measured, the shares.
fn scatter_header(
    frame: &FrameRender,
    s: &Scattered,
    shares: Option<&Shares>,
) -> Vec<(&'static str, String)> {
    let mut out = Vec::new();
    let list = |v: &mut dyn Iterator<Item = String>| v.collect::<Vec<_>>().join(",");
    let stop = frame.settings().scatter_stop;
    if stop > 0.0 {
        // The depth below is where the rule stopped (or the most asked for).
        out.push(("scatter_stop", stop.to_string()));
    }
    let skip = frame.settings().scatter_skip;
    if skip > 0.0 {
        // The pilot's bar (`scatter_skipped_share` below it: the pass skipped).
        out.push(("scatter_skip", skip.to_string()));
    }
    if stop > 0.0 {
        out.push((
            "scatter_tail",
            frame.settings().scatter_tail.name().to_string(),
        ));
    }
    if let Some(f) = s.tail() {
        // The depths beyond the last, as a multiple of its lights (in the merged lights).
        out.push(("scatter_tail_factor", format!("{f:.6e}")));
    }
    if let Some(k) = s.skipped() {
        // The pilot's prediction of depth 1's power, as a share of the emitted light.
        out.push(("scatter_skipped_share", format!("{:.6e}", k.share())));
    }
    out.extend([
        ("scatter_depth", s.depths().len().to_string()),
        (
            "scatter_depth_powers",
            list(&mut s.depths().iter().map(|d| format!("{:.6e}", d.power))),
        ),
        (
            "scatter_seconds",
            format!("{:.3}", frame.seconds().scattering),
        ),
        (
            "scatter_depth_seconds",
            list(&mut s.depths().iter().map(|d| format!("{:.3}", d.seconds))),
        ),
        ("scatter_lights", s.lights().lights().len().to_string()),
        (
            // What the render used: the grid needs the cache and shared shadows.
            "scattered_light",
            if s.radiance().is_some() {
                ScatteredLight::Grid
            } else {
                ScatteredLight::Merged
            }
            .name()
            .to_string(),
        ),
        (
            // The spacing used (the automatic one resolved on the frame's smoke).
            "scatter_spacing",
            s.spacing().to_string(),
        ),
    ]);
    if let Some((_, r)) = s.radiance() {
        // The scattered light as a grid (otherwise the merged lights).
        out.push(("scatter_grid_seconds", format!("{:.3}", r.seconds)));
    }
    if let Some(shares) = shares {
        let (f, tail) = fractions(shares);
        out.push((
            "scatter_shares",
            list(&mut f.iter().map(|x| format!("{x:.5}"))),
        ));
        if let Some(t) = tail {
            // The geometric tail's: with `scatter_shares`' entries, it sums to 1.
            out.push(("scatter_shares_tail", format!("{t:.5}")));
        }
    }
    out
}

/// The shares as fractions of the image ([`Shares::total`]): emission, then depths 0..=n; and
/// the geometric tail's, if there is one.
fn fractions(shares: &Shares) -> (Vec<f64>, Option<f64>) {
    let sum = shares.total().max(f64::MIN_POSITIVE);
    let parts = std::iter::once(shares.emission)
        .chain(shares.depths.iter().copied())
        .map(|p| p / sum)
        .collect();
    (parts, shares.tail.map(|t| t / sum))
}

/// A cache's grids as `first level:spacing in voxels`, comma-separated (`1:1,2:2`).
fn tiers(c: &LightingCache) -> String {
    let tiers: Vec<String> = c.tiers().iter().map(|(l, v)| format!("{l}:{v}")).collect();
    tiers.join(",")
}

/// Level 0's near reach in voxels (`all` without a near part), as headers and JSON give it.
fn near_reach(c: &LightingCache) -> String {
    c.settings()
        .near_reach
        .map_or_else(|| "all".to_string(), |r| r.to_string())
}

/// The summary line of a frame's lighting cache (nothing without one).
pub fn say_lighting_cache(frame: &FrameRender) -> Result<(), crate::Error> {
    let Some(c) = frame.lighting_cache() else {
        return Ok(());
    };
    let s = c.stats();
    let tiers: Vec<String> = c
        .tiers()
        .iter()
        .map(|&(l, v)| {
            let near = match c.settings().near_reach {
                Some(r) => format!("near part {r} voxels"),
                None => "summed whole".to_string(),
            };
            match (l, c.level0().unwrap_or(Level0Form::Light)) {
                (0, Level0Form::Ratio) => {
                    format!("level 0's shadows (a ratio, {near}) at {v:.3} voxels")
                }
                (0, Level0Form::FarLight) => {
                    format!("level 0's far light ({near}) at {v:.3} voxels")
                }
                _ => format!("levels {l}.. at {v:.3} voxels"),
            }
        })
        .collect();
    say!(
        "  cache      {}: {} vertices, {:.1} CPU-s, {:.1} lights each",
        tiers.join(", "),
        s.vertices,
        s.cpu_seconds,
        s.lights_evaluated as f64 / s.vertices.max(1) as f64
    );
    Ok(())
}

/// The summary lines of a frame's scattering pass (nothing without one).
pub fn say_scattering(frame: &FrameRender, shares: Option<&Shares>) -> Result<(), crate::Error> {
    let Some(s) = frame.scattered() else {
        return Ok(());
    };
    if let Some(k) = s.skipped() {
        say!(
            "  scattering skipped: depth 1 would add about {:.3}% of the emitted light (from {} of {} smoky voxels; --scatter-skip {}%); {:.2} s",
            100.0 * k.share(),
            k.sampled,
            k.voxels,
            100.0 * frame.settings().scatter_skip,
            k.seconds
        );
        return Ok(());
    }
    let d = s.depths();
    // With a geometric tail the merged lights hold every order of scattering, the depths past
    // the last as its lights times the factor.
    let events = match s.tail() {
        Some(f) => format!(
            "every scattering event, the rest as depth {} × {f:.3}",
            d.len()
        ),
        None => format!("up to {} scattering events", d.len() + 1),
    };
    say!(
        "  scattering {} depths ({events}): {} lights a depth, {} merged lights; {:.2} s",
        d.len(),
        d.first().map_or(0, |r| r.lights),
        s.lights().lights().len(),
        frame.seconds().scattering
    );
    for r in d {
        say!(
            "    depth {:>2}: {:.2} s ({:.2} s shadows of the depth before), power {:.4e}, {:.1} lights per voxel",
            r.depth,
            r.seconds,
            r.shadow_seconds,
            r.power,
            r.stats.lights_per_point()
        );
    }
    if let Some((grid, r)) = s.radiance() {
        say!(
            "    grid    : {:.2} s (depth {}'s fluence at the voxels: the scattered light's radiance, {:.1} MB), power {:.4e}",
            r.seconds,
            r.depth - 1,
            grid.bytes() as f64 / 1e6,
            r.power
        );
    }
    if let Some(shares) = shares {
        let (f, tail) = fractions(shares);
        let depths: Vec<String> = f[1..]
            .iter()
            .enumerate()
            .map(|(k, x)| format!("depth {k} {:.2}%", 100.0 * x))
            .chain(tail.map(|t| format!("tail {:.2}%", 100.0 * t)))
            .collect();
        say!(
            "    shares of the image: emission {:.2}%, {}",
            100.0 * f[0],
            depths.join(", ")
        );
    }
    Ok(())
}

/// Each depth's share of the image, when `args` asks for it (`--scatter-shares`).
pub fn shares(
    args: &ScatterArgs,
    frame: &FrameRender,
    camera: &Camera,
    progress: &dyn lgh_volume::Progress,
) -> Result<Option<Shares>, crate::Error> {
    if !args.scatter_shares {
        return Ok(None);
    }
    Ok(frame.scatter_shares(camera, progress)?)
}

/// The cube maps' default memory: 8 GiB, or 3/4 of the memory available now if less (read
/// from `/proc/meminfo` where there is one).
fn default_shadow_memory() -> u64 {
    let cap = 8u64 << 30;
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| {
            m.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .map(|kib| kib * 1024 / 4 * 3);
    available.map_or(cap, |a| a.min(cap))
}

/// CPU seconds this process has used so far (user + system, all threads), from
/// `/proc/self/stat` (Linux; `None` elsewhere): what a time on a shared machine should be
/// judged by next to the wall-clock seconds.
pub fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces, so skip past its ')'): utime and
    // stime are the 12th and 13th, in clock ticks of 1/100 s on Linux.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?;
    Some(ticks as f64 / 100.0)
}

/// Prints a level-by-level table of cube maps (the paper's Table 1 rows) to stderr.
pub fn say_cube_maps(table: &[LevelMaps], bytes: u64, seconds: f64) -> Result<(), crate::Error> {
    say!(
        "  shadows    cube maps: {:.1} MB for {} lights, traced in {seconds:.2} s",
        bytes as f64 / 1e6,
        table.iter().map(|l| l.lights).sum::<usize>()
    );
    for l in table {
        say!(
            "    level {:>2}: {:>7} lights, up to {:>4} cells per face side, {:>10} texels in {:>6} tiles, depths to {:.3}, {:>9.2} MB, {:>6.1}M samples, {:.2} s",
            l.level,
            l.lights,
            l.cells,
            l.texels,
            l.tiles,
            l.reach,
            l.bytes as f64 / 1e6,
            l.samples as f64 / 1e6,
            l.seconds
        );
    }
    Ok(())
}

/// Checks that the output is an `.exr` path and that its folder exists, before any work.
pub fn check_out(out: &Path) -> Result<PathBuf, crate::Error> {
    if out.extension().and_then(|e| e.to_str()) != Some("exr") {
        return Err(format!(
            "--out {}: the output must be an .exr file (a .png is written beside it)",
            out.display()
        )
        .into());
    }
    let dir = match out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(format!(
            "--out {}: folder {} does not exist",
            out.display(),
            dir.display()
        )
        .into());
    }
    Ok(out.with_extension("png"))
}

/// A frame's render, timed: `frame` seen by `camera` under `bars`.
pub struct Rendered {
    /// The image.
    pub image: Image,
    /// The marcher's counts (none from the path tracer).
    pub stats: Option<RenderStats>,
    /// Render time.
    pub seconds: f64,
}

impl Rendered {
    /// Renders `frame` through `camera`, with `bars`' progress.
    pub fn of(
        frame: &FrameRender,
        camera: &Camera,
        progress: &dyn lgh_volume::Progress,
    ) -> Result<Self, crate::Error> {
        Rendered::timed(|| {
            let (image, stats) = frame.render(camera, progress)?;
            Ok((image, Some(stats)))
        })
    }

    /// The image `render` makes, timed.
    pub fn timed(
        render: impl FnOnce() -> Result<(Image, Option<RenderStats>), crate::Error>,
    ) -> Result<Self, crate::Error> {
        let t = Instant::now();
        let (image, stats) = render()?;
        Ok(Rendered {
            image,
            stats,
            seconds: t.elapsed().as_secs_f64(),
        })
    }

    /// Writes `out` — an EXR whose header holds the march settings, the `backend`'s name,
    /// `extra` and the render's counts and time — and the PNG beside it; returns the PNG's path.
    pub fn write(
        &self,
        out: &Path,
        march: &MarchSettings,
        backend: &str,
        mut extra: Vec<(&'static str, String)>,
    ) -> Result<PathBuf, crate::Error> {
        extra.push(("render_seconds", format!("{:.3}", self.seconds)));
        if let Some(st) = &self.stats {
            extra.push(("shading_points", st.shading_points.to_string()));
            extra.push(("surface_points", st.surface_points.to_string()));
            extra.push((
                "lights_per_shading_point",
                format!("{:.2}", st.lights_per_point()),
            ));
        }
        let attributes = settings_attributes(march, backend, &extra);
        write_exr_png(out, &self.image, &attributes, None)
    }
}

/// The render settings as EXR header attributes (`lgh:` prefixed).
fn settings_attributes(
    march: &MarchSettings,
    backend: &str,
    extra: &[(&str, String)],
) -> Vec<(String, String)> {
    let march = [
        ("step_voxels", march.step_voxels.to_string()),
        ("shadow_step_voxels", march.shadow_step_voxels.to_string()),
        ("min_transmittance", march.min_transmittance.to_string()),
    ];
    header_attributes(backend, march.iter().chain(extra))
}

/// EXR header attributes: `lgh:backend`, then `settings` and `lgh:version`, every key with the
/// `lgh:` prefix.
pub fn header_attributes<'a>(
    backend: &str,
    settings: impl IntoIterator<Item = &'a (&'a str, String)>,
) -> Vec<(String, String)> {
    let mut attrs = vec![("lgh:backend".to_string(), backend.to_string())];
    attrs.extend(
        settings
            .into_iter()
            .map(|(k, v)| (format!("lgh:{k}"), v.clone())),
    );
    attrs.push((
        "lgh:version".to_string(),
        env!("CARGO_PKG_VERSION").to_string(),
    ));
    attrs
}

/// Writes the EXR (with `attrs` in its header, linear) and the PNG beside it, tone-mapped with
/// the filmic curve at `exposure` (`None`: automatic), which keeps a fire's highlights apart;
/// returns the PNG's path.
pub fn write_exr_png(
    out: &Path,
    image: &Image,
    attrs: &[(String, String)],
    exposure: Option<f32>,
) -> Result<PathBuf, crate::Error> {
    let png = out.with_extension("png");
    // The pair is written whole or not at all: an interruption waits for both (main.rs).
    let _pair = lgh_image::hold_writes();
    // The PNG first, the EXR (whose header says which render it is) last: an EXR beside its PNG
    // is a finished pair, which `--resume` relies on.
    let exposure = exposure.unwrap_or_else(|| lgh_image::auto_exposure(image));
    lgh_image::write_png_with(&png, image, exposure, lgh_image::ToneCurve::Filmic)?;
    lgh_image::write_exr(out, image, attrs)?;
    Ok(png)
}

/// Names on stderr, once each with the file and line of its first use, what `mesh`'s files
/// ask for and `command` does not honour.
pub fn print_unhonoured(command: &str, mesh: &lgh_vpl::Mesh) {
    for u in mesh.unhonoured() {
        eprintln!("{command}: not honoured: {u}");
    }
}
