//! Where the smoke is not: a distance field over blocks of voxels, so that texel rays jump over
//! empty space instead of adding up zeros (the maps come out bit for bit the same: a skipped
//! sample would have added exactly 0).

use lgh_core::glam::Vec3;

use crate::grid::DenseGrid;

/// Voxels per block side.
const BLOCK: usize = 4;

/// The Chebyshev distance, in blocks of [`BLOCK`]³ voxels, from every block to the nearest block
/// holding a voxel with a non-zero density (0 for such a block; capped at 255).
#[derive(Clone, Debug)]
pub struct EmptySpace {
    distance: Vec<u8>,
    dims: [usize; 3],
    /// World position of block `(0, 0, 0)`'s low corner (the density's low face).
    corner: Vec3,
    /// Block side, world units, and its inverse.
    block: f32,
    inv_block: f32,
}

impl EmptySpace {
    /// The field of `density` (only values of exactly 0 are empty, so that whatever the input,
    /// a jump skips only samples that would read zeros).
    #[must_use]
    pub fn new(density: &DenseGrid) -> Self {
        let dims = density.dims.map(|n| n.div_ceil(BLOCK).max(1));
        let [bx, by, _] = dims;
        // 0 where a block holds smoke, "infinitely far" elsewhere.
        let mut d = vec![u16::MAX; dims.iter().product()];
        let [nx, ny, _] = density.dims;
        for (idx, &v) in density.data.iter().enumerate() {
            if v != 0.0 {
                let (i, j, k) = (idx % nx, (idx / nx) % ny, idx / (nx * ny));
                d[(k / BLOCK * by + j / BLOCK) * bx + i / BLOCK] = 0;
            }
        }
        // The L∞ distance transform is separable (max is associative): along each axis in turn,
        // d(x) = min over y on x's line of max(|x − y|, d(y)).
        let strides = [1, bx, bx * by];
        for axis in 0..3 {
            let n = dims[axis];
            let mut line = vec![0u16; n];
            for base in 0..d.len() {
                if (base / strides[axis]) % n != 0 {
                    continue; // not the first block of its line
                }
                for (t, l) in line.iter_mut().enumerate() {
                    *l = d[base + t * strides[axis]];
                }
                for x in 0..n {
                    let best = (0..n)
                        .map(|y| (x.abs_diff(y) as u16).max(line[y]))
                        .min()
                        .unwrap_or(u16::MAX);
                    d[base + x * strides[axis]] = best;
                }
            }
        }
        let block = density.voxel_size * BLOCK as f32;
        EmptySpace {
            distance: d.into_iter().map(|v| v.min(255) as u8).collect(),
            dims,
            corner: density.origin - Vec3::splat(0.5 * density.voxel_size),
            block,
            inv_block: 1.0 / block,
        }
    }

    /// The side of a block, world units.
    #[must_use]
    pub fn block(&self) -> f32 {
        self.block
    }

    /// A distance around `x` (world units, ≥ 0) within which, in every direction, every voxel
    /// centre is empty: `(D − 1)` blocks for a block `D` blocks from the smoke (0 in or next to
    /// smoke, and for points outside the grid's blocks).
    #[inline]
    #[must_use]
    pub fn clearance(&self, x: Vec3) -> f32 {
        let u = (x - self.corner) * self.inv_block;
        if !(u.cmpge(Vec3::ZERO).all()) {
            return 0.0;
        }
        let [i, j, k] = [u.x as usize, u.y as usize, u.z as usize];
        let [bx, by, bz] = self.dims;
        if i >= bx || j >= by || k >= bz {
            return 0.0;
        }
        let d = self.distance[(k * by + j) * bx + i];
        f32::from(d.saturating_sub(1)) * self.block
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clearance_never_reaches_a_voxel_with_smoke() {
        // Sparse smoke in an uneven grid; from random points, no voxel with density lies within
        // the clearance (L∞, hence Euclidean too), and far from the smoke it is not zero.
        let mut g = DenseGrid::zeros([37, 21, 30], 0.1, Vec3::new(1.0, -2.0, 0.5));
        let mut rng = lgh_core::random::SplitMix64(4);
        let mut smoke = Vec::new();
        for _ in 0..6 {
            let [i, j, k] = [37, 21, 30].map(|n| (rng.next_f32() * n as f32) as usize % n);
            let idx = g.index(i, j, k);
            g.data[idx] = 1.0;
            smoke.push(g.centre(i, j, k));
        }
        let e = EmptySpace::new(&g);
        let (lo, hi) = g.bounds();
        let mut open = 0;
        for _ in 0..5000 {
            let x = rng.next_in(lo, hi);
            let c = e.clearance(x);
            for s in &smoke {
                assert!((*s - x).abs().max_element() > c, "{x}: {c} reaches {s}");
            }
            open += usize::from(c > 0.0);
        }
        assert!(open > 500, "{open}");
        // Outside the grid: no claim.
        assert_eq!(e.clearance(lo - Vec3::ONE), 0.0);
    }
}
