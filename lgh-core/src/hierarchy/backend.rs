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
        })
    }

    /// The hierarchy.
    #[must_use]
    pub fn hierarchy(&self) -> &'a LightingGridHierarchy {
        self.hierarchy
    }

    /// The blending parameters.
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
        let lights = self.hierarchy.query(point.position, &self.blending, |s| {
            radiance += shader.shade(s)
        })?;
        Ok(Illumination { radiance, lights })
    }
}
