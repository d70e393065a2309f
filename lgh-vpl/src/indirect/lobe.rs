//! Glossy lobes too sharp for the hierarchy (beyond the paper): the VPLs inside the lobe's
//! cone shaded one by one, the rest through the hierarchy without the lobe.
//!
//! A coarse light at α stands for VPLs spread over about `1/α` radian seen from the point; a
//! Phong lobe `(R·l)^n` narrower than that (`n` in the hundreds at α = 4) is where the
//! hierarchy's aggregation errs by tens of percent (12.9% on the Cornell box's Phong spheres at
//! `Ns` 1000, `docs/gi.md`). At such a point the BRDF is split by direction (eq. (1) of
//! Paquette et al. separates the same two terms):
//!
//! - the diffuse term `k_d/π` over every VPL, through the hierarchy as everywhere else;
//! - the glossy term `k_s (n+2)/2π (R·l)^n` over the VPLs inside the cone `R·l ≥ cos θ_c`,
//!   each shaded exactly (its own lobe and shadow ray), found through the hierarchy's level-0
//!   index by a chain of balls along `R`;
//! - the glossy term outside the cone is left out.
//!
//! **The bound.** Outside the cone the glossy term is at most `τ = cos^n θ_c` times its peak, so
//! what is left out is at most `τ · k_s (n+2)/2π · U`, where `U = Σ I_j 2 cos_j cos θ_j g(d_j)`
//! sums every VPL's unshadowed light at the point. The cone is chosen per point so that
//! `τ = ε · ((k_d + k_s)/π) / (k_s (n+2)/2π)`, the smallest over the colour channels: the glossy
//! light left out is, in every channel, at most `ε` times `(k_d + k_s)/π · U`, the light the point would reflect unshadowed if all it
//! reflects were diffuse (under light from every direction alike, a Phong lobe reflects `k_s`
//! as a Lambertian surface reflects `k_d`). `ε` ([`DEFAULT_LOBE_ERROR`], 1%) is a bound, not an
//! estimate; it holds for a lobe without a diffuse part too (a glossy mirror, `k_d = 0`). Where
//! that cone would be wider than [`MAX_CONE`] (a wide lobe), the point is shaded by the
//! hierarchy as before: the lobe is then wide enough for it.

use lgh_core::glam::Vec3;
use lgh_core::{LightSample, Lobe, Material, ShadingPoint};

use super::Indirect;
use lgh_core::LightingGridHierarchy;

/// The bound ε of the glossy light a split point leaves out, relative to its diffuse light
/// (module docs): 1%.
pub const DEFAULT_LOBE_ERROR: f32 = 0.01;

/// The widest cone the VPLs are gathered in one by one, half-angle in radians: 0.6 (1.1 sr,
/// 9% of the sphere of directions). A lobe that needs more is left to the hierarchy.
pub const MAX_CONE: f32 = 0.6;

/// The cone of a glossy point: the mirror direction `R` and `cos θ_c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// The unit mirror direction of the view about the shading normal.
    pub axis: Vec3,
    /// The cosine of the half-angle.
    pub cos: f32,
}

impl Cone {
    /// The cone `point` is split at for the bound `error` (module docs), or `None` where it is
    /// not split: not Phong, no normal or view, or a cone wider than [`MAX_CONE`].
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{Material, ShadingPoint};
    /// use lgh_vpl::indirect::lobe::Cone;
    ///
    /// let phong = |exponent| ShadingPoint {
    ///     position: Vec3::ZERO,
    ///     normal: Some(Vec3::Y),
    ///     geometric: None,
    ///     view: Some(Vec3::new(0.0, 1.0, 1.0).normalize()),
    ///     material: Material::Phong { kd: Vec3::splat(0.2), ks: Vec3::splat(0.6), exponent },
    /// };
    /// // Ns 1000: a cone of 0.14 rad about the mirror direction; Ns 10: left to the hierarchy.
    /// let sharp = Cone::of(&phong(1000.0), 0.01).unwrap();
    /// assert!((sharp.cos.acos() - 0.143).abs() < 0.002, "{}", sharp.cos.acos());
    /// assert!((sharp.axis - Vec3::new(0.0, 1.0, -1.0).normalize()).length() < 1e-6);
    /// assert_eq!(Cone::of(&phong(10.0), 0.01), None);
    /// ```
    #[must_use]
    pub fn of(point: &ShadingPoint, error: f32) -> Option<Cone> {
        let Material::Phong { kd, ks, exponent } = point.material else {
            return None;
        };
        let (normal, view) = (point.normal?, point.view?);
        if !(exponent > 0.0 && ks.max_element() > 0.0) {
            return None;
        }
        // Per channel, the glossy peak `k_s (n+2)/2π` against `(k_d + k_s)/π`: τ is the
        // smallest ratio, so that the bound holds in every channel (and so in luminance).
        let ratio = |c: usize| (kd[c] + ks[c]) / (ks[c] * 0.5 * (exponent + 2.0));
        let tau = (0..3)
            .filter(|&c| ks[c] > 0.0)
            .map(|c| error * ratio(c))
            .fold(f32::INFINITY, f32::min);
        // τ ≥ 1: the whole glossy term is within the bound; the hierarchy shades it as it is.
        if tau.is_nan() || tau >= 1.0 {
            return None;
        }
        // cos^n θ_c = τ.
        let cos = tau.powf(1.0 / exponent);
        // NaN (a NaN τ) is not inside either.
        if cos.is_nan() || cos < MAX_CONE.cos() {
            return None;
        }
        let axis = (2.0 * normal.dot(view) * normal - view).normalize_or_zero();
        (axis != Vec3::ZERO).then_some(Cone { axis, cos })
    }

    /// Whether the direction from `x` to `y` is inside the cone at `x`.
    #[must_use]
    pub fn contains(&self, x: Vec3, y: Vec3) -> bool {
        let to = y - x;
        self.axis.dot(to) >= self.cos * to.length()
    }
}

/// Calls `f(index)` once for every level-0 light of `lgh` inside `cone` at `x` (up to `reach`
/// away), through [`LightingGridHierarchy::lights_within`] on a chain of balls along the axis:
/// the first around `x` covers the cone up to `h1`; each next one, centred at `t` on the axis
/// with radius `ρt`, `ρ = min(max(2 tan θ_c, 0.1), (1 + sin θ_c)/2)` (between `sin θ_c`, below which it
/// covers no stretch, and 1, at which it reaches back to the apex), covers its axial stretch
/// `[t x_lo, t x_hi]` (the roots of `(u − t)² + u² tan² θ_c = ρ² t²`), the stretches tiling
/// the axis, so each light is reported by the ball whose stretch holds its axial distance.
pub(crate) fn for_each_in_cone(
    lgh: &LightingGridHierarchy,
    x: Vec3,
    cone: &Cone,
    reach: f32,
    mut f: impl FnMut(u32),
) {
    let lights = lgh.level(0);
    let tan = (1.0 - cone.cos * cone.cos).max(0.0).sqrt() / cone.cos;
    let mut visit = |centre: Vec3, radius: f32, lo: f32, hi: f32| {
        // Errors only for a non-finite x, which no shading point has.
        let _ = lgh.lights_within(0, centre, radius, |i, _| {
            let y = lights.position(i as usize);
            let u = cone.axis.dot(y - x);
            if u >= lo && u < hi && cone.contains(x, y) {
                f(i);
            }
        });
    };
    let first = lgh.h1().max(1e-6);
    visit(
        x,
        first * (1.0 + tan * tan).sqrt() * (1.0 + 1e-4),
        f32::NEG_INFINITY,
        first,
    );
    let a = 1.0 + tan * tan;
    let sin = (1.0 - cone.cos * cone.cos).max(0.0).sqrt();
    // At least 0.1, so that a very narrow cone still takes few balls (ρ/(1 − ρ) growth).
    let rho = (2.0 * tan).max(0.1).min(0.5 * (1.0 + sin));
    let root = (1.0 - a * (1.0 - rho * rho)).max(0.0).sqrt();
    let (x_lo, x_hi) = ((1.0 - root) / a, (1.0 + root) / a);
    let mut start = first;
    // x_hi > x_lo > 0 for every cone narrower than a hemisphere; a degenerate one stops here
    // rather than spinning.
    if !(x_lo > 0.0 && x_hi > x_lo) {
        return;
    }
    while start < reach {
        let t = start / x_lo;
        let end = t * x_hi;
        let last = end >= reach;
        visit(
            x + cone.axis * t,
            rho * t * (1.0 + 1e-4),
            start,
            if last { f32::INFINITY } else { end },
        );
        start = end;
    }
}

impl Indirect<'_> {
    /// The glossy term alone at `point` from the VPLs of `lgh`'s level 0 inside `cone`, each
    /// shaded exactly (lobe, clamp, shadow ray), and how many.
    pub(crate) fn glossy_in_cone(
        &self,
        point: &ShadingPoint,
        cone: &Cone,
        lgh: &LightingGridHierarchy,
    ) -> (Vec3, u32) {
        let Material::Phong { ks, exponent, .. } = point.material else {
            return (Vec3::ZERO, 0);
        };
        let glossy = ShadingPoint {
            material: Material::Phong {
                kd: Vec3::ZERO,
                ks,
                exponent,
            },
            ..*point
        };
        let lights = lgh.level(0);
        // Every VPL lies on the mesh, so within its diameter of the point.
        let reach = self.scene.diameter() * 1.01 + 1e-3;
        let (mut sum, mut count) = (Vec3::ZERO, 0u32);
        for_each_in_cone(lgh, point.position, cone, reach, |i| {
            let position = lights.position(i as usize);
            let intensity = lights.intensity(i as usize);
            let sample = LightSample::point(i, position, intensity, point.position, Lobe::All);
            sum += self.shade(&glossy, &sample, lgh.input_index(i));
            count += 1;
        });
        (sum, count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::indirect::tests::Fixture;
    use lgh_core::random::SplitMix64;
    use lgh_core::{luminance, GridSettings, PointLight};

    /// The bound of the module docs, against brute force over every VPL of the room at points
    /// on its floor made glossy (`Ns` 300 and 2000, with `k_d` 0.3 and 0, views from several
    /// sides): the VPLs the cone gathers, plus the glossy light brute force finds outside the
    /// cone, is brute force's glossy light (the split is a partition, 1e-4 for the order of
    /// the sums); and that outside light is at most ε = 1% of what a Lambertian surface of
    /// albedo `k_d + k_s` receives there unshadowed.
    #[test]
    fn the_cone_leaves_out_at_most_epsilon_of_the_reflected_light() {
        let f = Fixture::new();
        let shader = f.shader();
        let unshadowed = f.unshadowed_shader();
        let level = f.lgh.level(0);
        let mut checked = 0;
        for (exponent, kd) in [(300.0f32, 0.3f32), (2000.0, 0.3), (2000.0, 0.0)] {
            for k in 0..12 {
                let a = k as f32 * 0.55;
                let position = Vec3::new(0.6 * a.cos(), 0.0, 0.6 * a.sin());
                let view = Vec3::new(a.sin(), 0.8 + 0.1 * k as f32, -a.cos()).normalize();
                let point = ShadingPoint {
                    position,
                    normal: Some(Vec3::Y),
                    geometric: None,
                    view: Some(view),
                    material: Material::Phong {
                        kd: Vec3::splat(kd),
                        ks: Vec3::splat(0.6),
                        exponent,
                    },
                };
                let cone = Cone::of(&point, DEFAULT_LOBE_ERROR).expect("a sharp lobe");
                let with = |material| ShadingPoint { material, ..point };
                let glossy = with(Material::Phong {
                    kd: Vec3::ZERO,
                    ks: Vec3::splat(0.6),
                    exponent,
                });
                let diffuse = with(Material::Lambert {
                    albedo: Vec3::splat(kd + 0.6),
                });
                // Brute force, split by the cone.
                let (mut inside, mut outside, mut lit) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
                for i in 0..level.len() as u32 {
                    let (p, intensity) = (level.position(i as usize), level.intensity(i as usize));
                    let s = LightSample::point(i, p, intensity, position, Lobe::All);
                    let vpl = f.lgh.input_index(i);
                    let g = shader.shade(&glossy, &s, vpl);
                    if cone.contains(position, p) {
                        inside += g;
                    } else {
                        outside += g;
                    }
                    lit += unshadowed.shade(&diffuse, &s, vpl);
                }
                let (gathered, _) = shader.glossy_in_cone(&point, &cone, &f.lgh);
                assert!(
                    (gathered - inside).abs().max_element() <= 1e-4 * inside.max_element() + 1e-9,
                    "Ns {exponent}, view {k}: {gathered} against {inside}"
                );
                assert!(
                    luminance(outside) <= DEFAULT_LOBE_ERROR * luminance(lit) * 1.0001,
                    "Ns {exponent}, view {k}: {outside} left out, diffuse {lit}"
                );
                checked += usize::from(inside != Vec3::ZERO);
            }
        }
        // Most lobes see some VPLs (the floor's views look up at the lit room).
        assert!(checked >= 18, "{checked} of 36 cones held light");
    }

    #[test]
    fn a_lobe_within_the_bound_is_not_split_and_narrow_cones_end() {
        // Kd 0.8, Ks 0.005, Ns 1: the whole glossy term is within 1% (τ ≥ 1): not split
        // (it once made a cone of cos 1 whose chain of balls never advanced).
        let weak = ShadingPoint {
            position: Vec3::ZERO,
            normal: Some(Vec3::Y),
            geometric: None,
            view: Some(Vec3::Y),
            material: Material::Phong {
                kd: Vec3::splat(0.8),
                ks: Vec3::splat(0.005),
                exponent: 1.0,
            },
        };
        assert_eq!(Cone::of(&weak, DEFAULT_LOBE_ERROR), None);
        // A cone of 1e-6 rad and one of cos 1 end, each light found by a full scan included.
        let lights: Vec<PointLight> = (0..100)
            .map(|i| PointLight::new(Vec3::new(0.05 * i as f32, 0.0, 0.0), Vec3::ONE))
            .collect();
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        for cos in [1e-6f32.cos(), 1.0] {
            let cone = Cone { axis: Vec3::X, cos };
            let mut found = 0;
            for_each_in_cone(&lgh, Vec3::new(-0.01, 0.0, 0.0), &cone, 10.0, |_| {
                found += 1
            });
            assert!(found <= 100, "{found}");
        }
    }

    #[test]
    fn the_chain_of_balls_finds_every_light_in_the_cone_once() {
        // 20,000 lights in a 4-unit cube; cones of several widths from a point inside it:
        // the lights reported are exactly those a scan of all finds, each once.
        let mut rng = SplitMix64(11);
        let lights: Vec<PointLight> = (0..20_000)
            .map(|_| PointLight::new(rng.next_in(Vec3::splat(-2.0), Vec3::splat(2.0)), Vec3::ONE))
            .collect();
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        let x = Vec3::new(0.3, -0.2, 0.1);
        for (axis, half) in [
            (Vec3::X, 0.05f32),
            (Vec3::new(1.0, 2.0, -0.5).normalize(), 0.2),
            (Vec3::new(-1.0, -1.0, 1.0).normalize(), 0.6),
        ] {
            let cone = Cone {
                axis,
                cos: half.cos(),
            };
            let mut found = Vec::new();
            for_each_in_cone(&lgh, x, &cone, 8.0, |i| found.push(i));
            let n = found.len();
            found.sort_unstable();
            found.dedup();
            assert_eq!(found.len(), n, "half-angle {half}: a light reported twice");
            let level = lgh.level(0);
            let want: Vec<u32> = (0..level.len() as u32)
                .filter(|&i| cone.contains(x, level.position(i as usize)))
                .collect();
            assert_eq!(found, want, "half-angle {half}");
            assert!(!want.is_empty());
        }
    }
}
