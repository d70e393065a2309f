//! Representative VPLs of the hierarchy's coarse lights: beyond the paper, an alternative to
//! its Gaussian shadow samples (Fig. 11d) for lights that stand for surfaces.
//!
//! A coarse light `i` of level `ℓ` aggregates the input lights within one cell of its grid
//! vertex `v`, each with its trilinear weight `w_j = Π_a (1 − |p_j,a − v_a| / h_ℓ)` (eqs. 1,
//! 2). The paper shades it as a volume light: `k` shadow samples at `p_ℓi + σ ⊙ g`, Gaussian
//! offsets with its variance (eq. 4). On surfaces that Gaussian misleads twice: its samples
//! fall inside walls and blocks, or behind the surface the VPLs lie on, so their shadow rays
//! say "hidden" for light that is seen; and one point has no cosine lobe, while the VPLs it
//! stands for each have one about their own normal.
//!
//! Here the `k` samples are VPLs the light stands for instead, drawn once per light from its
//! own weights `w_j ‖I_j‖` by systematic sampling (`k` evenly spaced points of the weights'
//! cumulative sum, offset by a number seeded by the light's level and index): every sample lies
//! on a surface, in front of it, with its normal. Shading a sample is shading that VPL with
//! `1/k` of the light's blended intensity `B_ℓ(d) I_ℓi`
//! ([`Indirect::shade_representatives`](crate::indirect::Indirect::shade_representatives)). It is
//! a Monte Carlo estimate of the light's VPLs with `k` samples drawn in proportion to what they
//! carry, fixed per light, so it is deterministic and does not change from pixel to pixel or
//! frame to frame while the VPLs stay.

use lgh_core::glam::{DVec3, Vec3};
use lgh_core::random::SplitMix64;
use lgh_core::LightingGridHierarchy;
use rayon::prelude::*;

/// `k` representative input lights for every light of levels ≥ 1 of a hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Representatives {
    k: usize,
    /// Level `ℓ ≥ 1` at `ℓ − 1`: `k` indices (into the slice the hierarchy was built from) per
    /// light, in the level's order; [`NONE`] for a light with no weight.
    levels: Vec<Vec<u32>>,
}

/// Marks a light without representatives (no input light with weight: never reported).
const NONE: u32 = u32::MAX;

impl Representatives {
    /// Draws `k ≥ 1` representatives for every light of levels ≥ 1 of `lgh` (module docs), in
    /// parallel; the result does not depend on the thread count.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    /// use lgh_vpl::representatives::Representatives;
    ///
    /// // 64 lights on a 4 × 4 × 4 lattice.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let reps = Representatives::build(&lgh, 4);
    /// for level in 1..=lgh.max_level() {
    ///     for (i, light) in lgh.level(level).iter().enumerate() {
    ///         let r = reps.of(level, i as u32);
    ///         // A dark vertex (which queries never report) has none.
    ///         assert_eq!(r.len(), if light.luminance > 0.0 { 4 } else { 0 });
    ///         // Each lies within one cell of the light's grid vertex, as its weights say.
    ///         let v = lgh.origin() + Vec3::from(lgh.vertex(level, i as u32).unwrap().map(|c| c as f32)) * lgh.h(level);
    ///         for &j in r {
    ///             assert!((lights[j as usize].position - v).abs().max_element() < lgh.h(level));
    ///         }
    ///     }
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn build(lgh: &LightingGridHierarchy, k: u32) -> Self {
        let k = k.max(1) as usize;
        let origin = lgh.origin().as_dvec3();
        let levels = (1..=lgh.max_level())
            .map(|level| {
                let h = f64::from(lgh.h(level));
                let n = lgh.level(level).len() as u32;
                let per_light: Vec<Vec<u32>> = (0..n)
                    .into_par_iter()
                    .map(|i| {
                        let vertex = lgh.vertex(level, i).map_or(DVec3::NAN, |c| {
                            origin + DVec3::new(c[0].into(), c[1].into(), c[2].into()) * h
                        });
                        draw(lgh, level, i, vertex, h, k)
                    })
                    .collect();
                per_light.concat()
            })
            .collect();
        Representatives { k, levels }
    }

    /// Representatives per light.
    #[must_use]
    pub fn k(&self) -> usize {
        self.k
    }

    /// The representatives of light `index` of `level ≥ 1`: indices into the slice the
    /// hierarchy was built from (empty for level 0, out of range, or a light without weight).
    #[must_use]
    pub fn of(&self, level: u8, index: u32) -> &[u32] {
        let Some(all) = (level as usize)
            .checked_sub(1)
            .and_then(|l| self.levels.get(l))
        else {
            return &[];
        };
        let start = index as usize * self.k;
        match all.get(start..start + self.k) {
            Some(r) if r[0] != NONE => r,
            _ => &[],
        }
    }
}

/// `k` input lights of light `i` of `level` (grid vertex `vertex`, spacing `h`), by systematic
/// sampling of their weights `w_j ‖I_j‖`.
fn draw(
    lgh: &LightingGridHierarchy,
    level: u8,
    i: u32,
    vertex: DVec3,
    h: f64,
    k: usize,
) -> Vec<u32> {
    let level0 = lgh.level(0);
    let mut cands: Vec<(u32, f64)> = Vec::new();
    let reach = (3f64.sqrt() * h * (1.0 + 1e-6)) as f32;
    let centre: Vec3 = vertex.as_vec3();
    // The query cannot fail: the centre is finite for every light the hierarchy holds.
    let _ = lgh.lights_within(0, centre, reach, |j, _| {
        let p = level0.get(j as usize);
        let d = (p.position.as_dvec3() - vertex).abs() / h;
        let w = (1.0 - d).max(DVec3::ZERO);
        let w = w.x * w.y * w.z * f64::from(p.luminance);
        if w > 0.0 {
            if let Some(input) = lgh.input_index(j) {
                cands.push((input as u32, w));
            }
        }
    });
    let total: f64 = cands.iter().map(|c| c.1).sum();
    if total <= 0.0 || !total.is_finite() {
        return vec![NONE; k];
    }
    let mut rng = SplitMix64(SplitMix64::mix((u64::from(level) << 32) | u64::from(i)));
    let offset = f64::from(rng.next_f32());
    let mut out = Vec::with_capacity(k);
    let (mut c, mut acc) = (0, cands[0].1);
    for s in 0..k {
        let target = (s as f64 + offset) / k as f64 * total;
        while acc < target && c + 1 < cands.len() {
            c += 1;
            acc += cands[c].1;
        }
        out.push(cands[c].0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::{GridSettings, PointLight};

    /// Clumped lights of varied brightness (a fixed pseudo-random set).
    fn lights() -> Vec<PointLight> {
        let mut rng = SplitMix64(7);
        (0..3000)
            .map(|_| {
                let p = Vec3::new(rng.next_f32(), rng.next_f32() * 0.5, rng.next_f32()) * 10.0;
                let p = if rng.next_f32() < 0.5 { p * 0.2 } else { p };
                PointLight::new(p, Vec3::new(1.0, 0.5, 0.2) * (0.1 + 4.0 * rng.next_f32()))
            })
            .collect()
    }

    /// Systematic sampling gives each input light `j` of a coarse light `k p_j` picks up to
    /// one, `p_j = w_j ‖I_j‖ / Σ w ‖I‖` with the trilinear weights recomputed here from the
    /// vertex and `h_ℓ` — the representatives follow the light's own weights (eqs. 1, 2), on
    /// every level; and they do not depend on the thread count.
    #[test]
    fn representatives_follow_the_trilinear_weights() {
        let lights = lights();
        let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
        let k = 200;
        let reps = Representatives::build(&lgh, k);
        let mut checked = 0;
        for level in 1..=lgh.max_level() {
            let h = f64::from(lgh.h(level));
            for i in (0..lgh.level(level).len() as u32).step_by(37) {
                let c = lgh.vertex(level, i).unwrap();
                let v =
                    lgh.origin().as_dvec3() + DVec3::new(c[0].into(), c[1].into(), c[2].into()) * h;
                let weight = |l: &PointLight| {
                    let w = (1.0 - (l.position.as_dvec3() - v).abs() / h).max(DVec3::ZERO);
                    w.x * w.y * w.z * f64::from(lgh_core::luminance(l.intensity))
                };
                let total: f64 = lights.iter().map(weight).sum();
                let picks = reps.of(level, i);
                if total == 0.0 {
                    assert!(picks.is_empty());
                    continue;
                }
                assert_eq!(picks.len(), k as usize);
                for (j, l) in lights.iter().enumerate() {
                    let n = picks.iter().filter(|&&p| p as usize == j).count() as f64;
                    let expected = f64::from(k) * weight(l) / total;
                    assert!(
                        (n - expected).abs() <= 1.0 + 1e-6,
                        "level {level} light {i}: input {j} drawn {n} times, expected {expected}"
                    );
                }
                checked += 1;
            }
        }
        assert!(checked > 20, "{checked}");
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        assert_eq!(one.install(|| Representatives::build(&lgh, k)), reps);
        assert!(reps.of(0, 0).is_empty());
        assert!(reps.of(1, u32::MAX / 2).is_empty());
    }
}
