//! How a voxel light's own smoke changes what reaches a point near it: the exact fluence of a
//! uniform emitting voxel through uniform smoke, against the voxel light's model of it.
//!
//! A renderer shades a voxel light at `x` as `I · G(d) · V(x, c)`: the voxel's mean of `1/r²`
//! ([`voxel_falloff`](super::voxel_falloff)) times the transmittance `V` of a shadow ray to the
//! voxel's centre `c`. In smoke of extinction `σ` around both, that shadow ray gives
//! `e^{−σ d}`, while a uniform voxel's light reaches `x` from every point of the voxel, each
//! through its own path:
//!
//! `F(d, τ) = (1/h³) ∫_voxel e^{−σ ‖x − y‖} / ‖x − y‖² dy`, `τ = σ h` (the smoke's optical
//! depth a voxel),
//!
//! averaged over the directions of `x` from `c` as `G` is. The *escape* `R(u, τ) = F / (G
//! e^{−τ u})`, `u = d/h`, is the factor between the two:
//!
//! - below 1 inside the voxel (its centre sees its own light only from close by: `R(0, τ) G(0)`
//!   is the centre's fluence `K(τ)` of `CENTRE_FLUENCE`, which keeps a voxel's light scattered
//!   in itself below its albedo);
//! - above 1 from about 0.3 voxels on, rising with `τ`: the voxel's near half sends its light
//!   through less smoke than its centre does (Jensen's inequality on `e^{−σ r}`): 1.147 at
//!   `u = 1`, `τ = 1`; 1.42 at `τ = 2`; 2.66 at `τ = 4`; far away it tends to the cell's mean of
//!   `e^{−σ (y − c)·ω}`, `Π_i sinh(τ ω_i/2) / (τ ω_i/2)` averaged over `ω`, `1 + τ²/24 + …`
//!   (1.042 at `τ = 1`; the table's 1.064 at `u = 4`).
//!
//! Without it (a voxel light's near field unshielded beyond 0.3 voxels, as lgh had before), on
//! a dense baked fire (Blender 3.4.1's smoky Quick Smoke at 64 cells, up to 0.9 optical depths
//! a voxel) the brute-force sum over the voxel lights with ray-marched shadows — lgh's light
//! model without the hierarchy — gave 0.912 of the path tracer's single scattering; with it,
//! 0.978 (docs/cycles.md, "Real simulation caches").
//!
//! # The table
//!
//! `R` at `u = 0, 1/8, …, 4` and `τ = 0, 1/4, …, 8` (33 × 33), computed by
//! `tools/near_field/voxel_escape.py` (polar coordinates around `x`: the integral over
//! directions of `(e^{−τ r_in} − e^{−τ r_out}) / τ` along each ray's chord through the voxel;
//! 256 points `x` and 32,768 rays each, both on Fibonacci spheres: `G(u)` to 2·10⁻⁵ of
//! `VOXEL_MEAN`), read with bilinear interpolation. Beyond 4 voxels `R` is held at its value
//! there (a level-0 light is shaded that far only by a brute-force sum or a huge α): above the
//! far field's limit by 2% at `τ = 1`, 4% at `τ = 2`, 8% at `τ = 4` and 13% at `τ = 8` (the test
//! `far_away_the_escape_tends_to_the_cells_mean`); beyond `τ = 8` it is the table's last column
//! times `K(τ)/K(8)`: exact at the centre, an under-count elsewhere (the near side's light
//! rises with `τ` against the centre's). The tests below recompute entries by Monte Carlo, from
//! the definition.

/// `R(u, τ)` at `u = i/8` (rows, `i = 0..=32`) and `τ = j/4` (columns, `j = 0..=32`): printed by
/// `tools/near_field/voxel_escape.py` (module documentation).
#[rustfmt::skip]
const ESCAPE: [[f32; 33]; 33] = [
    [1.0, 0.926379, 0.859993, 0.800038, 0.745801, 0.696658, 0.652058, 0.611514, 0.574597, 0.540927, 0.510167, 0.48202, 0.456221, 0.432536, 0.410755, 0.390693, 0.372185, 0.355082, 0.339253, 0.32458, 0.310957, 0.29829, 0.286494, 0.275492, 0.265217, 0.255605, 0.246602, 0.238158, 0.230226, 0.222767, 0.215741, 0.209117, 0.202863],
    [1.0, 0.955794, 0.915566, 0.878945, 0.845597, 0.815225, 0.787561, 0.762367, 0.739428, 0.718551, 0.699562, 0.682306, 0.666642, 0.652444, 0.639597, 0.627998, 0.617554, 0.608182, 0.599805, 0.592355, 0.58577, 0.579993, 0.574973, 0.570664, 0.567024, 0.564016, 0.561606, 0.559761, 0.558454, 0.557659, 0.557354, 0.557518, 0.558131],
    [1.0, 0.986023, 0.974697, 0.965866, 0.959396, 0.955167, 0.953079, 0.953046, 0.954994, 0.958864, 0.964606, 0.972182, 0.981565, 0.992734, 1.00568, 1.0204, 1.03689, 1.05518, 1.07528, 1.09722, 1.12102, 1.14674, 1.17441, 1.20409, 1.23584, 1.26973, 1.30581, 1.34419, 1.38493, 1.42813, 1.4739, 1.52234, 1.57356],
    [1.0, 1.01643, 1.03632, 1.05974, 1.08675, 1.11746, 1.15198, 1.19047, 1.23309, 1.28005, 1.33157, 1.3879, 1.44932, 1.51614, 1.58872, 1.66742, 1.75266, 1.84489, 1.94461, 2.05237, 2.16874, 2.29436, 2.42995, 2.57624, 2.73406, 2.90431, 3.08795, 3.28604, 3.4997, 3.7302, 3.97885, 4.24713, 4.53661],
    [1.0, 1.04375, 1.09381, 1.15066, 1.21481, 1.28689, 1.36759, 1.45769, 1.55807, 1.66973, 1.79376, 1.93142, 2.08409, 2.25332, 2.44085, 2.6486, 2.87875, 3.13369, 3.4161, 3.72899, 4.07569, 4.45992, 4.88584, 5.35808, 5.88182, 6.46281, 7.1075, 7.82307, 8.61754, 9.49987, 10.48, 11.5692, 12.7799],
    [1.0, 1.05306, 1.11474, 1.18591, 1.26759, 1.36097, 1.4674, 1.58844, 1.72588, 1.88177, 2.05846, 2.25864, 2.48539, 2.7422, 3.03312, 3.36273, 3.73628, 4.1598, 4.64016, 5.18523, 5.80402, 6.50686, 7.30555, 8.21363, 9.24663, 10.4223, 11.7611, 13.2863, 15.0248, 17.0074, 19.2694, 21.8514, 24.8],
    [1.0, 1.04322, 1.09452, 1.15473, 1.22479, 1.30584, 1.39919, 1.50638, 1.62919, 1.7697, 1.93032, 2.11385, 2.32354, 2.56316, 2.83709, 3.1504, 3.509, 3.91975, 4.39063, 4.93093, 5.55146, 6.26481, 7.08568, 8.0312, 9.12136, 10.3795, 11.833, 13.5138, 15.4592, 17.713, 20.3264, 23.3596, 26.8831],
    [1.0, 1.03226, 1.07132, 1.11773, 1.17212, 1.23528, 1.30809, 1.39161, 1.48706, 1.59585, 1.71962, 1.86024, 2.01992, 2.20115, 2.40684, 2.64033, 2.90549, 3.20678, 3.54935, 3.93916, 4.38309, 4.88912, 5.46648, 6.12588, 6.87973, 7.74245, 8.73079, 9.86421, 11.1654, 12.6606, 14.3808, 16.3616, 18.645],
    [1.0, 1.02687, 1.06006, 1.10001, 1.14724, 1.20238, 1.26618, 1.33951, 1.42338, 1.51897, 1.62762, 1.7509, 1.89062, 2.04884, 2.22795, 2.43069, 2.66023, 2.92018, 3.21474, 3.54871, 3.92765, 4.35795, 4.847, 5.40332, 6.03675, 6.75869, 7.58232, 8.52288, 9.59807, 10.8284, 12.2376, 13.8534, 15.7079],
    [1.0, 1.02339, 1.05285, 1.08874, 1.13153, 1.18178, 1.24015, 1.30741, 1.38446, 1.47235, 1.57229, 1.68567, 1.81411, 1.95945, 2.12382, 2.30965, 2.51976, 2.75737, 3.02618, 3.33046, 3.67511, 4.06577, 4.50894, 5.01212, 5.58395, 6.2344, 6.97499, 7.81905, 8.78198, 9.8816, 11.1386, 12.5769, 14.2243],
    [1.0, 1.02087, 1.04765, 1.08066, 1.12032, 1.16715, 1.22174, 1.28481, 1.35719, 1.43984, 1.53388, 1.6406, 1.76149, 1.89825, 2.05285, 2.22753, 2.42489, 2.6479, 2.89997, 3.18502, 3.50755, 3.87274, 4.28657, 4.75589, 5.28862, 5.89387, 6.58217, 7.36568, 8.25843, 9.27666, 10.4392, 11.7677, 13.2875],
    [1.0, 1.01894, 1.04367, 1.0745, 1.1118, 1.15606, 1.20784, 1.2678, 1.33672, 1.41552, 1.50524, 1.6071, 1.7225, 1.85305, 2.00059, 2.16725, 2.35546, 2.56803, 2.80815, 3.07952, 3.38636, 3.73355, 4.12667, 4.57216, 5.07744, 5.65105, 6.30283, 7.04414, 7.8881, 8.84988, 9.94701, 11.1998, 12.6317],
    [1.0, 1.0174, 1.04051, 1.06961, 1.10506, 1.14731, 1.19689, 1.25443, 1.32068, 1.3965, 1.4829, 1.58103, 1.69223, 1.81804, 1.96021, 2.12078, 2.30206, 2.50674, 2.73785, 2.99892, 3.29398, 3.62767, 4.0053, 4.433, 4.91782, 5.46787, 6.09251, 6.80254, 7.61039, 8.53045, 9.57934, 10.7763, 12.1435],
    [1.0, 1.01614, 1.03792, 1.06562, 1.09956, 1.14018, 1.18799, 1.2436, 1.3077, 1.38115, 1.46489, 1.56005, 1.66792, 1.78996, 1.92789, 2.08364, 2.25947, 2.45792, 2.68196, 2.93495, 3.22077, 3.54389, 3.90941, 4.32322, 4.79209, 5.32381, 5.92736, 6.61308, 7.39292, 8.28066, 9.29222, 10.446, 11.7634],
    [1.0, 1.01509, 1.03577, 1.0623, 1.095, 1.13428, 1.18064, 1.23465, 1.297, 1.3685, 1.45009, 1.54283, 1.64799, 1.76699, 1.90147, 2.05334, 2.22475, 2.4182, 2.63654, 2.88303, 3.16144, 3.47608, 3.83191, 4.23461, 4.69073, 5.20782, 5.79454, 6.46091, 7.21847, 8.08051, 9.06244, 10.182, 11.4598],
    [1.0, 1.01419, 1.03393, 1.05947, 1.09112, 1.12927, 1.1744, 1.22707, 1.28795, 1.35782, 1.4376, 1.52833, 1.63122, 1.74768, 1.87931, 2.02794, 2.19569, 2.38499, 2.5986, 2.83972, 3.112, 3.41964, 3.76746, 4.16099, 4.60661, 5.11165, 5.68453, 6.33499, 7.07424, 7.91519, 8.8728, 9.96432, 11.2097],
    [1.0, 1.01342, 1.03235, 1.05705, 1.0878, 1.12498, 1.16906, 1.22059, 1.28022, 1.34872, 1.42696, 1.51598, 1.61697, 1.73129, 1.86051, 2.00642, 2.17109, 2.3569, 2.56655, 2.80316, 3.07031, 3.37209, 3.71322, 4.0991, 4.53596, 5.03094, 5.5923, 6.22951, 6.95351, 7.77693, 8.71434, 9.78256, 11.0011],
    [1.0, 1.01274, 1.03098, 1.05493, 1.0849, 1.12125, 1.16442, 1.21496, 1.27351, 1.34081, 1.41774, 1.50529, 1.60463, 1.71711, 1.84425, 1.98782, 2.14985, 2.33266, 2.53891, 2.77166, 3.03441, 3.33117, 3.66657, 4.0459, 4.47525, 4.96165, 5.51315, 6.13904, 6.85004, 7.6585, 8.57868, 9.62704, 10.8226],
    [1.0, 1.01215, 1.02977, 1.05308, 1.08236, 1.11798, 1.16037, 1.21005, 1.26766, 1.33393, 1.40972, 1.496, 1.59393, 1.70482, 1.83017, 1.97174, 2.1315, 2.31175, 2.51509, 2.74453, 3.00351, 3.29598, 3.62649, 4.00023, 4.42319, 4.90226, 5.44536, 6.06162, 6.76155, 7.55728, 8.46281, 9.4943, 10.6704],
    [1.0, 1.01162, 1.0287, 1.05144, 1.08012, 1.11509, 1.15678, 1.20571, 1.26249, 1.32785, 1.40263, 1.4878, 1.58448, 1.69397, 1.81776, 1.95757, 2.11534, 2.29333, 2.49412, 2.72067, 2.97635, 3.26508, 3.5913, 3.96016, 4.37754, 4.85022, 5.386, 5.99385, 6.68414, 7.46879, 8.36156, 9.37837, 10.5376],
    [1.0, 1.01115, 1.02775, 1.04998, 1.07812, 1.11252, 1.1536, 1.20186, 1.25792, 1.32248, 1.39637, 1.48055, 1.57614, 1.68441, 1.80683, 1.94509, 2.10112, 2.27714, 2.4757, 2.69971, 2.95253, 3.23798, 3.56048, 3.92509, 4.33761, 4.80474, 5.33417, 5.93476, 6.6167, 7.39178, 8.27356, 9.27772, 10.4224],
    [1.0, 1.01073, 1.02688, 1.04866, 1.07632, 1.1102, 1.15072, 1.19839, 1.25378, 1.31762, 1.39072, 1.47402, 1.56862, 1.67579, 1.79697, 1.93384, 2.0883, 2.26254, 2.45909, 2.68082, 2.93103, 3.21353, 3.53265, 3.89341, 4.30152, 4.76361, 5.28726, 5.88121, 6.55553, 7.32185, 8.19355, 9.1861, 10.3174],
    [1.0, 1.01035, 1.02611, 1.04747, 1.0747, 1.10812, 1.14815, 1.19528, 1.25009, 1.31329, 1.38568, 1.4682, 1.56193, 1.66813, 1.78822, 1.92386, 2.07694, 2.24963, 2.44442, 2.66415, 2.9121, 3.19202, 3.50821, 3.86561, 4.26991, 4.72763, 5.24629, 5.83452, 6.50229, 7.26107, 8.12413, 9.10674, 10.2266],
    [1.0, 1.01, 1.0254, 1.04638, 1.07321, 1.10621, 1.14578, 1.19241, 1.24668, 1.30928, 1.38102, 1.46281, 1.55573, 1.66102, 1.78009, 1.91459, 2.06638, 2.23761, 2.43074, 2.6486, 2.89442, 3.17191, 3.48534, 3.83958, 4.24028, 4.69387, 5.20779, 5.7906, 6.45213, 7.20376, 8.05857, 9.03169, 10.1406],
    [1.0, 1.00968, 1.02476, 1.04541, 1.07189, 1.10451, 1.14368, 1.18988, 1.24369, 1.30578, 1.37694, 1.45811, 1.55033, 1.65484, 1.77305, 1.90657, 2.05726, 2.22725, 2.41898, 2.63525, 2.87927, 3.15472, 3.46582, 3.81742, 4.21509, 4.66523, 5.17521, 5.75351, 6.40988, 7.15559, 8.00361, 8.96893, 10.0689],
    [1.0, 1.00939, 1.02417, 1.04451, 1.07065, 1.10293, 1.14172, 1.18751, 1.24087, 1.30247, 1.3731, 1.45366, 1.54522, 1.64899, 1.76637, 1.89895, 2.04859, 2.21739, 2.40778, 2.62253, 2.86482, 3.1383, 3.44715, 3.79619, 4.19094, 4.63775, 5.14391, 5.71782, 6.36917, 7.1091, 7.95049, 8.90818, 9.99933],
    [1.0, 1.00912, 1.02362, 1.04367, 1.06952, 1.10147, 1.13991, 1.18533, 1.23829, 1.29945, 1.36959, 1.44962, 1.54058, 1.64368, 1.76031, 1.89206, 2.04076, 2.20849, 2.39768, 2.61107, 2.85181, 3.12354, 3.4304, 3.77717, 4.16933, 4.61317, 5.11594, 5.68598, 6.33289, 7.06773, 7.90327, 8.85423, 9.93765],
    [1.0, 1.00888, 1.02313, 1.04291, 1.06848, 1.10014, 1.13827, 1.18335, 1.23594, 1.2967, 1.3664, 1.44593, 1.53635, 1.63884, 1.75479, 1.88577, 2.03361, 2.20038, 2.38846, 2.6006, 2.83993, 3.11005, 3.41509, 3.75977, 4.14955, 4.59067, 5.09034, 5.65681, 6.29964, 7.02979, 7.85995, 8.80473, 9.88103],
    [1.0, 1.00865, 1.02265, 1.0422, 1.0675, 1.09888, 1.13672, 1.18148, 1.23373, 1.2941, 1.36339, 1.44246, 1.53237, 1.63429, 1.7496, 1.87987, 2.0269, 2.19276, 2.37982, 2.59079, 2.82881, 3.09743, 3.40076, 3.7435, 4.13107, 4.56967, 5.06644, 5.62961, 6.26865, 6.99446, 7.81963, 8.75869, 9.8284],
    [1.0, 1.00843, 1.02222, 1.04154, 1.06661, 1.09773, 1.1353, 1.17976, 1.23168, 1.29171, 1.3606, 1.43925, 1.52868, 1.63007, 1.74478, 1.87438, 2.02066, 2.18567, 2.37176, 2.58165, 2.81843, 3.08565, 3.38738, 3.72831, 4.11379, 4.55002, 5.04407, 5.60413, 6.2396, 6.96132, 7.78178, 8.71542, 9.7789],
    [1.0, 1.00824, 1.02184, 1.04095, 1.0658, 1.09671, 1.13403, 1.17824, 1.22988, 1.2896, 1.35816, 1.43644, 1.52546, 1.62639, 1.74059, 1.86962, 2.01525, 2.17954, 2.36482, 2.57378, 2.80951, 3.07554, 3.37592, 3.71531, 4.09904, 4.53326, 5.02502, 5.58246, 6.21493, 6.9332, 7.74971, 8.67881, 9.73705],
    [1.0, 1.00805, 1.02145, 1.04035, 1.065, 1.09567, 1.13276, 1.1767, 1.22806, 1.28747, 1.35569, 1.43359, 1.52219, 1.62265, 1.73633, 1.86477, 2.00975, 2.17329, 2.35773, 2.56574, 2.80039, 3.06519, 3.36417, 3.70196, 4.08386, 4.516, 5.00537, 5.56007, 6.1894, 6.90406, 7.71642, 8.64074, 9.69348],
    [1.0, 1.00788, 1.02109, 1.03981, 1.06426, 1.09473, 1.13159, 1.1753, 1.2264, 1.28553, 1.35344, 1.43099, 1.51921, 1.61925, 1.73246, 1.86036, 2.00473, 2.1676, 2.35127, 2.55841, 2.79207, 3.05575, 3.35344, 3.68977, 4.07001, 4.50024, 4.98743, 5.53963, 6.16608, 6.87745, 7.68602, 8.60597, 9.65368],
];

/// Rows of [`ESCAPE`] per voxel of distance.
const PER_VOXEL: f32 = 8.0;
/// Columns of [`ESCAPE`] per unit of optical depth.
const PER_DEPTH: f32 = 4.0;
/// The deepest smoke of [`ESCAPE`], in optical depths a voxel.
const MAX_DEPTH: f32 = 8.0;

/// The escape `R(u, tau)` of a uniform voxel's light to a point `u` voxels from its centre
/// through uniform smoke of `tau` optical depths a voxel (module documentation): the exact
/// fluence over the voxel light's `G(u) e^{−τ u}`. 1 in clear air (`tau ≤ 0`, or not a
/// number).
///
/// ```
/// use lgh_core::near_field::escape;
///
/// assert_eq!(escape(0.7, 0.0), 1.0);
/// // At the centre, the voxel's own smoke hides most of its light...
/// assert!(escape(0.0, 1.0) < 0.75);
/// // ...one voxel over, its near half sends more than its centre's shadow ray says.
/// assert!((escape(1.0, 1.0) - 1.147).abs() < 2e-3);
/// assert!(escape(1.0, 4.0) > 2.5);
/// ```
#[must_use]
pub fn escape(u: f32, tau: f32) -> f32 {
    // Not above 0 (a NaN included): clear air.
    if tau.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
        return 1.0;
    }
    let (depth, beyond) = if tau <= MAX_DEPTH {
        (tau, 1.0)
    } else {
        (
            MAX_DEPTH,
            super::centre_fluence(tau) / super::centre_fluence(MAX_DEPTH),
        )
    };
    // Both indices ≥ 0 (a NaN `u` goes to row 0 by the saturating cast), each held below the
    // table's last row or column.
    let fu = (u.max(0.0) * PER_VOXEL).min(ESCAPE.len() as f32 - 1.0);
    let ft = depth * PER_DEPTH;
    let (i, j) = (
        (fu as usize).min(ESCAPE.len() - 2),
        (ft as usize).min(ESCAPE[0].len() - 2),
    );
    let (a, b) = (fu - i as f32, ft - j as f32);
    let row = |r: &[f32; 33]| r[j] + (r[j + 1] - r[j]) * b;
    let (near, far) = (row(&ESCAPE[i]), row(&ESCAPE[i + 1]));
    (near + (far - near) * a) * beyond
}

#[cfg(test)]
mod tests {
    use super::super::tests::{estimate, in_cone, span, unit};
    use super::*;
    use crate::random::SplitMix64;
    use wasm_bindgen_test::wasm_bindgen_test;

    #[wasm_bindgen_test(unsupported = test)]
    fn the_escape_by_monte_carlo() {
        // From the definition, independent of the table's script (its rays and points are
        // Fibonacci spheres, these are random): x = u ω with ω uniform, a ray from x uniform
        // over the directions that can meet the voxel (all of them inside its circumscribed
        // sphere, else the cone around it) weighted by their solid angle, gathering
        // `(e^{−τ t_in} − e^{−τ t_out}) / τ` along its chord; the mean over samples is F(u, τ),
        // divided by G(u) e^{−τ u} with G the tested `voxel_falloff` (to 7.3·10⁻⁴). Bound: 5
        // standard errors (a false alarm about once in 1.7 million runs per entry) plus 0.3%
        // for the table's bilinear interpolation and G's table.
        let mut rng = SplitMix64(0xe5ca9e);
        let n = 200_000;
        let reach = 0.75f64.sqrt();
        for (u, tau) in [
            (0.0, 0.5),
            (0.2, 1.0),
            (0.45, 2.0),
            (0.6, 0.9),
            (1.0, 1.0),
            (1.3, 3.0),
        ] {
            let (mut sum, mut sum2) = (0.0, 0.0);
            for _ in 0..n {
                let x = unit(&mut rng) * u;
                let (w, solid_angle) = if u <= reach {
                    (unit(&mut rng), 4.0 * core::f64::consts::PI)
                } else {
                    let cos_max = (1.0 - (reach / u).powi(2)).sqrt();
                    in_cone(&mut rng, -x / u, cos_max)
                };
                let (t0, t1) = span(x, w);
                let v = solid_angle * ((-tau * t0).exp() - (-tau * t1).exp()) / tau;
                sum += v;
                sum2 += v * v;
            }
            let (mean, err) = estimate(sum, sum2, n);
            let model = f64::from(super::super::voxel_falloff(u as f32, 1.0)) * (-tau * u).exp();
            let (want, err) = (mean / model, err / model);
            let got = f64::from(escape(u as f32, tau as f32));
            assert!(
                (got - want).abs() < 5.0 * err + 3e-3 * want,
                "u = {u}, τ = {tau}: table {got}, Monte Carlo {want} ± {err}"
            );
            assert!(
                err < 0.005 * want,
                "u = {u}, τ = {tau}: too few samples ({err})"
            );
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn the_centre_row_is_the_centre_fluence_and_clear_air_is_one() {
        // Two computations of K(τ): the table's script (rays on a Fibonacci sphere) and the
        // quadrature of `CENTRE_FLUENCE` (tested to 2·10⁻⁶): within the script's 2·10⁻⁴.
        let g0 = super::super::voxel_falloff(0.0, 1.0);
        for (j, &r) in ESCAPE[0].iter().enumerate() {
            let tau = j as f32 / PER_DEPTH;
            let k = super::super::centre_fluence(tau);
            assert!((r * g0 / k - 1.0).abs() < 2e-4, "τ = {tau}");
        }
        for row in &ESCAPE {
            assert_eq!(row[0], 1.0);
        }
        for u in [0.0, 0.3, 1.0, 7.0, f32::NAN] {
            assert_eq!(escape(u, 0.0), 1.0);
            assert_eq!(escape(u, f32::NAN), 1.0);
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn far_away_the_escape_tends_to_the_cells_mean() {
        // Far from the voxel its points' paths to x are parallel: R → the cell's mean of
        // `e^{−τ (y − c)·ω}`, a product over the axes of `sinh(a)/a`, `a = τ |ω_i| / 2`,
        // averaged over ω (a Fibonacci sphere of 4,096 directions). The table's last row holds
        // R at u = 4, which the escape keeps beyond: above the limit, by at most what the
        // module documentation says.
        let n = 4096;
        let limit = |tau: f64| {
            let golden = core::f64::consts::PI * (3.0 - 5f64.sqrt());
            let sum: f64 = (0..n)
                .map(|k| {
                    let z = 1.0 - (2 * k + 1) as f64 / n as f64;
                    let r = (1.0 - z * z).sqrt();
                    let phi = golden * k as f64;
                    [r * libm::cos(phi), r * libm::sin(phi), z]
                        .iter()
                        .map(|w| {
                            let a = 0.5 * tau * w.abs();
                            if a < 1e-9 {
                                1.0
                            } else {
                                libm::sinh(a) / a
                            }
                        })
                        .product::<f64>()
                })
                .sum();
            sum / n as f64
        };
        for (tau, above) in [
            (0.25, 0.006),
            (1.0, 0.022),
            (2.0, 0.043),
            (4.0, 0.08),
            (8.0, 0.13),
        ] {
            let far = limit(tau);
            assert!((far - (1.0 + tau * tau / 24.0)).abs() < 0.01 * tau.powi(4) + 1e-6);
            let held = f64::from(escape(40.0, tau as f32));
            assert!(
                held >= far && held <= far * (1.0 + above),
                "τ = {tau}: {held} vs {far}"
            );
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn continuous_everywhere_and_never_above_the_table_in_opaque_smoke() {
        // Continuous in u and τ across the table's last row and column.
        for tau in [0.3f32, 2.0, 7.9] {
            let (a, b) = (escape(4.0 - 1e-4, tau), escape(4.0 + 1e-4, tau));
            assert!((a - b).abs() < 1e-4 * a, "τ = {tau}: {a} {b}");
        }
        for u in [0.0f32, 0.4, 1.0, 3.0] {
            let (a, b) = (escape(u, MAX_DEPTH - 1e-4), escape(u, MAX_DEPTH + 1e-4));
            assert!((a - b).abs() < 1e-3 * a, "u = {u}: {a} {b}");
            // Beyond the table the escape falls as the centre's fluence: in opaque smoke a
            // voxel keeps its light in itself.
            assert!(escape(u, 100.0) < escape(u, MAX_DEPTH));
        }
        // The escape rises with the smoke beyond a third of a voxel, falls with it at the
        // centre.
        for j in 1..=32 {
            assert!(ESCAPE[0][j] < ESCAPE[0][j - 1]);
            for row in &ESCAPE[4..] {
                assert!(row[j] > row[j - 1]);
            }
        }
    }
}
