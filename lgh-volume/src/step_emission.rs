//! The emission a camera ray gathers over one step of its march, `∫_0^Δ j(s) e^{−σ s} ds`, from
//! the emission `j` at the step's two Gauss nodes `s = Δ (1/2 ∓ 1/(2√3))` and the step's
//! extinction `σ` (the density at its midpoint).
//!
//! The march takes the medium as constant over a step, and the emission along it as the line
//! through its values at the two nodes. With `x = σΔ` the step's optical depth, the integral of
//! that line is exact:
//!
//! `∫_0^Δ j(s) e^{−σ s} ds = W₀ j̄ + W₁ j′`, `W₀ = Δ (1 − e^{−x})/x`,
//! `W₁ = ∫_0^Δ (s − Δ/2) e^{−σ s} ds = Δ² f(x)`, `f(x) = ((1 − e^{−x}) − (x/2)(1 + e^{−x}))/x²`,
//!
//! with `j̄` the nodes' mean and `j′ = (j_far − j_near)/(Δ/√3)` the line's slope: node weights
//! `Δ (W₀/(2Δ) ∓ √3 f(x))`, near and far. In clear air (`x = 0`, `f = 0`) they are the two-point Gauss rule's
//! `Δ/2` each, exact for a cubic. In smoke the step's near part is seen through less of it, so
//! the near node weighs more: at `x = 1`, 0.406 Δ and 0.226 Δ where the rule gave 0.316 Δ each.
//! Taking the nodes' mean times `W₀` instead (what the march did) weighs the far half as much as
//! the near one, and where the emission rises into a flame along the ray — a flame seen through
//! its own smoke — counts it too bright: 2–3% of smoky64's image at one-voxel steps of optical
//! depth near 1, against lgh's path tracer (docs/cycles.md, "Real simulation caches").
//!
//! Beyond `x ≈ 4.49` the line's far weight would be negative (the near end, where nearly all the
//! light comes from, lies outside the nodes, and the line extrapolates to it); a negative weight
//! could make a step's emission negative where the emission is not a line, so the far weight is
//! held at 0 there and the near one takes `W₀` whole — still exact for a uniform emission.

/// `√3`: the nodes are `Δ/√3` apart.
const SQRT_3: f32 = 1.732_050_8;

/// `f(x) = ((1 − e^{−x}) − (x/2)(1 + e^{−x}))/x²`, the line's slope's weight over `Δ²` (module
/// documentation): by its series below `x = 1/2` (where the closed form cancels), exactly above.
#[must_use]
fn slope_weight(x: f32) -> f32 {
    if x < 0.5 {
        // −x/12 + x²/24 − x³/80 + x⁴/360 − x⁵/2016 + x⁶/13440: the next term is below 3·10⁻⁶
        // of f at x = 1/2.
        x * (-1.0 / 12.0
            + x * (1.0 / 24.0
                + x * (-1.0 / 80.0 + x * (1.0 / 360.0 + x * (-1.0 / 2016.0 + x / 13440.0)))))
    } else {
        let em = (-x).exp_m1(); // e^{−x} − 1
        (-em - 0.5 * x * (2.0 + em)) / (x * x)
    }
}

/// The weights of the emission at a step's near and far Gauss nodes, as fractions of the step's
/// length `Δ`, for a step of optical depth `x = σΔ` (≥ 0): `∫_0^Δ j e^{−σ s} ds ≈ Δ (w_near
/// j_near + w_far j_far)`, exact where `j` is linear along the step and `σ` constant (module
/// documentation). Both ≥ 0; they sum to `(1 − e^{−x})/x` (1 in clear air).
///
/// ```
/// use lgh_volume::step_emission::node_weights;
///
/// assert_eq!(node_weights(0.0), [0.5, 0.5]); // clear air: the two-point Gauss rule
/// let [near, far] = node_weights(1.0);
/// assert!((near - 0.4058).abs() < 1e-4 && (far - 0.2263).abs() < 1e-4);
/// assert!((near + far - (1.0 - (-1.0f32).exp())).abs() < 1e-6);
/// assert_eq!(node_weights(10.0)[1], 0.0); // held at 0 where the line's would be negative
/// ```
#[must_use]
pub fn node_weights(x: f32) -> [f32; 2] {
    // Not above 0 (a NaN included): clear air.
    if x.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
        return [0.5, 0.5];
    }
    let mean = -(-x).exp_m1() / x; // W₀/Δ
    let far = (0.5 * mean + SQRT_3 * slope_weight(x)).max(0.0);
    [mean - far, far]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `∫_0^Δ j(s) e^{−σ s} ds` by the midpoint rule on 200,000 pieces, in f64.
    fn integral(j: impl Fn(f64) -> f64, sigma: f64, delta: f64) -> f64 {
        let n = 200_000;
        let ds = delta / n as f64;
        (0..n)
            .map(|i| {
                let s = (i as f64 + 0.5) * ds;
                j(s) * (-sigma * s).exp() * ds
            })
            .sum()
    }

    /// The weights applied to `j` at the nodes of a step of length `delta` in extinction
    /// `sigma`.
    fn rule(j: impl Fn(f64) -> f64, sigma: f64, delta: f64) -> f64 {
        let [near, far] = node_weights((sigma * delta) as f32).map(f64::from);
        let g = 0.5 / 3f64.sqrt();
        delta * (near * j(delta * (0.5 - g)) + far * j(delta * (0.5 + g)))
    }

    #[test]
    fn exact_for_a_line_up_to_where_the_far_weight_is_held() {
        // A line rising or falling along the step, in smoke from clear to 4.4 optical depths a
        // step: the rule is the integral (to f32's rounding of the weights).
        for x in [0.0, 1e-3, 0.1, 0.49, 0.5, 0.51, 1.0, 2.0, 3.0, 4.4] {
            for (a, b) in [(1.0, 0.0), (1.0, 2.0), (3.0, -2.5), (0.0, 5.0)] {
                let j = |s: f64| a + b * s;
                let want = integral(j, x, 1.0);
                let got = rule(j, x, 1.0);
                assert!(
                    (got - want).abs() < 2e-6 * (a.abs() + b.abs()),
                    "x = {x}, j = {a} + {b}s: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn the_series_meets_the_closed_form() {
        // Continuous where the series hands over to the closed form, and the closed form in f64
        // agrees on both sides.
        let exact = |x: f64| ((1.0 - (-x).exp()) - 0.5 * x * (1.0 + (-x).exp())) / (x * x);
        for x in [0.05f32, 0.3, 0.4999, 0.5, 0.7, 2.0, 6.0] {
            let got = f64::from(slope_weight(x));
            let want = exact(f64::from(x));
            assert!(
                (got - want).abs() < 1e-5 * want.abs(),
                "x = {x}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn weights_are_never_negative_and_sum_to_the_steps_transmitted_share() {
        for i in 0..=400 {
            let x = i as f32 * 0.05;
            let [near, far] = node_weights(x);
            assert!(near >= 0.0 && far >= 0.0, "x = {x}: {near} {far}");
            let mean = if x > 0.0 { (1.0 - (-x).exp()) / x } else { 1.0 };
            assert!((near + far - mean).abs() < 1e-6, "x = {x}");
            assert!(
                near >= far,
                "x = {x}: the near node is seen through less smoke"
            );
        }
        // A uniform emission is exact at any depth, the held weights included.
        for x in [0.3, 4.0, 9.0, 30.0] {
            let (want, got) = (integral(|_| 2.0, x, 1.0), rule(|_| 2.0, x, 1.0));
            assert!((got - want).abs() < 1e-5 * want, "x = {x}: {got} vs {want}");
        }
        for bad in [f32::NAN, -1.0] {
            assert_eq!(node_weights(bad), [0.5, 0.5]);
        }
    }

    #[test]
    fn a_flame_rising_along_the_step_is_no_longer_too_bright() {
        // A steep emission (∝ T⁴ of a temperature rising linearly into a flame) over a step of
        // optical depth 1: the rule that weighs both nodes alike (the nodes' mean times W₀) is
        // too bright by percents; these weights are within a few tenths of a percent.
        let j = |s: f64| (0.6 + 0.8 * s).powi(4);
        let want = integral(j, 1.0, 1.0);
        let g = 0.5 / 3f64.sqrt();
        let alike = (1.0 - (-1.0f64).exp()) * 0.5 * (j(0.5 - g) + j(0.5 + g));
        let got = rule(j, 1.0, 1.0);
        assert!(alike > 1.05 * want, "{alike} vs {want}");
        assert!((got - want).abs() < 5e-3 * want, "{got} vs {want}");
    }
}
