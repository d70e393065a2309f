//! An explosion lit by itself, frame after frame (paper Sec. 3 and 6.1).
//!
//! The lights `S0` sit at the centres of the voxels that are hot in *any* frame of a sequence, so
//! their positions never move; each frame only changes their intensities `I0 = j h³`, which the
//! core's cheap rebuild ([`LightingGridHierarchy::update_intensities`]) absorbs. The grid of the
//! hierarchy is tied to the simulation grid as in the paper: `h0 = h`, `h1 = 2h`, level-1
//! vertices on voxel centres. Fixed positions and a fixed grid are what keep the approximation
//! from flickering: nothing is clustered anew each frame.

use std::borrow::Borrow;

use lgh_core::glam::Vec3;
use lgh_core::{
    BruteForce, Clustering, GridSettings, Illumination, LghBackend, LightPosition, LightTree,
    LightcutsBackend, LightcutsSettings, LightingGridHierarchy, ManyLights, PointLight, QueryError,
    Representative, Shader, ShadingPoint,
};
use lgh_image::Image;

use crate::error::VolumeError;
use crate::grid::DenseGrid;
use crate::lighting::Lights;
use crate::medium::{Medium, Volume};
#[cfg(test)]
use crate::render::Shadows;
use crate::render::{Camera, MarchSettings, Marcher, RenderStats};
use crate::shadow::{CubeMaps, Visibility, VolumeRays};

/// Which many-lights method shades the scattering (`--backend` of the CLI). The hierarchy's
/// α is a setting of its own, so that this stays a plain choice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Method {
    /// The lighting grid hierarchy (paper Sec. 3) at the paper's α.
    #[default]
    Lgh,
    /// Every light `S0`: the exact answer of the same light model.
    Brute,
    /// Lightcuts (Walter et al. 2005, the paper's Fig. 10 rival) at 2%: a light tree over the
    /// frame's lights with representatives drawn at random
    /// ([`set_lightcuts_seed`](ExplosionLights::set_lightcuts_seed); a new tree every frame, as
    /// the paper ran it), shadows ray-marched.
    Lightcuts,
    /// Lightcuts with each cluster's brightest light as its representative: no randomness.
    LightcutsDeterministic,
}

impl Method {
    /// The method's name, as in `lgh_core`'s [`ManyLights::name`] (`lgh`, `brute`, `lightcuts`,
    /// `lightcuts-deterministic`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::Lgh => "lgh",
            Method::Brute => "brute",
            Method::Lightcuts => "lightcuts",
            Method::LightcutsDeterministic => "lightcuts-deterministic",
        }
    }
}

/// The paper's flickering variants of the hierarchy (Secs. 3.1, 3.2, Fig. 9), each one choice
/// away from its method so that `lgh bench flicker` measures what each choice does to an
/// animation. The default is the paper's method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Variants {
    /// Trilinear splatting, or each light whole to its nearest vertex.
    pub clustering: Clustering,
    /// Coarse lights at their illumination centres, or at their grid vertices.
    pub position: LightPosition,
    /// Hard level switches instead of eq. (3)'s blending.
    pub hard_switches: bool,
}

/// The lights of a sequence of frames on one simulation grid.
#[derive(Clone, Debug)]
pub struct ExplosionLights {
    dims: [usize; 3],
    voxel_size: f32,
    origin: Vec3,
    /// Linear voxel index of each light.
    voxels: Vec<usize>,
    lights: Vec<PointLight>,
    hierarchy: LightingGridHierarchy,
    /// Weak-light pruning, a fraction of the frame's brightest light (see
    /// [`set_prune`](ExplosionLights::set_prune)).
    prune: f32,
    /// The hierarchy's variants (the paper's by default).
    variants: Variants,
    /// Seed of [`Method::Lightcuts`]' representatives.
    lightcuts_seed: u64,
    /// ε and the largest cut of the Lightcuts methods (Walter's 2% and 1000 by default).
    lightcuts: LightcutsSettings,
}

/// The grid of the paper's explosions (Sec. 6.1): `h1 = 2h`, level-1 vertices on voxel
/// centres (`origin`, a voxel centre), top level `max_level` (`None`: chosen from the lights).
fn explosion_grid(h: f32, origin: Vec3, max_level: Option<u8>) -> GridSettings {
    GridSettings {
        h1: Some(2.0 * h),
        origin: Some(origin),
        max_level,
        ..Default::default()
    }
}

/// `grid`'s layout (dimensions, voxel size, origin) without its values: what the lights'
/// positions are taken from.
fn layout_of(grid: &DenseGrid) -> DenseGrid {
    DenseGrid {
        dims: grid.dims,
        ..DenseGrid::zeros([0; 3], grid.voxel_size, grid.origin)
    }
}

/// Whether two grids have one layout (dimensions, voxel size, origin): what keeps the lights'
/// positions fixed over a sequence.
fn same_layout(a: &DenseGrid, b: &DenseGrid) -> bool {
    a.dims == b.dims && a.voxel_size == b.voxel_size && a.origin == b.origin
}

impl ExplosionLights {
    /// Lights at every voxel hotter than `T_min` in any of `frames`, with the intensities of
    /// `frames[0]`. Every frame's temperature (and flame) grid must have one layout (dimensions,
    /// voxel size, origin); the density may lie on another.
    pub fn new(frames: &[&Volume], medium: &Medium) -> Result<Self, VolumeError> {
        let first = frames.first().ok_or(VolumeError::NoFrames)?;
        let mut out = ExplosionLights::from_frames(frames.iter().map(|&f| Ok(f)), medium)?;
        out.set_frame(first, medium)?;
        Ok(out)
    }

    /// [`new`](Self::new) for frames that come one at a time (read from disk, say), each looked
    /// at once and then dropped; the lights are dark until [`set_frame`](Self::set_frame).
    pub fn from_frames<V: Borrow<Volume>>(
        frames: impl IntoIterator<Item = Result<V, VolumeError>>,
        medium: &Medium,
    ) -> Result<Self, VolumeError> {
        // The first frame's temperature layout, and which of its voxels are hot in any frame.
        let mut layout: Option<(DenseGrid, Vec<bool>)> = None;
        for (i, f) in frames.into_iter().enumerate() {
            let f = f?;
            let f = f.borrow();
            if f.flame
                .as_ref()
                .is_some_and(|fl| !same_layout(&f.temperature, fl))
            {
                return Err(VolumeError::FlameOffGrid { frame: Some(i) });
            }
            let (grid, hot) = layout.get_or_insert_with(|| {
                let t = &f.temperature;
                (layout_of(t), vec![false; t.data.len()])
            });
            if !same_layout(grid, &f.temperature) {
                return Err(VolumeError::FrameOffGrid { frame: Some(i) });
            }
            for (v, h) in hot.iter_mut().enumerate() {
                *h = *h || f.voxel_emits(medium, v);
            }
        }
        let (grid, hot) = layout.ok_or(VolumeError::NoFrames)?;
        let voxels: Vec<usize> = (0..hot.len()).filter(|&i| hot[i]).collect();
        let dark = vec![Vec3::ZERO; voxels.len()];
        ExplosionLights::at_voxels(&grid, voxels, &dark, None)
    }

    /// [`from_frames`](Self::from_frames)'s lights from their voxels (linear indices into the
    /// common grid, strictly ascending, as [`voxels`](Self::voxels) gives them) instead of
    /// from every frame: what a farm task rendering a few frames of a sequence takes from its
    /// manifest. `frame` is any frame of the sequence, for the grid's layout; the lights are
    /// dark until [`set_frame`](Self::set_frame). The same voxels give the same lights and
    /// hierarchy, bit for bit.
    ///
    /// ```
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let all = ExplosionLights::from_frames([Ok(&volume)], &medium)?;
    /// let again = ExplosionLights::at_hot_voxels(&volume, all.voxels().to_vec())?;
    /// assert_eq!(again.lights(), all.lights());
    /// assert!(ExplosionLights::at_hot_voxels(&volume, vec![3, 2]).is_err());
    /// # Ok::<(), lgh_volume::VolumeError>(())
    /// ```
    pub fn at_hot_voxels(frame: &Volume, voxels: Vec<usize>) -> Result<Self, VolumeError> {
        let t = &frame.temperature;
        let n = t.data.len();
        let bad = voxels
            .iter()
            .enumerate()
            .position(|(i, &v)| v >= n || (i > 0 && v <= voxels[i - 1]));
        if let Some(at) = bad {
            return Err(VolumeError::BadLightVoxels { at, voxels: n });
        }
        let grid = layout_of(t);
        let dark = vec![Vec3::ZERO; voxels.len()];
        ExplosionLights::at_voxels(&grid, voxels, &dark, None)
    }

    /// Lights at the centres of `voxels` (linear indices, ascending, into `grid`'s layout: its
    /// dimensions, voxel size and origin; its values are not read) with `intensities`, built into
    /// the hierarchy of the paper's explosions: `h1 = 2h`, level-1 vertices on voxel centres
    /// (Sec. 6.1), top level `max_level` (`None`: chosen from the lights). The one constructor of
    /// every explosion light set: the emission lights of [`from_frames`](Self::from_frames) and
    /// the scattered and merged lights of [`crate::scattering`], which must share one grid.
    pub(crate) fn at_voxels(
        grid: &DenseGrid,
        voxels: Vec<usize>,
        intensities: &[Vec3],
        max_level: Option<u8>,
    ) -> Result<Self, VolumeError> {
        if intensities.len() != voxels.len() {
            return Err(VolumeError::Lights(lgh_core::BuildError::LengthMismatch {
                expected: voxels.len(),
                got: intensities.len(),
            }));
        }
        let lights = voxels
            .iter()
            .zip(intensities)
            .map(|(&idx, &intensity)| {
                let [i, j, k] = crate::grid::unflatten(idx, grid.dims);
                PointLight::new(grid.centre(i, j, k), intensity)
            })
            .collect::<Vec<_>>();
        let settings = explosion_grid(grid.voxel_size, grid.origin, max_level);
        let hierarchy = LightingGridHierarchy::build(&lights, &settings)?;
        let h = grid.voxel_size;
        Ok(ExplosionLights {
            dims: grid.dims,
            voxel_size: h,
            origin: grid.origin,
            voxels,
            lights,
            hierarchy,
            prune: 0.0,
            variants: Variants::default(),
            lightcuts_seed: 0,
            lightcuts: LightcutsSettings::default(),
        })
    }

    /// The same lights with the hierarchy rebuilt as `variants` say (one of the paper's
    /// flickering alternatives, for measuring them); the intensities and pruning are kept.
    ///
    /// ```
    /// use lgh_volume::lgh_core::Clustering;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Variants};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let paper = ExplosionLights::new(&[&volume], &medium)?;
    /// let nearest = Variants { clustering: Clustering::NearestVertex, ..Default::default() };
    /// let variant = paper.clone().with_variants(nearest)?;
    /// assert_eq!(variant.variants(), nearest);
    /// assert_eq!(variant.lights(), paper.lights());
    /// assert_ne!(variant.hierarchy().level(1), paper.hierarchy().level(1));
    /// # Ok::<(), lgh_volume::VolumeError>(())
    /// ```
    pub fn with_variants(mut self, variants: Variants) -> Result<Self, VolumeError> {
        // Hard switches are the blending's, chosen per backend: only clustering and positions
        // make another hierarchy (the build is deterministic, so an unchanged one is the same).
        let same = (variants.clustering, variants.position)
            == (self.variants.clustering, self.variants.position);
        if !same {
            let settings = GridSettings {
                clustering: variants.clustering,
                position: variants.position,
                ..explosion_grid(
                    self.voxel_size,
                    self.origin,
                    Some(self.hierarchy.max_level()),
                )
            };
            self.hierarchy = LightingGridHierarchy::build(&self.lights, &settings)?;
            self.apply_prune()?;
        }
        self.variants = variants;
        Ok(self)
    }

    /// The hierarchy's variants ([`with_variants`](Self::with_variants)).
    #[must_use]
    pub fn variants(&self) -> Variants {
        self.variants
    }

    /// The seed of [`Method::Lightcuts`]' random representatives: the paper's comparison draws
    /// a new tree every frame, so a sequence sets a new seed per frame.
    pub fn set_lightcuts_seed(&mut self, seed: u64) {
        self.lightcuts_seed = seed;
    }

    /// ε and the largest cut of the Lightcuts methods (Walter's 2% and 1000 by default),
    /// checked when a backend is made.
    pub fn set_lightcuts_settings(&mut self, settings: LightcutsSettings) {
        self.lightcuts = settings;
    }

    /// The Lightcuts methods' ε and largest cut.
    #[must_use]
    pub fn lightcuts_settings(&self) -> LightcutsSettings {
        self.lightcuts
    }

    /// Prunes weak lights, as the paper does "for additional optimization" (Sec. 6): the
    /// hierarchy's queries skip, on every level but the top one, the lights whose luminance is
    /// below `fraction` of the brightest light of the frame (their energy still reaches the
    /// coarser levels, built from all lights). Re-applied to each new frame's intensities. 0 (the
    /// default) prunes nothing; a fraction outside `[0, 1)` is an error.
    ///
    /// ```
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let mut lights = ExplosionLights::new(&[&volume], &medium)?;
    /// let active = |l: &ExplosionLights| {
    ///     let h = l.hierarchy();
    ///     h.level(0).iter().filter(|g| h.is_active(0, g)).count()
    /// };
    /// let all = active(&lights);
    /// lights.set_prune(1e-2)?;
    /// assert!(active(&lights) < all);
    /// assert!(lights.set_prune(1.0).is_err());
    /// # Ok::<(), lgh_volume::VolumeError>(())
    /// ```
    pub fn set_prune(&mut self, fraction: f32) -> Result<(), VolumeError> {
        crate::error::check_setting(
            (0.0..1.0).contains(&fraction),
            "weak-light pruning",
            fraction,
            "must be a fraction of the brightest light in [0, 1)",
        )?;
        self.prune = fraction;
        self.apply_prune()
    }

    /// The pruning fraction of [`set_prune`](Self::set_prune).
    #[must_use]
    pub fn prune(&self) -> f32 {
        self.prune
    }

    /// Luminance of the frame's brightest light: what [`set_prune`](Self::set_prune)'s fraction
    /// is of.
    #[must_use]
    pub fn brightest(&self) -> f32 {
        self.lights
            .iter()
            .map(|l| lgh_core::luminance(l.intensity))
            .fold(0.0f32, f32::max)
    }

    /// Sets the hierarchy's threshold from the current intensities.
    fn apply_prune(&mut self) -> Result<(), VolumeError> {
        self.hierarchy
            .set_prune_below(self.prune * self.brightest())?;
        Ok(())
    }

    /// Whether `grid` has the lights' layout (dimensions, voxel size, origin).
    pub(crate) fn on_grid(&self, grid: &DenseGrid) -> bool {
        grid.dims == self.dims && grid.voxel_size == self.voxel_size && grid.origin == self.origin
    }

    /// Linear voxel index of each light into the common grid, strictly ascending: what
    /// [`at_hot_voxels`](Self::at_hot_voxels) takes back.
    #[must_use]
    pub fn voxels(&self) -> &[usize] {
        &self.voxels
    }

    /// Replaces the intensities (one per light, in the order of [`lights`](Self::lights)),
    /// keeping every position: the hierarchy's cheap rebuild.
    pub(crate) fn set_intensities(&mut self, intensities: &[Vec3]) -> Result<(), VolumeError> {
        self.hierarchy.update_intensities(intensities)?;
        for (l, &i) in self.lights.iter_mut().zip(intensities) {
            l.intensity = i;
        }
        if self.prune > 0.0 {
            self.apply_prune()?;
        }
        Ok(())
    }

    /// Sets the intensities to those of `frame` (same grid as at construction) and rebuilds the
    /// hierarchy's intensities, keeping every position.
    pub fn set_frame(&mut self, frame: &Volume, medium: &Medium) -> Result<(), VolumeError> {
        let t = &frame.temperature;
        if frame.flame.as_ref().is_some_and(|f| !same_layout(f, t)) {
            return Err(VolumeError::FlameOffGrid { frame: None });
        }
        if !self.on_grid(t) {
            return Err(VolumeError::FrameOffGrid { frame: None });
        }
        let h3 = self.voxel_size.powi(3);
        let intensities: Vec<Vec3> = self
            .voxels
            .iter()
            .map(|&idx| frame.voxel_emission(medium, idx) * h3)
            .collect();
        self.set_intensities(&intensities)
    }

    /// The lights `S0` (every candidate voxel; cold ones have zero intensity this frame).
    #[must_use]
    pub fn lights(&self) -> &[PointLight] {
        &self.lights
    }

    /// Number of lights with non-zero intensity this frame.
    #[must_use]
    pub fn lit(&self) -> usize {
        self.lights
            .iter()
            .filter(|l| l.intensity.max_element() > 0.0)
            .count()
    }

    /// The hierarchy over the lights.
    #[must_use]
    pub fn hierarchy(&self) -> &LightingGridHierarchy {
        &self.hierarchy
    }

    /// This frame's lights through `method` (`alpha`: the hierarchy's α; brute force takes only
    /// the lights that shine), with the fall-off clamped at the voxel size (`h0 = h`, paper
    /// Sec. 6.1): what [`render`](fn@crate::render::render) and [`Lights::incident`] take.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::ShadingPoint;
    /// use lgh_volume::lighting::LightScratch;
    /// use lgh_volume::render::RenderStats;
    /// use lgh_volume::shadow::Visibility;
    /// use lgh_volume::{procedural, ExplosionLights, Medium, Method};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let explosion = ExplosionLights::new(&[&volume], &medium)?;
    /// let at = ShadingPoint::in_medium(Vec3::new(0.0, 0.5, 0.0));
    /// let mut incident = |method| -> Result<Vec3, lgh_volume::VolumeError> {
    ///     let lights = explosion.backend(method, 64.0)?;
    ///     let (mut scratch, mut stats) = (LightScratch::default(), RenderStats::default());
    ///     Ok(lights.incident(&at, &Visibility::None, |_| Vec3::ONE, &mut scratch, &mut stats)?)
    /// };
    /// // At α = 64 every light is in level 0 with weight 1: brute force up to rounding.
    /// let (lgh, brute) = (incident(Method::Lgh)?, incident(Method::Brute)?);
    /// assert!((lgh - brute).abs().max_element() <= 1e-4 * brute.max_element());
    /// # Ok::<(), lgh_volume::VolumeError>(())
    /// ```
    pub fn backend(
        &self,
        method: Method,
        alpha: f32,
    ) -> Result<Lights<FrameBackend<'_>>, VolumeError> {
        let lit = || -> Vec<PointLight> {
            self.lights
                .iter()
                .copied()
                .filter(|l| l.intensity.max_element() > 0.0)
                .collect()
        };
        let lightcuts = |representative| -> Result<FrameBackend<'_>, VolumeError> {
            let tree = LightTree::build(&lit(), representative)?;
            let settings = self.lightcuts;
            // Checked once here; the backend is remade per query from the tree it owns.
            LightcutsBackend::new(&tree, settings)?;
            Ok(FrameBackend::Lightcuts(Box::new(tree), settings))
        };
        let backend = match method {
            Method::Lgh => {
                let mut blending = self.hierarchy.blending(alpha)?;
                if self.variants.hard_switches {
                    blending = blending.with_hard_switches();
                }
                FrameBackend::Lgh(LghBackend::with_blending(&self.hierarchy, blending)?)
            }
            Method::Brute => FrameBackend::Brute(BruteForce::new(&lit())?),
            Method::Lightcuts => lightcuts(Representative::Stochastic {
                seed: self.lightcuts_seed,
            })?,
            Method::LightcutsDeterministic => lightcuts(Representative::Brightest)?,
        };
        Ok(Lights::new(backend, self.voxel_size))
    }

    /// The visibility `settings.shadows` asks for, for this frame's lights through `method` at
    /// `alpha`: with [`Shadows::CubeMap`](crate::Shadows::CubeMap) and the hierarchy, its
    /// deep-shadow cube maps ([`CubeMaps::build`]: refused before any work if they would not
    /// fit `settings.cube_maps.memory_budget`; `progress(n)` as `n` more lights' maps are
    /// done); brute force, which has no hierarchy, ray-marches.
    pub fn visibility(
        &self,
        method: Method,
        alpha: f32,
        frame: &Volume,
        medium: &Medium,
        settings: &MarchSettings,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Visibility, VolumeError> {
        settings.check()?;
        if settings.shadows == crate::Shadows::CubeMap && method == Method::Lgh {
            let blending = self.hierarchy.blending(alpha)?;
            let maps = CubeMaps::build(
                &self.hierarchy,
                &blending,
                frame,
                medium,
                &settings.cube_maps,
                progress,
            )?;
            return Ok(Visibility::CubeMaps(maps));
        }
        if settings.shadows == crate::Shadows::RayMarchVolumes && method == Method::Lgh {
            return Ok(Visibility::VolumeRays(VolumeRays::new(
                &self.hierarchy,
                &self.hierarchy.blending(alpha)?,
                frame,
                medium,
                &settings.cube_maps,
                settings.shadow_step_voxels,
                settings.min_transmittance,
            )));
        }
        Ok(Visibility::new(
            settings.shadows,
            frame,
            medium,
            settings.shadow_step_voxels,
            settings.min_transmittance,
        ))
    }

    /// The marcher of `frame` with the visibility of [`visibility`](Self::visibility): what
    /// [`render`](Self::render) renders with, for a caller that adds to it (surfaces:
    /// [`Marcher::with_surfaces`]).
    pub fn marcher<'a>(
        &self,
        method: Method,
        alpha: f32,
        frame: &'a Volume,
        medium: &'a Medium,
        settings: &MarchSettings,
    ) -> Result<Marcher<'a>, VolumeError> {
        let visibility = self.visibility(method, alpha, frame, medium, settings, &|_| {})?;
        Marcher::with_visibility(frame, medium, settings, visibility)
    }

    /// Renders `frame` (whose intensities were set by [`set_frame`](Self::set_frame) or
    /// [`new`](Self::new)) through `method` at `alpha`; `progress(rows)` as rows finish.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &self,
        method: Method,
        alpha: f32,
        frame: &Volume,
        medium: &Medium,
        camera: &Camera,
        settings: &MarchSettings,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<(Image, RenderStats), VolumeError> {
        let lights = self.backend(method, alpha)?;
        self.marcher(method, alpha, frame, medium, settings)?
            .render(Some(&lights), camera, progress)
    }

    /// Renders only the pixels `(x, y)` of `pixels`, as [`render`](Self::render) would.
    #[allow(clippy::too_many_arguments)]
    pub fn render_pixels(
        &self,
        method: Method,
        alpha: f32,
        frame: &Volume,
        medium: &Medium,
        camera: &Camera,
        settings: &MarchSettings,
        pixels: &[[usize; 2]],
    ) -> Result<(Vec<Vec3>, RenderStats), VolumeError> {
        let lights = self.backend(method, alpha)?;
        self.marcher(method, alpha, frame, medium, settings)?
            .render_pixels(Some(&lights), camera, pixels)
    }
}

/// A [`Method`] made ready over one frame's lights: one type for the renderer, whichever
/// method was chosen. (One value per render, so the variants' size difference costs nothing.)
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum FrameBackend<'a> {
    /// The hierarchy at one α.
    Lgh(LghBackend<'a>),
    /// Every light that shines this frame.
    Brute(BruteForce),
    /// Lightcuts over a light tree of the frame's lights.
    Lightcuts(Box<LightTree>, LightcutsSettings),
}

impl ManyLights for FrameBackend<'_> {
    fn name(&self) -> &'static str {
        match self {
            FrameBackend::Lgh(b) => b.name(),
            FrameBackend::Brute(b) => b.name(),
            FrameBackend::Lightcuts(..) => "lightcuts",
        }
    }

    fn selection_follows_shader(&self) -> bool {
        matches!(self, FrameBackend::Lightcuts(..))
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        match self {
            FrameBackend::Lgh(b) => b.illuminate(point, shader),
            FrameBackend::Brute(b) => b.illuminate(point, shader),
            FrameBackend::Lightcuts(tree, settings) => {
                LightcutsBackend::new(tree, *settings)?.illuminate(point, shader)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::procedural;
    use crate::render::Framing;

    #[test]
    fn pruning_follows_each_frames_brightest_light() {
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let a = procedural(32, 0.2).unwrap();
        let b = procedural(32, 0.8).unwrap();
        let mut seq = ExplosionLights::new(&[&a, &b], &m).unwrap();
        seq.set_frame(&a, &m).unwrap();
        seq.set_prune(1e-3).unwrap();
        assert_eq!(seq.hierarchy().prune_below(), 1e-3 * seq.brightest());
        seq.set_frame(&b, &m).unwrap();
        assert_eq!(seq.hierarchy().prune_below(), 1e-3 * seq.brightest());
        assert!(seq.hierarchy().prune_below() > 0.0);
        // A bad fraction changes nothing.
        assert!(seq.set_prune(f32::NAN).is_err());
        assert_eq!(seq.prune(), 1e-3);
    }

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
        let none = &|_: usize| {};
        let x = seq
            .render(Method::Lgh, 2.0, &b, &m, &cam, &s, none)
            .unwrap();
        let y = alone
            .render(Method::Lgh, 2.0, &b, &m, &cam, &s, none)
            .unwrap();
        assert_eq!(x.0.pixels, y.0.pixels);
        assert!(x.0.pixels.iter().any(|p| p.max_element() > 0.0));
    }

    #[test]
    fn frames_on_other_grids_are_refused() {
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let a = procedural(32, 0.2).unwrap();
        let b = procedural(40, 0.2).unwrap();
        assert!(ExplosionLights::new(&[&a, &b], &m).is_err());
        assert!(ExplosionLights::new(&[], &m).is_err());
        let mut s = ExplosionLights::new(&[&a], &m).unwrap();
        assert!(s.set_frame(&b, &m).is_err());
    }

    #[test]
    fn lights_carry_the_emitted_power_of_their_voxels() {
        let v = procedural(32, 0.3).unwrap();
        let medium = Medium::new(1.0, 1.0, 1e-3, 1000.0).unwrap();
        let s = ExplosionLights::new(&[&v], &medium).unwrap();
        let hot = v.temperature.data.iter().filter(|&&t| t > 1000.0).count();
        assert_eq!((s.lights.len(), s.lit()), (hot, hot));
        let h3 = v.temperature.voxel_size.powi(3);
        for (l, &idx) in s.lights.iter().zip(&s.voxels).step_by(17) {
            let want = medium.emission_at(v.temperature.data[idx]) * h3;
            assert_eq!(l.intensity, want);
            assert!(v.temperature.sample(l.position) > 1000.0 * 0.999);
        }
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
            let render = |b, alpha| {
                s.render_pixels(b, alpha, &v, &m, &cam, &march, &pixels)
                    .unwrap()
                    .0
            };
            let exact = render(Method::Brute, 0.0);
            let errs: Vec<f64> = [2.0f32, 64.0]
                .iter()
                .map(|&alpha| {
                    let got = render(Method::Lgh, alpha);
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
}
