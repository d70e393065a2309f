//! The camera and the volume ray marcher (ARCHITECTURE.md, "lgh-volume"; paper Sec. 6.1).
//!
//! A camera ray marches the smoke from where it enters the grid's box; each step of length `dt`
//! adds `T · σ_s/(4π) Σ_lights V·g·B·I · (1 − e^{−σ_t dt}) / σ_t` — the exact integral over a
//! step whose medium is constant (evaluated at the step's midpoint) — plus `T` times the
//! emission `j` at the step's two Gauss nodes, each weighed by what the step's smoke lets
//! through from it ([`crate::step_emission`]: exact for an emission linear along the step), and
//! multiplies the transmittance `T` by `e^{−σ_t dt}`, until `T` is negligible. The sum over lights is
//! [`Lights::incident`], through any [`ManyLights`] backend, with the [`Visibility`] the
//! [`Marcher`] built from its settings.
//!
//! Every renderer of the crate (this marcher, the path tracer) computes its pixels through one
//! loop, [`shade_pixels`]: rows in parallel, each pixel independent, so no result depends on the
//! thread count.

use lgh_core::glam::Vec3;
use lgh_core::{LightSample, ManyLights, ShadingPoint};
use lgh_image::Image;
use rayon::prelude::*;

use crate::error::RenderError;
use crate::lighting::{LightScratch, Lights};
use crate::lighting_cache::CachedLights;
use crate::medium::{Medium, Volume};
use crate::occupancy::Occupancy;
use crate::progress::{self, Phase, Progress};
use crate::scattered_light::ScatteredRadiance;
pub use crate::shadow::Shadows;
use crate::shadow::Visibility;
use crate::step_emission;
use crate::surfaces::{SurfaceHit, Surfaces};

pub use crate::camera::{check_image_size, Camera, Framing, Up, MAX_IMAGE_SIDE};
pub use crate::pixel_refinement::pixels_to_refine;
use crate::settings::ADAPTIVE_FIRST_RULE;
pub use crate::settings::{
    auto_emission_samples, auto_pixel_samples, pixel_footprint, MarchSettings, PixelRefinement,
    AUTO_EMISSION_SUBPIXEL_VOXELS, AUTO_SUBPIXEL_VOXELS, MAX_PIXEL_SAMPLES, REFINEMENT,
};
pub use crate::stats::RenderStats;

/// A frame ready to march: the volume, its medium, the checked settings and the visibility they
/// ask for, built once. The state is consistent by construction: nothing can change the
/// settings without building the visibility anew (make another `Marcher`).
pub struct Marcher<'a> {
    volume: &'a Volume,
    medium: &'a Medium,
    settings: MarchSettings,
    visibility: Visibility,
    /// Opaque surfaces the camera rays stop at ([`with_surfaces`](Self::with_surfaces)).
    surfaces: Option<&'a dyn Surfaces>,
    /// The bricks of the box where a sample finds no smoke and no emission, skipped.
    occupancy: Occupancy,
}

impl<'a> Marcher<'a> {
    /// Prepares `volume` in `medium` for marching with `settings` (checked), building the
    /// visibility `settings.shadows` asks for.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{BruteForce, PointLight};
    /// use lgh_volume::{procedural, Lights, Medium};
    /// use lgh_volume::render::{MarchSettings, Marcher, RenderStats};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let marcher = Marcher::new(&volume, &medium, &MarchSettings::default())?;
    /// // One light at the centre, shadows ray-marched: radiance along a ray through it.
    /// let lights = Lights::new(BruteForce::new(&[PointLight::new(Vec3::ZERO, Vec3::ONE)])?, 0.05);
    /// let l = marcher.march(&lights, Vec3::new(0.0, 0.0, 3.0), -Vec3::Z, &mut RenderStats::default())?;
    /// assert!(l.max_element() > 0.0);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn new(
        volume: &'a Volume,
        medium: &'a Medium,
        settings: &MarchSettings,
    ) -> Result<Self, RenderError> {
        settings.check()?;
        let visibility = Visibility::new(
            settings.shadows,
            volume,
            medium,
            settings.shadow_step_voxels,
            settings.min_transmittance,
        );
        Marcher::with_visibility(volume, medium, settings, visibility)
    }

    /// [`new`](Self::new) with a visibility made for the lights it will shade (the cube maps
    /// of a hierarchy: [`FrameRender`](crate::FrameRender) ties the two) instead of the one
    /// `settings.shadows` asks for.
    pub(crate) fn with_visibility(
        volume: &'a Volume,
        medium: &'a Medium,
        settings: &MarchSettings,
        visibility: Visibility,
    ) -> Result<Self, RenderError> {
        settings.check()?;
        Ok(Marcher {
            occupancy: occupancy(volume, medium, settings),
            volume,
            medium,
            settings: MarchSettings {
                shadows: visibility.shadows(),
                ..*settings
            },
            visibility,
            surfaces: None,
        })
    }

    /// The same marcher with opaque `surfaces` behind and around the smoke (a ground, a room:
    /// [`crate::surfaces`]): a camera ray stops at the first one, which adds its reflected
    /// light through the smoke in front of it.
    #[must_use]
    pub fn with_surfaces(mut self, surfaces: &'a dyn Surfaces) -> Self {
        self.surfaces = Some(surfaces);
        self
    }

    /// Renders the image of `camera` with single scattering from `lights`, rows in parallel (each
    /// pixel is independent and the counts are integer sums, so neither depends on the thread
    /// count); `progress` hears [`Phase::Render`] over rows, then, with adaptive pixels
    /// ([`PixelRefinement::Adaptive`]), [`Phase::Refinement`] over the pixels refined.
    pub fn render<B: ManyLights + Sync>(
        &self,
        lights: &Lights<B>,
        camera: &Camera,
        progress: &dyn Progress,
    ) -> Result<(Image, RenderStats), RenderError> {
        self.render_lit(Lit::lights(Some(lights)), camera, progress)
    }

    /// [`render`](Self::render), emission alone without `lights`.
    pub(crate) fn render_lit<B: ManyLights + Sync>(
        &self,
        lights: Lit<'_, B>,
        camera: &Camera,
        progress: &dyn Progress,
    ) -> Result<(Image, RenderStats), RenderError> {
        let (pixels, stats) = march_pixels(self, lights, camera, None, progress)?;
        Ok((image(camera, pixels.into_iter()), stats))
    }

    /// The pixels `(x, y)` of `pixels` only, exactly as [`render`](Self::render) computes them,
    /// in parallel: for references and benchmarks on pixel subsets. Pixels outside the image are
    /// an error.
    pub fn render_pixels<B: ManyLights + Sync>(
        &self,
        lights: &Lights<B>,
        camera: &Camera,
        pixels: &[[usize; 2]],
    ) -> Result<(Vec<Vec3>, RenderStats), RenderError> {
        self.render_pixels_lit(Lit::lights(Some(lights)), camera, pixels)
    }

    /// [`render_pixels`](Self::render_pixels), emission alone without `lights`.
    pub(crate) fn render_pixels_lit<B: ManyLights + Sync>(
        &self,
        lights: Lit<'_, B>,
        camera: &Camera,
        pixels: &[[usize; 2]],
    ) -> Result<(Vec<Vec3>, RenderStats), RenderError> {
        march_pixels(self, lights, camera, Some(pixels), &())
    }

    /// The volume.
    #[must_use]
    pub fn volume(&self) -> &'a Volume {
        self.volume
    }

    /// Its medium.
    #[must_use]
    pub fn medium(&self) -> &'a Medium {
        self.medium
    }

    /// The (checked) settings.
    #[must_use]
    pub fn settings(&self) -> &MarchSettings {
        &self.settings
    }

    /// The visibility the settings asked for.
    #[must_use]
    pub fn visibility(&self) -> &Visibility {
        &self.visibility
    }

    /// Radiance arriving at `origin` along `-dir` (the ray `origin + t·dir`), with single
    /// scattering from `lights`; a failed lighting query is an error.
    pub fn march<B: ManyLights>(
        &self,
        lights: &Lights<B>,
        origin: Vec3,
        dir: Vec3,
        stats: &mut RenderStats,
    ) -> Result<Vec3, RenderError> {
        self.march_with(
            Lit::lights(Some(lights)),
            Terms::All,
            origin,
            dir,
            stats,
            &mut LightScratch::default(),
        )
    }

    /// [`march`](Self::march) of `terms` (emission alone without `lights`) with buffers that
    /// the caller reuses from ray to ray.
    fn march_with<B: ManyLights>(
        &self,
        lit: Lit<'_, B>,
        terms: Terms,
        origin: Vec3,
        dir: Vec3,
        stats: &mut RenderStats,
        scratch: &mut LightScratch,
    ) -> Result<Vec3, RenderError> {
        let (volume, medium, settings) = (self.volume, self.medium, &self.settings);
        // The emission's march reads no light and sees nothing behind the smoke.
        let lit = match terms {
            Terms::Emission => Lit::lights(None),
            Terms::All | Terms::Light => lit,
        };
        let lights = lit.lights;
        let h = volume.density.voxel_size;
        let (lo, hi) = volume.density.bounds();
        let hit = self.surfaces.and_then(|s| Some((s, s.hit(origin, dir)?)));
        let surface = |stats: &mut RenderStats, scratch: &mut LightScratch| match (hit, terms) {
            (_, Terms::Emission) => Ok(Vec3::ZERO),
            (Some((s, hit)), _) => {
                let lights = lit.surface.or(lights).map(|l| (l, s));
                self.shade_surface(lights, origin + dir * hit.t, hit, stats, scratch)
            }
            (None, _) => Ok(settings.background),
        };
        let Some((t0, t1)) = crate::grid::slab(origin, dir, lo, hi) else {
            return surface(stats, scratch);
        };
        // The smoke in front of the surface, if one is hit.
        let t1 = hit.map_or(t1, |(_, hit)| t1.min(hit.t));
        if t1 <= t0 {
            return surface(stats, scratch);
        }
        let n = ((t1 - t0) / (settings.step_voxels * h)).ceil().max(1.0) as usize;
        let dt = (t1 - t0) / n as f32;
        let mut radiance = Vec3::ZERO;
        let mut trans = 1.0f32;
        let gauss = dir * (dt * GAUSS_OFFSET);
        // The occupancy's reach assumes a unit direction (the Gauss nodes `gauss` away).
        let may_skip = (dir.length_squared() - 1.0).abs() < 1e-3;
        for i in 0..n {
            let x = origin + dir * (t0 + (i as f32 + 0.5) * dt);
            // Nothing to find here: the sample would add exactly 0 and leave `trans` as it is
            // (unless `trans` is not finite, where 0 · ∞ would not be 0).
            if may_skip
                && trans.is_finite()
                && self.occupancy.is_empty_at(x)
                && lit.scattered.is_none_or(|s| s.is_empty_at(x))
            {
                continue;
            }
            let rho = volume.density.sample(x);
            let sigma_t = medium.extinction(rho);
            // The emission at the step's two Gauss nodes (thin flames' emission is steep in T,
            // and the step's midpoint alone missed 2.7% of the dev fire's light at one-voxel
            // steps: docs/cycles.md), weighed by what the smoke lets through from each
            // (`step_emission`; in clear air the two-point Gauss rule, exact for a cubic).
            let emitted = if terms == Terms::Light {
                Vec3::ZERO
            } else {
                let (near, far) = (
                    volume.emission(medium, x - gauss),
                    volume.emission(medium, x + gauss),
                );
                let [w_near, w_far] = step_emission::node_weights(sigma_t * dt);
                (w_near * dt) * near + (w_far * dt) * far
            };
            let mut source = Vec3::ZERO;
            if let Some(scattered) = lit.scattered {
                source += scattered.sample(x);
            }
            let sigma_s = medium.scattering * rho;
            if let (Some(lights), true) = (lights, sigma_s > 0.0) {
                let v = &self.visibility;
                source += match lit.cached {
                    Some(c) => c.in_scattered(x, sigma_s, sigma_t, v, scratch, stats)?,
                    None => lights.in_scattered(x, sigma_s, sigma_t, v, scratch, stats)?,
                };
            }
            // Exact integral over a step of constant medium: ∫ e^{−σ s} ds = (1 − e^{−σ dt}) / σ.
            let step_t = (-sigma_t * dt).exp();
            let weight = if sigma_t > 0.0 {
                (1.0 - step_t) / sigma_t
            } else {
                dt
            };
            radiance += trans * (weight * source + emitted);
            trans *= step_t;
            if trans < settings.min_transmittance {
                break;
            }
        }
        if trans >= settings.min_transmittance
            && terms != Terms::Emission
            && (hit.is_some() || settings.background != Vec3::ZERO)
        {
            radiance += trans * surface(stats, scratch)?;
        }
        Ok(radiance)
    }

    /// The light a Lambertian surface reflects towards the camera at `hit` (the point `at` of
    /// one of `surfaces`): `Σ_j (ρ/π) max(0, n·ω_j) I_j g(d_j) T_smoke V_surfaces` through the
    /// same backend and smoke visibility as the medium ([`crate::surfaces`]). Black without
    /// lights.
    fn shade_surface<B: ManyLights>(
        &self,
        lights: Option<(&Lights<B>, &dyn Surfaces)>,
        at: Vec3,
        hit: SurfaceHit,
        stats: &mut RenderStats,
        scratch: &mut LightScratch,
    ) -> Result<Vec3, RenderError> {
        let Some((lights, surfaces)) = lights else {
            return Ok(Vec3::ZERO);
        };
        // Lifted off the surface by a thousandth of a voxel, so that its own shadow tests do
        // not meet it.
        let lift = 1e-3 * self.volume.density.voxel_size;
        let x = at + hit.normal * lift;
        let brdf = hit.albedo * std::f32::consts::FRAC_1_PI;
        let response = |l: &LightSample| {
            let cos = hit.normal.dot(l.position - x) / l.distance;
            if cos > 0.0 && !surfaces.occluded(x, l.position) {
                brdf * cos
            } else {
                Vec3::ZERO
            }
        };
        stats.surface_points += 1;
        // The point's material is what Lightcuts bounds a cluster's light with: a Lambertian
        // bound `a max(0, n·ω) I g` with `a = ρ/π`, the BRDF, so that the bound and the response
        // are in the same units. The other backends do not read it.
        let point = ShadingPoint {
            normal: Some(hit.normal),
            geometric: None,
            material: lgh_core::Material::Lambert { albedo: brdf },
            ..ShadingPoint::in_medium(x)
        };
        Ok(lights.incident(&point, &self.visibility, response, scratch, stats)?)
    }
}

/// The one pixel loop of every renderer in the crate: `shade(scratch, x, y)` for each pixel of
/// `camera`'s image (`pixels: None`, rows in parallel, `progress(1)` as each row finishes) or
/// of a list (`Some`, in parallel, no progress), results in pixel order. Each row (or rayon
/// split of a list) makes its scratch with `init`; pixels are independent, so nothing depends on
/// the thread count. The first error in pixel order is returned; the other pixels still run.
/// (Walking 8 × 8 tiles instead, to keep the lights' cube maps in cache, was measured: the
/// demo's cube-map render took the same time, 17.0 s against 17.2 s by rows.)
pub fn shade_pixels<T: Send, S>(
    camera: &Camera,
    pixels: Option<&[[usize; 2]]>,
    init: impl Fn() -> S + Sync + Send,
    shade: impl Fn(&mut S, usize, usize) -> Result<T, RenderError> + Sync + Send,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<T>, RenderError> {
    let results: Vec<Result<T, RenderError>> = match pixels {
        None => {
            let w = camera.width();
            let rows: Vec<Vec<Result<T, RenderError>>> = (0..camera.height())
                .into_par_iter()
                .map(|y| {
                    let mut scratch = init();
                    let row = (0..w).map(|x| shade(&mut scratch, x, y)).collect();
                    progress(1);
                    row
                })
                .collect();
            rows.into_iter().flatten().collect()
        }
        Some(list) => {
            camera.check_pixels(list)?;
            list.par_iter()
                .map_init(&init, |scratch, &[x, y]| shade(scratch, x, y))
                .collect()
        }
    };
    results.into_iter().collect()
}

/// Which of a camera ray's terms a march adds up ([`MarchSettings::emission_samples`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Terms {
    /// The whole radiance: the emission, the light the smoke scatters, and the surfaces and
    /// background behind it, each through the smoke in front of it.
    All,
    /// The emission alone, through the smoke in front of it.
    Emission,
    /// All but the emission.
    Light,
}

/// What a march shades with: the lights (of surfaces, and of the medium without a cache;
/// `None` for emission alone) and the lights split for a lighting cache, if any.
pub(crate) struct Lit<'s, B> {
    pub(crate) lights: Option<&'s Lights<B>>,
    pub(crate) cached: Option<&'s CachedLights<'s>>,
    /// Multiple scattering's light as in-scattered radiance at the voxels, added at every
    /// sample ([`crate::scattered_light`]); `lights` are then the emission's.
    pub(crate) scattered: Option<&'s ScatteredRadiance>,
    /// The lights of surfaces, where they differ from `lights` (the merged lights, with the
    /// scattered light as a grid).
    pub(crate) surface: Option<&'s Lights<B>>,
}

impl<B> Clone for Lit<'_, B> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<B> Copy for Lit<'_, B> {}

impl<'s, B> Lit<'s, B> {
    /// `lights` alone, no cache.
    pub(crate) fn lights(lights: Option<&'s Lights<B>>) -> Self {
        Lit {
            lights,
            cached: None,
            scattered: None,
            surface: None,
        }
    }
}

/// The marcher's radiance and counts for `pixels` (`None`: the whole image) of `camera`: each
/// pixel `n × n` rays ([`MarchSettings::pixel_samples`]), and with
/// [`PixelRefinement::Adaptive`] `2n × 2n` where neighbouring rays differ (the whole image
/// only: the decision reads the neighbours and the image's mean). `progress` hears
/// [`Phase::Render`] over rows, then [`Phase::Refinement`] over the refined pixels (a list of
/// pixels reports nothing).
fn march_pixels<B: ManyLights + Sync>(
    marcher: &Marcher<'_>,
    lights: Lit<'_, B>,
    camera: &Camera,
    pixels: Option<&[[usize; 2]]>,
    progress: &dyn Progress,
) -> Result<(Vec<Vec3>, RenderStats), RenderError> {
    let (n, e) = (
        marcher.settings.pixel_samples,
        marcher.settings.emission_samples,
    );
    let rays = PixelRays {
        marcher,
        lights,
        camera,
    };
    let rows = camera.height() as u64;
    let tolerance = match (marcher.settings.pixel_refinement, pixels) {
        (PixelRefinement::Uniform, _) => {
            let progress: &dyn Progress = if pixels.is_some() { &() } else { progress };
            let out = progress::phase(progress, Phase::Render, rows, |p| {
                shade_pixels(
                    camera,
                    pixels,
                    LightScratch::default,
                    |scratch, x, y| rays.filtered([x, y], n, e, scratch),
                    p,
                )
            })?;
            return Ok(summed(out));
        }
        (PixelRefinement::Adaptive { tolerance }, None) => tolerance,
        (PixelRefinement::Adaptive { .. }, Some(list)) => {
            return Err(RenderError::InvalidCount {
                name: "pixels of an adaptively refined render",
                value: list.len(),
                rule: "must be the whole image (the refinement compares neighbouring pixels \
                       against the image's mean)",
            })
        }
    };
    // The first rays, n × n a pixel: the decision's, and the pixels that are not refined.
    let (all, mut stats) = progress::phase(progress, Phase::Render, rows, |p| match n {
        1 => first_rays::<1, B>(&rays, camera, p),
        2 => first_rays::<4, B>(&rays, camera, p),
        3 => first_rays::<9, B>(&rays, camera, p),
        4 => first_rays::<16, B>(&rays, camera, p),
        // `MarchSettings::check` refuses these before any work.
        _ => Err(RenderError::InvalidCount {
            name: "pixel samples refined adaptively",
            value: n,
            rule: ADAPTIVE_FIRST_RULE,
        }),
    })?;
    let (w, h) = (camera.width(), camera.height());
    let refine = pixels_to_refine(&all, w, h, n, tolerance);
    let m = REFINEMENT * n;
    let refined = progress::phase(progress, Phase::Refinement, refine.len() as u64, |p| {
        shade_pixels(
            camera,
            Some(&refine),
            LightScratch::default,
            |scratch, x, y| {
                // Adaptive pixels take the emission with the light (`MarchSettings::check`).
                let r = rays.filtered([x, y], m, m, scratch);
                p(1);
                r
            },
            &|_| {},
        )
    })?;
    let mut radiance: Vec<Vec3> = all
        .chunks_exact(n * n)
        .map(|r| mean_of(r.iter().copied(), n))
        .collect();
    for (&[x, y], (r, s)) in refine.iter().zip(&refined) {
        radiance[y * w + x] = *r;
        stats.add(s);
    }
    stats.refined_pixels = refine.len() as u64;
    Ok((radiance, stats))
}

/// [`PixelRefinement::Adaptive`]'s first pass: `K = n²` rays for every pixel of `camera`
/// (`n` ≤ [`MAX_PIXEL_SAMPLES`] / [`REFINEMENT`] = 4, checked with the settings), in pixel
/// order and each pixel's row by row, with their counts summed. `K` is the rays taken: a pixel
/// holds only those while the rows are shaded (with a bound of 16 for every `n`, a 1280×720
/// render at one ray a pixel peaked at 491 MB against 232).
fn first_rays<const K: usize, B: ManyLights + Sync>(
    rays: &PixelRays<'_, '_, '_, B>,
    camera: &Camera,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<(Vec<Vec3>, RenderStats), RenderError> {
    let n = K.isqrt();
    debug_assert_eq!(n * n, K, "a square number of rays a pixel");
    let first = shade_pixels(
        camera,
        None,
        LightScratch::default,
        |scratch, x, y| {
            let mut stats = RenderStats::default();
            let mut first = [Vec3::ZERO; K];
            for j in 0..n {
                for i in 0..n {
                    let (u, v) = (sub_pixel(x, i, n), sub_pixel(y, j, n));
                    first[j * n + i] = rays.march(Terms::All, [u, v], &mut stats, scratch)?;
                }
            }
            Ok((first, stats))
        },
        progress,
    )?;
    let mut stats = RenderStats::default();
    let mut all = Vec::with_capacity(first.len() * K);
    for (r, s) in first {
        stats.add(&s);
        all.extend_from_slice(&r);
    }
    Ok((all, stats))
}

/// What a pixel's camera rays march: the marcher, its lights, the camera.
struct PixelRays<'a, 'm, 's, B> {
    marcher: &'a Marcher<'m>,
    lights: Lit<'s, B>,
    camera: &'a Camera,
}

impl<B: ManyLights> PixelRays<'_, '_, '_, B> {
    /// `terms` of the ray through image point `(u, v)`.
    fn march(
        &self,
        terms: Terms,
        [u, v]: [f32; 2],
        stats: &mut RenderStats,
        scratch: &mut LightScratch,
    ) -> Result<Vec3, RenderError> {
        let d = self.camera.direction(u, v);
        self.marcher
            .march_with(self.lights, terms, self.camera.eye(), d, stats, scratch)
    }

    /// Pixel `[x, y]`'s box filter of `terms` by the midpoint rule: the mean of `n × n` rays
    /// through the centres of its sub-pixels (the centre ray for `n = 1`).
    fn box_filter(
        &self,
        terms: Terms,
        [x, y]: [usize; 2],
        n: usize,
        stats: &mut RenderStats,
        scratch: &mut LightScratch,
    ) -> Result<Vec3, RenderError> {
        if n <= 1 {
            let (eye, d) = self.camera.ray(x, y);
            return (self.marcher).march_with(self.lights, terms, eye, d, stats, scratch);
        }
        let mut sum = Vec3::ZERO;
        for j in 0..n {
            for i in 0..n {
                let at = [sub_pixel(x, i, n), sub_pixel(y, j, n)];
                sum += self.march(terms, at, stats, scratch)?;
            }
        }
        Ok(sum / (n * n) as f32)
    }

    /// Pixel `[x, y]` with `n × n` rays a pixel, and `e × e` for its emission where `e > n`
    /// ([`MarchSettings::emission_samples`]): the box filter of the whole radiance, or that
    /// of the emission plus that of the rest. With its own counts: what a pixel pass returns.
    fn filtered(
        &self,
        pixel: [usize; 2],
        n: usize,
        e: usize,
        scratch: &mut LightScratch,
    ) -> Result<(Vec3, RenderStats), RenderError> {
        let mut stats = RenderStats::default();
        let r = if e > n {
            let light = self.box_filter(Terms::Light, pixel, n, &mut stats, scratch)?;
            light + self.box_filter(Terms::Emission, pixel, e, &mut stats, scratch)?
        } else {
            self.box_filter(Terms::All, pixel, n, &mut stats, scratch)?
        };
        Ok((r, stats))
    }
}

/// The mean of a pixel's `n × n` rays, summed in order (one ray: itself).
fn mean_of(rays: impl Iterator<Item = Vec3>, n: usize) -> Vec3 {
    if n <= 1 {
        return rays.fold(Vec3::ZERO, |_, r| r);
    }
    rays.fold(Vec3::ZERO, |a, r| a + r) / (n * n) as f32
}

/// The pixels' radiance, and their counts summed.
fn summed(out: Vec<(Vec3, RenderStats)>) -> (Vec<Vec3>, RenderStats) {
    let mut stats = RenderStats::default();
    let radiance = out
        .into_iter()
        .map(|(r, s)| {
            stats.add(&s);
            r
        })
        .collect();
    (radiance, stats)
}

/// The bricks of `volume`'s box where a march with `settings` reads zero density and no
/// emission ([`crate::occupancy`]): a sample reads the density at its position and the emission
/// at the two-point Gauss nodes, up to `GAUSS_OFFSET` of a step from it.
fn occupancy(volume: &Volume, medium: &Medium, settings: &MarchSettings) -> Occupancy {
    let reach = GAUSS_OFFSET * settings.step_voxels * volume.density.voxel_size;
    let mut occupancy = Occupancy::empty(&volume.density);
    occupancy.mark(&volume.density, |rho| rho != 0.0, 0.0);
    match volume.colour.as_deref() {
        Some(channels) => {
            for c in channels {
                occupancy.mark(c, |v| v != 0.0, reach);
            }
        }
        None => {
            // `Medium::emits` is `T > T_min` (and `T > 0`): a value whose |T| is below T_min by
            // more than rounding can only interpolate to a temperature that does not emit.
            let t_min = medium.min_temperature.max(0.0) * (1.0 - 1e-5);
            let scale = medium.temperature_scale;
            occupancy.mark(
                &volume.temperature,
                |v| (v * scale).abs() > t_min || v.is_nan(),
                reach,
            );
        }
    }
    occupancy
}

/// The two-point Gauss rule's nodes on a step of length 1 around its midpoint: `±1/(2√3)`.
const GAUSS_OFFSET: f32 = 0.288_675_13;

/// The image coordinate of the centre of sub-pixel `i` of `n` along pixel `p`'s side: the
/// midpoint rule's nodes, `p + (i + 1/2)/n`.
#[must_use]
fn sub_pixel(p: usize, i: usize, n: usize) -> f32 {
    p as f32 + (i as f32 + 0.5) / n as f32
}

/// An image of `camera`'s size from its pixels in order (what [`shade_pixels`] returns for the
/// whole image), without a black image to overwrite first.
pub(crate) fn image(camera: &Camera, pixels: impl Iterator<Item = Vec3>) -> Image {
    Image {
        width: camera.width(),
        height: camera.height(),
        pixels: pixels.collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::DenseGrid;
    use lgh_core::BruteForce;

    /// A homogeneous box of density 1 and temperature `kelvin`, 2 units on a side.
    fn slab_volume(kelvin: f32) -> Volume {
        let origin = Vec3::splat(-1.0 + 1.0 / 32.0);
        let mut density = DenseGrid::zeros([32; 3], 1.0 / 16.0, origin);
        density.data.fill(1.0);
        let mut temperature = density.clone();
        temperature.data.fill(kelvin);
        Volume::new(density, temperature)
    }

    /// The radiance marched down the z axis through the middle of `v`, lit by nothing.
    fn through_the_middle(v: &Volume, m: &Medium) -> Vec3 {
        Marcher::new(v, m, &MarchSettings::default())
            .unwrap()
            .march_with::<BruteForce>(
                Lit::lights(None),
                Terms::All,
                Vec3::new(0.0, 0.0, 5.0),
                -Vec3::Z,
                &mut RenderStats::default(),
                &mut LightScratch::default(),
            )
            .unwrap()
    }

    /// `got` is the slab's closed form `want` (emission `j`, extinction `sigma`): each step is
    /// integrated exactly, so what remains is f32 rounding over 64 steps (1e-4) and the early
    /// stop at T < min_transmittance, which drops at most T_stop · j / σ of the tail.
    fn assert_slab(got: Vec3, want: Vec3, j: Vec3, sigma: f32) {
        let s = MarchSettings::default();
        let tol = 1e-4 * want.max_element() + s.min_transmittance * j.max_element() / sigma;
        assert!(
            (got - want).abs().max_element() <= tol,
            "σ {sigma}: {got} vs {want}"
        );
    }

    #[test]
    fn emitting_absorbing_slab_matches_the_closed_form() {
        // L = j / σ_a (1 − e^{−σ_a ℓ}) through a slab of length ℓ = 2.
        let v = slab_volume(2000.0);
        for sigma in [0.1f32, 1.0, 4.0] {
            let m = Medium::new(sigma, 0.0, 1e-3, 500.0).unwrap();
            let j = m.emission_at(2000.0);
            let got = through_the_middle(&v, &m);
            let want = j / sigma * (1.0 - (-2.0 * sigma).exp());
            assert_slab(got, want, j, sigma);
        }
    }

    #[test]
    fn the_background_is_seen_through_the_slab_and_around_it() {
        // L = j / σ (1 − e^{−σ ℓ}) + e^{−σ ℓ} · background through the slab (ℓ = 2), the
        // background itself past it, and an image without it the same without that term.
        let v = slab_volume(2000.0);
        let background = Vec3::new(0.5, 1.0, 2.0);
        let march = |m: &Medium, origin: Vec3, background: Vec3| {
            let s = MarchSettings {
                background,
                ..Default::default()
            };
            Marcher::new(&v, m, &s)
                .unwrap()
                .march_with::<BruteForce>(
                    Lit::lights(None),
                    Terms::All,
                    origin,
                    -Vec3::Z,
                    &mut RenderStats::default(),
                    &mut LightScratch::default(),
                )
                .unwrap()
        };
        for sigma in [0.1f32, 1.0, 4.0] {
            let m = Medium::new(sigma, 0.0, 1e-3, 500.0).unwrap();
            let j = m.emission_at(2000.0);
            let through = march(&m, Vec3::new(0.0, 0.0, 5.0), background);
            let t = (-2.0 * sigma).exp();
            let want = j / sigma * (1.0 - t) + t * background;
            assert_slab(through, want, j + sigma * background, sigma);
            let black = march(&m, Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
            assert_eq!(black, through_the_middle(&v, &m));
            // Past the slab's side: the background alone, exactly.
            assert_eq!(march(&m, Vec3::new(9.0, 0.0, 5.0), background), background);
        }
        let bad = MarchSettings {
            background: Vec3::new(0.0, f32::NAN, 0.0),
            ..Default::default()
        };
        let err = bad.check().unwrap_err().to_string();
        assert!(err.contains("background radiance"), "{err}");
    }

    #[test]
    fn an_rgb_emission_slab_matches_the_closed_form() {
        // A vec3 emission read as it is: L = k_e rgb / σ_a (1 − e^{−σ_a ℓ}) per channel, with no
        // temperature cut (T_min = 10⁶ K would cut any blackbody) and no blackbody colour.
        let slab = slab_volume(0.0);
        let rgb = Vec3::new(3.0, 1.5, 0.25);
        let channel = |c: f32| {
            let mut g = slab.temperature.clone();
            g.data.fill(c);
            g
        };
        let v = Volume::with_colour(slab.density.clone(), rgb.to_array().map(channel)).unwrap();
        for sigma in [0.1f32, 1.0, 4.0] {
            let m = Medium::new(sigma, 0.0, 0.5, 1e6).unwrap();
            let got = through_the_middle(&v, &m);
            let j = 0.5 * rgb;
            let want = j / sigma * (1.0 - (-2.0 * sigma).exp());
            assert_slab(got, want, j, sigma);
        }
    }

    #[test]
    fn pixel_samples_are_the_sub_pixels_of_a_finer_image_averaged() {
        // n × n rays a pixel (a box filter by the midpoint rule) are the pixel centres of the
        // image n times finer with the same framing, averaged: the same rays, up to the
        // rounding of their directions (a few ulps), hence a relative 1e-4.
        let v = crate::procedural::ball(16, 0.5, 2500.0);
        let m = Medium::new(4.0, 0.0, 1e-3, 500.0).unwrap();
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let (w, h) = (6, 4);
        let render = |camera: &Camera, n: usize| {
            let s = MarchSettings {
                pixel_samples: n,
                ..Default::default()
            };
            let marcher = Marcher::new(&v, &m, &s).unwrap();
            let lit = Lit::<BruteForce>::lights(None);
            marcher.render_lit(lit, camera, &()).unwrap().0
        };
        let centres = render(&Camera::frame(lo, hi, w, h).unwrap(), 1);
        for n in [2usize, 3] {
            let boxed = render(&Camera::frame(lo, hi, w, h).unwrap(), n);
            let fine = render(&Camera::frame(lo, hi, w * n, h * n).unwrap(), 1);
            let mut moved = 0;
            for y in 0..h {
                for x in 0..w {
                    let sub = |s: usize| fine.pixels[(n * y + s / n) * w * n + n * x + s % n];
                    let mean = (0..n * n).map(sub).sum::<Vec3>() / (n * n) as f32;
                    let got = boxed.pixels[y * w + x];
                    let tol = 1e-4 * mean.max_element() + 1e-12;
                    assert!(
                        (got - mean).abs().max_element() <= tol,
                        "n {n}, pixel ({x}, {y}): {got} vs {mean}"
                    );
                    let centre = centres.pixels[y * w + x];
                    moved +=
                        usize::from((got - centre).abs().max_element() > 0.01 * mean.max_element());
                }
            }
            // The filter is not the centre ray: across the ball's edge it averages.
            assert!(moved > 0, "n {n}: no pixel differs from its centre by 1%");
        }
        for bad in [0, crate::settings::MAX_PIXEL_SAMPLES + 1] {
            let s = MarchSettings {
                pixel_samples: bad,
                ..Default::default()
            };
            assert!(s.check().is_err(), "{bad} rays a side accepted");
        }
    }

    /// The ball lit by two point lights (brute force) with a grey world behind it: emission,
    /// scattered light and background in every image.
    fn lit_ball() -> (Volume, Medium, Lights<BruteForce>) {
        let v = crate::procedural::ball(16, 0.5, 2500.0);
        let m = Medium::new(2.0, 2.0, 1e-3, 500.0).unwrap();
        let bulbs = [
            lgh_core::PointLight::new(Vec3::new(0.0, -1.5, 0.8), Vec3::splat(0.05)),
            lgh_core::PointLight::new(Vec3::new(1.2, 0.3, -0.4), Vec3::new(0.03, 0.02, 0.01)),
        ];
        let lights = Lights::new(BruteForce::new(&bulbs).unwrap(), v.density.voxel_size);
        (v, m, lights)
    }

    #[test]
    fn the_emission_and_the_light_marched_apart_add_up_to_the_whole() {
        // `Terms::Emission` and `Terms::Light` split each ray's radiance in two: their sum is
        // the whole march's, up to the rounding of two sums against one (a relative 1e-5); the
        // emission's march sees no background, the light's sees it where the ray leaves the
        // box (`Terms` is what `MarchSettings::emission_samples` marches apart).
        let (v, m, lights) = lit_ball();
        let s = MarchSettings {
            background: Vec3::new(1e-4, 2e-4, 3e-4),
            ..Default::default()
        };
        let marcher = Marcher::new(&v, &m, &s).unwrap();
        let lit = Lit::lights(Some(&lights));
        let (mut stats, mut scratch) = (RenderStats::default(), LightScratch::default());
        let mut march = |terms, origin: Vec3, dir: Vec3| {
            let (st, sc) = (&mut stats, &mut scratch);
            marcher.march_with(lit, terms, origin, dir, st, sc).unwrap()
        };
        let eye = Vec3::new(0.0, -4.0, 0.0);
        let (mut emission_seen, mut light_seen) = (0.0f32, 0.0f32);
        for k in 0..25 {
            let target = Vec3::new(-0.9 + 0.075 * k as f32, 0.0, 0.6 - 0.05 * k as f32);
            let dir = (target - eye).normalize();
            let all = march(Terms::All, eye, dir);
            let (emission, light) = (
                march(Terms::Emission, eye, dir),
                march(Terms::Light, eye, dir),
            );
            let tol = 1e-5 * all.max_element();
            assert!(
                (emission + light - all).abs().max_element() <= tol,
                "ray {k}: {emission} + {light} against {all}"
            );
            emission_seen = emission_seen.max(emission.max_element());
            light_seen = light_seen.max((light - s.background).max_element());
        }
        // Both parts are present on these rays: the test splits something.
        assert!(emission_seen > 0.0 && light_seen > 0.0);
        // A ray that misses the box: the background is the light's, none is the emission's.
        let away = Vec3::new(0.0, 0.0, 1.0);
        assert_eq!(march(Terms::Emission, eye, away), Vec3::ZERO);
        assert_eq!(march(Terms::Light, eye, away), s.background);
        assert_eq!(march(Terms::All, eye, away), s.background);
    }

    #[test]
    fn finer_emission_rays_filter_the_emission_alone() {
        let (v, m, lights) = lit_ball();
        let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 24, 16).unwrap();
        let render = |n: usize, e: usize, lit: Lit<'_, BruteForce>| {
            let s = MarchSettings {
                pixel_samples: n,
                emission_samples: e,
                ..Default::default()
            };
            let marcher = Marcher::new(&v, &m, &s).unwrap();
            marcher.render_lit(lit, &camera, &()).unwrap().0
        };
        // Without light the pixel is its emission alone: 3 × 3 emission rays and one ray of
        // (no) light are the 3 × 3 filter, bit for bit; emission rays at most the pixel samples
        // change nothing.
        let dark = Lit::<BruteForce>::lights(None);
        assert_eq!(render(1, 3, dark).pixels, render(3, 3, dark).pixels);
        let lit = Lit::lights(Some(&lights));
        assert_eq!(render(2, 1, lit).pixels, render(2, 2, lit).pixels);
        // With light, the pixel is the 4 × 4 filter of the emission (the dark image) plus the
        // centre ray's light (the lit image less the dark one), up to rounding (1e-5 of the
        // brightest channel; each term marched apart).
        let (split, coarse, fine) = (render(1, 4, lit), render(1, 1, lit), render(4, 4, lit));
        let (dark_coarse, dark_fine) = (render(1, 1, dark), render(4, 4, dark));
        for (i, p) in split.pixels.iter().enumerate() {
            let want = dark_fine.pixels[i] + (coarse.pixels[i] - dark_coarse.pixels[i]);
            let tol = 1e-5 * fine.pixels[i].max_element().max(want.max_element()) + 1e-12;
            assert!(
                (*p - want).abs().max_element() <= tol,
                "pixel {i}: {p} vs {want}"
            );
        }
        // So it errs from the 4 × 4 image by the light's filter alone: here, where the ball's
        // steep rim emits far more than the two dim bulbs light, by a fraction of the one ray's
        // error (measured: 0.07 of it).
        let error = |a: &Image, b: &Image| {
            let squares = a
                .pixels
                .iter()
                .zip(&b.pixels)
                .map(|(x, y)| f64::from(lgh_core::luminance(*x - *y)).powi(2));
            squares.sum::<f64>().sqrt()
        };
        let (before, after) = (error(&coarse, &fine), error(&split, &fine));
        eprintln!("1 ray: {before:.4e} from 4 × 4; 4 × 4 emission rays apart: {after:.4e}");
        assert!(after < 0.25 * before, "{after} left of {before}");
    }

    #[test]
    fn emission_samples_are_checked() {
        // 1 to 8 a side; with adaptive pixels, which refine both together, at most the pixel
        // samples.
        let ok = MarchSettings::default();
        for (e, n, refinement, good) in [
            (0, 1, PixelRefinement::Uniform, false),
            (MAX_PIXEL_SAMPLES + 1, 1, PixelRefinement::Uniform, false),
            (MAX_PIXEL_SAMPLES, 1, PixelRefinement::Uniform, true),
            (1, 4, PixelRefinement::Uniform, true),
            (2, 2, PixelRefinement::Adaptive { tolerance: 0.05 }, true),
            (3, 2, PixelRefinement::Adaptive { tolerance: 0.05 }, false),
        ] {
            let s = MarchSettings {
                emission_samples: e,
                pixel_samples: n,
                pixel_refinement: refinement,
                ..ok
            };
            assert_eq!(
                s.check().is_ok(),
                good,
                "{e} emission rays, {n} rays, {refinement:?}"
            );
        }
    }

    #[test]
    fn adaptive_pixels_report_their_refinement_after_the_rows() {
        // The first pass is `Phase::Render` over rows; the refined pixels are a phase of their
        // own whose steps add up to its total, the pixels `RenderStats` counts as refined.
        use crate::progress::{Heard, Recorder};
        let v = crate::procedural::ball(16, 0.5, 2500.0);
        let m = Medium::new(4.0, 0.0, 1e-3, 500.0).unwrap();
        let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 24, 16).unwrap();
        for refinement in [
            PixelRefinement::Uniform,
            PixelRefinement::Adaptive { tolerance: 0.05 },
        ] {
            let s = MarchSettings {
                pixel_samples: 2,
                pixel_refinement: refinement,
                ..Default::default()
            };
            let marcher = Marcher::new(&v, &m, &s).unwrap();
            let recorder = Recorder::default();
            let lit = Lit::<BruteForce>::lights(None);
            let (_, stats) = marcher.render_lit(lit, &camera, &recorder).unwrap();
            let whole = |phase, n| Heard {
                phase,
                total: n,
                steps: n,
            };
            let mut want = vec![whole(Phase::Render, camera.height() as u64)];
            if refinement != PixelRefinement::Uniform {
                assert!(stats.refined_pixels > 0);
                want.push(whole(Phase::Refinement, stats.refined_pixels));
            }
            assert_eq!(recorder.heard(), want, "{refinement:?}");
        }
    }

    #[test]
    fn adaptive_refinement_is_the_finer_filter_where_rays_differ() {
        // Each pixel of an adaptive render is, bit for bit, the pixel of the n × n filter or of
        // the 2n × 2n one; a tolerance of zero refines wherever rays differ, a huge one
        // nowhere; in between it comes much closer to the finer image than n × n does, at a
        // fraction of its rays.
        let v = crate::procedural::ball(16, 0.5, 2500.0);
        let m = Medium::new(4.0, 0.0, 1e-3, 500.0).unwrap();
        let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 24, 16).unwrap();
        let render = |n: usize, refinement: PixelRefinement| {
            let s = MarchSettings {
                pixel_samples: n,
                pixel_refinement: refinement,
                ..Default::default()
            };
            let marcher = Marcher::new(&v, &m, &s).unwrap();
            let lit = Lit::<BruteForce>::lights(None);
            marcher.render_lit(lit, &camera, &()).unwrap()
        };
        let adaptive = |n, tolerance| render(n, PixelRefinement::Adaptive { tolerance });
        let luminance_error = |a: &Image, b: &Image| {
            a.pixels
                .iter()
                .zip(&b.pixels)
                .map(|(x, y)| f64::from(lgh_core::luminance(*x - *y)).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        for n in [1usize, 2] {
            let coarse = render(n, PixelRefinement::Uniform).0;
            let fine = render(REFINEMENT * n, PixelRefinement::Uniform).0;
            let (never, stats) = adaptive(n, 1e30);
            assert_eq!(
                (never.pixels, stats.refined_pixels),
                (coarse.pixels.clone(), 0)
            );
            let (all, stats) = adaptive(n, 0.0);
            let pixels = coarse.pixels.len();
            assert!(
                stats.refined_pixels > 0,
                "n {n}: nothing refined at tolerance 0"
            );
            for (i, p) in all.pixels.iter().enumerate() {
                assert!(
                    *p == coarse.pixels[i] || *p == fine.pixels[i],
                    "n {n}, pixel {i}"
                );
                // Where the image varies at all, tolerance 0 refines.
                if coarse.pixels[i] != fine.pixels[i]
                    && (fine.pixels[i] - coarse.pixels[i]).length() > 1e-6
                {
                    assert_eq!(
                        *p, fine.pixels[i],
                        "n {n}, pixel {i} differs and was not refined"
                    );
                }
            }
            let (some, stats) = adaptive(n, 0.05);
            let refined = stats.refined_pixels as usize;
            assert!(
                refined > 0 && refined < pixels,
                "n {n}: {refined} of {pixels} refined"
            );
            let (before, after) = (
                luminance_error(&coarse, &fine),
                luminance_error(&some, &fine),
            );
            assert!(after < 0.25 * before, "n {n}: {after} left of {before}");
        }
        // A refined pixel takes 2n ≤ 8 rays a side; the tolerance is a share, at least 0.
        for (n, tolerance) in [(5, 0.05), (1, -0.1), (1, f32::NAN)] {
            let s = MarchSettings {
                pixel_samples: n,
                pixel_refinement: PixelRefinement::Adaptive { tolerance },
                ..Default::default()
            };
            assert!(
                s.check().is_err(),
                "{n} rays a side, tolerance {tolerance} accepted"
            );
        }
        // The decision needs the whole image: a render of some pixels refuses it.
        let s = MarchSettings {
            pixel_refinement: PixelRefinement::Adaptive { tolerance: 0.05 },
            ..Default::default()
        };
        let marcher = Marcher::new(&v, &m, &s).unwrap();
        let lit = Lit::<BruteForce>::lights(None);
        let err = marcher
            .render_pixels_lit(lit, &camera, &[[0, 0]])
            .unwrap_err();
        assert!(err.to_string().contains("whole image"), "{err}");
    }

    /// A backend whose every query fails, as a backend does on a point it cannot shade.
    struct Failing;

    impl ManyLights for Failing {
        fn name(&self) -> &'static str {
            "failing"
        }

        fn illuminate<S: lgh_core::Shader>(
            &self,
            _: &ShadingPoint,
            _: &mut S,
        ) -> Result<lgh_core::Illumination, lgh_core::QueryError> {
            Err(lgh_core::QueryError::NonFinitePoint)
        }
    }

    /// Skipping the bricks where nothing is found (`crate::occupancy`) changes no bit of the
    /// image: the explosion at 32³ (smoke in a ball, emission inside it) lit by its hottest
    /// voxels with ray-marched shadows, at a 1.7-voxel step (whose Gauss nodes reach farther
    /// than the default's), against the same marcher with every brick occupied. Also with the
    /// temperature read through its corners (the emission interpolation Cycles 4.x uses).
    #[test]
    fn skipping_empty_space_changes_no_bit() {
        let v = crate::procedural::explosion(32, 0.5).unwrap();
        let hot: Vec<lgh_core::PointLight> = (0..v.temperature.data.len())
            .filter(|&i| v.temperature.data[i] > 1800.0)
            .take(200)
            .map(|i| {
                let [nx, ny, _] = v.temperature.dims;
                let c = v.temperature.centre(i % nx, (i / nx) % ny, i / (nx * ny));
                lgh_core::PointLight::new(c, Vec3::splat(1e-3))
            })
            .collect();
        assert!(hot.len() > 10);
        let lights = Lights::new(BruteForce::new(&hot).unwrap(), v.density.voxel_size);
        let camera = Camera::frame(v.density.bounds().0, v.density.bounds().1, 24, 16).unwrap();
        let s = MarchSettings {
            shadows: Shadows::RayMarch,
            step_voxels: 1.7,
            ..Default::default()
        };
        for interpolation in [
            crate::medium::EmissionInterpolation::Temperature,
            crate::medium::EmissionInterpolation::Attributes,
        ] {
            let m = Medium::new(2.0, 6.0, 1e-4, 1000.0)
                .unwrap()
                .with_interpolation(interpolation);
            let skipping = Marcher::new(&v, &m, &s).unwrap();
            assert!(skipping.occupancy.occupied_share() < 0.9);
            let mut every = Marcher::new(&v, &m, &s).unwrap();
            every.occupancy.mark(&v.density, |_| true, 0.0);
            assert_eq!(every.occupancy.occupied_share(), 1.0);
            let a = skipping.render(&lights, &camera, &()).unwrap();
            let b = every.render(&lights, &camera, &()).unwrap();
            assert_eq!(a.0.pixels, b.0.pixels);
            assert!(a.0.pixels.iter().any(|p| p.max_element() > 0.0));
        }
    }

    /// The same where the emission lies outside the smoke, on a temperature grid of another
    /// layout (coarser, shifted by a third of its voxel), with a march step of 3.3 voxels whose
    /// Gauss nodes reach a voxel from the sample: the hot ball without smoke must glow, and
    /// the image is the same bits as without skipping.
    #[test]
    fn skipping_keeps_emission_outside_the_smoke_on_a_grid_of_another_layout() {
        let h = 1.0 / 20.0;
        let mut density = DenseGrid::zeros([40; 3], h, Vec3::splat(-1.0 + 0.5 * h));
        let ht = 1.5 * h;
        let mut temperature = DenseGrid::zeros([28; 3], ht, Vec3::splat(-1.0 + ht / 3.0));
        let fill = |g: &mut DenseGrid, centre: Vec3, radius: f32, inside: f32, outside: f32| {
            let [nx, ny, nz] = g.dims;
            for k in 0..nz {
                for j in 0..ny {
                    for i in 0..nx {
                        let at = g.index(i, j, k);
                        let c = g.centre(i, j, k);
                        g.data[at] = if (c - centre).length() < radius {
                            inside
                        } else {
                            outside
                        };
                    }
                }
            }
        };
        fill(&mut density, Vec3::new(-0.45, 0.0, 0.0), 0.3, 1.0, 0.0);
        fill(
            &mut temperature,
            Vec3::new(0.45, 0.1, 0.0),
            0.25,
            2500.0,
            300.0,
        );
        let v = Volume::new(density, temperature);
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let light = lgh_core::PointLight::new(Vec3::new(-0.45, 0.5, 0.0), Vec3::splat(1e-2));
        let lights = Lights::new(BruteForce::new(&[light]).unwrap(), h);
        let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 32, 20).unwrap();
        let s = MarchSettings {
            shadows: Shadows::RayMarch,
            step_voxels: 3.3,
            ..Default::default()
        };
        let skipping = Marcher::new(&v, &m, &s).unwrap();
        assert!(skipping.occupancy.occupied_share() < 0.8);
        let mut every = Marcher::new(&v, &m, &s).unwrap();
        every.occupancy.mark(&v.density, |_| true, 0.0);
        let a = skipping.render(&lights, &camera, &()).unwrap().0;
        let b = every.render(&lights, &camera, &()).unwrap().0;
        assert_eq!(a.pixels, b.pixels);
        // The hot ball without smoke glows (its emission alone), and so does the lit smoke.
        let emission_only = Marcher::new(&v, &m, &s)
            .unwrap()
            .render_lit::<BruteForce>(Lit::lights(None), &camera, &())
            .unwrap()
            .0;
        let lit = |img: &Image| img.pixels.iter().filter(|p| p.max_element() > 0.0).count();
        assert!(lit(&emission_only) > 10 && lit(&a) > lit(&emission_only));
    }

    #[test]
    fn a_failed_lighting_query_is_an_error_not_a_dark_pixel() {
        // The marcher used to drop the query's error and render on as if the point had no
        // light; now the render fails with the query's error as its source.
        let v = slab_volume(0.0);
        let m = Medium::new(1.0, 1.0, 0.0, 0.0).unwrap();
        let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 4, 3).unwrap();
        for shadows in [Shadows::None, Shadows::RayMarch] {
            let s = MarchSettings {
                shadows,
                ..Default::default()
            };
            let lights = Lights::new(Failing, 0.1);
            let marcher = Marcher::new(&v, &m, &s).unwrap();
            let e = marcher.render(&lights, &camera, &()).unwrap_err();
            assert!(
                matches!(e, RenderError::Query(lgh_core::QueryError::NonFinitePoint)),
                "{shadows:?}: {e}"
            );
            assert!(std::error::Error::source(&e).is_some());
        }
        // Without lights nothing is queried, and the render succeeds.
        let marcher = Marcher::new(&v, &m, &MarchSettings::default()).unwrap();
        assert!(marcher
            .render_lit::<Failing>(Lit::lights(None), &camera, &())
            .is_ok());
    }

    #[test]
    fn bad_march_settings_are_errors() {
        let v = slab_volume(0.0);
        let m = Medium::new(1.0, 1.0, 0.0, 0.0).unwrap();
        let ok = MarchSettings::default();
        assert!(Marcher::new(&v, &m, &ok).is_ok());
        for bad in [
            MarchSettings {
                step_voxels: 0.0,
                ..ok
            },
            MarchSettings {
                step_voxels: f32::NAN,
                ..ok
            },
            MarchSettings {
                shadow_step_voxels: -1.0,
                ..ok
            },
            MarchSettings {
                shadow_step_voxels: f32::INFINITY,
                ..ok
            },
            MarchSettings {
                min_transmittance: 1.0,
                ..ok
            },
            MarchSettings {
                min_transmittance: -0.1,
                ..ok
            },
        ] {
            assert!(Marcher::new(&v, &m, &bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn camera_frames_the_box_and_rejects_nonsense() {
        let c = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 64, 36).unwrap();
        // The centre pixel looks at the box centre.
        let d = c.direction(32.0, 18.0);
        assert!((c.eye() + d * (c.eye().length())).length() < 1e-3);
        assert!(Camera::look_at(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 40.0, 8, 8).is_err());
        assert!(Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 40.0, 8, 8).is_err());
        assert!(Camera::look_at(Vec3::ZERO, Vec3::X, Vec3::Y, 0.0, 8, 8).is_err());
        assert!(Camera::look_at(Vec3::ZERO, Vec3::X, Vec3::Y, 40.0, 0, 8).is_err());
        // The messages are the shared camera's.
        assert!(matches!(
            Camera::look_at(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 40.0, 8, 8),
            Err(RenderError::Camera(
                lgh_image::camera::CameraError::EyeAtTarget
            ))
        ));
        // Pixel lists are checked against the image size.
        assert!(c.check_pixels(&[[0, 0], [63, 35]]).is_ok());
        for outside in [[64, 0], [0, 36]] {
            let e = c.check_pixels(&[[1, 1], outside]).unwrap_err().to_string();
            assert!(e.contains("outside the 64x36 image"), "{e}");
        }
    }
}
