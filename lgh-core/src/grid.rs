//! Where the grids sit: the level-1 spacing `h1`, the shared origin, and `ℓ_max`.

use glam::Vec3;

use crate::blend::MAX_LEVEL;
use crate::error::BuildError;
use crate::light::PointLight;
use crate::math::floor64;
use crate::morton;

/// The largest level-1 cell coordinate a hierarchy addresses (`2^20 − 1`): vertices, one further,
/// still fit the 21-bit Morton codes, and level [`MAX_LEVEL`] is then always a single cell.
pub(crate) const MAX_CELL: u32 = (1 << 20) - 1;
const _: () = assert!(MAX_CELL < morton::MAX_COORD);

/// How level ℓ ≥ 2 is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LevelSource {
    /// Every level splats the input lights `S0` (eqs. 1, 2, 4, 5 exactly as written). The default.
    #[default]
    InputLights,
    /// Level ℓ splats the lights of level ℓ−1 (their centres and intensities), as the paper allows
    /// at the end of Sec. 3.1: faster, smoother, and not exactly equivalent. The variance σ² stays
    /// exact (the level ℓ−1 variances are added by the law of total variance); the size `s` measures
    /// distances to the level ℓ−1 centres, so it underestimates eq. (5).
    PreviousLevel,
}

/// Settings of a build. `Default` chooses everything automatically.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct GridSettings {
    /// Level-1 spacing `h1`. `None`: the Sec. 6.4 rule — start from one cell over the lights'
    /// bounding box and halve `h1` until the level-1 vertices that receive light outnumber the lights.
    pub h1: Option<f32>,
    /// Origin shared by all levels (a level-1 vertex). `None`: the lights' bounding-box minimum.
    pub origin: Option<Vec3>,
    /// Top level `ℓ_max` (0 ..= [`MAX_LEVEL`]). `None`: the lowest level whose grid holds all lights in
    /// one cell, so the always-evaluated top level has at most 8 lights.
    pub max_level: Option<u8>,
    /// Build levels ≥ 2 from `S0` (default) or from the previous level.
    pub source: LevelSource,
    /// Weak-light pruning (paper Sec. 6): lights whose luminance `‖I_ℓi‖` is below this threshold are
    /// skipped at every level except the top one. Their energy still reaches the coarser levels, which
    /// are built from all lights. 0 (the default) prunes nothing.
    pub prune_below: f32,
}

/// Resolved placement of the grids.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Placement {
    pub h1: f64,
    /// The origin moved by `base · h1` so that every light's level-1 cell coordinate is in
    /// `0..=MAX_CELL`; still a vertex of every level's grid (the shift is a multiple of `2^(ℓmax−1)`).
    pub origin: [f64; 3],
    pub max_level: u8,
    /// Largest level-1 cell coordinate of any light, per axis.
    pub max_cell: [u32; 3],
}

/// Bounding box of the lights' positions (validated elsewhere).
pub(crate) fn bounds(lights: &[PointLight]) -> (Vec3, Vec3) {
    lights.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), l| (lo.min(l.position), hi.max(l.position)),
    )
}

/// Absolute level-1 cell coordinates of a point (floor of `(p − origin) / h1`).
#[inline]
fn abs_cell(p: Vec3, origin: [f64; 3], h1: f64) -> [f64; 3] {
    let mut c = [0.0; 3];
    for a in 0..3 {
        c[a] = floor64((p[a] as f64 - origin[a]) / h1);
    }
    c
}

/// Places the grids for the given lights (non-empty, validated).
pub(crate) fn place(
    lights: &[PointLight],
    settings: &GridSettings,
) -> Result<Placement, BuildError> {
    let (lo, hi) = bounds(lights);
    let origin = match settings.origin {
        Some(o) if !o.is_finite() => return Err(BuildError::NonFiniteOrigin),
        Some(o) => o,
        None => lo,
    };
    let origin = [origin.x as f64, origin.y as f64, origin.z as f64];
    let h1 = match settings.h1 {
        Some(h) if !(h.is_finite() && h > 0.0) => return Err(BuildError::InvalidSpacing { h1: h }),
        Some(h) => h as f64,
        None => auto_h1(lights, lo, hi, origin),
    };
    let cmin = abs_cell(lo, origin, h1);
    let cmax = abs_cell(hi, origin, h1);
    let span = (0..3).map(|a| cmax[a] - cmin[a]).fold(0.0, f64::max);
    if span > MAX_CELL as f64 {
        return Err(BuildError::GridTooFine {
            cells: span + 1.0,
            max: MAX_CELL + 1,
        });
    }
    let max_level = match settings.max_level {
        Some(l) if l > MAX_LEVEL => {
            return Err(BuildError::TooManyLevels {
                requested: l,
                max: MAX_LEVEL,
            })
        }
        Some(l) => l,
        None => {
            // Lowest ℓ ≥ 1 whose cells (level-1 cells divided by 2^(ℓ−1)) hold everything in one.
            let mut l = 1u8;
            while l < MAX_LEVEL {
                let s = (1u64 << (l - 1)) as f64;
                if (0..3).all(|a| floor64(cmin[a] / s) == floor64(cmax[a] / s)) {
                    break;
                }
                l += 1;
            }
            l
        }
    };
    // Align the shift to the coarsest grid so every level keeps its vertices on the same lattice.
    let align = (1u64 << max_level.saturating_sub(1)) as f64;
    let mut shifted = [0.0; 3];
    let mut max_cell = [0u32; 3];
    for a in 0..3 {
        let base = floor64(cmin[a] / align) * align;
        shifted[a] = origin[a] + base * h1;
        let m = cmax[a] - base;
        if m > MAX_CELL as f64 {
            return Err(BuildError::GridTooFine {
                cells: m + 1.0,
                max: MAX_CELL + 1,
            });
        }
        max_cell[a] = m as u32;
    }
    Ok(Placement {
        h1,
        origin: shifted,
        max_level,
        max_cell,
    })
}

/// The Sec. 6.4 rule: start from one cell over the bounding box and halve `h1` until the level-1
/// vertices that receive light (the corners of occupied cells) outnumber the lights. Stops early if
/// the grid would exceed [`MAX_CELL`] cells per axis. Coincident lights (an empty box) get `h1 = 1`.
fn auto_h1(lights: &[PointLight], lo: Vec3, hi: Vec3, origin: [f64; 3]) -> f64 {
    let extent = (hi - lo).max_element() as f64;
    if extent <= 0.0 {
        return 1.0;
    }
    // Each halving doubles the span in cells, so the MAX_CELL test below ends the loop.
    let mut h = extent;
    let mut codes: alloc::vec::Vec<u64> = alloc::vec::Vec::with_capacity(lights.len());
    let mut vertices: alloc::vec::Vec<u64> = alloc::vec::Vec::new();
    loop {
        let next = h * 0.5;
        let cmin = abs_cell(lo, origin, next);
        let cmax = abs_cell(hi, origin, next);
        if (0..3).any(|a| cmax[a] - cmin[a] > MAX_CELL as f64 - 1.0) {
            return h;
        }
        h = next;
        codes.clear();
        codes.extend(lights.iter().map(|l| {
            let c = abs_cell(l.position, origin, h);
            morton::encode([
                (c[0] - cmin[0]) as u32,
                (c[1] - cmin[1]) as u32,
                (c[2] - cmin[2]) as u32,
            ])
        }));
        codes.sort_unstable();
        codes.dedup();
        crate::level::corner_codes(&codes, &mut vertices);
        if vertices.len() > lights.len() {
            return h;
        }
    }
}
