//! Helpers shared by the integration tests.
#![allow(clippy::needless_range_loop)]
#![allow(dead_code)]

use lgh_core::glam::Vec3;
use lgh_core::{falloff, Blending, LightingGridHierarchy, PointLight};
use proptest::prelude::*;

/// f32 unit round-off.
pub const EPS: f64 = f32::EPSILON as f64 / 2.0;

/// Random lights: clustered or spread, positions in ±`extent`.
pub fn lights_strategy(max: usize, extent: f32) -> impl Strategy<Value = Vec<PointLight>> {
    prop::collection::vec(
        (
            (-extent..extent, -extent..extent, -extent..extent),
            (0.0f32..10.0, 0.0f32..10.0, 0.0f32..10.0),
        ),
        1..max,
    )
    .prop_map(|v| {
        v.into_iter()
            .map(|((x, y, z), (r, g, b))| PointLight::new(Vec3::new(x, y, z), Vec3::new(r, g, b)))
            .collect()
    })
}

/// Eq. (3) without visibility, evaluated naively: every light of every level, no radius query.
/// Returns the sum of `B·I·g(d)` and the number of lights with non-zero weight.
pub fn naive_lgh(h: &LightingGridHierarchy, b: &Blending, x: Vec3) -> (Vec3, u32) {
    let mut sum = Vec3::ZERO;
    let mut n = 0;
    for l in 0..=h.max_level() {
        for light in h.level(l).iter() {
            if !h.is_active(l, &light) {
                continue;
            }
            let d = (light.position - x).length();
            let w = b.weight(l, d);
            if w > 0.0 {
                n += 1;
                sum += light.intensity * w * falloff(d, h.h0());
            }
        }
    }
    (sum, n)
}

/// `Σ_j I_j g(d_j)` over the input lights, in f64.
pub fn brute_f64(lights: &[PointLight], x: Vec3, h0: f32) -> [f64; 3] {
    let mut s = [0.0f64; 3];
    for l in lights {
        let d = (l.position - x).length() as f64;
        let c = d.max(h0 as f64);
        let g = 1.0 / (c * c);
        for a in 0..3 {
            s[a] += l.intensity[a] as f64 * g;
        }
    }
    s
}

/// Sum through the hierarchy's query.
pub fn lgh_sum(h: &LightingGridHierarchy, b: &Blending, x: Vec3) -> (Vec3, u32) {
    let mut sum = Vec3::ZERO;
    let n = h
        .query(x, b, |s| sum += s.intensity * falloff(s.distance, h.h0()))
        .unwrap();
    (sum, n)
}

pub fn lum64(v: [f64; 3]) -> f64 {
    0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]
}
