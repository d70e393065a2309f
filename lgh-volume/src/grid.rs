//! Dense voxel grids in world space: what the renderer samples.

use lgh_core::glam::Vec3;

use crate::error::ReadError;
use crate::vdb;

/// A dense scalar grid: `dims` voxels of edge `voxel_size`; voxel `(0, 0, 0)` has its centre at
/// `origin` (world space). Values are stored x fastest, then y, then z.
#[derive(Clone, Debug, PartialEq)]
pub struct DenseGrid {
    /// Voxels per axis.
    pub dims: [usize; 3],
    /// Voxel edge length `h` (world units).
    pub voxel_size: f32,
    /// World position of the centre of voxel `(0, 0, 0)`.
    pub origin: Vec3,
    /// `dims[0] · dims[1] · dims[2]` values.
    pub data: Vec<f32>,
}

impl DenseGrid {
    /// A grid of zeros.
    #[must_use]
    pub fn zeros(dims: [usize; 3], voxel_size: f32, origin: Vec3) -> Self {
        DenseGrid {
            dims,
            voxel_size,
            origin,
            data: vec![0.0; dims[0] * dims[1] * dims[2]],
        }
    }

    /// Linear index of voxel `(i, j, k)`.
    #[inline]
    #[must_use]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.dims[1] + j) * self.dims[0] + i
    }

    /// The voxel `[i, j, k]` at linear index `idx`: [`index`](Self::index)'s inverse.
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let grid = DenseGrid::zeros([4, 3, 2], 1.0, Vec3::ZERO);
    /// assert_eq!(grid.voxel(grid.index(3, 1, 1)), [3, 1, 1]);
    /// ```
    #[inline]
    #[must_use]
    pub fn voxel(&self, idx: usize) -> [usize; 3] {
        unflatten(idx, self.dims)
    }

    /// Value of voxel `(i, j, k)`.
    #[inline]
    #[must_use]
    pub fn get(&self, i: usize, j: usize, k: usize) -> f32 {
        self.data[self.index(i, j, k)]
    }

    /// World position of the centre of voxel `(i, j, k)`.
    #[inline]
    #[must_use]
    pub fn centre(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.origin + Vec3::new(i as f32, j as f32, k as f32) * self.voxel_size
    }

    /// Whether `other` has this grid's layout (dimensions, voxel size, origin): grids whose
    /// voxels are the same places, as a sequence's frames and a frame's grids must be.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::DenseGrid;
    ///
    /// let a = DenseGrid::zeros([2, 3, 4], 0.5, Vec3::ZERO);
    /// assert!(a.same_layout(&DenseGrid::zeros([2, 3, 4], 0.5, Vec3::ZERO)));
    /// assert!(!a.same_layout(&DenseGrid::zeros([2, 3, 4], 0.5, Vec3::X)));
    /// ```
    #[must_use]
    pub fn same_layout(&self, other: &DenseGrid) -> bool {
        self.dims == other.dims
            && self.voxel_size == other.voxel_size
            && self.origin == other.origin
    }

    /// World-space box covered by the voxels (their outer faces).
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let half = Vec3::splat(0.5 * self.voxel_size);
        let d = Vec3::new(
            self.dims[0] as f32,
            self.dims[1] as f32,
            self.dims[2] as f32,
        );
        (self.origin - half, self.origin - half + d * self.voxel_size)
    }

    /// World-space box of the voxels with a value above zero (their outer faces), or `None` when
    /// there are none: what a camera should frame.
    #[must_use]
    pub fn active_bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut lo = [usize::MAX; 3];
        let mut hi = [0usize; 3];
        for (idx, _) in self.data.iter().enumerate().filter(|(_, &v)| v > 0.0) {
            let c = unflatten(idx, self.dims);
            for a in 0..3 {
                lo[a] = lo[a].min(c[a]);
                hi[a] = hi[a].max(c[a]);
            }
        }
        if lo[0] == usize::MAX {
            return None;
        }
        let half = Vec3::splat(0.5 * self.voxel_size);
        Some((
            self.centre(lo[0], lo[1], lo[2]) - half,
            self.centre(hi[0], hi[1], hi[2]) + half,
        ))
    }

    /// Trilinear interpolation between voxel centres at world position `p`. Inside the grid's
    /// [`bounds`](Self::bounds) the half voxel beyond the outermost centres takes their values
    /// (each voxel fills its cell, so a uniform grid is uniform up to its faces); outside, zero.
    #[must_use]
    pub fn sample(&self, p: Vec3) -> f32 {
        self.local(p).map_or(0.0, |u| self.sample_voxel(u))
    }

    /// `p` in voxel units from the centre of voxel `(0, 0, 0)`, if it is inside the grid's
    /// [`bounds`](Self::bounds) (where [`sample`](Self::sample) interpolates).
    #[inline]
    fn local(&self, p: Vec3) -> Option<Vec3> {
        let u = (p - self.origin) / self.voxel_size;
        let n = Vec3::new(
            self.dims[0] as f32,
            self.dims[1] as f32,
            self.dims[2] as f32,
        );
        (u.cmpge(Vec3::splat(-0.5)).all() && u.cmplt(n - 0.5).all()).then_some(u)
    }

    /// The cell of the interpolation at `u` (voxel units, clamped to the outermost centres):
    /// its first voxel's linear index, the steps to the next voxel along x, y and z (0 at the
    /// last one, which holds its value to the face) and the weights along each axis.
    #[inline]
    fn cell(&self, u: Vec3) -> (usize, [usize; 3], Vec3) {
        let [nx, ny, nz] = self.dims;
        let max = Vec3::new((nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32);
        let t = u.clamp(Vec3::ZERO, max);
        // t ≥ 0, so truncation is the floor (and avoids a libm call per axis on baseline x86-64).
        let (i, j, k) = (t.x as usize, t.y as usize, t.z as usize);
        let w = t - Vec3::new(i as f32, j as f32, k as f32);
        let di = usize::from(i + 1 < nx);
        let dj = if j + 1 < ny { nx } else { 0 };
        let dk = if k + 1 < nz { nx * ny } else { 0 };
        ((k * ny + j) * nx + i, [di, dj, dk], w)
    }

    /// The eight voxels [`sample`](Self::sample) interpolates at `p` and their weights (summing
    /// to 1), or `None` outside the grid (where it gives 0): for interpolating something of the
    /// voxels' values rather than the values themselves.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::DenseGrid;
    ///
    /// let mut g = DenseGrid::zeros([2, 2, 2], 1.0, Vec3::ZERO);
    /// g.data = (0..8).map(|v| v as f32).collect();
    /// let p = Vec3::new(0.25, 0.5, 0.75);
    /// let (idx, w) = g.corners(p).unwrap();
    /// let by_corners: f32 = (0..8).map(|c| g.data[idx[c]] * w[c]).sum();
    /// assert!((by_corners - g.sample(p)).abs() < 1e-6);
    /// assert!(g.corners(Vec3::splat(5.0)).is_none());
    /// ```
    #[must_use]
    pub fn corners(&self, p: Vec3) -> Option<([usize; 8], [f32; 8])> {
        let (b, [di, dj, dk], w) = self.cell(self.local(p)?);
        let (mut idx, mut weight) = ([0usize; 8], [0f32; 8]);
        let along = |bit: usize, f: f32| if bit == 1 { f } else { 1.0 - f };
        for c in 0..8 {
            let (a, e, f) = (c & 1, (c >> 1) & 1, c >> 2);
            idx[c] = b + a * di + e * dj + f * dk;
            weight[c] = along(a, w.x) * along(e, w.y) * along(f, w.z);
        }
        Some((idx, weight))
    }

    /// Trilinear interpolation at `u`, in voxel units from the centre of voxel `(0, 0, 0)`,
    /// clamped to the outermost centres: [`sample`](Self::sample) without its bounds test, for
    /// callers that clipped their ray to the grid's bounds already.
    #[inline]
    #[must_use]
    pub fn sample_voxel(&self, u: Vec3) -> f32 {
        let (b, [di, dj, dk], w) = self.cell(u);
        trilinear(&self.data[b..], di, dj, dk, w)
    }

    /// The active values of a scalar VDB grid over the index box `lo..=hi`, as a dense grid in
    /// world space (voxel centres at `index_to_world · index`; only axis-aligned uniform-scale
    /// transforms). Inactive voxels are zero; vector grids give their length.
    pub fn from_vdb(grid: &vdb::Grid, lo: [i32; 3], hi: [i32; 3]) -> Result<Self, ReadError> {
        let origin = DenseGrid::world_position(&grid.index_to_world, lo);
        DenseGrid::from_vdb_at(grid, lo, hi, origin)
    }

    /// World position of index-space voxel `p` under an axis-aligned index-to-world matrix.
    pub(crate) fn world_position(m: &[[f64; 4]; 4], p: [i32; 3]) -> Vec3 {
        Vec3::from([0, 1, 2].map(|a| (m[a][a] * f64::from(p[a]) + m[a][3]) as f32))
    }

    /// [`from_vdb`](Self::from_vdb), with voxel `lo`'s centre placed at `origin`.
    pub(crate) fn from_vdb_at(
        grid: &vdb::Grid,
        lo: [i32; 3],
        hi: [i32; 3],
        origin: Vec3,
    ) -> Result<Self, ReadError> {
        DenseGrid::from_vdb_with(grid, lo, hi, origin, |v| vdb::Grid::scalar(v) as f32)
    }

    /// Component `c` of a vector VDB grid (`c` = 0, 1, 2 for x, y, z: a vec3 emission's red,
    /// green and blue), placed as [`from_vdb_at`](Self::from_vdb_at) places it.
    pub(crate) fn component_from_vdb_at(
        grid: &vdb::Grid,
        c: usize,
        lo: [i32; 3],
        hi: [i32; 3],
        origin: Vec3,
    ) -> Result<Self, ReadError> {
        DenseGrid::from_vdb_with(grid, lo, hi, origin, |v| v[c.min(v.len() - 1)])
    }

    /// The grid of `value(voxel's components)` over the index box `lo..=hi`, voxel `lo`'s
    /// centre at `origin`.
    fn from_vdb_with(
        grid: &vdb::Grid,
        lo: [i32; 3],
        hi: [i32; 3],
        origin: Vec3,
        value: impl Fn(&[f32]) -> f32,
    ) -> Result<Self, ReadError> {
        let m = grid.index_to_world;
        let h = grid.voxel_size[0];
        let uniform = (grid.voxel_size[1] - h).abs() <= 1e-9 * h
            && (grid.voxel_size[2] - h).abs() <= 1e-9 * h;
        let axis_aligned = m[0][1] == 0.0
            && m[0][2] == 0.0
            && m[1][0] == 0.0
            && m[1][2] == 0.0
            && m[2][0] == 0.0
            && m[2][1] == 0.0;
        if !(uniform && axis_aligned) {
            return Err(ReadError::UnsupportedTransform {
                grid: grid.name.clone(),
            });
        }
        let dims = [0, 1, 2].map(|a| (hi[a] as i64 - lo[a] as i64 + 1).max(0) as usize);
        if dims
            .iter()
            .try_fold(1usize, |a, &d| a.checked_mul(d))
            .is_none_or(|v| v > MAX_DENSE_VOXELS)
        {
            return Err(ReadError::TooManyVoxels {
                max: MAX_DENSE_VOXELS,
                grid: Some(grid.name.clone()),
                dims: Some(dims),
            });
        }
        let mut out = DenseGrid::zeros(dims, h as f32, origin);
        let c = grid.components();
        let scalar = value;
        let inside = |p: [i32; 3]| (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]);
        for leaf in &grid.leaves {
            for (i, p) in leaf.active_voxels().filter(|&(_, p)| inside(p)) {
                let idx = out.index(
                    (p[0] - lo[0]) as usize,
                    (p[1] - lo[1]) as usize,
                    (p[2] - lo[2]) as usize,
                );
                out.data[idx] = scalar(&leaf.values[i * c..(i + 1) * c]);
            }
        }
        for t in grid.tiles.iter().filter(|t| t.active) {
            let v = scalar(&t.value[..c]);
            let e = t.edge as i32;
            for z in t.origin[2].max(lo[2])..(t.origin[2] + e).min(hi[2] + 1) {
                for y in t.origin[1].max(lo[1])..(t.origin[1] + e).min(hi[1] + 1) {
                    for x in t.origin[0].max(lo[0])..(t.origin[0] + e).min(hi[0] + 1) {
                        let idx = out.index(
                            (x - lo[0]) as usize,
                            (y - lo[1]) as usize,
                            (z - lo[2]) as usize,
                        );
                        out.data[idx] = v;
                    }
                }
            }
        }
        Ok(out)
    }
}

/// Largest grid made dense from a sparse one (voxels): 2²⁸, 1 GiB per f32 grid.
pub const MAX_DENSE_VOXELS: usize = 1 << 28;

/// The voxel `[i, j, k]` at linear index `idx` (x fastest) of a grid of `dims` voxels.
pub(crate) fn unflatten(idx: usize, dims: [usize; 3]) -> [usize; 3] {
    [
        idx % dims[0],
        (idx / dims[0]) % dims[1],
        idx / (dims[0] * dims[1]),
    ]
}

/// Parameter interval `(t0, t1)`, `0 ≤ t0 < t1`, where the ray `o + t d` (t ≥ 0) is inside the
/// box `lo..hi`, or `None` if it misses. An axis the ray runs parallel to must hold `o`
/// within `[lo, hi)`.
pub(crate) fn slab(o: Vec3, d: Vec3, lo: Vec3, hi: Vec3) -> Option<(f32, f32)> {
    let (mut t0, mut t1) = (0.0f32, f32::INFINITY);
    for a in 0..3 {
        if d[a] == 0.0 {
            if o[a] < lo[a] || o[a] >= hi[a] {
                return None;
            }
            continue;
        }
        let (u, v) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
        t0 = t0.max(u.min(v));
        t1 = t1.min(u.max(v));
    }
    (t0 < t1).then_some((t0, t1))
}

/// Trilinear interpolation with weights `w` between the eight values at offsets `0`, `di`, `dj`,
/// `dj + di`, `dk`, … of `c` (x, y and z neighbours; an offset of 0 repeats a border value).
#[inline(always)]
pub(crate) fn trilinear(c: &[f32], di: usize, dj: usize, dk: usize, w: Vec3) -> f32 {
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(c[0], c[di], w.x);
    let x10 = lerp(c[dj], c[dj + di], w.x);
    let x01 = lerp(c[dk], c[dk + di], w.x);
    let x11 = lerp(c[dk + dj], c[dk + dj + di], w.x);
    lerp(lerp(x00, x10, w.y), lerp(x01, x11, w.y), w.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trilinear_sampling_hits_voxel_centres_and_interpolates() {
        let mut g = DenseGrid::zeros([3, 3, 3], 0.5, Vec3::new(1.0, 2.0, 3.0));
        let i = g.index(1, 1, 1);
        g.data[i] = 8.0;
        assert_eq!(g.sample(g.centre(1, 1, 1)), 8.0);
        assert_eq!(g.sample(g.centre(0, 1, 1)), 0.0);
        assert!((g.sample(g.centre(1, 1, 1) + Vec3::new(0.25, 0.0, 0.0)) - 4.0).abs() < 1e-6);
        assert_eq!(g.sample(Vec3::splat(100.0)), 0.0);
        // A uniform grid is uniform up to its faces, and zero beyond.
        let u = DenseGrid {
            data: vec![2.0; 27],
            ..g.clone()
        };
        let (lo, hi) = u.bounds();
        assert_eq!(u.sample(lo), 2.0);
        assert_eq!(u.sample(hi - Vec3::splat(1e-4)), 2.0);
        assert_eq!(u.sample(lo - Vec3::splat(1e-4)), 0.0);
        let (lo, hi) = g.bounds();
        assert_eq!(lo, Vec3::new(0.75, 1.75, 2.75));
        assert_eq!(hi, Vec3::new(2.25, 3.25, 4.25));
    }
}
