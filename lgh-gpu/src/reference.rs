//! The GPU query's answer computed on the CPU: lgh-core's `query_sum` with the kernel's
//! Lambertian response (`shade.wgsl`'s `contribution`). The reference of the tests, of
//! `lgh bench gpu`'s CPU path and of the benches, written once.

use lgh_core::glam::Vec3;
use lgh_core::{falloff, Blending, LightSample, LightingGridHierarchy, QueryError};

use crate::layout::ShadingPoint;

/// One light's `B·I·g(d)·max(0, n·ω)` at `x` with unit normal `n` (its intensity already
/// weighted by `B`, as lgh-core's query gives it); 0 where the light sits on the point.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::LightSample;
/// use lgh_gpu::reference::response;
///
/// let s = LightSample::point(0, Vec3::new(0.0, 0.0, 2.0), Vec3::ONE, Vec3::ZERO, Default::default());
/// assert_eq!(response(Vec3::ZERO, Vec3::Z, 0.1, &s), Vec3::splat(0.25)); // 1/d², cos 1
/// ```
#[inline]
#[must_use]
pub fn response(x: Vec3, n: Vec3, h0: f32, s: &LightSample) -> Vec3 {
    let d = s.distance;
    let cosine = if d > 0.0 {
        (n.dot(s.position - x) / d).max(0.0)
    } else {
        0.0
    };
    s.intensity * falloff(d, h0) * cosine
}

/// The outgoing radiance at `p`: `ρ/π · Σ response` over the lights lgh-core's query reports,
/// what [`GpuHierarchy::shade`](crate::GpuHierarchy::shade) computes up to the order of the sum.
pub fn shade(
    lgh: &LightingGridHierarchy,
    blending: &Blending,
    p: &ShadingPoint,
) -> Result<Vec3, QueryError> {
    let (x, n) = (Vec3::from(p.position), Vec3::from(p.normal));
    let (sum, _) = lgh.query_sum(x, blending, |s| response(x, n, lgh.h0(), s))?;
    Ok(sum * Vec3::from(p.albedo) * core::f32::consts::FRAC_1_PI)
}
