//! Adaptive knots: a texel's transmittance `V(d) = e^{−τ(d)}` as `K` (distance, value) knots
//! placed where `V` changes, instead of `τ` at fixed distances `D/n … D` ([`Depths::Adaptive`]).
//!
//! This is the deep shadow map of Lokovic & Veach (2000) compressed as in the adaptive volumetric
//! shadow maps of Salvi et al. (2010): along the texel's dense march, every step that crosses
//! smoke adds a node `(d, τ)` to a buffer of at most [`BUFFER`] nodes, and a full buffer drops
//! the node whose removal costs least (Salvi's node removal); once the ray is traced, nodes are
//! dropped the same way until `K` remain. Unreal Engine's heterogeneous-volume shadows keep at
//! most eight such nodes a texel. Salvi's cost is the area the polyline of `V` changes by; ours
//! is what the image sees ([`Knots::interior_cost`]): the change `ΔV` of the light a point
//! receives, where the lookup would interpolate without the node, times the shading points it
//! moves (the scattering a point adds is `∝ ρ`, and `∫ρ` is `τ` itself), weighted by the
//! level's blending weight `B_ℓ` (eq. 3), which is zero nearer than `r_{ℓ−1}`: no knot is spent
//! where the level is never looked up. On the demo this takes four knots from 5.45% (Salvi's
//! area) to 1.74% against the maps' own model (`docs/shadows.md`). Steps through clear space
//! add no node: `τ` is constant there, and the node that starts the next rise is added with it,
//! so the polyline is flat across gaps.
//!
//! **Storage.** A knot is two bytes, one `u16`: its distance in 255ths of the reach `D` (high
//! byte) and its `V` in 255ths (low byte). `K = 4` knots are the eight bytes of the paper's four
//! 16-bit depths. The lookup walks the knots from an implicit first one at the light `(0, 1)`,
//! interpolates between the two around the distance and holds the last value beyond the last
//! knot; the texels around a direction are blended bilinearly, and `V = e^{−τ}` taken last, as
//! the fixed depths do. It interpolates `τ = −ln V`, not `V`: within a step of the march `τ` is
//! linear (the midpoint rule), so between two nodes that were consecutive steps the lookup is
//! the march itself, where a chord of the convex `e^{−τ}` would leak light through a rise of
//! several units of `τ` in a step (the soot rim of the demo). Both steps are continuous in the
//! shading point; knots that move between frames are measured as flicker (`docs/shadows.md`).
//!
//! [`Depths::Adaptive`]: super::Depths::Adaptive

use lgh_core::glam::Vec3;

use super::cube;
use super::lookup::{self, Slot};

/// Nodes the streaming buffer holds, besides the light's `(0, 1)`: the most knots a texel may
/// keep. A larger buffer lets the removals see more of the ray at once; on the demo, 32 moved
/// the image by 0.002% of its error (1.948% against 1.949% for four knots) for 5% more time.
pub(super) const BUFFER: usize = 16;

/// Quantisation steps of a knot's distance (per reach) and value.
pub(super) const STEPS: f32 = 255.0;

/// A texel ray's nodes, as its march goes (see the module docs).
#[derive(Clone, Copy, Debug)]
pub(super) struct Knots {
    /// Knots to keep.
    keep: usize,
    /// Where lookups weigh (see [`Knots::new`]).
    support: Support,
    /// The distance of the last stored knot, `D`.
    reach: f32,
    /// Nodes in use, the light's `(0, 1)` at index 0 included.
    len: usize,
    /// Distances, optical depths and transmittances of the nodes, in order of distance.
    d: [f32; BUFFER + 1],
    tau: [f32; BUFFER + 1],
    v: [f32; BUFFER + 1],
    /// `B_ℓ` at each node.
    b: [f32; BUFFER + 1],
    /// What dropping each interior node costs ([`Knots::interior_cost`]), kept up to date.
    cost: [f32; BUFFER + 1],
}

impl Knots {
    /// No node yet but the light's; `keep` knots to store for lookups over `support`, to
    /// `reach`. A coarse level's lights are only looked up beyond `r_{ℓ−1}`, where its
    /// blending weight `B_ℓ` starts (eq. 3): nearer, the finer levels light every point. So no
    /// knot is spent there: the first node is `τ` at `r_{ℓ−1}`, reached from the light in a
    /// straight line no lookup reads.
    pub(super) fn new(keep: usize, support: Support, reach: f32) -> Self {
        let mut k = Knots {
            keep,
            support,
            reach,
            len: 1,
            d: [0.0; BUFFER + 1],
            tau: [0.0; BUFFER + 1],
            v: [0.0; BUFFER + 1],
            b: [0.0; BUFFER + 1],
            cost: [0.0; BUFFER + 1],
        };
        k.v[0] = 1.0;
        k.b[0] = support.weight(0.0);
        k
    }

    /// A step of the march from `d0` to `d1` through which `τ` rose from `tau0` to `tau1`.
    #[inline]
    pub(super) fn step(&mut self, d0: f32, tau0: f32, d1: f32, tau1: f32) {
        let inner = self.support.inner;
        if d1 <= inner {
            return;
        }
        if self.len == 1 && inner > 0.0 {
            // τ at the inner edge: on this step, or before it, flat since.
            let t = if d0 < inner {
                tau0 + (tau1 - tau0) * ((inner - d0) / (d1 - d0))
            } else {
                tau0
            };
            self.push(inner, t);
        }
        if self.d[self.len - 1] < d0 {
            // Clear space since the last node: V was flat up to here.
            self.push(d0, tau0);
        }
        self.push(d1, tau1);
    }

    /// Appends the node at `d` where the optical depth is `tau`, first dropping the least
    /// important interior node if the buffer is full (the last node stays: the march goes on
    /// from it).
    fn push(&mut self, d: f32, tau: f32) {
        if self.len == BUFFER + 1 {
            self.remove(false);
        }
        self.d[self.len] = d;
        self.tau[self.len] = tau;
        self.v[self.len] = lookup::exp_neg(tau.min(80.0));
        self.b[self.len] = self.support.weight(d);
        self.len += 1;
        if self.len >= 3 {
            // The last node but one has become interior.
            self.cost[self.len - 2] = self.interior_cost(self.len - 2);
        }
    }

    /// What dropping node `i` (neither the first nor the last) costs the image: the change of
    /// `V` at the node, where the lookup would interpolate `τ` between its neighbours instead,
    /// falling to 0 at each neighbour, over the shading points of the two segments
    /// ([`Knots::points`]).
    #[inline]
    fn interior_cost(&self, i: usize) -> f32 {
        let (da, ta) = (self.d[i - 1], self.tau[i - 1]);
        let (db, tb) = (self.d[i + 1], self.tau[i + 1]);
        let t = ta + (tb - ta) * ((self.d[i] - da) / (db - da));
        let points = self.points(i - 1, i) + self.points(i, i + 1);
        points * (self.v[i] - lookup::exp_neg(t.min(80.0))).abs()
    }

    /// The shading points between nodes `a` and `b`, weighted by `B_ℓ` (its mean at the two):
    /// the scattering a point adds is `∝ ρ`, and `τ` rises by `σ_t ∫ρ` between them; a stretch
    /// of clear space as long as the reach weighs as much as a unit of optical depth (the
    /// ground, and smoke too thin to mark, are lit through it too). Costs are counted twice
    /// over: a segment across which the error falls linearly to 0 costs its points times the
    /// error at the node (twice the mean error), a stretch at the full error twice that.
    #[inline]
    fn points(&self, a: usize, b: usize) -> f32 {
        let along = (self.tau[b] - self.tau[a]) + (self.d[b] - self.d[a]) / self.reach;
        0.5 * (self.b[a] + self.b[b]) * along
    }

    /// Drops the node whose removal costs least (Salvi's node removal, with the cost of
    /// [`Knots::interior_cost`]): interior nodes only while the march goes on; once it is
    /// `done`, the last node too, whose value is held to the reach.
    fn remove(&mut self, done: bool) {
        let last = self.len - 1;
        let mut best = (f32::INFINITY, 0);
        for (i, &c) in self.cost.iter().enumerate().take(last).skip(1) {
            if c < best.0 {
                best = (c, i);
            }
        }
        if done {
            // Without the last node, the one before is held from there: `V` changes by the
            // drop between them, over the last segment (half of it, as a triangle) and all
            // the way to the reach.
            let beyond = (self.reach - self.d[last]) / self.reach;
            let b = 0.5 * (self.b[last] + self.support.weight(self.reach));
            let points = self.points(last - 1, last) + 2.0 * b * beyond;
            let c = points * (self.v[last - 1] - self.v[last]);
            if c < best.0 {
                best = (c, last);
            }
        }
        let i = best.1.max(1); // (every cost finite: nodes are at increasing distances)
        self.d.copy_within(i + 1..self.len, i);
        self.tau.copy_within(i + 1..self.len, i);
        self.v.copy_within(i + 1..self.len, i);
        self.b.copy_within(i + 1..self.len, i);
        self.cost.copy_within(i + 1..self.len, i);
        self.len -= 1;
        // The neighbours' costs changed with their neighbours.
        for j in [i - 1, i] {
            if j >= 1 && j + 1 < self.len {
                self.cost[j] = self.interior_cost(j);
            }
        }
    }

    /// The `keep` knots, quantised for distances up to `reach`, into `out` (one `u16` each, see
    /// the module docs), the march having ended with optical depth `tau`; unused knots repeat
    /// the last.
    pub(super) fn store(mut self, tau: f32, out: &mut [u16]) {
        if self.len == 1 && tau > 0.0 {
            // All the smoke was nearer than `inner`: flat from there.
            self.push(self.support.inner, tau);
        }
        while self.len > self.keep + 1 {
            self.remove(true);
        }
        let scale = STEPS / self.reach;
        let mut last = pack(STEPS as u16, 1.0);
        let mut q = 0u16;
        for (k, o) in out.iter_mut().enumerate().take(self.keep) {
            if k + 1 < self.len {
                // Rounded, and at least a step past the knot before, so that no two knots share
                // a distance (a jump of V) but at the reach itself.
                let at = (self.d[k + 1] * scale).clamp(0.0, STEPS) + 0.5;
                q = (at as u16).max(q + 1).min(STEPS as u16);
                last = pack(q, self.v[k + 1]);
            }
            *o = last;
        }
    }
}

/// The transmittance at `x` of the light centred at `c` whose map of adaptive knots (module
/// `knots`, `n` a texel) is `slot` in `texels`, with `scale` = 255 / its reach: each of the four
/// texels' `τ` around the direction evaluated at the distance, blended bilinearly, `e^{−τ}` of
/// that; `None` as `lookup::quantised_depth`.
#[inline]
#[must_use]
pub(super) fn transmittance(
    texels: &[u16],
    n: usize,
    slot: Slot,
    scale: f32,
    x: Vec3,
    c: Vec3,
) -> Option<f32> {
    let (at, d) = lookup::locate(slot, x, c)?;
    let q = d * scale;
    let tau = cube::bilinear(&at, slot.cells, |t| depth(&texels[t * n..(t + 1) * n], q));
    Some(lookup::exp_neg(tau))
}

/// Where a level's lookups weigh: its blending weight `B_ℓ(d)` of eq. 3, which rises from 0 at
/// `inner = r_{ℓ−1}` to 1 at `peak = r_ℓ` and falls to 0 at `outer = 2 r_ℓ` (level 0: 1 from
/// the light; the top level: 1 beyond `peak`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Support {
    pub inner: f32,
    pub peak: f32,
    pub outer: f32,
}

impl Support {
    /// Every distance weighs the same (for tests).
    #[cfg(test)]
    pub(super) const FLAT: Support = Support {
        inner: 0.0,
        peak: f32::INFINITY,
        outer: f32::INFINITY,
    };

    /// `B_ℓ(d)`.
    #[inline]
    fn weight(&self, d: f32) -> f32 {
        let w = if d <= self.peak {
            if self.inner > 0.0 {
                (d - self.inner) / (self.peak - self.inner)
            } else {
                1.0
            }
        } else if self.outer.is_finite() {
            (self.outer - d) / (self.outer - self.peak)
        } else {
            1.0
        };
        w.clamp(0.0, 1.0)
    }
}

/// A knot at `q` 255ths of the reach with transmittance `v`, rounded.
#[inline]
fn pack(q: u16, v: f32) -> u16 {
    let v = (v.clamp(0.0, 1.0) * STEPS + 0.5) as u16;
    (q << 8) | v
}

/// The optical depth at `q` 255ths of the reach, from a texel's `knots` (see the module docs).
#[inline(always)]
#[must_use]
pub(super) fn depth(knots: &[u16], q: f32) -> f32 {
    let (mut q0, mut t0) = (0.0f32, 0.0f32);
    for &k in knots {
        let (q1, t1) = (f32::from(k >> 8), TAU[usize::from(k & 0xff)]);
        if q < q1 {
            return t0 + (t1 - t0) * ((q - q0) / (q1 - q0));
        }
        (q0, t0) = (q1, t1);
    }
    t0
}

/// The optical depth of each stored value: `τ = −ln(v/255)`, and for 0 (`V` below half a step,
/// `1/510`) the middle of that bin, `ln 1020 ≈ 6.93`: a knot past an opaque rise is read as
/// `V = 1/1020`, off by at most that, and the `τ` interpolated towards it is not pulled to the
/// much larger `TAU_MAX` (which would darken the whole segment before it). A `static`, so that
/// the AVX2 lookups gather from one table.
pub(super) static TAU: [f32; 256] = {
    let mut t = [0.0; 256];
    t[0] = -ln(0.25 / 255.0) as f32;
    let mut v = 1;
    while v < 256 {
        t[v] = -ln(v as f64 / 255.0) as f32;
        v += 1;
    }
    t
};

/// The natural logarithm of `x > 0` to f64 precision, in a `const`: `x = m 2^e` with
/// `m ∈ [1, 2)`, `ln m = 2 atanh z` with `z = (m − 1)/(m + 1) ≤ 1/3`, whose series
/// `Σ z^{2k+1}/(2k+1)` has converged after 30 terms (`3^{−61}`).
const fn ln(mut x: f64) -> f64 {
    let mut e = 0.0;
    while x >= 2.0 {
        x /= 2.0;
        e += 1.0;
    }
    while x < 1.0 {
        x *= 2.0;
        e -= 1.0;
    }
    let z = (x - 1.0) / (x + 1.0);
    let (mut sum, mut power, mut k) = (0.0, z, 0);
    while k < 30 {
        sum += power / (2 * k + 1) as f64;
        power *= z * z;
        k += 1;
    }
    e * core::f64::consts::LN_2 + 2.0 * sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::deep::TAU_MAX;

    /// The stored knots of `tau(d)` marched in `steps` steps to `reach` (steps through which `τ`
    /// does not rise add nothing, as in the march), for lookups over `support`.
    fn fitted(
        keep: usize,
        support: Support,
        (reach, steps): (f32, usize),
        tau: impl Fn(f32) -> f32,
    ) -> Vec<u16> {
        let mut k = Knots::new(keep, support, reach);
        let dt = reach / steps as f32;
        for i in 0..steps {
            let (a, b) = (i as f32 * dt, (i + 1) as f32 * dt);
            if tau(b) > tau(a) {
                k.step(a, tau(a), b, tau(b));
            }
        }
        let mut out = vec![0; keep];
        k.store(tau(reach), &mut out);
        out
    }

    /// `τ` looked up at distance `d` of `reach`.
    fn at(knots: &[u16], d: f32, reach: f32) -> f32 {
        depth(knots, d * STEPS / reach)
    }

    #[test]
    fn stored_values_decode_to_their_optical_depth() {
        assert_eq!(TAU[255], 0.0);
        assert!((TAU[0] - 1020f32.ln()).abs() < 1e-6);
        for v in 1..255 {
            let want = -(f64::from(v) / 255.0).ln();
            assert!(
                (f64::from(TAU[v as usize]) - want).abs() < 1e-6 * want.max(1.0),
                "{v}"
            );
        }
    }

    #[test]
    fn a_clear_ray_is_unshadowed_everywhere() {
        let knots = fitted(4, Support::FLAT, (10.0, 100), |_| 0.0);
        for d in [0.0, 5.0, 9.99, 10.0, 12.0] {
            assert_eq!(at(&knots, d, 10.0), 0.0);
        }
    }

    #[test]
    fn a_shell_in_clear_space_is_exact_to_the_quantisation_of_its_knots() {
        // τ: 0 up to d = 3, rising linearly by 2 to d = 4, flat after. Piecewise linear in τ,
        // which the lookup interpolates: three knots hold it, and dropping any other node
        // costs nothing. What remains is quantisation: a knot's distance moves by at most half
        // a 255th of the reach (0.0196), which moves τ by the slope 2 times that; its value by
        // half a 255th of V, at most 0.5 / (255 e^{−2}) = 0.0145 in τ.
        let tau = |d: f32| (2.0 * (d - 3.0)).clamp(0.0, 2.0);
        let knots = fitted(4, Support::FLAT, (10.0, 200), tau);
        let bound = 2.0 * 0.5 * 10.0 / STEPS + 0.5 / (STEPS * (-2.0f32).exp()) + 1e-5;
        for i in 0..=1200 {
            let d = i as f32 * 0.01;
            let got = at(&knots, d, 10.0);
            assert!(
                (got - tau(d)).abs() <= bound,
                "d = {d}: {got} vs {}",
                tau(d)
            );
        }
        // Clear before the shell, exactly.
        assert_eq!(at(&knots, 2.95, 10.0), 0.0);
    }

    #[test]
    fn the_smaller_rise_goes_first() {
        // Two rises: a small one (τ by 0.01) early, a large one (to τ = 2) later. One knot
        // keeps the end of the large one.
        let mut k = Knots::new(1, Support::FLAT, 10.0);
        k.step(1.0, 0.0, 1.1, 0.01);
        k.step(5.0, 0.01, 5.5, 2.0);
        let mut out = [0u16; 1];
        k.store(2.0, &mut out);
        assert_eq!(out[0] >> 8, (5.5 * STEPS / 10.0 + 0.5) as u16);
        assert_eq!(out[0] & 0xff, ((-2.0f32).exp() * STEPS + 0.5) as u16);
    }

    #[test]
    fn no_knot_is_spent_where_the_level_is_not_looked_up() {
        // A rise at d ∈ [1, 2], before the level's support begins at 4, and one at [6, 7]:
        // from 4 on, τ is piecewise linear through (4, 1), (6, 1) and (7, 2.5), and three
        // knots hold it, exact to quantisation (from the light, four would be needed).
        let tau = |d: f32| (d - 1.0).clamp(0.0, 1.0) + 1.5 * (d - 6.0).clamp(0.0, 1.0);
        let support = Support {
            inner: 4.0,
            peak: 8.0,
            outer: 16.0,
        };
        let knots = fitted(3, support, (16.0, 160), tau);
        let bound = 1.5 * 0.5 * 16.0 / STEPS + 0.5 / (STEPS * (-2.5f32).exp()) + 1e-5;
        for i in 400..=1600 {
            let d = i as f32 * 0.01;
            let got = at(&knots, d, 16.0);
            assert!(
                (got - tau(d)).abs() <= bound,
                "d = {d}: {got} vs {}",
                tau(d)
            );
        }
    }

    #[test]
    fn lookups_are_continuous_and_monotone() {
        // A smooth rise and a kink; six knots. Knots are at least one 255th apart, so the
        // lookup's slope is at most the largest step of τ between knots (≤ TAU_MAX) per 255th.
        let knots = fitted(6, Support::FLAT, (8.0, 64), |d| {
            0.3 * d + (d - 4.0).max(0.0)
        });
        let mut prev = 0.0;
        for i in 0..=30000 {
            let q = i as f32 * 0.01;
            let t = depth(&knots, q);
            assert!(
                t >= prev - 1e-5 && t - prev <= 0.01 * TAU_MAX,
                "q = {q}: {prev} → {t}"
            );
            prev = t;
        }
    }
}
