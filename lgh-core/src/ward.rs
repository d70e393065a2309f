//! Ward's adaptive shadow testing (G. Ward, *Adaptive shadow testing for ray tracing*, EGWR 1991),
//! with the absolute error bound Paquette et al. used for their comparison (`papers/004_…`, §5.1).
//!
//! At each point, every light's *potential contribution* — its unoccluded reflection, eq. (1) with
//! `S = 1`, [`reflected`] — is computed and the lights are sorted by it, largest first. They are
//! shaded (visibility included, by the shader) in that order until the potential contributions
//! left sum to at most the threshold `T`. The rest are not shaded: Ward adds them estimated as their
//! potential times the fraction of potential the tested lights delivered, clamped to `[0, 1]`.
//! Since each untested light's true contribution lies between 0 and its potential, so does the
//! estimate, and the absolute error (per channel: the order and the stopping sum use each light's
//! largest channel) is at most `T`. Ward's original stops at a *relative* tolerance; the absolute
//! one is Paquette's change.
//!
//! Without occlusion the estimate is exact and Ward's method costs a full pass over the lights
//! plus a sort: it can only save the shader calls (in Ward's setting, the shadow rays).

use alloc::vec::Vec;
use glam::Vec3;

use crate::backend::{BruteForce, Illumination, LightSample, ManyLights, Shader, ShadingPoint};
use crate::error::QueryError;
use crate::reflection::{reflected, Lobe};

/// Ward's method over the lights of a [`BruteForce`], with absolute threshold `T`.
#[derive(Clone, Copy, Debug)]
pub struct WardBackend<'a> {
    lights: &'a BruteForce,
    threshold: f32,
}

impl<'a> WardBackend<'a> {
    /// Ward's method over `lights` with threshold `threshold` (radiance units, per channel; finite
    /// and > 0).
    pub fn new(lights: &'a BruteForce, threshold: f32) -> Result<Self, QueryError> {
        if !(threshold.is_finite() && threshold > 0.0) {
            return Err(QueryError::InvalidThreshold { threshold });
        }
        Ok(WardBackend { lights, threshold })
    }

    /// The threshold `T`.
    pub fn threshold(&self) -> f32 {
        self.threshold
    }
}

impl ManyLights for WardBackend<'_> {
    fn name(&self) -> &'static str {
        "ward"
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        let x = point.position;
        if !x.is_finite() {
            return Err(QueryError::NonFinitePoint);
        }
        let n = self.lights.len();
        // Potential contributions, with each light's largest channel as its sort key.
        let mut potential: Vec<(f32, u32, Vec3)> = (0..n)
            .map(|i| {
                let (position, intensity) = self.lights.light(i);
                let p = reflected(point, position, intensity, Lobe::All);
                (p.max_element(), i as u32, p)
            })
            .collect();
        // Largest first, ties by index: deterministic.
        potential.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        // Suffix sums of the keys (in f64): tested[k..] is what is left after testing k lights.
        let mut left = 0.0f64;
        let mut cut = n;
        let threshold = f64::from(self.threshold);
        for (k, p) in potential.iter().enumerate().rev() {
            if left + f64::from(p.0) > threshold {
                cut = k + 1;
                break;
            }
            left += f64::from(p.0);
            cut = k;
        }
        let mut out = Illumination::default();
        let mut tested_potential = Vec3::ZERO;
        for &(_, i, p) in &potential[..cut] {
            let (position, intensity) = self.lights.light(i as usize);
            out.radiance += shader.shade(&LightSample {
                level: 0,
                index: i,
                position,
                intensity,
                variance: Vec3::ZERO,
                size: 0.0,
                distance: (position - x).length(),
                weight: 1.0,
                lobe: Lobe::All,
            });
            tested_potential += p;
        }
        out.lights = cut as u32;
        if cut < n {
            let untested = potential[cut..]
                .iter()
                .fold(Vec3::ZERO, |acc, &(_, _, p)| acc + p);
            // Ward's estimate: the untested potential times the fraction the tested lights
            // delivered (all of it when nothing was tested or nothing was potential).
            let delivered = Vec3::select(
                tested_potential.cmpgt(Vec3::ZERO),
                (out.radiance / tested_potential).clamp(Vec3::ZERO, Vec3::ONE),
                Vec3::ONE,
            );
            out.radiance += untested * delivered;
        }
        Ok(out)
    }
}
