//! The near field of a voxel light: what a light that stands for a whole emitting voxel gives
//! at a point close to it.
//!
//! The paper models every input light as a point with the fall-off clamped at `h0`
//! (Sec. 6: `g(d) = 1/max(d, h0)²`, [`falloff`]). For an explosion, a level-0 light is the
//! emission of one voxel of side `h`, spread over that voxel, and a point in the smoke sums the
//! light arriving from every direction (its *fluence*, which isotropic scattering turns into
//! radiance). The fluence of a uniform voxel of total intensity `I` at `x` is `I · G(x)` with
//!
//! `G(x) = (1/h³) ∫_voxel 1/‖x − y‖² dy`,
//!
//! the voxel's mean of the inverse square. At the voxel's centre `G = 7.674/h²`, not the clamp's
//! `1/h²`: a point inside a glowing voxel is lit from all around, at distances below `h`.
//! A scattering pass evaluates every voxel's fluence at its own centre, so the clamp loses most
//! of each voxel's light on itself, at every scattering depth.
//!
//! [`voxel_falloff`] is `G` averaged over the directions from the voxel's centre, a function of
//! the distance `d` alone (continuous, decreasing): the voxel's orientation is the grid's, which
//! a light does not carry, and the average over directions is what a march through the voxel
//! sees. It is exact in the mean: for a point at distance `d` in a random direction, its
//! expected fluence. Beyond the voxel (`d > √3 h/2`) it is
//!
//! `G(d) = (1/d²) Σ_k E[r^2k] / ((2k + 1) d^2k)`, with `E[r²] = h²/4`,
//!
//! the inverse square plus a near-field term that falls as `1/d⁴`: within 2.2% of `1/d²` beyond
//! `2h`, 0.53% beyond `4h`, 0.1% beyond `9.2h`. It never equals `1/d²` exactly: the mean of
//! `1/r²` over a spread source exceeds `1/d²` at any distance (Jensen's inequality; Newton's
//! shell theorem holds for the flux of an inverse-square field, which a surface's irradiance
//! is, not for its mean, which the fluence is).
//!
//! # Which lights, which points
//!
//! [`NearField::Voxel`] gives the level-0 lights this fall-off where the shading point is in a
//! medium. Coarse lights (ℓ ≥ 1) keep the point's `1/max(d, h0)²`: a level-ℓ light is used only
//! beyond `r_{ℓ−1}` (eq. 3), and giving it the near field of its own extent (its variance
//! `σ²_ℓi`, eq. 4, plus the voxels' `h²/4`) moved the hierarchy *away* from the brute-force sum
//! over the same voxel lights, measured: at α = 2 the fluence of a 48³ ball of hot voxels
//! differs from the brute-force sum by +0.34% in the mean and 2.35% RMS with point-like coarse
//! lights, by +2.0% and 5.4% with a ball of matching variance (α = 1: +0.52% and 6.7% against
//! +5.8% and 33%). The splatting of eq. (1) and the blending of eq. (3) already give the coarse
//! levels a small surplus that offsets their missing spread. Surfaces keep the point fall-off
//! too: a surface's irradiance from a source outside it is nearly the point's (exactly so for a
//! spherical source, by the shell theorem), and the renderers' surfaces lie outside the smoke.
//!
//! # The table
//!
//! `h² G(d)` is tabulated at `d = 0, h/64, …, 2h` (129 values, read with linear interpolation:
//! at most 0.073% between entries, near `d = h/2` where the sphere of radius `d` first leaves
//! the voxel) and summed from the series above beyond `2h` (five terms: 5·10⁻⁸ relative at `2h`,
//! where the table's last entry is the series' value so that `G` is continuous). Each entry is
//! the integral over directions of the radial integral in closed form: with `u = d/h` and the
//! voxel the unit cube,
//! `G = ∫_{S²} F(ℓ(ω)) dω`, `F(R) = ∫_0^R ρ² K(u, ρ) dρ`, where `K(u, ρ) =
//! ln|(u + ρ)/(u − ρ)| / (2uρ)` is the mean of `1/‖x − y‖²` over a sphere of radius `ρ` and
//! `ℓ(ω)` the distance from the centre to the cube's face along `ω`; the test below recomputes
//! every entry from that formula in `f64`, and checks it against a Monte-Carlo estimate of the
//! definition.

use crate::blend::falloff;

/// How the fall-off `g(d)` behaves near a light (see the [module](self) documentation).
///
/// ```
/// use lgh_core::{falloff, NearField};
///
/// let h = 0.5;
/// // The paper's clamp: every light a point, g = 1/max(d, h0)².
/// assert_eq!(NearField::Clamp.falloff(0, 0.1, h), falloff(0.1, h));
/// // A voxel light at its own centre: the voxel's mean of 1/r², 7.674/h², not 1/h².
/// let centre = NearField::Voxel.falloff(0, 0.0, h) * h * h;
/// assert!((centre - 7.674).abs() < 1e-3);
/// // Coarse lights keep the point fall-off.
/// assert_eq!(NearField::Voxel.falloff(2, 3.0, h), falloff(3.0, h));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NearField {
    /// A level-0 light is a uniform emitting voxel of side `h0`: [`voxel_falloff`].
    #[default]
    Voxel,
    /// The paper's model (Sec. 6): every light a point, the fall-off clamped at `h0`.
    Clamp,
}

impl NearField {
    /// Both models, the default first.
    pub const ALL: [NearField; 2] = [NearField::Voxel, NearField::Clamp];

    /// The fall-off of a level-`level` light at distance `d` from a point in a medium, with the
    /// level-0 voxels of side `h0`: [`voxel_falloff`] for a voxel light, [`falloff`] otherwise.
    #[inline(always)]
    #[must_use]
    pub fn falloff(self, level: u8, d: f32, h0: f32) -> f32 {
        match self {
            NearField::Voxel if level == 0 => voxel_falloff(d, h0),
            _ => falloff(d, h0),
        }
    }

    /// The model's name on the command line and in file headers: `voxel` or `clamp`.
    ///
    /// ```
    /// use lgh_core::NearField;
    ///
    /// for model in NearField::ALL {
    ///     assert_eq!(NearField::from_name(model.name()), Some(model));
    /// }
    /// assert_eq!(NearField::from_name("point"), None);
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            NearField::Voxel => "voxel",
            NearField::Clamp => "clamp",
        }
    }

    /// The model named `name` ([`name`](Self::name)), `None` for any other string.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        NearField::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// Entries per voxel size of [`VOXEL_MEAN`].
const PER_VOXEL: f32 = 64.0;

/// `h² G(d)` at `d = i h / 64`, `i = 0..=128`: the mean of `1/‖x − y‖²` over a voxel of side
/// `h`, averaged over the directions of `x` from the voxel's centre (module documentation).
/// The last entry is the series' value at `2h`, so that [`voxel_falloff`] is continuous there.
#[rustfmt::skip]
const VOXEL_MEAN: [f32; 129] = [
    7.6741242, 7.672424, 7.6673203, 7.6588044,
    7.646862, 7.6314726, 7.612609, 7.5902386,
    7.564321, 7.534809, 7.501648, 7.4647737,
    7.424114, 7.379587, 7.331098, 7.278541,
    7.2217956, 7.1607256, 7.0951753, 7.024969,
    6.9499044, 6.869749, 6.784234, 6.6930456,
    6.5958133, 6.492093, 6.381346, 6.2629027,
    6.135904, 5.9992046, 5.851175, 5.6892166,
    5.5077024, 5.2963414, 5.070098, 4.8371925,
    4.601963, 4.367311, 4.1353574, 3.9077399,
    3.6857834, 3.4706104, 3.263225, 3.064594,
    2.8757477, 2.697997, 2.5338097, 2.38421,
    2.247875, 2.1235628, 2.0101469, 1.906598,
    1.8119713, 1.7253932, 1.6460469, 1.5731534,
    1.5059236, 1.4435587, 1.385465, 1.331183,
    1.2803322, 1.2325898, 1.1876771, 1.1453512,
    1.1053979, 1.0676279, 1.0318724, 0.99798006,
    0.96581495, 0.9352543, 0.9061869, 0.87851167,
    0.8521365, 0.82697725, 0.8029569, 0.78000474,
    0.7580558, 0.73705006, 0.7169323, 0.6976514,
    0.67915994, 0.6614141, 0.64437294, 0.62799865,
    0.6122559, 0.5971116, 0.5825351, 0.5684976,
    0.55497223, 0.5419338, 0.52935857, 0.51722455,
    0.50551075, 0.49419767, 0.48326683, 0.4727009,
    0.4624835, 0.4525992, 0.4430334, 0.43377233,
    0.424803, 0.41611302, 0.4076908, 0.39952525,
    0.39160588, 0.38392276, 0.37646645, 0.369228,
    0.3621989, 0.355371, 0.34873664, 0.34228846,
    0.3360195, 0.32992306, 0.32399282, 0.31822273,
    0.312607, 0.3071401, 0.3018168, 0.29663202,
    0.29158098, 0.28665903, 0.2818618, 0.27718508,
    0.27262482, 0.26817715, 0.26383832, 0.25960484,
    0.25547326,
];

/// `E[r^2k] / (2k + 1)` for `k = 1..=5`, `r` the distance from a unit cube's centre to a uniform
/// point in it: the coefficients of the series `u² h² G = 1 + Σ_k c_k / u^2k` beyond the voxel
/// (exact fractions: `E[x^2k] = 1 / (4^k (2k + 1))` per axis, combined by the multinomial
/// theorem).
const SERIES: [f32; 5] = [
    1.0 / 12.0,
    0.015_833_333,
    0.004_131_236,
    0.001_300_43,
    0.000_466_131_5,
];

/// The fall-off of a level-0 light that is a uniform emitting voxel of side `h`, at distance
/// `d` from its centre: the voxel's mean of `1/‖x − y‖²` over the directions of `x`
/// (module documentation). `7.674/h²` at `d = 0`, continuous and decreasing, `(1/d²)(1 +
/// h²/(12 d²) + …)` beyond the voxel.
///
/// ```
/// use lgh_core::near_field::voxel_falloff;
///
/// let h = 0.25;
/// assert!((voxel_falloff(0.0, h) * h * h - 7.674).abs() < 1e-3);
/// // Far away, the inverse square plus h²/(12 d²) of it.
/// let d = 10.0 * h;
/// let near_field = voxel_falloff(d, h) * d * d - 1.0;
/// assert!((near_field - 1.0 / 1200.0).abs() < 1e-5);
/// ```
#[inline]
#[must_use]
pub fn voxel_falloff(d: f32, h: f32) -> f32 {
    let u = d / h;
    let h2 = h * h;
    if u < 2.0 {
        // u ≥ 0, so truncation is the floor; u < 2 keeps i + 1 ≤ 128 (a NaN goes to the series).
        let f = u * PER_VOXEL;
        let i = (f as usize).min(VOXEL_MEAN.len() - 2);
        let w = f - i as f32;
        let (a, b) = (VOXEL_MEAN[i], VOXEL_MEAN[i + 1]);
        (a + (b - a) * w) / h2
    } else {
        let x = 1.0 / (u * u);
        let s = SERIES;
        let c = 1.0 + x * (s[0] + x * (s[1] + x * (s[2] + x * (s[3] + x * s[4]))));
        x * c / h2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;
    use glam::DVec3;

    /// `P(s)`, an antiderivative of `F(s)/s²` with `F(R) = ∫_0^R ρ² K(u, ρ) dρ` (module
    /// documentation): `((s + u)² ln(s + u) − (s − u)² ln|s − u|) / (4us)`, and `ln s` at `u = 0`.
    fn antiderivative(s: f64, u: f64) -> f64 {
        if u == 0.0 {
            return s.ln();
        }
        let below = if s == u {
            0.0
        } else {
            (s - u).powi(2) * (s - u).abs().ln()
        };
        ((s + u).powi(2) * (s + u).ln() - below) / (4.0 * u * s)
    }

    /// `h² G(u h)` in `f64`: by the cube's 48 symmetries, 48 times the part of one face's
    /// eighth (`0 ≤ b ≤ a ≤ 1/2` on the face `x = 1/2`). In polar coordinates on the face, at
    /// angle φ the face's points lie at distances `s ∈ [1/2, s_max(φ)]` from the centre, and the
    /// solid angle times `F` integrates in closed form over `s`: `(1/2)[P(s_max) − P(1/2)]`.
    /// The remaining integral over `φ ∈ [0, π/4]` is smooth but where `s_max(φ) = u`; composite
    /// Simpson on each side of that point.
    fn quadrature(u: f64) -> f64 {
        let s_max = |phi: f64| 0.5 * (1.0 + 1.0 / phi.cos().powi(2)).sqrt();
        let f = |phi: f64| antiderivative(s_max(phi), u) - antiderivative(0.5, u);
        let quarter = core::f64::consts::FRAC_PI_4;
        let mut cuts = [0.0, quarter, quarter];
        if 4.0 * u * u > 2.0 && 4.0 * u * u < 3.0 {
            cuts[1] = (1.0 / (4.0 * u * u - 1.0).sqrt()).acos();
        }
        let simpson = |a: f64, b: f64| {
            let n = 400;
            let step = (b - a) / f64::from(n);
            let mut sum = f(a) + f(b);
            for i in 1..n {
                sum += f(a + step * f64::from(i)) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            sum * step / 3.0
        };
        24.0 * (simpson(cuts[0], cuts[1]) + simpson(cuts[1], cuts[2]))
    }

    #[test]
    fn the_table_is_the_quadrature_of_its_formula() {
        for (i, &entry) in VOXEL_MEAN.iter().enumerate() {
            let u = i as f64 / f64::from(PER_VOXEL);
            let want = quadrature(u);
            let rel = (f64::from(entry) / want - 1.0).abs();
            // f32 storage (6·10⁻⁸), and the last entry is the series' (5·10⁻⁸ off, below).
            assert!(
                rel < 2e-7,
                "entry {i} (u = {u}): {entry} against {want} ({rel:e})"
            );
        }
    }

    #[test]
    fn the_series_continues_the_table() {
        for u in [2.0, 2.5, 3.0, 4.0, 8.0] {
            let x = 1.0 / (u * u);
            let s = SERIES.map(f64::from);
            let series = x * (1.0 + x * (s[0] + x * (s[1] + x * (s[2] + x * (s[3] + x * s[4])))));
            let want = quadrature(u);
            // The first term left out, E[r¹²]/13 / u¹², is below 2·10⁻⁸ beyond u = 2.
            assert!(
                (series / want - 1.0).abs() < 1e-7,
                "u = {u}: {series} vs {want}"
            );
        }
        // Continuous at the switch, to f32 rounding.
        let h = 0.37;
        let below = voxel_falloff(2.0 * h * (1.0 - 1e-7), h);
        let at = voxel_falloff(2.0 * h, h);
        assert!((below / at - 1.0).abs() < 1e-6, "{below} vs {at}");
    }

    #[test]
    fn linear_interpolation_stays_within_its_stated_bound() {
        // Midway between entries, where linear interpolation errs most: ≤ 0.073% (module docs).
        let mut worst = 0.0f64;
        for i in 0..128 {
            let u = (f64::from(i) + 0.5) / f64::from(PER_VOXEL);
            let got = f64::from(voxel_falloff(u as f32, 1.0));
            worst = worst.max((got / quadrature(u) - 1.0).abs());
        }
        assert!(worst < 7.3e-4, "{worst}");
        assert!(worst > 1e-4, "the bound is no longer tight: {worst}");
    }

    /// Length of the ray `x + t ω`, `t ≥ 0`, inside the unit cube centred at the origin.
    fn chord(x: DVec3, w: DVec3) -> f64 {
        let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
        for a in 0..3 {
            let (o, d) = (x[a], w[a]);
            if d == 0.0 {
                if o.abs() > 0.5 {
                    return 0.0;
                }
                continue;
            }
            let (ta, tb) = ((-0.5 - o) / d, (0.5 - o) / d);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        (t1 - t0).max(0.0)
    }

    fn unit(rng: &mut SplitMix64) -> DVec3 {
        let z = 2.0 * f64::from(rng.next_f32()) - 1.0;
        let phi = core::f64::consts::TAU * f64::from(rng.next_f32());
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// A direction uniform in the cone of half-angle `acos(cos_max)` around `axis` (a unit
    /// vector), and the cone's solid angle, the sample's weight.
    fn in_cone(rng: &mut SplitMix64, axis: DVec3, cos_max: f64) -> (DVec3, f64) {
        let z = 1.0 - f64::from(rng.next_f32()) * (1.0 - cos_max);
        let phi = core::f64::consts::TAU * f64::from(rng.next_f32());
        let r = (1.0 - z * z).max(0.0).sqrt();
        let (a, b) = axis.any_orthonormal_pair();
        let w = a * (r * phi.cos()) + b * (r * phi.sin()) + axis * z;
        (w, core::f64::consts::TAU * (1.0 - cos_max))
    }

    #[test]
    fn the_definition_by_monte_carlo() {
        // Independent of the closed form: in polar coordinates around x, the voxel's mean of
        // 1/‖x − y‖² is ∫ (chord of the ray from x along ω' through the voxel) dω'. One sample:
        // x = d ω with ω uniform on the sphere, ω' uniform over the directions that can meet the
        // voxel (all of them inside its circumscribed sphere, else the cone around it), weighted
        // by their solid angle. The chord is at most √3, so the estimate's variance is finite and
        // measured; the bound is 5 of its standard errors (a false alarm about once in 1.7
        // million runs per distance) plus 0.1% for the table's interpolation (≤ 0.073%).
        let mut rng = SplitMix64(0x5eed);
        let n = 160_000;
        let reach = 0.75f64.sqrt();
        for u in [0.0, 0.2, 0.45, 0.5, 0.6, 0.8, 1.0, 1.5, 2.5, 6.0] {
            let (mut sum, mut sum2) = (0.0, 0.0);
            for _ in 0..n {
                let x = unit(&mut rng) * u;
                let v = if u <= reach {
                    4.0 * core::f64::consts::PI * chord(x, unit(&mut rng))
                } else {
                    let cos_max = (1.0 - (reach / u).powi(2)).sqrt();
                    let (w, solid_angle) = in_cone(&mut rng, -x / u, cos_max);
                    solid_angle * chord(x, w)
                };
                sum += v;
                sum2 += v * v;
            }
            let mean = sum / f64::from(n);
            let err = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
            let got = f64::from(voxel_falloff(u as f32, 1.0));
            assert!(
                (got - mean).abs() < 5.0 * err + 1e-3 * got,
                "u = {u}: table {got}, Monte Carlo {mean} ± {err}"
            );
            assert!(
                err < 0.01 * got,
                "u = {u}: too few samples to test ({err} of {got})"
            );
        }
    }

    #[test]
    fn decreasing_and_scaled_by_the_voxel_size() {
        let mut last = f32::INFINITY;
        for i in 0..=1000 {
            let d = i as f32 * 0.01;
            let g = voxel_falloff(d, 1.0);
            assert!(g <= last && g > 0.0, "d = {d}: {g} after {last}");
            last = g;
            // G(d; h) = G(d/h; 1) / h²: one table for every voxel size.
            let h = 0.125;
            let scaled = voxel_falloff(d * h, h) * h * h;
            assert!((scaled / g - 1.0).abs() < 1e-5, "d = {d}: {scaled} vs {g}");
        }
        assert_eq!(voxel_falloff(f32::INFINITY, 1.0), 0.0);
        assert!(voxel_falloff(f32::NAN, 1.0).is_nan());
    }
}
