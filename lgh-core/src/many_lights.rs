//! The many-lights interface renderers shade through: the shading vocabulary ([`LightSample`],
//! [`Lobe`], [`Material`], [`ShadingPoint`], [`Shader`], [`Illumination`]), the [`ManyLights`]
//! trait every backend implements, and [`probe`].
//!
//! A renderer describes the point it shades ([`ShadingPoint`]: position, and for surfaces the normal,
//! view direction and material) and supplies a [`Shader`] that turns one light — an input light or a
//! cluster standing for many — into outgoing radiance, visibility included. A backend decides which
//! lights to present and sums what the shader returns. Backends that bound their error (the light
//! octree, Lightcuts, Ward's method) read the normal, view direction and material for their bounds;
//! the LGH and brute force ignore them.
//!
//! The backends live beside their structures: [`LghBackend`](crate::LghBackend) beside the
//! hierarchy, [`BruteForce`](crate::BruteForce) in its own module,
//! [`OctreeBackend`](crate::OctreeBackend), [`LightcutsBackend`](crate::LightcutsBackend) and
//! [`WardBackend`](crate::WardBackend) beside theirs. This module depends on none of them.

use glam::Vec3;

use crate::blend::falloff;
use crate::error::QueryError;

/// Which part of the reflection a light is shaded for.
///
/// The light octree treats the diffuse and the specular term separately (Paquette et al. §4.4: a
/// virtual light may stand in for a node's diffuse term while the same node's lights are shaded
/// one by one for the specular term), so it asks the shader for one term at a time. Other backends
/// ask for [`Lobe::All`]. Also reachable as `reflection::Lobe`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Lobe {
    /// The whole reflection (or the phase function in a medium).
    #[default]
    All,
    /// Only the diffuse term `k_d (N·L)`.
    Diffuse,
    /// Only the specular term `k_s (R·E)^n`.
    Specular,
}

/// One light presented to a shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Level ℓ of the light (0 for input lights).
    pub level: u8,
    /// Index of the light within its level (see
    /// [`LightingGridHierarchy::level`](crate::LightingGridHierarchy::level)).
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
    /// Blending weight `B_ℓ(d)` already folded into `intensity` (1 for non-LGH backends); with
    /// [`CoarseSpread::Averaged`](crate::CoarseSpread::Averaged), a coarse light's `B_ℓ/d²`
    /// averaged over its spread times `max(d, h0)²`, which may exceed 1.
    pub weight: f32,
    /// The part of the reflection to shade this light for ([`Lobe::All`] but for the light
    /// octree, which shades the diffuse and specular terms of eq. (1) separately).
    pub lobe: Lobe,
}

impl LightSample {
    /// Input light `index` — a point at full weight — seen from `x`, to be shaded for `lobe`.
    #[inline]
    #[must_use]
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

/// The isotropic phase function `1/4π`: the share of the light arriving at a point of a medium
/// ([`Material::Isotropic`]) that it scatters per unit solid angle towards any direction.
pub const ISOTROPIC_PHASE: f32 = 0.25 * core::f32::consts::FRAC_1_PI;

/// Where and what is shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    /// World position `x`.
    pub position: Vec3,
    /// Unit surface normal (the shading normal, interpolated from a mesh's vertex normals
    /// where it has them); `None` in a medium.
    pub normal: Option<Vec3>,
    /// The surface's own unit normal, on the same side as `normal`, where it differs from it
    /// (smooth shading over flat triangles): shadow rays leave the surface along it, and light
    /// behind it is hidden by the surface itself whatever `normal` says. `None`: `normal`.
    /// Renderers that trace shadow rays (`lgh-vpl`) read it; the core's unshadowed shading
    /// uses `normal` alone.
    pub geometric: Option<Vec3>,
    /// Unit direction towards the viewer; `None` if not needed.
    pub view: Option<Vec3>,
    /// Material.
    pub material: Material,
}

impl ShadingPoint {
    /// The normal shadow rays leave along and the surface hides light behind
    /// ([`geometric`](Self::geometric), or [`normal`](Self::normal) where it is `None`).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{Material, ShadingPoint};
    ///
    /// let flat = ShadingPoint { position: Vec3::ZERO, normal: Some(Vec3::Y), geometric: None, view: None, material: Material::Isotropic };
    /// assert_eq!(flat.geometric_normal(), Some(Vec3::Y));
    /// let smooth = ShadingPoint { geometric: Some(Vec3::Z), ..flat };
    /// assert_eq!(smooth.geometric_normal(), Some(Vec3::Z));
    /// assert_eq!(ShadingPoint::in_medium(Vec3::ZERO).geometric_normal(), None);
    /// ```
    #[must_use]
    pub fn geometric_normal(&self) -> Option<Vec3> {
        self.geometric.or(self.normal)
    }

    /// A point in a medium (no normal, isotropic phase function).
    #[must_use]
    pub fn in_medium(position: Vec3) -> Self {
        ShadingPoint {
            position,
            normal: None,
            geometric: None,
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
    #[must_use]
    fn name(&self) -> &'static str;

    /// Shades `point` with every light the method selects and returns the sum.
    fn illuminate<S: Shader>(
        &self,
        point: &ShadingPoint,
        shader: &mut S,
    ) -> Result<Illumination, QueryError>;

    /// Whether which lights are selected depends on what the shader returns. Lightcuts refines
    /// its cut by the shaded estimates and calls the shader on clusters it then replaces by
    /// their children, so its shader must return each light's whole contribution (shadows
    /// included) when called; a renderer may not gather the lights first and shade them later.
    /// `false` (the default) for methods whose selection depends on the point only: the
    /// hierarchy and brute force, whose every shader call is a term of the sum.
    #[must_use]
    fn selection_follows_shader(&self) -> bool {
        false
    }
}

/// The unshadowed light-probe value `L(x) = Σ B·I·g(d)` through any backend, with the clamped
/// fall-off [`falloff`](crate::falloff) at `h0`, and the number of lights it took.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::{probe, BruteForce, GridSettings, LghBackend, LightingGridHierarchy, PointLight};
///
/// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
/// let lights: Vec<PointLight> = (0..64u32)
///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
///     .map(|p| PointLight::new(p, Vec3::ONE))
///     .collect();
/// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
/// let x = Vec3::new(1.5, 1.5, 8.0);
/// let exact = probe(&BruteForce::new(&lights)?, x, lgh.h0())?;
/// let approx = probe(&LghBackend::new(&lgh, 2.0)?, x, lgh.h0())?;
/// assert_eq!(exact.lights, 64);
/// assert!(approx.lights < exact.lights);
/// // The paper's α = 2 is within a few per cent of the exact sum here.
/// assert!(((approx.radiance - exact.radiance) / exact.radiance).abs().max_element() < 0.05);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn probe<B: ManyLights>(backend: &B, x: Vec3, h0: f32) -> Result<Illumination, QueryError> {
    // What an isotropic point scatters, `I g / 4π` — what an error-bounded backend's bounds
    // (Lightcuts') are of — with the phase function undone afterwards.
    let mut shader = |s: &LightSample| s.intensity * (falloff(s.distance, h0) * ISOTROPIC_PHASE);
    let mut sum = backend.illuminate(&ShadingPoint::in_medium(x), &mut shader)?;
    sum.radiance /= ISOTROPIC_PHASE;
    Ok(sum)
}
