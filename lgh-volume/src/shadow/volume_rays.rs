//! The cube maps' model without the maps: the same-model reference of the deep-shadow cube maps
//! (paper Sec. 4, eq. 6).
//!
//! A cube map tabulates, for one light, the optical depth from the light's illumination centre
//! `p_ℓi` outwards through the density prefiltered with the tent of width
//! `δ(d) = (1 − d/r_ℓ) s_ℓi + (d/r_ℓ) h_0` (coarse lights are volume lights). Ray-marched
//! shadows (`Shadows::RayMarch`) treat every light as a point seen through the plain density: a
//! different model for coarse lights, so the difference between those and the maps mixes what
//! the maps' discretisation costs (four depths, texels `h` wide at `r_ℓ`) with what the
//! prefilter changes. [`VolumeRays`] evaluates the maps' own model exactly, up to the step: the
//! integral of eq. 6's prefiltered density along the segment from the light's centre to the
//! shading point, marched from the light's end as the texel rays are. Comparing the maps with it
//! isolates their discretisation. It marches a ray per light per shading point, through two
//! pyramid levels per sample: a reference, slower than the point-light march.

use lgh_core::glam::Vec3;

use super::deep::filter_width;
use super::prefilter::DensityPyramid;
use super::Casters;
use crate::medium::{Medium, Volume};

/// Transmittance from each light of a hierarchy's levels through the density prefiltered for
/// that light (eq. 6), ray-marched: see the module docs.
#[derive(Clone, Debug)]
pub struct VolumeRays {
    pyramid: DensityPyramid,
    /// `σ_t` per unit density.
    kappa: f32,
    lo: Vec3,
    hi: Vec3,
    /// `h_0`, the filter width at `r_ℓ` (the voxel size).
    h0: f32,
    /// Step along a ray, world units.
    step: f32,
    prefilter: bool,
    /// A light whose optical depth exceeds this (transmittance below the cut-off) counts as
    /// hidden, as in the point march.
    tau_cut: f32,
    /// Per level: `r_ℓ` and every light's size `s_ℓi`.
    levels: Vec<(f32, Vec<f32>)>,
}

/// The cone steps' step ([`VolumeRays::spread_part`]) as a share of the filter's width: the
/// density prefiltered at width `δ` has no detail finer than `δ`, so two midpoint samples per
/// width integrate it closely. Measured on the explosion at 64³, the first scattered depth
/// against brute force: uniform steps +0.44%, cone steps +0.84% (the test
/// `coarse_lights_shadowed_as_volume_lights_keep_the_first_depth_near_brute_force`).
pub const CONE_STEP: f32 = 0.5;

impl VolumeRays {
    /// The reference for the maps [`CubeMaps::build`](super::CubeMaps::build) would make of
    /// `hierarchy` at `blending`'s α over `volume` in `medium` with `settings` (its
    /// `prefilter`; `step_voxels` of `step_voxels` voxels instead of the maps' step schedule),
    /// lights hidden below transmittance `cutoff`.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_volume::shadow::{Casters, VolumeRays};
    /// use lgh_volume::{procedural, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let light = PointLight::new(Vec3::new(0.0, 0.0, 0.9), Vec3::ONE);
    /// let lgh = LightingGridHierarchy::build(&[light], &GridSettings::default())?;
    /// let blending = lgh.blending(2.0)?;
    /// let rays = VolumeRays::new(Casters::new(&lgh, &blending), &volume, &medium, 0.5, 1e-3);
    /// // Through the smoke's middle the light is dimmed; from right beside it, hardly.
    /// let far = rays.transmittance(Vec3::new(0.0, 0.0, -0.9), 0, 0, light.position);
    /// let near = rays.transmittance(Vec3::new(0.0, 0.0, 0.89), 0, 0, light.position);
    /// assert!(far < near && near <= 1.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn new(
        casters: Casters<'_>,
        volume: &Volume,
        medium: &Medium,
        step_voxels: f32,
        cutoff: f32,
    ) -> Self {
        let Casters {
            hierarchy,
            blending,
            coarse,
        } = casters;
        let density = &volume.density;
        let levels: Vec<(f32, Vec<f32>)> = (0..=hierarchy.max_level())
            .map(|l| {
                let sizes = hierarchy.level(l).iter().map(|g| g.size).collect();
                (blending.radius(l), sizes)
            })
            .collect();
        let (lo, hi) = density.bounds();
        VolumeRays {
            pyramid: DensityPyramid::for_hierarchy(density, hierarchy, coarse),
            kappa: medium.extinction(1.0),
            lo,
            hi,
            h0: density.voxel_size,
            step: step_voxels.clamp(0.01, 64.0) * density.voxel_size,
            prefilter: casters.prefiltered(),
            // e^{−τ} < cutoff ⇔ τ > −ln cutoff.
            tau_cut: -cutoff.max(f32::MIN_POSITIVE).ln(),
            levels,
        }
    }

    /// Transmittance `e^{−τ}` from light `index` of `level`, centred at `centre`, to `x`: `τ`
    /// the midpoint-rule integral from the centre to `x` of `σ_t` times the density filtered at
    /// `δ(d)` (`d` the distance from the centre; samples outside the density's box add nothing),
    /// 0 below the cut-off. A light the hierarchy does not have is unshadowed.
    #[must_use]
    pub fn transmittance(&self, x: Vec3, level: u8, index: u32, centre: Vec3) -> f32 {
        self.march(x, level, index, centre).0
    }

    /// [`transmittance`](Self::transmittance) for each light (`centres` with their level and
    /// index in `ids`) into `out` (resized to match); returns the density samples taken.
    pub fn transmittances(
        &self,
        x: Vec3,
        centres: &[Vec3],
        ids: &[(u8, u32)],
        out: &mut Vec<f32>,
    ) -> u64 {
        out.clear();
        let mut samples = 0u64;
        for (&c, &(level, index)) in centres.iter().zip(ids) {
            let (v, n) = self.march(x, level, index, c);
            out.push(v);
            samples += u64::from(n);
        }
        samples
    }

    /// The transmittance and the density samples taken.
    fn march(&self, x: Vec3, level: u8, index: u32, centre: Vec3) -> (f32, u32) {
        let Some((r, sizes)) = self.levels.get(level as usize) else {
            return (1.0, 0);
        };
        let Some(&s) = sizes.get(index as usize) else {
            return (1.0, 0);
        };
        let v = x - centre;
        let dist = v.length();
        if !(dist > 0.0 && dist.is_finite()) {
            return (1.0, 0);
        }
        let dir = v / dist;
        // At most ~10⁶ steps (a ray across a 512³ box in 0.01-voxel steps is 8.9·10⁴).
        let n = (dist / self.step).ceil().clamp(1.0, 1e6) as u32;
        let dt = dist / n as f32;
        let (mut tau, mut samples) = (0.0f32, 0u32);
        for i in 0..n {
            let d = (i as f32 + 0.5) * dt;
            let y = centre + dir * d;
            if !super::in_box(y, self.lo, self.hi) {
                continue;
            }
            let width = filter_width(self.prefilter, d, s, *r, self.h0);
            tau += self.kappa * self.pyramid.sample(y, width) * dt;
            samples += 1;
            if tau > self.tau_cut {
                return (0.0, samples);
            }
        }
        ((-tau).exp(), samples)
    }

    /// [`march`](Self::march) from `centre` along `dir` for `dist`, for a light of size `s` and
    /// radius `r`, in cone steps: each step `max(step, CONE_STEP · δ)` with `δ` the width at
    /// its start (the width shrinks along the ray, so a step never spans more than it
    /// resolves), sampled at its midpoint on the pyramid level nearest its width. Returns the
    /// optical depth (∞ once past the cut-off) and the samples taken.
    fn march_cone(&self, centre: Vec3, dir: Vec3, dist: f32, s: f32, r: f32) -> (f32, u32) {
        // As many steps as the uniform march at most (its 10⁶ cap included).
        let least = self.step.max(dist / 1e6);
        let (mut d, mut tau, mut samples) = (0.0f32, 0.0f32, 0u32);
        while d < dist {
            let wide = CONE_STEP * filter_width(true, d, s, r, self.h0);
            let dt = wide.max(least).min(dist - d);
            let mid = d + 0.5 * dt;
            let y = centre + dir * mid;
            d += dt;
            if !super::in_box(y, self.lo, self.hi) {
                continue;
            }
            let width = filter_width(true, mid, s, r, self.h0);
            tau += self.kappa * self.pyramid.sample_nearest(y, width) * dt;
            samples += 1;
            if tau > self.tau_cut {
                return (f32::INFINITY, samples);
            }
        }
        (tau, samples)
    }

    /// The part of light `index` of `level`'s ray to `x` that reads the prefiltered density, in
    /// cone steps (`max(step, CONE_STEP · δ(d))`, `δ(d)` eq. 6's width at the distance `d` from
    /// the light's centre, so the steps are long near a coarse light, whose prefiltered density
    /// is smooth over its size, and shorten towards the shading point): from the light's centre to `r_ℓ` along the ray (the whole ray if `x` is
    /// nearer), where eq. 6's width falls to the plain density's. Returns its optical depth (∞
    /// past the cut-off), the point where the rest of the ray — plain density from there to
    /// `x` — starts (the centre itself for a light without spread), and the samples taken.
    /// [`Shadows::Volumes`](super::Shadows::Volumes) marches the rest as a point light's ray,
    /// eight abreast.
    #[must_use]
    pub fn spread_part(&self, x: Vec3, level: u8, index: u32, centre: Vec3) -> (f32, Vec3, u32) {
        let spread = self
            .levels
            .get(level as usize)
            .and_then(|(r, sizes)| Some((*r, *sizes.get(index as usize)?)));
        let v = x - centre;
        let dist = v.length();
        // Beyond the distance where eq. 6's width falls to 1.5 h_0, the nearest level is the
        // plain density: the rest of the ray is a point light's.
        let plain_from = |r: f32, s: f32| r * (s - 1.5 * self.h0) / (s - self.h0);
        match spread {
            Some((r, s))
                if self.prefilter && s > 1.5 * self.h0 && dist > 0.0 && dist.is_finite() =>
            {
                let dir = v / dist;
                let end = dist.min(plain_from(r, s));
                let (tau, samples) = self.march_cone(centre, dir, end, s, r);
                (tau, centre + dir * end, samples)
            }
            _ => (0.0, centre, 0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::DenseGrid;
    use crate::shadow::CoarseShadows;
    use lgh_core::{Blending, LightingGridHierarchy};
    use lgh_core::{GridSettings, PointLight};

    /// 64 lights on a 4³ lattice of spacing 0.2 around the origin, and its blending at α = 2.
    fn lattice() -> (LightingGridHierarchy, Blending) {
        let lights: Vec<PointLight> = (0..64)
            .map(|i| {
                let c = |k: u32| -0.3 + 0.2 * ((i >> (2 * k)) & 3) as f32;
                PointLight::new(Vec3::new(c(0), c(1), c(2)), Vec3::ONE)
            })
            .collect();
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        let blending = lgh.blending(2.0).unwrap();
        (lgh, blending)
    }

    /// A 4-unit box of 32³ voxels centred on the origin, density `rho(voxel centre)`.
    fn box_of(rho: impl Fn(Vec3) -> f32) -> Volume {
        let (n, h) = (32usize, 0.125f32);
        let mut density = DenseGrid::zeros([n; 3], h, Vec3::splat(-0.5 * h * (n - 1) as f32));
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let idx = density.index(i, j, k);
                    density.data[idx] = rho(density.centre(i, j, k));
                }
            }
        }
        Volume::new(density.clone(), density)
    }

    /// In a density linear in space the prefilter changes nothing (a symmetric tent of a linear
    /// function is the function), and the midpoint rule is exact: the reference is
    /// `e^{−σ_t ρ(midpoint) d}` to any point, for a point light and for a coarse one alike, as is
    /// the point-light march. The lights and the point lie well inside the box, so the widest
    /// filter stays inside it, where the tent of a linear function is the function.
    #[test]
    fn a_linear_density_gives_beer_lambert_for_every_light() {
        let rho = |p: Vec3| 0.5 + 0.1 * p.x - 0.05 * p.y + 0.08 * p.z;
        let volume = box_of(rho);
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let (lgh, blending) = lattice();
        let rays = VolumeRays::new(Casters::new(&lgh, &blending), &volume, &medium, 0.5, 0.0);
        let points = super::super::ShadowGrid::new(&volume, &medium, 0.5, 0.0);
        let x = Vec3::new(0.5, -0.4, 0.3);
        let mut checked = 0;
        for l in 0..=lgh.max_level() {
            for (i, g) in lgh.level(l).iter().enumerate() {
                if g.luminance <= 0.0 {
                    continue;
                }
                let p = g.position;
                let want = (-medium.extinction(rho(0.5 * (x + p))) * (x - p).length()).exp();
                let got = rays.transmittance(x, l, i as u32, p);
                let point = points.transmittance(x, p).0;
                // f32 sums of a few dozen samples: a few ulps each.
                for v in [got, point] {
                    assert!((v - want).abs() <= 1e-5, "level {l}: {v} vs {want}");
                }
                checked += 1;
            }
        }
        assert!(checked > 64, "coarse lights were checked too");
    }

    /// Coarse lights see the prefiltered density: a small dense blob just in front of a coarse
    /// light, on the way to the point, is spread by the light's wide filter, and casts a softer
    /// shadow than through the plain density.
    #[test]
    fn coarse_lights_see_the_prefiltered_density() {
        let (lgh, blending) = lattice();
        let (level, index) = (1..=lgh.max_level())
            .flat_map(|l| (0..lgh.level(l).len()).map(move |i| (l, i)))
            .find(|&(l, i)| lgh.level(l).get(i).size > 0.2)
            .expect("a coarse light");
        let p = lgh.level(level).get(index).position;
        let dir = Vec3::new(1.0, 0.2, 0.1).normalize();
        let (x, blob) = (p + dir, p + 0.15 * dir);
        let volume = box_of(|c| {
            if (c - blob).abs().max_element() < 0.1 {
                4.0
            } else {
                0.0
            }
        });
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let rays = |coarse| {
            let casters = Casters {
                coarse,
                ..Casters::new(&lgh, &blending)
            };
            VolumeRays::new(casters, &volume, &medium, 0.5, 0.0)
        };
        let soft = rays(CoarseShadows::Volumes).transmittance(x, level, index as u32, p);
        let hard = rays(CoarseShadows::Points).transmittance(x, level, index as u32, p);
        assert!(hard < 0.5, "the blob is in the way: {hard}");
        assert!(soft > 1.5 * hard, "prefiltered {soft} against plain {hard}");
    }
}
