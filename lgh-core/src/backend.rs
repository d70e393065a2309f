//! The many-lights interface renderers shade through, and its backends.
//!
//! A renderer describes the point it shades ([`ShadingPoint`]: position, and for surfaces the normal,
//! view direction and material) and supplies a [`Shader`] that turns one light — an input light or a
//! cluster standing for many — into outgoing radiance, visibility included. A backend decides which
//! lights to present and sums what the shader returns. Backends that bound their error (the light
//! octree, Lightcuts, Ward's method) read the normal, view direction and material for their bounds;
//! the LGH and brute force ignore them.

use alloc::vec::Vec;
use glam::Vec3;

use crate::blend::Blending;
use crate::error::{BuildError, QueryError};
use crate::hierarchy::LightingGridHierarchy;
use crate::light::PointLight;
use crate::reflection::Lobe;

/// One light presented to a shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Level ℓ of the light (0 for input lights).
    pub level: u8,
    /// Index of the light within its level (see [`LightingGridHierarchy::level`]).
    pub index: u32,
    /// Light position (the illumination centre `p_ℓi` for grid lights).
    pub position: Vec3,
    /// Intensity to shade with: `B_ℓ(d) I_ℓi` for the LGH, the light's own intensity otherwise.
    pub intensity: Vec3,
    /// Per-axis variance `σ²_ℓi` of the positions this light stands for (eq. 4); zero for a point.
    pub variance: Vec3,
    /// Size `s_ℓi` (eq. 5); zero for a point.
    pub size: f32,
    /// Distance `d = ‖x − position‖`.
    pub distance: f32,
    /// Blending weight `B_ℓ(d)` already folded into `intensity` (1 for non-LGH backends).
    pub weight: f32,
    /// The part of the reflection to shade this light for ([`Lobe::All`] but for the light
    /// octree, which shades the diffuse and specular terms of eq. (1) separately).
    pub lobe: Lobe,
}

impl LightSample {
    /// Input light `index` — a point at full weight — seen from `x`, to be shaded for `lobe`.
    #[inline]
    pub fn point(index: u32, position: Vec3, intensity: Vec3, x: Vec3, lobe: Lobe) -> Self {
        LightSample {
            level: 0,
            index,
            position,
            intensity,
            variance: Vec3::ZERO,
            size: 0.0,
            distance: (position - x).length(),
            weight: 1.0,
            lobe,
        }
    }
}

/// The material at a shading point, for backends that bound a light's contribution.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Material {
    /// Participating medium with the isotropic phase function `1 / 4π`.
    #[default]
    Isotropic,
    /// Lambertian surface with the given albedo.
    Lambert {
        /// Diffuse reflectance.
        albedo: Vec3,
    },
    /// Phong surface: diffuse `kd` plus specular `ks` with exponent `n`.
    Phong {
        /// Diffuse reflectance.
        kd: Vec3,
        /// Specular reflectance.
        ks: Vec3,
        /// Phong exponent.
        exponent: f32,
    },
}

/// Where and what is shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    /// World position `x`.
    pub position: Vec3,
    /// Unit surface normal; `None` in a medium.
    pub normal: Option<Vec3>,
    /// Unit direction towards the viewer; `None` if not needed.
    pub view: Option<Vec3>,
    /// Material.
    pub material: Material,
}

impl ShadingPoint {
    /// A point in a medium (no normal, isotropic phase function).
    pub fn in_medium(position: Vec3) -> Self {
        ShadingPoint {
            position,
            normal: None,
            view: None,
            material: Material::Isotropic,
        }
    }
}

/// Turns one light into radiance at the shading point, visibility included.
pub trait Shader {
    /// Radiance contributed by `light` (its intensity already weighted by the backend).
    fn shade(&mut self, light: &LightSample) -> Vec3;
}

impl<F: FnMut(&LightSample) -> Vec3> Shader for F {
    #[inline(always)]
    fn shade(&mut self, light: &LightSample) -> Vec3 {
        self(light)
    }
}

/// The sum a backend returns.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Illumination {
    /// Σ of the shader's results.
    pub radiance: Vec3,
    /// Number of lights (or clusters) shaded.
    pub lights: u32,
}

/// A many-lights method a renderer can shade through.
pub trait ManyLights {
    /// Short name, e.g. `"lgh"` or `"brute"`.
    fn name(&self) -> &'static str;

    /// Shades `point` with every light the method selects and returns the sum.
    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError>;
}

/// The lighting grid hierarchy as a backend: one hierarchy and one α.
#[derive(Clone, Copy, Debug)]
pub struct LghBackend<'a> {
    hierarchy: &'a LightingGridHierarchy,
    blending: Blending,
}

impl<'a> LghBackend<'a> {
    /// The backend for `hierarchy` at the paper's α.
    pub fn new(hierarchy: &'a LightingGridHierarchy, alpha: f32) -> Result<Self, QueryError> {
        Ok(LghBackend {
            hierarchy,
            blending: hierarchy.blending(alpha)?,
        })
    }

    /// The hierarchy.
    pub fn hierarchy(&self) -> &'a LightingGridHierarchy {
        self.hierarchy
    }

    /// The blending parameters.
    pub fn blending(&self) -> &Blending {
        &self.blending
    }
}

impl ManyLights for LghBackend<'_> {
    fn name(&self) -> &'static str {
        "lgh"
    }

    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError> {
        let mut radiance = Vec3::ZERO;
        let lights = self.hierarchy.query(point.position, &self.blending, |s| {
            radiance += shader.shade(s)
        })?;
        Ok(Illumination { radiance, lights })
    }
}

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
    /// Validates and stores the lights.
    pub fn new(lights: &[PointLight]) -> Result<Self, BuildError> {
        let mut bf = BruteForce::default();
        for (index, l) in lights.iter().enumerate() {
            if !l.position.is_finite() {
                return Err(BuildError::NonFinitePosition { index });
            }
            if !l.intensity.is_finite() || l.intensity.min_element() < 0.0 {
                return Err(BuildError::InvalidIntensity { index });
            }
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
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True if there are no lights.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Position and intensity of light `i` (panics if `i ≥ len()`).
    pub fn light(&self, i: usize) -> (Vec3, Vec3) {
        (
            Vec3::new(self.x[i], self.y[i], self.z[i]),
            Vec3::new(self.r[i], self.g[i], self.b[i]),
        )
    }

    /// `Σ_j I_j g(‖x − p_j‖)` with the clamped fall-off `g(d) = 1 / max(d, h0)²`: the unshadowed
    /// light-probe sum, vectorised over lights (8 lanes, in a fixed order, so it is deterministic).
    pub fn falloff_sum(&self, x: Vec3, h0: f32) -> Result<Vec3, QueryError> {
        QueryError::check_point(x)?;
        const LANES: usize = 8;
        let h02 = h0 * h0;
        let mut acc = [[0.0f32; LANES]; 3];
        let n = self.len();
        let full = n - n % LANES;
        let lane = |i: usize| {
            let dx = self.x[i] - x.x;
            let dy = self.y[i] - x.y;
            let dz = self.z[i] - x.z;
            let d2 = (dx * dx + dy * dy + dz * dz).max(h02);
            1.0 / d2
        };
        for base in (0..full).step_by(LANES) {
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
                acc[0][k] += rs[k] * g;
                acc[1][k] += gs[k] * g;
                acc[2][k] += bs[k] * g;
            }
        }
        let mut sum = Vec3::new(
            acc[0].iter().sum(),
            acc[1].iter().sum(),
            acc[2].iter().sum(),
        );
        for i in full..n {
            let g = lane(i);
            sum += Vec3::new(self.r[i], self.g[i], self.b[i]) * g;
        }
        Ok(sum)
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
        let mut radiance = Vec3::ZERO;
        for i in 0..self.len() {
            let (position, intensity) = self.light(i);
            radiance += shader.shade(&LightSample::point(
                i as u32,
                position,
                intensity,
                x,
                Lobe::All,
            ));
        }
        Ok(Illumination {
            radiance,
            lights: self.len() as u32,
        })
    }
}

/// The unshadowed light-probe value `L(x) = Σ B·I·g(d)` through any backend, with the clamped
/// fall-off [`falloff`](crate::falloff) at `h0`, and the number of lights it took.
pub fn probe<B: ManyLights>(backend: &B, x: Vec3, h0: f32) -> Result<Illumination, QueryError> {
    let mut shader = |s: &LightSample| s.intensity * crate::blend::falloff(s.distance, h0);
    backend.illuminate(&ShadingPoint::in_medium(x), &mut shader)
}
