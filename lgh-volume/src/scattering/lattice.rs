//! The lattice kernel: a voxel's fluence in the scattering pass as the mean over its cell,
//! for the light of the voxels nearest it (paper Sec. 5, its depth-`k` lights `S^k_0` at the
//! voxel centres).
//!
//! A depth-`k` light carries what its whole cell scatters, `h³ σ_s ⟨Φ⟩_cell / 4π`, where the
//! pass computes `Φ` at the voxel's centre (collocation). Far from a light the two agree; near
//! it they do not. A level-0 light is a uniform emitting voxel (`lgh_core::near_field`): the
//! centre of a voxel sees its own light as `voxel_falloff(0) = 7.674/h²` and the cell's mean of
//! it is `5.65/h²`, so the centre over-counts a voxel's own light by 36% — and under-counts
//! its face neighbours' by 8% (the cell's mean `1.192/h²` against the centre's `1.105/h²`),
//! edges' by 7%, corners' by 5%, the voxels two over by 2%. Over the shells of uniform smoke the
//! two rules give about the same total; where a voxel's neighbours are empty — thin, sparse
//! smoke — the centre's rule is bright, and in dense smoke, where the near side of a neighbour
//! sends its light through less smoke than its centre does, dark.
//!
//! So each voxel's fluence from the level-0 lights within [`REACH_VOXELS`] is taken at the
//! cell's mean: the pass adds `(Q(o, τ) − 1)` times each such light's term in the table's own
//! uniform smoke — its fall-off and escape, unshadowed, times `e^{−σ_t d}` of the receiving
//! voxel's extinction (no shadow rays) — `Q` the cell's mean over the centre's value for a uniform
//! emitting voxel at offset `o` in uniform smoke of `τ = σ_t h` optical depths a voxel
//! ([`cell_mean`]; the receiving voxel's `τ`, clamped to the table's 0–4):
//!
//! `Q(o, τ) = M(o, τ) / F(|o|, τ)`, `M` the mean over the receiving cell and `F` the value at
//! its centre (averaged over directions, as `voxel_falloff` and `escape` are) of
//! `∫_voxel e^{−σ‖x − y‖} / ‖x − y‖² dy`.
//!
//! Measured on Blender's own fires (docs/cycles.md, "Real simulation caches") together with
//! the scattering depths' far light (`lighting_cache`, "Level 0 on the scattering depths'
//! grid"): each alone moves the image away from lgh's path tracer, the two together towards
//! it. Brute force applies it too (every light, weighted 0 beyond the reach); lightcuts keeps
//! the centres' values (no neighbour query).
//!
//! # The table
//!
//! `tools/near_field/lattice_kernel.py` prints it (polar coordinates around each receiving
//! point, as `tools/near_field/voxel_escape.py`: the midpoints of 16³ cells of the receiving voxel,
//! 8,192 directions; the voxel's own entry, whose `1/r²` the midpoints sample worst, is 0.2% above
//! 24³'s);
//! the test below recomputes entries from the definition by the same quadrature in `f64`.

/// Where a depth's pass takes the fluence of the level-0 lights near each voxel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NearLights {
    /// At the voxel's centre, as every other light (collocation): depth 1, lit by the emission.
    AtCentres,
    /// At the cell's mean, by this module's kernel, within [`REACH_VOXELS`]: the depths lit by
    /// scattered light.
    CellMeans,
}

/// The farthest a light is from a voxel's centre, in voxels, for its term to be taken at the
/// cell's mean: two voxels over along an axis (the offset `(2, 0, 0)`), not `(2, 1, 0)`.
pub const REACH_VOXELS: f32 = 2.1;

/// The optical depths a voxel of the table's columns.
const TAUS: [f32; 6] = [0.0, 0.25, 0.5, 1.0, 2.0, 4.0];

/// `Q(o, τ)` for the offsets `(0, 0, 0)`, `(1, 0, 0)`, `(1, 1, 0)`, `(1, 1, 1)`, `(2, 0, 0)`
/// (rows) at [`TAUS`] (columns): printed by `tools/near_field/lattice_kernel.py 16 8192`.
#[rustfmt::skip]
const CELL_MEAN: [[f32; 6]; 5] = [
    [0.73719, 0.73368, 0.73148, 0.73044, 0.73825, 0.77353],
    [1.07865, 1.10355, 1.13406, 1.21234, 1.44267, 2.26451],
    [1.07510, 1.10378, 1.14081, 1.24308, 1.59314, 3.38509],
    [1.04813, 1.07110, 1.10208, 1.19157, 1.51865, 3.45549],
    [1.01737, 1.02918, 1.04584, 1.09366, 1.24840, 1.82362],
];

/// Which of the table's offsets a light `u` voxels from a voxel's centre is at — the voxel
/// itself, a face, an edge, a corner, two voxels over — or `None` beyond [`REACH_VOXELS`]
/// (the lights sit on voxel centres: `u` is 0, 1, √2, √3, 2 or more).
#[must_use]
fn offset(u: f32) -> Option<usize> {
    const BOUNDS: [f32; 5] = [0.5, 1.2, 1.6, 1.9, REACH_VOXELS];
    BOUNDS.iter().position(|&b| u < b)
}

/// The cell's mean over the centre's value, `Q(o, τ)`, for a light at offset `offset` (0: the
/// voxel itself, 1: a face, 2: an edge, 3: a corner, 4: two voxels over), linear in `τ` between
/// the table's columns and held at its ends (0 and 4 optical depths a voxel).
///
/// ```
/// use lgh_volume::scattering::lattice::cell_mean;
///
/// // In clear air the centre over-counts a voxel's own light by a third, and under-counts its
/// // face neighbours' by 8%.
/// assert!((cell_mean(0, 0.0) - 0.737).abs() < 1e-3); // 5.657 / 7.674
/// assert!((cell_mean(1, 0.0) - 1.079).abs() < 1e-3);
/// // In dense smoke a neighbour's near side shines through less smoke than its centre.
/// assert!(cell_mean(1, 2.0) > 1.4);
/// assert_eq!(cell_mean(2, 9.0), cell_mean(2, 4.0));
/// ```
#[must_use]
pub fn cell_mean(offset: usize, tau: f32) -> f32 {
    let row = &CELL_MEAN[offset];
    let t = tau.clamp(TAUS[0], TAUS[TAUS.len() - 1]);
    // A NaN τ reads the first column.
    let k = TAUS[..TAUS.len() - 1]
        .iter()
        .rposition(|&x| x <= t)
        .unwrap_or(0);
    let f = (t - TAUS[k]) / (TAUS[k + 1] - TAUS[k]);
    row[k] + f * (row[k + 1] - row[k])
}

/// The correction's weights at a voxel of `tau` optical depths: `Q(o, τ) − 1` for each offset.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corrections([f32; 5]);

impl Corrections {
    /// The weights at a receiving voxel of `tau = σ_t h`.
    #[must_use]
    pub(crate) fn at(tau: f32) -> Self {
        Corrections(core::array::from_fn(|o| cell_mean(o, tau) - 1.0))
    }

    /// The weight of a level-0 light's term at distance `d` from the voxel's centre, voxels of
    /// side `h`: `Q − 1` within [`REACH_VOXELS`], 0 beyond.
    #[must_use]
    pub(crate) fn weight(&self, d: f32, h: f32) -> f32 {
        offset(d / h).map_or(0.0, |o| self.0[o])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::near_field::{escape, voxel_falloff};

    /// Directions on a Fibonacci sphere.
    fn fibonacci(n: usize) -> Vec<[f64; 3]> {
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
                let r = (1.0 - z * z).sqrt();
                let phi = (i as f64 + 0.5) * core::f64::consts::PI * (3.0 - 5f64.sqrt());
                [r * phi.cos(), r * phi.sin(), z]
            })
            .collect()
    }

    /// `∫_voxel e^{−τ‖x − y‖}/‖x − y‖² dy` for the unit voxel at the origin, by directions
    /// around `x`: the chord `[r_in, r_out]` of each ray through the voxel.
    fn fluence(x: [f64; 3], dirs: &[[f64; 3]], tau: f64) -> f64 {
        let mut sum = 0.0;
        for w in dirs {
            let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
            for a in 0..3 {
                if w[a] == 0.0 {
                    if x[a].abs() > 0.5 {
                        hi = -1.0;
                    }
                    continue;
                }
                let (t1, t2) = ((-0.5 - x[a]) / w[a], (0.5 - x[a]) / w[a]);
                lo = lo.max(t1.min(t2));
                hi = hi.min(t1.max(t2));
            }
            if hi > lo {
                sum += if tau == 0.0 {
                    hi - lo
                } else {
                    ((-tau * lo).exp() - (-tau * hi).exp()) / tau
                };
            }
        }
        sum * 4.0 * core::f64::consts::PI / dirs.len() as f64
    }

    #[test]
    fn the_table_is_the_cells_mean_over_the_centres_value() {
        // M by the midpoints of 12³ cells of the receiving voxel and 1,024 directions, against
        // the pass's own centre value, `voxel_falloff · escape · e^{−τu}` (lgh_core's tables,
        // read as the pass reads them). The midpoints' error falls as 1/n²: at 8³ the face
        // entry at τ = 2 is 1.9% below the printed table's 16³ (the smoke's e^{−τr} varies
        // most across the cell there), at 12³ the worst entry is 0.6% off (printed), and the
        // centre's tables are within 0.2% of their definitions. Tolerance 1.5%.
        let dirs = fibonacci(1024);
        let n = 12;
        let offsets = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 1.0, 1.0],
            [2.0, 0.0, 0.0],
        ];
        let mut worst = 0.0f64;
        for (o, off) in offsets.iter().enumerate() {
            let u: f64 = off.iter().map(|c| c * c).sum::<f64>().sqrt();
            for tau in [0.0f32, 0.5, 1.0, 2.0] {
                let mut m = 0.0;
                for i in 0..n * n * n {
                    let c = [i % n, i / n % n, i / (n * n)];
                    let x: [f64; 3] =
                        core::array::from_fn(|a| off[a] + (c[a] as f64 + 0.5) / n as f64 - 0.5);
                    m += fluence(x, &dirs, f64::from(tau));
                }
                m /= (n * n * n) as f64;
                let h = 1.0f32;
                let centre = f64::from(
                    voxel_falloff(u as f32, h) * escape(u as f32, tau) * (-tau * u as f32).exp(),
                );
                let q = m / centre;
                let table = f64::from(cell_mean(o, tau));
                worst = worst.max((table / q - 1.0).abs());
                assert!(
                    (table / q - 1.0).abs() < 0.015,
                    "offset {o}, τ {tau}: table {table:.4}, quadrature {q:.4}"
                );
            }
        }
        eprintln!("the table against the quadrature: worst relative difference {worst:.4}");
    }

    #[test]
    fn lights_beyond_two_voxels_are_not_corrected() {
        let c = Corrections::at(1.0);
        assert!(
            c.weight(0.0, 0.5) < 0.0,
            "a voxel's own light is over-counted at its centre"
        );
        assert!(c.weight(0.5, 0.5) > 0.0 && c.weight(1.0, 0.5) > 0.0);
        assert_eq!(c.weight(5f32.sqrt() * 0.5, 0.5), 0.0);
        assert_eq!(c.weight(f32::NAN, 0.5), 0.0);
    }
}
