//! A frame to render: everything `lgh demo` and `lgh explosion` do for one frame, as one value
//! (ARCHITECTURE.md, "From a VDB file to an EXR").
//!
//! [`FrameRender::new`] takes a frame's lights (their intensities set for the frame), the
//! volume and medium, the [`Method`] with its own parameters and the march settings, and makes
//! everything the render needs once: the multiple-scattering pass if the settings ask for
//! depths (paper Sec. 5; the render then shades the merged lights), the method over the lights
//! (the hierarchy's blending for α, eq. 3), and the visibility (the paper's deep-shadow cube
//! maps over prefiltered density, Sec. 4, or ray-marched shadows) of exactly those lights.
//! [`render`](FrameRender::render) then renders any camera, with opaque surfaces if given.
//! The lights are borrowed (or, with scattering, owned): they cannot change under their maps.

use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_image::Image;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::lighting::Lights;
use crate::lighting_cache::{CachedLights, LightingCache, LightingCacheSettings, RenderedLights};
use crate::lights::ExplosionLights;
use crate::medium::{Medium, Volume};
use crate::method::{FrameBackend, Method, Prepared};
use crate::progress::{Phase, Progress, Steps};
use crate::render::{Lit, Marcher};
use crate::scattering::{self, Scattered, Shares};
use crate::settings::MarchSettings;
use crate::shading::Shading;
use crate::shadow::{CubeMaps, Visibility};
use crate::stats::RenderStats;
use crate::surfaces::Surfaces;

/// Seconds a [`FrameRender`] spent before its first render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PrepareSeconds {
    /// The multiple-scattering pass (0 without one).
    pub scattering: f64,
    /// The render's shadows: the cube maps' tracing, or the ray marcher's padded density.
    pub shadows: f64,
}

/// One frame made ready to render: its lights through a [`Method`], their visibility, the
/// volume, the medium and the checked settings, consistent by construction.
///
/// ```
/// use lgh_volume::render::{Camera, Framing, MarchSettings};
/// use lgh_volume::{procedural, ExplosionLights, FrameRender, Medium, Method};
///
/// let volume = procedural(32, 0.5)?;
/// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?; // κ_a, κ_s, k_e, T_min
/// let lights = ExplosionLights::new(&[&volume], &medium)?;
/// let settings = MarchSettings::default(); // ray-marched shadows, single scattering
/// let frame = FrameRender::new(&lights, Method::Lgh { alpha: 2.0 }, &volume, &medium, &settings, &())?;
/// let (lo, hi) = volume.active_bounds().unwrap();
/// let (image, stats) = frame.render(&Camera::frame(lo, hi, 32, 18)?, &())?;
/// assert_eq!(image.pixels.len(), 32 * 18);
/// assert!(stats.lights_per_point() > 0.0);
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
pub struct FrameRender<'a> {
    /// The frame's emission lights, as given.
    emission: &'a ExplosionLights,
    /// What the render takes of multiple scattering.
    scattering: Scattering,
    method: Method,
    /// The method over the lights the medium is shaded with, and their visibility (moved into
    /// the marcher).
    prepared: Prepared,
    marcher: Marcher<'a>,
    /// The coarse levels' lighting cache, if the settings ask for one and the method is the
    /// hierarchy (filled as renders need it).
    cache: Option<LightingCache>,
    seconds: PrepareSeconds,
}

/// What a [`FrameRender`] takes of multiple scattering (paper Sec. 5).
enum Scattering {
    /// Single scattering: the emission lights alone (depth 0).
    Single,
    /// The pass's merged lights (each voxel's emission and every scattered depth), which the
    /// medium and the surfaces are shaded with. A pass that stopped before its first depth
    /// merges nothing: its lights are the emission's.
    Merged(Scattered),
    /// The scattered light as a grid of in-scattered radiance
    /// ([`MarchSettings::scattered_grid`]): the medium is shaded with the emission lights and
    /// the grid, the surfaces with the merged lights through `surfaces`.
    Grid {
        /// The pass, with its radiance grid.
        scattered: Scattered,
        /// The method over the merged lights, for surfaces (boxed: the other variants are
        /// small).
        surfaces: Box<Prepared>,
    },
}

impl Scattering {
    /// The pass, if there is one.
    fn scattered(&self) -> Option<&Scattered> {
        match self {
            Scattering::Single => None,
            Scattering::Merged(s) | Scattering::Grid { scattered: s, .. } => Some(s),
        }
    }
}

impl<'a> FrameRender<'a> {
    /// Makes `frame` ready to render with `lights` (their intensities set for this frame)
    /// through `method`: checks every setting first, then runs the multiple-scattering pass if
    /// `settings.scatter_depth > 0`, prepares the method (the blending for α once) and builds
    /// the visibility `settings.shadows` asks for, of the lights rendered. `progress` hears
    /// [`Phase::Scattering`] and [`Phase::ShadowMaps`].
    pub fn new(
        lights: &'a ExplosionLights,
        method: Method,
        frame: &'a Volume,
        medium: &'a Medium,
        settings: &MarchSettings,
        progress: &dyn Progress,
    ) -> Result<Self, RenderError> {
        settings.check()?;
        method.check()?;
        let t = Instant::now();
        // Level 0's form in the cache, where it is automatic: light for the scattering pass,
        // whose samples are the voxel centres — the vertices, where light is exact and a ratio
        // would only add the unshadowed sum — and for merged lights (`Level0Form::Auto`).
        let with_level0 = |level0| MarchSettings {
            lighting_cache: LightingCacheSettings {
                level0,
                ..settings.lighting_cache
            },
            ..*settings
        };
        let form = settings.lighting_cache.level0;
        let (scattered, pilot_shading) = match settings.scatter_depth {
            0 => (None, None),
            _ => {
                let pass = with_level0(form.for_lights(RenderedLights::Merged));
                let (s, shading) =
                    scattering::scatter_keeping(lights, method, frame, medium, &pass, progress)?;
                (Some(s), shading)
            }
        };
        let scattering_seconds = if scattered.is_some() {
            t.elapsed().as_secs_f64()
        } else {
            0.0
        };
        // With the scattered light as a grid the medium is shaded with the emission lights and
        // surfaces with the merged ones; their shadows (ray-marched or none) serve both.
        let scattering = match scattered {
            None => Scattering::Single,
            Some(s) if s.radiance().is_some() => Scattering::Grid {
                surfaces: Box::new(method.prepare(s.lights())?),
                scattered: s,
            },
            Some(s) => Scattering::Merged(s),
        };
        let (rendered, cached_lights) = match &scattering {
            Scattering::Single => (lights, RenderedLights::Emission),
            Scattering::Merged(s) => (s.lights(), RenderedLights::Merged),
            Scattering::Grid { .. } => (lights, RenderedLights::Emission),
        };
        // A skipped pass renders its emission lights with the shading its pilot made for them,
        // with a cache of the render's own form.
        let rendering = with_level0(form.for_lights(cached_lights));
        let shading = match pilot_shading {
            Some(mut shading) => {
                if shading.cache.is_some()
                    && form.for_lights(RenderedLights::Emission)
                        != form.for_lights(RenderedLights::Merged)
                {
                    let (density, hierarchy) = (&frame.density, rendered.hierarchy());
                    let cache = &rendering.lighting_cache;
                    shading.cache = Some(LightingCache::new(density, medium, hierarchy, cache)?);
                }
                shading
            }
            None => Shading::new(rendered, method, frame, medium, &rendering, progress)?,
        };
        let shadows = shading.shadow_seconds;
        let cache = shading.cache;
        Ok(FrameRender {
            emission: lights,
            method,
            prepared: shading.prepared,
            marcher: Marcher::with_visibility(frame, medium, settings, shading.visibility)?,
            cache,
            seconds: PrepareSeconds {
                scattering: scattering_seconds,
                shadows,
            },
            scattering,
        })
    }

    /// The same frame with opaque `surfaces` behind and around the smoke (a ground, a room:
    /// [`crate::surfaces`]), lit through the same lights and visibility.
    #[must_use]
    pub fn with_surfaces(mut self, surfaces: &'a dyn Surfaces) -> Self {
        self.marcher = self.marcher.with_surfaces(surfaces);
        self
    }

    /// Renders `camera`'s image, rows in parallel (nothing depends on the thread count);
    /// `progress` hears [`Phase::Render`] over rows, then, with adaptive pixels,
    /// [`Phase::Refinement`] over the pixels refined.
    pub fn render(
        &self,
        camera: &Camera,
        progress: &dyn Progress,
    ) -> Result<(Image, RenderStats), RenderError> {
        self.with_lit(|lit| self.marcher.render_lit(lit, camera, progress))
    }

    /// The pixels `(x, y)` of `pixels` only, exactly as [`render`](Self::render) computes them
    /// (for references and benchmarks on pixel subsets); pixels outside the image are an error.
    pub fn render_pixels(
        &self,
        camera: &Camera,
        pixels: &[[usize; 2]],
    ) -> Result<(Vec<Vec3>, RenderStats), RenderError> {
        self.with_lit(|lit| self.marcher.render_pixels_lit(lit, camera, pixels))
    }

    /// `f` with what the marcher shades with: the rendered lights through the method, split
    /// for the lighting cache if there is one.
    fn with_lit<R>(
        &self,
        f: impl FnOnce(Lit<'_, FrameBackend<'_>>) -> Result<R, RenderError>,
    ) -> Result<R, RenderError> {
        let lights = self.shading_lights()?;
        let cached = self.cached(lights.as_ref());
        let surface = match &self.scattering {
            Scattering::Grid { surfaces, .. } => surfaces.lights(self.lights())?,
            Scattering::Single | Scattering::Merged(_) => None,
        };
        let scattered = self.scattered().and_then(Scattered::radiance);
        f(Lit {
            lights: lights.as_ref(),
            cached: cached.as_ref(),
            scattered: scattered.map(|(r, _)| r),
            surface: surface.as_ref(),
        })
    }

    /// `lights` split for the lighting cache, if there is one (the hierarchy's only).
    fn cached<'l>(&'l self, lights: Option<&Lights<FrameBackend<'l>>>) -> Option<CachedLights<'l>> {
        CachedLights::of(self.cache.as_ref(), &self.marcher.volume().density, lights?)
    }

    /// The coarse levels' lighting cache, if the settings asked for one (the hierarchy's only):
    /// what it has computed so far.
    #[must_use]
    pub fn lighting_cache(&self) -> Option<&LightingCache> {
        self.cache.as_ref()
    }

    /// The lights the medium is shaded with through the method, with the fall-off clamp
    /// `h0 = h` (what [`Lights::incident`] shades a point with): [`lights`](Self::lights), or
    /// the emission lights when the scattered light comes as a grid
    /// ([`MarchSettings::scattered_grid`]); `None` for [`Method::Emission`].
    pub fn shading_lights(&self) -> Result<Option<Lights<FrameBackend<'_>>>, RenderError> {
        let medium = match self.scattering {
            Scattering::Grid { .. } => self.emission,
            Scattering::Single | Scattering::Merged(_) => self.lights(),
        };
        self.prepared.lights(medium)
    }

    /// Each scattering depth's share of `camera`'s image (`None` without scattering): renders
    /// the emission alone, each depth's lights alone ([`Scattered::depth_lights`]) and the
    /// geometric tail's ([`Scattered::tail_lights`]) through the method with the same shadows
    /// — `n + 2` renders, one more with a tail, which `progress` hears as one
    /// [`Phase::ScatterShares`] over all their rows. For brute force the parts add up to the
    /// image up to rounding (the marcher is linear in the lights' intensities); the hierarchy's
    /// centres are weighted by luminance, so for it they add up approximately.
    pub fn scatter_shares(
        &self,
        camera: &Camera,
        progress: &dyn Progress,
    ) -> Result<Option<Shares>, RenderError> {
        let Some(scattered) = self.scattered() else {
            return Ok(None);
        };
        let (frame, medium) = (self.marcher.volume(), self.marcher.medium());
        let settings = MarchSettings {
            scatter_depth: 0,
            ..*self.settings()
        };
        let depths = scattered.depths().len() + 1;
        let tail = scattered.tail_lights()?;
        let renders = depths + 1 + usize::from(tail.is_some());
        let rows = (renders * camera.height()) as u64;
        progress.begin(Phase::ScatterShares, rows);
        let steps = Steps::new(progress);
        let render = |lights: &ExplosionLights, method| {
            FrameRender::new(lights, method, frame, medium, &settings, &())?
                .render(camera, &steps)
                .map(|(image, _)| image)
        };
        let shares = (|| {
            let emitted = render(self.emission, Method::Emission)?;
            let images = (0..depths)
                .map(|k| render(&scattered.depth_lights(k)?, self.method))
                .collect::<Result<Vec<_>, _>>()?;
            let tail = tail.as_ref().map(|l| render(l, self.method)).transpose()?;
            Ok(Shares::of_images(&emitted, &images, tail.as_ref()))
        })();
        progress.end(Phase::ScatterShares);
        shares.map(Some)
    }

    /// The lights rendered: the merged lights of the scattering pass, or the emission lights.
    /// (With the scattered light as a grid, the merged lights light the surfaces, and the
    /// medium is shaded with the emission lights and the grid.)
    #[must_use]
    pub fn lights(&self) -> &ExplosionLights {
        self.scattered().map_or(self.emission, Scattered::lights)
    }

    /// The multiple-scattering pass, if the settings asked for one.
    #[must_use]
    pub fn scattered(&self) -> Option<&Scattered> {
        self.scattering.scattered()
    }

    /// The method.
    #[must_use]
    pub fn method(&self) -> Method {
        self.method
    }

    /// The settings (checked; `shadows` as the visibility was built).
    #[must_use]
    pub fn settings(&self) -> &MarchSettings {
        self.marcher.settings()
    }

    /// The lights' visibility.
    #[must_use]
    pub fn visibility(&self) -> &Visibility {
        self.marcher.visibility()
    }

    /// The cube maps, if the shadows are the paper's deep-shadow cube maps.
    #[must_use]
    pub fn cube_maps(&self) -> Option<&CubeMaps> {
        match self.visibility() {
            Visibility::CubeMaps(m) => Some(m),
            _ => None,
        }
    }

    /// What the preparation took.
    #[must_use]
    pub fn seconds(&self) -> PrepareSeconds {
        self.seconds
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::procedural;
    use crate::render::Framing;
    use crate::shadow::Shadows;

    #[test]
    fn a_sequence_frame_matches_the_frames_own_lights() {
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let a = procedural(32, 0.2).unwrap();
        let b = procedural(32, 0.8).unwrap();
        let mut seq = ExplosionLights::new(&[&a, &b], &m).unwrap();
        seq.set_frame(&b, &m).unwrap();
        // Frame b alone: its hot voxels are a subset, with the same intensities.
        let alone = ExplosionLights::new(&[&b], &m).unwrap();
        assert_eq!(alone.lit(), seq.lit());
        let lit = |s: &ExplosionLights| {
            s.lights()
                .iter()
                .filter(|l| l.intensity.max_element() > 0.0)
                .map(|l| (l.position, l.intensity))
                .collect::<Vec<_>>()
        };
        assert_eq!(lit(&alone), lit(&seq));
        // Dark lights add exactly nothing to eqs. 1-5, so with the same number of levels the
        // sequence renders the frame bit for bit as the frame's own lights do.
        assert_eq!(seq.hierarchy().max_level(), alone.hierarchy().max_level());
        let cam = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 12, 8).unwrap();
        let s = MarchSettings::default();
        let render = |lights| {
            FrameRender::new(lights, Method::Lgh { alpha: 2.0 }, &b, &m, &s, &())
                .and_then(|f| f.render(&cam, &()))
                .unwrap()
        };
        let (x, y) = (render(&seq), render(&alone));
        assert_eq!(x.0.pixels, y.0.pixels);
        assert!(x.0.pixels.iter().any(|p| p.max_element() > 0.0));
    }

    #[test]
    fn lgh_single_scattering_converges_to_brute_force() {
        let v = procedural(32, 0.4).unwrap();
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let s = ExplosionLights::new(&[&v], &m).unwrap();
        let cam = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 16, 16).unwrap();
        let pixels = [[8, 8], [6, 9], [10, 7], [5, 5]];
        for shadows in [Shadows::None, Shadows::RayMarch] {
            let march = MarchSettings {
                shadows,
                ..Default::default()
            };
            let render = |method| {
                FrameRender::new(&s, method, &v, &m, &march, &())
                    .and_then(|f| f.render_pixels(&cam, &pixels))
                    .unwrap()
                    .0
            };
            let exact = render(Method::Brute);
            let errs: Vec<f64> = [2.0f32, 64.0]
                .iter()
                .map(|&alpha| {
                    let got = render(Method::Lgh { alpha });
                    let num: f64 = got
                        .iter()
                        .zip(&exact)
                        .map(|(a, r)| f64::from((*a - *r).abs().max_element()))
                        .sum();
                    num / exact
                        .iter()
                        .map(|r| f64::from(r.max_element()))
                        .sum::<f64>()
                })
                .collect();
            // α = 64 puts every light in level 0 with weight 1: brute force up to summation
            // order. α = 2 stays within 10 % on these pixels (tests/explosion.rs bounds whole
            // images of a real frame, when the data is there).
            assert!(errs[1] < 1e-4, "{shadows:?}: {errs:?}");
            assert!(errs[0] < 0.1 && errs[1] < errs[0], "{shadows:?}: {errs:?}");
        }
    }

    #[test]
    fn the_scattered_light_as_a_grid_keeps_the_merged_lights_mean() {
        // The grid is the pass's own in-scattered radiance at the voxel centres (exact there:
        // `scattering`'s tests); between centres it is interpolated, where the merged lights
        // have the sub-voxel pattern of point lights clamped at one voxel. That pattern
        // averages out over the image: the means agree (measured −0.5% on the demo at 64³,
        // −1.1% on the Fig. 8-class frame, docs/shadows.md); bounded here at 3%.
        use crate::lighting_cache::{LightingCacheSettings, ScatteredLight};
        let v = procedural(32, 0.5).unwrap();
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let s = ExplosionLights::new(&[&v], &m).unwrap();
        let (lo, hi) = v.active_bounds().unwrap();
        let cam = Camera::frame(lo, hi, 40, 24).unwrap();
        let render = |scattered_light| {
            let march = MarchSettings {
                scatter_depth: 2,
                lighting_cache: LightingCacheSettings {
                    scattered_spacing: 1,
                    scattered_light,
                    ..LightingCacheSettings::coarse()
                },
                ..Default::default()
            };
            let frame =
                FrameRender::new(&s, Method::Lgh { alpha: 2.0 }, &v, &m, &march, &()).unwrap();
            let grid = frame.scattered().unwrap().radiance().is_some();
            let image = frame.render(&cam, &()).unwrap().0;
            let sum = image
                .pixels
                .iter()
                .map(|p| f64::from(lgh_core::luminance(*p)));
            (grid, sum.sum::<f64>())
        };
        let (merged, grid) = (render(ScatteredLight::Merged), render(ScatteredLight::Grid));
        assert!(!merged.0 && grid.0);
        let ratio = grid.1 / merged.1;
        eprintln!("grid / merged mean: {ratio:.4}");
        assert!(ratio != 1.0 && (ratio - 1.0).abs() < 0.03, "{ratio}");
    }
}
