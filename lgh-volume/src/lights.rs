//! An explosion lit by itself, frame after frame (paper Sec. 3 and 6.1).
//!
//! The lights `S0` sit at the centres of the voxels that are hot in *any* frame of a sequence, so
//! their positions never move; each frame only changes their intensities `I0 = j h³`, which the
//! core's cheap rebuild ([`LightingGridHierarchy::update_intensities`]) absorbs. The grid of the
//! hierarchy is tied to the simulation grid as in the paper: `h0 = h`, `h1 = 2h`, level-1
//! vertices on voxel centres. Fixed positions and a fixed grid are what keep the approximation
//! from flickering: nothing is clustered anew each frame.

use std::borrow::Borrow;
use std::sync::Arc;

use lgh_core::glam::Vec3;
use lgh_core::{
    Clustering, CoarseSpread, GridSettings, LightPosition, LightingGridHierarchy, NearField,
    PointLight,
};

use crate::error::RenderError;
use crate::grid::DenseGrid;
use crate::medium::{Medium, Volume};
use crate::shadow::CoarseShadows;
use crate::voxel_smoke::VoxelSmoke;

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
    /// Coarse lights' shadows through the prefiltered density (eq. 6), or as points.
    pub coarse_shadows: CoarseShadows,
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
    /// Voxel lights or the paper's points ([`with_near_field`](Self::with_near_field)).
    near_field: NearField,
    /// Coarse lights weighted at their centres or averaged over their spread
    /// ([`set_coarse_spread`](Self::set_coarse_spread)).
    coarse_spread: CoarseSpread,
    /// The smoke in each voxel light's own voxel, of the frame set last (voxel lights only:
    /// [`smoke`](Self::smoke)).
    smoke: Option<Arc<VoxelSmoke>>,
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

/// Whether `frame`'s flame and RGB emission grids lie on its temperature's layout (`frame`:
/// its index in a sequence, for the error).
fn check_factors(frame: &Volume, index: Option<usize>) -> Result<(), RenderError> {
    let t = &frame.temperature;
    if frame.flame.as_ref().is_some_and(|f| !f.same_layout(t)) {
        return Err(RenderError::FlameOffGrid { frame: index });
    }
    if let Some(colour) = frame.colour.as_deref() {
        if colour.iter().any(|c| !c.same_layout(t)) {
            return Err(RenderError::ColourOffGrid { frame: index });
        }
    }
    Ok(())
}

impl ExplosionLights {
    /// Lights at every voxel whose cell or centre emits in any of `frames`
    /// ([`Volume::emitting_cells`]), with the intensities of
    /// `frames[0]`. Every frame's temperature (and flame) grid must have one layout (dimensions,
    /// voxel size, origin); the density may lie on another.
    pub fn new(frames: &[&Volume], medium: &Medium) -> Result<Self, RenderError> {
        let first = frames.first().ok_or(RenderError::NoFrames)?;
        let frames = frames.iter().map(|&f| Ok::<_, RenderError>(f));
        let mut out = ExplosionLights::from_frames(frames, medium)?;
        out.set_frame(first, medium)?;
        Ok(out)
    }

    /// [`new`](Self::new) for frames that come one at a time (read from disk, say), each looked
    /// at once and then dropped; the lights are dark until [`set_frame`](Self::set_frame).
    /// The frames may fail as they come (a [`ReadError`](crate::ReadError) of a sequence's
    /// file, say): the first failure is returned.
    pub fn from_frames<V: Borrow<Volume>, E: Into<RenderError>>(
        frames: impl IntoIterator<Item = Result<V, E>>,
        medium: &Medium,
    ) -> Result<Self, RenderError> {
        // The first frame's temperature layout, and which of its voxels are hot in any frame.
        let mut layout: Option<(DenseGrid, Vec<bool>)> = None;
        for (i, f) in frames.into_iter().enumerate() {
            let f = f.map_err(Into::into)?;
            let f = f.borrow();
            check_factors(f, Some(i))?;
            let (grid, hot) = layout.get_or_insert_with(|| {
                let t = &f.temperature;
                (layout_of(t), vec![false; t.data.len()])
            });
            if !grid.same_layout(&f.temperature) {
                return Err(RenderError::FrameOffGrid { frame: Some(i) });
            }
            for (h, emits) in hot.iter_mut().zip(f.emitting_cells(medium)) {
                *h = *h || emits;
            }
        }
        let (grid, hot) = layout.ok_or(RenderError::NoFrames)?;
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
    /// let all = ExplosionLights::from_frames([Ok::<_, lgh_volume::ReadError>(&volume)], &medium)?;
    /// let again = ExplosionLights::at_hot_voxels(&volume, all.voxels().to_vec())?;
    /// assert_eq!(again.lights(), all.lights());
    /// assert!(ExplosionLights::at_hot_voxels(&volume, vec![3, 2]).is_err());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn at_hot_voxels(frame: &Volume, voxels: Vec<usize>) -> Result<Self, RenderError> {
        let t = &frame.temperature;
        let n = t.data.len();
        let bad = voxels
            .iter()
            .enumerate()
            .position(|(i, &v)| v >= n || (i > 0 && v <= voxels[i - 1]));
        if let Some(at) = bad {
            return Err(RenderError::BadLightVoxels { at, voxels: n });
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
    ) -> Result<Self, RenderError> {
        if intensities.len() != voxels.len() {
            return Err(RenderError::Lights(lgh_core::BuildError::LengthMismatch {
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
            near_field: NearField::default(),
            coarse_spread: CoarseSpread::Centre,
            smoke: None,
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
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn with_variants(mut self, variants: Variants) -> Result<Self, RenderError> {
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

    /// Sets how coarse lights cast shadows ([`Variants::coarse_shadows`]), which needs no
    /// rebuild: the one variant a scattering pass carries from the emission lights to its own
    /// ([`crate::scattering`]), since the render's shadows are one choice.
    ///
    /// ```
    /// use lgh_volume::shadow::CoarseShadows;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let mut lights = ExplosionLights::new(&[&volume], &medium)?;
    /// lights.set_coarse_shadows(CoarseShadows::Points);
    /// assert_eq!(lights.variants().coarse_shadows, CoarseShadows::Points);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn set_coarse_shadows(&mut self, coarse: CoarseShadows) {
        self.variants.coarse_shadows = coarse;
    }

    /// The hierarchy's variants ([`with_variants`](Self::with_variants)).
    #[must_use]
    pub fn variants(&self) -> Variants {
        self.variants
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
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn set_prune(&mut self, fraction: f32) -> Result<(), RenderError> {
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
    fn apply_prune(&mut self) -> Result<(), RenderError> {
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
    pub(crate) fn set_intensities(&mut self, intensities: &[Vec3]) -> Result<(), RenderError> {
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
    pub fn set_frame(&mut self, frame: &Volume, medium: &Medium) -> Result<(), RenderError> {
        let t = &frame.temperature;
        check_factors(frame, None)?;
        if !self.on_grid(t) {
            return Err(RenderError::FrameOffGrid { frame: None });
        }
        let (h, h3) = (self.voxel_size, self.voxel_size.powi(3));
        let (intensities, smoke): (Vec<Vec3>, _) = match self.near_field {
            NearField::Voxel => {
                // Each voxel light emits what its cell does, its near field centred where the
                // cell emits (`crate::voxel_light`).
                let (cells, centres): (Vec<Vec3>, Vec<Vec3>) = self
                    .voxels
                    .iter()
                    .map(|&idx| frame.cell_light(medium, idx))
                    .unzip();
                let centroids = self
                    .voxels
                    .iter()
                    .zip(centres)
                    .filter(|(_, c)| *c != Vec3::ZERO)
                    .map(|(&idx, c)| (idx, c * h));
                let smoke = VoxelSmoke::of(t, &frame.density, medium).with_centroids(centroids);
                let intensities = cells.into_iter().map(|j| j * h3).collect();
                (intensities, Some(Arc::new(smoke)))
            }
            NearField::Clamp => {
                let intensities = self
                    .voxels
                    .iter()
                    .map(|&idx| frame.voxel_emission(medium, idx) * h3)
                    .collect();
                (intensities, None)
            }
        };
        self.set_intensities(&intensities)?;
        self.smoke = smoke;
        Ok(())
    }

    /// The smoke in each light's own voxel, of the frame set last ([`set_frame`](Self::set_frame)),
    /// through which a voxel light's light escapes (`lgh_core::near_field::escape`); `None` for
    /// the paper's points and for lights whose frame is not set yet.
    ///
    /// ```
    /// use lgh_volume::lgh_core::NearField;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let lights = ExplosionLights::new(&[&volume], &medium)?;
    /// let smoke = lights.smoke().unwrap();
    /// let d = &volume.density;
    /// let (i, j, k) = (16, 16, 16);
    /// let want = medium.extinction(d.get(i, j, k)) * d.voxel_size;
    /// assert_eq!(smoke.at(d.centre(i, j, k)), want);
    /// let points = lights.with_near_field(NearField::Clamp, &volume, &medium)?;
    /// assert!(points.smoke().is_none());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn smoke(&self) -> Option<&Arc<VoxelSmoke>> {
        self.smoke.as_ref()
    }

    /// Sets the smoke of the lights' voxels: scattered lights on the emission's grid take the
    /// emission lights' ([`smoke`](Self::smoke)), their near field centred on their voxels or,
    /// merged, as their emission's share of it says (`crate::scattering`).
    pub(crate) fn set_smoke(&mut self, smoke: Option<Arc<VoxelSmoke>>) {
        self.smoke = smoke;
    }

    /// The same lights as voxels or as the paper's points, their intensities taken anew from
    /// `frame`: with [`NearField::Voxel`] (the default) each light is a uniform emitting voxel,
    /// `I0 = ∫_cell j dx` ([`Volume::cell_emission`]) with the voxel's near field
    /// ([`lgh_core::near_field`]); with [`NearField::Clamp`], the paper's point of intensity
    /// `I0 = j(T_i) h³` ([`Volume::voxel_emission`]) with the fall-off clamped at `h`.
    ///
    /// ```
    /// use lgh_volume::lgh_core::NearField;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural::ball(16, 0.7, 3000.0);
    /// let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0)?;
    /// let voxels = ExplosionLights::new(&[&volume], &medium)?;
    /// assert_eq!(voxels.near_field(), NearField::Voxel);
    /// let points = voxels.clone().with_near_field(NearField::Clamp, &volume, &medium)?;
    /// let total = |l: &ExplosionLights| l.lights().iter().map(|p| p.intensity.x).sum::<f32>();
    /// assert!(total(&points) > total(&voxels)); // centres overshoot their cells (j convex in T)
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn with_near_field(
        mut self,
        near_field: NearField,
        frame: &Volume,
        medium: &Medium,
    ) -> Result<Self, RenderError> {
        self.near_field = near_field;
        self.set_frame(frame, medium)?;
        Ok(self)
    }

    /// Whether the lights are voxels or points ([`with_near_field`](Self::with_near_field)).
    #[must_use]
    pub fn near_field(&self) -> NearField {
        self.near_field
    }

    /// Sets whether the lights are voxels or points, their intensities following at the next
    /// [`set_frame`](Self::set_frame) ([`with_near_field`](Self::with_near_field) does both):
    /// for a sequence whose frames come one at a time. A scattering pass's lights take the
    /// emission lights' model this way, their intensities coming from the pass.
    pub fn set_near_field(&mut self, near_field: NearField) {
        self.near_field = near_field;
    }

    /// How the hierarchy weighs its coarse lights ([`CoarseSpread`]): at their centres as the
    /// paper prints eq. (3) (the default), or averaged over the spread of the voxels each stands
    /// for, which makes eq. (3)'s blended fall-off the exact sum over the voxels to about 0.1% on
    /// a uniform cloud at α = 2, where at the centres it is up to 2% bright outside the cloud
    /// (`lgh_core`'s `blend::spread`). Averaged costs more (each level's support reaches further)
    /// and is not yet the default: on Blender's fires its images move away from Cycles', whose
    /// other biases the hierarchy's surplus had offset (docs/cycles.md, "The hierarchy's α-2
    /// error, taken apart"). Hard level switches ([`Variants::hard_switches`]) take every light
    /// at its centre.
    ///
    /// ```
    /// use lgh_volume::lgh_core::CoarseSpread;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural::ball(16, 0.7, 3000.0);
    /// let medium = Medium::new(0.5, 4.5, 1e-3, 1000.0)?;
    /// let mut lights = ExplosionLights::new(&[&volume], &medium)?;
    /// assert_eq!(lights.coarse_spread(), CoarseSpread::Centre);
    /// lights.set_coarse_spread(CoarseSpread::Averaged);
    /// assert_eq!(lights.coarse_spread(), CoarseSpread::Averaged);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn set_coarse_spread(&mut self, spread: CoarseSpread) {
        self.coarse_spread = spread;
    }

    /// How the hierarchy weighs its coarse lights ([`set_coarse_spread`](Self::set_coarse_spread)).
    #[must_use]
    pub fn coarse_spread(&self) -> CoarseSpread {
        self.coarse_spread
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

    /// The voxel size `h` of the lights' grid: the fall-off clamp `h0 = h` of the paper's
    /// explosions (Sec. 6.1).
    #[must_use]
    pub fn voxel_size(&self) -> f32 {
        self.voxel_size
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::procedural;

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
        let n = v.temperature.data.len();
        let hot = v.temperature.data.iter().filter(|&&t| t > 1000.0).count();
        let cells = (0..n).filter(|&i| v.cell_emits(&medium, i)).count();
        // A light at every emitting cell: the hot voxels and the cells they warm.
        assert_eq!(s.lit(), cells);
        assert!(
            s.lights.len() >= cells && cells > hot,
            "{cells} cells, {hot} hot"
        );
        let h3 = v.temperature.voxel_size.powi(3);
        let points = s
            .clone()
            .with_near_field(NearField::Clamp, &v, &medium)
            .unwrap();
        assert_eq!(points.lit(), hot);
        let lights = s.lights.iter().zip(&points.lights).zip(&s.voxels);
        for ((voxel, point), &idx) in lights.step_by(17) {
            // A voxel light emits what its cell does, a point light its centre's emission.
            assert_eq!(voxel.intensity, v.cell_emission(&medium, idx) * h3);
            assert_eq!(
                point.intensity,
                medium.emission_at(v.temperature.data[idx]) * h3
            );
            assert_eq!(voxel.position, point.position);
        }
    }

    #[test]
    fn voxel_lights_hold_every_cells_emitted_power() {
        // The lights' intensities add up to the emission integrated over every cell of the grid
        // (`Volume::cell_emission`, the same quadrature): nothing is lost at the cells beside the
        // hot voxels, whichever interpolation, with a flame factor and with RGB emission. Lights
        // at the hot voxels alone held 0.9930 of it with `attributes` on Blender's 64³ fires.
        // The bound is the f32 sums' rounding (the two sums differ only in order and in the
        // cells that emit nothing).
        let ball = crate::procedural::ball(16, 0.6, 2600.0);
        let mut flamed = ball.clone();
        let mut flame = ball.temperature.clone();
        for (i, f) in flame.data.iter_mut().enumerate() {
            *f = 0.25 + 0.75 * ((i * 7919) % 13) as f32 / 12.0;
        }
        flamed.flame = Some(flame);
        let colour = |c: usize| {
            let mut g = ball.temperature.clone();
            for (i, v) in g.data.iter_mut().enumerate() {
                *v = (ball.temperature.data[i] - 1500.0).max(0.0) * (1.0 + c as f32);
            }
            g
        };
        let rgb = Volume::with_colour(ball.density.clone(), [0, 1, 2].map(colour)).unwrap();
        let temperature = Medium::new(0.5, 4.5, 1e-3, 1000.0).unwrap();
        let attributes = temperature
            .clone()
            .with_interpolation(crate::medium::EmissionInterpolation::Attributes);
        let unit = Medium::new(0.5, 4.5, 1e-3, 1e6).unwrap();
        let cases = [
            ("temperature", &ball, &temperature),
            ("attributes", &ball, &attributes),
            ("flame", &flamed, &attributes),
            ("rgb", &rgb, &unit),
        ];
        for (name, volume, medium) in cases {
            let lights = ExplosionLights::new(&[volume], medium).unwrap();
            let h3 = f64::from(volume.temperature.voxel_size.powi(3));
            let held: f64 = lights
                .lights()
                .iter()
                .map(|l| f64::from(l.intensity.x))
                .sum();
            let every: f64 = (0..volume.temperature.data.len())
                .map(|i| f64::from(volume.cell_emission(medium, i).x) * h3)
                .sum();
            let centres: f64 = (0..volume.temperature.data.len())
                .filter(|&i| volume.voxel_emits(medium, i))
                .map(|i| f64::from(volume.cell_emission(medium, i).x) * h3)
                .sum();
            assert!(
                (held / every - 1.0).abs() < 1e-9,
                "{name}: {held} of {every}"
            );
            // And the cells beside the hot voxels are worth holding: the hot voxels' cells alone
            // hold 0.99964 (temperature), 0.9928 (attributes), 0.9926 (flame), 0.830 (rgb,
            // whose colour blends linearly into every neighbour's cell), measured.
            assert!(
                centres / every < 0.9999,
                "{name}: centres hold {}",
                centres / every
            );
        }
    }
}
