//! What a render did: the work counts that explain its time.

/// What a render did: the work counts that explain its time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Steps where the lights were evaluated (scattering medium, lights given).
    pub shading_points: u64,
    /// Lights (or clusters) evaluated, summed over shading points.
    pub lights_evaluated: u64,
    /// Density samples taken along shadow rays.
    pub shadow_samples: u64,
    /// Surface points shaded: camera rays that met a surface (also in `shading_points`).
    pub surface_points: u64,
    /// Pixels refined ([`PixelRefinement::Adaptive`](crate::render::PixelRefinement)): their
    /// rays twice as fine a side.
    pub refined_pixels: u64,
}

impl RenderStats {
    /// Adds another count.
    pub fn add(&mut self, o: &RenderStats) {
        self.shading_points += o.shading_points;
        self.lights_evaluated += o.lights_evaluated;
        self.shadow_samples += o.shadow_samples;
        self.surface_points += o.surface_points;
        self.refined_pixels += o.refined_pixels;
    }

    /// Mean lights evaluated per shading point (0 when none).
    #[must_use]
    pub fn lights_per_point(&self) -> f64 {
        if self.shading_points == 0 {
            0.0
        } else {
            self.lights_evaluated as f64 / self.shading_points as f64
        }
    }
}
