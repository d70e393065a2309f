//! The gather (`GpuHierarchy::gather`, `gather.wgsl`): K lights a point drawn in proportion to
//! their unshadowed light, weighted so that their sum estimates eq. (1)'s sum without bias.
//!
//! **The statistical test.** Each seed gives at each point an estimate `X = Σ_k weight_k` whose
//! mean is the query's radiance (`shade`). Over `S` independent seeds the sample mean is within
//! `z·σ/√S` of it with probability erfc(z/√2); with `z = 5` and a few thousand point-channels a
//! false failure has odds below 1e-3. Summed over all points the same holds with the summed
//! variance, which catches a small bias that no single point shows (a bias of 1% would stand
//! ~20 σ out there). Floats add a relative 1e-5 of slack (the draws' weights are quotients of
//! sums of a few hundred terms).

mod common;

use common::{g_buffer, gpu};
use lgh_core::glam::Vec3;
use lgh_core::testsets::{clumped_lights, uniform_cube};
use lgh_core::PointLight;
use lgh_gpu::{GpuBuilder, GpuError, GpuGrid, GpuHierarchy};

fn builder(lights: &[PointLight]) -> Option<GpuHierarchy> {
    let gpu = gpu()?;
    let mut b = GpuBuilder::new(gpu, GpuGrid::fitting(lights).unwrap(), 2.0).unwrap();
    b.rebuild(lights).unwrap();
    Some(b.hierarchy())
}

#[test]
fn the_draws_are_an_unbiased_estimate_of_the_sum() {
    for (name, lights) in [
        ("uniform", uniform_cube(1500, 11)),
        ("clumped", clumped_lights(1500, 12)),
    ] {
        let Some(h) = builder(&lights) else { return };
        let points = g_buffer(&lights, 150, 13);
        let want = h.shade(&points).unwrap();
        let (k, seeds) = (4u32, 96u32);
        let mut sum = vec![[0.0f64; 3]; points.len()];
        let mut sum2 = vec![[0.0f64; 3]; points.len()];
        for seed in 0..seeds {
            let draws = h.gather(&points, k, seed).unwrap();
            for (p, chunk) in draws.chunks(k as usize).enumerate() {
                let x: Vec3 = chunk.iter().map(|d| Vec3::from(d.weight)).sum();
                for c in 0..3 {
                    sum[p][c] += x[c] as f64;
                    sum2[p][c] += (x[c] as f64).powi(2);
                }
            }
        }
        let s = seeds as f64;
        let (mut total, mut total_want, mut total_var) = (0.0, 0.0, 0.0);
        let mut worst = 0.0f64;
        for p in 0..points.len() {
            for c in 0..3 {
                let mean = sum[p][c] / s;
                let var = (sum2[p][c] / s - mean * mean).max(0.0) * s / (s - 1.0);
                let w = want[p][c] as f64;
                let slack = 1e-5 * w.abs();
                let sd = (var / s).sqrt();
                let z = ((mean - w).abs() - slack).max(0.0) / sd.max(1e-300);
                assert!(
                    (mean - w).abs() <= 5.0 * sd + slack,
                    "{name}: point {p} channel {c}: mean {mean} of {seeds} seeds against {w} \
                     (σ/√S {sd:e})"
                );
                if w > 0.0 {
                    worst = worst.max(z);
                }
                total += mean;
                total_want += w;
                total_var += var / s;
            }
        }
        let z = (total - total_want).abs() / total_var.sqrt();
        eprintln!(
            "{name}: summed over the points {total:.6} against {total_want:.6} ({z:.2} σ); \
             the largest point's {worst:.2} σ"
        );
        assert!(z <= 5.0, "{name}: the summed estimate is {z:.2} σ off");
    }
}

#[test]
fn the_same_seed_gives_the_same_bits_and_one_light_is_drawn_every_time() {
    let lights = clumped_lights(800, 14);
    let Some(h) = builder(&lights) else { return };
    let points = g_buffer(&lights, 100, 15);
    let a = h.gather(&points, 3, 7).unwrap();
    assert_eq!(a, h.gather(&points, 3, 7).unwrap());
    assert_ne!(a, h.gather(&points, 3, 8).unwrap());
    assert!(matches!(
        h.gather(&points, 0, 1),
        Err(GpuError::InvalidK { k: 0, .. })
    ));
    assert!(matches!(
        h.gather(&points, 17, 1),
        Err(GpuError::InvalidK { k: 17, .. })
    ));
    // One light: every draw is it, and the draws add up to its light.
    let one = [PointLight::new(
        Vec3::new(0.3, 0.2, 2.0),
        Vec3::new(1.0, 2.0, 3.0),
    )];
    let Some(h) = builder(&one) else { return };
    let points = g_buffer(&[one[0], PointLight::new(Vec3::ZERO, Vec3::ONE)], 20, 16);
    let want = h.shade(&points).unwrap();
    let draws = h.gather(&points, 4, 3).unwrap();
    for (p, chunk) in draws.chunks(4).enumerate() {
        let x: Vec3 = chunk.iter().map(|d| Vec3::from(d.weight)).sum();
        let w = Vec3::from(want[p]);
        assert!(
            (x - w).abs().max_element() <= 1e-6 * w.max_element(),
            "{x} against {w}"
        );
        if w.max_element() > 0.0 {
            assert!(chunk
                .iter()
                .all(|d| d.position == one[0].position.to_array()));
        }
    }
}
