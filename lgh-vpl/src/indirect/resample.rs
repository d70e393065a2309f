//! Resampled draws of a coarse light's representatives, beyond the paper.
//!
//! The adaptive shading ([`Coarse::Adaptive`](super::Coarse::Adaptive)) gives most coarse
//! lights one shadow ray at a point, to one representative VPL. Which VPL it draws is then
//! most of the point's noise: on Sponza at α = 4, without shadow rays, one representative a
//! light errs by 1.97% against brute force, and every representative of the same lights by
//! 0.66% (`docs/gi.md`) — the lights' lobes, distances and blending differ across a cell,
//! and one draw sees one of them.
//!
//! Resampled importance sampling (Talbot, Bresenham and Gruber, "Importance Resampling for
//! Global Illumination", EGSR 2005) keeps the one ray and evaluates more VPLs without rays. A
//! light's `s`-th sample looks at `G` *candidates*, its representatives `sG .. (s + 1)G`:
//!
//! - each candidate `k` is evaluated unshadowed, `ũ_k` (its lobe, the BRDF, the fall-off and
//!   the blending: what the plain estimator, `Indirect::shade_drawn`, gives for that
//!   representative before its ray), with weight `r_k = ‖ũ_k‖` (luminance);
//! - one candidate is picked with probability `r_k / Σ r`, and one shadow ray traced to it;
//! - the sample is `V_k ũ_k · r̄ / r_k`, with `r̄ = Σ r / G` and `V_k` the ray's visibility.
//!
//! Given the candidates, the pick's expectation is `Σ_k (r_k / Σ r) V_k ũ_k r̄ / r_k =
//! (1/G) Σ_k V_k ũ_k`: the plain estimator over the same `G` representatives, each with its own
//! ray (a candidate with `r_k = 0` has `ũ_k = 0` and gives nothing either way). The `m`
//! samples of a light together look at its first `mG` representatives, a power-of-two prefix
//! of its nested draw (`m` and `G` are powers of two; a light drawn afresh takes a smaller `G`
//! the larger its `m`, so that `mG` stays within its representatives), whose plain estimate is
//! unbiased ([`crate::representatives`]); so is this one. A light the point bound
//! ([`refine`](super::refine)) draws again keeps its `G`, and draws past its representatives
//! wrap around: `m` draws then look at each run of `G` alike, `mG/len` times, each with a pick
//! of its own, and their mean is again unbiased. What is left of the which-VPL noise is the
//! spread of `r̄`, the mean of `G` unshadowed values; the visibility's noise is that of one
//! ray, now sent where the light is.
//!
//! A draw worth little at the point next to the others there — its light's share
//! overestimated, its candidates mostly turned away — plays for its shadow ray
//! (`RayRoulette`): traced with a probability in proportion to its value and weighted by
//! the inverse, it stays unbiased and spares the rays that carry least.
//!
//! The pick's number is drawn per point, light and sample from a hash
//! (`pick_number`), independent of the roulette that chose the light: the same on any
//! thread count.
//!
//! The point bound ([`refine`](super::refine)) needs one draw's variance. Its which-VPL part
//! is estimated from the candidates themselves: `s²_r / G`, the sample variance of the `r_k`
//! over `G` (an over-estimate for the stratified candidates, on the side of refining). Its
//! visibility part is the one of any single draw.

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_core::ShadingPoint;

use super::{Drawn, Indirect, Tally};

/// The candidates a resampled draw looks at by default (`lgh gi --candidates`): 4. On Sponza
/// at α = 4 without the point bound (`docs/gi.md`), 1, 2, 4 and 8 candidates erred by 2.49%,
/// 2.04%, 1.87% and 1.89% against brute force, for 792, 846, 884 and 913 shadow rays a pixel
/// (a candidate with no unshadowed light is never picked, so fewer draws go unlit).
pub const DEFAULT_CANDIDATES: u32 = 4;

/// The most candidates of one draw: 16. (Only powers of two are taken, so that a light's
/// draws look at a power-of-two prefix of its nested representatives.)
pub const MAX_CANDIDATES: u32 = 16;

/// The salt of the picks' hash at a shading point (the roulette's is `0xada << 40`).
pub(super) const PICK_SALT: u64 = 0x91c << 40;

/// The two numbers in `[0, 1)` of sample `s` of light `index` on level `level` at the point
/// whose seed is `seed`: the first picks its candidate, the second plays for its ray
/// ([`RayRoulette`]). A hash, so that a light's samples keep their numbers from one
/// refinement round to the next, and each is independent of the roulette over the lights.
#[inline]
#[must_use]
pub(super) fn pick_number(seed: u64, level: u8, index: u32, s: usize) -> (f64, f64) {
    let key = (u64::from(level) << 56) ^ (u64::from(index) << 8) ^ (s as u64 & 0xff);
    let mut numbers = SplitMix64(SplitMix64::mix(seed ^ key));
    (numbers.next_f64(), numbers.next_f64())
}

/// Russian roulette on the shadow rays of the resampled draws at one point, beyond the
/// paper: a draw whose value at the point (its candidates' mean `r̄`, over its light's
/// roulette probability) is below [`RAY_ROULETTE`] times the mean of the point's draws so far
/// traces its ray with probability `value / (RAY_ROULETTE · mean)`, and is weighted by its
/// inverse. Unbiased whatever the threshold: the roulette's number is the draw's own
/// (`pick_number`'s second), independent of its ray, and the mean is of values already
/// drawn. The first [`RAY_ROULETTE_WARM_UP`] draws at a point always trace. On Sponza at
/// α = 4 (53 × 30, the first pass, without the point bound) the draws below a quarter of the
/// point's mean (before the roulette) were 22% of the rays and carried 2.4% of the light.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RayRoulette {
    /// The draws' values so far, and how many.
    sum: f64,
    count: u32,
}

/// The fraction of the mean draw below which a draw's ray is played for (`RayRoulette`):
/// 0.35. Against brute force at α = 4 (`lgh gi`'s defaults otherwise), with none, 0.25,
/// 0.35, 0.5, 0.7 and 1.0:
///
/// | | none | 0.25 | 0.35 | 0.5 | 0.7 | 1.0 |
/// |---|---:|---:|---:|---:|---:|---:|
/// | Sponza (53 × 30) | 2.219% | 2.222% | 2.219% | 2.244% | 2.391% | 2.819% |
/// | its shadow rays a pixel | 583 | 524 | 506 | 479 | 445 | 402 |
/// | the Cornell box (`lgh bench gi`) | 2.199% | 2.228% | 2.241% | 2.302% | | |
///
/// On Sponza 0.25 took 0.94× no roulette's time and 0.5 0.977× 0.35's (alternating pairs):
/// 0.35 keeps both scenes' error, for 13% fewer rays on Sponza.
pub const RAY_ROULETTE: f64 = 0.35;

/// The draws at a point that always trace their ray, before their mean is trusted: 16.
pub const RAY_ROULETTE_WARM_UP: u32 = 16;

impl RayRoulette {
    /// The probability a draw worth `value` at the point traces its ray; the value is then
    /// counted in the mean.
    #[inline]
    pub(crate) fn probability(&mut self, value: f64) -> f64 {
        let q = if self.count < RAY_ROULETTE_WARM_UP || self.sum <= 0.0 {
            1.0
        } else {
            let cut = RAY_ROULETTE * self.sum / f64::from(self.count);
            (value / cut).min(1.0)
        };
        self.sum += value;
        self.count += 1;
        q
    }
}

/// How a resampled draw is made ([`Indirect::shade_resampled`]).
#[derive(Debug)]
pub(crate) struct How<'r> {
    /// Its numbers in `[0, 1)`: `u` picks the candidate, `v` plays for the ray
    /// ([`pick_number`]).
    pub(crate) numbers: (f64, f64),
    /// What the draw's value is worth at the point, times (its light's inverse roulette
    /// probability, its share of the light's draws).
    pub(crate) at_point: f32,
    /// The point's ray roulette.
    pub(crate) rays: &'r mut RayRoulette,
}

/// One resampled draw: what it gives, and the which-VPL variance of its unshadowed value in
/// luminance (0 with one candidate, which says nothing of it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Draw {
    /// The sample `V_k ũ_k r̄ / r_k` (RGB).
    pub(crate) lit: Vec3,
    /// `s²_r / G`.
    pub(crate) spread: f64,
    /// What the ray roulette adds to the draw's variance, estimated from the draw itself:
    /// `y² (1 − q)` in luminance for a draw `y` whose ray was played for with probability `q`
    /// (0 for a ray always traced). Its expectation is the roulette's variance,
    /// `u² V (1/q − 1)`, as the light roulette's `X² (1 − p)` is (`refine`).
    pub(crate) played: f64,
}

impl Indirect<'_> {
    /// One resampled draw of coarse light `light` at `point` (unit shading `normal`) among the
    /// representative VPLs `candidates` (at most [`MAX_CANDIDATES`]; the rest are ignored),
    /// picked by `how`'s `u` (module docs); `light`'s luminance is its own over the draws
    /// shaded at this call ([`How`]). At most one shadow ray, played for by the point's
    /// [`RayRoulette`]. The draw is added to `tally`.
    pub(crate) fn shade_resampled(
        &self,
        point: &ShadingPoint,
        normal: Vec3,
        light: Drawn<'_>,
        candidates: &[u32],
        how: How<'_>,
        tally: &mut Tally,
    ) -> Draw {
        let How {
            numbers: (u, chance),
            at_point,
            rays,
        } = how;
        let mut each = [(0usize, Vec3::ZERO, 0.0f32); MAX_CANDIDATES as usize];
        let n = candidates.len().min(each.len());
        // Their VPLs hinted together, so that the loads overlap (those `Pass::hint` hinted
        // two lights ahead may have left the cache since): without it the render took 1.03×
        // the time on Sponza (four alternating pairs).
        for &i in &candidates[..n] {
            if let Some(v) = self.vpls.get(i as usize) {
                crate::prefetch::prefetch(v);
            }
        }
        let mut sum = 0.0f32;
        for (slot, &i) in each.iter_mut().zip(candidates) {
            let i = i as usize;
            let Some(v) = self.vpls.get(i) else {
                continue;
            };
            let unshadowed = self.unshadowed_drawn(point, normal, light, v, light.luminance, 1.0);
            let r = lgh_core::luminance(unshadowed).max(0.0);
            *slot = (i, unshadowed, r);
            sum += r;
        }
        if n == 0 || sum <= 0.0 {
            tally.add(1, Vec3::ZERO, Vec3::ZERO);
            return Draw {
                lit: Vec3::ZERO,
                spread: 0.0,
                played: 0.0,
            };
        }
        // The first candidate whose running weight passes u Σr (the last lit one, should
        // rounding leave u Σr at the very top).
        let target = u * f64::from(sum);
        let (mut acc, mut pick) = (0.0f64, 0);
        for (k, &(_, _, r)) in each[..n].iter().enumerate() {
            if r > 0.0 {
                pick = k;
                acc += f64::from(r);
                if target < acc {
                    break;
                }
            }
        }
        let (i, unshadowed, r) = each[pick];
        let mean = sum / n as f32;
        let value = unshadowed * (mean / r);
        // Without shadow rays there is no ray to spare.
        let q = if self.settings.shadows {
            rays.probability(f64::from(mean * at_point))
        } else {
            1.0
        };
        // (Weighted by 1/q, which is 1 for a ray always traced.)
        let lit = if (q >= 1.0 || chance < q) && self.visible(point, normal, &self.vpls[i]) {
            value * (1.0 / q) as f32
        } else {
            Vec3::ZERO
        };
        tally.add(1, value, lit);
        let spread = if n >= 2 {
            let mean = f64::from(mean);
            let squares: f64 = each[..n]
                .iter()
                .map(|&(_, _, r)| (f64::from(r) - mean).powi(2))
                .sum();
            squares / (n - 1) as f64 / n as f64
        } else {
            0.0
        };
        let played = if q < 1.0 {
            let y = f64::from(lgh_core::luminance(lit));
            y * y * (1.0 - q)
        } else {
            0.0
        };
        Draw {
            lit,
            spread,
            played,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::indirect::tests::{light_sum, pool, rel_rmse, Fixture};
    use crate::indirect::{render_lgh, BlendAt, Coarse};
    use crate::representatives::{Allocation, Representatives};
    use lgh_core::{LghBackend, ShadingPoint};

    /// One draw's candidates in the room: a coarse light's first four representatives at a
    /// point the camera sees.
    struct Set<'r> {
        point: ShadingPoint,
        normal: Vec3,
        level: u8,
        index: u32,
        /// The light at its own luminance, unblended.
        drawn: Drawn<'static>,
        them: &'r [u32],
    }

    /// Every [`Set`] of the lights of `levels` (every 24th or so of a level, those with four
    /// representatives or more) at the points the room's camera sees at 8 × 6.
    fn candidate_sets<'r>(
        f: &Fixture,
        reps: &'r Representatives,
        levels: std::ops::RangeInclusive<u8>,
    ) -> Vec<Set<'r>> {
        let mut sets = Vec::new();
        for (point, normal) in f.seen(8, 6) {
            for level in levels.clone() {
                let lights = f.lgh.level(level);
                for index in (0..lights.len() as u32).step_by(lights.len() / 24 + 1) {
                    let all = reps.of(level, index);
                    if all.len() < 4 {
                        continue;
                    }
                    let drawn = Drawn {
                        luminance: lights.luminance(index as usize),
                        blend: None,
                    };
                    sets.push(Set {
                        point,
                        normal,
                        level,
                        index,
                        drawn,
                        them: &all[..4],
                    });
                }
            }
        }
        sets
    }

    /// A draw's [`How`]: numbers `u` and `v`, worth its own value at the point.
    fn how(u: f64, v: f64, rays: &mut RayRoulette) -> How<'_> {
        How {
            numbers: (u, v),
            at_point: 1.0,
            rays,
        }
    }

    /// A resampled draw's expectation over its pick is the plain estimate over its candidates,
    /// each with its own shadow ray (module docs): at points the camera sees in the room, for
    /// coarse lights of level 1 and 2 and their first `G` = 4 representatives, the draw
    /// averaged over 4,096 evenly spread pick numbers against [`Indirect::shade_drawn`] over
    /// the same four. The draw is piecewise constant in the number, with at most `G` steps, so
    /// the even spread errs by at most `(G − 1)/4,096` of its largest value — the largest
    /// `ũ_k r̄ / r_k` of the candidates, computed here from their unshadowed light — asserted
    /// per channel, with 1e-5 of it for the f32 sums. The test bites: some of the candidate
    /// sets are partly hidden, so visibility and the pick interact.
    #[test]
    fn a_resampled_draw_averages_to_its_candidates_plain_estimate() {
        let f = Fixture::new();
        let shader = f.shader();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(8));
        let (mut checked, mut mixed) = (0, 0);
        for Set {
            point,
            normal,
            level,
            index,
            drawn,
            them,
        } in candidate_sets(&f, &reps, 1..=2)
        {
            let mut plain_tally = Tally::default();
            let ids = them.iter().map(|&i| i as usize);
            let plain = shader.shade_drawn(&point, normal, drawn, ids, &mut plain_tally);
            let n = 4096;
            let mut mean = Vec3::ZERO.as_dvec3();
            let mut seen = [false; 2];
            for k in 0..n {
                let u = (k as f64 + 0.5) / n as f64;
                let mut tally = Tally::default();
                // A fresh ray roulette always traces (its warm-up).
                let fresh = &mut RayRoulette::default();
                let draw = shader.shade_resampled(
                    &point,
                    normal,
                    drawn,
                    them,
                    how(u, 0.5, fresh),
                    &mut tally,
                );
                mean += draw.lit.as_dvec3() / n as f64;
                if tally.unshadowed() > 0.0 {
                    seen[usize::from(tally.lit() > 0.0)] = true;
                }
            }
            // The largest value a pick can take: `ũ_k r̄ / r_k` over the lit candidates.
            let lit: Vec<Vec3> = them
                .iter()
                .map(|&i| {
                    let v = &f.vpls[i as usize];
                    shader.unshadowed_drawn(&point, normal, drawn, v, drawn.luminance, 1.0)
                })
                .collect();
            let r = |u: &Vec3| f64::from(lgh_core::luminance(*u));
            let r_mean = lit.iter().map(r).sum::<f64>() / 4.0;
            let largest = lit
                .iter()
                .filter(|u| r(u) > 0.0)
                .map(|u| u.as_dvec3().max_element() * r_mean / r(u))
                .fold(0.0, f64::max);
            let off = (mean - plain.as_dvec3()).abs().max_element();
            let bound = (3.0 / n as f64 + 1e-5) * largest;
            assert!(
                off <= bound,
                "{level}/{index}: {mean} against {plain}, bound {bound}"
            );
            checked += usize::from(plain != Vec3::ZERO);
            mixed += usize::from(seen == [true, true]);
        }
        println!("{checked} lit candidate sets, {mixed} partly hidden");
        assert!(checked > 20 && mixed > 0, "{checked} {mixed}");
    }

    /// The ray roulette's probability: 1 through the warm-up and for draws worth at least
    /// [`RAY_ROULETTE`] times the mean so far, else the draw's value over that; every value
    /// counted in the mean.
    #[test]
    fn the_ray_roulette_plays_for_the_rays_of_small_draws() {
        let mut rays = RayRoulette::default();
        for _ in 0..RAY_ROULETTE_WARM_UP {
            assert_eq!(rays.probability(1e-9), 1.0);
        }
        // The mean is now 1e-9: a draw of 2 is far above it.
        assert_eq!(rays.probability(2.0), 1.0);
        let warm = f64::from(RAY_ROULETTE_WARM_UP);
        let mean = (warm * 1e-9 + 2.0) / (warm + 1.0);
        let q = rays.probability(0.01);
        assert!((q - 0.01 / (RAY_ROULETTE * mean)).abs() < 1e-12, "{q}");
        assert_eq!(RayRoulette::default().probability(0.0), 1.0);
    }

    /// A draw whose ray is played for averages to the same draw traced: at the room's points
    /// and candidate sets (as above), with a roulette whose mean is ten times the draw's
    /// value (so `q = 1/(10 RAY_ROULETTE)`), the draw averaged over 4,096 evenly spread
    /// roulette numbers against the draw with its ray. Kept with probability `q` and
    /// weighted `1/q`, the even spread errs by at most `1/(4,096 q)` of the traced value
    /// (asserted, with 1e-5 of it for f32). Some draws are hidden, some seen: it bites both
    /// ways.
    #[test]
    fn a_draw_whose_ray_is_played_for_is_unbiased() {
        let f = Fixture::new();
        let shader = f.shader();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(8));
        let (mut checked, mut hidden) = (0, 0);
        for Set {
            point,
            normal,
            index,
            drawn,
            them,
            ..
        } in candidate_sets(&f, &reps, 1..=1)
        {
            let u = 0.37;
            let mut tally = Tally::default();
            let fresh = &mut RayRoulette::default();
            let traced =
                shader.shade_resampled(&point, normal, drawn, them, how(u, 0.0, fresh), &mut tally);
            if tally.unshadowed() <= 0.0 {
                continue;
            }
            // The draw's value at the point is the candidates' mean luminance.
            let value = tally.unshadowed();
            let primed = RayRoulette {
                sum: 10.0 * value * f64::from(RAY_ROULETTE_WARM_UP),
                count: RAY_ROULETTE_WARM_UP,
            };
            let q = 1.0 / (10.0 * RAY_ROULETTE);
            let n = 4096;
            let mut mean = Vec3::ZERO.as_dvec3();
            for k in 0..n {
                let v = (k as f64 + 0.5) / n as f64;
                let (rays, tally) = (&mut primed.clone(), &mut Tally::default());
                let draw =
                    shader.shade_resampled(&point, normal, drawn, them, how(u, v, rays), tally);
                mean += draw.lit.as_dvec3() / n as f64;
            }
            let full = traced.lit.as_dvec3();
            let scale = full.max_element().max(value);
            let bound = (1.0 / (n as f64 * q) + 1e-5) * scale;
            let off = (mean - full).abs().max_element();
            assert!(
                off <= bound,
                "{index}: {mean} against {full}, bound {bound}"
            );
            checked += 1;
            hidden += usize::from(traced.lit == Vec3::ZERO);
        }
        println!("{checked} draws, {hidden} hidden");
        assert!(
            checked > 20 && hidden > 0 && hidden < checked,
            "{checked} {hidden}"
        );
    }

    /// Resampled draws in the room at α = 4 with shadow rays, at `lgh gi`'s default mean
    /// ([`DEFAULT_ADAPTIVE_SAMPLES`](crate::gi::DEFAULT_ADAPTIVE_SAMPLES), 0.35 draws a light):
    /// unbiased, their image's mean that of every coarse light shaded through all 32 of its
    /// representatives; and less noisy than as many draws of one representative each.
    /// Measured (32 × 24, blended per representative): 4 candidates 4.38% from brute force
    /// against 6.53% with 1, the mean 0.9951 times the complete estimate's (at 0.5 draws a
    /// light, the default before: 3.4%, 5.4%, 0.9965).
    /// Asserted: the error falls by a fifth or more (measured: by a third), and the mean is
    /// within 1.25% of the complete estimate's, 2.5× the 0.49% measured: the image's mean is
    /// one draw of the estimator, its spread the per-pixel noise of a few percent over 768
    /// pixels that share lights, so a bias of 1% or more fails while the draw's own deviation
    /// passes; the image is the same on 1 and 3 threads.
    #[test]
    fn resampled_draws_are_unbiased_and_err_less() {
        let f = Fixture::new();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(32));
        let (shader, camera) = (f.shader(), Fixture::camera(32, 24));
        let exact = f.exact(&shader, &camera);
        let backend = LghBackend::new(&f.lgh, 4.0).unwrap();
        let render = |mean: f32, candidates: u32| {
            let coarse = Coarse::Adaptive {
                reps: &reps,
                mean,
                blend: BlendAt::Representative,
                candidates,
            };
            render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {}).unwrap()
        };
        let mean = crate::gi::DEFAULT_ADAPTIVE_SAMPLES;
        let (one, four) = (render(mean, 1), render(mean, DEFAULT_CANDIDATES));
        let complete = render(64.0, 1);
        let (e1, e4) = (rel_rmse(&one, &exact), rel_rmse(&four, &exact));
        let ratio = light_sum(&four) / light_sum(&complete);
        println!("1 candidate {e1:.4}, 4 candidates {e4:.4}; mean {ratio:.4}");
        assert!(e4 < 0.8 * e1, "{e4} against {e1}");
        assert!((ratio - 1.0).abs() < 0.0125, "{ratio}");
        let again = || render(mean, DEFAULT_CANDIDATES);
        assert_eq!(pool(1).install(again), pool(3).install(again));
    }
}
