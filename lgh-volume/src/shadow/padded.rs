//! The density laid out for rays: padded by one voxel of its border values, so a trilinear
//! lookup anywhere in its box reads eight neighbours without clamping, and stored in bricks of
//! [`BRICK`]³ cells, so that the eight neighbours and the next samples of a ray lie close in
//! memory.
//!
//! **Why bricks.** Shadow rays and texel rays cross the grid in every direction. Stored x
//! fastest, a lookup's eight values lie on four rows far apart (a z-neighbour is a whole slice
//! away: 289 KB on a 267³ grid), and every step of a ray that is not along x reads four new
//! cache lines and touches new pages: on the Fig. 8-class frame three quarters of the shadow
//! march's time was spent waiting on those gathers. In a brick the `(BRICK + 1)³` values of its
//! cells are stored together (x fastest within the brick), each brick holding its cells' far
//! faces as well (the first values of its neighbours, repeated), so a lookup's eight values are
//! in one brick, a few cache lines of it, and a ray's next few samples read the same brick. The repeated faces cost `(9/8)³ ≈ 1.42` times the memory of the padded grid.
//!
//! The values read and the arithmetic on them are those of the plain layout: a lookup is the
//! same bits whatever the layout.

use lgh_core::glam::{Vec3, Vec3A};

use super::ROUND;

/// log₂ of the cells per brick side.
pub(super) const BRICK_BITS: u32 = 3;
/// Cells per brick side.
pub(super) const BRICK: usize = 1 << BRICK_BITS;
/// Values per brick side: its cells and their far faces.
pub(super) const SIDE: usize = BRICK + 1;
/// Values per brick.
pub(super) const BRICK_VALUES: usize = SIDE * SIDE * SIDE;

/// A grid padded by one voxel on every side with its border values, in bricks of 8³
/// cells (module docs), so that a trilinear lookup anywhere in its box is a clamp-free read of
/// eight neighbours close together: what shadow rays and cube-map texel rays read.
#[derive(Clone, Debug)]
pub struct PaddedGrid {
    /// The bricks, x fastest, each [`BRICK_VALUES`] values, x fastest within.
    pub(super) data: Vec<f32>,
    /// Padded dimensions (the grid's plus 2), in values.
    dims: [usize; 3],
    /// Bricks per axis.
    bricks: [usize; 3],
    /// World position of the centre of padded voxel `(0, 0, 0)`.
    pub(super) origin: Vec3,
    pub(super) inv_voxel_size: f32,
}

/// Bricks per axis of a grid of `dims` voxels, padded: its `n + 1` cells per axis (each between
/// two of its `n + 2` padded values), [`BRICK`] to a brick.
fn bricks(dims: [usize; 3]) -> [usize; 3] {
    dims.map(|n| (n + 1).div_ceil(BRICK))
}

/// Offsets of a cell's eight corners from its first, in [`crate::grid::trilinear`]'s order.
pub(super) const CORNERS: [usize; 8] = [
    0,
    1,
    SIDE,
    SIDE + 1,
    SIDE * SIDE,
    SIDE * SIDE + 1,
    SIDE * SIDE + SIDE,
    SIDE * SIDE + SIDE + 1,
];

impl PaddedGrid {
    /// `g` padded and bricked (an empty grid stays empty).
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::shadow::PaddedGrid;
    ///
    /// let mut g = DenseGrid::zeros([20, 3, 2], 0.5, Vec3::ZERO);
    /// g.data[19] = 4.0; // voxel (19, 0, 0)
    /// let padded = PaddedGrid::new(&g);
    /// // Its bricks hold 22 × 5 × 4 padded values, in 3 × 1 × 1 bricks of 9³.
    /// assert_eq!(padded.bytes(), 3 * 729 * 4);
    /// // Half a voxel beyond the last centre the border value holds, as in the grid's lookup.
    /// let p = padded.local(Vec3::new(9.75, 0.0, 0.0));
    /// assert_eq!(padded.sample(p), 4.0);
    /// assert_eq!(padded.sample(p), g.sample_voxel(Vec3::new(19.5, 0.0, 0.0)));
    /// ```
    #[must_use]
    pub fn new(g: &crate::grid::DenseGrid) -> Self {
        let [nx, ny, nz] = g.dims;
        let dims = [nx + 2, ny + 2, nz + 2];
        let bricks = bricks(g.dims);
        // Padded index p maps to the clamped source index p − 1 (the border value repeats, as
        // the grid's own trilinear lookup clamps to its outermost centres); values beyond the
        // padded grid (the last bricks' unused faces) repeat it too.
        let src = |p: usize, n: usize| p.saturating_sub(1).min(n.saturating_sub(1));
        let mut data = Vec::new();
        if !g.data.is_empty() {
            data.reserve(bricks.iter().product::<usize>() * BRICK_VALUES);
            for bk in 0..bricks[2] {
                for bj in 0..bricks[1] {
                    for bi in 0..bricks[0] {
                        for k in bk * BRICK..=bk * BRICK + BRICK {
                            for j in bj * BRICK..=bj * BRICK + BRICK {
                                let row = (src(k, nz) * ny + src(j, ny)) * nx;
                                data.extend(
                                    (bi * BRICK..=bi * BRICK + BRICK)
                                        .map(|i| g.data[row + src(i, nx)]),
                                );
                            }
                        }
                    }
                }
            }
        }
        PaddedGrid {
            data,
            dims,
            bricks,
            origin: g.origin - Vec3::splat(g.voxel_size),
            inv_voxel_size: 1.0 / g.voxel_size,
        }
    }

    /// Bytes the bricks take.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.data.len() * 4
    }

    /// Bytes [`new`](Self::new) would take for a grid of `dims` voxels: what a memory budget
    /// counts before building one.
    #[must_use]
    pub fn bytes_for(dims: [usize; 3]) -> u64 {
        bricks(dims).iter().map(|&b| b as u64).product::<u64>() * BRICK_VALUES as u64 * 4
    }

    /// World position `x` in padded voxel units.
    #[inline(always)]
    #[must_use]
    pub fn local(&self, x: Vec3) -> Vec3A {
        Vec3A::from((x - self.origin) * self.inv_voxel_size)
    }

    /// Whether the grid holds no values.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The largest cell index per axis (cells `0..=last`), and the bricks per axis: what a
    /// lookup eight at a time needs to find a cell's first value.
    pub(super) fn layout(&self) -> ([usize; 3], [usize; 3]) {
        (self.dims.map(|n| n - 2), self.bricks)
    }

    /// Index of the first value of cell `(i, j, k)`, each clamped into the cells first (as the
    /// eight-abreast lookup clamps): whatever the indices, the cell's eight values are inside
    /// the data.
    #[inline(always)]
    fn first(&self, cell: [i32; 3]) -> usize {
        let [i, j, k] = [0, 1, 2].map(|a| cell[a].clamp(0, self.dims[a] as i32 - 2) as usize);
        let [bx, by, _] = self.bricks;
        let brick = ((k >> BRICK_BITS) * by + (j >> BRICK_BITS)) * bx + (i >> BRICK_BITS);
        let m = BRICK - 1;
        brick * BRICK_VALUES + ((k & m) * SIDE + (j & m)) * SIDE + (i & m)
    }

    /// Trilinear value at `p`, in padded voxel units, for `p` in the grid's box (padded
    /// `[0.5, n + 0.5]` per axis, `n` the grid's size) give or take rounding; outside it, the
    /// value of the nearest cell's lookup for finite `p` (clamped, never a read outside the
    /// grid; not a number for infinite or NaN `p`); zero for an empty grid.
    #[inline(always)]
    #[must_use]
    pub fn sample(&self, p: Vec3A) -> f32 {
        // floor(p) without a saturating float-to-integer conversion: adding 2^23 rounds p − ½
        // (exact) to the nearest integer, whose value sits in the float's low mantissa bits.
        // At an integer p the tie may round down to p − 1, with weight 1: the same value.
        let r = (p - Vec3A::splat(0.5)) + Vec3A::splat(ROUND);
        let w = p - (r - Vec3A::splat(ROUND));
        let cell = r
            .to_array()
            .map(|v| v.to_bits().wrapping_sub(ROUND.to_bits()) as i32);
        debug_assert!(
            cell.iter()
                .zip(self.dims)
                .all(|(&c, n)| (0..n as i32 - 1).contains(&c)),
            "sample outside the padded grid: {p}"
        );
        match self
            .data
            .get(self.first(cell)..)
            .filter(|c| c.len() > CORNERS[7])
        {
            Some(c) => crate::grid::trilinear(c, 1, SIDE, SIDE * SIDE, w.into()),
            None => 0.0, // an empty grid
        }
    }
}
