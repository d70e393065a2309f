//! The smoke in each voxel light's own voxel: what sets the escape of its light
//! (`lgh_core::near_field::escape`).
//!
//! A voxel light's light leaves its voxel through that voxel's smoke, and a shadow ray to its
//! centre attenuates all of it as if it came from the centre: the escape `R(u, τ)` corrects
//! that for a uniform voxel in uniform smoke of `τ` optical depths a voxel. The `τ` that
//! matters is the light's own voxel's, `σ_t(c) h` at its centre `c`: where the smoke varies
//! from voxel to voxel, the shading point's extinction is another voxel's, and a point in dense
//! soot lit by a light in clear air took the dense voxel's escape — up to 3× at 4.7 optical
//! depths a voxel (the demo's soot at 32³), which made each depth of scattered light brighter
//! than the one before. [`VoxelSmoke`] holds `τ` at every voxel centre of the lights' grid, so
//! that a light is shaded with its own voxel's, or the point's where that is thinner
//! (`Lights::with_smoke`).

use lgh_core::glam::Vec3;

use crate::grid::DenseGrid;
use crate::medium::Medium;

/// `τ = σ_t h` at the centre of every voxel of a light grid (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelSmoke {
    /// The optical depth a voxel at each centre, on the lights' layout.
    depth: DenseGrid,
}

impl VoxelSmoke {
    /// The smoke of `density` (on any layout, sampled trilinearly) at the centres of `layout`'s
    /// voxels (its values are not read), in optical depths of one of `layout`'s voxels.
    ///
    /// ```
    /// use lgh_volume::grid::DenseGrid;
    /// use lgh_volume::voxel_smoke::VoxelSmoke;
    /// use lgh_volume::Medium;
    /// use lgh_volume::lgh_core::glam::Vec3;
    ///
    /// let mut density = DenseGrid::zeros([4, 4, 4], 0.5, Vec3::ZERO);
    /// let at = density.index(1, 2, 3);
    /// density.data[at] = 2.0;
    /// let medium = Medium::new(1.0, 3.0, 1e-4, 1000.0)?; // σ_t = 4 ρ
    /// let smoke = VoxelSmoke::of(&density, &density, &medium);
    /// assert_eq!(smoke.at(density.centre(1, 2, 3)), 4.0); // 4 · 2 · 0.5
    /// assert_eq!(smoke.at(density.centre(0, 0, 0)), 0.0);
    /// assert_eq!(smoke.at(Vec3::splat(-9.0)), 0.0); // outside: clear air
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn of(layout: &DenseGrid, density: &DenseGrid, medium: &Medium) -> Self {
        let h = layout.voxel_size;
        let [nx, ny, nz] = layout.dims;
        let data = if density.same_layout(layout) {
            density
                .data
                .iter()
                .map(|&rho| medium.extinction(rho) * h)
                .collect()
        } else {
            (0..nx * ny * nz)
                .map(|v| {
                    let (i, j, k) = (v % nx, (v / nx) % ny, v / (nx * ny));
                    medium.extinction(density.sample(layout.centre(i, j, k))) * h
                })
                .collect()
        };
        let depth = DenseGrid {
            dims: layout.dims,
            voxel_size: h,
            origin: layout.origin,
            data,
        };
        VoxelSmoke { depth }
    }

    /// `τ` of the voxel whose cell holds `p` (a light's position: its voxel's centre); 0
    /// outside the grid.
    #[inline]
    #[must_use]
    pub fn at(&self, p: Vec3) -> f32 {
        let g = &self.depth;
        let u = ((p - g.origin) / g.voxel_size).round();
        let [nx, ny, nz] = g.dims;
        if !(u.cmpge(Vec3::ZERO).all() && u.cmplt(Vec3::new(nx as f32, ny as f32, nz as f32)).all())
        {
            return 0.0;
        }
        let (i, j, k) = (u.x as usize, u.y as usize, u.z as usize);
        g.data[(k * ny + j) * nx + i]
    }

    /// Whether this is the smoke of lights on `grid`'s layout.
    #[must_use]
    pub fn on_layout(&self, grid: &DenseGrid) -> bool {
        self.depth.same_layout(grid)
    }
}
