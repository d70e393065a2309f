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
    pub fn new(hierarchy: &'a LightingGridHierarchy, alpha: f32) -> Result<Self, QueryError> {
        Ok(LghBackend {
            hierarchy,
            blending: hierarchy.blending(alpha)?,
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
