//! The lighting grid hierarchy as a [`ManyLights`] backend.

use glam::Vec3;

use super::LightingGridHierarchy;
use crate::blend::Blending;
use crate::error::QueryError;
use crate::many_lights::{Illumination, ManyLights, Shader, ShadingPoint};

/// The lighting grid hierarchy as a backend: one hierarchy and one α.
#[derive(Clone, Copy, Debug)]
pub struct LghBackend<'a> {
    hierarchy: &'a LightingGridHierarchy,
    blending: Blending,
    /// The levels shaded, `first..=last` (every level unless [`with_levels`](Self::with_levels)).
    first: u8,
    last: u8,
    /// Only the lights within this distance of a point are shaded (∞ unless
    /// [`within`](Self::within)).
    reach: f32,
}

impl<'a> LghBackend<'a> {
    /// The backend for `hierarchy` at the paper's α.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{
    ///     GridSettings, LghBackend, LightSample, LightingGridHierarchy, ManyLights, PointLight,
    ///     ShadingPoint,
    /// };
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let backend = LghBackend::new(&lgh, 2.0)?;
    /// // A shader that counts the intensity it is given (a renderer would shade and trace shadows).
    /// let mut shader = |s: &LightSample| s.intensity;
    /// let point = ShadingPoint::in_medium(Vec3::new(20.0, 0.0, 0.0));
    /// let sum = backend.illuminate(&point, &mut shader)?;
    /// // Far away, the blended levels still carry the total intensity.
    /// assert!((sum.radiance - Vec3::splat(64.0)).abs().max_element() < 1e-3);
    /// assert!(sum.lights < 64);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(hierarchy: &'a LightingGridHierarchy, alpha: f32) -> Result<Self, QueryError> {
        Ok(LghBackend {
            hierarchy,
            blending: hierarchy.blending(alpha)?,
            first: 0,
            last: u8::MAX,
            reach: f32::INFINITY,
        })
    }

    /// The backend for `hierarchy` with `blending` made for it (by
    /// [`LightingGridHierarchy::blending`], then changed: [`Blending::with_hard_switches`]). A
    /// blending for another hierarchy (other `h1` or `ℓ_max`) is an error.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LghBackend, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let hard = lgh.blending(2.0)?.with_hard_switches();
    /// let backend = LghBackend::with_blending(&lgh, hard)?;
    /// assert!(backend.blending().hard_switches());
    /// let other = LightingGridHierarchy::build(&lights, &GridSettings { h1: Some(0.1), ..Default::default() })?;
    /// assert!(LghBackend::with_blending(&other, hard).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_blending(
        hierarchy: &'a LightingGridHierarchy,
        blending: Blending,
    ) -> Result<Self, QueryError> {
        hierarchy.check_blending(&blending)?;
        Ok(LghBackend {
            hierarchy,
            blending,
            first: 0,
            last: u8::MAX,
            reach: f32::INFINITY,
        })
    }

    /// The same backend shading only the lights of the levels in `levels` (eq. 3's sum split
    /// by level, as [`LightingGridHierarchy::query_levels`]): a lighting cache shades the finest
    /// level per point and interpolates the rest.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LghBackend, LightingGridHierarchy, ManyLights, PointLight, ShadingPoint};
    ///
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let all = LghBackend::new(&lgh, 2.0)?;
    /// let point = ShadingPoint::in_medium(Vec3::new(1.5, 1.5, 2.5));
    /// let mut intensity = |s: &lgh_core::LightSample| s.intensity;
    /// let whole = all.illuminate(&point, &mut intensity)?;
    /// let fine = all.with_levels(0..=0).illuminate(&point, &mut intensity)?;
    /// let coarse = all.with_levels(1..=u8::MAX).illuminate(&point, &mut intensity)?;
    /// assert_eq!(fine.lights + coarse.lights, whole.lights);
    /// assert!((fine.radiance + coarse.radiance - whole.radiance).abs().max_element() < 1e-5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn with_levels(self, levels: core::ops::RangeInclusive<u8>) -> Self {
        LghBackend {
            first: *levels.start(),
            last: *levels.end(),
            ..self
        }
    }

    /// The same backend shading only the lights within `reach` of a point, with their weights
    /// (∞: every light, the default). A lighting cache sums a level's near lights per point
    /// and interpolates the rest: the query then scans only the cells that meet the smaller ball.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LghBackend, LightingGridHierarchy, ManyLights, PointLight, ShadingPoint};
    ///
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let level0 = LghBackend::new(&lgh, 2.0)?.with_levels(0..=0);
    /// let point = ShadingPoint::in_medium(Vec3::new(1.0, 1.0, 1.0));
    /// let mut count = |_: &lgh_core::LightSample| Vec3::ONE;
    /// assert_eq!(level0.within(1.0).illuminate(&point, &mut count)?.lights, 7); // itself and 6 neighbours
    /// let all = level0.illuminate(&point, &mut count)?.lights;
    /// assert_eq!(level0.within(f32::INFINITY).illuminate(&point, &mut count)?.lights, all);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn within(self, reach: f32) -> Self {
        LghBackend { reach, ..self }
    }

    /// The hierarchy.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LghBackend, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let backend = LghBackend::new(&lgh, 2.0)?;
    /// assert!(core::ptr::eq(backend.hierarchy(), &lgh));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn hierarchy(&self) -> &'a LightingGridHierarchy {
        self.hierarchy
    }

    /// The blending parameters.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LghBackend, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let backend = LghBackend::new(&lgh, 4.0)?;
    /// assert_eq!(backend.blending().radius(1), 4.0 * lgh.h1()); // r_1 = α h_1
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn blending(&self) -> &Blending {
        &self.blending
    }
}

impl ManyLights for LghBackend<'_> {
    fn name(&self) -> &'static str {
        "lgh"
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        let mut radiance = Vec3::ZERO;
        let levels = self.first..=self.last;
        let ((), lights) =
            self.hierarchy
                .gather(point.position, &self.blending, levels, self.reach, |s| {
                    radiance += shader.shade(s)
                })?;
        Ok(Illumination { radiance, lights })
    }
}
