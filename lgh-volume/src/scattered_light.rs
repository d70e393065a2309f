//! The scattered light of multiple scattering as a grid of in-scattered radiance at the voxel
//! centres, instead of lights shaded at every march sample.
//!
//! **What the render needs of the scattered lights.** A march sample at `x` in-scatters, from
//! the depth-`k` lights `S^k` (paper Sec. 5), `σ_s(x)/(4π) · Φ^k(x)`, `Φ^k` their shadowed
//! fluence. The scattering pass computes exactly that quantity at every voxel with smoke to
//! make the next depth's lights: `I^{k+1}(v) = h³ σ_s(v)/(4π) · Φ^k(v)`
//! ([`crate::scattering`]). So the in-scattered radiance of depths `1..=n` at voxel `v` is
//! `S(v) = Σ_{k=2}^{n+1} I^k(v) / h³` — one more fluence pass than the merged lights need
//! (depth `n + 1`'s, whose lights are never built), and no light of depth ≥ 1 left to shade
//! per sample. The render adds `S` trilinearly interpolated between voxel centres, as it
//! interpolates the density and the emission (zero beyond the smoke, where `σ_s = 0`).
//!
//! **Why it may be interpolated.** Light that has scattered once comes from all the smoke, not
//! from a hot voxel next door: `Φ^k` for `k ≥ 1` varies over the smoke's scale and its shadows,
//! which is why the scattering pass already computes depths ≥ 2 on a coarser grid
//! ([`LightingCacheSettings::scattered_depths`]). Interpolating `σ_s Φ^k` between voxel
//! centres is the lighting cache at one voxel for those lights (`docs/shadows.md`: 0.5% on the
//! Fig. 8-class frame), here without a shadow gradient.
//!
//! **What it changes.** The merged lights (the paper's one light per voxel) shade every march
//! sample with the emission and all scattered depths: on the Fig. 8-class frame at depth 4,
//! 236 lights a sample where the emission alone needs 86. With the grid, samples shade the
//! emission lights only; surfaces, which have no voxels, are still lit by the merged lights.
//!
//! [`LightingCacheSettings::scattered_depths`]: crate::lighting_cache::LightingCacheSettings::scattered_depths

use lgh_core::glam::Vec3;

use crate::grid::DenseGrid;
use crate::occupancy::Occupancy;

/// In-scattered radiance of the scattered light at the voxel centres (module docs), per
/// colour channel.
#[derive(Clone, Debug)]
pub struct ScatteredRadiance {
    channels: [DenseGrid; 3],
    /// The bricks where it is not zero ([`is_empty_at`](Self::is_empty_at)).
    occupancy: Occupancy,
}

impl ScatteredRadiance {
    /// `S(v) = Σ_k I^k(v) / h³` over `voxels` (flat indices into `grid`, with `summed[i]` the
    /// summed intensity of depths ≥ 2 at `voxels[i]`), zero at every other voxel of `grid`'s
    /// lattice.
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::scattered_light::ScatteredRadiance;
    ///
    /// let grid = DenseGrid::zeros([3, 1, 1], 0.5, Vec3::ZERO);
    /// let s = ScatteredRadiance::new(&grid, &[1, 2], &[Vec3::splat(0.125), Vec3::ZERO]);
    /// assert_eq!(s.sample(Vec3::new(0.5, 0.0, 0.0)), Vec3::ONE); // 0.125 / 0.5³
    /// assert_eq!(s.sample(Vec3::new(0.25, 0.0, 0.0)), Vec3::splat(0.5)); // halfway to 0
    /// ```
    #[must_use]
    pub fn new(grid: &DenseGrid, voxels: &[usize], summed: &[Vec3]) -> Self {
        let inv_h3 = 1.0 / grid.voxel_size.powi(3);
        let mut channels =
            [0, 1, 2].map(|_| DenseGrid::zeros(grid.dims, grid.voxel_size, grid.origin));
        for (&v, &i) in voxels.iter().zip(summed) {
            let s = i * inv_h3;
            for (c, value) in channels.iter_mut().zip(s.to_array()) {
                c.data[v] = value;
            }
        }
        let mut occupancy = Occupancy::empty(grid);
        for c in &channels {
            occupancy.mark(c, |v| v != 0.0, 0.0);
        }
        ScatteredRadiance {
            channels,
            occupancy,
        }
    }

    /// Whether [`sample`](Self::sample) is zero at `x` for certain: `x` lies in a brick of
    /// [`crate::occupancy`] that no voxel with light reaches (the march skips such samples).
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::scattered_light::ScatteredRadiance;
    ///
    /// let grid = DenseGrid::zeros([32, 8, 8], 1.0, Vec3::ZERO);
    /// let s = ScatteredRadiance::new(&grid, &[grid.index(2, 4, 4)], &[Vec3::ONE]);
    /// assert!(!s.is_empty_at(Vec3::new(2.0, 4.0, 4.0)));
    /// assert!(s.is_empty_at(Vec3::new(20.0, 4.0, 4.0)));
    /// ```
    #[must_use]
    pub fn is_empty_at(&self, x: Vec3) -> bool {
        self.occupancy.is_empty_at(x)
    }

    /// The radiance in-scattered at `x` per unit length of the march, interpolated between
    /// voxel centres ([`DenseGrid::sample`]; zero outside the grid).
    #[must_use]
    pub fn sample(&self, x: Vec3) -> Vec3 {
        Vec3::from_array(self.channels.each_ref().map(|c| c.sample(x)))
    }

    /// The value at voxel `v` (a flat index of the grid it was made on), as stored; zero past
    /// the grid.
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::scattered_light::ScatteredRadiance;
    ///
    /// let grid = DenseGrid::zeros([2, 1, 1], 0.5, Vec3::ZERO);
    /// let s = ScatteredRadiance::new(&grid, &[1], &[Vec3::new(0.125, 0.0, 0.25)]);
    /// assert_eq!((s.voxel(0), s.voxel(1), s.voxel(9)), (Vec3::ZERO, Vec3::new(1.0, 0.0, 2.0), Vec3::ZERO));
    /// ```
    #[must_use]
    pub fn voxel(&self, v: usize) -> Vec3 {
        Vec3::from_array(
            self.channels
                .each_ref()
                .map(|c| c.data.get(v).copied().unwrap_or(0.0)),
        )
    }

    /// Bytes it holds.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.channels
            .iter()
            .map(|c| c.data.len() as u64 * 4)
            .sum::<u64>()
            + self.occupancy.bytes()
    }
}
