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
//! (automatic by default: 4, 2 or 1 voxels, at least 9 cells across the smoke,
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

mod fluence;
pub mod lattice;
mod merge;
mod pass;
mod pilot;
mod plan;
mod shares;
mod stop;

use lgh_core::glam::Vec3;

use crate::error::RenderError;
use crate::lights::ExplosionLights;
use crate::medium::{Medium, Volume};
use crate::method::Method;
use crate::progress::{self, Phase, Progress};
use crate::scattered_light::ScatteredRadiance;
use crate::settings::MarchSettings;
use crate::shading::Shading;
use crate::stats::RenderStats;

pub use crate::settings::{check_depth, ScatterTail, MAX_SCATTER_DEPTH};
pub use fluence::CHUNK_VOXELS;
pub use pilot::PILOT_VOXELS;
pub use plan::{ScatterPlan, BYTES_PER_LIGHT};
pub use shares::Shares;
pub use stop::{geometric_tail, shape_change, stop_after, tail_settled};

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
    /// With a geometric tail ([`ScatterTail::Geometric`]): the depths beyond the last, as a
    /// multiple of its lights, which the merged lights include.
    tail_factor: Option<f64>,
}

/// A pass whose first depth was skipped by its pilot: the smoke scatters too little of the
/// emitted light to matter under the skipping share (`--scatter-depth auto`; see
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
    let plan = plan::check_pass(emission, method, frame, settings)?;
    let passes = plan.depth + usize::from(settings.scattered_grid(method));
    let total = (passes * plan.lights_per_depth) as u64;
    progress::phase(progress, Phase::Scattering, total, |p| {
        pass::pass(emission, method, frame, medium, settings, p)
    })
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

    /// Whether the pass was skipped: under a skipping share
    /// ([`scatter_skip`](MarchSettings::scatter_skip), `--scatter-depth auto`), depth 1's
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
    ///     scatter_stop: 0.002,
    ///     scatter_skip: 0.01,
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

    /// With a geometric tail ([`ScatterTail::Geometric`], a pass with a stopping share,
    /// stopped by its rule or at its most depths): the depths beyond the last as a multiple
    /// `r/(1 − r)` of its lights, which the merged lights include ([`geometric_tail`]); `None`
    /// where the tail is dropped, the pass computed a fixed number of depths (no stopping
    /// share), or there is no fall to extend (one scattered depth, light that does not fall,
    /// a depth of negative luminance).
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::scattering::{scatter, ScatterTail};
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
    ///
    /// let volume = procedural::ball(10, 0.7, 3000.0);
    /// let medium = Medium::new(4.0, 0.8, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let auto = MarchSettings {
    ///     shadows: Shadows::None,
    ///     scatter_depth: 16,
    ///     scatter_stop: 0.002,
    ///     ..Default::default()
    /// };
    /// let lgh = Method::Lgh { alpha: 2.0 };
    /// let s = scatter(&emission, lgh, &volume, &medium, &auto, &())?;
    /// let tail = s.tail().expect("a pass with a stopping share, a fall in [0, 1)");
    /// assert!(tail > 0.0 && s.depths().len() < 16);
    /// let dropped = MarchSettings { scatter_tail: ScatterTail::Dropped, ..auto };
    /// assert_eq!(scatter(&emission, lgh, &volume, &medium, &dropped, &())?.tail(), None);
    /// let fixed = MarchSettings { scatter_stop: 0.0, scatter_depth: 3, ..auto };
    /// assert_eq!(scatter(&emission, lgh, &volume, &medium, &fixed, &())?.tail(), None);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn tail(&self) -> Option<f64> {
        self.tail_factor
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
    /// grid: what [`FrameRender::scatter_shares`](crate::FrameRender::scatter_shares) renders.
    /// Each keeps the merged lights' near-field centres (a light's emission centroid times the
    /// emission's share of its light, `crate::voxel_light`), so that the depths' images add up
    /// to the whole: depth 0 is the single-scattering image but where a voxel's scattered light
    /// moves its light's centre (the added voxels are dark, the grid is the emission lights').
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
        self.lights_with(intensities)
    }

    /// The lights of the depths beyond the last alone, the geometric tail ([`tail`](Self::tail)):
    /// the last depth's lights times the tail's factor, on the merged lights' voxels and grid as
    /// [`depth_lights`](Self::depth_lights)' are, so that with them the depths' images add up
    /// to the whole; `None` without a tail.
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::scattering::scatter;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method, Shadows};
    ///
    /// let volume = procedural::ball(10, 0.7, 3000.0);
    /// let medium = Medium::new(4.0, 0.8, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let settings = MarchSettings {
    ///     shadows: Shadows::None,
    ///     scatter_depth: 16,
    ///     scatter_stop: 0.002,
    ///     ..Default::default()
    /// };
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
    /// let (n, f) = (s.depths().len(), s.tail().unwrap() as f32);
    /// let tail = s.tail_lights()?.unwrap();
    /// for (l, &last) in tail.lights().iter().zip(s.intensities(n).unwrap()) {
    ///     assert_eq!(l.intensity, last * f);
    /// }
    /// let fixed = MarchSettings { scatter_stop: 0.0, scatter_depth: 2, ..settings };
    /// let s = scatter(&emission, Method::Lgh { alpha: 2.0 }, &volume, &medium, &fixed, &())?;
    /// assert!(s.tail_lights()?.is_none());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn tail_lights(&self) -> Result<Option<ExplosionLights>, RenderError> {
        merge::tail_intensities(&self.per_depth, self.tail_factor)
            .map(|tail| self.lights_with(&tail))
            .transpose()
    }

    /// The merged lights with `intensities` in place of theirs.
    fn lights_with(&self, intensities: &[Vec3]) -> Result<ExplosionLights, RenderError> {
        let mut lights = self.merged.clone();
        lights.set_intensities(intensities)?;
        debug_assert_eq!(lights.hierarchy().max_level(), self.max_level);
        Ok(lights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::{ShadowGrid, Shadows};

    /// A ball of smoke with a hot core (up to 2500 K inside radius 0.35), `n³` voxels.
    pub(super) fn blob(n: usize) -> Volume {
        crate::procedural::ball(n, 0.35, 2500.0)
    }

    pub(super) fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
        v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
    }

    /// The pass of `depth` with `settings` and no progress.
    pub(super) fn pass(
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
    fn the_scattered_depths_grid_keeps_the_second_depths_power_at_every_voxel() {
        // Depth 2 through the cache of every level four voxels apart against the same pass at
        // every voxel (`scattered_spacing` 1), on a ball of smoke of up to about 0.2 and 0.4
        // optical depths a voxel. The grid keeps level 0's far light and each voxel sums its
        // near part (`Level0Form::FarLight`), so the light that follows each voxel's smoke is
        // not lost between the vertices. Measured (printed): 0.996 and 1.049 of the pass at
        // every voxel; with level 0 interpolated whole, as the grid kept it before, 1.111 and
        // 1.257 — here the linear blend of corners extrapolated through dense smoke is bright,
        // on the smoky64 fire it lost 7% (lighting_cache's module docs). Denser, the far light
        // over-lights too (1.17 at 0.8 optical depths a voxel, against 1.66). Bounds 2% and 8%.
        use crate::lighting_cache::{CacheMode, LightingCacheSettings};
        let volume = blob(32);
        for (ka, ks, bound) in [(1.0, 1.5, 0.02), (2.0, 3.0, 0.08)] {
            let medium = Medium::new(ka, ks, 1e-4, 1000.0).unwrap();
            let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
            let power = |scattered_spacing| {
                let settings = MarchSettings {
                    shadows: Shadows::RayMarch,
                    lighting_cache: LightingCacheSettings {
                        mode: CacheMode::Coarse,
                        scattered_spacing,
                        ..Default::default()
                    },
                    ..Default::default()
                };
                let lgh = Method::Lgh { alpha: 2.0 };
                let pass = pass(&emission, 2, lgh, &volume, &medium, &settings);
                (pass.depths()[1].power, pass.spacing)
            };
            let ((every, one), (grid, four)) = (power(1), power(4));
            assert_eq!((one, four), (1, 4));
            let ratio = grid / every;
            eprintln!(
                "κ_a {ka}: depth 2 on the grid four voxels apart, {ratio:.4} of every voxel's"
            );
            assert!((ratio - 1.0).abs() < bound, "κ_a {ka}: {ratio}");
        }
    }

    #[test]
    fn coarse_lights_shadowed_as_volume_lights_keep_the_first_depth_near_brute_force() {
        // The demo's explosion at 64³ (thin fire in a shell of soot) in Blender's model, σ_t =
        // 4ρ, albedo 0.7 (the Cycles comparison's explosion64): the first scattered depth's
        // power through the hierarchy at α = 2 against brute force over the same lights, with
        // ray-marched shadows. Coarse lights shadowed as points (`RayMarch`) let more light
        // through than their lights do; as the volume lights of eq. 6 — the reference model
        // (`RayMarchVolumes`) and its cone-stepped form (`Volumes`) — the power is near brute
        // force's. Measured (printed): points +3.2%, reference +0.37%, cone +0.76% (before the
        // voxel lights' escape through their smoke +3.3%, +0.44%, +0.84%; the CLI on the same
        // volume read from its Z-up VDB then: +3.4%, +0.4%, +0.7%; 128³ against α = 8: +3.3%,
        // +0.3%, +0.8%); the bounds leave about 40% of room.
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
        // stay non-negative: ≤ k (N + 12) u at depth k. (From depth 2 the lattice kernel adds
        // a second sum over the lights within two voxels, its voxel's own term negative but
        // a third of that light's: the same bound holds with room.)
        let u = f64::from(f32::EPSILON) / 2.0;
        let n = voxels.len() as f64;
        let mut worst = 0.0f64;
        let centroids: Vec<Vec3> = voxels
            .iter()
            .map(|&w| volume.cell_centroid(&medium, w) * h as f32)
            .collect();
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
                    // their light's escape through the smoke of their own voxel or x's,
                    // the thinner (`Lights::with_smoke`).
                    let tau = medium.extinction(d.data[w].min(rho)) * h as f32;
                    // Depth 1's lights, the emission's, have their near field centred where
                    // their cell emits; the scattered depths' on their voxel.
                    let centroid = if k == 1 { centroids[q] } else { Vec3::ZERO };
                    let g = NearField::Voxel.falloff_in(0, x.distance(p + centroid), h as f32, tau);
                    let g = f64::from(g);
                    let vis = f64::from(grid.transmittance(x, p).0);
                    // From depth 2, the lights within two voxels at the cell's mean: their
                    // term in the table's uniform smoke, `(Q − 1) e^{−σ_t d}` (`lattice`).
                    let dist = x.distance(p);
                    let cell_mean = if k >= 2 && dist < lattice::REACH_VOXELS * h as f32 {
                        let sigma_t = medium.extinction(rho);
                        let q = lattice::Corrections::at(sigma_t * h as f32);
                        f64::from(q.weight(dist, h as f32) * (-sigma_t * dist).exp())
                    } else {
                        0.0
                    };
                    for c in 0..3 {
                        sum[c] += previous[q][c] * (vis + cell_mean) * g;
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
}
