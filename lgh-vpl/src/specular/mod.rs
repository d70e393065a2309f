//! Specular paths, the standard companion of VPLs: at a mirror or a dielectric (glass) the
//! camera's path continues by reflection and refraction to the next surface, where the VPLs'
//! light is gathered, and light paths pass through such surfaces instead of depositing VPLs on
//! them (Keller's instant radiosity and its successors treat delta BSDFs the same way).
//!
//! - A **mirror** ([`Specular::Mirror`], MTL `illum` 3, 5 and 8) reflects `Ks` of what arrives
//!   along the mirrored direction; its `Kd`, if any, is shaded as a Lambertian surface beside it.
//! - A **dielectric** ([`Specular::Dielectric`], MTL `illum` 4, 6, 7 and 9) of index of
//!   refraction `η` (`Ni`) reflects the Fresnel fraction `F` of the light and refracts the rest
//!   by Snell's law, filtered by `Tf` where the light enters it (so once for light that passes
//!   in and out); where Snell's law has no solution the
//!   reflection is total. `F` is the exact unpolarised Fresnel reflectance of a dielectric
//!   interface, `((r_s² + r_p²)/2` with `r_s = (η_i cos θ_i − η_t cos θ_t)/(η_i cos θ_i + η_t
//!   cos θ_t)` and `r_p = (η_t cos θ_i − η_i cos θ_t)/(η_t cos θ_i + η_i cos θ_t)`). Which side
//!   is outside, the face's winding decides (its face normal points out): a dielectric's mesh
//!   must be closed and wound counter-clockwise seen from outside.
//!
//! The camera's path splits at a dielectric into its reflected and refracted branches
//! (deterministic: no random choice, so no noise and no flicker), each weighted by what it
//! carries; radiance refracted from medium `t` into medium `i` is scaled by `(η_i/η_t)²` (the
//! invariance of `L/η²`), which cancels on a path that leaves the medium it entered. A branch
//! ends after [`Scene::specular_depth`](crate::Scene::specular_depth) specular surfaces, or when what it carries is below
//! [`MIN_WEIGHT`] of the pixel's; what it would have brought is lost (a bias, the same for
//! every many-lights method, so comparisons against brute force stay exact). A light path
//! chooses one branch with the probability of its share (`F` or `Ks`'s luminance), keeping the
//! flux it carries unbiased.

use lgh_core::glam::Vec3;

mod paths;

pub(crate) use paths::{branches, camera_path, Branch};

/// A branch of a camera path carrying less than this fraction of the pixel (in luminance) is
/// not followed: 1/1000, a tenth of the 1% relative error the renderer's targets are stated at.
pub const MIN_WEIGHT: f32 = 1e-3;

/// The most specular surfaces a path may meet by default, camera and light paths alike: 6 (a
/// glass sphere's way in and out, with a reflection inside and a mirror besides).
pub const DEFAULT_SPECULAR_DEPTH: u32 = 6;

/// How a material reflects and transmits specularly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Specular {
    /// No specular part: the material's BRDF is all there is.
    #[default]
    None,
    /// A perfect mirror reflecting `reflectance` (MTL `Ks`).
    Mirror {
        /// The fraction reflected, per channel.
        reflectance: Vec3,
    },
    /// A smooth dielectric interface (glass, water).
    Dielectric {
        /// Index of refraction `η` inside (MTL `Ni`), outside being 1.
        ior: f32,
        /// The fraction of refracted light that enters, per channel (MTL `Tf`).
        transmittance: Vec3,
    },
}

impl Specular {
    /// Why `self` cannot be a material's specular part, if it cannot: a reflectance or a
    /// transmittance outside 0 to 1, an index of refraction that is not finite or not above
    /// zero.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::specular::Specular;
    ///
    /// assert!(Specular::Dielectric { ior: 1.5, transmittance: Vec3::ONE }.check().is_ok());
    /// assert!(Specular::Dielectric { ior: 0.0, transmittance: Vec3::ONE }.check().is_err());
    /// ```
    pub fn check(&self) -> Result<(), &'static str> {
        // Fractions: 0 to 1 (more would create light, and a camera path's branches would no
        // longer carry at most what reaches them).
        let fraction = |c: Vec3| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0;
        match *self {
            Specular::None => Ok(()),
            Specular::Mirror { reflectance } if fraction(reflectance) => Ok(()),
            Specular::Mirror { .. } => Err("a mirror's Ks must be from 0 to 1"),
            Specular::Dielectric { ior, .. } if !(ior.is_finite() && ior > 0.0) => {
                Err("the index of refraction Ni must be finite and above 0")
            }
            Specular::Dielectric { transmittance, .. } if !fraction(transmittance) => {
                Err("the transmission filter Tf must be from 0 to 1")
            }
            Specular::Dielectric { .. } => Ok(()),
        }
    }

    /// Whether the material has no diffuse or glossy part to shade: a dielectric.
    #[must_use]
    pub fn is_pure(&self) -> bool {
        matches!(self, Specular::Dielectric { .. })
    }
}

/// The unpolarised Fresnel reflectance of a dielectric interface for light arriving at
/// `cos_i = cos θ_i ≥ 0` from the side of index `eta_i` towards the side of index `eta_t`; 1
/// where the reflection is total.
///
/// ```
/// use lgh_vpl::specular::fresnel;
///
/// // Glass at normal incidence: ((1.5 − 1)/(1.5 + 1))² = 0.04, from either side.
/// assert!((fresnel(1.0, 1.0, 1.5) - 0.04).abs() < 1e-6);
/// assert!((fresnel(1.0, 1.5, 1.0) - 0.04).abs() < 1e-6);
/// // Past the critical angle asin(1/1.5) ≈ 41.8° inside the glass: total.
/// assert_eq!(fresnel(60f32.to_radians().cos(), 1.5, 1.0), 1.0);
/// ```
#[must_use]
pub fn fresnel(cos_i: f32, eta_i: f32, eta_t: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin_t2 = (eta_i / eta_t).powi(2) * (1.0 - cos_i * cos_i);
    if sin_t2 >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// The mirror direction of the unit `dir` about the unit normal `n`.
#[must_use]
pub fn reflect(dir: Vec3, n: Vec3) -> Vec3 {
    dir - 2.0 * dir.dot(n) * n
}

/// The direction the unit `dir` refracts to through a surface of unit normal `n` (on the side
/// `dir` comes from, `dir·n < 0`), the indices being `eta_i` on that side and `eta_t` beyond;
/// `None` where the reflection is total.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_vpl::specular::refract;
///
/// // Straight in: unbent.
/// assert_eq!(refract(-Vec3::Y, Vec3::Y, 1.0, 1.5), Some(-Vec3::Y));
/// // 45° into glass: sin θ_t = sin 45° / 1.5.
/// let d = Vec3::new(1.0, -1.0, 0.0).normalize();
/// let t = refract(d, Vec3::Y, 1.0, 1.5).unwrap();
/// assert!((t.x - 45f32.to_radians().sin() / 1.5).abs() < 1e-6);
/// ```
#[must_use]
pub fn refract(dir: Vec3, n: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
    let eta = eta_i / eta_t;
    let cos_i = -dir.dot(n);
    let sin_t2 = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin_t2 >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    Some((eta * dir + (eta * cos_i - cos_t) * n).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_conserves_energy_and_meets_its_limits() {
        // Reflected + refracted flux = 1 at every angle (no absorption at an interface), and
        // the reflectance rises to 1 at grazing incidence; from inside, total past the
        // critical angle. Checked against Brewster's angle, where r_p = 0: F = r_s²/2.
        let (n1, n2) = (1.0f32, 1.5f32);
        let brewster = (n2 / n1).atan();
        let cos_b = brewster.cos();
        let cos_t = (1.0 - (n1 / n2 * brewster.sin()).powi(2)).sqrt();
        let rs = (n1 * cos_b - n2 * cos_t) / (n1 * cos_b + n2 * cos_t);
        assert!((fresnel(cos_b, n1, n2) - 0.5 * rs * rs).abs() < 1e-6);
        assert!(fresnel(1e-4, n1, n2) > 0.99);
        let critical = (n1 / n2).asin();
        assert!(fresnel((critical - 0.01).cos(), n2, n1) < 1.0);
        assert_eq!(fresnel((critical + 0.01).cos(), n2, n1), 1.0);
        // Snell's law: η_i sin θ_i = η_t sin θ_t, and the refracted ray stays in the plane.
        for deg in [10.0f32, 30.0, 60.0, 85.0] {
            let a = deg.to_radians();
            let d = Vec3::new(a.sin(), -a.cos(), 0.0);
            let t = refract(d, Vec3::Y, n1, n2).unwrap();
            assert!((n1 * a.sin() - n2 * t.x).abs() < 1e-6, "{deg}°: {t}");
            assert!(t.z.abs() < 1e-7 && t.y < 0.0);
            // And back out along the reversed ray: the same angle.
            let back = refract(-t, -Vec3::Y, n2, n1).unwrap();
            assert!((back + d).length() < 1e-5, "{deg}°: {back}");
        }
    }
}
