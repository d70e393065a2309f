//! What a frame's render is asked to do: the march's steps and cut-off, the shadows and how
//! cube maps are traced, and how many depths of scattered light (paper Sec. 5) come first —
//! checked before any work.

use lgh_core::glam::Vec3;

use crate::error::{check_setting, RenderError};
use crate::lighting_cache::LightingCacheSettings;
use crate::method::Method;
use crate::shadow::{CubeMapSettings, Shadows};

/// The deepest scattering the pass accepts (`--scatter-depth`): the paper's Fig. 7 uses 4, and
/// each depth costs a hierarchy, its shadows and a fluence pass over the smoke, while the light
/// it adds shrinks like `albedo^k`.
pub const MAX_SCATTER_DEPTH: usize = 16;

/// The most camera rays a pixel's side takes ([`MarchSettings::pixel_samples`]): 8 × 8 = 64 a
/// pixel, where the box filter's own error is far below a hierarchy's.
pub const MAX_PIXEL_SAMPLES: usize = 8;

/// How many times finer a side an adaptively refined pixel is sampled
/// ([`PixelRefinement::Adaptive`]): two. The midpoint rule's nodes of `n` and `2n` rays a side
/// do not coincide, so a refined pixel marches its `2n × 2n` rays anew (`4n²` more than a
/// factor of three, under which the first rays are among the finer filter's, would spend on
/// `8n²` new ones). On the dev fire at 128² against Cycles 3.4.1 (docs/cycles.md, "Adaptive
/// pixels"), where all of the fire's pixels refine, three (2 × 2 → 6 × 6) and two (→ 4 × 4)
/// gave the same error to the eye in about two thirds of the time with two; that document's
/// table holds the measured errors and speed-ups, each with the commit that made it.
pub const REFINEMENT: usize = 2;

/// The rule adaptive pixels' first rays a side are held to (`MAX_PIXEL_SAMPLES / REFINEMENT`).
pub(crate) const ADAPTIVE_FIRST_RULE: &str =
    "must be 1 to 4 a side (refined twice as fine, at most 8)";

/// Where a pixel takes more camera rays than [`MarchSettings::pixel_samples`] a side.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum PixelRefinement {
    /// Every pixel takes `n × n` rays (`n` = [`MarchSettings::pixel_samples`]).
    #[default]
    Uniform,
    /// Every pixel takes `n × n` rays first. Then a pixel where one of them differs from a
    /// neighbouring ray — the next on the image's grid of rays, `n` times finer than its pixels,
    /// in the pixel or across its border — by more than `tolerance` times the mean luminance
    /// of all those first rays takes `2n × 2n` ([`REFINEMENT`]): it is the pixel of
    /// `pixel_samples: 2n`, bit for bit. Thin flames are filtered as
    /// the finer box filter would, at the cost of the finer filter only where the image varies
    /// within a pixel; deterministic, no noise. It needs the whole image (the mean and the
    /// neighbours): a render of some pixels only refuses it.
    Adaptive {
        /// The luminance difference between neighbouring rays that refines a pixel, as a
        /// share of the image's mean luminance (at least 0; 0 refines every pixel whose rays
        /// differ at all).
        tolerance: f32,
    },
}

impl PixelRefinement {
    /// The rays a side of a refined pixel where the first take `n` a side: `2n` adaptively,
    /// else `n`.
    ///
    /// ```
    /// use lgh_volume::render::PixelRefinement;
    ///
    /// assert_eq!(PixelRefinement::Uniform.refined(2), 2);
    /// assert_eq!(PixelRefinement::Adaptive { tolerance: 0.05 }.refined(2), 4);
    /// ```
    #[must_use]
    pub fn refined(&self, n: usize) -> usize {
        match self {
            PixelRefinement::Uniform => n,
            PixelRefinement::Adaptive { .. } => REFINEMENT * n,
        }
    }
}

/// The largest footprint of a sub-pixel at the volume, in voxels, under
/// [`auto_pixel_samples`]. Below about a voxel a pixel's radiance varies over the pixel and its
/// centre is not its mean (Cycles' box filter): on the demo's explosion at 128³ seen at 128²
/// (a pixel 1.45 voxels wide) pixel centres err by 13.5% from converged Cycles 3.4.1, 2 × 2
/// rays (sub-pixels 0.73 voxel wide) by 4.9%, 4 × 4 (0.36) by 4.3% (docs/cycles.md; against
/// its reference image): most of the filter's gain is had at three quarters of a voxel.
pub const AUTO_SUBPIXEL_VOXELS: f32 = 0.75;

/// The width of a pixel of `camera`'s image at `centre`, in voxels of `voxel_size`: the angle
/// between the rays through the image centre's neighbouring pixels times the distance from the
/// eye.
///
/// ```
/// use lgh_volume::lgh_core::glam::Vec3;
/// use lgh_volume::render::{pixel_footprint, Camera, Framing};
///
/// // 40° over 720 rows, 4 units away: 0.0040 units, a quarter of a voxel of 1/64.
/// let camera = Camera::look_at(Vec3::new(0.0, -4.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0, 720, 720)?;
/// assert!((pixel_footprint(&camera, Vec3::ZERO, 1.0 / 64.0) - 0.259).abs() < 1e-3);
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
#[must_use]
pub fn pixel_footprint(
    camera: &crate::camera::Camera,
    centre: lgh_core::glam::Vec3,
    voxel_size: f32,
) -> f32 {
    let (x, y) = (0.5 * camera.width() as f32, 0.5 * camera.height() as f32);
    let angle = (camera.direction(x + 0.5, y) - camera.direction(x - 0.5, y)).length();
    angle * (centre - camera.eye()).length() / voxel_size
}

/// The fewest rays a pixel side, at most 4, for which a sub-pixel of `camera`'s image covers
/// at most [`AUTO_SUBPIXEL_VOXELS`] of a voxel of `voxel_size` at `centre` (the volume's
/// middle; [`pixel_footprint`]): `lgh explosion --pixel-samples auto`.
///
/// ```
/// use lgh_volume::lgh_core::glam::Vec3;
/// use lgh_volume::render::{auto_pixel_samples, Camera, Framing};
///
/// let camera = |side| Camera::look_at(Vec3::new(0.0, -4.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0, side, side);
/// // The comparison's explosion: 128³ over [−1, 1]³ (h = 1/64), 4 units away, 40°.
/// assert_eq!(auto_pixel_samples(&camera(128)?, Vec3::ZERO, 1.0 / 64.0), 2); // 1.45 voxels a pixel
/// assert_eq!(auto_pixel_samples(&camera(128)?, Vec3::ZERO, 1.0 / 32.0), 1); // 64³: 0.73
/// assert_eq!(auto_pixel_samples(&camera(720)?, Vec3::ZERO, 1.0 / 64.0), 1); // 0.26
/// assert_eq!(auto_pixel_samples(&camera(16)?, Vec3::ZERO, 1.0 / 64.0), 4); // at most 4
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
#[must_use]
pub fn auto_pixel_samples(
    camera: &crate::camera::Camera,
    centre: lgh_core::glam::Vec3,
    voxel_size: f32,
) -> usize {
    rays_a_side(
        pixel_footprint(camera, centre, voxel_size),
        AUTO_SUBPIXEL_VOXELS,
        4,
    )
}

/// The fewest rays a pixel side, at most `max`, for which a sub-pixel of a pixel `footprint`
/// voxels wide covers at most `sub_pixel` voxels; 1 where that is not a finite count.
fn rays_a_side(footprint: f32, sub_pixel: f32, max: usize) -> usize {
    let n = (footprint / sub_pixel).ceil();
    if n.is_finite() && n >= 1.0 {
        (n as usize).min(max)
    } else {
        1
    }
}

/// The largest footprint of an emission sub-pixel at the volume, in voxels, under
/// [`auto_emission_samples`]: a quarter of a voxel. The blackbody's emission is steep in the
/// temperature, so a thin flame's emission varies well below a voxel where the scattered light
/// does not. Measured at 128² against converged Cycles 3.4.1 (docs/cycles.md, "Emission rays
/// apart"): the dev fire (1.1 voxels a pixel) errs by 2.2 / 1.14 / 0.83 / 0.73 / 0.76% with 2 /
/// 3 / 4 / 5 / 6 emission rays a side, its scattered light at one ray a pixel; fire64 and
/// smoky64 (half a voxel to three quarters a pixel across the fire) gain nothing beyond two or
/// three.
pub const AUTO_EMISSION_SUBPIXEL_VOXELS: f32 = 0.25;

/// The fewest emission rays a pixel side ([`MarchSettings::emission_samples`]), at least
/// `pixel_samples` and at most [`MAX_PIXEL_SAMPLES`], for which an emission sub-pixel of
/// `camera`'s image covers at most [`AUTO_EMISSION_SUBPIXEL_VOXELS`] of a voxel of
/// `voxel_size` at `centre` ([`pixel_footprint`]): `lgh explosion --emission-samples auto`.
///
/// ```
/// use lgh_volume::lgh_core::glam::Vec3;
/// use lgh_volume::render::{auto_emission_samples, Camera, Framing};
///
/// let camera = |side| Camera::look_at(Vec3::new(0.0, -4.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0, side, side);
/// // 128³ over [−1, 1]³ (h = 1/64) at 128²: 1.45 voxels a pixel, six a side.
/// assert_eq!(auto_emission_samples(&camera(128)?, Vec3::ZERO, 1.0 / 64.0, 2), 6);
/// // At 720² a pixel is 0.26 voxel: two a side; never fewer than the pixel samples.
/// assert_eq!(auto_emission_samples(&camera(720)?, Vec3::ZERO, 1.0 / 64.0, 1), 2);
/// assert_eq!(auto_emission_samples(&camera(720)?, Vec3::ZERO, 1.0 / 64.0, 3), 3);
/// // At most 8.
/// assert_eq!(auto_emission_samples(&camera(16)?, Vec3::ZERO, 1.0 / 64.0, 1), 8);
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
#[must_use]
pub fn auto_emission_samples(
    camera: &crate::camera::Camera,
    centre: lgh_core::glam::Vec3,
    voxel_size: f32,
    pixel_samples: usize,
) -> usize {
    let footprint = pixel_footprint(camera, centre, voxel_size);
    rays_a_side(footprint, AUTO_EMISSION_SUBPIXEL_VOXELS, MAX_PIXEL_SAMPLES).max(pixel_samples)
}

/// `depth` if it is at most [`MAX_SCATTER_DEPTH`], else [`RenderError::InvalidCount`]: checked
/// before any work.
///
/// ```
/// use lgh_volume::scattering::check_depth;
///
/// assert_eq!(check_depth(4)?, 4);
/// assert_eq!(
///     check_depth(17).unwrap_err().to_string(),
///     "scatter depth 17 must be 0 to 16"
/// );
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
pub fn check_depth(depth: usize) -> Result<usize, RenderError> {
    if depth > MAX_SCATTER_DEPTH {
        return Err(RenderError::InvalidCount {
            name: "scatter depth",
            value: depth,
            rule: "must be 0 to 16",
        });
    }
    Ok(depth)
}

/// Ray-marching parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchSettings {
    /// Step along camera rays, in voxels.
    pub step_voxels: f32,
    /// Step along shadow rays, in voxels.
    pub shadow_step_voxels: f32,
    /// Camera rays stop when their transmittance falls below this; a light whose shadow-ray
    /// transmittance falls below it counts as hidden (each drops at most this fraction of what
    /// it cuts off).
    pub min_transmittance: f32,
    /// Shadowing of the lights.
    pub shadows: Shadows,
    /// How cube maps are traced (with `shadows: CubeMap` and a hierarchy).
    pub cube_maps: CubeMapSettings,
    /// Depths of scattered light (paper Sec. 5) a [`FrameRender`](crate::FrameRender) computes
    /// before it renders: 0 is single scattering; `n` adds lights for light scattered `1..=n`
    /// times, so paths of up to `n + 1` scattering events (the paper's Fig. 7 uses 4). At most
    /// [`MAX_SCATTER_DEPTH`].
    pub scatter_depth: usize,
    /// Stop the scattering pass before `scatter_depth` when the next depth would add less than
    /// this share of the light so far ([`crate::scattering::stop_after`]); 0 computes every
    /// depth asked for.
    pub scatter_stop: f32,
    /// Skip the whole scattering pass when a pilot sample of the voxels predicts that its first
    /// depth would add less than this share of the emitted light
    /// ([`crate::scattering::PILOT_VOXELS`]); 0 runs no pilot. Apart from `scatter_stop`: the
    /// stopping rule weighs the next depth alone while the depths it leaves out hold about
    /// `1/(1 − r)` times it (`r` the steady fall a depth, 0.66 in the demo's explosion), so it
    /// needs a smaller share than the skip, whose first depth in smoke that scatters almost
    /// nothing is nearly all the scattered light.
    pub scatter_skip: f32,
    /// What a pass with a stopping share (`scatter_stop`) does with the depths beyond its
    /// last, whether its rule stopped it or it reached `scatter_depth`: adds them as a
    /// geometric series (the default, which then stops when that series has settled,
    /// [`crate::scattering::tail_settled`]) or leaves them out. No effect without a stopping
    /// share: a fixed number of depths is the paths of that many events.
    pub scatter_tail: ScatterTail,
    /// Whether the hierarchy's coarse levels are shaded through a lighting cache
    /// ([`crate::lighting_cache`]; the hierarchy only, none by default).
    pub lighting_cache: LightingCacheSettings,
    /// Camera rays per side of a pixel: `n × n` rays through the centres of an `n × n` grid of
    /// sub-pixels, averaged: the midpoint rule for the integral of the radiance over the pixel,
    /// i.e. a one-pixel box filter (Cycles' "Box" filter of width 1), without noise. 1 (the
    /// default) is the pixel's centre. At most [`MAX_PIXEL_SAMPLES`].
    pub pixel_samples: usize,
    /// Where pixels take more rays than [`pixel_samples`](Self::pixel_samples) a side: nowhere
    /// (the default) or where neighbouring rays differ.
    pub pixel_refinement: PixelRefinement,
    /// Camera rays per side of a pixel for the emission alone — what the fire emits along the
    /// ray and the smoke lets through — where it is more than
    /// [`pixel_samples`](Self::pixel_samples): then each pixel is the box filter of
    /// `emission_samples²` rays that march the emission alone plus that of `pixel_samples²`
    /// rays that march the light the smoke scatters (and the surfaces and background behind
    /// it), rather than `pixel_samples²` rays that march both. At most `pixel_samples` (1, the
    /// default, always is), every ray marches both. A thin flame's emission varies far below a
    /// voxel — the blackbody `j(T)` is steep in `T` — while the scattered light varies as the
    /// smoke does, and an emission ray reads no light: on the dev fire at 128² it costs about a
    /// tenth of a ray that shades the smoke (1.5 µs against 15 µs; docs/cycles.md, "Emission
    /// rays apart"); [`auto_emission_samples`] chooses it from the pixel's footprint. At most
    /// [`MAX_PIXEL_SAMPLES`]; with [`PixelRefinement::Adaptive`], which refines both together,
    /// at most `pixel_samples`.
    pub emission_samples: usize,
    /// Radiance (linear RGB) seen where a camera ray leaves the scene without meeting a
    /// surface, times the ray's transmittance through the smoke: a constant world behind the
    /// volume (Blender's world colour × strength). It lights nothing. Black by default; a ray
    /// cut off below [`min_transmittance`](Self::min_transmittance) sees none of it.
    pub background: Vec3,
}

impl MarchSettings {
    /// Checks the settings: steps of 0.01 to 64 voxels, a cut-off in [0, 1), a scattering depth
    /// of at most [`MAX_SCATTER_DEPTH`].
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    ///
    /// assert!(MarchSettings::default().check().is_ok());
    /// let bad = MarchSettings { step_voxels: 100.0, ..Default::default() };
    /// assert_eq!(
    ///     bad.check().unwrap_err().to_string(),
    ///     "march settings: step 100 must be 0.01 to 64 voxels"
    /// );
    /// ```
    pub fn check(&self) -> Result<(), RenderError> {
        for (name, v) in [
            ("march settings: step", self.step_voxels),
            ("march settings: shadow step", self.shadow_step_voxels),
        ] {
            check_setting(
                (0.01..=64.0).contains(&v),
                name,
                v,
                "must be 0.01 to 64 voxels",
            )?;
        }
        check_setting(
            (0.0..1.0).contains(&self.min_transmittance),
            "march settings: minimum transmittance",
            self.min_transmittance,
            "must be in [0, 1)",
        )?;
        check_depth(self.scatter_depth)?;
        check_setting(
            (0.0..1.0).contains(&self.scatter_stop),
            "march settings: scattering stop",
            self.scatter_stop,
            "must be a share in [0, 1)",
        )?;
        check_setting(
            (0.0..1.0).contains(&self.scatter_skip),
            "march settings: scattering skip",
            self.scatter_skip,
            "must be a share in [0, 1)",
        )?;
        if !(self.background.is_finite() && self.background.min_element() >= 0.0) {
            return Err(RenderError::InvalidBackground {
                radiance: self.background,
            });
        }
        if !(1..=MAX_PIXEL_SAMPLES).contains(&self.pixel_samples) {
            return Err(RenderError::InvalidCount {
                name: "pixel samples",
                value: self.pixel_samples,
                rule: "must be 1 to 8 a side",
            });
        }
        if !(1..=MAX_PIXEL_SAMPLES).contains(&self.emission_samples) {
            return Err(RenderError::InvalidCount {
                name: "emission samples",
                value: self.emission_samples,
                rule: "must be 1 to 8 a side",
            });
        }
        if let PixelRefinement::Adaptive { tolerance } = self.pixel_refinement {
            if self.emission_samples > self.pixel_samples {
                return Err(RenderError::InvalidCount {
                    name: "emission samples with adaptive pixels",
                    value: self.emission_samples,
                    rule: "must be at most the pixel samples (adaptive pixels refine the \
                           emission with the light)",
                });
            }
            check_setting(
                tolerance.is_finite() && tolerance >= 0.0,
                "march settings: adaptive pixel tolerance",
                tolerance,
                "must be a share of the mean luminance, at least 0",
            )?;
            if self.pixel_refinement.refined(self.pixel_samples) > MAX_PIXEL_SAMPLES {
                return Err(RenderError::InvalidCount {
                    name: "pixel samples refined adaptively",
                    value: self.pixel_samples,
                    rule: ADAPTIVE_FIRST_RULE,
                });
            }
        }
        self.lighting_cache.check()?;
        Ok(())
    }

    /// Whether a render through `method` takes the scattered light in as a grid
    /// ([`crate::scattered_light`]): scattered depths asked for, the lighting cache's
    /// [`scattered_grid`](LightingCacheSettings::scattered_grid), the hierarchy (the cache's
    /// only method), and shadows that every light set shares (ray-marched or none; cube maps
    /// and their model are made for one light set's hierarchy).
    ///
    /// ```
    /// use lgh_volume::lighting_cache::{LightingCacheSettings, ScatteredLight};
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::{Method, Shadows};
    ///
    /// let lgh = Method::Lgh { alpha: 2.0 };
    /// let grid = LightingCacheSettings { scattered_light: ScatteredLight::Grid, ..LightingCacheSettings::coarse() };
    /// let cached = MarchSettings { scatter_depth: 4, lighting_cache: grid, ..Default::default() };
    /// assert!(cached.scattered_grid(lgh));
    /// assert!(!cached.scattered_grid(Method::Brute));
    /// assert!(!MarchSettings { shadows: Shadows::CubeMap, ..cached }.scattered_grid(lgh));
    /// assert!(!MarchSettings { scatter_depth: 0, ..cached }.scattered_grid(lgh));
    /// ```
    #[must_use]
    pub fn scattered_grid(&self, method: Method) -> bool {
        self.scatter_depth > 0
            && self.lighting_cache.scattered_grid()
            && matches!(method, Method::Lgh { .. })
            && matches!(self.shadows, Shadows::RayMarch | Shadows::None)
    }

    /// The default march with `shadows`.
    ///
    /// ```
    /// use lgh_volume::render::MarchSettings;
    /// use lgh_volume::Shadows;
    ///
    /// let maps = MarchSettings::with_shadows(Shadows::CubeMap);
    /// assert_eq!(maps.shadows, Shadows::CubeMap);
    /// assert_eq!(maps.step_voxels, MarchSettings::default().step_voxels);
    /// ```
    #[must_use]
    pub fn with_shadows(shadows: Shadows) -> Self {
        MarchSettings {
            shadows,
            ..Default::default()
        }
    }
}

/// What a pass with a stopping share does with the depths beyond its last, whether its rule
/// stopped it or it reached its most depths (`--scatter-tail`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ScatterTail {
    /// Left out: the image holds the depths computed, and the rule's share bounds what it
    /// loses ([`stop_after`](crate::scattering::stop_after)).
    Dropped,
    /// Added as a geometric series: each depth scatters the one before through the same
    /// smoke, so once the fall a depth `r = P_k/P_{k−1}` has settled, the depths beyond `n`
    /// are `r^j` times depth `n`'s light and its voxels' shares those of depth `n` (the
    /// transport's dominant eigenfunction, which the depths approach: the Neumann series'
    /// tail). Their sum is depth `n`'s lights times
    /// [`geometric_tail`](crate::scattering::geometric_tail)'s `r/(1 − r)`; the pass stops
    /// when that sum, taken with the last fall and with the one before, differs by less than
    /// the stopping share of the light so far
    /// ([`tail_settled`](crate::scattering::tail_settled)); where the rule has not settled
    /// the fall, the medium's albedo bounds it. On the dense
    /// fire smoky128 (Blender's Quick Smoke, 128 cells) the falls are 0.600, 0.603, 0.606,
    /// 0.609, … a depth: the tail from depth 5 holds 0.078 (depth 1: 0.375) where depths 6
    /// to 10 and the rest hold 0.079, and the pass computes 5 depths instead of 10. Where the
    /// albedo bounds an unsettled fall that the model exceeds (smoke without shadows, which
    /// does not conserve energy), the tail is the exact transport's bound, not the model's own
    /// depths beyond `n`.
    #[default]
    Geometric,
}

impl ScatterTail {
    /// The name on the command line (`dropped`, `geometric`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ScatterTail::Dropped => "dropped",
            ScatterTail::Geometric => "geometric",
        }
    }
}

impl Default for MarchSettings {
    fn default() -> Self {
        MarchSettings {
            step_voxels: 1.0,
            shadow_step_voxels: 1.0,
            min_transmittance: 1e-3,
            shadows: Shadows::RayMarch,
            cube_maps: CubeMapSettings::default(),
            scatter_depth: 0,
            scatter_stop: 0.0,
            scatter_skip: 0.0,
            scatter_tail: ScatterTail::Geometric,
            lighting_cache: LightingCacheSettings::default(),
            pixel_samples: 1,
            pixel_refinement: PixelRefinement::Uniform,
            emission_samples: 1,
            background: Vec3::ZERO,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule's words are written by hand (a `const` cannot be formatted): they must say the
    /// constants they stand for.
    #[test]
    fn the_adaptive_rule_says_its_constants() {
        let times = match REFINEMENT {
            2 => "twice".to_string(),
            n => format!("{n} times"),
        };
        let rule = format!(
            "must be 1 to {} a side (refined {times} as fine, at most {MAX_PIXEL_SAMPLES})",
            MAX_PIXEL_SAMPLES / REFINEMENT
        );
        assert_eq!(ADAPTIVE_FIRST_RULE, rule);
    }
}
