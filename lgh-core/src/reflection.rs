//! The reflection model the error-bounded backends reason about: Phong's model as Paquette et al.
//! write it (`papers/004_…`, §4.1, eq. (1)) with `S = 1` and `f_att = 1/d²`:
//!
//! `I = Σ_i I_i / d_i² · ( k_d (N·L_i) + k_s (R_i·E)^n )`,
//!
//! with the dot products clamped at zero and the specular term only for lights above the surface
//! (`N·L_i > 0`). `k_d` multiplies the cosine directly, with no `1/π`, as in the paper. The light
//! octree's bounds (Appendix A), Ward's potential contributions and Lightcuts' bounds are all bounds
//! on this function, so a renderer that wants their guarantees shades with [`reflected`].

use glam::Vec3;

pub use crate::many_lights::Lobe;
use crate::many_lights::{Material, ShadingPoint};

/// Eq. (1) for one light of intensity `intensity` at `light`: the radiance it reflects at `point`
/// towards the viewer, restricted to `lobe`. Surfaces need [`ShadingPoint::normal`] (and
/// [`ShadingPoint::view`] for the specular term); without them the point is shaded as a medium
/// with the isotropic phase function `1/4π`. A light at the point itself contributes nothing.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::reflection::{reflected, Lobe};
/// use lgh_core::{Material, ShadingPoint};
///
/// let point = ShadingPoint {
///     position: Vec3::ZERO,
///     normal: Some(Vec3::Z),
///     geometric: None,
///     view: Some(Vec3::Z),
///     material: Material::Lambert { albedo: Vec3::splat(0.5) },
/// };
/// // A light of intensity 8 straight above at distance 2: k_d (N·L) I / d² = 0.5 · 1 · 8 / 4.
/// let l = reflected(&point, Vec3::new(0.0, 0.0, 2.0), Vec3::splat(8.0), Lobe::All);
/// assert_eq!(l, Vec3::splat(1.0));
/// // Below the surface: nothing.
/// assert_eq!(reflected(&point, Vec3::new(0.0, 0.0, -2.0), Vec3::ONE, Lobe::All), Vec3::ZERO);
/// ```
#[must_use]
pub fn reflected(point: &ShadingPoint, light: Vec3, intensity: Vec3, lobe: Lobe) -> Vec3 {
    let to_light = light - point.position;
    let d2 = to_light.length_squared();
    if d2 == 0.0 || !d2.is_finite() {
        return Vec3::ZERO;
    }
    let falloff = intensity / d2;
    let (kd, ks, n) = match point.material {
        Material::Isotropic => {
            return match lobe {
                Lobe::Specular => Vec3::ZERO,
                _ => falloff * crate::many_lights::ISOTROPIC_PHASE,
            };
        }
        Material::Lambert { albedo } => (albedo, Vec3::ZERO, 0.0),
        Material::Phong { kd, ks, exponent } => (kd, ks, exponent),
    };
    let Some(normal) = point.normal else {
        return Vec3::ZERO;
    };
    let l = to_light / crate::math::sqrt(d2);
    let cos_theta = normal.dot(l);
    if cos_theta <= 0.0 {
        return Vec3::ZERO;
    }
    let mut weight = Vec3::ZERO;
    if lobe != Lobe::Specular {
        weight += kd * cos_theta;
    }
    if lobe != Lobe::Diffuse && ks != Vec3::ZERO {
        if let Some(view) = point.view {
            // R = 2 (N·L) N − L, the mirror direction of L.
            let cos_alpha = (2.0 * cos_theta * normal - l).dot(view).max(0.0);
            weight += ks * libm::powf(cos_alpha, n);
        }
    }
    falloff * weight
}

#[cfg(test)]
mod tests {
    use super::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    fn surface(material: Material) -> ShadingPoint {
        ShadingPoint {
            position: Vec3::ZERO,
            normal: Some(Vec3::Z),
            geometric: None,
            view: Some(Vec3::new(0.6, 0.0, 0.8)),
            material,
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn lambert_is_kd_cos_over_d2() {
        let p = surface(Material::Lambert {
            albedo: Vec3::splat(0.5),
        });
        // Light at distance 2, 60° off the normal: cos θ = 1/2.
        let light = 2.0 * Vec3::new(libm::sqrtf(3.0) / 2.0, 0.0, 0.5);
        let l = reflected(&p, light, Vec3::splat(8.0), Lobe::All);
        assert!((l - Vec3::splat(8.0 / 4.0 * 0.5 * 0.5)).abs().max_element() < 1e-6);
        // Below the surface: nothing.
        assert_eq!(
            reflected(&p, -light, Vec3::ONE, Lobe::All),
            Vec3::ZERO,
            "a light below the surface must not light it"
        );
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn phong_lobes_add_up_and_peak_at_the_mirror_direction() {
        let p = surface(Material::Phong {
            kd: Vec3::splat(0.3),
            ks: Vec3::splat(0.7),
            exponent: 200.0,
        });
        // The mirror direction of the view about +z.
        let mirror = Vec3::new(-0.6, 0.0, 0.8) * 3.0;
        let all = reflected(&p, mirror, Vec3::ONE, Lobe::All);
        let diffuse = reflected(&p, mirror, Vec3::ONE, Lobe::Diffuse);
        let specular = reflected(&p, mirror, Vec3::ONE, Lobe::Specular);
        assert!((all - diffuse - specular).abs().max_element() < 1e-6);
        assert!((specular - Vec3::splat(0.7 / 9.0)).abs().max_element() < 1e-5);
        assert!((diffuse - Vec3::splat(0.3 * 0.8 / 9.0)).abs().max_element() < 1e-6);
        // Ten degrees off the mirror direction, n = 200 leaves cos(10°)^200 ≈ 0.047 % of the peak.
        let off = glam::Quat::from_rotation_y(10f32.to_radians()) * mirror;
        let s = reflected(&p, off, Vec3::ONE, Lobe::Specular);
        let expected = 0.7 / 9.0 * libm::powf(libm::cosf(10f32.to_radians()), 200.0);
        assert!((s.x - expected).abs() < 1e-7, "{} vs {expected}", s.x);
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn medium_uses_the_isotropic_phase_function() {
        let p = ShadingPoint::in_medium(Vec3::ZERO);
        let l = reflected(&p, Vec3::new(0.0, 2.0, 0.0), Vec3::ONE, Lobe::All);
        assert!((l.x - 1.0 / (16.0 * core::f32::consts::PI)).abs() < 1e-7);
    }
}
