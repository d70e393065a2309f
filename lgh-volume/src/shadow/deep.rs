//! Deep-shadow cube maps: the paper's precomputed volumetric shadows (Sec. 4, Table 1).
//!
//! Every light of every level of the hierarchy only lights points within `2 r_ℓ` of it
//! (`r_ℓ = α h_ℓ`, the blending function `B_ℓ` is zero beyond). So its shadow can be precomputed
//! once per frame, at a resolution fixed by `r_ℓ`: a cube map whose cells are `h` (a voxel) wide
//! at distance `r_ℓ`, where `B_ℓ` peaks — `R = ⌈2 r_ℓ / h⌉` cells per face side, `24 (r_ℓ/h)²` in
//! all — each texel storing the optical depth `τ` along its direction at four distances
//! `D/4, D/2, 3D/4, D` (or `n` at `D/n … D`, [`CubeMapSettings::depth_count`]; `D = 2 r_ℓ`;
//! the top level, whose lights reach everything, and any level whose `2 r_ℓ` exceeds the
//! density's box, take the box's diagonal). A lookup interpolates
//! bilinearly between texels (seamless across faces, [`super::cube`]) and linearly between
//! the depths, so the shadow is continuous in the shading point and in the light's position.
//!
//! The texel rays start at the light's illumination centre `p_ℓi`. Level-0 lights are points;
//! coarser lights are volume lights: their rays read the density prefiltered with the tent of
//! width `δ(d) = (1 − d/r_ℓ) s_ℓi + (d/r_ℓ) h_0` (eq. 6, [`super::prefilter`]), which is the
//! paper's cure for the flicker of point-light shadows of clustered lights. The smoothing also
//! sets the step: a tent of width `δ` leaves nothing of the density finer than `δ`, so the rays
//! step `max(step, δ/2)` — which is what makes the big maps of the coarse levels affordable.
//!
//! **What a texel stores.** By default, [`Depths::Adaptive`]: four knots (distance,
//! transmittance) placed along the texel's ray where `V` changes, in the eight bytes of the
//! paper's four depths (module `knots`): 1.74% against the maps' own model on the demo, where the
//! fixed depths below err by 8.65% (`docs/shadows.md`).
//!
//! **Fixed depths.** The paper records `τ` at the four distances. We can
//! do that ([`Depths::Sampled`]), but a piecewise-linear `τ` through four samples leaks light
//! wherever a shell of smoke lies between two of them (the chord lies below the step), and the
//! shading points that matter are exactly those in the smoke. [`Depths::Fitted`], the default,
//! stores instead the four values whose piecewise-linear `τ` is closest, in least squares, to the
//! traced `τ` at the ray's samples, each weighted by what an error there costs the image:
//! the density there (the scattering a shading point adds is `∝ ρ`) times `V² = e^{−2τ}` (an
//! error `Δτ` changes `V` by `V·Δτ`). Same storage, same lookup. Both layouts are looked up eight
//! lights abreast with AVX2 (module `avx2`).
//!
//! **Storage of fixed depths.** `τ` is quantised to 16 bits on `[0, TAU_MAX]`: an absolute error of at most
//! `TAU_MAX / 131070 ≈ 1.2·10⁻⁴` in `τ`, a relative error of at most that in `V`; depths beyond
//! `TAU_MAX` (`V < 1.1·10⁻⁷`) are stored as `TAU_MAX`. Two bytes a depth: eight a texel with
//! the paper's four depths. On the demo's explosion, whose dense soot rim is a rise of `τ` by
//! several units within two or three voxels, levels 3 and 4 (depths 8 and 16 voxels apart)
//! cannot place that rise: 8.65% relative RMSE of the image against the same model marched
//! (`super::volume_rays`), 2.76% with eight depths, 1.67% with twelve (`docs/shadows.md`).
//!
//! The maps are traced in parallel (rayon) in tiles of texel rows, each into its own slice, so
//! that a level of few lights with large maps keeps every core busy: the result does not
//! depend on the thread count. The tiles are handed out in order as threads come free, so the
//! threads trace neighbouring rows through the same density at once (rayon's halving split
//! had them on opposite faces: the Table-1 frame's maps took 114–118 s on 2 threads against
//! 90–106 s, `docs/shadows.md`). Nothing is allocated per texel.

use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::Blending;
use rayon::prelude::*;

use super::cube;
use super::empty::EmptySpace;
use super::knots::{self, Knots, Support};
use super::lookup::{self, Slot, NO_MAP};
use super::prefilter::DensityPyramid;
use super::{Casters, CoarseShadows};
use crate::error::RenderError;
use crate::grid::DenseGrid;
use crate::medium::{Medium, Volume};

#[cfg(target_arch = "x86_64")]
mod avx2;

pub use super::lookup::TAU_MAX;

/// The most depths a texel can store ([`CubeMapSettings::depth_count`]).
pub const MAX_DEPTHS: usize = 16;

/// Quantisation steps per unit of optical depth.
const QUANT: f32 = 65535.0 / TAU_MAX;

/// What the depths of a texel hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Depths {
    /// Transmittance at knots placed per texel where it changes (module `knots`: deep shadow
    /// maps compressed by Salvi's node removal), `depth_count` knots of two bytes each.
    #[default]
    Adaptive,
    /// The least-squares fit of the traced `τ` at the fixed distances `D/n … D`, weighted by
    /// density × `V²` (see the module docs).
    Fitted,
    /// `τ` at the fixed distances, as the paper records it.
    Sampled,
}

impl Depths {
    /// The name in EXR headers and reports: `knots`, `fitted` or `sampled`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Depths::Adaptive => "knots",
            Depths::Fitted => "fitted",
            Depths::Sampled => "sampled",
        }
    }
}

/// How the maps are traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubeMapSettings {
    /// Shortest step along a texel ray, in voxels (longer where the prefilter is wider).
    pub step_voxels: f32,
    /// What the depths hold.
    pub depths: Depths,
    /// Depths (or knots) per texel, `2..=`[`MAX_DEPTHS`], two bytes each: 4 knots by default
    /// (the memory of the paper's four depths); fixed depths at `D/n … D`, the paper's four
    /// or more for a shadow that follows thin shells of smoke more closely.
    pub depth_count: usize,
    /// Bytes the maps may take; a plan above it is refused before any work.
    pub memory_budget: u64,
}

impl Default for CubeMapSettings {
    fn default() -> Self {
        CubeMapSettings {
            step_voxels: 1.0,
            depths: Depths::Adaptive,
            depth_count: 4,
            memory_budget: 8 << 30,
        }
    }
}

/// One level's maps as planned (and, once traced, timed): a row of the paper's Table 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelMaps {
    /// The level ℓ.
    pub level: u8,
    /// Lights with a map (those the queries can return).
    pub lights: usize,
    /// The paper's cells per face side, `R = ⌈2 r_ℓ / h⌉` (the most any light of the level gets;
    /// see [`CubeMaps::plan`]).
    pub cells: u32,
    /// Texels of all the level's maps.
    pub texels: u64,
    /// Tiles the level's tracing is split into, the items traced in parallel (whole small
    /// maps, or runs of texel rows of at most 1,024 texels).
    pub tiles: u64,
    /// Distance of the last stored depth `D`.
    pub reach: f32,
    /// Bytes of the level's maps and index.
    pub bytes: u64,
    /// Density samples taken tracing them (0 in a plan).
    pub samples: u64,
    /// Seconds spent tracing them (0 in a plan).
    pub seconds: f64,
}

/// The maps of every level: what [`CubeMaps::plan`] finds before any tracing.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeMapPlan {
    /// One row per level.
    pub levels: Vec<LevelMaps>,
    /// Bytes of the density pyramid the maps are traced through (freed after tracing).
    pub pyramid_bytes: u64,
    /// Each level's maps: (light index, centre, size, cells per face side).
    maps: Vec<Vec<Planned>>,
}

impl CubeMapPlan {
    /// Bytes of all the maps.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.levels.iter().map(|l| l.bytes).sum()
    }

    /// Lights with a map, over all levels.
    #[must_use]
    pub fn lights(&self) -> usize {
        self.levels.iter().map(|l| l.lights).sum()
    }
}

/// One light's map as planned.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Planned {
    index: u32,
    centre: Vec3,
    size: f32,
    cells: u32,
    /// Where its level's blending weight `B_ℓ` is not zero (and no lookup is outside).
    support: Support,
}

/// One level's maps.
#[derive(Clone, Debug)]
struct Level {
    /// n / D: spacings of the depths per unit distance (255 / D with adaptive knots).
    inv_spacing: f32,
    /// Each light's map in [`CubeMaps`]' texels, or [`NO_MAP`].
    slots: Vec<Slot>,
}

/// The deep-shadow cube maps of one frame's hierarchy at one α (see the module docs).
#[derive(Clone, Debug)]
pub struct CubeMaps {
    levels: Vec<Level>,
    /// Every map of every level: quantised `τ` at the depths, `per_texel` values a texel,
    /// `6 (R + 1)²` texels a map.
    texels: Vec<u16>,
    /// Depths (or knots) a texel.
    per_texel: usize,
    /// What the texels hold.
    storage: Depths,
    table: Vec<LevelMaps>,
}

/// The paper's `R` and `D` of `level`: cells `h` wide at `r_ℓ`, depths to `2 r_ℓ` (to the
/// level's support, further by [`Blending::spread_reach`] where coarse lights are averaged
/// over their spread); the top level, or a level reaching beyond the box, to the box's
/// diagonal (and no finer than `h` there).
fn resolution(blending: &Blending, level: u8, h: f32, diagonal: f32) -> (u32, f32) {
    let r = blending.radius(level);
    let top = level == blending.max_level();
    let reach = if top {
        diagonal
    } else {
        (2.0 * r + blending.spread_reach(level)).min(diagonal)
    };
    let cells = (2.0 * r / h).min(2.0 * diagonal / h).ceil().max(1.0);
    (cells.min(1e6) as u32, reach)
}

/// The filter width `δ(d)` of eq. 6 for a light of size `s` and blending radius `r` (0, the
/// plain density, for points — `prefilter` off — and beyond `r`).
#[inline]
pub(super) fn filter_width(prefilter: bool, d: f32, s: f32, r: f32, h0: f32) -> f32 {
    if prefilter && d < r {
        (1.0 - d / r) * s + (d / r) * h0
    } else {
        0.0
    }
}

impl CubeMaps {
    /// The maps [`build`](Self::build) would make for `hierarchy` at `blending`'s α over
    /// `density` with `settings`, level by level, with their exact sizes: cheap (no tracing).
    ///
    /// Each light's map gets the paper's resolution (cells `h` wide at `r_ℓ`) or less where
    /// that adds nothing: neighbouring texels at distance `d` are `2d/R` apart, and the density
    /// a texel ray reads there is filtered over `δ_eff(d) = max(δ(d), h)` (eq. 6; the voxels
    /// themselves beyond `r_ℓ`), so `R = 2d/δ_eff(d)` resolves everything the ray can see up to
    /// `d`, and `2d/δ_eff(d)` grows with `d`. Rays see nothing new past the smoke: `d` is the
    /// smaller of `r_ℓ` and the distance to the farthest corner of the smoke's box (grown by the
    /// filter's reach). For a level-0 light, or any light whose rays reach `r_ℓ` in smoke, this
    /// is the paper's `2 r_ℓ / h`; for a coarse light in the middle of the smoke, whose rays
    /// leave the smoke while its filter is still wide, far less.
    #[must_use]
    pub fn plan(
        casters: Casters<'_>,
        density: &DenseGrid,
        settings: &CubeMapSettings,
    ) -> CubeMapPlan {
        let Casters {
            hierarchy,
            blending,
            ..
        } = casters;
        let h = density.voxel_size;
        let (lo, hi) = density.bounds();
        let diagonal = (hi - lo).length();
        let smoke = density.active_bounds();
        let mut levels = Vec::new();
        let mut maps = Vec::new();
        for level in 0..=hierarchy.max_level() {
            let (cells, reach) = resolution(blending, level, h, diagonal);
            let r = blending.radius(level);
            let planned: Vec<Planned> = hierarchy
                .level(level)
                .iter()
                .enumerate()
                .filter(|(_, l)| hierarchy.is_active(level, l))
                .map(|(i, l)| {
                    let (p, s) = (l.position, l.size);
                    let far = smoke.map_or(0.0, |(a, b)| {
                        let grow = Vec3::splat(3.0 * s.max(h));
                        ((a - grow - p).abs().max((b + grow - p).abs())).length()
                    });
                    let d = r.min(far);
                    let width = filter_width(casters.prefiltered(), d, s, r, h).max(h);
                    let own = (2.0 * d / width).ceil().clamp(1.0, cells as f32) as u32;
                    Planned {
                        index: i as u32,
                        centre: p,
                        size: s,
                        cells: own,
                        support: Support {
                            inner: blending.support(level).0,
                            peak: r,
                            outer: blending.support(level).1,
                        },
                    }
                })
                .collect();
            let texels: u64 = planned.iter().map(|m| cube::texels(m.cells) as u64).sum();
            let tiles: u64 = planned.iter().map(|m| tile_count(m.cells) as u64).sum();
            levels.push(LevelMaps {
                level,
                lights: planned.len(),
                cells,
                texels,
                tiles,
                reach,
                bytes: texels * 2 * settings.depth_count as u64
                    + hierarchy.level(level).len() as u64 * 8,
                samples: 0,
                seconds: 0.0,
            });
            maps.push(planned);
        }
        // The pyramid: a padded copy of the density, a full-resolution level, then levels
        // sampled every 2, 4, … voxels, each padded and bricked. Bricks round each level up, so
        // the levels are bounded one by one (at most n/s + 2 samples an axis at spacing s), up
        // to the last level any light could ask for.
        let mut pyramid_bytes = super::PaddedGrid::bytes_for(density.dims);
        for m in 0..24 {
            let dims = density.dims.map(|n| (n >> m) + 2);
            pyramid_bytes += super::PaddedGrid::bytes_for(dims);
            if dims.iter().all(|&n| n <= 4) {
                break;
            }
        }
        CubeMapPlan {
            levels,
            pyramid_bytes,
            maps,
        }
    }

    /// Traces the maps of every light of `hierarchy` (at `blending`'s α) through `volume`'s
    /// density in `medium`. Refused before any work, with [`RenderError::ShadowMemory`], if the
    /// [`plan`](Self::plan) exceeds `settings.memory_budget`. `progress(n)` as each batch of `n`
    /// lights is done.
    pub fn build(
        casters: Casters<'_>,
        volume: &Volume,
        medium: &Medium,
        settings: &CubeMapSettings,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, RenderError> {
        let Casters {
            hierarchy,
            blending,
            coarse,
        } = casters;
        check_settings(settings)?;
        let density = &volume.density;
        let plan = CubeMaps::plan(casters, density, settings);
        check_memory(&plan, settings, blending)?;
        let pyramid = DensityPyramid::for_hierarchy(density, hierarchy, coarse);
        let empty = EmptySpace::new(density);
        let tracer = Tracer::for_maps(&pyramid, &empty, density, medium, settings, coarse);
        let mut levels = Vec::new();
        let mut table = Vec::new();
        let total: u64 = plan.levels.iter().map(|l| l.texels).sum();
        let per_texel = settings.depth_count;
        let mut texels = vec![0u16; total as usize * per_texel];
        let mut slicer = TexelSlicer {
            rest: &mut texels,
            offset: 0,
            per_texel,
        };
        for (row, planned) in plan.levels.iter().zip(&plan.maps) {
            let t = Instant::now();
            let (slots, jobs) = slicer.level(hierarchy.level(row.level).len(), planned);
            let r = blending.radius(row.level);
            let samples = tracer.trace_level(jobs, r, row.reach, progress);
            levels.push(Level {
                inv_spacing: if settings.depths == Depths::Adaptive {
                    knots::STEPS / row.reach
                } else {
                    per_texel as f32 / row.reach
                },
                slots,
            });
            table.push(LevelMaps {
                samples,
                seconds: t.elapsed().as_secs_f64(),
                ..*row
            });
        }
        Ok(CubeMaps {
            levels,
            texels,
            per_texel,
            storage: settings.depths,
            table,
        })
    }

    /// Table 1's rows for these maps: lights, resolution, bytes and tracing seconds per level.
    #[must_use]
    pub fn table(&self) -> &[LevelMaps] {
        &self.table
    }

    /// Bytes of all the maps.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.table.iter().map(|l| l.bytes).sum()
    }

    /// Lights with a map, over all levels.
    #[must_use]
    pub fn lights(&self) -> usize {
        self.table.iter().map(|l| l.lights).sum()
    }

    /// Transmittance `e^{−τ}` from light `index` of `level`, centred at `centre`, to `x`: `τ`
    /// interpolated bilinearly between the texels around the direction and linearly between
    /// the depths around the distance (0 at the light, constant beyond the last depth). A light
    /// without a map (one no query returns) is unshadowed.
    #[inline]
    #[must_use]
    pub fn transmittance(&self, x: Vec3, level: u8, index: u32, centre: Vec3) -> f32 {
        let (slot, inv_spacing) = self.slot(level, index);
        if self.adaptive() {
            let (texels, n) = (&self.texels, self.per_texel);
            return knots::transmittance(texels, n, slot, inv_spacing, x, centre).unwrap_or(1.0);
        }
        lookup::quantised_depth(&self.texels, self.per_texel, slot, inv_spacing, x, centre)
            .map_or(1.0, |q| lookup::exp_neg(q * (1.0 / QUANT)))
    }

    /// Light `index` of `level`'s map and its level's 4 / reach ([`NO_MAP`] if it has none).
    #[inline]
    pub(super) fn slot(&self, level: u8, index: u32) -> (Slot, f32) {
        self.levels.get(level as usize).map_or((NO_MAP, 0.0), |l| {
            (
                l.slots.get(index as usize).copied().unwrap_or(NO_MAP),
                l.inv_spacing,
            )
        })
    }

    /// [`transmittance`](Self::transmittance) for each light (`centres` with their level and
    /// index in `ids`) into `out`, bit for bit: eight abreast with AVX2 where the CPU has it
    /// (module `avx2`), one by one elsewhere.
    pub fn transmittances(&self, x: Vec3, centres: &[Vec3], ids: &[(u8, u32)], out: &mut Vec<f32>) {
        out.clear();
        out.resize(centres.len(), 1.0);
        #[cfg(target_arch = "x86_64")]
        if avx2::cube_transmittances(self, x, centres, ids, out) {
            return;
        }
        for ((o, &c), &(level, index)) in out.iter_mut().zip(centres).zip(ids) {
            *o = self.transmittance(x, level, index, c);
        }
    }

    /// Every map's texels, in one array (for module `avx2`).
    pub(super) fn texels(&self) -> &[u16] {
        &self.texels
    }

    /// Depths (or knots) a texel.
    #[must_use]
    pub fn depths_per_texel(&self) -> usize {
        self.per_texel
    }

    /// What the texels hold.
    #[must_use]
    pub fn storage(&self) -> Depths {
        self.storage
    }

    /// Whether the texels hold adaptive knots (module `knots`) rather than depths.
    fn adaptive(&self) -> bool {
        self.storage == Depths::Adaptive
    }
}

/// Quantisation steps per unit of optical depth, for module `avx2`.
pub(super) const INV_QUANT: f32 = 1.0 / QUANT;

/// Checks the settings [`CubeMaps::build`] traces with: the step (0.01 to 64 voxels) and the
/// depths per texel (2 to [`MAX_DEPTHS`]).
fn check_settings(settings: &CubeMapSettings) -> Result<(), RenderError> {
    crate::error::check_setting(
        (0.01..=64.0).contains(&settings.step_voxels),
        "cube maps: step",
        settings.step_voxels,
        "must be 0.01 to 64 voxels",
    )?;
    let what = if settings.depths == Depths::Adaptive {
        "cube maps: knots per texel"
    } else {
        "cube maps: depths per texel"
    };
    crate::error::check_setting(
        (2..=MAX_DEPTHS).contains(&settings.depth_count),
        what,
        settings.depth_count as f32,
        "must be 2 to 16",
    )?;
    Ok(())
}

/// Refuses, with [`RenderError::ShadowMemory`], a `plan` whose maps and pyramid exceed
/// `settings.memory_budget`, or whose texels a 32-bit [`Slot`] offset cannot address.
fn check_memory(
    plan: &CubeMapPlan,
    settings: &CubeMapSettings,
    blending: &Blending,
) -> Result<(), RenderError> {
    let needed = plan.bytes() + plan.pyramid_bytes;
    if needed > settings.memory_budget
        || plan.levels.iter().map(|l| l.texels).sum::<u64>() >= u64::from(u32::MAX)
    {
        return Err(RenderError::ShadowMemory {
            needed,
            budget: settings.memory_budget,
            alpha: blending.alpha(),
        });
    }
    Ok(())
}

/// The texels of every map, handed out light by light in the order of the plan: each light's
/// own slice, so that the maps can be traced in parallel.
struct TexelSlicer<'t> {
    /// The texels not yet handed out.
    rest: &'t mut [u16],
    /// Texels handed out so far (the next map's [`Slot`] offset).
    offset: usize,
    /// Depths a texel.
    per_texel: usize,
}

impl<'t> TexelSlicer<'t> {
    /// The slots of a level of `lights` lights (those without a map [`NO_MAP`]) and the
    /// `planned` maps' jobs: each map's slice of the texels, in order.
    fn level(
        &mut self,
        lights: usize,
        planned: &[Planned],
    ) -> (Vec<Slot>, Vec<(&'t mut [u16], Planned)>) {
        let mut slots = vec![NO_MAP; lights];
        let mut jobs = Vec::with_capacity(planned.len());
        for m in planned {
            slots[m.index as usize] = Slot {
                offset: self.offset as u32,
                cells: m.cells,
            };
            let (map, tail) = core::mem::take(&mut self.rest)
                .split_at_mut(cube::texels(m.cells) * self.per_texel);
            self.offset += map.len() / self.per_texel;
            jobs.push((map, *m));
            self.rest = tail;
        }
        (slots, jobs)
    }
}

/// Texels a [`Tile`] holds at most, unless one texel row of its map is longer: small enough that
/// the demo's levels of a few large maps make thousands of tiles (a 64-core node kept busy),
/// large enough that a tile's setup is nothing beside its rays.
const TILE_TEXELS: usize = 1024;

/// A run of consecutive texels of one light's map: the unit of parallel tracing.
struct Tile<'t> {
    /// The run's depths.
    texels: &'t mut [u16],
    /// Index in the map of its first texel.
    first: usize,
    /// The light whose map it is.
    light: Planned,
}

/// Texel rows a tile of a map with `cells` per face side holds.
fn tile_rows(cells: u32) -> usize {
    (TILE_TEXELS / cube::side(cells)).max(1)
}

/// Tiles of a map with `cells` per face side ([`tiles_of`]).
fn tile_count(cells: u32) -> usize {
    (6 * cube::side(cells)).div_ceil(tile_rows(cells))
}

/// `map` (of light `m`, `depths` values a texel) as tiles of whole texel rows, at most
/// [`TILE_TEXELS`] texels each (one row if a row is longer); a small map is one tile.
fn tiles_of(map: &mut [u16], m: Planned, depths: usize) -> impl Iterator<Item = Tile<'_>> {
    let side = cube::side(m.cells);
    let rows = tile_rows(m.cells);
    map.chunks_mut(rows * side * depths)
        .enumerate()
        .map(move |(k, texels)| Tile {
            texels,
            first: k * rows * side,
            light: m,
        })
}

/// What tracing a texel ray needs.
pub(super) struct Tracer<'a> {
    pub(super) pyramid: &'a DensityPyramid,
    pub(super) empty: &'a EmptySpace,
    /// Jump over empty space (off only to test that it changes nothing).
    pub(super) skip_empty: bool,
    /// `σ_t` per unit density.
    pub(super) kappa: f32,
    /// The density's box.
    pub(super) lo: Vec3,
    pub(super) hi: Vec3,
    /// `h_0`, the filter width at `r_ℓ` (the voxel size).
    pub(super) h0: f32,
    /// Shortest step, world units.
    pub(super) min_step: f32,
    pub(super) prefilter: bool,
    pub(super) depths: Depths,
    /// Depths a texel.
    pub(super) n: usize,
    /// Trace eight rays abreast with AVX2 where the CPU has it (off to test that it changes
    /// nothing).
    pub(super) simd: bool,
}

impl Tracer<'_> {
    /// The tracer [`CubeMaps::build`] traces the maps with: through `pyramid` (and past the
    /// `empty` space) of `density`, in `medium`, with `settings`' step, prefilter and depths.
    #[must_use]
    fn for_maps<'a>(
        pyramid: &'a DensityPyramid,
        empty: &'a EmptySpace,
        density: &DenseGrid,
        medium: &Medium,
        settings: &CubeMapSettings,
        coarse: CoarseShadows,
    ) -> Tracer<'a> {
        let h = density.voxel_size;
        let (lo, hi) = density.bounds();
        Tracer {
            pyramid,
            empty,
            skip_empty: true,
            simd: true,
            kappa: medium.extinction(1.0),
            lo,
            hi,
            h0: h,
            min_step: settings.step_voxels * h,
            prefilter: coarse == CoarseShadows::Volumes,
            depths: settings.depths,
            n: settings.depth_count,
        }
    }

    /// Traces a level's maps, the `jobs` of [`TexelSlicer::level`], for its blending radius `r`
    /// and depths to `reach`; returns the density samples taken. Batches of about a million
    /// texels, so that `progress(n)` is reported as the work goes; within a batch the work is
    /// split into [`Tile`]s of about [`TILE_TEXELS`] texels — whole maps, or runs of texel rows
    /// of one map — traced in parallel: a level of 27 lights with 444-cell faces keeps every core
    /// busy, and each texel depends only on its light and direction, so the maps are the same
    /// whatever the thread count.
    fn trace_level(
        &self,
        jobs: Vec<(&mut [u16], Planned)>,
        r: f32,
        reach: f32,
        progress: &(dyn Fn(usize) + Sync),
    ) -> u64 {
        let mut samples = 0u64;
        let mut jobs = jobs.into_iter().peekable();
        while jobs.peek().is_some() {
            let mut tiles = Vec::new();
            let (mut size, mut maps) = (0, 0);
            while let Some((map, m)) = jobs.next_if(|_| size < 1 << 20) {
                size += map.len();
                maps += 1;
                tiles.extend(tiles_of(map, m, self.n));
            }
            // Handed out in order as threads come free, so that the threads trace neighbouring
            // tiles — rays of one face, through the same part of the density — at once.
            let queue = std::sync::Mutex::new(tiles.into_iter());
            samples += (0..rayon::current_num_threads())
                .into_par_iter()
                .map(|_| {
                    let mut taken = 0u64;
                    loop {
                        // The lock is released before the tile is traced. Nothing can panic
                        // while it is held (a vector's iterator steps), so it is never
                        // poisoned; were it, the iterator would still be whole, so a poisoned
                        // lock hands out its tiles all the same instead of panicking.
                        let next = queue
                            .lock()
                            .unwrap_or_else(std::sync::PoisonError::into_inner)
                            .next();
                        let Some(tile) = next else {
                            return taken;
                        };
                        taken += self.trace_tile(tile, r, reach);
                    }
                })
                .sum::<u64>();
            progress(maps);
        }
        samples
    }

    /// Traces the map of the light at `p` of size `s`, blending radius `r`, depths to `reach`;
    /// returns the density samples taken.
    #[cfg(test)]
    fn trace_map(&self, map: &mut [u16], p: Vec3, s: f32, r: f32, reach: f32, cells: u32) -> u64 {
        let light = Planned {
            index: 0,
            centre: p,
            size: s,
            cells,
            support: Support::FLAT,
        };
        self.trace_tile(
            Tile {
                texels: map,
                first: 0,
                light,
            },
            r,
            reach,
        )
    }

    /// Traces `tile`'s texels of its light's map (blending radius `r`, depths to `reach`);
    /// returns the density samples taken.
    fn trace_tile(&self, tile: Tile<'_>, r: f32, reach: f32) -> u64 {
        let Tile {
            texels: map,
            first,
            light,
        } = tile;
        let (p, s, cells) = (light.centre, light.size, light.cells);
        let side = cube::side(cells);
        let mut samples = 0u64;
        let count = map.len() / self.n;
        let direction = |t: usize| {
            let t = first + t;
            let (face, j, i) = (t / (side * side), (t / side) % side, t % side);
            cube::direction(face, i, j, cells).normalize()
        };
        let mut t = 0;
        let adaptive = self.depths == Depths::Adaptive;
        #[cfg(target_arch = "x86_64")]
        if self.simd {
            while t < count {
                let dirs: [Vec3; 8] = core::array::from_fn(|l| direction((t + l).min(count - 1)));
                let mut knots = adaptive.then(|| [Knots::new(self.n, light.support, reach); 8]);
                let Some(rays) = avx2::trace8(self, p, &dirs, s, r, reach, knots.as_mut()) else {
                    break;
                };
                for (l, (tau, n)) in rays.into_iter().enumerate().take(count - t) {
                    samples += u64::from(n);
                    let out = self.texel(map, t + l);
                    match &knots {
                        Some(knots) => knots[l].store(tau[self.n - 1], out),
                        None => quantise(&tau[..self.n], out),
                    }
                }
                t += 8;
            }
        }
        for t in t..count {
            let out = self.texel(map, t);
            if adaptive {
                let ray = (p, direction(t), light.support);
                samples += u64::from(self.trace_knots(ray, (s, r, reach), out));
            } else {
                let (tau, n) = self.trace(p, direction(t), s, r, reach);
                samples += u64::from(n);
                quantise(&tau[..self.n], out);
            }
        }
        samples
    }

    /// Texel `t`'s depths in `map`.
    #[inline]
    fn texel<'m>(&self, map: &'m mut [u16], t: usize) -> &'m mut [u16] {
        &mut map[t * self.n..(t + 1) * self.n]
    }

    /// The filter width `δ(d)` of eq. 6 ([`filter_width`]).
    #[inline]
    pub(super) fn width(&self, d: f32, s: f32, r: f32) -> f32 {
        filter_width(self.prefilter, d, s, r, self.h0)
    }

    /// The `n` depths of the ray from `p` along `dir` (unit), for a light of size `s` and
    /// radius `r`, depths at `reach/n … reach` (the first `n` of the array), and the density
    /// samples taken: midpoint rule between consecutive depths ([`Tracer::schedule`]: the same
    /// steps for every ray of a light),
    /// samples outside the density's box adding nothing. Samples in empty space are jumped
    /// over (they would add exactly 0); once the ray has left the box (for a light inside it),
    /// or `τ` has passed [`TAU_MAX`], the rest is not traced (every later depth is stored as it
    /// is, or as `TAU_MAX`). Module `avx2` traces eight rays of a light abreast with exactly
    /// these operations.
    fn trace(&self, p: Vec3, dir: Vec3, s: f32, r: f32, reach: f32) -> ([f32; MAX_DEPTHS], u32) {
        let spacing = reach / self.n as f32;
        let mut fit = Fit::new(self.n);
        let fitted = self.depths == Depths::Fitted;
        let (at, samples) = self.march(p, dir, s, r, reach, |d, dt, rho, tau, dtau| {
            if fitted && rho > 0.0 {
                // The sample stands for the step: τ at its middle, weight ρ·V²·dt.
                let mid = tau + 0.5 * dtau;
                let w = rho * lookup::exp_neg((2.0 * mid).min(80.0)) * dt;
                fit.add(d / spacing, mid, w);
            }
        });
        let depths = match self.depths {
            Depths::Fitted => fit.solve(&at, 1e-6 * spacing),
            Depths::Sampled | Depths::Adaptive => at,
        };
        (depths, samples)
    }

    /// The ray from `p` along `dir` of [`trace`](Self::trace) marched the same way, its `n`
    /// adaptive knots (module `knots`) for lookups over `support` stored into `out`; returns
    /// the density samples taken.
    fn trace_knots(
        &self,
        (p, dir, support): (Vec3, Vec3, Support),
        (s, r, reach): (f32, f32, f32),
        out: &mut [u16],
    ) -> u32 {
        let mut knots = Knots::new(self.n, support, reach);
        let (at, samples) = self.march(p, dir, s, r, reach, |d, dt, _, tau, dtau| {
            if dtau > 0.0 {
                knots.step(d - 0.5 * dt, tau, d + 0.5 * dt, tau + dtau);
            }
        });
        knots.store(at[self.n - 1], out);
        samples
    }

    /// The march of [`trace`](Self::trace): `τ` at the `n` depths and the density samples
    /// taken; each sample at distance `d` standing for a step `dt` of density `rho`, reached
    /// with optical depth `tau` and adding `dtau`, is also handed to `step`.
    #[inline]
    fn march(
        &self,
        p: Vec3,
        dir: Vec3,
        s: f32,
        r: f32,
        reach: f32,
        mut step: impl FnMut(f32, f32, f32, f32, f32),
    ) -> ([f32; MAX_DEPTHS], u32) {
        let spacing = reach / self.n as f32;
        let p_inside = self.inside(p);
        let mut samples = 0u32;
        let mut tau = 0.0f32;
        let mut at = [0.0f32; MAX_DEPTHS];
        let mut look_again = 0.0f32;
        let mut live = true;
        for (k, at_k) in at.iter_mut().enumerate().take(self.n) {
            if live {
                let (a, n, dt) = self.schedule(k, spacing, s, r);
                let mut i = 0;
                while i < n {
                    let d = a + (i as f32 + 0.5) * dt;
                    let x = p + dir * d;
                    if !self.inside(x) {
                        if p_inside {
                            live = false; // a convex box is not entered again
                            break;
                        }
                        i += 1;
                        continue;
                    }
                    let width = self.width(d, s, r);
                    // In or near smoke: look again two blocks further on (a clear stretch
                    // shorter than that is sampled, which only costs time).
                    if self.skip_empty && d >= look_again {
                        let margin = self.empty.clearance(x) - 3.0 * width.max(self.h0);
                        if margin >= 0.0 {
                            i += (margin / dt) as u32 + 1;
                            continue;
                        }
                        look_again = d + 2.0 * self.empty.block();
                    }
                    let rho = self.pyramid.sample(x, width);
                    samples += 1;
                    let dtau = self.kappa * rho * dt;
                    step(d, dt, rho, tau, dtau);
                    tau += dtau;
                    i += 1;
                    if tau > TAU_MAX {
                        live = false;
                        break;
                    }
                }
            }
            *at_k = tau;
        }
        (at, samples)
    }

    /// Interval `k`'s steps (between depths `k` and `k + 1`, `spacing` apart), the same for
    /// every ray of a light: its start, the step count and the step, `max(min_step, δ/2)` with
    /// `δ` the narrower filter width at its two ends.
    #[inline]
    pub(super) fn schedule(&self, k: usize, spacing: f32, s: f32, r: f32) -> (f32, u32, f32) {
        let a = k as f32 * spacing;
        let b = (k + 1) as f32 * spacing;
        let widest = self.width(a, s, r).min(self.width(b, s, r));
        let step = self.min_step.max(0.5 * widest);
        let n = (spacing / step).ceil().max(1.0) as u32;
        (a, n, spacing / n as f32)
    }

    /// Whether `x` is in the density's box (faces included).
    #[inline]
    pub(super) fn inside(&self, x: Vec3) -> bool {
        super::in_box(x, self.lo, self.hi)
    }
}

/// The depths as stored in `out`: `τ` clamped to `[0, TAU_MAX]`, rounded to 16 bits.
fn quantise(tau: &[f32], out: &mut [u16]) {
    for (o, &t) in out.iter_mut().zip(tau) {
        *o = (t.clamp(0.0, TAU_MAX) * QUANT + 0.5) as u16;
    }
}

/// The weighted least-squares fit of a piecewise-linear `τ(q)` through `(0, 0)` and `n` knots
/// at `q = 1 … n` (distances in spacings of the depths): normal equations of the hat basis,
/// tridiagonal.
#[derive(Clone, Copy, Debug)]
pub(super) struct Fit {
    /// Knots.
    pub(super) n: usize,
    /// Diagonal and upper diagonal of the normal matrix.
    pub(super) diag: [f64; MAX_DEPTHS],
    pub(super) upper: [f64; MAX_DEPTHS - 1],
    pub(super) rhs: [f64; MAX_DEPTHS],
}

impl Fit {
    /// No samples yet, `n` knots.
    pub(super) fn new(n: usize) -> Self {
        Fit {
            n,
            diag: [0.0; MAX_DEPTHS],
            upper: [0.0; MAX_DEPTHS - 1],
            rhs: [0.0; MAX_DEPTHS],
        }
    }

    /// Adds a sample of `tau` at `q` spacings with weight `w`.
    #[inline]
    fn add(&mut self, q: f32, tau: f32, w: f32) {
        // q in [k, k + 1]: hats k (weight 1 − t, absent for k = 0) and k + 1 (weight t).
        let k = (q as usize).min(self.n - 1);
        let t = f64::from(q - k as f32).clamp(0.0, 1.0);
        let (w, tau) = (f64::from(w), f64::from(tau));
        let hi = k; // knot k + 1 is index k
        self.diag[hi] += w * t * t;
        self.rhs[hi] += w * t * tau;
        if k > 0 {
            let lo = k - 1;
            self.diag[lo] += w * (1.0 - t) * (1.0 - t);
            self.rhs[lo] += w * (1.0 - t) * tau;
            self.upper[lo] += w * (1.0 - t) * t;
        }
    }

    /// The knots' values, pulled towards `sampled` (the traced values at the knots) with weight
    /// `ridge`, which decides wherever the samples leave a knot free (no smoke near it).
    pub(super) fn solve(mut self, sampled: &[f32], ridge: f32) -> [f32; MAX_DEPTHS] {
        let n = self.n;
        for (k, &s) in sampled.iter().enumerate().take(n) {
            self.diag[k] += f64::from(ridge);
            self.rhs[k] += f64::from(ridge) * f64::from(s);
        }
        // Thomas algorithm (the matrix is symmetric positive definite: no pivoting needed).
        let mut c = [0.0f64; MAX_DEPTHS];
        let mut d = [0.0f64; MAX_DEPTHS];
        if n > 1 {
            c[0] = self.upper[0] / self.diag[0];
        }
        d[0] = self.rhs[0] / self.diag[0];
        for k in 1..n {
            let m = self.diag[k] - self.upper[k - 1] * c[k - 1];
            if k + 1 < n {
                c[k] = self.upper[k] / m;
            }
            d[k] = (self.rhs[k] - self.upper[k - 1] * d[k - 1]) / m;
        }
        let mut x = [0.0f64; MAX_DEPTHS];
        x[n - 1] = d[n - 1];
        for k in (0..n - 1).rev() {
            x[k] = d[k] - c[k] * x[k + 1];
        }
        x.map(|v| v as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};

    /// A volume of `n`³ voxels of size 1/16 centred on the origin, density `f(centre)`.
    fn volume(n: usize, f: impl Fn(Vec3) -> f32) -> Volume {
        let h = 1.0 / 16.0;
        let origin = Vec3::splat(-0.5 * h * (n - 1) as f32);
        let mut density = DenseGrid::zeros([n; 3], h, origin);
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let idx = density.index(i, j, k);
                    density.data[idx] = f(density.centre(i, j, k));
                }
            }
        }
        let temperature = density.clone();
        Volume::new(density, temperature)
    }

    /// One light at `p`, on the volume's grid (`h1 = 2h`), blended at `alpha`.
    fn one_light(v: &Volume, p: Vec3, alpha: f32) -> (LightingGridHierarchy, Blending) {
        let h = v.density.voxel_size;
        let settings = GridSettings {
            h1: Some(2.0 * h),
            origin: Some(v.density.origin),
            ..Default::default()
        };
        let lgh =
            LightingGridHierarchy::build(&[PointLight::new(p, Vec3::ONE)], &settings).unwrap();
        let b = lgh.blending(alpha).unwrap();
        (lgh, b)
    }

    /// Two blobs of smoke with empty space between, 30³ voxels, and a medium dense enough that
    /// maps through them vary: what the tracing tests trace through.
    fn two_blobs() -> (Volume, Medium) {
        let v = blobs(
            30,
            Vec3::new(0.3, 0.2, 0.1),
            Vec3::new(-0.5, -0.4, 0.0),
            6.0,
        );
        (v, Medium::new(2.0, 1.0, 0.0, 0.0).unwrap())
    }

    /// Two blobs of smoke (peak density `peak`) with empty space between, on an `n`³ grid.
    fn blobs(n: usize, a: Vec3, b: Vec3, peak: f32) -> Volume {
        volume(n, |c| {
            let blob = |o: Vec3, r: f32| (1.0 - (c - o).length() / r).max(0.0) * peak;
            blob(a, 0.4) + blob(b, 0.3)
        })
    }

    /// A tracer through `pyramid` of `v` in a medium of extinction `kappa` per unit density.
    fn tracer<'a>(
        pyramid: &'a DensityPyramid,
        empty: &'a EmptySpace,
        v: &Volume,
        kappa: f32,
        (skip_empty, simd, depths): (bool, bool, Depths),
    ) -> Tracer<'a> {
        let (lo, hi) = v.density.bounds();
        Tracer {
            pyramid,
            empty,
            skip_empty,
            simd,
            kappa,
            lo,
            hi,
            h0: v.density.voxel_size,
            min_step: v.density.voxel_size,
            prefilter: true,
            depths,
            n: 4,
        }
    }

    /// The older demo's explosion at 32³, its lights and their hierarchy's blending at α = 2.
    fn demo32() -> (Volume, Medium, crate::ExplosionLights) {
        let v = crate::procedural(32, 0.5).unwrap();
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let lights = crate::ExplosionLights::new(&[&v], &m).unwrap();
        (v, m, lights)
    }

    fn settings(depths: Depths) -> CubeMapSettings {
        CubeMapSettings {
            depths,
            ..Default::default()
        }
    }

    #[test]
    fn in_a_homogeneous_medium_the_map_is_beer_lambert_up_to_quantisation() {
        // τ(d) = σ_t d along every ray inside the box: linear in d (the four depths interpolate
        // it exactly, sampled or fitted), the same in every direction (bilinear is exact), the
        // midpoint rule exact. What remains is the 16-bit quantisation, ≤ TAU_MAX/131070 =
        // 1.22e-4 in τ, so |V_map/V − 1| ≤ 1.3e-4, plus f32 rounding (τ ≤ 3: ~1e-6).
        let v = volume(32, |_| 1.5);
        let m = Medium::new(1.0, 1.0, 0.0, 0.0).unwrap(); // σ_t = 3 per unit density... ×1.5
        let p = Vec3::new(0.013, -0.021, 0.007);
        let (lgh, b) = one_light(&v, p, 4.0); // r_0 = 4h, depths to 8h = 0.5: inside the box
                                              // Every lookup of maps of `n` values of `depths` is `within` its exact value.
        let check = |depths, n, within: &dyn Fn(f32, f32) -> bool| {
            let settings = CubeMapSettings {
                depth_count: n,
                ..settings(depths)
            };
            let maps = CubeMaps::build(Casters::new(&lgh, &b), &v, &m, &settings, &|_| {}).unwrap();
            let mut rng = lgh_core::random::SplitMix64(2);
            for _ in 0..2000 {
                let x = p + rng.next_in(Vec3::splat(-0.3), Vec3::splat(0.3));
                let d = (x - p).length();
                let want = (-m.extinction(1.5) * d.min(0.5)).exp();
                let got = maps.transmittance(x, 0, 0, p);
                assert!(
                    within(got, want),
                    "{depths:?} {n}, d = {d}: {got} vs {want}"
                );
            }
        };
        for (depths, n) in [
            (Depths::Fitted, 4),
            (Depths::Sampled, 4),
            (Depths::Fitted, 8),
        ] {
            check(depths, n, &|got, want| {
                (got / want - 1.0).abs() < 1.3e-4 + 2e-6
            });
        }
        // Adaptive knots: the nodes are collinear in τ, which the lookup interpolates, so any
        // knots hold it; what remains is their 8-bit quantisation. A knot's distance moves by
        // at most half a 255th of the reach 0.5, τ by σ_t = 4.5 times that (0.0044); its value
        // by half a 255th of V ≥ e^{−2.25} at the reach, τ by at most 0.5 / (255 · 0.105) =
        // 0.0187. So |ln(V_map / V)| ≤ 0.0231.
        let bound = 4.5 * 0.25 / 255.0 + 0.5 / (255.0 * (-2.25f32).exp()) + 1e-5;
        for n in [2, 4, 8] {
            check(Depths::Adaptive, n, &|got, want| {
                (got / want).ln().abs() < bound
            });
        }
    }

    #[test]
    fn along_texel_directions_sampled_depths_err_by_the_interpolation_bound() {
        // ρ = 3 + 4 x_a along each axis a in turn (positive wherever the rays and their lookups
        // reach; clamped at 0 far away, where the grid is no density): linear, so trilinear
        // lookups and the midpoint rule are exact, and along a texel's direction ω from p,
        // τ(d) = σ_t (ρ(p) d + 2 ω_a d²)
        // is quadratic. The four sampled depths interpolate it with error ≤ Q²/8 · |τ''| =
        // Q² σ_t |ω_a| / 2 (Q the spacing of the depths); plus quantisation (1.22e-4). Every
        // axis, so that a face laid out with two axes swapped cannot pass.
        for axis in 0..3 {
            let v = volume(40, |c| (3.0 + 4.0 * c[axis]).max(0.0));
            let m = Medium::new(1.0, 0.0, 0.0, 0.0).unwrap();
            let p = Vec3::new(0.02, 0.01, -0.03);
            let (lgh, b) = one_light(&v, p, 4.0);
            let maps = CubeMaps::build(
                Casters::new(&lgh, &b),
                &v,
                &m,
                &settings(Depths::Sampled),
                &|_| {},
            )
            .unwrap();
            let slot = maps.levels[0].slots[0];
            let reach = 4.0 / maps.levels[0].inv_spacing;
            let q = reach / 4.0;
            let sigma = m.extinction(1.0);
            let mut worst = 0.0f32;
            for face in 0..6 {
                for j in 0..cube::side(slot.cells) {
                    for i in 0..cube::side(slot.cells) {
                        let w = cube::direction(face, i, j, slot.cells).normalize();
                        for t in 1..40 {
                            let d = reach * t as f32 / 40.0;
                            let x = p + w * d;
                            let exact = sigma * ((3.0 + 4.0 * p[axis]) * d + 2.0 * w[axis] * d * d);
                            let got = -maps.transmittance(x, 0, 0, p).ln();
                            let bound = q * q * sigma * w[axis].abs() / 2.0 + 1.22e-4 + 1e-5;
                            assert!(
                                (got - exact).abs() <= bound,
                                "axis {axis} {w} d {d}: {got} vs {exact}"
                            );
                            worst = worst.max((got - exact).abs() / bound);
                        }
                    }
                }
            }
            // The bound is attained in order of magnitude (midway between depths), not loose.
            assert!(worst > 0.5, "axis {axis}: {worst}");
        }
    }

    #[test]
    fn the_fit_is_exact_for_piecewise_linear_depth_and_closer_than_samples_behind_a_shell() {
        // Exact: τ piecewise linear with knots at the depths (any positive weights).
        let tau =
            |q: f32| 0.3 * q.min(1.0) + 1.1 * (q - 1.0).clamp(0.0, 2.0) + 0.2 * (q - 3.0).max(0.0);
        let mut fit = Fit::new(4);
        for i in 0..400 {
            let q = (i as f32 + 0.5) / 100.0;
            fit.add(q, tau(q), 0.5 + (i % 7) as f32);
        }
        let knots = fit.solve(&[tau(1.0), tau(2.0), tau(3.0), tau(4.0)], 1e-9);
        for (k, &t) in knots.iter().take(4).enumerate() {
            assert!((t - tau(k as f32 + 1.0)).abs() < 1e-5, "{k}: {t}");
        }
        // A thin dense shell at q ∈ [1.4, 1.6], shading points (weight) all around it: the
        // sampled depths' chord misses τ around the shell; the fit's weighted squared error is
        // no larger (it is the least-squares optimum over the same piecewise-linear functions,
        // which include the chord; the ridge of 10⁻⁹ is negligible).
        let shell = |q: f32| 2.0 * ((q - 1.4).clamp(0.0, 0.2) / 0.2);
        let mut fit = Fit::new(4);
        let samples: Vec<f32> = (0..400).map(|i| (i as f32 + 0.5) / 100.0).collect();
        for &q in &samples {
            fit.add(q, shell(q), 1.0);
        }
        let sampled = [shell(1.0), shell(2.0), shell(3.0), shell(4.0)];
        let fitted = fit.solve(&sampled, 1e-9);
        let fitted: [f32; 4] = fitted[..4].try_into().unwrap();
        let err = |k: [f32; 4]| -> f32 {
            samples
                .iter()
                .map(|&q| {
                    let i = (q as usize).min(3);
                    let lo = if i == 0 { 0.0 } else { k[i - 1] };
                    let t = lo + (k[i] - lo) * (q - i as f32);
                    (t - shell(q)).powi(2)
                })
                .sum()
        };
        assert!(
            err(fitted) < err(sampled),
            "{} vs {}",
            err(fitted),
            err(sampled)
        );
    }

    #[test]
    fn jumping_over_empty_space_changes_no_bit() {
        // Smoke in a few blobs with empty space between: rays from lights of every size, with
        // and without jumps, must give the same four depths bit for bit.
        let v = blobs(
            36,
            Vec3::new(0.6, 0.5, 0.4),
            Vec3::new(-0.7, -0.6, 0.0),
            3.0,
        );
        let m = Medium::new(2.0, 1.0, 0.0, 0.0).unwrap();
        let pyramid = DensityPyramid::new(&v.density, 1.0);
        let empty = EmptySpace::new(&v.density);
        let (lo, hi) = v.density.bounds();
        let tracer = |skip| {
            tracer(
                &pyramid,
                &empty,
                &v,
                m.extinction(1.0),
                (skip, false, Depths::Fitted),
            )
        };
        let (with, without) = (tracer(true), tracer(false));
        let mut rng = lgh_core::random::SplitMix64(6);
        let mut shadowed = 0;
        for i in 0..3000 {
            let p = rng.next_in(lo, hi);
            let dir = rng.next_in(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize();
            let s = [0.0, 0.05, 0.3][i % 3];
            let r = [0.25, 0.5, 1.0][i % 3];
            let a = with.trace(p, dir, s, r, 2.0 * r).0;
            let b = without.trace(p, dir, s, r, 2.0 * r).0;
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{p} {dir}");
            shadowed += usize::from(a[3] > 0.0);
        }
        assert!(shadowed > 300, "{shadowed}");
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn batched_lookups_are_the_one_by_one_lookups_bit_for_bit() {
        // Without AVX2 both sides are the one-by-one code: nothing to compare.
        if !std::arch::is_x86_feature_detected!("avx2") {
            return lgh_tests::Piece::Avx2.missing("this CPU has no AVX2");
        }
        // Every level's lights, looked up from points all over the box and beyond, in batches of
        // every length (AVX2 eights and the scalar rest), with lights without a map (index out
        // of range, a level above the top), points on a light and non-finite points among them.
        let (v, m, lights) = demo32();
        let lgh = lights.hierarchy();
        let b = lgh.blending(2.0).unwrap();
        for n in [2, 4, 8, MAX_DEPTHS] {
            batched_lookups_match(&v, &m, lgh, &b, (Depths::Fitted, n));
        }
        // Adaptive knots: eight abreast for an even count, one by one for an odd one.
        for n in [2, 3, 4, 8] {
            batched_lookups_match(&v, &m, lgh, &b, (Depths::Adaptive, n));
        }
    }

    /// [`batched_lookups_are_the_one_by_one_lookups_bit_for_bit`] with `n` depths a texel.
    fn batched_lookups_match(
        v: &Volume,
        m: &Medium,
        lgh: &LightingGridHierarchy,
        b: &Blending,
        (depths, n): (Depths, usize),
    ) {
        let settings = CubeMapSettings {
            depth_count: n,
            ..settings(depths)
        };
        let maps = CubeMaps::build(Casters::new(lgh, b), v, m, &settings, &|_| {}).unwrap();
        let (lo, hi) = v.density.bounds();
        let mut rng = lgh_core::random::SplitMix64(12);
        let mut all: Vec<(Vec3, (u8, u32))> = Vec::new();
        for level in 0..=lgh.max_level() {
            for (i, l) in lgh.level(level).iter().enumerate() {
                all.push((l.position, (level, i as u32)));
            }
        }
        all.push((Vec3::ZERO, (0, u32::MAX)));
        all.push((Vec3::ZERO, (lgh.max_level() + 1, 0)));
        let (mut shadowed, mut out) = (0, Vec::new());
        for s in 0..300 {
            let x = match s % 50 {
                0 => Vec3::NAN,
                1 => all[s].0,
                _ => rng.next_in(lo - 0.2, hi + 0.2),
            };
            let count = (s * 13) % 70;
            let batch: Vec<(Vec3, (u8, u32))> = (0..count)
                .map(|i| all[(s * 977 + i * 31) % all.len()])
                .collect();
            let centres: Vec<Vec3> = batch.iter().map(|b| b.0).collect();
            let ids: Vec<(u8, u32)> = batch.iter().map(|b| b.1).collect();
            maps.transmittances(x, &centres, &ids, &mut out);
            for (&(c, (level, index)), &t) in batch.iter().zip(&out) {
                let want = maps.transmittance(x, level, index, c);
                assert_eq!(
                    t.to_bits(),
                    want.to_bits(),
                    "{n} depths: {x} {level} {index}"
                );
                shadowed += usize::from(t < 0.99);
            }
        }
        assert!(shadowed > 500, "{shadowed}");
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn texel_rays_eight_abreast_are_the_one_by_one_rays_bit_for_bit() {
        // Without AVX2 both sides are the one-by-one code: nothing to compare.
        if !std::arch::is_x86_feature_detected!("avx2") {
            return lgh_tests::Piece::Avx2.missing("this CPU has no AVX2");
        }
        // Lights of every size inside and outside the box, in smoke with empty space between
        // blobs, both depth rules: whole maps traced with and without AVX2 must agree.
        let (v, m) = two_blobs();
        let pyramid = DensityPyramid::new(&v.density, 0.5);
        let empty = EmptySpace::new(&v.density);
        let (lo, hi) = v.density.bounds();
        let mut rng = lgh_core::random::SplitMix64(31);
        let mut compared = 0;
        for (depths, n) in [
            (Depths::Fitted, 4),
            (Depths::Sampled, 4),
            (Depths::Fitted, 8),
            (Depths::Sampled, 8),
            (Depths::Fitted, MAX_DEPTHS),
            (Depths::Adaptive, 4),
            (Depths::Adaptive, MAX_DEPTHS),
        ] {
            let tracer = |simd| Tracer {
                n,
                ..tracer(
                    &pyramid,
                    &empty,
                    &v,
                    m.extinction(1.0),
                    (true, simd, depths),
                )
            };
            let (fast, slow) = (tracer(true), tracer(false));
            for i in 0..24 {
                let p = if i % 6 == 5 {
                    rng.next_in(lo - 0.3, hi + 0.3)
                } else {
                    rng.next_in(lo, hi)
                };
                let s = [0.0, 0.03, 0.12, 0.4][i % 4];
                let r = [0.125, 0.25, 0.5][i % 3];
                let cells = [3u32, 4, 9][i % 3];
                let mut a = vec![0u16; cube::texels(cells) * n];
                let mut b = a.clone();
                fast.trace_map(&mut a, p, s, r, 2.0 * r, cells);
                slow.trace_map(&mut b, p, s, r, 2.0 * r, cells);
                assert_eq!(a, b, "{depths:?} {n} depths: light {i} at {p}");
                compared += a.chunks(n).filter(|t| t[n - 1] > 0).count();
            }
        }
        assert!(compared > 1000, "{compared}");
    }

    #[test]
    fn a_map_traced_in_tiles_is_the_map_traced_whole() {
        // Maps large enough to be cut (a face side of 65 and 129 texels: 15 and 7 rows a
        // tile) and one smaller than a tile; tiles of rows traced apart, eight texels abreast
        // from each tile's first, give the whole map's bits, and as many tiles as planned.
        let (v, m) = two_blobs();
        let pyramid = DensityPyramid::new(&v.density, 0.5);
        let empty = EmptySpace::new(&v.density);
        for (depths, cells) in [
            (Depths::Fitted, 4u32),
            (Depths::Fitted, 64),
            (Depths::Fitted, 128),
            (Depths::Adaptive, 64),
        ] {
            let tracer = tracer(
                &pyramid,
                &empty,
                &v,
                m.extinction(1.0),
                (true, true, depths),
            );
            let light = Planned {
                index: 0,
                centre: Vec3::new(0.1, -0.2, 0.05),
                size: 0.1,
                cells,
                support: Support::FLAT,
            };
            let (r, n) = (0.5, tracer.n);
            let mut whole = vec![0u16; cube::texels(cells) * n];
            tracer.trace_map(&mut whole, light.centre, light.size, r, 2.0 * r, cells);
            let mut tiled = vec![0u16; whole.len()];
            let tiles: Vec<Tile> = tiles_of(&mut tiled, light, n).collect();
            assert_eq!(tiles.len(), tile_count(cells), "{cells} cells");
            assert!(tiles.iter().all(|t| t.texels.len() <= TILE_TEXELS * n));
            for tile in tiles {
                tracer.trace_tile(tile, r, 2.0 * r);
            }
            assert_eq!(tiled, whole, "{cells} cells");
            assert!(whole.iter().any(|&q| q > 0));
        }
    }

    #[test]
    fn maps_do_not_depend_on_the_thread_count_and_oversized_plans_are_refused() {
        let (v, m, lights) = demo32();
        let lgh = lights.hierarchy();
        let b = lgh.blending(2.0).unwrap();
        let build = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    CubeMaps::build(
                        Casters::new(lgh, &b),
                        &v,
                        &m,
                        &settings(Depths::Adaptive),
                        &|_| {},
                    )
                })
                .unwrap()
        };
        let one = build(1);
        let three = build(3);
        assert!(one.lights() > 100);
        for (a, b) in one.levels.iter().zip(&three.levels) {
            assert_eq!(a.slots, b.slots);
        }
        assert_eq!(one.texels, three.texels);
        // The plan's bytes are what was built; a budget one byte short refuses before tracing.
        let plan = CubeMaps::plan(Casters::new(lgh, &b), &v.density, &settings(Depths::Fitted));
        assert_eq!(plan.bytes(), one.bytes());
        let tight = CubeMapSettings {
            memory_budget: plan.bytes() + plan.pyramid_bytes - 1,
            ..Default::default()
        };
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let err = CubeMaps::build(Casters::new(lgh, &b), &v, &m, &tight, &|_| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap_err();
        assert!(matches!(err, RenderError::ShadowMemory { .. }), "{err}");
        assert_eq!(calls.into_inner(), 0);
    }
}
