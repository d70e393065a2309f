//! Deterministic light sets and query points for tests and benchmarks only (the cargo feature
//! `testsets`, off by default; lgh-core's own unit tests always have it).
//!
//! Everything here is generated from the seeded generators of [`random`](crate::random), so every
//! machine gets the same lights.

use alloc::vec::Vec;
use glam::Vec3;

use crate::light::PointLight;
use crate::many_lights::{Material, ShadingPoint};
use crate::random::{fractal_noise, SplitMix64};
use crate::spectrum::BlackbodyTable;

/// `n` lights in four dense clumps over a sparse background, one in eleven dark, random RGB
/// intensities in `[0, 10)`: what hierarchies find hardest to bound (clusters of very different
/// size and brightness side by side).
#[must_use]
pub fn clumped_lights(n: usize, seed: u64) -> Vec<PointLight> {
    let mut rng = SplitMix64(seed);
    (0..n)
        .map(|i| {
            let centre = Vec3::splat((i % 4) as f32 * 3.0);
            let p = if i % 5 == 0 {
                rng.next_in(Vec3::splat(-10.0), Vec3::splat(20.0))
            } else {
                centre + rng.next_in(Vec3::splat(-0.5), Vec3::splat(0.5))
            };
            let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            PointLight::new(p, if i % 11 == 0 { Vec3::ZERO } else { c * 10.0 })
        })
        .collect()
}

/// `n` surface and medium points for a light set with bounding box `lo..hi`, placed as
/// [`query_points`] places them, each with a random unit normal and view direction and, in turn,
/// a Lambert, a Phong (exponent 1…300) and a medium material.
#[must_use]
pub fn shading_points(lo: Vec3, hi: Vec3, n: usize, seed: u64) -> Vec<ShadingPoint> {
    let mut rng = SplitMix64(SplitMix64::mix(seed));
    query_points(lo, hi, n, seed)
        .into_iter()
        .enumerate()
        .map(|(i, position)| {
            let kd = rng.next_in(Vec3::splat(0.1), Vec3::ONE);
            let material = match i % 3 {
                0 => Material::Lambert { albedo: kd },
                1 => Material::Phong {
                    kd,
                    ks: rng.next_in(Vec3::splat(0.1), Vec3::ONE),
                    exponent: 1.0 + 299.0 * rng.next_f32(),
                },
                _ => return ShadingPoint::in_medium(position),
            };
            ShadingPoint {
                position,
                normal: Some(rng.next_unit()),
                geometric: None,
                view: Some(rng.next_unit()),
                material,
            }
        })
        .collect()
}

/// Benchmark set (a): `n` lights uniform in the unit cube with random RGB intensities in `[0, 1)`.
#[must_use]
pub fn uniform_cube(n: usize, seed: u64) -> Vec<PointLight> {
    let mut rng = SplitMix64(seed);
    (0..n)
        .map(|_| {
            let p = rng.next_in(Vec3::ZERO, Vec3::ONE);
            let i = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            PointLight::new(p, i)
        })
        .collect()
}

/// Benchmark set (b): explosion-like lights on a `res³` lattice filling the unit cube — one light at
/// the centre of every voxel of a turbulent fireball shell, coloured by a blackbody temperature that
/// falls from about 3000 K inside the shell to 1300 K at its rim, with intensity `∝ T⁴ h³`.
/// At `res = 128` it yields about a million lights. Level-1 grids for this set should use
/// `h1 = 2 / res` with the origin on a voxel centre, as the paper does for explosions.
#[must_use]
pub fn explosion_shell(res: u32) -> Vec<PointLight> {
    let h = 1.0 / res as f32;
    let centre = Vec3::splat(0.5);
    // About 1.04 million lights at res = 128.
    let (inner, outer) = (0.17f32, 0.5f32);
    let table = BlackbodyTable::new(1300.0, 3000.0, 1.0).expect("valid range");
    let mut out = Vec::new();
    for k in 0..res {
        for j in 0..res {
            for i in 0..res {
                let p = Vec3::new(i as f32 + 0.5, j as f32 + 0.5, k as f32 + 0.5) * h;
                let q = p - centre;
                let n = fractal_noise(p * 6.0, 4, 7);
                let r = q.length() * (1.0 + 0.35 * n);
                if r <= inner || r >= outer {
                    continue;
                }
                let depth = (r - inner) / (outer - inner); // 0 inside, 1 at the rim
                let heat = (1.0 - depth) * (0.75 + 0.25 * fractal_noise(p * 11.0 + 3.0, 3, 11));
                let kelvin = 1300.0 + 1700.0 * heat.clamp(0.0, 1.0);
                let t = kelvin / 3000.0;
                let t4 = (t * t) * (t * t);
                // The colour of the whole kelvin below (a table entry, exactly blackbody_rgb).
                let c = table.radiance((kelvin as u32) as f32);
                let colour = c / c.max_element();
                let intensity = colour * t4 * (h * h * h) * 1e4;
                out.push(PointLight::new(p, intensity));
            }
        }
    }
    out
}

/// Benchmark set (c): `n` equal lights along 8 long curves ("light strings") spanning about
/// 20 × 4 × 10 units: Paquette's Light Strings lights, [`crate::scenes::light_strings`] itself.
pub use crate::scenes::light_strings;

/// `n` query points for a light set with bounding box `lo..hi`: half uniform inside the box, half
/// uniform in the box scaled by 3 about its centre ("inside and around").
#[must_use]
pub fn query_points(lo: Vec3, hi: Vec3, n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64(seed);
    let c = (lo + hi) * 0.5;
    let e = (hi - lo).max(Vec3::splat(1e-3));
    (0..n)
        .map(|i| {
            if i % 2 == 0 {
                rng.next_in(lo, hi)
            } else {
                rng.next_in(c - 1.5 * e, c + 1.5 * e)
            }
        })
        .collect()
}
