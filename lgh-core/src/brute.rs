//! Brute force: every input light at every point, the exact answer of the light model and the
//! baseline the other backends are measured against.
//!
//! Being the reference, its sums are accumulated in `f64`: each light's term is still computed
//! in `f32` (a relative error of ~6·10⁻⁸ per term, of random sign), but a million of them summed
//! in `f32` drift by ~10⁻⁴, more than the approximations measured against it are allowed to.
//! In `f64` the sum of 10⁶ terms agrees with an all-`f64` evaluation to ~10⁻⁷ (tested below).

use alloc::vec::Vec;
use glam::{DVec3, Vec3};

use crate::error::{BuildError, QueryError};
use crate::light::{validate_lights, Channels, PointLight};
use crate::many_lights::{Illumination, LightSample, Lobe, ManyLights, Shader, ShadingPoint};

/// Every input light, every time: the exact answer of the same light model, and the baseline.
///
/// Lights are stored as structure-of-arrays so [`BruteForce::falloff_sum`] vectorises.
#[derive(Clone, Debug, Default)]
pub struct BruteForce {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    r: Vec<f32>,
    g: Vec<f32>,
    b: Vec<f32>,
}

impl BruteForce {
    /// Validates (as every backend does, [`BuildError`]) and stores the lights.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{BruteForce, BuildError, LightSample, ManyLights, PointLight, ShadingPoint};
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let brute = BruteForce::new(&lights)?;
    /// let mut shader = |s: &LightSample| s.intensity / (s.distance * s.distance);
    /// let sum = brute.illuminate(&ShadingPoint::in_medium(Vec3::new(1.5, 1.5, -4.0)), &mut shader)?;
    /// assert_eq!(sum.lights, 64); // every light, every time
    /// assert!(sum.radiance.x > 0.0);
    /// // The same validation as every backend.
    /// let negative = [PointLight::new(Vec3::ZERO, Vec3::new(1.0, -1.0, 0.0))];
    /// assert_eq!(BruteForce::new(&negative).unwrap_err(), BuildError::InvalidIntensity { index: 0 });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(lights: &[PointLight]) -> Result<Self, BuildError> {
        validate_lights(lights, Channels::OutOfGamut)?;
        let mut bf = BruteForce::default();
        for l in lights {
            bf.x.push(l.position.x);
            bf.y.push(l.position.y);
            bf.z.push(l.position.z);
            bf.r.push(l.intensity.x);
            bf.g.push(l.intensity.y);
            bf.b.push(l.intensity.z);
        }
        Ok(bf)
    }

    /// Number of lights.
    #[must_use]
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True if there are no lights.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Position and intensity of light `i` (panics if `i ≥ len()`).
    #[must_use]
    pub fn light(&self, i: usize) -> (Vec3, Vec3) {
        (
            Vec3::new(self.x[i], self.y[i], self.z[i]),
            Vec3::new(self.r[i], self.g[i], self.b[i]),
        )
    }

    /// `Σ_j I_j g(‖x − p_j‖)` with the clamped fall-off `g(d) = 1 / max(d, h0)²`: the unshadowed
    /// light-probe sum, vectorised over lights (8 lanes, in a fixed order, so it is deterministic),
    /// each term in `f32` and the sum in `f64`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{falloff, BruteForce, PointLight};
    ///
    /// let lights = [
    ///     PointLight::new(Vec3::ZERO, Vec3::ONE),
    ///     PointLight::new(Vec3::new(3.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 1.0)),
    /// ];
    /// let x = Vec3::new(0.0, 2.0, 0.0);
    /// let sum = BruteForce::new(&lights)?.falloff_sum(x, 0.1)?;
    /// let want =
    ///     Vec3::ONE * falloff(2.0, 0.1) + Vec3::new(2.0, 0.0, 1.0) * falloff(13f32.sqrt(), 0.1);
    /// assert!((sum - want).abs().max_element() < 1e-6);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn falloff_sum(&self, x: Vec3, h0: f32) -> Result<Vec3, QueryError> {
        QueryError::check_point(x)?;
        const LANES: usize = 8;
        let h02 = h0 * h0;
        let mut acc = [[0.0f64; LANES]; 3];
        let n = self.len();
        let full = n - n % LANES;
        let lane = |i: usize| {
            let dx = self.x[i] - x.x;
            let dy = self.y[i] - x.y;
            let dz = self.z[i] - x.z;
            let d2 = (dx * dx + dy * dy + dz * dz).max(h02);
            1.0 / d2
        };
        // Blocks of `BLOCK` lights are summed per lane in f32 (at most 8 terms a lane, so at most
        // ~8 ulps, 5·10⁻⁷ relative), and the blocks in f64: nearly the speed of an all-f32 sum,
        // the accuracy of an f64 one.
        const BLOCK: usize = 8 * LANES;
        for block in (0..full).step_by(BLOCK) {
            let mut part = [[0.0f32; LANES]; 3];
            for base in (block..full.min(block + BLOCK)).step_by(LANES) {
                let xs = &self.x[base..base + LANES];
                let ys = &self.y[base..base + LANES];
                let zs = &self.z[base..base + LANES];
                let rs = &self.r[base..base + LANES];
                let gs = &self.g[base..base + LANES];
                let bs = &self.b[base..base + LANES];
                for k in 0..LANES {
                    let dx = xs[k] - x.x;
                    let dy = ys[k] - x.y;
                    let dz = zs[k] - x.z;
                    let g = 1.0 / (dx * dx + dy * dy + dz * dz).max(h02);
                    part[0][k] += rs[k] * g;
                    part[1][k] += gs[k] * g;
                    part[2][k] += bs[k] * g;
                }
            }
            for (a, p) in acc.iter_mut().zip(&part) {
                for k in 0..LANES {
                    a[k] += f64::from(p[k]);
                }
            }
        }
        let mut sum = DVec3::new(
            acc[0].iter().sum(),
            acc[1].iter().sum(),
            acc[2].iter().sum(),
        );
        for i in full..n {
            let g = lane(i);
            sum += (Vec3::new(self.r[i], self.g[i], self.b[i]) * g).as_dvec3();
        }
        Ok(sum.as_vec3())
    }
}

impl ManyLights for BruteForce {
    fn name(&self) -> &'static str {
        "brute"
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        let x = QueryError::check_point(point.position)?;
        // Summed in f64, as every reference sum here (module doc).
        let mut radiance = DVec3::ZERO;
        for i in 0..self.len() {
            let (position, intensity) = self.light(i);
            radiance += shader
                .shade(&LightSample::point(
                    i as u32,
                    position,
                    intensity,
                    x,
                    Lobe::All,
                ))
                .as_dvec3();
        }
        Ok(Illumination {
            radiance: radiance.as_vec3(),
            lights: self.len() as u32,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::falloff;
    use crate::many_lights::ShadingPoint;
    use crate::testsets::{clumped_lights, query_points};
    use wasm_bindgen_test::wasm_bindgen_test;

    /// `Σ_j I_j / max(d_j, h0)²` with every operation in `f64`, from the same `f32` inputs.
    fn exact(lights: &[PointLight], x: Vec3, h0: f64) -> DVec3 {
        lights
            .iter()
            .map(|l| {
                let d2 = (l.position.as_dvec3() - x.as_dvec3()).length_squared();
                l.intensity.as_dvec3() / d2.max(h0 * h0)
            })
            .sum()
    }

    /// The relative error of `got` against `want`, worst channel, on the sum's scale.
    fn rel(got: Vec3, want: DVec3) -> f64 {
        (got.as_dvec3() - want).abs().max_element() / want.max_element()
    }

    /// A reference must be accurate to the last digit that matters: on 10⁶ clustered lights
    /// (the explosion-like set whose `f32` sum drifted by 2.8·10⁻⁴), both brute-force sums agree
    /// with an all-`f64` evaluation to 10⁻⁶. The bound: each `f32` term is off by at most a few
    /// ulps (~2·10⁻⁷ relative), all terms are positive, so the sum is off by at most that
    /// relatively; an `f32` accumulation of 10⁶ terms is not (the test fails with one).
    #[wasm_bindgen_test(unsupported = test)]
    fn both_sums_agree_with_an_f64_evaluation_on_a_million_lights() {
        let lights = clumped_lights(1_000_000, 11);
        let brute = BruteForce::new(&lights).unwrap();
        let h0 = 0.01;
        let mut shade = |s: &LightSample| s.intensity * falloff(s.distance, h0);
        let mut worst = (0.0f64, 0.0f64);
        for x in query_points(Vec3::splat(-10.0), Vec3::splat(20.0), 6, 3) {
            let want = exact(&lights, x, f64::from(h0));
            let probe = brute.falloff_sum(x, h0).unwrap();
            let shaded = brute
                .illuminate(&ShadingPoint::in_medium(x), &mut shade)
                .unwrap()
                .radiance;
            worst.0 = worst.0.max(rel(probe, want));
            worst.1 = worst.1.max(rel(shaded, want));
        }
        std::println!(
            "relative error: falloff_sum {:e}, illuminate {:e}",
            worst.0,
            worst.1
        );
        assert!(worst.0 < 1e-6, "falloff_sum off by {:e}", worst.0);
        assert!(worst.1 < 1e-6, "illuminate off by {:e}", worst.1);
    }
}
