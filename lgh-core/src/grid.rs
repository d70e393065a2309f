//! Where the grids sit: the level-1 spacing `h1`, the shared origin, and `ℓ_max`.

use glam::Vec3;

use crate::blend::MAX_LEVEL;
use crate::error::BuildError;
use crate::light::PointLight;
use crate::math::{floor64, level_scale};
use crate::morton;

/// The most level-1 cells the lights may span along one axis (minus one): about a million.
pub(crate) const MAX_SPAN: u32 = (1 << 20) - 1;
/// The largest level-1 cell coordinate after the origin is aligned to the coarsest grid (the
/// alignment adds less than `2^20`); vertices, one further, still fit the 21-bit Morton codes.
pub(crate) const MAX_CELL: u32 = (1 << 21) - 2;
const _: () = assert!(MAX_CELL < morton::MAX_COORD);
const _: () = assert!(MAX_SPAN as u64 + (1 << (MAX_LEVEL - 1)) - 1 <= MAX_CELL as u64);
/// Lights may lie at most this many level-1 cells from the origin: a position in cells is an f64,
/// and beyond `2^29` cells it no longer holds the position inside its cell to f32 precision.
const MAX_ORIGIN_CELLS: f64 = (1u64 << 29) as f64;

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

/// How a level's lights gather the lights below them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Clustering {
    /// Each light is split among the eight vertices of its cell by its trilinear weights (eq. 1):
    /// the paper's, continuous as a light moves or brightens. The default.
    #[default]
    Trilinear,
    /// Each light goes whole to the nearest vertex of its cell: plain clustering, which the paper
    /// names as flickering (Sec. 3.1: a light crossing a cell's middle jumps between clusters).
    /// A variant, only to measure that.
    NearestVertex,
}

/// Where a coarse light sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LightPosition {
    /// At its illumination centre `p_ℓi`, the luminance-weighted mean of what it gathers (eq. 2):
    /// the paper's. The default.
    #[default]
    IlluminationCentre,
    /// At its grid vertex: the variant of the paper's Fig. 9, which shifts light towards the
    /// vertices (and makes shading jump with the grid). A variant, only to measure that.
    GridVertex,
}

/// Settings of a build. `Default` chooses everything automatically.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::{GridSettings, LevelSource, LightingGridHierarchy, PointLight};
///
/// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::splat(3.0), Vec3::ONE)];
/// let settings = GridSettings { h1: Some(0.5), source: LevelSource::PreviousLevel, ..Default::default() };
/// assert_eq!(LightingGridHierarchy::build(&lights, &settings)?.h1(), 0.5);
/// // `None`: chosen by the build (here `h1` by the paper's Sec. 6.4 rule).
/// assert_eq!((GridSettings::default().h1, GridSettings::default().max_level), (None, None));
/// # Ok::<(), lgh_core::BuildError>(())
/// ```
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
    /// How levels ℓ ≥ 1 gather their lights (the paper's trilinear splat by default).
    pub clustering: Clustering,
    /// Where levels ℓ ≥ 1 place their lights (the illumination centres by default).
    pub position: LightPosition,
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

/// Bounding box `(min, max)` of the lights' positions (±∞ for no lights).
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::{bounds, PointLight};
///
/// let lights = [PointLight::new(Vec3::new(1.0, -2.0, 0.0), Vec3::ONE), PointLight::new(Vec3::Z, Vec3::ONE)];
/// assert_eq!(bounds(&lights), (Vec3::new(0.0, -2.0, 0.0), Vec3::new(1.0, 0.0, 1.0)));
/// assert_eq!(bounds(&[]).0, Vec3::INFINITY); // no lights: an empty box
/// ```
#[must_use]
pub fn bounds(lights: &[PointLight]) -> (Vec3, Vec3) {
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
        Some(h) => h as f64,
        None => auto_h1(lights, lo, hi, origin),
    };
    let max_level = match settings.max_level {
        Some(l) if l > MAX_LEVEL => {
            return Err(BuildError::TooManyLevels {
                requested: l,
                max: MAX_LEVEL,
            })
        }
        Some(l) => Some(l),
        None => None,
    };
    // h0 = h1 / 2 must be a normal f32 (it clamps the fall-off).
    if !(h1.is_finite() && (h1 * 0.5) as f32 >= f32::MIN_POSITIVE) {
        return Err(BuildError::InvalidSpacing { h1: h1 as f32 });
    }
    let cmin = abs_cell(lo, origin, h1);
    let cmax = abs_cell(hi, origin, h1);
    check_extent((lo, hi), origin, h1, (cmin, cmax))?;
    let max_level = max_level.unwrap_or_else(|| enclosing_level(cmin, cmax));
    // The coarsest spacing squared (variances are in squared units) must be finite in f32.
    let top = (h1 * level_scale(max_level.max(1))) as f32;
    if !(top * top).is_finite() {
        return Err(BuildError::InvalidSpacing { h1: h1 as f32 });
    }
    let (shifted, max_cell) = align_to_coarsest(origin, h1, max_level, (cmin, cmax));
    Ok(Placement {
        h1,
        origin: shifted,
        max_level,
        max_cell,
    })
}

/// Checks that the lights' box `(lo, hi)`, level-1 cells `(cmin, cmax)`, spans at most
/// [`MAX_SPAN`] cells and lies within [`MAX_ORIGIN_CELLS`] cells of `origin`.
fn check_extent(
    (lo, hi): (Vec3, Vec3),
    origin: [f64; 3],
    h1: f64,
    (cmin, cmax): ([f64; 3], [f64; 3]),
) -> Result<(), BuildError> {
    let span = (0..3).map(|a| cmax[a] - cmin[a]).fold(0.0, f64::max);
    if span > MAX_SPAN as f64 {
        return Err(BuildError::GridTooFine {
            cells: span + 1.0,
            max: MAX_SPAN + 1,
        });
    }
    let far = (0..3)
        .map(|a| {
            ((lo[a] as f64 - origin[a])
                .abs()
                .max((hi[a] as f64 - origin[a]).abs()))
                / h1
        })
        .fold(0.0, f64::max);
    if far > MAX_ORIGIN_CELLS {
        return Err(BuildError::OriginTooFar { cells: far });
    }
    Ok(())
}

/// The automatic `ℓ_max`: the lowest ℓ ≥ 1 whose cells (level-1 cells divided by `2^(ℓ−1)`)
/// hold the level-1 cells `cmin ..= cmax` in one, at most [`MAX_LEVEL`].
#[must_use]
fn enclosing_level(cmin: [f64; 3], cmax: [f64; 3]) -> u8 {
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

/// The origin shifted so that the lights' level-1 cells `cmin ..= cmax` start near 0, by a
/// multiple of the coarsest grid's spacing so that every level keeps its vertices on the same
/// lattice; and the largest level-1 cell coordinate per axis from the shifted origin.
#[must_use]
fn align_to_coarsest(
    origin: [f64; 3],
    h1: f64,
    max_level: u8,
    (cmin, cmax): ([f64; 3], [f64; 3]),
) -> ([f64; 3], [u32; 3]) {
    let align = (1u64 << max_level.saturating_sub(1)) as f64;
    let mut shifted = [0.0; 3];
    let mut max_cell = [0u32; 3];
    for a in 0..3 {
        let base = floor64(cmin[a] / align) * align;
        shifted[a] = origin[a] + base * h1;
        // cmax − base ≤ span + align − 1 ≤ MAX_CELL (checked at compile time above).
        max_cell[a] = (cmax[a] - base).min(MAX_CELL as f64) as u32;
    }
    (shifted, max_cell)
}

/// The Sec. 6.4 rule: start from one cell over the bounding box and halve `h1` until the level-1
/// vertices that receive light (the corners of occupied cells) outnumber the lights. Stops before
/// the lights span more than [`MAX_SPAN`] cells. Coincident lights (an empty box) get `h1 = 1`.
fn auto_h1(lights: &[PointLight], lo: Vec3, hi: Vec3, origin: [f64; 3]) -> f64 {
    let extent = (0..3)
        .map(|a| hi[a] as f64 - lo[a] as f64)
        .fold(0.0, f64::max);
    if extent <= 0.0 {
        return 1.0;
    }
    let mut h = extent;
    let mut codes: alloc::vec::Vec<u64> = alloc::vec::Vec::with_capacity(lights.len());
    let mut vertices: alloc::vec::Vec<u64> = alloc::vec::Vec::new();
    // Each halving doubles extent / h, so this ends within about 21 rounds.
    while extent / (h * 0.5) < (MAX_SPAN - 1) as f64 {
        h *= 0.5;
        let cmin = abs_cell(lo, origin, h);
        let cmax = abs_cell(hi, origin, h);
        let spans = |a: usize| cmax[a] - cmin[a];
        if (0..3).any(|a| spans(a).is_nan() || spans(a) > MAX_SPAN as f64) {
            return h * 2.0; // the origin is too far for this spacing; `place` will say so
        }
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
        morton::corner_codes(&codes, &mut vertices);
        if vertices.len() > lights.len() {
            return h;
        }
    }
    h
}
