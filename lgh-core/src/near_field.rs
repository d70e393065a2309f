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
//! In smoke, a voxel light's light also passes through its own voxel's smoke, which a shadow
//! ray to its centre attenuates as if all of it came from the centre: [`NearField::falloff_in`]
//! multiplies the fall-off by the [`escape`] of a uniform voxel's light through uniform smoke of
//! the point's extinction, so that with that shadow ray it is the exact fluence (less at the
//! voxel's own centre, more beyond a third of a voxel).
//!
//! Lightcuts' cluster bounds (`lightcuts`) stay the point lights' `1/d_min²`: a voxel light's
//! fall-off exceeds `1/d²` by at most 1.46× (at `d ≈ 0.59 h`), 10.5% at `h` and 2.2% at `2h`,
//! so near a cluster the bound may be that much too low and the cut refined less than ε asks.
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

mod escape;
pub use escape::escape;

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
        self.falloff_in(level, d, h0, 0.0)
    }

    /// [`falloff`](Self::falloff) at a point in smoke of `tau = σ_t h0` optical depths a voxel:
    /// a voxel light's fall-off is [`voxel_falloff`] times the [`escape`] of its light through
    /// that smoke, so that with the shadow ray to its centre (`e^{−τ d/h0}` in uniform smoke) it
    /// is the exact fluence of a uniform emitting voxel in uniform smoke (1 in clear air:
    /// [`voxel_falloff`]). Coarse lights and [`NearField::Clamp`] keep the point's fall-off.
    ///
    /// ```
    /// use lgh_core::near_field::voxel_falloff;
    /// use lgh_core::{falloff, NearField};
    ///
    /// let h = 0.5;
    /// let clear = NearField::Voxel.falloff_in(0, 0.1, h, 0.0);
    /// assert_eq!(clear, voxel_falloff(0.1, h));
    /// // In dense smoke the voxel's own light reaches its centre only from close by...
    /// let dense = NearField::Voxel.falloff_in(0, 0.0, h, 3.0);
    /// assert!(dense < 0.5 * voxel_falloff(0.0, h) && dense > falloff(0.0, h));
    /// // ...and a voxel away, its near half's light through less smoke than its centre's.
    /// assert!(NearField::Voxel.falloff_in(0, h, h, 1.0) > 1.1 * voxel_falloff(h, h));
    /// assert_eq!(NearField::Clamp.falloff_in(0, 0.1, h, 2.0), falloff(0.1, h));
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn falloff_in(self, level: u8, d: f32, h0: f32, tau: f32) -> f32 {
        match self {
            NearField::Voxel if level == 0 => {
                let near = voxel_falloff(d, h0);
                if h0 == 0.0 {
                    return near;
                }
                // 1 in clear air (τ ≤ 0 or not a number).
                near * escape(d / h0, tau)
            }
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

/// Entries per unit of optical depth of [`CENTRE_FLUENCE`].
const PER_DEPTH: f32 = 4.0;

/// `h² K(τ)` at `τ = i / 4`, `i = 0..=128`: the fluence at a uniform voxel's centre from its own
/// light through its own smoke, `(1/h³) ∫_voxel e^{−σ r} / r² dy` with `τ = σ h`, which in
/// polar coordinates around the centre is `∫_{S²} (1 − e^{−τ ℓ(ω)}) / τ dω`, `ℓ(ω)` the distance
/// to the face in units of `h` (7.674 at τ = 0, [`VOXEL_MEAN`]'s first entry; `4π/τ` beyond
/// τ = 32, to `e^{−16}`).
#[rustfmt::skip]
const CENTRE_FLUENCE: [f32; 129] = [
    7.6741242, 7.1091413, 6.5996943, 6.1395855,
    5.7233663, 5.3462386, 5.0039716, 4.692834,
    4.409528, 4.1511383, 3.9150846, 3.6990802,
    3.5010962, 3.3193312, 3.1521828, 2.9982257,
    2.8561897, 2.724941, 2.6034677, 2.490865,
    2.3863225, 2.2891142, 2.1985888, 2.114161,
    2.0353045, 1.9615457, 1.892457, 1.8276529,
    1.7667849, 1.7095377, 1.6556259, 1.6047902,
    1.5567956, 1.5114282, 1.4684936, 1.4278141,
    1.3892281, 1.3525877, 1.3177578, 1.2846148,
    1.253045, 1.2229444, 1.1942172, 1.1667757,
    1.1405386, 1.1154314, 1.091385, 1.0683358,
    1.0462247, 1.0249975, 1.0046033, 0.9849952,
    0.96612966, 0.9479663, 0.9304672, 0.9135972,
    0.8973237, 0.881616, 0.8664454, 0.85178536,
    0.8376107, 0.823898, 0.81062526, 0.7977719,
    0.78531843, 0.77324665, 0.7615394, 0.75018054,
    0.7391548, 0.72844785, 0.7180461, 0.7079368,
    0.69810784, 0.68854773, 0.6792456, 0.67019117,
    0.66137475, 0.6527871, 0.64441943, 0.63626343,
    0.6283112, 0.62055516, 0.6129882, 0.60560346,
    0.59839445, 0.591355, 0.5844793, 0.5777615,
    0.5711963, 0.5647786, 0.55850357, 0.5523664,
    0.5463626, 0.5404879, 0.5347381, 0.5291094,
    0.52359796, 0.5182001, 0.51291245, 0.50773156,
    0.5026543, 0.4976776, 0.49279845, 0.488014,
    0.4833216, 0.47871858, 0.4742024, 0.4697706,
    0.4654209, 0.461151, 0.45695874, 0.452842,
    0.44879878, 0.4448271, 0.44092512, 0.437091,
    0.433323, 0.42961937, 0.42597854, 0.4223989,
    0.4188789, 0.4154171, 0.41201204, 0.40866235,
    0.4053667, 0.40212375, 0.3989323, 0.39579108,
    0.39269897,
];

/// `h² K(τ)`, the fluence at a uniform voxel's centre from its own light through its own smoke
/// of `tau = σ h` optical depths (`CENTRE_FLUENCE`; `4π/τ` beyond τ = 32). It keeps a scattering
/// pass from scattering more of a voxel's light in that voxel than its albedo: the share is
/// `(σ_s h / 4π) K(τ) h² = albedo · (1/4π) ∫ (1 − e^{−τ ℓ(ω)}) dω < albedo`. (Without it, on
/// the demo's explosion at 32³, where a voxel of soot is 4.7 optical depths across, each depth
/// of scattered light was 1.9 times the one before.)
fn centre_fluence(tau: f32) -> f32 {
    if tau < 32.0 {
        lerp_table(&CENTRE_FLUENCE, tau.max(0.0) * PER_DEPTH)
    } else {
        4.0 * core::f32::consts::PI / tau
    }
}

/// `table` read at the fractional index `f ∈ [0, len − 1]` with linear interpolation (`f ≥ 0`,
/// so truncation is the floor; the index is held below the last entry).
#[inline(always)]
fn lerp_table(table: &[f32; 129], f: f32) -> f32 {
    let i = (f as usize).min(table.len() - 2);
    let w = f - i as f32;
    let (a, b) = (table[i], table[i + 1]);
    a + (b - a) * w
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
/// // A voxel of no size is a point.
/// assert_eq!(voxel_falloff(0.5, 0.0), 4.0);
/// ```
#[inline]
#[must_use]
pub fn voxel_falloff(d: f32, h: f32) -> f32 {
    if h == 0.0 {
        // The limit h → 0 at a fixed d: the series' 1/d² (0/0 below).
        return 1.0 / (d * d);
    }
    let u = d / h;
    let h2 = h * h;
    if u < 2.0 {
        // A NaN goes to the series.
        lerp_table(&VOXEL_MEAN, u * PER_VOXEL) / h2
    } else {
        let x = 1.0 / (u * u);
        let s = SERIES;
        let c = 1.0 + x * (s[0] + x * (s[1] + x * (s[2] + x * (s[3] + x * s[4]))));
        x * c / h2
    }
}

/// Entries per voxel size of [`CELL_MEAN`].
const CELL_PER_VOXEL: f32 = 32.0;

/// `h² G₂(d)` at `d = i h / 32`, `i = 0..=128`: the mean of `1/‖x − y‖²` over `x` in one voxel
/// and `y` in another whose centre is `d` away, averaged over the directions between them
/// ([`cell_falloff`]); computed by `tools/near_field/cell_falloff.py` (the closed-form radial
/// integral over the two cubes' difference, whose density is `Π(1 − |z_i|)`, and the midpoint
/// rule on 800 × 800 directions an octant: 10⁻⁶ of the limit), recomputed in the tests below.
/// The last entry agrees with the series at `4h` to 2·10⁻⁸.
#[rustfmt::skip]
const CELL_MEAN: [f32; 129] = [
    5.6337156, 5.608775, 5.5509543, 5.4698515,
    5.370546, 5.2565556, 5.130564, 4.9947324,
    4.8508573, 4.700472, 4.5449023, 4.385314,
    4.222738, 4.0580964, 3.892217, 3.7258484,
    3.5596693, 3.3942976, 3.230298, 3.0681887,
    2.9084444, 2.751504, 2.597773, 2.447628,
    2.3014207, 2.159482, 2.0221252, 1.8896531,
    1.7623624, 1.6405536, 1.5245448, 1.4146986,
    1.3114938, 1.2157813, 1.1280634, 1.04813,
    0.9755445, 0.9097788, 0.8502701, 0.7964515,
    0.7477697, 0.7036953, 0.6637301, 0.6274108,
    0.5943118, 0.5640471, 0.5362732, 0.510693,
    0.4870549, 0.4651454, 0.4447819, 0.425808,
    0.4080885, 0.3915064, 0.3759593, 0.3613575,
    0.3476217, 0.3346813, 0.3224734, 0.3109414,
    0.3000345, 0.2897069, 0.2799167, 0.2706264,
    0.2618013, 0.2534103, 0.2454245, 0.2378176,
    0.2305656, 0.2236461, 0.2170389, 0.2107249,
    0.2046868, 0.1989085, 0.193375, 0.1880725,
    0.182988, 0.1781096, 0.1734262, 0.1689273,
    0.1646033, 0.1604451, 0.1564443, 0.1525928,
    0.1488833, 0.1453087, 0.1418626, 0.1385389,
    0.1353316, 0.1322354, 0.1292453, 0.1263562,
    0.1235637, 0.1208636, 0.1182516, 0.1157241,
    0.1132774, 0.110908, 0.1086126, 0.1063883,
    0.1042321, 0.1021412, 0.100113, 0.098145,
    0.0962348, 0.0943802, 0.092579, 0.0908292,
    0.0891287, 0.0874759, 0.0858688, 0.0843059,
    0.0827855, 0.081306, 0.0798661, 0.0784642,
    0.0770991, 0.0757695, 0.0744741, 0.0732119,
    0.0719816, 0.0707822, 0.0696126, 0.0684719,
    0.0673591, 0.0662734, 0.0652138, 0.0641795,
    0.0631697,
];

/// The series of [`cell_falloff`] beyond `4h`: `E[r^2k] / (2k + 1)` for `r` the distance
/// between two uniform points of the unit cube and of its copy at the origin (each axis'
/// difference triangular on `[−1, 1]`, `E[z^2k] = 2/((2k + 1)(2k + 2))`), `k = 1..=6`.
const CELL_SERIES: [f32; 6] = [
    0.166_666_67,
    0.073_333_33,
    0.047_845_805,
    0.039_576_72,
    0.038_692_116,
    0.042_986_11,
];

/// The mean of a uniform voxel light's `1/r²` over another voxel's cell (both of side `h`, their
/// centres `d` apart, averaged over the directions between them): the fluence a voxel receives
/// on the whole, where [`voxel_falloff`] is that at its centre. Not used by the renderers: a
/// scattering pass that took it (with the cell's mean density) moved a path-traced
/// ball 3% further from the path tracer (ARCHITECTURE.md); kept, tested, for a lattice-exact
/// kernel of the nearest voxels. `5.634/h²` at `d = 0` (a voxel's own light, in the mean over itself), continuous
/// and decreasing, `(1/d²)(1 + h²/(6 d²) + …)` far away (twice the one voxel's `h²/12`: two
/// spreads).
///
/// ```
/// use lgh_core::near_field::{cell_falloff, voxel_falloff};
///
/// let h = 0.25;
/// assert!((cell_falloff(0.0, h) * h * h - 5.6337).abs() < 1e-3);
/// // One voxel over: the cell reaches closer than its centre.
/// assert!(cell_falloff(h, h) > voxel_falloff(h, h));
/// let d = 10.0 * h;
/// assert!((cell_falloff(d, h) * d * d - 1.0 - 1.0 / 600.0).abs() < 2e-5);
/// assert_eq!(cell_falloff(0.5, 0.0), 4.0);
/// ```
#[inline]
#[must_use]
pub fn cell_falloff(d: f32, h: f32) -> f32 {
    if h == 0.0 {
        return 1.0 / (d * d);
    }
    let u = d / h;
    let h2 = h * h;
    if u < 4.0 {
        // A NaN goes to the series.
        lerp_table(&CELL_MEAN, u * CELL_PER_VOXEL) / h2
    } else {
        let x = 1.0 / (u * u);
        let mut c = 0.0;
        for k in CELL_SERIES.iter().rev() {
            c = x * (k + c);
        }
        x * (1.0 + c) / h2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;
    use glam::DVec3;
    use wasm_bindgen_test::wasm_bindgen_test;

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

    #[wasm_bindgen_test(unsupported = test)]
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

    #[wasm_bindgen_test(unsupported = test)]
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

    #[wasm_bindgen_test(unsupported = test)]
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

    /// The mean of `n` samples whose sum and sum of squares are `sum` and `sum2`, and its
    /// standard error.
    pub(super) fn estimate(sum: f64, sum2: f64, n: u32) -> (f64, f64) {
        let n = f64::from(n);
        let mean = sum / n;
        (mean, ((sum2 / n - mean * mean) / n).sqrt())
    }

    /// Length of the ray `x + t ω`, `t ≥ 0`, inside the unit cube centred at the origin.
    fn chord(x: DVec3, w: DVec3) -> f64 {
        let (t0, t1) = span(x, w);
        t1 - t0
    }

    /// `[t_in, t_out]` of the ray `x + t ω`, `t ≥ 0`, through the unit cube centred at the
    /// origin (`t_in = t_out = 0` if it misses).
    pub(super) fn span(x: DVec3, w: DVec3) -> (f64, f64) {
        let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
        for a in 0..3 {
            let (o, d) = (x[a], w[a]);
            if d == 0.0 {
                if o.abs() > 0.5 {
                    return (0.0, 0.0);
                }
                continue;
            }
            let (ta, tb) = ((-0.5 - o) / d, (0.5 - o) / d);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        if t1 > t0 {
            (t0, t1)
        } else {
            (0.0, 0.0)
        }
    }

    pub(super) fn unit(rng: &mut SplitMix64) -> DVec3 {
        let z = 2.0 * f64::from(rng.next_f32()) - 1.0;
        let phi = core::f64::consts::TAU * f64::from(rng.next_f32());
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// A direction uniform in the cone of half-angle `acos(cos_max)` around `axis` (a unit
    /// vector), and the cone's solid angle, the sample's weight.
    pub(super) fn in_cone(rng: &mut SplitMix64, axis: DVec3, cos_max: f64) -> (DVec3, f64) {
        let z = 1.0 - f64::from(rng.next_f32()) * (1.0 - cos_max);
        let phi = core::f64::consts::TAU * f64::from(rng.next_f32());
        let r = (1.0 - z * z).max(0.0).sqrt();
        let (a, b) = axis.any_orthonormal_pair();
        let w = a * (r * phi.cos()) + b * (r * phi.sin()) + axis * z;
        (w, core::f64::consts::TAU * (1.0 - cos_max))
    }

    #[wasm_bindgen_test(unsupported = test)]
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
            let (mean, err) = estimate(sum, sum2, n);
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

    #[wasm_bindgen_test(unsupported = test)]
    fn the_cell_mean_by_monte_carlo() {
        // As above, with x uniform over the receiving voxel around p = u ω (ω uniform on the
        // sphere): the light voxel's mean of 1/‖x − y‖² is the chord integral over directions
        // from x. Independent of the closed form and the quadrature of the table. Bound: 5
        // standard errors plus 0.1% (the table's interpolation, 32 entries a voxel, and the
        // table's own 10⁻⁶).
        let mut rng = SplitMix64(0xce11);
        let n = 200_000;
        let reach = 0.75f64.sqrt();
        for u in [0.0, 0.3, 0.6, 1.0, 1.4, 2.0, 3.0, 3.9, 5.0] {
            let (mut sum, mut sum2) = (0.0, 0.0);
            for _ in 0..n {
                let mut next = || f64::from(rng.next_f32());
                let jitter = DVec3::new(next(), next(), next());
                let x = unit(&mut rng) * u + jitter - DVec3::splat(0.5);
                let r = x.length();
                let v = if r <= reach {
                    4.0 * core::f64::consts::PI * chord(x, unit(&mut rng))
                } else {
                    let cos_max = (1.0 - (reach / r).powi(2)).sqrt();
                    let (w, solid_angle) = in_cone(&mut rng, -x / r, cos_max);
                    solid_angle * chord(x, w)
                };
                sum += v;
                sum2 += v * v;
            }
            let (mean, err) = estimate(sum, sum2, n);
            let got = f64::from(cell_falloff(u as f32, 1.0));
            assert!(
                (got - mean).abs() < 5.0 * err + 1e-3 * got,
                "u = {u}: table {got}, Monte Carlo {mean} ± {err}"
            );
            assert!(
                err < 0.01 * got,
                "u = {u}: too few samples ({err} of {got})"
            );
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn the_cell_table_starts_at_its_quadrature_and_ends_at_its_series() {
        // d = 0: 8 ∫_octant ∫_0^R Π(1 − r ω_i) dr dω, R = 1/max ω_i (the radial integral of the
        // difference density times r² / r²), midpoint rule on 600² directions (10⁻⁶).
        let n = 600;
        let step = core::f64::consts::FRAC_PI_2 / f64::from(n);
        let mut total = 0.0;
        for i in 0..n {
            let theta = (f64::from(i) + 0.5) * step;
            for j in 0..n {
                let phi = (f64::from(j) + 0.5) * step;
                let w = DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let big_r = 1.0 / w.max_element();
                let (s1, s2, s3) = (
                    w.x + w.y + w.z,
                    w.x * w.y + w.y * w.z + w.z * w.x,
                    w.x * w.y * w.z,
                );
                let f = big_r - s1 * big_r.powi(2) / 2.0 + s2 * big_r.powi(3) / 3.0
                    - s3 * big_r.powi(4) / 4.0;
                total += 8.0 * f * theta.sin() * step * step;
            }
        }
        let got = f64::from(CELL_MEAN[0]);
        assert!((got - total).abs() < 1e-5 * total, "{got} vs {total}");
        // Continuous at 4h, where the series takes over; decreasing throughout.
        let (below, above) = (CELL_MEAN[128], cell_falloff(4.0, 1.0));
        assert!((below - above).abs() < 2e-6 * above, "{below} vs {above}");
        assert!(CELL_MEAN.windows(2).all(|w| w[1] < w[0]));
        let far = (0..50).map(|i| cell_falloff(4.0 + i as f32 * 0.3, 1.0));
        let mut last = f32::INFINITY;
        for v in far {
            assert!(v < last, "{v} after {last}");
            last = v;
        }
    }

    /// `h² K(τ)` in `f64` by the same polar reduction as [`quadrature`]: 24 ∫ dφ ∫ f(s)/s² ds
    /// over the face's eighth, `f(s) = (1 − e^{−τ s})/τ` the integral along a ray to the face.
    fn centre_quadrature(tau: f64) -> f64 {
        let f = |s: f64| {
            if tau == 0.0 {
                s
            } else {
                -(-tau * s).exp_m1() / tau
            }
        };
        let n = 200;
        let quarter = core::f64::consts::FRAC_PI_4;
        let mut sum = 0.0;
        for i in 0..n {
            let phi = (f64::from(i) + 0.5) / f64::from(n) * quarter;
            let s_max = 0.5 * (1.0 + 1.0 / phi.cos().powi(2)).sqrt();
            let m = 400;
            let step = (s_max - 0.5) / f64::from(m);
            let mut inner = f(0.5) / 0.25 + f(s_max) / (s_max * s_max);
            for j in 1..m {
                let s = 0.5 + step * f64::from(j);
                inner += f(s) / (s * s) * if j % 2 == 1 { 4.0 } else { 2.0 };
            }
            sum += inner * step / 3.0;
        }
        24.0 * sum * quarter / f64::from(n)
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn the_centre_fluence_is_its_quadrature_and_conserves_energy() {
        for (i, &entry) in CENTRE_FLUENCE.iter().enumerate() {
            let tau = i as f64 / f64::from(PER_DEPTH);
            let want = centre_quadrature(tau);
            // Midpoint in φ on 200 points: 10⁻⁶ of the closed form at τ = 0 (VOXEL_MEAN[0]).
            assert!(
                (f64::from(entry) / want - 1.0).abs() < 2e-6,
                "τ = {tau}: {entry} vs {want}"
            );
            // The share of a voxel's light absorbed or scattered in it: below 1, towards 1.
            let share = f64::from(entry) * tau / (4.0 * core::f64::consts::PI);
            assert!(share < 1.0, "τ = {tau}: {share}");
        }
        assert!((CENTRE_FLUENCE[0] - VOXEL_MEAN[0]).abs() < 1e-6);
        // Continuous into 4π/τ at τ = 32, and decreasing.
        let (below, above) = (centre_fluence(32.0 - 1e-4), centre_fluence(32.0 + 1e-4));
        assert!((below - above).abs() < 1e-5, "{below} {above}");
        let mut last = f32::INFINITY;
        for i in 0..2000 {
            let k = centre_fluence(i as f32 * 0.05);
            assert!(k <= last && k > 0.0, "{k}");
            last = k;
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
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
