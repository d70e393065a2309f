//! Per-point refinement of the coarse lights' samples, beyond the paper: a bound on each
//! point's error, not only on the image's.
//!
//! The hierarchy's default shading ([`Coarse::Adaptive`](super::Coarse::Adaptive)) estimates
//! each coarse light's VPLs at a point from a few of its representatives — 0.35 draws per
//! light on average, each resampled among four ([`resample`](super::resample)), shared in
//! proportion to an unshadowed guess of what each light brings. Most points
//! are well served, but where a few coarse lights carry a point and their representatives
//! disagree (a penumbra, a corner, a light half behind a pillar), that point's estimate can be
//! off by tens of percent while the image's RMSE stays at 2–3%. On Sponza at α = 4, 1.2% of the
//! pixels erred by more than 10% for this reason: with 8 samples per light on average, at most
//! 64, none did (`docs/gi.md`).
//!
//! A point's coarse estimate is a sum of independent per-light estimates, so its variance is
//! the sum of theirs, and the samples estimate it ([`Tally::variance`]):
//!
//! - a light shaded through `k ≥ 2` representatives: the sample variance of its `k` draws,
//!   over `k` — `(k Σy² − (Σy)²) / (k − 1)` for the shares `y` (each draw's estimate of the
//!   light is `k y`);
//! - a light shaded through one: one draw says nothing of its own spread, which has two parts.
//!   Whether the shadow ray gets through is taken as a Bernoulli draw with the fraction `v̄` of
//!   the point's coarse light that its shadow rays let through: `v̄ (1 − v̄) u²` for the draw's
//!   unshadowed share `u`. Which VPL was drawn — its lobe, its distance — is measured by `u`'s
//!   deviation from the light's own unshadowed light as the isotropic point the hierarchy
//!   holds, `u_ℓ`, scaled by the factor `r̂` that fits all the point's single draws best
//!   ([`WhichVpl`]): `(u − r̂ u_ℓ)²`, one draw's squared deviation from (an estimate of) its
//!   mean. The isotropic point misjudges the lights of one point alike — it has no lobe, so on
//!   a floor it gives the floor's own coarse lights light their VPLs do not — and what all
//!   lights share is not noise: measured against `(u − u_ℓ)²` on Sponza, the fit spends 7%
//!   fewer shadow rays with no pixel over the bound either way (`docs/gi.md`). A resampled
//!   draw ([`resample`](super::resample)) measures it from its own candidates instead,
//!   `s²_r / G`, unless every candidate was dark (then the fit); and a resampled draw whose
//!   ray was played for with probability `q` adds `y² (1 − q)` for what it gave, `y`;
//! - a light kept by Russian roulette with probability `p` and weight `1/p`: to the above,
//!   scaled by `1/p²`, is added `X² (1 − p)` for its weighted value `X` (an unbiased estimate
//!   of the roulette's own variance, `E[Y²](1 − p)/p`). That is the variance of independent
//!   roulettes; the systematic one (the `indirect::roulette` module) spreads the kept lights
//!   evenly and usually has less, so the rule over-states it and errs on the side of refining.
//!
//! If `z σ̂ > ε L` for the point's estimated luminance `L` (level 0's exact part included),
//! with `z` = [`CONFIDENCE_Z`], the coarse part is shaded again with [`GROWTH`] times the
//! samples, up to all the representatives there are ([`MAX_ROUNDS`] times at most, or until
//! every light has taken as many draws as it has representatives). A round shades only the
//! draws it adds (a light's draws keep their candidates from round to round, and past its
//! representatives they wrap around), and a light's roulette number is drawn once per point,
//! so a light the roulette kept keeps its draw in the next round, at its new weight (coupled
//! roulettes: the last round's light roulette is distributed as if drawn afresh; a light's
//! number of candidates a draw is the one its first round chose). The estimate is still
//! unbiased for a fixed number of rounds; stopping on the estimate itself adds a bias far
//! below the noise it removes (the refined render's mean is tested against that of every
//! representative).
//! Systematic sampling spreads the draws more evenly than independent ones, so the sample
//! variance over-states it: the rule errs on the side of refining.
//!
//! What it does not bound: the hierarchy's own smoothing (at α = 4 about 2% of the image's
//! light, measured with many samples), and the error of a light whose every representative has
//! been used.

use lgh_core::glam::Vec3;

/// The default per-point bound ε: 10% of the point's light (`lgh gi --point-error`).
pub const DEFAULT_POINT_ERROR: f32 = 0.1;

/// The normal quantile the estimated standard error is scaled by before it is held to the
/// bound: 1.645, two-sided 90%. A point whose estimate just meets the rule errs by more than ε
/// one time in ten, and most points are far inside it, so the fraction of points over ε is
/// far below 10%; the target is 1% of the pixels. Measured on Sponza at α = 4 (1,566 pixels,
/// `docs/gi.md`): 1.645 refines 27% of the points and leaves 0.70% of the pixels over 10%
/// (2.62% without refinement), 2.0 leaves 0.13% for 12% more shadow rays; with four times the
/// samples a round, 1.645 left 0.38% and 1.28 1.02%. (Before the which-VPL term, with VPLs
/// emitting about their shading normal: 2.576 refined 35% and left 0.13%, 1.645 10% and
/// 0.32%, 1.0 0.3% and 1.1%, against 1.2% without.)
pub const CONFIDENCE_Z: f64 = 1.645;

/// How much a refinement round multiplies the mean samples per coarse light: 2. A round
/// shades only the representatives the longer prefixes add, so doubling costs what it adds and
/// stops close to where the rule is met; on Sponza 4 (three rounds) left 0.38% of the pixels
/// over 10% for 33% more shadow rays than no bound, 2 (six rounds) 0.70% for 16% more
/// (`docs/gi.md`).
pub const GROWTH: f32 = 2.0;

/// The most refinement rounds at a point: six, in which the default 0.35 samples per light
/// grow to 22 (0.5, the default before, to 32, as many as a light's representatives by
/// default, `AdaptiveShading::max_samples`; a light whose share is above the mean takes
/// all of them sooner).
pub const MAX_ROUNDS: u32 = 6;

/// Luminance sums over the draws of one estimate (a coarse light's representatives at a
/// point), from which its variance is estimated.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// Draws (a VPL drawn `t` times counts `t` times).
    draws: u32,
    /// `Σ y` and `Σ y²` of the draws' shares, shadowed.
    lit: f64,
    lit_sq: f64,
    /// `Σ u` and `Σ u²` of the same shares, unshadowed.
    unshadowed: f64,
    unshadowed_sq: f64,
}

impl Tally {
    /// Adds a VPL drawn `times` times whose shares sum to `unshadowed` and `lit` (RGB): each
    /// of its `times` draws is `1/times` of them.
    pub fn add(&mut self, times: u32, unshadowed: Vec3, lit: Vec3) {
        let t = f64::from(times.max(1));
        let (u, y) = (
            f64::from(lgh_core::luminance(unshadowed)),
            f64::from(lgh_core::luminance(lit)),
        );
        self.draws += times.max(1);
        self.lit += y;
        self.lit_sq += y * y / t;
        self.unshadowed += u;
        self.unshadowed_sq += u * u / t;
    }

    /// The tally of the same draws with every share multiplied by `f` (an estimate of `k`
    /// draws seen as part of one of `k/f`).
    #[must_use]
    pub fn scaled(&self, f: f64) -> Tally {
        Tally {
            draws: self.draws,
            lit: self.lit * f,
            lit_sq: self.lit_sq * f * f,
            unshadowed: self.unshadowed * f,
            unshadowed_sq: self.unshadowed_sq * f * f,
        }
    }

    /// Both tallies' draws together.
    #[must_use]
    pub fn merged(&self, other: &Tally) -> Tally {
        Tally {
            draws: self.draws + other.draws,
            lit: self.lit + other.lit,
            lit_sq: self.lit_sq + other.lit_sq,
            unshadowed: self.unshadowed + other.unshadowed,
            unshadowed_sq: self.unshadowed_sq + other.unshadowed_sq,
        }
    }

    /// The draws tallied.
    #[must_use]
    pub fn draws(&self) -> u32 {
        self.draws
    }

    /// `Σ y`: the estimate's luminance.
    #[must_use]
    pub fn lit(&self) -> f64 {
        self.lit
    }

    /// `Σ u`: the estimate's luminance without shadows.
    #[must_use]
    pub fn unshadowed(&self) -> f64 {
        self.unshadowed
    }

    /// `Σ u²` of the draws' unshadowed shares.
    #[must_use]
    pub fn unshadowed_squares(&self) -> f64 {
        self.unshadowed_sq
    }

    /// The estimated variance of the estimate `Σ y` (module docs), `visible` being the
    /// fraction `v̄` of the point's unshadowed coarse light its shadow rays let through.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::indirect::refine::Tally;
    ///
    /// // Two draws, one seen and one hidden, each 1/2 of an estimate of luminance 1.
    /// let mut t = Tally::default();
    /// t.add(1, Vec3::splat(0.5), Vec3::splat(0.5));
    /// t.add(1, Vec3::splat(0.5), Vec3::ZERO);
    /// // The draws' estimates are 1 and 0: sample variance 1/2, over 2 draws.
    /// assert!((t.variance(0.5) - 0.25).abs() < 1e-6);
    /// // One draw: a Bernoulli visibility at the point's fraction.
    /// let mut one = Tally::default();
    /// one.add(1, Vec3::ONE, Vec3::ONE);
    /// assert!((one.variance(0.5) - 0.25).abs() < 1e-6);
    /// assert_eq!(one.variance(1.0), 0.0);
    /// ```
    #[must_use]
    pub fn variance(&self, visible: f64) -> f64 {
        if self.draws >= 2 {
            let k = f64::from(self.draws);
            ((k * self.lit_sq - self.lit * self.lit) / (k - 1.0)).max(0.0)
        } else {
            let v = visible.clamp(0.0, 1.0);
            v * (1.0 - v) * self.unshadowed_sq
        }
    }
}

/// The which-VPL part of the variance of a point's coarse lights shaded through one draw
/// each (module docs): for each, its unshadowed share `u` and its light's isotropic-point
/// estimate `u_ℓ`, weighted by `s` (`1/p²` under roulette). The variance is the least-squares
/// residual `Σ s u² − (Σ s u u_ℓ)² / Σ s u_ℓ²`, that of `u` about `r̂ u_ℓ` with the best `r̂`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WhichVpl {
    uu: f64,
    ul: f64,
    ll: f64,
}

impl WhichVpl {
    /// Adds a draw of unshadowed share `u` from a light whose isotropic point gives
    /// `point_like`, weighted by `s`.
    pub fn add(&mut self, u: f64, point_like: f64, s: f64) {
        self.uu += s * u * u;
        self.ul += s * u * point_like;
        self.ll += s * point_like * point_like;
    }

    /// The residual variance: 0 where every draw is the same multiple of its light's isotropic
    /// point, `Σ s u²` where no light has one.
    ///
    /// ```
    /// use lgh_vpl::indirect::refine::WhichVpl;
    ///
    /// // Every draw 0.4 times its point's estimate: the point misjudges them all alike.
    /// let mut alike = WhichVpl::default();
    /// for l in [1.0, 2.0, 0.5] {
    ///     alike.add(0.4 * l, l, 1.0);
    /// }
    /// assert!(alike.variance().abs() < 1e-12);
    /// // Two draws of one estimate, 1 and 3: the fit is r̂ = 2, each off by 1.
    /// let mut apart = WhichVpl::default();
    /// apart.add(1.0, 1.0, 1.0);
    /// apart.add(3.0, 1.0, 1.0);
    /// assert!((apart.variance() - 2.0).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn variance(&self) -> f64 {
        if self.ll > 0.0 {
            (self.uu - self.ul * self.ul / self.ll).max(0.0)
        } else {
            self.uu
        }
    }
}

/// Whether a point whose estimate has luminance `luminance` and estimated variance `variance`
/// needs more samples to stay within `bound`: `z σ̂ > ε L`.
#[must_use]
pub fn needs_refining(luminance: f64, variance: f64, bound: f32) -> bool {
    let allowed = f64::from(bound) * luminance.max(0.0);
    CONFIDENCE_Z * CONFIDENCE_Z * variance > allowed * allowed
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::random::SplitMix64;

    /// The fitted which-VPL variance against the spread it estimates: 200 lights whose draws
    /// scatter about 0.6 of their isotropic points (the points misjudge them alike), each by
    /// ±30% uniformly (variance `(0.6 u_ℓ)² · 0.03`). Over 2,000 points, the mean estimate is
    /// the true sum within 3% (the fit spends one of 200 degrees of freedom: −0.5%; the mean
    /// of 2,000 has a relative standard error under 1%). The unfitted `(u − u_ℓ)²` counts the
    /// shared misjudgement as noise: over five times too large.
    #[test]
    fn the_fitted_which_vpl_variance_matches_the_scatter() {
        let mut rng = SplitMix64(0xf17);
        let lights: Vec<f64> = (0..200)
            .map(|_| 0.5 + 1.5 * f64::from(rng.next_f32()))
            .collect();
        let truth: f64 = lights.iter().map(|l| (0.6 * l) * (0.6 * l) * 0.03).sum();
        let (mut fitted, mut unfitted) = (0.0, 0.0);
        let n = 2000;
        for _ in 0..n {
            let mut which = WhichVpl::default();
            for &l in &lights {
                let u = 0.6 * l * (1.0 + 0.6 * (f64::from(rng.next_f32()) - 0.5));
                which.add(u, l, 1.0);
                unfitted += (u - l) * (u - l);
            }
            fitted += which.variance();
        }
        let (fitted, unfitted) = (fitted / f64::from(n), unfitted / f64::from(n));
        println!("fitted {fitted:.4}, unfitted {unfitted:.4}, truth {truth:.4}");
        assert!(
            (fitted / truth - 1.0).abs() < 0.03,
            "{fitted} against {truth}"
        );
        assert!(unfitted > 5.0 * truth, "{unfitted} against {truth}");
    }

    /// The variance estimate against the spread it estimates: a light of 16 VPLs of which a
    /// fraction is hidden, estimated from `k` draws with replacement; over 20,000 repetitions
    /// the mean of the estimated variance matches the estimates' observed variance. For
    /// `k ≥ 2` it is the textbook unbiased sample variance (tolerance 5%: the observed
    /// variance over 20,000 repetitions has a relative standard error of about 1%, the mean
    /// estimate a few percent); for `k = 1` with the point's visible fraction equal to the
    /// light's, the Bernoulli term is exact when the draws differ only in visibility.
    #[test]
    fn the_estimated_variance_matches_the_observed_spread() {
        let hidden = [0, 3, 5, 6, 11]; // 5 of 16 VPLs hidden
        let seen = |i: usize| !hidden.contains(&i);
        for k in [1u32, 2, 4, 8] {
            let mut rng = SplitMix64(0x5eed + u64::from(k));
            let (mut sum, mut sum_sq, mut est) = (0.0f64, 0.0f64, 0.0f64);
            let n = 20_000;
            for _ in 0..n {
                let mut t = Tally::default();
                for _ in 0..k {
                    let i = (rng.next_u64() % 16) as usize;
                    let u = Vec3::splat(1.0 / k as f32);
                    t.add(1, u, if seen(i) { u } else { Vec3::ZERO });
                }
                sum += t.lit();
                sum_sq += t.lit() * t.lit();
                est += t.variance(11.0 / 16.0);
            }
            let mean = sum / n as f64;
            let observed = sum_sq / n as f64 - mean * mean;
            let estimated = est / n as f64;
            println!("k {k}: observed {observed:.5}, estimated {estimated:.5}");
            assert!(
                (estimated / observed - 1.0).abs() < 0.05,
                "k = {k}: {estimated} against {observed}"
            );
        }
    }

    /// The rule: within the bound it does not refine; a zero estimate with any spread does.
    #[test]
    fn the_rule_holds_the_scaled_deviation_to_the_bound() {
        // σ = 0.05 at L = 1: z σ = 0.082 ≤ 0.1.
        assert!(!needs_refining(1.0, 0.0025, 0.1));
        // σ = 0.07: z σ = 0.115 > 0.1.
        assert!(needs_refining(1.0, 0.0049, 0.1));
        assert!(needs_refining(0.0, 1e-12, 0.1));
        assert!(!needs_refining(0.0, 0.0, 0.1));
    }
}
