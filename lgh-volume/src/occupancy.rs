//! Empty space: the bricks of a volume's box where a march sample can find nothing.
//!
//! The camera's march (eq. 7's integral of the emission and the in-scattered light,
//! [`crate::render`]) steps through the whole box of the density grid, but the smoke of an
//! explosion fills a ball in it: on the Fig. 8-class frame most of a ray's samples find zero
//! density and zero emission, yet each paid three trilinear lookups and two blackbody
//! evaluations. A sample where every grid it interpolates is zero adds nothing (`σ_t = 0`, so
//! its transmittance factor `e^{−0·dt}` is exactly 1 and its source exactly 0), so skipping it
//! leaves the image the same bits.
//!
//! [`Occupancy`] splits the density's box into bricks of [`BRICK`]³ voxels and marks a brick
//! *occupied* when any voxel that a sample inside it could read is non-zero: each non-zero voxel
//! of a grid marks every brick that overlaps the box of half-width `h_g + reach` around its
//! centre (`h_g` that grid's voxel: trilinear interpolation reads voxels less than a voxel
//! away along each axis, and the outermost ones up to half a voxel past the grid's last
//! centres; `reach` how far from the sample the march reads, its two-point Gauss nodes).
//! What a voxel's value "non-zero" means is the caller's: density `≠ 0`, a temperature that
//! emits, any colour channel; NaN counts as non-zero. (The march also keeps every sample once
//! its transmittance is not finite, and skips none along a ray whose direction is not of unit
//! length, whose Gauss nodes would reach farther.)

use lgh_core::glam::Vec3;

use crate::grid::DenseGrid;

/// Voxels of the density grid along a brick's edge.
pub const BRICK: usize = 8;

/// Which bricks of a box are occupied (module docs).
#[derive(Clone, Debug)]
pub struct Occupancy {
    /// The box's lowest corner (world).
    corner: Vec3,
    /// A brick's edge (world) and its inverse.
    size: f32,
    inv_size: f32,
    /// Bricks per axis.
    bricks: [usize; 3],
    /// One flag a brick, x fastest.
    occupied: Vec<bool>,
}

impl Occupancy {
    /// No brick occupied, over the box of `grid` (its [`bounds`](DenseGrid::bounds)) in bricks of
    /// [`BRICK`]³ of its voxels.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::{occupancy::Occupancy, DenseGrid};
    ///
    /// let grid = DenseGrid::zeros([20, 8, 8], 1.0, Vec3::ZERO);
    /// let none = Occupancy::empty(&grid);
    /// assert_eq!(none.bricks(), [3, 1, 1]);
    /// assert!(none.is_empty_at(Vec3::splat(3.0)));
    /// ```
    #[must_use]
    pub fn empty(grid: &DenseGrid) -> Self {
        let (lo, _) = grid.bounds();
        let size = BRICK as f32 * grid.voxel_size;
        let bricks = grid.dims.map(|n| n.div_ceil(BRICK).max(1));
        Occupancy {
            corner: lo,
            size,
            inv_size: 1.0 / size,
            bricks,
            occupied: vec![false; bricks.iter().product()],
        }
    }

    /// Bricks per axis.
    #[must_use]
    pub fn bricks(&self) -> [usize; 3] {
        self.bricks
    }

    /// The share of bricks occupied, in [0, 1].
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::{occupancy::Occupancy, DenseGrid};
    ///
    /// let mut grid = DenseGrid::zeros([32, 32, 32], 1.0, Vec3::ZERO);
    /// *grid.data.last_mut().unwrap() = 1.0; // one voxel in a corner
    /// let mut occupancy = Occupancy::empty(&grid);
    /// occupancy.mark(&grid, |v| v != 0.0, 0.0);
    /// assert_eq!(occupancy.occupied_share(), 1.0 / 64.0);
    /// ```
    #[must_use]
    pub fn occupied_share(&self) -> f32 {
        let n = self.occupied.iter().filter(|&&o| o).count();
        n as f32 / self.occupied.len() as f32
    }

    /// Marks the bricks that `grid`'s voxels with `nonzero(value)` reach: those overlapping the
    /// box of half-width `grid.voxel_size + reach` (world) around the voxel's centre. `grid` may
    /// have any layout; a voxel beyond the box marks nothing.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::{occupancy::Occupancy, DenseGrid};
    ///
    /// let mut grid = DenseGrid::zeros([24, 8, 8], 1.0, Vec3::ZERO);
    /// let at = grid.index(12, 4, 4);
    /// grid.data[at] = 2.0; // in the middle brick
    /// let mut occupancy = Occupancy::empty(&grid);
    /// occupancy.mark(&grid, |v| v > 1.0, 0.0);
    /// assert!(!occupancy.is_empty_at(Vec3::new(12.0, 4.0, 4.0)));
    /// assert!(occupancy.is_empty_at(Vec3::new(2.0, 4.0, 4.0)));
    /// // A voxel near a brick's face reaches into the brick beside it.
    /// let at = grid.index(8, 4, 4);
    /// grid.data[at] = 2.0; // brick 1 (voxels 8 to 15)
    /// occupancy.mark(&grid, |v| v > 1.0, 0.0);
    /// assert!(!occupancy.is_empty_at(Vec3::new(2.0, 4.0, 4.0)));
    /// ```
    pub fn mark(&mut self, grid: &DenseGrid, nonzero: impl Fn(f32) -> bool, reach: f32) {
        // A little more than the reach, so that rounding in the sample's position never puts a
        // read voxel's brick outside the marked ones.
        let half = (grid.voxel_size + reach) * (1.0 + 1e-3) + 1e-3 * self.size;
        let last = self.bricks.map(|n| n as i64 - 1);
        let [nx, ny, nz] = grid.dims;
        // Neighbouring voxels mostly mark the same bricks: the last range marked is skipped.
        let mut marked = None;
        for k in 0..nz {
            for j in 0..ny {
                let row = &grid.data[grid.index(0, j, k)..][..nx];
                for (i, _) in row.iter().enumerate().filter(|&(_, &v)| nonzero(v)) {
                    let c = grid.centre(i, j, k);
                    let lo = self.brick_of(c - Vec3::splat(half));
                    let hi = self.brick_of(c + Vec3::splat(half));
                    if marked == Some((lo, hi)) || (0..3).any(|a| hi[a] < 0 || lo[a] > last[a]) {
                        continue;
                    }
                    marked = Some((lo, hi));
                    let lo = [0, 1, 2].map(|a| lo[a].max(0) as usize);
                    let hi = [0, 1, 2].map(|a| hi[a].min(last[a]) as usize);
                    for z in lo[2]..=hi[2] {
                        for y in lo[1]..=hi[1] {
                            let row = (z * self.bricks[1] + y) * self.bricks[0];
                            self.occupied[row + lo[0]..=row + hi[0]].fill(true);
                        }
                    }
                }
            }
        }
    }

    /// Bytes it holds.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.occupied.len() as u64
    }

    /// The brick holding world position `x`, unclamped.
    #[inline]
    fn brick_of(&self, x: Vec3) -> [i64; 3] {
        let b = ((x - self.corner) * self.inv_size).floor();
        [b.x as i64, b.y as i64, b.z as i64]
    }

    /// Whether `x` lies in a brick that nothing marked (outside the box: the nearest brick's
    /// answer; a NaN position is never empty).
    #[inline]
    #[must_use]
    pub fn is_empty_at(&self, x: Vec3) -> bool {
        let b = (x - self.corner) * self.inv_size;
        if b.is_nan() {
            return false;
        }
        let at = |a: usize| (b[a].max(0.0) as usize).min(self.bricks[a] - 1);
        let idx = (at(2) * self.bricks[1] + at(1)) * self.bricks[0] + at(0);
        !self.occupied[idx]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point of a brick that nothing marked reads zero from the grid at any offset up to
    /// the reach: checked on a grid of random sparse voxels, at random points and offsets.
    #[test]
    fn an_empty_brick_reads_zero_within_the_reach() {
        let mut grid = DenseGrid::zeros([37, 29, 23], 0.25, Vec3::new(-1.0, 0.5, 2.0));
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..12 {
            let last = grid.data.len() - 1;
            let i = ((next() * last as f32) as usize).min(last);
            grid.data[i] = 1.0 + next();
        }
        let reach = 0.6 * grid.voxel_size;
        let mut occupancy = Occupancy::empty(&grid);
        occupancy.mark(&grid, |v| v != 0.0, reach);
        let (lo, hi) = grid.bounds();
        let (mut empty, mut checked) = (0, 0);
        for _ in 0..200_000 {
            let x = lo + (hi - lo) * Vec3::new(next(), next(), next());
            let d = (Vec3::new(next(), next(), next()) * 2.0 - 1.0) * reach;
            checked += 1;
            if occupancy.is_empty_at(x) {
                empty += 1;
                assert_eq!(grid.sample(x + d), 0.0, "{x} {d}");
            }
        }
        // The test tests something: most of the box is empty with 12 voxels in it.
        assert!(empty > checked / 2, "{empty} of {checked}");
    }

    #[test]
    fn a_grid_of_another_layout_marks_the_bricks_it_reaches() {
        let density = DenseGrid::zeros([32, 8, 8], 1.0, Vec3::ZERO);
        // A coarser grid shifted by 20 voxels along x: its one hot voxel's centre is at x = 24.
        let mut hot = DenseGrid::zeros([4, 4, 4], 2.0, Vec3::new(20.0, 0.0, 0.0));
        let at = hot.index(2, 1, 1);
        hot.data[at] = 5.0;
        let mut occupancy = Occupancy::empty(&density);
        occupancy.mark(&hot, |v| v > 0.0, 0.0);
        // Reaches x in (22, 26): brick 2 (15.5..23.5) and brick 3 (23.5..31.5), the bricks
        // counted from the box's face at −0.5.
        assert!(!occupancy.is_empty_at(Vec3::new(23.0, 2.0, 2.0)));
        assert!(!occupancy.is_empty_at(Vec3::new(25.0, 2.0, 2.0)));
        assert!(occupancy.is_empty_at(Vec3::new(10.0, 2.0, 2.0)));
    }

    #[test]
    fn nan_values_and_positions_are_never_empty() {
        let mut grid = DenseGrid::zeros([16, 8, 8], 1.0, Vec3::ZERO);
        grid.data[0] = f32::NAN;
        let mut occupancy = Occupancy::empty(&grid);
        occupancy.mark(&grid, |v| v != 0.0, 0.0);
        assert!(!occupancy.is_empty_at(Vec3::ZERO));
        assert!(occupancy.is_empty_at(Vec3::new(12.0, 4.0, 4.0)));
        assert!(!occupancy.is_empty_at(Vec3::NAN));
    }
}
