//! Ward's adaptive shadow testing (G. Ward, *Adaptive shadow testing for ray tracing*, EGWR 1991),
//! with the absolute error bound Paquette et al. used for their comparison (`papers/004_…`, §5.1).
//!
//! At each point, every light's *potential contribution* — its unoccluded reflection, eq. (1) with
//! `S = 1`, [`reflected`] — is computed, and the lights are taken largest first (Ward sorts them; a heap gives the same
//! order without sorting the lights that are never tested). They are
//! shaded (visibility included, by the shader) in that order until the potential contributions
//! left sum to at most the threshold `T`. The rest are not shaded: Ward adds them estimated as their
//! potential times the fraction of potential the tested lights delivered, clamped to `[0, 1]`.
//! Since each untested light's true contribution lies between 0 and its potential, so does the
//! estimate, and the absolute error (per channel: the order and the stopping sum use each light's
//! largest channel) is at most `T`. Ward's original stops at a *relative* tolerance; the absolute
//! one is Paquette's change.
//!
//! Without occlusion the estimate is exact and Ward's method costs a full pass over the lights
//! plus a heap: it can only save the shader calls (in Ward's setting, the shadow rays).

use alloc::collections::BinaryHeap;
use alloc::vec::Vec;
use glam::Vec3;

use crate::brute::BruteForce;
use crate::error::QueryError;
use crate::many_lights::{Illumination, LightSample, Lobe, ManyLights, Shader, ShadingPoint};
use crate::ranked::Ranked;
use crate::reflection::reflected;

/// Ward's method over the lights of a [`BruteForce`], with absolute threshold `T`.
///
/// Without occlusion Ward's estimate of the untested lights is exact, so the result is brute
/// force's to within rounding (and always within `T`):
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::reflection::reflected;
/// use lgh_core::{
///     BruteForce, LightSample, ManyLights, Material, PointLight, ShadingPoint, WardBackend,
/// };
///
/// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
/// let lights: Vec<PointLight> = (0..64u32)
///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
///     .map(|p| PointLight::new(p, Vec3::ONE))
///     .collect();
/// // A diffuse floor below the lights, shaded with eq. (1) (no shadows here).
/// let point = ShadingPoint {
///     position: Vec3::new(1.5, -20.0, 1.5),
///     normal: Some(Vec3::Y),
///     geometric: None,
///     view: Some(Vec3::Y),
///     material: Material::Lambert { albedo: Vec3::splat(0.8) },
/// };
/// let shade = |s: &LightSample| reflected(&point, s.position, s.intensity, s.lobe);
/// let exact = BruteForce::new(&lights)?.illuminate(&point, &mut { shade })?;
/// let brute = BruteForce::new(&lights)?;
/// let threshold = 0.01; // about 9 % of the exact value here
/// let ward = WardBackend::new(&brute, threshold)?.illuminate(&point, &mut { shade })?;
/// assert!((ward.radiance - exact.radiance).abs().max_element() <= threshold);
/// assert!(ward.lights < 64); // the lights left untested were not shaded
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct WardBackend<'a> {
    lights: &'a BruteForce,
    threshold: f32,
}

impl<'a> WardBackend<'a> {
    /// Ward's method over `lights` with threshold `threshold` (radiance units, per channel; finite
    /// and > 0).
    pub fn new(lights: &'a BruteForce, threshold: f32) -> Result<Self, QueryError> {
        Ok(WardBackend {
            lights,
            threshold: QueryError::check_threshold(threshold)?,
        })
    }

    /// The threshold `T`.
    #[must_use]
    pub fn threshold(&self) -> f32 {
        self.threshold
    }
}

impl ManyLights for WardBackend<'_> {
    fn name(&self) -> &'static str {
        "ward"
    }

    /// Ward scales the lights it does not test by the shaded radiance of those it does.
    fn selection_follows_shader(&self) -> bool {
        true
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        let x = QueryError::check_point(point.position)?;
        let n = self.lights.len();
        // Potential contributions, keyed by each light's largest channel in magnitude (a
        // colour outside Rec. 709's gamut has a negative one; for others, the largest).
        let potential: Vec<Ranked<Vec3>> = (0..n)
            .map(|i| {
                let (position, intensity) = self.lights.light(i);
                let value = reflected(point, position, intensity, Lobe::All);
                Ranked::new(value.abs().max_element(), i as u32, value)
            })
            .collect();
        let mut left: f64 = potential.iter().map(|p| f64::from(p.key())).sum();
        // Largest first (ties by index, so deterministic): a heap, built in O(n), gives them
        // without sorting the many lights that are never tested.
        let mut heap = BinaryHeap::from(potential);
        let threshold = f64::from(self.threshold);
        let mut out = Illumination::default();
        let mut tested_potential = Vec3::ZERO;
        while left > threshold {
            let Some(p) = heap.pop() else { break };
            left -= f64::from(p.key());
            let (position, intensity) = self.lights.light(p.index() as usize);
            out.radiance += shader.shade(&LightSample::point(
                p.index(),
                position,
                intensity,
                x,
                Lobe::All,
            ));
            tested_potential += p.item;
            out.lights += 1;
        }
        if !heap.is_empty() {
            // In heap order, which depends only on the input: deterministic.
            let untested = heap.iter().fold(Vec3::ZERO, |acc, p| acc + p.item);
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
