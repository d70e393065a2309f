//! Systematic Russian roulette over a point's coarse lights, beyond the paper.
//!
//! [`Coarse::Adaptive`](super::Coarse::Adaptive) owes each coarse light `want` samples at a
//! point. A light owed less than one is shaded with probability `p = want` and weighted by
//! `1/p`. Drawn independently, the number of lights the roulette keeps varies from point to
//! point about `Σ p`, and so may all land in one corner of the point's lights.
//!
//! Here the lights' probabilities are laid end to end, in the order the hierarchy's query
//! reports them (level by level, each level in the spatial order of its bricks), and one
//! uniform number `U` is drawn per point: light `i` is kept if an integer lies in
//! `[C_{i−1} − U, C_i − U)`, `C_i` the running sum of the probabilities. That is systematic
//! sampling (Madow's), and it is the roulette with the light's own number
//! `u_i = frac(U − C_{i−1})`, `p_i` to keep it: each `u_i` is uniform on `[0, 1)`, so each light
//! is still kept with probability `p_i` and the estimate is unbiased; but the kept lights are
//! spread evenly along the order, and their count is `⌊Σ p⌋` or `⌈Σ p⌉`.
//!
//! A light keeps its number when the per-point bound ([`refine`](super::refine)) asks for more
//! samples: a later round, whose probabilities are larger, keeps every light this one kept (the
//! rounds are coupled), each light still with its own probability.

/// The roulette's numbers `u_i = frac(U − C_{i−1})` of one point's lights, in order.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Systematic {
    /// `U`, uniform on `[0, 1)`.
    offset: f64,
    /// `C_{i−1}`: the probabilities of the lights so far.
    sum: f64,
}

impl Systematic {
    /// The sequence with offset `U = offset` (uniform on `[0, 1)`).
    #[must_use]
    pub(crate) fn new(offset: f64) -> Self {
        Systematic { offset, sum: 0.0 }
    }

    /// The next light's number `u`, for a light kept with probability `p` (`u < p`); a light
    /// with `p ≥ 1` is always kept and does not move the sequence (it gets 0).
    ///
    /// In f64: a 24-bit draw would make the probability of a tiny `p` differ from it.
    #[must_use]
    pub(crate) fn next(&mut self, p: f64) -> f64 {
        if p >= 1.0 {
            return 0.0;
        }
        let x = self.offset - self.sum;
        self.sum += p.max(0.0);
        // frac, for either sign of x: floor by truncation, one lower for a negative
        // fraction (`floor` is a library call on the x86-64 baseline, `rem_euclid` an fmod).
        // Exact for |x| < 2⁵³, far beyond any sum of a point's probabilities.
        let t = x as i64 as f64;
        let u = x - if t > x { t - 1.0 } else { t };
        // x − floor(x) can round up to 1 for a tiny negative x.
        if u < 1.0 {
            u
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::random::SplitMix64;

    /// Random probabilities, some tiny, some near one.
    fn probabilities(rng: &mut SplitMix64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|_| {
                let x = f64::from(rng.next_f32());
                x * x * x
            })
            .collect()
    }

    /// The count kept is `Σ p` rounded one way or the other, for any offset: the systematic
    /// sample's defining property. The same lights with independent numbers miss it.
    #[test]
    fn keeps_the_sum_of_the_probabilities_to_within_one() {
        let mut rng = SplitMix64(3);
        let mut independent_misses = 0;
        for _ in 0..200 {
            let p = probabilities(&mut rng, 300);
            let sum: f64 = p.iter().sum();
            let mut roulette = Systematic::new(f64::from(rng.next_f32()));
            let kept = p.iter().filter(|&&p| roulette.next(p) < p).count() as f64;
            assert!((kept - sum).abs() < 1.0 + 1e-9, "{kept} of {sum}");
            let independent = p.iter().filter(|&&p| f64::from(rng.next_f32()) < p).count();
            independent_misses += usize::from((independent as f64 - sum).abs() >= 1.0);
        }
        assert!(independent_misses > 100, "{independent_misses}");
    }

    /// Each light is kept with its own probability: over offsets spread evenly on `[0, 1)`,
    /// light `i` is kept in a fraction `p_i` of them, to within one offset (the offsets
    /// that keep it are an interval of length `p_i`, modulo 1). And every number is in
    /// `[0, 1)`; lights with `p ≥ 1` are always kept.
    #[test]
    fn keeps_each_light_with_its_probability() {
        let mut rng = SplitMix64(5);
        let mut p = probabilities(&mut rng, 64);
        p[10] = 1.0;
        p[20] = 3.5;
        let offsets = 4096;
        let mut kept = vec![0usize; p.len()];
        for k in 0..offsets {
            let mut roulette = Systematic::new((k as f64 + 0.5) / offsets as f64);
            for (i, &pi) in p.iter().enumerate() {
                let u = roulette.next(pi);
                assert!((0.0..1.0).contains(&u), "{u}");
                kept[i] += usize::from(u < pi);
            }
        }
        for (i, &pi) in p.iter().enumerate() {
            let want = pi.min(1.0) * offsets as f64;
            assert!(
                (kept[i] as f64 - want).abs() <= 1.0,
                "light {i}: {} of {want}",
                kept[i]
            );
        }
    }
}
