//! What the GPU tests share: the one device, or SKIPPED; a G-buffer over a light set; lights
//! flickering. Each test binary uses some of them.

#![allow(dead_code)]

use std::sync::OnceLock;

use lgh_core::glam::Vec3;
use lgh_core::testsets::shading_points;
use lgh_core::{Material, PointLight};
use lgh_gpu::{Gpu, GpuError, ShadingPoint};
use lgh_tests::Piece;

/// The one device of the tests, or SKIPPED.
pub fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Result<Gpu, GpuError>> = OnceLock::new();
    match GPU.get_or_init(Gpu::new) {
        Ok(gpu) => Some(gpu),
        Err(e) => {
            Piece::Gpu.missing(&e.to_string());
            None
        }
    }
}

/// A G-buffer's points from lgh-core's shading points: Lambert's albedo where it has one (0.5
/// otherwise), the normal where it has one (+z otherwise).
pub fn g_buffer(lights: &[PointLight], n: usize, seed: u64) -> Vec<ShadingPoint> {
    let (lo, hi) = lights
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), l| {
            (lo.min(l.position), hi.max(l.position))
        });
    shading_points(lo, hi, n, seed)
        .into_iter()
        .map(|p| {
            let albedo = match p.material {
                Material::Lambert { albedo } => albedo,
                Material::Phong { kd, .. } => kd,
                _ => Vec3::splat(0.5),
            };
            ShadingPoint::new(p.position, p.normal.unwrap_or(Vec3::Z), albedo)
        })
        .collect()
}

/// Frame `frame`'s intensities of `lights` flickering: each scaled by `1 + ½ sin(i·frame)`.
pub fn flicker(lights: &[PointLight], frame: usize) -> Vec<Vec3> {
    lights
        .iter()
        .enumerate()
        .map(|(i, l)| l.intensity * (1.0 + 0.5 * ((i * frame) as f32).sin()))
        .collect()
}
