//! Where the GPU's grids sit: the origin, the level-1 spacing `h1`, and how many Morton bits a
//! side. The build (`build.wgsl`) numbers cells and vertices by Morton code on a cube of
//! `2^bits` level-1 cells a side, so a level-ℓ cell is one run of level-1 cells; the top level
//! is `ℓ = bits − 1`, of 4 cells a side, and the lights keep out of the last quarter of the
//! cube so that every vertex of every level has a number in it.

use lgh_core::glam::Vec3;
use lgh_core::{GridSettings, PointLight};

use crate::error::GpuError;

/// The GPU's grids for lights within a box: origin, level-1 spacing and Morton bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuGrid {
    /// The low corner of level-1 cell (0, 0, 0).
    pub origin: Vec3,
    /// The level-1 spacing `h1`.
    pub h1: f32,
    /// Level-1 cells a side: `2^bits` (at most 2^[`MAX_BITS`](GpuGrid::MAX_BITS)).
    pub bits: u8,
}

impl GpuGrid {
    /// The most Morton bits a side: 256³ level-1 cells (64 MiB of cell starts).
    pub const MAX_BITS: u8 = 8;

    /// The grid over the box `lo..=hi` with level-1 spacing `h1`: the fewest bits whose cube
    /// holds the box in its first three quarters a side. Errors where the box is more than
    /// 192 cells of `h1` across ([`GpuError::TooManyCells`]: a larger `h1` fits), or where the
    /// box or `h1` is not finite and positive.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_gpu::GpuGrid;
    ///
    /// let grid = GpuGrid::enclosing(Vec3::ZERO, Vec3::splat(10.0), 0.5)?;
    /// assert_eq!(grid.bits, 5); // 21 cells across: 24 = three quarters of 32
    /// assert_eq!(grid.max_level(), 4);
    /// assert!(GpuGrid::enclosing(Vec3::ZERO, Vec3::splat(1000.0), 0.5).is_err());
    /// # Ok::<(), lgh_gpu::GpuError>(())
    /// ```
    pub fn enclosing(lo: Vec3, hi: Vec3, h1: f32) -> Result<GpuGrid, GpuError> {
        if !(lo.is_finite() && hi.is_finite() && h1.is_finite() && h1 > 0.0) {
            return Err(GpuError::InvalidGrid);
        }
        let across = ((hi - lo).max_element().max(0.0) / h1).floor() as f64 + 1.0;
        let mut bits = 2u8;
        while ((3u64 << (bits - 2)) as f64) < across {
            if bits == Self::MAX_BITS {
                let most = 3u64 << (Self::MAX_BITS - 2);
                return Err(GpuError::TooManyCells {
                    level: 1,
                    cells: across as u64,
                    most,
                });
            }
            bits += 1;
        }
        Ok(GpuGrid {
            origin: lo,
            h1,
            bits,
        })
    }

    /// The grid over `lights` with level-1 cells about as many as the lights where they fill
    /// their box (the cube root of the box's volume a light, at least 1/192 of its width): a
    /// default for [`GpuBuilder`](crate::GpuBuilder). Errors on no lights or a non-finite one.
    pub fn fitting(lights: &[PointLight]) -> Result<GpuGrid, GpuError> {
        let (lo, hi) = lgh_core::bounds(lights);
        let extent = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
        let width = extent.max_element();
        let per_light =
            (extent.x as f64 * extent.y as f64 * extent.z as f64) / lights.len().max(1) as f64;
        let h1 = (per_light.cbrt() as f32).max(width / 190.0);
        let h1 = if h1 > 0.0 && h1.is_finite() { h1 } else { 1.0 };
        Self::enclosing(lo, hi, h1)
    }

    /// The top level, `bits − 1`.
    #[must_use]
    pub fn max_level(&self) -> u8 {
        self.bits - 1
    }

    /// The largest level-1 cell coordinate of a light: lights beyond it are clamped into it.
    #[must_use]
    pub fn max_cell(&self) -> u32 {
        (3u32 << (self.bits - 2)) - 1
    }

    /// Level-1 cells a side of the Morton cube.
    #[must_use]
    pub fn side(&self) -> u32 {
        1 << self.bits
    }

    /// Level ℓ's spacing `h_ℓ = 2^(ℓ−1) h1` (`h1 / 2` for level 0: lgh-core's `h0`).
    #[must_use]
    pub fn h(&self, level: u8) -> f32 {
        if level == 0 {
            self.h1 * 0.5
        } else {
            self.h1 * (1u32 << (level - 1)) as f32
        }
    }

    /// lgh-core's settings for the same placement: a CPU build with them has the same levels,
    /// cells and vertices (the reference of the tests).
    #[must_use]
    pub fn settings(&self) -> GridSettings {
        GridSettings {
            h1: Some(self.h1),
            origin: Some(self.origin),
            max_level: Some(self.max_level()),
            ..Default::default()
        }
    }
}
