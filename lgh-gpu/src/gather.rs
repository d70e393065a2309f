//! The gather (`gather.wgsl`): for each shading point, K lights drawn in proportion to their
//! unshadowed light there, with weights that make them an unbiased estimate of eq. (1)'s sum,
//! so that an engine traces its own shadow rays to a few lights a pixel (the real-time LGH of
//! Lin & Yuksel, I3D 2019, draws its shadow rays' lights this way).

use crate::error::GpuError;
use crate::hierarchy::{GpuHierarchy, Walk};
use crate::layout::{GatherSample, ShadingPoint};
use crate::timing::GpuTiming;

/// The most lights a point the gather draws (`gather.wgsl`'s `MAX_K`).
pub const MAX_K: u32 = 16;

impl GpuHierarchy {
    /// `k` lights for each point (`k` samples a point, point by point), each drawn among the
    /// lights the query sums there with probability proportional to its term's luminance
    /// (weighted reservoir sampling, `k` independent reservoirs), and weighted by
    /// `ρ/π · term · W / w / k` (`W` the sum of the lights' luminances): `Σ weight` over a
    /// point's samples is an unbiased estimate of [`shade`](GpuHierarchy::shade)'s radiance,
    /// and `Σ weight · visibility` of the shadowed one. The same `seed` gives the same bits.
    ///
    /// Errors unless `1 ≤ k ≤ MAX_K`, and as [`shade`](GpuHierarchy::shade).
    ///
    /// ```no_run
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_gpu::{Gpu, GpuHierarchy, ShadingPoint};
    ///
    /// let lights = [PointLight::new(Vec3::new(0.0, 0.0, 1.0), Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let on_gpu = GpuHierarchy::upload(&Gpu::new()?, &lgh, 2.0)?;
    /// let floor = ShadingPoint::new(Vec3::ZERO, Vec3::Z, Vec3::splat(0.8));
    /// let draws = on_gpu.gather(&[floor], 4, 7)?;
    /// assert_eq!(draws.len(), 4);
    /// assert_eq!(draws[0].position, [0.0, 0.0, 1.0]); // the one light, every time
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn gather(
        &self,
        points: &[ShadingPoint],
        k: u32,
        seed: u32,
    ) -> Result<Vec<GatherSample>, GpuError> {
        self.gather_timed(points, k, seed).map(|(s, _)| s)
    }

    /// [`gather`](Self::gather), with how long it took.
    pub fn gather_timed(
        &self,
        points: &[ShadingPoint],
        k: u32,
        seed: u32,
    ) -> Result<(Vec<GatherSample>, GpuTiming), GpuError> {
        if !(1..=MAX_K).contains(&k) {
            return Err(GpuError::InvalidK { k, most: MAX_K });
        }
        self.walk(Walk::Gather, points, k, seed)
    }

    /// Records the gather into the caller's `encoder`: for `count` points of `points`, `k`
    /// [`GatherSample`]s a point to `samples` (32 bytes each, point by
    /// point), as [`gather`](Self::gather) draws them, nothing read back.
    ///
    /// Errors unless `1 ≤ k ≤ MAX_K`, and as [`record_shade`](GpuHierarchy::record_shade).
    pub fn record_gather(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        points: &wgpu::Buffer,
        samples: &wgpu::Buffer,
        count: u32,
        (k, seed): (u32, u32),
    ) -> Result<(), GpuError> {
        if !(1..=MAX_K).contains(&k) {
            return Err(GpuError::InvalidK { k, most: MAX_K });
        }
        self.check_buffers((points, samples, count), 32 * u64::from(k))?;
        self.record_walk(
            encoder,
            Walk::Gather,
            (points, samples, count),
            k,
            seed,
            None,
        );
        Ok(())
    }
}
