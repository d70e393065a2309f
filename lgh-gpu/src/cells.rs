//! A level's lights sorted into a dense grid of cells, on the CPU: the query visits the cells
//! that meet the ball of a level's reach around a shading point and scans their lights, as
//! lgh-core's query scans the level-1 cells of its bricks (paper Sec. 3.1: a light of level ℓ
//! only matters within `2 r_ℓ` of it).

use lgh_core::glam::Vec3;

use crate::error::GpuError;

/// Lights sorted by the cell that holds them, each cell a range of that order.
#[derive(Clone, Debug, PartialEq)]
pub struct Cells {
    /// The low corner of cell (0, 0, 0): the lights' lowest corner.
    pub origin: Vec3,
    /// A cell's side.
    pub cell: f32,
    /// Cells along x, y, z (each at least 1 when there are lights).
    pub dims: [u32; 3],
    /// `starts[c]..starts[c + 1]` are cell `c`'s entries of `order` (`c = (z·dims.y + y)·dims.x
    /// + x`); `cells + 1` entries.
    pub starts: Vec<u32>,
    /// The lights' indices, cell by cell, in increasing index within a cell (so the order does
    /// not depend on anything but the lights).
    pub order: Vec<u32>,
}

impl Cells {
    /// Sorts `positions` into cells of side `cell`, at most `most` cells. Errors with
    /// [`GpuError::TooManyCells`] (naming `level`) when the lights' box needs more.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_gpu::cells::Cells;
    ///
    /// let p = [Vec3::ZERO, Vec3::new(2.5, 0.0, 0.0), Vec3::new(0.5, 0.0, 0.0)];
    /// let c = Cells::sort(&p, 1.0, 1 << 20, 1)?;
    /// assert_eq!(c.dims, [3, 1, 1]);
    /// assert_eq!(c.order, [0, 2, 1]); // cell 0 holds lights 0 and 2, cell 2 light 1
    /// assert_eq!(c.starts, [0, 2, 2, 3]);
    /// # Ok::<(), lgh_gpu::GpuError>(())
    /// ```
    pub fn sort(positions: &[Vec3], cell: f32, most: u64, level: u8) -> Result<Cells, GpuError> {
        let (lo, hi) = positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
        if positions.is_empty() {
            return Ok(Cells {
                origin: Vec3::ZERO,
                cell,
                dims: [0; 3],
                starts: vec![0],
                order: Vec::new(),
            });
        }
        let span = ((hi - lo) / cell).to_array();
        let dims_f = span.map(|s| s.floor() as f64 + 1.0);
        let cells = dims_f.iter().product::<f64>();
        if cells.is_nan() || cells > most as f64 {
            let cells = if cells.is_finite() {
                cells as u64
            } else {
                u64::MAX
            };
            return Err(GpuError::TooManyCells { level, cells, most });
        }
        let dims = dims_f.map(|d| d as u32);
        let index = |p: Vec3| -> usize {
            let t = ((p - lo) / cell).to_array();
            let c: [u32; 3] = core::array::from_fn(|a| (t[a].floor() as u32).min(dims[a] - 1));
            ((c[2] as usize * dims[1] as usize) + c[1] as usize) * dims[0] as usize + c[0] as usize
        };
        let mut starts = vec![0u32; cells as usize + 1];
        for &p in positions {
            starts[index(p) + 1] += 1;
        }
        for c in 1..starts.len() {
            starts[c] += starts[c - 1];
        }
        let mut next = starts.clone();
        let mut order = vec![0u32; positions.len()];
        for (i, &p) in positions.iter().enumerate() {
            let c = index(p);
            order[next[c] as usize] = i as u32;
            next[c] += 1;
        }
        Ok(Cells {
            origin: lo,
            cell,
            dims,
            starts,
            order,
        })
    }
}
