//! The physical reflection of the GI renderer's surfaces (Sec. 6.4): energy-conserving Lambert
//! and Phong, shared by the direct light ([`crate::direct`]), the VPLs' indirect light
//! ([`crate::indirect`]) and the light paths ([`crate::vpl`]).
//!
//! (Paquette et al.'s test scenes use [`lgh_core::reflection`] instead: the same Phong lobe
//! without the `1/π` normalisation, the model their error bounds are stated for.)

use lgh_core::glam::Vec3;
use lgh_core::{Material, ShadingPoint};

/// The BRDF of `point` (unit shading `normal`) for light arriving from the unit direction `l`:
/// Lambert `ρ/π`; Phong `k_d/π + k_s (n+2)/2π (R·E)^n`, `R` the mirror of `l`, `E` the view.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::{Material, ShadingPoint};
/// use lgh_vpl::brdf::brdf;
///
/// let grey = Material::Lambert { albedo: Vec3::splat(0.5) };
/// let p = ShadingPoint { position: Vec3::ZERO, normal: Some(Vec3::Y), geometric: None, view: Some(Vec3::Y), material: grey };
/// assert_eq!(brdf(&p, Vec3::Y, Vec3::X), Vec3::splat(0.5 / std::f32::consts::PI));
/// ```
#[must_use]
pub fn brdf(point: &ShadingPoint, normal: Vec3, l: Vec3) -> Vec3 {
    use std::f32::consts::PI;
    match point.material {
        Material::Lambert { albedo } => albedo / PI,
        Material::Phong { kd, ks, exponent } => {
            let spec = point.view.map_or(0.0, |view| {
                let r = 2.0 * normal.dot(l) * normal - l;
                (exponent + 2.0) / (2.0 * PI) * r.dot(view).max(0.0).powf(exponent)
            });
            kd / PI + ks * spec
        }
        Material::Isotropic => Vec3::ZERO,
    }
}

/// The diffuse albedo of `material`: what a light path keeps at a diffuse bounce and what a
/// VPL reflects (Lambert `ρ`, Phong `k_d`; a participating medium's phase function, none).
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::Material;
/// use lgh_vpl::brdf::diffuse_albedo;
///
/// let shiny = Material::Phong { kd: Vec3::splat(0.3), ks: Vec3::splat(0.5), exponent: 20.0 };
/// assert_eq!(diffuse_albedo(&shiny), Vec3::splat(0.3));
/// assert_eq!(diffuse_albedo(&Material::Isotropic), Vec3::ZERO);
/// ```
#[must_use]
pub fn diffuse_albedo(material: &Material) -> Vec3 {
    match *material {
        Material::Lambert { albedo } => albedo,
        Material::Phong { kd, .. } => kd,
        Material::Isotropic => Vec3::ZERO,
    }
}
