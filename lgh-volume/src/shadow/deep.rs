//! Deep-shadow cube maps: the paper's precomputed volumetric shadows (Sec. 4, Table 1).
//!
//! Every light of every level of the hierarchy only lights points within `2 r_ℓ` of it
//! (`r_ℓ = α h_ℓ`, the blending function `B_ℓ` is zero beyond). So its shadow can be precomputed
//! once per frame, at a resolution fixed by `r_ℓ`: a cube map whose cells are `h` (a voxel) wide
//! at distance `r_ℓ`, where `B_ℓ` peaks — `R = ⌈2 r_ℓ / h⌉` cells per face side, `24 (r_ℓ/h)²` in
//! all — each texel storing the optical depth `τ` along its direction at four distances
//! `D/4, D/2, 3D/4, D` (`D = 2 r_ℓ`; the top level, whose lights reach everything, and any level
//! whose `2 r_ℓ` exceeds the density's box, take the box's diagonal). A lookup interpolates
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
//! **What is stored at the four depths.** The paper records `τ` at the four distances. We can
//! do that ([`Depths::Sampled`]), but a piecewise-linear `τ` through four samples leaks light
//! wherever a shell of smoke lies between two of them (the chord lies below the step), and the
//! shading points that matter are exactly those in the smoke. [`Depths::Fitted`], the default,
//! stores instead the four values whose piecewise-linear `τ` is closest, in least squares, to the
//! traced `τ` at the ray's samples, each weighted by what an error there costs the image:
//! the density there (the scattering a shading point adds is `∝ ρ`) times `V² = e^{−2τ}` (an
//! error `Δτ` changes `V` by `V·Δτ`). Same storage, same lookup.
//!
//! **Storage.** `τ` is quantised to 16 bits on `[0, TAU_MAX]`: an absolute error of at most
//! `TAU_MAX / 131070 ≈ 1.2·10⁻⁴` in `τ`, a relative error of at most that in `V`; depths beyond
//! `TAU_MAX` (`V < 1.1·10⁻⁷`) are stored as `TAU_MAX`. Eight bytes a texel.
//!
//! The maps are traced in parallel (rayon), one light at a time, each into its own slice: the
//! result does not depend on the thread count. Nothing is allocated per texel.

use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::{Blending, LightingGridHierarchy};
use rayon::prelude::*;

use super::cube;
use super::prefilter::DensityPyramid;
use crate::error::VolumeError;
use crate::grid::DenseGrid;
use crate::medium::{Medium, Volume};

/// The largest optical depth a texel stores (`V = e^{−16} ≈ 1.1·10⁻⁷`).
pub const TAU_MAX: f32 = 16.0;

/// Quantisation steps per unit of optical depth.
const QUANT: f32 = 65535.0 / TAU_MAX;

/// A light without a map (dark, or pruned: queries never return it).
const NO_MAP: u32 = u32::MAX;

/// What the four depths of a texel hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Depths {
    /// The least-squares fit of the traced `τ`, weighted by density × `V²` (see the module docs).
    #[default]
    Fitted,
    /// `τ` at the four distances, as the paper records it.
    Sampled,
}

/// How the maps are traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubeMapSettings {
    /// Shortest step along a texel ray, in voxels (longer where the prefilter is wider).
    pub step_voxels: f32,
    /// Coarse lights as volume lights through the prefiltered density (eq. 6); `false` traces
    /// every light as a point through the plain density (the flickering variant the paper
    /// compares against).
    pub prefilter: bool,
    /// What the four depths hold.
    pub depths: Depths,
    /// Bytes the maps may take; a plan above it is refused before any work.
    pub memory_budget: u64,
}

impl Default for CubeMapSettings {
    fn default() -> Self {
        CubeMapSettings {
            step_voxels: 1.0,
            prefilter: true,
            depths: Depths::Fitted,
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
    /// Cells per face side `R`.
    pub cells: u32,
    /// Distance of the last stored depth `D`.
    pub reach: f32,
    /// Bytes of the level's maps and index.
    pub bytes: u64,
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
}

impl CubeMapPlan {
    /// Bytes of all the maps.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.levels.iter().map(|l| l.bytes).sum()
    }
}

/// One level's maps.
#[derive(Clone, Debug)]
struct Level {
    cells: u32,
    /// 4 / D: quarters of the reach per unit distance.
    inv_quarter: f32,
    /// First texel of each light's map, or [`NO_MAP`].
    offsets: Vec<u32>,
    /// Quantised `τ` at the four depths, `6 (R + 1)²` texels per map.
    texels: Vec<[u16; 4]>,
}

/// The deep-shadow cube maps of one frame's hierarchy at one α (see the module docs).
#[derive(Clone, Debug)]
pub struct CubeMaps {
    levels: Vec<Level>,
    table: Vec<LevelMaps>,
}

/// The lights of `level` that queries return, with their index, centre and size.
fn active(h: &LightingGridHierarchy, level: u8) -> Vec<(u32, Vec3, f32)> {
    h.level(level)
        .iter()
        .enumerate()
        .filter(|(_, l)| h.is_active(level, l))
        .map(|(i, l)| (i as u32, l.position, l.size))
        .collect()
}

/// `R` and `D` of `level`: cells `h` wide at `r_ℓ`, depths to `2 r_ℓ`; the top level, or a
/// level reaching beyond the box, to the box's diagonal (and no finer than `h` there).
fn resolution(blending: &Blending, level: u8, h: f32, diagonal: f32) -> (u32, f32) {
    let r = blending.radius(level);
    let top = level == blending.max_level();
    let reach = if top {
        diagonal
    } else {
        (2.0 * r).min(diagonal)
    };
    let cells = (2.0 * r / h).min(2.0 * diagonal / h).ceil().max(1.0);
    (cells.min(1e6) as u32, reach)
}

impl CubeMaps {
    /// The maps [`build`](Self::build) would make for `hierarchy` at `blending`'s α over
    /// `density`, level by level, with their exact sizes: cheap (no tracing).
    #[must_use]
    pub fn plan(
        hierarchy: &LightingGridHierarchy,
        blending: &Blending,
        density: &DenseGrid,
    ) -> CubeMapPlan {
        let h = density.voxel_size;
        let (lo, hi) = density.bounds();
        let diagonal = (hi - lo).length();
        let levels = (0..=hierarchy.max_level())
            .map(|level| {
                let lights = hierarchy
                    .level(level)
                    .iter()
                    .filter(|l| hierarchy.is_active(level, l))
                    .count();
                let (cells, reach) = resolution(blending, level, h, diagonal);
                let texels = cube::texels(cells) as u64 * lights as u64;
                LevelMaps {
                    level,
                    lights,
                    cells,
                    reach,
                    bytes: texels * 8 + hierarchy.level(level).len() as u64 * 4,
                    seconds: 0.0,
                }
            })
            .collect();
        CubeMapPlan {
            levels,
            pyramid_bytes: density.data.len() as u64 * 4 * 8 / 7,
        }
    }

    /// Traces the maps of every light of `hierarchy` (at `blending`'s α) through `volume`'s
    /// density in `medium`. Refused before any work, with [`VolumeError::ShadowMemory`], if the
    /// [`plan`](Self::plan) exceeds `settings.memory_budget`. `progress(n)` as each batch of `n`
    /// lights is done.
    pub fn build(
        hierarchy: &LightingGridHierarchy,
        blending: &Blending,
        volume: &Volume,
        medium: &Medium,
        settings: &CubeMapSettings,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, VolumeError> {
        crate::error::check_setting(
            (0.01..=64.0).contains(&settings.step_voxels),
            "cube maps: step",
            settings.step_voxels,
            "must be 0.01 to 64 voxels",
        )?;
        let density = &volume.density;
        let plan = CubeMaps::plan(hierarchy, blending, density);
        let needed = plan.bytes() + plan.pyramid_bytes;
        if needed > settings.memory_budget
            || plan.levels.iter().any(|l| l.bytes / 8 >= u64::from(NO_MAP))
        {
            return Err(VolumeError::ShadowMemory {
                needed,
                budget: settings.memory_budget,
                alpha: blending.alpha(),
            });
        }
        let h = density.voxel_size;
        let max_size = (0..=hierarchy.max_level())
            .flat_map(|l| hierarchy.level(l).iter().map(|g| g.size))
            .fold(0.0f32, f32::max);
        let pyramid = DensityPyramid::new(density, if settings.prefilter { max_size } else { 0.0 });
        let (lo, hi) = density.bounds();
        let tracer = Tracer {
            pyramid: &pyramid,
            kappa: medium.extinction(1.0),
            lo,
            hi,
            h0: h,
            min_step: settings.step_voxels * h,
            prefilter: settings.prefilter,
            depths: settings.depths,
        };
        let mut levels = Vec::new();
        let mut table = Vec::new();
        for row in &plan.levels {
            let t = Instant::now();
            let lights = active(hierarchy, row.level);
            let per_map = cube::texels(row.cells);
            let mut offsets = vec![NO_MAP; hierarchy.level(row.level).len()];
            for (n, &(i, _, _)) in lights.iter().enumerate() {
                offsets[i as usize] = (n * per_map) as u32;
            }
            let mut texels = vec![[0u16; 4]; lights.len() * per_map];
            let r = blending.radius(row.level);
            // Batches of lights so that progress is reported as the work goes (the maps of a
            // batch are traced in parallel; each map depends only on its light).
            let batch = (1 << 20) / per_map.max(1) + 1;
            for (maps, lights) in texels.chunks_mut(batch * per_map).zip(lights.chunks(batch)) {
                maps.par_chunks_mut(per_map)
                    .zip(lights.par_iter())
                    .for_each(|(map, &(_, p, s))| {
                        tracer.trace_map(map, p, s, r, row.reach, row.cells);
                    });
                progress(lights.len());
            }
            levels.push(Level {
                cells: row.cells,
                inv_quarter: 4.0 / row.reach,
                offsets,
                texels,
            });
            table.push(LevelMaps {
                seconds: t.elapsed().as_secs_f64(),
                ..*row
            });
        }
        Ok(CubeMaps { levels, table })
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
        let Some(l) = self.levels.get(level as usize) else {
            return 1.0;
        };
        let off = l.offsets.get(index as usize).copied().unwrap_or(NO_MAP);
        let v = x - centre;
        let d = v.length();
        if off == NO_MAP || d.is_nan() || d <= 0.0 {
            return 1.0;
        }
        let f = cube::footprint(v, l.cells);
        let map = &l.texels[off as usize..];
        let q = d * l.inv_quarter;
        let k = (q as usize).min(4);
        let depth = |k: usize| cube::bilinear(&f, l.cells, |t| f32::from(map[t][k]));
        let quantised = if k >= 4 {
            depth(3)
        } else {
            let lo = if k == 0 { 0.0 } else { depth(k - 1) };
            let hi = depth(k);
            lo + (hi - lo) * (q - k as f32)
        };
        (-quantised * (1.0 / QUANT)).exp()
    }
}

/// What tracing a texel ray needs.
struct Tracer<'a> {
    pyramid: &'a DensityPyramid,
    /// `σ_t` per unit density.
    kappa: f32,
    /// The density's box.
    lo: Vec3,
    hi: Vec3,
    /// `h_0`, the filter width at `r_ℓ` (the voxel size).
    h0: f32,
    /// Shortest step, world units.
    min_step: f32,
    prefilter: bool,
    depths: Depths,
}

impl Tracer<'_> {
    /// Traces the map of the light at `p` of size `s`, blending radius `r`, depths to `reach`.
    fn trace_map(&self, map: &mut [[u16; 4]], p: Vec3, s: f32, r: f32, reach: f32, cells: u32) {
        let side = cube::side(cells);
        for face in 0..6 {
            for j in 0..side {
                for i in 0..side {
                    let dir = cube::direction(face, i, j, cells).normalize();
                    let tau = self.trace(p, dir, s, r, reach);
                    map[(face * side + j) * side + i] =
                        tau.map(|t| (t.clamp(0.0, TAU_MAX) * QUANT).round() as u16);
                }
            }
        }
    }

    /// The filter width `δ(d)` of eq. 6 (0, the plain density, for points and beyond `r`).
    #[inline]
    fn width(&self, d: f32, s: f32, r: f32) -> f32 {
        if self.prefilter && d < r {
            (1.0 - d / r) * s + (d / r) * self.h0
        } else {
            0.0
        }
    }

    /// The four depths of the ray from `p` along `dir` (unit), for a light of size `s` and
    /// radius `r`, depths at `reach/4 … reach`: midpoint rule over the part of each quarter
    /// inside the density's box, in steps of `max(min_step, δ/2)`.
    fn trace(&self, p: Vec3, dir: Vec3, s: f32, r: f32, reach: f32) -> [f32; 4] {
        let Some((t0, t1)) = crate::grid::slab(p, dir, self.lo, self.hi) else {
            return [0.0; 4];
        };
        let quarter = reach / 4.0;
        let mut tau = 0.0f32;
        let mut at = [0.0f32; 4];
        let mut fit = Fit::default();
        for (k, at_k) in at.iter_mut().enumerate() {
            let a = (k as f32 * quarter).max(t0);
            let b = ((k + 1) as f32 * quarter).min(t1);
            if b > a {
                let widest = self.width(a, s, r).min(self.width(b, s, r));
                let step = self.min_step.max(0.5 * widest);
                let n = ((b - a) / step).ceil().max(1.0);
                let dt = (b - a) / n;
                for i in 0..n as u32 {
                    let d = a + (i as f32 + 0.5) * dt;
                    let rho = self.pyramid.sample(p + dir * d, self.width(d, s, r));
                    let dtau = self.kappa * rho * dt;
                    if self.depths == Depths::Fitted && rho > 0.0 {
                        // The sample stands for the step: τ at its middle, weight ρ·V²·dt.
                        let mid = tau + 0.5 * dtau;
                        fit.add(d / quarter, mid, rho * (-2.0 * mid).exp() * dt);
                    }
                    tau += dtau;
                }
            }
            *at_k = tau;
        }
        match self.depths {
            Depths::Sampled => at,
            Depths::Fitted => fit.solve(at, 1e-6 * quarter),
        }
    }
}

/// The weighted least-squares fit of a piecewise-linear `τ(q)` through `(0, 0)` and four knots
/// at `q = 1, 2, 3, 4` (distances in quarters of the reach): normal equations of the hat basis,
/// tridiagonal.
#[derive(Clone, Copy, Debug, Default)]
struct Fit {
    /// Diagonal and upper diagonal of the normal matrix.
    diag: [f64; 4],
    upper: [f64; 3],
    rhs: [f64; 4],
}

impl Fit {
    /// Adds a sample of `tau` at `q` quarters with weight `w`.
    #[inline]
    fn add(&mut self, q: f32, tau: f32, w: f32) {
        // q in [k, k + 1]: hats k (weight 1 − t, absent for k = 0) and k + 1 (weight t).
        let k = (q as usize).min(3);
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
    fn solve(mut self, sampled: [f32; 4], ridge: f32) -> [f32; 4] {
        for (k, &s) in sampled.iter().enumerate() {
            self.diag[k] += f64::from(ridge);
            self.rhs[k] += f64::from(ridge) * f64::from(s);
        }
        // Thomas algorithm (the matrix is symmetric positive definite: no pivoting needed).
        let mut c = [0.0f64; 3];
        let mut d = [0.0f64; 4];
        c[0] = self.upper[0] / self.diag[0];
        d[0] = self.rhs[0] / self.diag[0];
        for k in 1..4 {
            let m = self.diag[k] - self.upper[k - 1] * c[k - 1];
            if k < 3 {
                c[k] = self.upper[k] / m;
            }
            d[k] = (self.rhs[k] - self.upper[k - 1] * d[k - 1]) / m;
        }
        let mut x = [0.0f64; 4];
        x[3] = d[3];
        for k in (0..3).rev() {
            x[k] = d[k] - c[k] * x[k + 1];
        }
        x.map(|v| v as f32)
    }
}
