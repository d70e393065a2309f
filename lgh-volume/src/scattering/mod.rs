//! Multiple scattering: light that scatters more than once in the smoke (paper Sec. 5;
//! ARCHITECTURE.md, "Where each part of the papers lives").
//!
//! The paper's lights `S^0_ℓ` (the emission lights of [`ExplosionLights`]) light the smoke
//! directly: the marcher's single scattering. Sec. 5 adds virtual point lights for the light
//! that has scattered: the depth-`k` lights `S^k_0` sit at the centre of every voxel with smoke
//! density, with intensity
//!
//! `I^k(x) = h³ σ_s(x) / (4π) · Φ^{k−1}(x)`,
//!
//! where `Φ^{k−1}(x)` is the shadowed fluence at `x` of the depth-`(k−1)` lights — exactly what
//! [`Lights::incident`](crate::lighting::Lights::incident) returns with the response `1` at an isotropic point
//! (`Σ I · g(d) · V` over the lights the backend selects, eq. 1 with visibility), `h³` the voxel's
//! volume and `σ_s/(4π)` the isotropic phase function times the scattering coefficient
//! ([`Lights::in_scattered`](crate::lighting::Lights::in_scattered) computes `I^k` from them). Each
//! depth is built into a hierarchy of its own ("the higher levels `S^k_ℓ` … in the same way as
//! explained in Section 3") with its own shadows (the same [`Shadows`](crate::Shadows) choice and
//! settings as the render: deep-shadow cube maps by default), which lights the next depth.
//! With a lighting cache in the settings ([`LightingCacheSettings`]), each depth's fluence is
//! computed as the render's in-scattering is: its finest levels at every voxel, its coarse levels
//! at the cache's vertices (each depth's own cache, filled where the voxels need it) and
//! interpolated — the cache's vertices of level 1 are the voxel centres themselves, coarser
//! levels' fewer, where their light varies slowly. Where no grid of the cache is coarser than
//! the voxels (dense smoke), the pass shades every voxel exactly: such a cache would only add
//! work. Depths ≥ 2 light the smoke with light that has scattered already, spread over all of
//! it: they go through a cache of every level, the finest included, on a grid
//! [`scattered_spacing`](crate::lighting_cache::LightingCacheSettings::scattered_spacing) voxels apart
//! (automatic by default: 4, 2 or 1 voxels, at least 8 cells across the smoke,
//! [`scattered_spacing_on`](crate::lighting_cache::LightingCacheSettings::scattered_spacing_on);
//! on the Fig. 8-class frame four apart, a depth takes 8–12 s instead of 58–70 s).
//!
//! **The scattered light as a grid.** With the cache and shadows that every light set shares
//! ([`MarchSettings::scattered_grid`]), the pass computes one depth more, `n + 1`, and keeps
//! `Σ_{k=2}^{n+1} I^k / h³` at the voxels: the in-scattered radiance of depths `1..=n`
//! ([`crate::scattered_light`]), which the render interpolates at every sample instead of shading
//! the merged lights there. The merged lights are still made: surfaces are lit by them.
//!
//! [`LightingCacheSettings`]: crate::lighting_cache::LightingCacheSettings
//!
//! All lights of all depths sit at voxel centres of the simulation grid, so — as the paper
//! does — the lights of one voxel are merged into one light: the voxel's emission light plus its
//! scattered lights of depths `1..=n`. The merged set ([`Scattered::lights`]) is what the final
//! render shades with; with `n` scattered depths the image holds paths of up to `n + 1`
//! scattering events (the paper's Fig. 7 uses `n = 4`). The merged hierarchy uses the emission
//! lights' grid (`h1 = 2h`, level-1 vertices on voxel centres, and their top level `ℓ_max`), so a
//! voxel that neither emits nor scatters adds exactly nothing: with `σ_s = 0` the merged lights
//! render the single-scattering image bit for bit.
//!
//! **Determinism.** Each voxel's fluence depends only on the voxel and the previous depth's
//! lights; voxels are processed in fixed chunks of [`CHUNK_VOXELS`] (rayon), each chunk with its
//! own scratch (nothing is allocated per voxel), and the only sums across voxels are integer
//! counts and the per-depth power, summed in voxel order. The merged intensity of a voxel is
//! summed in depth order. The result is the same bit for bit on any thread count.
//!
//! **Memory.** The pass's lights are planned ([`ScatterPlan`]) and checked against the cube
//! maps' budget (`MarchSettings::cube_maps.memory_budget`) before any work; each depth's cube
//! maps are checked against it when they are built.
//!
//! A [`FrameRender`](crate::FrameRender) runs the pass when its settings ask for depths and
//! renders the merged lights:
//!
//! ```
//! use lgh_volume::render::{Camera, Framing, MarchSettings};
//! use lgh_volume::{procedural, ExplosionLights, FrameRender, Medium, Method, Shadows};
//!
//! let volume = procedural(32, 0.5)?;
//! let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
//! let emission = ExplosionLights::new(&[&volume], &medium)?;
//! // Two scattered depths: paths of up to three scattering events.
//! let settings = MarchSettings { shadows: Shadows::None, scatter_depth: 2, ..Default::default() };
//! let frame = FrameRender::new(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
//! assert_eq!(frame.scattered().unwrap().depths().len(), 2);
//! let (lo, hi) = volume.active_bounds().unwrap();
//! let (image, _) = frame.render(&Camera::frame(lo, hi, 16, 9)?, &())?;
//! assert_eq!(image.pixels.len(), 16 * 9);
//! # Ok::<(), lgh_volume::RenderError>(())
//! ```

use std::time::Instant;

use lgh_core::glam::Vec3;
use rayon::prelude::*;

use lgh_image::Image;

use crate::error::RenderError;
use crate::lighting::LightScratch;
use crate::lighting_cache::{CachedLights, LightingCache};
use crate::lights::ExplosionLights;
use crate::medium::{Medium, Volume};
use crate::method::Method;
use crate::progress::{self, Phase, Progress};
use crate::scattered_light::ScatteredRadiance;
use crate::settings::MarchSettings;
pub use crate::settings::{check_depth, MAX_SCATTER_DEPTH};
use crate::shading::Shading;
use crate::stats::RenderStats;

/// Voxels per parallel job of the fluence pass: a fixed split, so that nothing depends on the
/// thread count, large enough that a job's scratch is reused over many voxels.
pub const CHUNK_VOXELS: usize = 1024;

/// Bytes planned per light of a depth's (or the merged) light set: its voxel index (8), the
/// point light (24), and the hierarchy — level 0 (44 a light), the sorted input (36) and the
/// levels above, planned at one vertex of 72 bytes per light (a level-1 grid of `h1 = 2h` over
/// voxel lights has about one vertex per 8 lights where the smoke is solid, and the levels above
/// fewer still; the test `the_memory_plan_covers_what_the_pass_holds` checks the vertices).
pub const BYTES_PER_LIGHT: u64 = 8 + 24 + 44 + 36 + 72;

/// What a scattering pass will hold, found before any work: its lights and their bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScatterPlan {
    /// Scattered depths `n`.
    pub depth: usize,
    /// Lights of each scattered depth: the voxels with smoke density.
    pub lights_per_depth: usize,
    /// Lights of the merged set: the voxels that emit (in any frame of the emission lights) or
    /// have smoke.
    pub merged_lights: usize,
    /// Bytes of the pass's lights: one depth's light set at a time, the per-depth intensities
    /// of every voxel of the merged set (kept for [`Scattered::depth_lights`]) and the merged set.
    pub bytes: u64,
}

impl ScatterPlan {
    /// The plan of [`scatter`] to `depth` scattered depths from `emission` in `frame`: checks the
    /// depth ([`check_depth`]) and that the density lies on the lights' grid
    /// ([`RenderError::DensityOffGrid`]); counts voxels, nothing more.
    ///
    /// ```
    /// use lgh_volume::scattering::ScatterPlan;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let plan = ScatterPlan::new(&emission, &volume, 4)?;
    /// let smoke = volume.density.data.iter().filter(|&&r| r > 0.0).count();
    /// assert_eq!(plan.lights_per_depth, smoke);
    /// assert!(plan.check(1 << 30).is_ok());
    /// assert!(plan.check(1000).is_err()); // refused before any work
    /// assert!(ScatterPlan::new(&emission, &volume, 17).is_err());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn new(
        emission: &ExplosionLights,
        frame: &Volume,
        depth: usize,
    ) -> Result<Self, RenderError> {
        check_depth(depth)?;
        if !emission.on_grid(&frame.density) {
            return Err(RenderError::DensityOffGrid);
        }
        let dense = frame.density.data.iter().filter(|&&r| r > 0.0).count();
        let merged = merge_count(emission.voxels(), &frame.density.data);
        let (d, m, n) = (dense as u64, merged as u64, depth as u64);
        let bytes = if depth == 0 {
            0
        } else {
            // One depth's lights and its new intensities; every depth's intensities on the
            // merged voxels, their sum and the merged lights.
            d * (BYTES_PER_LIGHT + 12 + 8) + m * (12 * (n + 2) + BYTES_PER_LIGHT)
        };
        Ok(ScatterPlan {
            depth,
            lights_per_depth: dense,
            merged_lights: merged,
            bytes,
        })
    }

    /// The plan with the scattered light kept as a grid ([`MarchSettings::scattered_grid`]):
    /// its three channels over every voxel of `frame`, and the summed intensities of the
    /// voxels with smoke.
    ///
    /// ```
    /// use lgh_volume::scattering::ScatterPlan;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let emission = ExplosionLights::new(&[&volume], &Medium::new(2.0, 6.0, 1e-4, 1000.0)?)?;
    /// let plan = ScatterPlan::new(&emission, &volume, 2)?;
    /// let grid = plan.with_grid(&volume);
    /// assert_eq!(grid.bytes - plan.bytes, 12 * (32 * 32 * 32 + plan.lights_per_depth as u64));
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn with_grid(self, frame: &Volume) -> Self {
        let extra = 12 * (frame.density.data.len() as u64 + self.lights_per_depth as u64);
        ScatterPlan {
            bytes: self.bytes + extra,
            ..self
        }
    }

    /// `Ok` if the plan fits in `budget` bytes, else [`RenderError::ScatterMemory`].
    ///
    /// ```
    /// use lgh_volume::scattering::ScatterPlan;
    ///
    /// let plan = ScatterPlan { depth: 4, lights_per_depth: 10, merged_lights: 12, bytes: 5000 };
    /// assert!(plan.check(5000).is_ok());
    /// assert!(plan.check(4999).unwrap_err().to_string().contains("--scatter-depth"));
    /// ```
    pub fn check(&self, budget: u64) -> Result<(), RenderError> {
        if self.bytes > budget {
            return Err(RenderError::ScatterMemory {
                needed: self.bytes,
                budget,
                depth: self.depth,
            });
        }
        Ok(())
    }
}

/// Voxels that emit (`hot`, ascending) or have smoke (`density > 0`).
fn merge_count(hot: &[usize], density: &[f32]) -> usize {
    let dense = density.iter().filter(|&&r| r > 0.0).count();
    dense + hot.iter().filter(|&&v| density[v] <= 0.0).count()
}

/// What one scattered depth took and gave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthReport {
    /// The depth `k ≥ 1`.
    pub depth: usize,
    /// Its lights (voxels with smoke; dark ones included).
    pub lights: usize,
    /// Seconds spent on the shadows of the depth-`(k−1)` lights that light it.
    pub shadow_seconds: f64,
    /// Seconds spent on the whole depth: shadows, fluence and its hierarchy.
    pub seconds: f64,
    /// Luminance of the depth's summed intensity, `‖Σ I^k‖` (summed in voxel order, in f64).
    pub power: f64,
    /// The fluence queries' counts (one shading point per voxel), the lights and shadow samples
    /// of the lighting cache's vertices included.
    pub stats: RenderStats,
}

/// The result of [`scatter`]: the merged lights the final render shades with, and each depth's
/// intensities and report.
#[derive(Clone, Debug)]
pub struct Scattered {
    merged: ExplosionLights,
    /// Voxels between the vertices depths ≥ 2 computed their fluence at (1: every voxel).
    spacing: u8,
    /// Intensities of each depth `0..=n` on the merged voxels (depth 0: the emission).
    per_depth: Vec<Vec<Vec3>>,
    reports: Vec<DepthReport>,
    /// The top level of the emission lights, which every light set of the pass shares.
    max_level: u8,
    /// The scattered depths' in-scattered radiance at the voxels, when the settings take the
    /// scattered light in as a grid ([`MarchSettings::scattered_grid`]).
    radiance: Option<ScatteredRadiance>,
    /// The fluence pass of depth `n + 1` that the grid needs.
    radiance_report: Option<DepthReport>,
    /// Set when the first depth's pilot skipped the pass.
    skipped: Option<Skipped>,
}

/// A pass whose first depth was skipped by its pilot: the smoke scatters too little of the
/// emitted light to matter under the stopping share (`--scatter-depth auto`; see
/// [`Scattered::skipped`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Skipped {
    /// Depth 1's power predicted from the sample (luminance, as [`DepthReport::power`]).
    pub predicted: f64,
    /// The emission lights' power.
    pub emitted: f64,
    /// Voxels sampled.
    pub sampled: usize,
    /// Voxels with smoke, which the depth would have shaded.
    pub voxels: usize,
    /// Seconds the pilot took, its shadows and lighting cache included.
    pub seconds: f64,
}

impl Skipped {
    /// Depth 1's predicted power as a share of the emitted light (0 where nothing is emitted).
    ///
    /// ```
    /// use lgh_volume::scattering::Skipped;
    ///
    /// let s = Skipped { predicted: 0.3, emitted: 100.0, sampled: 10, voxels: 90, seconds: 0.1 };
    /// assert!((s.share() - 0.003).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn share(&self) -> f64 {
        self.predicted / self.emitted.max(f64::MIN_POSITIVE)
    }
}

/// The multiple-scattering pass (paper Sec. 5; see the module docs): `settings.scatter_depth`
/// scattered depths of the `emission` lights in `frame` and `medium`, each depth's fluence
/// through `method` (with its own parameters, the hierarchy's α) with the shadows of
/// `settings`, merged into one light per voxel. Checked before any
/// work: the depth ([`check_depth`]), the density's grid, the settings, and the plan's memory
/// against `settings.cube_maps.memory_budget` ([`ScatterPlan`]). `progress` hears
/// [`Phase::Scattering`] over the voxels (`depth × lights_per_depth` in all, one depth more
/// with the scattered light as a grid). Depth 0 returns the emission
/// lights as they are.
///
/// ```
/// use lgh_volume::render::MarchSettings;
/// use lgh_volume::scattering::scatter;
/// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
///
/// let volume = procedural(32, 0.5)?;
/// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
/// let emission = ExplosionLights::new(&[&volume], &medium)?;
/// let settings = MarchSettings { shadows: Shadows::None, scatter_depth: 1, ..Default::default() };
/// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
/// // One merged light per voxel that emits or has smoke; the scattered light is there.
/// assert!(s.lights().lights().len() > emission.lights().len());
/// assert!(s.depths()[0].power > 0.0);
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
pub fn scatter(
    emission: &ExplosionLights,
    method: Method,
    frame: &Volume,
    medium: &Medium,
    settings: &MarchSettings,
    progress: &dyn Progress,
) -> Result<Scattered, RenderError> {
    scatter_keeping(emission, method, frame, medium, settings, progress).map(|(s, _)| s)
}

/// [`scatter`], and when the pilot skipped the pass, the emission lights' shading it made
/// (their shadows and the lighting cache it began to fill): what the render of the same lights
/// with the same settings needs, which [`FrameRender`](crate::FrameRender) takes instead of
/// building it again. (A cache brick's light depends on the brick alone, so the render's image
/// is the same bit for bit.)
pub(crate) fn scatter_keeping(
    emission: &ExplosionLights,
    method: Method,
    frame: &Volume,
    medium: &Medium,
    settings: &MarchSettings,
    progress: &dyn Progress,
) -> Result<(Scattered, Option<Shading>), RenderError> {
    let plan = check_pass(emission, method, frame, settings)?;
    let passes = plan.depth + usize::from(settings.scattered_grid(method));
    let total = (passes * plan.lights_per_depth) as u64;
    progress::phase(progress, Phase::Scattering, total, |p| {
        pass(emission, method, frame, medium, settings, p)
    })
}

/// [`scatter`] after its checks, `progress(n)` as `n` more voxels' fluence is done.
fn pass(
    emission: &ExplosionLights,
    method: Method,
    frame: &Volume,
    medium: &Medium,
    settings: &MarchSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<(Scattered, Option<Shading>), RenderError> {
    let depth = settings.scatter_depth;
    let max_level = emission.hierarchy().max_level();
    if depth == 0 {
        return Ok((single_scattering(emission, max_level), None));
    }
    let grid = &frame.density;
    let dense: Vec<usize> = (0..grid.data.len())
        .filter(|&v| grid.data[v] > 0.0)
        .collect();
    let (voxels, hot_slots, dense_slots) = merge(emission.voxels(), &dense);
    let mut per_depth = Vec::with_capacity(depth + 1);
    let emitted = emission.lights().iter().map(|l| l.intensity);
    per_depth.push(on_slots(voxels.len(), emitted, &hot_slots));

    // Every depth k ≥ 1 at the same voxels: one hierarchy, rebuilt with each depth's intensities.
    let mut scattered = ExplosionLights::at_voxels(
        grid,
        dense.clone(),
        &vec![Vec3::ZERO; dense.len()],
        Some(max_level),
    )?;
    // The emission lights' weak-light pruning and coarse lights' shadows carry over, to each
    // depth and to the merge.
    scattered.set_prune(emission.prune())?;
    scattered.set_near_field(emission.near_field());
    let coarse = emission.variants().coarse_shadows;
    scattered.set_coarse_shadows(coarse);
    let single = MarchSettings {
        scatter_depth: 0,
        ..*settings
    };
    // Depths ≥ 2 through their own cache of every level, where the settings ask for one.
    let later_cache = single.lighting_cache.scattered_depths(grid);
    // The later depths' spacing, if there are any (1: every voxel).
    let later_depths = depth + usize::from(settings.scattered_grid(method)) >= 2;
    let spacing = match later_cache {
        Some(_) if later_depths => single.lighting_cache.scattered_spacing_on(grid),
        _ => 1,
    };
    let later_settings = later_cache.map_or(single, |lighting_cache| MarchSettings {
        lighting_cache,
        ..single
    });
    let fluence = |settings| Fluence {
        method,
        frame,
        medium,
        settings,
        voxels: &dense,
        progress,
    };
    let (first, later) = (fluence(&single), fluence(&later_settings));
    let mut next = vec![Vec3::ZERO; dense.len()];
    let mut reports = Vec::with_capacity(depth);
    // With the scattered light as a grid: depths ≥ 2's intensities summed, each `h³ σ_s Φ/4π`
    // of the depth before (`scattered_light`), and one more depth than asked for.
    let grid_mode = settings.scattered_grid(method);
    let mut summed = grid_mode.then(|| vec![Vec3::ZERO; dense.len()]);
    let mut radiance_report = None;
    // Each depth's power, the emission's first: what the stopping rule reads.
    let mut powers = vec![power(&per_depth[0])];
    let mut last = depth;
    for k in 1..=depth + usize::from(grid_mode) {
        let t = Instant::now();
        let (source, pass) = if k == 1 {
            (emission, &first)
        } else {
            (&scattered, &later)
        };
        // The first depth under a stopping share has a pilot: skipped, if it cannot matter.
        let pilot = (k == 1 && settings.scatter_stop > 0.0).then(|| Pilot {
            share: settings.scatter_stop,
            emitted: powers[0],
        });
        let (stats, shadow_seconds) = match pass.run(source, &mut next, pilot)? {
            Ran::Done(stats, shadow_seconds) => (stats, shadow_seconds),
            Ran::Skipped {
                predicted,
                sampled,
                shading,
            } => {
                let skipped = Skipped {
                    predicted,
                    emitted: powers[0],
                    sampled,
                    voxels: dense.len(),
                    seconds: t.elapsed().as_secs_f64(),
                };
                let scattered = Scattered {
                    skipped: Some(skipped),
                    ..single_scattering(emission, max_level)
                };
                return Ok((scattered, Some(*shading)));
            }
        };
        if let (Some(summed), true) = (summed.as_mut(), k >= 2) {
            for (s, n) in summed.iter_mut().zip(&next) {
                *s += *n;
            }
        }
        let report = |seconds| DepthReport {
            depth: k,
            lights: dense.len(),
            shadow_seconds,
            seconds,
            power: power(&next),
            stats,
        };
        if k > last {
            // Depth n + 1: its intensities only, never lights.
            radiance_report = Some(report(t.elapsed().as_secs_f64()));
            break;
        }
        scattered.set_intensities(&next)?;
        per_depth.push(on_slots(voxels.len(), next.iter().copied(), &dense_slots));
        let report = report(t.elapsed().as_secs_f64());
        powers.push(report.power);
        reports.push(report);
        if k < last && settings.scatter_stop > 0.0 && stop_after(&powers, settings.scatter_stop) {
            // The last depth; with the grid, one more for its radiance.
            last = k;
            if !grid_mode {
                break;
            }
        }
    }
    let radiance = summed.map(|s| ScatteredRadiance::new(grid, &dense, &s));
    drop(scattered);
    // The paper's merge: one light per voxel, its depths summed in order.
    let merged_intensities: Vec<Vec3> = (0..voxels.len())
        .map(|s| per_depth.iter().fold(Vec3::ZERO, |a, d| a + d[s]))
        .collect();
    let mut merged =
        ExplosionLights::at_voxels(grid, voxels, &merged_intensities, Some(max_level))?;
    merged.set_prune(emission.prune())?;
    merged.set_near_field(emission.near_field());
    merged.set_coarse_shadows(coarse);
    let scattered = Scattered {
        merged,
        per_depth,
        reports,
        max_level,
        radiance,
        radiance_report,
        spacing,
        skipped: None,
    };
    Ok((scattered, None))
}

/// The pass of no depth: the emission lights as they are.
fn single_scattering(emission: &ExplosionLights, max_level: u8) -> Scattered {
    Scattered {
        merged: emission.clone(),
        per_depth: vec![emission_intensities(emission)],
        reports: Vec::new(),
        max_level,
        radiance: None,
        radiance_report: None,
        spacing: 1,
        skipped: None,
    }
}

/// Every check of a pass, before any work: the settings, the method (emission alone has no
/// lights to scatter), and the pass's memory; the pass's [`ScatterPlan`].
fn check_pass(
    emission: &ExplosionLights,
    method: Method,
    frame: &Volume,
    settings: &MarchSettings,
) -> Result<ScatterPlan, RenderError> {
    let depth = settings.scatter_depth;
    let mut plan = ScatterPlan::new(emission, frame, depth)?;
    if settings.scattered_grid(method) {
        plan = plan.with_grid(frame);
    }
    settings.check()?;
    method.check()?;
    if method == Method::Emission && depth > 0 {
        return Err(nothing_to_scatter(depth));
    }
    plan.check(settings.cube_maps.memory_budget)?;
    Ok(plan)
}

/// The error of a pass of `depth` asked of [`Method::Emission`], which has no lights.
fn nothing_to_scatter(depth: usize) -> RenderError {
    RenderError::InvalidCount {
        name: "scatter depth",
        value: depth,
        rule: "needs lights to scatter: emission alone has none",
    }
}

/// `len` intensities, `values` at their `slots` and zero elsewhere.
fn on_slots(len: usize, values: impl Iterator<Item = Vec3>, slots: &[usize]) -> Vec<Vec3> {
    let mut out = vec![Vec3::ZERO; len];
    for (v, &s) in values.zip(slots) {
        out[s] = v;
    }
    out
}

/// Whether a scattering pass stops after the depths whose powers are `powers` (depth 0, the
/// emission lights', first): when the next depth's power, predicted from the last two, is below
/// `share` of all the light so far. Each depth scatters the one before through the same smoke,
/// so the power falls by a nearly steady factor `r` a depth and the next is about
/// `P_k · (P_k / P_{k−1})`. The rule weighs that next depth alone: all the depths left out hold
/// about `P_{k+1} / (1 − r)`, so with `r` = 0.66 (the demo's explosion) a share of 1% leaves out
/// about 3% of the light, with `r` = 0.8 about 5%.
///
/// ```
/// use lgh_volume::scattering::stop_after;
///
/// let halving = [1.0, 0.5, 0.25]; // the next about 0.125, 7% of the 1.75 so far
/// assert!(stop_after(&halving, 0.1));
/// assert!(!stop_after(&halving, 0.05));
/// assert!(!stop_after(&[1.0], 0.5)); // no depth yet: nothing to predict from
/// assert!(stop_after(&[1.0, 0.0], 0.01)); // nothing scattered: nothing more will be
/// ```
#[must_use]
pub fn stop_after(powers: &[f64], share: f32) -> bool {
    let [.., before, last] = powers else {
        return false;
    };
    let next = if *before > 0.0 {
        last * (last / before)
    } else {
        0.0
    };
    next < f64::from(share) * powers.iter().sum::<f64>()
}

/// The emission lights' intensities, in their order.
fn emission_intensities(emission: &ExplosionLights) -> Vec<Vec3> {
    emission.lights().iter().map(|l| l.intensity).collect()
}

/// The luminance of the summed intensities, in f64 (a depth's power, [`DepthReport::power`]).
fn power(intensities: &[Vec3]) -> f64 {
    let total = intensities.iter().fold([0.0f64; 3], |a, i| {
        [0, 1, 2].map(|c| a[c] + f64::from(i[c]))
    });
    lgh_core::LUMINANCE_WEIGHTS
        .to_array()
        .iter()
        .zip(total)
        .map(|(&w, t)| f64::from(w) * t)
        .sum()
}

/// The sorted union of `hot` and `dense` (both ascending), with each one's slot in it.
fn merge(hot: &[usize], dense: &[usize]) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let mut voxels = Vec::with_capacity(hot.len() + dense.len());
    let (mut hot_slots, mut dense_slots) = (Vec::with_capacity(hot.len()), Vec::new());
    dense_slots.reserve(dense.len());
    let (mut a, mut b) = (0, 0);
    while a < hot.len() || b < dense.len() {
        let v = match (hot.get(a), dense.get(b)) {
            (Some(&h), Some(&d)) => h.min(d),
            (Some(&h), None) => h,
            (None, Some(&d)) => d,
            (None, None) => unreachable!("the loop runs while one is left"),
        };
        if hot.get(a) == Some(&v) {
            hot_slots.push(voxels.len());
            a += 1;
        }
        if dense.get(b) == Some(&v) {
            dense_slots.push(voxels.len());
            b += 1;
        }
        voxels.push(v);
    }
    (voxels, hot_slots, dense_slots)
}

/// One depth's fluence pass: what stays the same from depth to depth.
struct Fluence<'a> {
    method: Method,
    frame: &'a Volume,
    medium: &'a Medium,
    settings: &'a MarchSettings,
    /// The voxels with smoke, ascending.
    voxels: &'a [usize],
    progress: &'a (dyn Fn(usize) + Sync),
}

impl Fluence<'_> {
    /// `out[i] = h³ σ_s(x_i)/(4π) · Φ(x_i)` for each voxel `x_i`, with `Φ` the shadowed fluence
    /// of `source` (shadows built here, as the settings ask). Returns the queries' counts and
    /// the seconds spent on the shadows.
    ///
    /// With a `pilot`, the fluence is first computed at a systematic sample of the voxels
    /// ([`Pilot`]); if the depth's power predicted from it is below the pilot's bar, nothing
    /// more is done and the prediction is returned ([`Ran::Skipped`]). Each voxel's fluence
    /// depends on the voxel alone (the lighting cache fills each of its bricks once, the same
    /// whoever asks first), so a depth the pilot lets through is the same bit for bit.
    fn run(
        &self,
        source: &ExplosionLights,
        out: &mut [Vec3],
        pilot: Option<Pilot>,
    ) -> Result<Ran, RenderError> {
        let shading = Shading::new(
            source,
            self.method,
            self.frame,
            self.medium,
            self.settings,
            &(),
        )?;
        let (visibility, shadow_seconds) = (&shading.visibility, shading.shadow_seconds);
        // Refused by `check_pass` before any work; never met here.
        let Some(lights) = shading.prepared.lights(source)? else {
            return Err(nothing_to_scatter(1));
        };
        // The fluence at the voxel's centre: the cell means (`near_field::cell_falloff`,
        // `Volume::cell_density`) took the path-tracer test's ball 3% further from the path
        // tracer (docs/shadows.md, "Cell means in the pass").
        let grid = &self.frame.density;
        // With a lighting cache, the coarse levels' fluence comes from it, as in the render —
        // where some grid is coarser than the voxels: the pass queries every voxel, so a cache
        // whose vertices are all at least as dense as the voxels would only add work.
        let sparse = |c: &&LightingCache| c.tiers().iter().any(|&(_, voxels)| voxels > 1.0);
        let cache = shading.cache.as_ref().filter(sparse);
        let cached = CachedLights::of(cache, grid, &lights);
        let h3 = grid.voxel_size.powi(3);
        let shade = |voxels: &[usize], out: &mut [Vec3], progress: bool| {
            shade_voxels(voxels, out, |out, voxels| {
                let mut scratch = LightScratch::default();
                let mut stats = RenderStats::default();
                for (o, &v) in out.iter_mut().zip(voxels) {
                    let [i, j, k] = crate::grid::unflatten(v, grid.dims);
                    let (x, rho) = (grid.centre(i, j, k), grid.data[v]);
                    let scale = h3 * self.medium.scattering * rho;
                    *o = match &cached {
                        Some(c) => {
                            let sigma_t = self.medium.extinction(rho);
                            c.in_scattered(x, scale, sigma_t, visibility, &mut scratch, &mut stats)?
                        }
                        None => {
                            let sigma_t = self.medium.extinction(rho);
                            let s = (&mut scratch, &mut stats);
                            lights.in_scattered(x, scale, sigma_t, visibility, s.0, s.1)?
                        }
                    };
                }
                if progress {
                    (self.progress)(voxels.len());
                }
                Ok(stats)
            })
        };
        let mut stats = RenderStats::default();
        if let Some(pilot) = pilot {
            let sample = pilot.sample(self.voxels);
            let mut fluence = vec![Vec3::ZERO; sample.len()];
            stats.add(&shade(&sample, &mut fluence, false)?);
            let predicted = power(&fluence) * self.voxels.len() as f64 / sample.len() as f64;
            if predicted < pilot.bar() {
                return Ok(Ran::Skipped {
                    predicted,
                    sampled: sample.len(),
                    shading: Box::new(shading),
                });
            }
        }
        stats.add(&shade(self.voxels, out, true)?);
        // One shading point per voxel, whether it shaded lights or only read the cache; the
        // cache's vertices are this depth's work too: their lights and shadow samples count
        // with the voxels' (a depth through a cache of every level shades no light per voxel).
        stats.shading_points = self.voxels.len() as u64;
        if let Some(c) = cache {
            let filled = c.stats();
            stats.lights_evaluated += filled.lights_evaluated;
            stats.shadow_samples += filled.shadow_samples;
        }
        Ok(Ran::Done(stats, shadow_seconds))
    }
}

/// `shade(out, voxels)` over `voxels` and `out` in fixed chunks of [`CHUNK_VOXELS`], in
/// parallel; the chunks' counts summed in order.
fn shade_voxels(
    voxels: &[usize],
    out: &mut [Vec3],
    shade: impl Fn(&mut [Vec3], &[usize]) -> Result<RenderStats, RenderError> + Sync,
) -> Result<RenderStats, RenderError> {
    let chunks: Vec<Result<RenderStats, RenderError>> = out
        .par_chunks_mut(CHUNK_VOXELS)
        .zip(voxels.par_chunks(CHUNK_VOXELS))
        .map(|(out, voxels)| shade(out, voxels))
        .collect();
    let mut stats = RenderStats::default();
    for c in chunks {
        stats.add(&c?);
    }
    Ok(stats)
}

/// Voxels the pilot of a pass's first depth samples, at most ([`Scattered::skipped`]).
pub const PILOT_VOXELS: usize = 4096;

/// The pilot of a pass's first depth under a stopping share (`--scatter-depth auto`): before
/// the depth-1 fluence is computed at every smoky voxel, it is computed at every `m`-th of
/// them (in index order, `m` the smallest that keeps the sample to [`PILOT_VOXELS`]), and the
/// depth's power is predicted as the sample's times `n / sample`. Depth 1 — and so every depth —
/// is skipped when that prediction is below `share` of the emission lights' power: the rule of
/// [`stop_after`] for the first depth, which has no depth before it to predict from. Where the
/// smoke scatters nothing (albedo 0) the prediction is exactly 0; where it scatters almost
/// nothing (thin smoke around a flame) the pass, its lights and their cost in the render are
/// saved, and the image is the single-scattering one, bit for bit.
#[derive(Clone, Copy, Debug)]
struct Pilot {
    share: f32,
    /// The emission lights' power (depth 0).
    emitted: f64,
}

impl Pilot {
    /// The sample: every `m`-th of `voxels`.
    fn sample(self, voxels: &[usize]) -> Vec<usize> {
        let m = voxels.len().div_ceil(PILOT_VOXELS).max(1);
        voxels.iter().step_by(m).copied().collect()
    }

    /// The power below which the depth is skipped.
    fn bar(self) -> f64 {
        f64::from(self.share) * self.emitted
    }
}

/// What [`Fluence::run`] did.
enum Ran {
    /// The depth, with its counts and the seconds of its shadows.
    Done(RenderStats, f64),
    /// Skipped by the pilot: its predicted power, from `sampled` voxels, and the source's
    /// shading it made.
    Skipped {
        predicted: f64,
        sampled: usize,
        shading: Box<Shading>,
    },
}

/// How the image splits by where its light comes from: the luminance summed over an image's
/// pixels of the emission alone, and of what each depth's lights add (see
/// [`FrameRender::scatter_shares`](crate::FrameRender::scatter_shares)).
#[derive(Clone, Debug, PartialEq)]
pub struct Shares {
    /// `Σ_px ‖E‖`: the emission seen through the smoke, no scattering.
    pub emission: f64,
    /// `Σ_px ‖R_k − E‖` for `k = 0..=n`, `R_k` the image lit by depth `k`'s lights alone (depth
    /// 0: single scattering of the emission lights).
    pub depths: Vec<f64>,
}

impl Shares {
    /// The shares of `emitted`, the emission alone, and `depths[k]`, the image lit by depth
    /// `k`'s lights alone (the same size).
    pub(crate) fn of_images(emitted: &Image, depths: &[Image]) -> Shares {
        let luminance = |p: Vec3| f64::from(lgh_core::luminance(p));
        Shares {
            emission: emitted.pixels.iter().map(|&p| luminance(p)).sum(),
            depths: depths
                .iter()
                .map(|image| {
                    image
                        .pixels
                        .iter()
                        .zip(&emitted.pixels)
                        .map(|(&r, &e)| luminance(r) - luminance(e))
                        .sum()
                })
                .collect(),
        }
    }
}

impl Scattered {
    /// Voxels between the vertices of the grid that depths ≥ 2 computed their fluence at
    /// ([`LightingCacheSettings::scattered_spacing_on`](crate::lighting_cache::LightingCacheSettings::scattered_spacing_on));
    /// 1 where every voxel's was computed.
    #[must_use]
    pub fn spacing(&self) -> u8 {
        self.spacing
    }

    /// The merged lights (one per voxel that emits or has smoke): what the final render shades
    /// with ([`FrameRender::lights`](crate::FrameRender::lights)). (Their
    /// [`set_frame`](ExplosionLights::set_frame) would replace the merged intensities with a
    /// frame's emission.)
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::scattering::scatter;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let settings = MarchSettings { shadows: Shadows::None, scatter_depth: 1, ..Default::default() };
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
    /// // The merged hierarchy is on the emission lights' grid.
    /// assert_eq!(s.lights().hierarchy().h1(), emission.hierarchy().h1());
    /// assert_eq!(s.lights().hierarchy().max_level(), emission.hierarchy().max_level());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn lights(&self) -> &ExplosionLights {
        &self.merged
    }

    /// Whether the pass was skipped: under a stopping share (`--scatter-depth auto`), depth 1's
    /// power is first predicted from a sample of the voxels, and the pass stops before any
    /// depth if it is below the share of the emitted light. The lights are then the emission
    /// lights as they are, and the image the single-scattering one, bit for bit.
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::scattering::scatter;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let emission = ExplosionLights::new(&[&volume], &Medium::new(2.0, 6.0, 1e-4, 1000.0)?)?;
    /// let auto = MarchSettings {
    ///     shadows: Shadows::None,
    ///     scatter_depth: 16,
    ///     scatter_stop: 0.01,
    ///     ..Default::default()
    /// };
    /// // Smoke that only absorbs (albedo 0) scatters nothing: no depth is computed.
    /// let black = Medium::new(2.0, 0.0, 1e-4, 1000.0)?;
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &black, &auto, &())?;
    /// assert_eq!(s.skipped().unwrap().predicted, 0.0);
    /// assert!(s.depths().is_empty());
    /// // A scattering one goes on.
    /// let grey = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &grey, &auto, &())?;
    /// assert!(s.skipped().is_none() && !s.depths().is_empty());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn skipped(&self) -> Option<&Skipped> {
        self.skipped.as_ref()
    }

    /// One report per scattered depth `1..=n`.
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::scattering::scatter;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let settings = MarchSettings { shadows: Shadows::None, scatter_depth: 1, ..Default::default() };
    /// let settings = MarchSettings { scatter_depth: 2, ..settings };
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
    /// let d = s.depths();
    /// assert_eq!((d[0].depth, d[1].depth), (1, 2));
    /// assert_eq!(d[0].stats.shading_points, d[0].lights as u64); // one query per voxel
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn depths(&self) -> &[DepthReport] {
        &self.reports
    }

    /// The scattered depths' in-scattered radiance at the voxels, if the settings take the
    /// scattered light in as a grid ([`MarchSettings::scattered_grid`]), and the report of the
    /// extra fluence pass (depth `n + 1`'s) it took.
    #[must_use]
    pub fn radiance(&self) -> Option<(&ScatteredRadiance, &DepthReport)> {
        self.radiance.as_ref().zip(self.radiance_report.as_ref())
    }

    /// The intensities of depth `k` (0: the emission) on the merged lights' voxels, in the order
    /// of [`lights`](Self::lights)' lights; `None` past the last depth.
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::scattering::scatter;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let settings = MarchSettings { shadows: Shadows::None, scatter_depth: 1, ..Default::default() };
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
    /// // A merged light is its voxel's depths summed in order.
    /// let (e, one) = (s.intensities(0).unwrap(), s.intensities(1).unwrap());
    /// for ((l, &a), &b) in s.lights().lights().iter().zip(e).zip(one) {
    ///     assert_eq!(l.intensity, a + b);
    /// }
    /// assert!(s.intensities(2).is_none());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn intensities(&self, depth: usize) -> Option<&[Vec3]> {
        self.per_depth.get(depth).map(Vec::as_slice)
    }

    /// The lights of depth `k` alone (0: the emission lights) on the merged lights' voxels and
    /// grid: what [`FrameRender::scatter_shares`](crate::FrameRender::scatter_shares) renders. Depth 0 renders the single-scattering image
    /// bit for bit (the added voxels are dark, the grid is the emission lights').
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::scattering::scatter;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let settings = MarchSettings { shadows: Shadows::None, scatter_depth: 1, ..Default::default() };
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
    /// assert_eq!(s.depth_lights(0)?.lit(), emission.lit());
    /// assert!(s.depth_lights(2).is_err());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn depth_lights(&self, depth: usize) -> Result<ExplosionLights, RenderError> {
        let intensities = self.intensities(depth).ok_or(RenderError::InvalidCount {
            name: "scatter depth",
            value: depth,
            rule: "is past the pass's last depth",
        })?;
        let mut lights = self.merged.clone();
        lights.set_intensities(intensities)?;
        debug_assert_eq!(lights.hierarchy().max_level(), self.max_level);
        Ok(lights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::procedural;
    use crate::render::{Camera, Framing};
    use crate::shadow::{ShadowGrid, Shadows};

    /// A ball of smoke with a hot core (up to 2500 K inside radius 0.35), `n³` voxels.
    fn blob(n: usize) -> Volume {
        crate::procedural::ball(n, 0.35, 2500.0)
    }

    fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
        v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
    }

    /// The pass of `depth` with `settings` and no progress.
    fn pass(
        emission: &ExplosionLights,
        depth: usize,
        method: Method,
        volume: &Volume,
        medium: &Medium,
        settings: &MarchSettings,
    ) -> Scattered {
        let settings = MarchSettings {
            scatter_depth: depth,
            ..*settings
        };
        scatter(emission, method, volume, medium, &settings, &()).unwrap()
    }

    #[test]
    fn coarse_lights_shadowed_as_volume_lights_keep_the_first_depth_near_brute_force() {
        // The demo's explosion at 64³ (thin fire in a shell of soot) in Blender's model, σ_t =
        // 4ρ, albedo 0.7 (the Cycles comparison's explosion64): the first scattered depth's
        // power through the hierarchy at α = 2 against brute force over the same lights, with
        // ray-marched shadows. Coarse lights shadowed as points (`RayMarch`) let more light
        // through than their lights do; as the volume lights of eq. 6 — the reference model
        // (`RayMarchVolumes`) and its cone-stepped form (`Volumes`) — the power is near brute
        // force's. Measured (printed): points +3.3%, reference +0.44%, cone +0.84% (the CLI on
        // the same volume read from its Z-up VDB: +3.4%, +0.4%, +0.7%; 128³ against α = 8:
        // +3.3%, +0.3%, +0.8%); the bounds leave about 40% of room.
        let volume = crate::procedural::explosion(64, 0.5).unwrap();
        let medium = Medium::new(1.2, 2.8, 1.0, 0.0)
            .unwrap()
            .with_model(crate::medium::EmissionModel::Blender);
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let power = |method, shadows| {
            let settings = MarchSettings {
                shadows,
                lighting_cache: crate::lighting_cache::LightingCacheSettings::default(),
                ..Default::default()
            };
            pass(&emission, 1, method, &volume, &medium, &settings).depths()[0].power
        };
        let lgh = Method::Lgh { alpha: 2.0 };
        let brute = power(Method::Brute, Shadows::RayMarch);
        let points = power(lgh, Shadows::RayMarch) / brute - 1.0;
        let reference = power(lgh, Shadows::RayMarchVolumes) / brute - 1.0;
        let cone = power(lgh, Shadows::Volumes) / brute - 1.0;
        eprintln!(
            "against brute force: points {points:+.4}, volumes {reference:+.4}, cone {cone:+.4}"
        );
        assert!(points > 0.025, "{points}");
        assert!(reference.abs() < 0.006, "{reference}");
        assert!(cone.abs() < 0.012, "{cone}");
    }

    #[test]
    fn the_pilot_skips_a_pass_that_cannot_matter_and_predicts_its_power() {
        // The ball at 32³: 8,744 smoky voxels, so the pilot samples every 3rd (2,915).
        let volume = blob(32);
        let lgh = Method::Lgh { alpha: 2.0 };
        let frame = |medium: &Medium, depth, stop| {
            let emission = ExplosionLights::new(&[&volume], medium).unwrap();
            let settings = MarchSettings {
                scatter_depth: depth,
                scatter_stop: stop,
                ..Default::default()
            };
            let render = crate::FrameRender::new(&emission, lgh, &volume, medium, &settings, &());
            let render = render.unwrap();
            let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 24, 24).unwrap();
            let image = render.render(&camera, &()).unwrap().0;
            let skipped = render.scattered().and_then(Scattered::skipped).copied();
            let power = render
                .scattered()
                .and_then(|s| s.depths().first().map(|d| d.power));
            (bits(&image.pixels), skipped, power)
        };
        // Thin, nearly black smoke: depth 1 would add well under 1% of the emitted light.
        let thin = Medium::new(1.0, 0.02, 1e-4, 1000.0).unwrap();
        let (image, skipped, _) = frame(&thin, 16, 0.01);
        let skipped = skipped.expect("the pilot skips the pass");
        assert!(skipped.predicted > 0.0 && skipped.predicted < 0.01 * skipped.emitted);
        assert_eq!((skipped.sampled, skipped.voxels), (2915, 8744));
        // The image is the single-scattering one, bit for bit.
        let (single, none, _) = frame(&thin, 0, 0.0);
        assert!(none.is_none());
        assert_eq!(image, single);
        // The prediction against the depth computed at every voxel, from a systematic sample of
        // a third of them. 2%: a uniformly random sample of 2,915 voxels whose powers spread
        // with a coefficient of variation of 1 errs by 1/√2915 = 1.85% (one standard
        // deviation); a systematic sample of a smooth field does better (measured: 0.26%).
        let (_, _, exact) = frame(&thin, 1, 0.0);
        let (_, by_pilot, _) = frame(&thin, 16, 0.999);
        let (exact, predicted) = (exact.unwrap(), by_pilot.unwrap().predicted);
        assert!(
            (predicted / exact - 1.0).abs() < 0.02,
            "{predicted} against {exact}"
        );
        // Smoke that scatters goes on, and its first depth is the full pass's, bit for bit.
        let grey = Medium::new(1.0, 4.0, 1e-4, 1000.0).unwrap();
        let (_, skipped, auto) = frame(&grey, 16, 0.01);
        let (_, _, full) = frame(&grey, 1, 0.0);
        assert!(skipped.is_none());
        assert_eq!(auto.map(f64::to_bits), full.map(f64::to_bits));
    }

    #[test]
    fn the_pass_stops_where_the_next_depth_would_add_too_little() {
        // A pass of up to 8 depths that stops by the rule computes the same first depths as the
        // full pass, bit for bit, and stops at the first depth after which the rule holds.
        let volume = blob(12);
        let medium = Medium::new(1.0, 4.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let lgh = Method::Lgh { alpha: 2.0 };
        let full = pass(
            &emission,
            8,
            lgh,
            &volume,
            &medium,
            &MarchSettings::default(),
        );
        let share = 0.05;
        let stopping = MarchSettings {
            scatter_stop: share,
            ..Default::default()
        };
        let stopped = pass(&emission, 8, lgh, &volume, &medium, &stopping);
        let n = stopped.depths().len();
        assert!((1..8).contains(&n), "{n} depths");
        let mut powers = vec![power(&emission_intensities(&emission))];
        powers.extend(full.depths().iter().map(|d| d.power));
        for k in 1..=n {
            assert_eq!(
                bits(stopped.intensities(k).unwrap()),
                bits(full.intensities(k).unwrap())
            );
            assert_eq!(
                stop_after(&powers[..=k], share),
                k == n,
                "depth {k}: {powers:?}"
            );
        }
        // What it left out is near what the rule predicted: the next depth within a factor 2.
        let (predicted, actual) = (powers[n] * powers[n] / powers[n - 1], powers[n + 1]);
        assert!(
            actual < 2.0 * predicted && predicted < 2.0 * actual,
            "{powers:?}"
        );
        let bad = MarchSettings {
            scatter_stop: 1.0,
            ..stopping
        };
        assert!(bad.check().is_err());

        // With the scattered light as a grid, the pass stops at the same depth and computes one
        // more for the grid alone.
        use crate::lighting_cache::{LightingCacheSettings, ScatteredLight};
        let grid = MarchSettings {
            lighting_cache: LightingCacheSettings {
                scattered_light: ScatteredLight::Grid,
                ..LightingCacheSettings::coarse()
            },
            ..stopping
        };
        let gridded = pass(&emission, 8, lgh, &volume, &medium, &grid);
        let (_, report) = gridded.radiance().expect("a grid");
        let m = gridded.depths().len();
        assert!((1..8).contains(&m), "{m} depths");
        assert_eq!(report.depth, m + 1);
    }

    #[test]
    fn the_emission_lights_pruning_carries_over_to_the_merged_lights() {
        let volume = blob(16);
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let mut emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        emission.set_prune(1e-3).unwrap();
        let settings = MarchSettings {
            shadows: Shadows::RayMarch,
            ..Default::default()
        };
        let s = pass(
            &emission,
            1,
            Method::Lgh { alpha: 2.0 },
            &volume,
            &medium,
            &settings,
        );
        let merged = s.lights();
        assert_eq!(merged.prune(), 1e-3);
        let brightest = merged.brightest();
        assert_eq!(merged.hierarchy().prune_below(), 1e-3 * brightest);
        assert!(brightest > 0.0);
    }

    #[test]
    fn with_albedo_zero_the_merged_lights_render_single_scattering_bit_for_bit() {
        // The pass runs in a medium that does not scatter (κ_s = 0, the same extinction as the
        // render's, so the same shadows): every scattered light is computed — one fluence query
        // per voxel with smoke, per depth — and is exactly dark. The merged set then holds
        // those dark lights beside the emission lights (more lights, another hierarchy and
        // other cube maps over it); rendered in a medium that *does* scatter, it must give the
        // single-scattering image bit for bit. (Rendered in the albedo-0 medium itself the
        // marcher would never query the lights, and the test would prove nothing.)
        //
        // The smoke reaches far beyond the fire (radius 0.8 against 0.35), so that lights
        // chosen on their own would take a higher top level (5 against 3) and another image:
        // the merged set must keep the emission lights' grid.
        let volume = blob(24);
        let render_medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let pass_medium = Medium::new(8.0, 0.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &render_medium).unwrap();
        let (lo, hi) = volume.active_bounds().unwrap();
        let camera = Camera::frame(lo, hi, 20, 12).unwrap();
        let smoke = volume.density.data.iter().filter(|&&r| r > 0.0).count() as u64;
        for (method, shadows) in [
            (Method::Lgh { alpha: 2.0 }, Shadows::CubeMap),
            (Method::Lgh { alpha: 2.0 }, Shadows::RayMarch),
            (Method::Brute, Shadows::RayMarch),
        ] {
            let settings = MarchSettings {
                shadows,
                ..Default::default()
            };
            let s = pass(&emission, 2, method, &volume, &pass_medium, &settings);
            for d in s.depths() {
                assert_eq!(
                    d.stats.shading_points, smoke,
                    "{method:?}: every voxel queried"
                );
                assert_eq!(d.power, 0.0);
            }
            assert!(s.lights().lights().len() as u64 >= smoke);
            let own = ExplosionLights::at_voxels(
                &volume.density,
                s.lights().voxels().to_vec(),
                &vec![Vec3::ZERO; s.lights().lights().len()],
                None,
            )
            .unwrap();
            assert!(own.hierarchy().max_level() > emission.hierarchy().max_level());
            assert!(s.lights().lights().len() > emission.lights().len());
            assert_eq!(s.lights().lit(), emission.lit());
            let render = |lights: &ExplosionLights| {
                let frame = &volume;
                crate::FrameRender::new(lights, method, frame, &render_medium, &settings, &())
                    .and_then(|f| f.render(&camera, &()))
                    .unwrap()
                    .0
            };
            let single = render(&emission);
            assert!(single.pixels.iter().any(|p| p.max_element() > 0.0));
            assert!(
                bits(&render(s.lights()).pixels) == bits(&single.pixels),
                "{method:?}, {shadows:?}: the images differ"
            );
        }
    }

    #[test]
    fn each_depth_scales_exactly_as_the_albedo_to_its_power() {
        // At a fixed extinction σ_t, `I^k = h³ σ_s/(4π) Φ^{k−1}` is linear in the depth-(k−1)
        // intensities and in σ_s, and the shadows depend on σ_t only; so scaling κ_s by c scales
        // depth k by c^k. With c a power of two every rounding commutes with the scaling
        // (and the hierarchy's centres are ratios of luminance-weighted sums, unchanged), so the
        // identity holds bit for bit: I^k(κ_s / 2^m) = I^k(κ_s) / 2^{mk}, for the hierarchy with
        // its cube maps as for brute force. The depths' light shrinks geometrically with the
        // albedo (1 and 1/4 here).
        let media = [(0.0, 4.0), (3.0, 1.0)].map(|(a, s)| Medium::new(a, s, 1e-4, 1000.0).unwrap());
        for (method, shadows, volume) in [
            (Method::Lgh { alpha: 2.0 }, Shadows::CubeMap, blob(16)),
            (Method::Brute, Shadows::RayMarch, blob(12)),
        ] {
            let emission = ExplosionLights::new(&[&volume], &media[0]).unwrap();
            let settings = MarchSettings {
                shadows,
                ..Default::default()
            };
            let runs: Vec<Scattered> = media
                .iter()
                .map(|m| pass(&emission, 3, method, &volume, m, &settings))
                .collect();
            // κ_s / 4: depth k scaled by 4^{-k}.
            for run in &runs[1..] {
                for k in 0..=3 {
                    let scale = 0.25f32.powi(k as i32);
                    let want: Vec<Vec3> = runs[0]
                        .intensities(k)
                        .unwrap()
                        .iter()
                        .map(|&i| i * scale)
                        .collect();
                    assert_eq!(
                        bits(run.intensities(k).unwrap()),
                        bits(&want),
                        "{method:?}: depth {k}"
                    );
                }
            }
            // And the light is there to scale: each depth adds some.
            assert!(runs[0].depths().iter().all(|d| d.power > 0.0), "{method:?}");
        }
    }

    #[test]
    fn brute_force_depths_match_a_direct_sum_and_lgh_at_huge_alpha_matches_brute_force() {
        // The reference: every depth-k light computed here by the definition, in f64, with
        // the ray-marched transmittance V(x, p) of the same ShadowGrid (so that V is the same
        // bits): I^k(x) = h³ σ_s(x)/(4π) Σ_p I^{k−1}(p) V(x, p) G(|x − p|), with G the voxel
        // lights' fall-off (the voxel's mean of 1/r², `lgh_core::near_field`).
        use lgh_core::near_field::shielding;
        use lgh_core::NearField;
        let volume = blob(12);
        let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let settings = MarchSettings::default(); // ray-marched shadows
        let depth = 3;
        let brute = pass(&emission, depth, Method::Brute, &volume, &medium, &settings);
        let grid = ShadowGrid::new(
            &volume,
            &medium,
            settings.shadow_step_voxels,
            settings.min_transmittance,
        );
        let d = &volume.density;
        let h = f64::from(d.voxel_size);
        let voxels = brute.lights().voxels().to_vec();
        let centre = |v: usize| {
            let [i, j, k] = crate::grid::unflatten(v, d.dims);
            d.centre(i, j, k)
        };
        let mut previous: Vec<[f64; 3]> = brute
            .intensities(0)
            .unwrap()
            .iter()
            .map(|i| i.to_array().map(f64::from))
            .collect();
        // Each light's f32 result is a sum of N non-negative terms (N lights of the depth
        // before), each a product of a few rounded factors: relative error ≤ (N + 12) u per
        // depth (u = 2⁻²⁴; any summation order), carried on to the next depth, where all terms
        // stay non-negative: ≤ k (N + 12) u at depth k.
        let u = f64::from(f32::EPSILON) / 2.0;
        let n = voxels.len() as f64;
        let mut worst = 0.0f64;
        for k in 1..=depth {
            let got = brute.intensities(k).unwrap();
            let bound = k as f64 * (n + 12.0) * u;
            let mut next = vec![[0.0f64; 3]; voxels.len()];
            for (s, &v) in voxels.iter().enumerate() {
                let rho = d.data[v];
                if rho <= 0.0 {
                    assert_eq!(got[s], Vec3::ZERO);
                    continue;
                }
                let x = centre(v);
                let mut sum = [0.0f64; 3];
                for (q, &w) in voxels.iter().enumerate() {
                    if previous[q] == [0.0; 3] {
                        continue;
                    }
                    let p = centre(w);
                    // The voxel lights' fall-off (`lgh_core::near_field`), as the pass's lights,
                    // shielded by the smoke at x.
                    let shield = shielding(medium.extinction(rho) * h as f32);
                    let g = NearField::Voxel.falloff_in(0, x.distance(p), h as f32, shield);
                    let g = f64::from(g);
                    let vis = f64::from(grid.transmittance(x, p).0);
                    for c in 0..3 {
                        sum[c] += previous[q][c] * vis * g;
                    }
                }
                let factor =
                    h.powi(3) * f64::from(medium.scattering * rho) / (4.0 * std::f64::consts::PI);
                for c in 0..3 {
                    next[s][c] = sum[c] * factor;
                    let err = (f64::from(got[s][c]) - next[s][c]).abs();
                    worst = worst.max(err / next[s][c].max(f64::MIN_POSITIVE));
                    assert!(
                        err <= bound * next[s][c],
                        "depth {k}, voxel {v}: {} vs {}",
                        got[s][c],
                        next[s][c]
                    );
                }
            }
            previous = next;
        }
        assert!(previous.iter().any(|p| p[1] > 0.0));
        eprintln!("brute-force pass against the direct sum: worst relative error {worst:.2e}");

        // At α = 64, r_0 = 64 h exceeds the grid's diagonal (12√3 h ≈ 21 h): every light is in
        // level 0 with weight B_0 = 1 and the hierarchy sums the same terms as brute force, in
        // another order. Both are within k (N + 12) u of the exact sum.
        let lgh = pass(
            &emission,
            depth,
            Method::Lgh { alpha: 64.0 },
            &volume,
            &medium,
            &settings,
        );
        for k in 1..=depth {
            let bound = 2.0 * k as f64 * (n + 12.0) * u;
            let (a, b) = (lgh.intensities(k).unwrap(), brute.intensities(k).unwrap());
            for (x, y) in a.iter().zip(b) {
                for c in 0..3 {
                    let err = f64::from((x[c] - y[c]).abs());
                    assert!(err <= bound * f64::from(y[c]), "depth {k}: {x} vs {y}");
                }
            }
        }
        // The merged lights shade as brute force does, up to rounding, through both.
        assert_eq!(lgh.lights().voxels(), brute.lights().voxels());
    }

    #[test]
    fn the_shares_add_up_to_the_image_for_brute_force() {
        // The marcher is linear in the lights' intensities: without shadows (V = 1) and with
        // brute force, emission + Σ_k (R_k − E) is the merged image up to rounding. Each
        // pixel's scattered light is a sum of N non-negative terms per step (N ≤ merged
        // lights): relative error ≤ (N + 12) u of its value, for the merged image and each of
        // the n + 2 parts; their sum errs by at most (n + 3) (N + 12) u of the total.
        let volume = blob(12);
        let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let settings = MarchSettings {
            shadows: Shadows::None,
            ..Default::default()
        };
        let settings = MarchSettings {
            scatter_depth: 2,
            ..settings
        };
        let frame =
            crate::FrameRender::new(&emission, Method::Brute, &volume, &medium, &settings, &())
                .unwrap();
        let s = frame.scattered().unwrap();
        let camera = Camera::frame(Vec3::splat(-0.8), Vec3::splat(0.8), 16, 12).unwrap();
        let shares = frame.scatter_shares(&camera, &()).unwrap().unwrap();
        let (image, _) = frame.render(&camera, &()).unwrap();
        let total: f64 = image
            .pixels
            .iter()
            .map(|&p| f64::from(lgh_core::luminance(p)))
            .sum();
        let parts = shares.emission + shares.depths.iter().sum::<f64>();
        let u = f64::from(f32::EPSILON) / 2.0;
        let n = s.lights().lights().len() as f64;
        let bound = 5.0 * (n + 12.0) * u;
        assert!(
            (parts - total).abs() <= bound * total,
            "{parts} vs {total} ({shares:?})"
        );
        // Every depth adds light. (Without shadows nothing bounds the ratio of one depth to
        // the last: unshadowed, the model does not conserve energy.)
        assert!(shares.depths.iter().all(|&d| d > 0.0), "{shares:?}");
    }

    #[test]
    fn bad_passes_are_refused_before_any_work() {
        let volume = procedural(32, 0.5).unwrap();
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        /// Counts the voxels whose fluence was computed.
        #[derive(Default)]
        struct Work(std::sync::atomic::AtomicU64);
        impl Progress for Work {
            fn advance(&self, steps: u64) {
                self.0
                    .fetch_add(steps, std::sync::atomic::Ordering::Relaxed);
            }
        }
        let work = Work::default();
        let run = |depth, settings: &MarchSettings, frame: &Volume| {
            let settings = MarchSettings {
                scatter_depth: depth,
                ..*settings
            };
            let lgh = Method::Lgh { alpha: 2.0 };
            scatter(&emission, lgh, frame, &medium, &settings, &work).map(|_| ())
        };
        let ok = MarchSettings::default();
        let e = run(17, &ok, &volume).unwrap_err();
        assert!(
            matches!(e, RenderError::InvalidCount { value: 17, .. }),
            "{e}"
        );
        let small = MarchSettings {
            cube_maps: crate::shadow::CubeMapSettings {
                memory_budget: 100_000,
                ..Default::default()
            },
            ..ok
        };
        let e = run(4, &small, &volume).unwrap_err();
        assert!(
            matches!(e, RenderError::ScatterMemory { depth: 4, .. }),
            "{e}"
        );
        let mut moved = volume.clone();
        moved.density.origin += Vec3::splat(0.01);
        assert!(matches!(
            run(1, &ok, &moved).unwrap_err(),
            RenderError::DensityOffGrid
        ));
        assert_eq!(work.0.into_inner(), 0, "no voxel's fluence was computed");
    }

    #[test]
    fn the_memory_plan_covers_what_the_pass_holds() {
        // BYTES_PER_LIGHT plans one vertex of the levels ≥ 1 per light: check it on the
        // procedural explosion's smoke and on a thin scatter of lights (every 5th voxel).
        let volume = procedural(48, 0.5).unwrap();
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let settings = MarchSettings {
            shadows: Shadows::None,
            ..Default::default()
        };
        let s = pass(
            &emission,
            1,
            Method::Lgh { alpha: 2.0 },
            &volume,
            &medium,
            &settings,
        );
        let plan = ScatterPlan::new(&emission, &volume, 1).unwrap();
        assert_eq!(plan.merged_lights, s.lights().lights().len());
        let h = s.lights().hierarchy();
        let vertices: usize = (1..=h.max_level()).map(|l| h.level(l).len()).sum();
        assert!(
            vertices <= h.len(),
            "{vertices} vertices, {} lights",
            h.len()
        );
        let sparse: Vec<usize> = (0..volume.density.data.len()).step_by(5).collect();
        let dark = vec![Vec3::ZERO; sparse.len()];
        let thin = ExplosionLights::at_voxels(&volume.density, sparse, &dark, None).unwrap();
        let h = thin.hierarchy();
        let vertices: usize = (1..=h.max_level()).map(|l| h.level(l).len()).sum();
        assert!(
            vertices <= h.len(),
            "{vertices} vertices, {} lights",
            h.len()
        );
    }

    #[test]
    fn through_a_lighting_cache_depth_one_is_exact_at_its_vertices_and_dense_caches_are_skipped() {
        // Cells two voxels wide on the voxel centres' lattice: an eighth of the voxels are
        // vertices, where the cache holds the coarse levels' fluence computed exactly as the
        // uncached query computes it, and a vertex's own value comes back through the
        // interpolation with weight 1 and a zero offset. What may differ there is the order of
        // the sums (fine and coarse levels apart, then added) and e^{ln L}: a few ulps,
        // relative 1e-5 at most. Between vertices the cache interpolates: those voxels differ
        // (the cache is used), by an amount printed as each depth's power. A cache one voxel
        // apart has no vertex fewer than the voxels: the pass skips it, bit for bit.
        use crate::lighting_cache::{
            CacheMode, CacheSpacing, LightingCacheSettings, ScatteredLight,
        };
        let volume = blob(20);
        let medium = Medium::new(4.0, 6.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let lgh = Method::Lgh { alpha: 2.0 };
        let with = |spacing| {
            let settings = MarchSettings {
                shadows: Shadows::RayMarch,
                lighting_cache: LightingCacheSettings {
                    mode: CacheMode::Coarse,
                    spacing,
                    // Depth 2 at every voxel too, as depth 1: what this test compares.
                    scattered_spacing: 1,
                    scattered_light: ScatteredLight::Merged,
                    ..Default::default()
                },
                ..Default::default()
            };
            pass(&emission, 2, lgh, &volume, &medium, &settings)
        };
        let plain = pass(
            &emission,
            2,
            lgh,
            &volume,
            &medium,
            &MarchSettings::with_shadows(Shadows::RayMarch),
        );
        let (dense, coarse) = (
            with(CacheSpacing::Voxels(1.0)),
            with(CacheSpacing::Voxels(2.0)),
        );
        for depth in 1..=2 {
            let a = plain.intensities(depth).unwrap();
            assert_eq!(
                bits(a),
                bits(dense.intensities(depth).unwrap()),
                "depth {depth}"
            );
        }
        let (a, b) = (
            plain.intensities(1).unwrap(),
            coarse.intensities(1).unwrap(),
        );
        let lit = a.iter().filter(|v| v.max_element() > 0.0).count();
        let same = a
            .iter()
            .zip(b)
            .filter(|(x, y)| {
                x.max_element() > 0.0 && (**x - **y).abs().max_element() <= 1e-5 * x.max_element()
            })
            .count();
        assert!(lit > 1000, "{lit}");
        assert!(10 * same >= lit && same < lit, "{same} of {lit}");
        for depth in 1..=2 {
            let power = |s: &Scattered| s.depths()[depth - 1].power;
            eprintln!(
                "depth {depth}: power {:.6e} uncached, {:.6e} through 2-voxel cells",
                power(&plain),
                power(&coarse)
            );
        }
    }

    #[test]
    fn later_depths_on_a_coarser_grid_are_exact_at_its_vertices_and_the_grid_is_the_next_depth() {
        // Depths ≥ 2 through a cache of every level two voxels apart: at the voxels on its
        // vertices (even indices) the cache returns what it computed there, the fluence of the
        // uncached pass (relative 1e-5: the cache sums levels in another order); between them,
        // it interpolates. The grid of scattered light is depth 2..=n+1's intensities over h³,
        // at every voxel with smoke, n + 1 being what a pass one depth longer computes.
        use crate::lighting_cache::{LightingCacheSettings, ScatteredLight};
        let volume = blob(20);
        let medium = Medium::new(4.0, 6.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let lgh = Method::Lgh { alpha: 2.0 };
        let cache = |scattered_spacing, scattered_light| MarchSettings {
            shadows: Shadows::RayMarch,
            lighting_cache: LightingCacheSettings {
                scattered_spacing,
                scattered_light,
                ..LightingCacheSettings::coarse()
            },
            ..Default::default()
        };
        let run = |depth, spacing, light| {
            pass(
                &emission,
                depth,
                lgh,
                &volume,
                &medium,
                &cache(spacing, light),
            )
        };
        let exact = run(3, 1, ScatteredLight::Merged);
        let coarse = run(2, 2, ScatteredLight::Grid);
        let merged3 = run(3, 2, ScatteredLight::Merged);
        // Depth 1 is the same pass in both.
        assert_eq!(
            bits(exact.intensities(1).unwrap()),
            bits(coarse.intensities(1).unwrap())
        );
        // Depth 2 from the same depth-1 lights: equal on the vertices, not between them.
        let (a, b) = (
            exact.intensities(2).unwrap(),
            coarse.intensities(2).unwrap(),
        );
        let grid = &volume.density;
        let voxels = &exact.lights().voxels().to_vec();
        let (mut on, mut off, mut off_same) = (0, 0, 0);
        for ((x, y), &v) in a.iter().zip(b).zip(voxels) {
            if x.max_element() <= 0.0 {
                continue;
            }
            let close = (*x - *y).abs().max_element() <= 1e-5 * x.max_element();
            if crate::grid::unflatten(v, grid.dims)
                .iter()
                .all(|c| c % 2 == 0)
            {
                assert!(close, "voxel {v}: {x} against {y}");
                on += 1;
            } else {
                off += 1;
                off_same += usize::from(close);
            }
        }
        assert!(
            on > 100 && off > 7 * on / 2 && off_same < off / 2,
            "{on} {off} {off_same}"
        );
        // The grid: depths 2 and 3 of the coarse pass, the third computed for the grid alone.
        let (radiance, report) = coarse.radiance().unwrap();
        assert_eq!(report.depth, 3);
        assert!(exact.radiance().is_none() && coarse.depths().len() == 2);
        let h3 = grid.voxel_size.powi(3);
        let d2 = coarse.intensities(2).unwrap();
        let mut checked = 0;
        for (s, &v) in voxels.iter().enumerate() {
            let got = radiance.voxel(v);
            if grid.data[v] <= 0.0 {
                assert_eq!(got, Vec3::ZERO);
                continue;
            }
            // Depth 3 is not kept as lights: it is what is left over, and it is the depth 3
            // of a pass one depth longer (up to the rounding of the sum and of 1/h³).
            let third = got * h3 - d2[s];
            let want = merged3.intensities(3).unwrap()[s];
            let scale = want.max_element().max(d2[s].max_element());
            assert!(
                (third - want).abs().max_element() <= 1e-5 * scale,
                "voxel {v}: {third} against {want}"
            );
            checked += 1;
        }
        assert!(checked > 1000, "{checked}");
        assert_eq!(report.power, merged3.depths()[2].power);
        // Against the exact chain (every voxel): each cached depth interpolates the one before,
        // so the error compounds. Measured here −0.2% and −0.5% at depths 2 and 3 (blended
        // geometrically, −22% at depth 2: `lighting_cache`); with the paper's point lights, on
        // the Fig. 8-class frame, depths 2-4 lost 0.4%, 0.9%, 1.5%. Bounded at 2% a depth, so
        // that the geometric blend's loss, or one a tenth of it, fails; printed.
        for depth in 2..=3 {
            let (p, q) = (
                exact.depths()[depth - 1].power,
                merged3.depths()[depth - 1].power,
            );
            eprintln!("depth {depth}: power {p:.6e} at every voxel, {q:.6e} two voxels apart");
            assert!(
                (q - p).abs() <= 0.02 * (depth as f64 - 1.0) * p,
                "{q} against {p}"
            );
        }
    }
}
