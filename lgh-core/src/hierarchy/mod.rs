//! The lighting grid hierarchy (paper Sec. 3): build, cheap rebuild, and the radius query.

use alloc::vec::Vec;
use core::cmp::Ordering;
use glam::Vec3;

use crate::blend::{Blending, Ramp};
use crate::bricks::{Ball, BrickIndex};
use crate::error::{BuildError, QueryError};
use crate::grid::{self, GridSettings, LevelSource, Placement};
use crate::level::{self, SplatInput, Topology};
use crate::light::{
    is_reported, luminance, validate_intensity, validate_lights, Contribution, GridLight, Hit,
    LevelLights, PointLight,
};
use crate::many_lights::{LightSample, Lobe};
use crate::math::{floor64, level_scale};
use crate::morton;
use crate::radix;

mod backend;

pub use backend::LghBackend;

/// The input lights in the hierarchy's order: by Morton code of their level-1 cell, ties broken by
/// position and intensity bits — a total order on the lights' values, so the build does not depend
/// on the order in which lights were given.
#[derive(Clone, Debug, Default)]
struct SortedInput {
    /// `perm[i]` = index in the caller's slice of sorted light `i`.
    perm: Vec<u32>,
    /// Morton code of each light's level-1 cell.
    code: Vec<u64>,
    /// Level-1 cell of each light.
    cell: Vec<[u32; 3]>,
    /// Position inside the level-1 cell, in cell units.
    frac: Vec<[f32; 3]>,
    /// Ranges `start..end` of lights with identical positions (usually none). Inside them the
    /// order is by intensity, which a rebuild must restore to stay identical to a fresh build.
    coincident: Vec<(u32, u32)>,
}

/// One level ℓ ≥ 1: its lights (grid vertices) and the topology that locates them.
#[derive(Clone, Debug)]
struct Level {
    lights: LevelLights,
    topo: Topology,
}

/// A lighting grid hierarchy over a set of point lights `S0`.
///
/// Level 0 holds the input lights; level ℓ ≥ 1 is a sparse grid with spacing `h_ℓ = 2^(ℓ−1) h_1`
/// whose vertices are lights with intensity (eq. 1), illumination centre (eq. 2), per-axis variance
/// (eq. 4) and size (eq. 5). See the crate documentation for an example.
#[derive(Clone, Debug)]
pub struct LightingGridHierarchy {
    placement: Placement,
    source: LevelSource,
    prune_below: f32,
    /// The variants of the splat (the paper's by default).
    splat: level::SplatVariant,
    input: SortedInput,
    /// Level 0: the input lights, sorted, as grid lights (zero variance and size).
    level0: LevelLights,
    /// Level-1 cells holding level-0 lights: index and runs, for level-0 radius queries.
    cells0: BrickIndex,
    cells0_starts: Vec<u32>,
    cells0_codes: Vec<u64>,
    /// Levels 1..=ℓ_max.
    levels: Vec<Level>,
}

fn position_bits(p: Vec3) -> [u32; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

fn intensity_bits(i: Vec3) -> [u32; 3] {
    [i.x.to_bits(), i.y.to_bits(), i.z.to_bits()]
}

/// Total order on a light's value (position, then intensity), by bits.
fn value_order(a: &PointLight, b: &PointLight) -> Ordering {
    position_bits(a.position)
        .cmp(&position_bits(b.position))
        .then_with(|| intensity_bits(a.intensity).cmp(&intensity_bits(b.intensity)))
}

/// Level-1 cell and in-cell position of `p` under `placement`.
#[inline]
fn locate(p: Vec3, pl: &Placement) -> ([u32; 3], [f32; 3]) {
    let mut cell = [0u32; 3];
    let mut frac = [0.0f32; 3];
    for a in 0..3 {
        let t = (p[a] as f64 - pl.origin[a]) / pl.h1;
        let c = floor64(t).clamp(0.0, pl.max_cell[a] as f64);
        cell[a] = c as u32;
        frac[a] = ((t - c) as f32).clamp(0.0, 1.0);
    }
    (cell, frac)
}

/// Sorts `(Morton code, light index)` pairs by code, ties by the lights' values, so the result
/// does not depend on the input order. Returns the lights in that order with their input indices
/// (gathered once, so everything after reads memory in order).
fn sort_lights(keys: &mut Vec<(u64, u32)>, lights: &[PointLight]) -> Vec<(PointLight, u32)> {
    radix::sort_by_key(keys, |k| k.0);
    let mut sorted: Vec<(PointLight, u32)> =
        keys.iter().map(|&(_, i)| (lights[i as usize], i)).collect();
    let mut k = 0;
    while k < keys.len() {
        let mut e = k + 1;
        while e < keys.len() && keys[e].0 == keys[k].0 {
            e += 1;
        }
        if e - k > 1 {
            sorted[k..e].sort_unstable_by(|a, b| value_order(&a.0, &b.0));
        }
        k = e;
    }
    sorted
}

/// Maps `f` over `jobs`, in parallel with the `rayon` feature; the output keeps the jobs' order.
fn par_map<J: Send, T: Send, F: Fn(J) -> T + Sync + Send>(jobs: Vec<J>, f: F) -> Vec<T> {
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        jobs.into_par_iter().map(f).collect()
    }
    #[cfg(not(feature = "rayon"))]
    {
        jobs.into_iter().map(f).collect()
    }
}

impl LightingGridHierarchy {
    /// Builds the hierarchy over `lights` with the given settings.
    ///
    /// Errors on non-finite positions, non-finite or negative intensities, invalid settings, or a
    /// grid too fine for the lights' extent. An empty light set gives an empty hierarchy whose
    /// queries report nothing.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{BuildError, GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// assert_eq!(lgh.len(), 64);
    /// // Every level holds all the input intensity (eq. 1: the trilinear weights sum to 1).
    /// for level in 0..=lgh.max_level() {
    ///     let total: Vec3 = lgh.level(level).iter().map(|l| l.intensity).sum();
    ///     assert!((total - Vec3::splat(64.0)).abs().max_element() < 1e-3);
    /// }
    /// // Invalid lights are reported with their index.
    /// let nan = [PointLight::new(Vec3::ONE, Vec3::ONE), PointLight::new(Vec3::NAN, Vec3::ONE)];
    /// let err = LightingGridHierarchy::build(&nan, &GridSettings::default()).unwrap_err();
    /// assert_eq!(err, BuildError::NonFinitePosition { index: 1 });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn build(lights: &[PointLight], settings: &GridSettings) -> Result<Self, BuildError> {
        validate_lights(lights)?;
        if !(settings.prune_below.is_finite() && settings.prune_below >= 0.0) {
            return Err(BuildError::InvalidThreshold {
                threshold: settings.prune_below,
            });
        }
        if lights.is_empty() {
            return Self::empty(settings);
        }
        let placement = grid::place(lights, settings)?;

        let mut keys: Vec<(u64, u32)> = lights
            .iter()
            .enumerate()
            .map(|(i, l)| (morton::encode(locate(l.position, &placement).0), i as u32))
            .collect();
        let sorted = sort_lights(&mut keys, lights);

        let n = lights.len();
        let mut input = SortedInput {
            perm: Vec::with_capacity(n),
            code: Vec::with_capacity(n),
            cell: Vec::with_capacity(n),
            frac: Vec::with_capacity(n),
            coincident: Vec::new(),
        };
        for (&(code, _), &(l, i)) in keys.iter().zip(&sorted) {
            let (cell, frac) = locate(l.position, &placement);
            input.perm.push(i);
            input.code.push(code);
            input.cell.push(cell);
            input.frac.push(frac);
        }
        drop(keys);
        let mut k = 0;
        while k < n {
            let p = position_bits(sorted[k].0.position);
            let mut e = k + 1;
            while e < n && position_bits(sorted[e].0.position) == p {
                e += 1;
            }
            if e - k > 1 {
                input.coincident.push((k as u32, e as u32));
            }
            k = e;
        }
        let level0 = LevelLights::from_lights(
            sorted.iter().map(|&(l, _)| GridLight {
                position: l.position,
                intensity: l.intensity,
                variance: Vec3::ZERO,
                size: 0.0,
                luminance: luminance(l.intensity),
            }),
            true,
            level_threshold(0, placement.max_level, settings.prune_below),
        );
        drop(sorted);
        let (cells0_codes, cells0_starts) = level::runs(input.code.iter().copied());
        let cells0 = BrickIndex::from_sorted_codes(&cells0_codes);

        let mut h = LightingGridHierarchy {
            placement,
            source: settings.source,
            prune_below: settings.prune_below,
            splat: level::SplatVariant::of(settings),
            input,
            level0,
            cells0,
            cells0_starts,
            cells0_codes,
            levels: Vec::new(),
        };
        h.build_levels(Vec::new());
        Ok(h)
    }

    fn empty(settings: &GridSettings) -> Result<Self, BuildError> {
        let h1 = settings.h1.unwrap_or(1.0);
        if !(h1.is_finite() && h1 > 0.0) {
            return Err(BuildError::InvalidSpacing { h1 });
        }
        let max_level = settings.max_level.unwrap_or(1);
        if max_level > crate::blend::MAX_LEVEL {
            return Err(BuildError::TooManyLevels {
                requested: max_level,
                max: crate::blend::MAX_LEVEL,
            });
        }
        let o = settings.origin.unwrap_or(Vec3::ZERO);
        if !o.is_finite() {
            return Err(BuildError::NonFiniteOrigin);
        }
        Ok(LightingGridHierarchy {
            placement: Placement {
                h1: h1 as f64,
                origin: [o.x as f64, o.y as f64, o.z as f64],
                max_level,
                max_cell: [0; 3],
            },
            source: settings.source,
            prune_below: settings.prune_below,
            splat: level::SplatVariant::of(settings),
            input: SortedInput::default(),
            level0: LevelLights::default(),
            cells0: BrickIndex::from_sorted_codes(&[]),
            cells0_starts: Vec::new(),
            cells0_codes: Vec::new(),
            levels: Vec::new(),
        })
    }

    /// (Re)computes levels 1..=ℓ_max, reusing the topologies of `old` levels where the lights did not
    /// move (every level when built from S0; only level 1 when built from the previous level).
    fn build_levels(&mut self, old: Vec<Level>) {
        let top = self.placement.max_level;
        let mut topos: Vec<Option<Topology>> = old.into_iter().map(|l| Some(l.topo)).collect();
        topos.resize_with(top as usize, || None);
        let this = &*self;
        let levels = match self.source {
            LevelSource::InputLights => {
                let jobs: Vec<(u8, Option<Topology>)> = (1..=top).zip(topos).collect();
                par_map(jobs, |(l, topo)| {
                    let topo = topo.unwrap_or_else(|| this.input_topology(l));
                    let lights = this.splat_input(l, &topo);
                    Level { lights, topo }
                })
            }
            LevelSource::PreviousLevel => {
                let mut levels = Vec::with_capacity(top as usize);
                if let Some(topo) = topos.into_iter().next() {
                    let topo = topo.unwrap_or_else(|| this.input_topology(1));
                    let lights = this.splat_input(1, &topo);
                    levels.push(Level { lights, topo });
                }
                for l in 2..=top {
                    let next = this.splat_previous(l, &levels[l as usize - 2].lights);
                    levels.push(next);
                }
                levels
            }
        };
        self.levels = levels;
    }

    /// Topology of level `l` built from the input lights: level-1 cell runs merged by `2^(l−1)`.
    fn input_topology(&self, l: u8) -> Topology {
        let shift = 3 * (l as u32 - 1);
        let mut cells = Vec::new();
        let mut starts = Vec::new();
        for (c, &code) in self.cells0_codes.iter().enumerate() {
            let code = code >> shift;
            if cells.last() != Some(&code) {
                cells.push(code);
                starts.push(self.cells0_starts[c]);
            }
        }
        starts.push(self.input.code.len() as u32);
        Topology::new(&cells, starts)
    }

    /// Level `l`'s lights splatted from the input lights `S0` (eqs. 1, 2, 4, 5).
    fn splat_input(&self, l: u8, topo: &Topology) -> LevelLights {
        let sub = l as u32 - 1;
        let mask = (1u32 << sub) - 1;
        let scale = 1.0 / (1u32 << sub) as f32;
        let frac: Vec<[f32; 3]> = self
            .input
            .cell
            .iter()
            .zip(&self.input.frac)
            .map(|(c, f)| {
                let mut g = [0.0; 3];
                for a in 0..3 {
                    g[a] = (((c[a] & mask) as f32 + f[a]) * scale).min(1.0);
                }
                g
            })
            .collect();
        let input = SplatInput {
            frac: &frac,
            intensity: self.level0.intensities(),
            luminance: self.level0.luminances(),
            extra_variance: None,
        };
        level::splat(
            topo,
            &input,
            self.h(l) as f64,
            self.placement.origin,
            self.threshold(l),
            self.splat,
        )
    }

    /// Level `l` splatted from the lights of level `l − 1` (the `PreviousLevel` option).
    fn splat_previous(&self, l: u8, prev: &LevelLights) -> Level {
        let pl = &self.placement;
        let h = self.h64(l);
        let max = [
            pl.max_cell[0] >> (l - 1),
            pl.max_cell[1] >> (l - 1),
            pl.max_cell[2] >> (l - 1),
        ];
        let mut items: Vec<(u64, u32, [f32; 3])> = (0..prev.len())
            .map(|i| {
                let g = prev.get(i);
                let mut cell = [0u32; 3];
                let mut frac = [0.0f32; 3];
                for a in 0..3 {
                    let t = ((g.position[a] as f64 - pl.origin[a]) / h).max(0.0);
                    let c = floor64(t).min(max[a] as f64);
                    cell[a] = c as u32;
                    frac[a] = ((t - c) as f32).clamp(0.0, 1.0);
                }
                (morton::encode(cell), i as u32, frac)
            })
            .collect();
        // Stable: ties keep the previous level's (deterministic) order.
        radix::sort_by_key(&mut items, |t| t.0);
        let (cells, starts) = level::runs(items.iter().map(|t| t.0));
        let topo = Topology::new(&cells, starts);
        let hf = h as f32;
        let frac: Vec<[f32; 3]> = items.iter().map(|t| t.2).collect();
        let intensity: Vec<Vec3> = items.iter().map(|t| prev.intensity(t.1 as usize)).collect();
        let lum: Vec<f32> = items.iter().map(|t| prev.luminance(t.1 as usize)).collect();
        let extra: Vec<Vec3> = items
            .iter()
            .map(|t| prev.variance(t.1 as usize) / hf / hf)
            .collect();
        let input = SplatInput {
            frac: &frac,
            intensity: &intensity,
            luminance: &lum,
            extra_variance: Some(&extra),
        };
        let lights = level::splat(&topo, &input, h, pl.origin, self.threshold(l), self.splat);
        Level { lights, topo }
    }

    /// Replaces the lights' intensities, keeping their positions: the explosion case, where lights sit
    /// at fixed voxel centres and only their intensities animate. `intensities[i]` is the new
    /// intensity of light `i` of the slice given to [`build`](Self::build).
    ///
    /// Skips everything that depends only on positions (validation of positions, the sort, the
    /// grids' topology) and re-splats the levels. The result is bit-identical to a fresh build with
    /// the new intensities.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let settings = GridSettings::default();
    /// let mut lgh = LightingGridHierarchy::build(&lights, &settings)?;
    /// // The next frame: same positions, new intensities.
    /// let hotter: Vec<Vec3> = (0..64).map(|i| Vec3::new(1.0, 0.5, i as f32 / 64.0)).collect();
    /// lgh.update_intensities(&hotter)?;
    /// let moved: Vec<PointLight> =
    ///     lights.iter().zip(&hotter).map(|(l, &i)| PointLight::new(l.position, i)).collect();
    /// let fresh = LightingGridHierarchy::build(&moved, &settings)?;
    /// // Bit-identical to building afresh.
    /// let (b1, b2) = (lgh.blending(2.0)?, fresh.blending(2.0)?);
    /// let x = Vec3::new(5.0, 1.0, -2.0);
    /// let a = lgh.query_sum(x, &b1, |s| s.intensity)?;
    /// let b = fresh.query_sum(x, &b2, |s| s.intensity)?;
    /// assert_eq!(a, b);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn update_intensities(&mut self, intensities: &[Vec3]) -> Result<(), BuildError> {
        let n = self.input.perm.len();
        if intensities.len() != n {
            return Err(BuildError::LengthMismatch {
                expected: n,
                got: intensities.len(),
            });
        }
        for (i, &v) in intensities.iter().enumerate() {
            validate_intensity(i, v)?;
        }
        if n == 0 {
            return Ok(());
        }
        for (s, &i) in self.input.perm.iter().enumerate() {
            self.level0.set_intensity(s, intensities[i as usize]);
        }
        // Coincident lights are ordered by intensity (see `SortedInput`): restore that order.
        for &(s, e) in &self.input.coincident {
            let (s, e) = (s as usize, e as usize);
            let mut run: Vec<(u32, Vec3)> = (s..e)
                .map(|k| (self.input.perm[k], self.level0.intensity(k)))
                .collect();
            run.sort_by_key(|a| intensity_bits(a.1));
            for (k, (p, v)) in (s..e).zip(run) {
                self.input.perm[k] = p;
                self.level0.set_intensity(k, v);
            }
        }
        let old = core::mem::take(&mut self.levels);
        self.build_levels(old);
        Ok(())
    }

    /// Number of input lights.
    #[must_use]
    pub fn len(&self) -> usize {
        self.level0.len()
    }

    /// True if the hierarchy has no lights.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.level0.is_empty()
    }

    /// The top level `ℓ_max`.
    #[must_use]
    pub fn max_level(&self) -> u8 {
        self.placement.max_level
    }

    /// Level-1 spacing `h_1`.
    #[must_use]
    pub fn h1(&self) -> f32 {
        self.placement.h1 as f32
    }

    /// Spacing `h_ℓ = 2^(ℓ−1) h_1` of level ℓ (`h_0 = h_1 / 2`).
    #[must_use]
    pub fn h(&self, level: u8) -> f32 {
        self.h64(level) as f32
    }

    /// `h_ℓ` in f64, as the grids are placed.
    fn h64(&self, level: u8) -> f64 {
        self.placement.h1 * level_scale(level)
    }

    /// `h_0 = h_1 / 2`, the clamp distance of the fall-off [`falloff`](crate::falloff).
    #[must_use]
    pub fn h0(&self) -> f32 {
        self.h(0)
    }

    /// The grids' shared origin (a vertex of every level).
    #[must_use]
    pub fn origin(&self) -> Vec3 {
        let o = self.placement.origin;
        Vec3::new(o[0] as f32, o[1] as f32, o[2] as f32)
    }

    /// Weak-light threshold of this hierarchy (0 = no pruning).
    #[must_use]
    pub fn prune_below(&self) -> f32 {
        self.prune_below
    }

    /// Changes the weak-light threshold ([`GridSettings::prune_below`]; the paper prunes "lights
    /// weaker than a small threshold from the lower levels", Sec. 6): queries then skip the
    /// lights below it on every level but the top one, exactly as if the hierarchy had been
    /// built with it (the levels themselves are built from all lights and do not change).
    /// A renderer can so set a threshold relative to a frame's brightest light after
    /// [`update_intensities`](Self::update_intensities). An invalid threshold (negative, NaN,
    /// infinite) is an error and changes nothing.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::splat(if p.x == 0.0 { 0.01 } else { 1.0 })))
    ///     .collect();
    /// let mut lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let (b, x) = (lgh.blending(2.0)?, Vec3::new(1.5, 1.5, 1.5));
    /// let all = lgh.query(x, &b, |_| {})?;
    /// lgh.set_prune_below(0.1)?;
    /// assert!(lgh.query(x, &b, |_| {})? < all); // the dim lights at x = 0 are skipped
    /// assert!(lgh.set_prune_below(f32::NAN).is_err());
    /// assert_eq!(lgh.prune_below(), 0.1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_prune_below(&mut self, prune_below: f32) -> Result<(), BuildError> {
        if !(prune_below.is_finite() && prune_below >= 0.0) {
            return Err(BuildError::InvalidThreshold {
                threshold: prune_below,
            });
        }
        self.prune_below = prune_below;
        let top = self.placement.max_level;
        self.level0
            .set_threshold(level_threshold(0, top, prune_below));
        for (l, level) in self.levels.iter_mut().enumerate() {
            let threshold = level_threshold(l as u8 + 1, top, prune_below);
            level.lights.set_threshold(threshold);
        }
        Ok(())
    }

    /// The lights of level `level` (level 0: the input lights, in the hierarchy's order).
    /// Empty for levels above `ℓ_max`.
    #[must_use]
    pub fn level(&self, level: u8) -> &LevelLights {
        static EMPTY: LevelLights = LevelLights::EMPTY;
        if level == 0 {
            &self.level0
        } else {
            self.levels
                .get(level as usize - 1)
                .map_or(&EMPTY, |l| &l.lights)
        }
    }

    /// The grid vertex (integer coordinates relative to [`origin`](Self::origin), in units of `h_ℓ`)
    /// of light `index` of level `level ≥ 1`.
    #[must_use]
    pub fn vertex(&self, level: u8, index: u32) -> Option<[u32; 3]> {
        let l = self.levels.get((level as usize).checked_sub(1)?)?;
        l.topo
            .vertex_codes
            .get(index as usize)
            .map(|&c| morton::decode(c))
    }

    /// Index, in the slice given to [`build`](Self::build), of level-0 light `index`.
    #[must_use]
    pub fn input_index(&self, index: u32) -> Option<usize> {
        self.input.perm.get(index as usize).map(|&i| i as usize)
    }

    /// True if `light` of `level` is reported by queries: not dark, and not weaker than the
    /// weak-light threshold unless it is on the top level (which is never pruned).
    #[inline]
    #[must_use]
    pub fn is_active(&self, level: u8, light: &GridLight) -> bool {
        is_reported(light.luminance, self.threshold(level))
    }

    /// Weak-light threshold of `level`: [`prune_below`](Self::prune_below), or 0 on the top level.
    #[inline]
    fn threshold(&self, level: u8) -> f32 {
        level_threshold(level, self.placement.max_level, self.prune_below)
    }

    /// Blending parameters for this hierarchy and the paper's α (`r_ℓ = α h_ℓ`).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight, QueryError};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::ONE, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let blending = lgh.blending(2.0)?;
    /// assert_eq!(blending.radius(1), 2.0 * lgh.h1()); // r_1 = α h_1
    /// assert!(matches!(lgh.blending(-1.0), Err(QueryError::InvalidAlpha { .. })));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn blending(&self, alpha: f32) -> Result<Blending, QueryError> {
        Blending::new(alpha, self.h1(), self.max_level())
    }

    /// Calls `f(index, distance)` for every light of `level` whose position lies within `radius`
    /// of `x` and that queries report (see [`is_active`](Self::is_active)), using the level's
    /// index (no allocation). Useful for shadow precomputation and tests.
    pub fn lights_within(
        &self,
        level: u8,
        x: Vec3,
        radius: f32,
        mut f: impl FnMut(u32, f32),
    ) -> Result<(), QueryError> {
        QueryError::check_point(x)?;
        if self.is_empty() || level > self.max_level() || radius.is_nan() || radius < 0.0 {
            return Ok(());
        }
        let lights = self.level(level);
        let r2 = radius * radius;
        let mut report = |s: usize, e: usize| {
            lights.scan(s, e, x, -1.0, r2, &mut |i: usize, d: f32| -> Option<()> {
                f(i as u32, d);
                Some(())
            });
        };
        if level == self.max_level() || !radius.is_finite() {
            report(0, lights.len());
        } else {
            self.for_each_range(level, x, radius, report);
        }
        Ok(())
    }

    /// Calls `f(start, end)` with ranges of light indices of `level` (< ℓ_max) that together hold
    /// every light whose position lies within `radius` of `x` (and possibly others).
    #[inline]
    fn for_each_range(&self, level: u8, x: Vec3, radius: f32, mut f: impl FnMut(usize, usize)) {
        // A hair wider than asked (relative, and 1e-4 of a cell absolute), so rounding of positions
        // and of the f64 culling never drops a light at the edge.
        let reach = |h: f64| radius as f64 * (1.0 + 1e-6) / h + 1e-4;
        if level == 0 {
            // Level-1 cells hold the level-0 lights; the cells of a brick and their lights are
            // contiguous.
            let ball = Ball {
                centre: self.local(x, 1),
                radius: reach(self.placement.h1),
                lo_pad: 0.0,
                hi_pad: 4.0,
            };
            self.cells0.for_each_brick_near(&ball, |first, n| {
                let s = self.cells0_starts[first as usize] as usize;
                let e = self.cells0_starts[(first + n) as usize] as usize;
                f(s, e)
            });
        } else {
            // A vertex's illumination centre lies within h_ℓ of it (pads −1 and 4).
            let ball = Ball {
                centre: self.local(x, level),
                radius: reach(self.h64(level)),
                lo_pad: -1.0,
                hi_pad: 4.0,
            };
            self.levels[level as usize - 1]
                .topo
                .index
                .for_each_brick_near(&ball, |first, n| f(first as usize, (first + n) as usize));
        }
    }

    /// Level-ℓ coordinates of `x` (world position relative to the origin, in units of `h_ℓ`).
    #[inline]
    fn local(&self, x: Vec3, level: u8) -> [f64; 3] {
        let inv = 1.0 / self.h64(level);
        let o = self.placement.origin;
        [
            (x.x as f64 - o[0]) * inv,
            (x.y as f64 - o[1]) * inv,
            (x.z as f64 - o[2]) * inv,
        ]
    }

    /// The lighting query of eq. (3): calls `f` once for every light (of any level) that contributes
    /// at `x`, i.e. whose blending weight `B_ℓ(d)` is non-zero at its distance `d = ‖x − p_ℓi‖`, with
    /// the weighted intensity `B_ℓ(d) I_ℓi`. Returns the number of calls.
    ///
    /// Visibility `V`, fall-off `g` (see [`falloff`](crate::falloff)), BRDF or phase function are the
    /// caller's. The query allocates nothing; the order of calls is fixed for a given hierarchy, α
    /// and `x`, so sums over them are deterministic.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let blending = lgh.blending(2.0)?;
    /// let mut calls = 0;
    /// let n = lgh.query(Vec3::new(10.0, 1.5, 1.5), &blending, |light| {
    ///     assert!(light.weight > 0.0 && light.weight <= 1.0);
    ///     calls += 1;
    /// })?;
    /// assert_eq!(n, calls);
    /// // Far from the lights only coarse levels are gathered: fewer calls than lights.
    /// assert!(calls > 0 && calls < 64);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query<F: FnMut(&LightSample)>(
        &self,
        x: Vec3,
        blending: &Blending,
        mut f: F,
    ) -> Result<u32, QueryError> {
        self.gather(x, blending, |s| f(s)).map(|((), n)| n)
    }

    /// Like [`query`](Self::query), but sums what `f` returns for each light (radiance, say) and
    /// returns the sum with the number of lights. Prefer this to accumulating into a captured
    /// variable: the running sum stays in registers instead of memory.
    ///
    /// With a large α every light is within `r_0` of the point, so only level 0 contributes, at full
    /// weight: the sum is brute force's.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{
    ///     falloff, BruteForce, GridSettings, LightSample, LightingGridHierarchy, PointLight,
    /// };
    ///
    /// // 64 white lights on a 4 × 4 × 4 lattice of unit spacing.
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// let x = Vec3::new(1.2, 5.0, 0.7);
    /// let shade = |s: &LightSample| s.intensity * falloff(s.distance, lgh.h0());
    /// let (sum, n) = lgh.query_sum(x, &lgh.blending(1000.0)?, shade)?;
    /// assert_eq!(n, 64);
    /// let exact = BruteForce::new(&lights)?.falloff_sum(x, lgh.h0())?;
    /// assert!(((sum - exact) / exact).abs().max_element() < 1e-5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn query_sum<F: FnMut(&LightSample) -> Vec3>(
        &self,
        x: Vec3,
        blending: &Blending,
        f: F,
    ) -> Result<(Vec3, u32), QueryError> {
        self.gather(x, blending, f)
    }

    /// `Ok` if `blending` is for this hierarchy's levels (its `h1` and top level), else
    /// [`QueryError::BlendingMismatch`].
    #[inline]
    fn check_blending(&self, blending: &Blending) -> Result<(), QueryError> {
        if blending.h1() != self.h1() || blending.max_level() != self.max_level() {
            return Err(QueryError::BlendingMismatch);
        }
        Ok(())
    }

    #[inline]
    fn gather<R: Contribution, F: FnMut(&LightSample) -> R>(
        &self,
        x: Vec3,
        blending: &Blending,
        mut f: F,
    ) -> Result<(R, u32), QueryError> {
        QueryError::check_point(x)?;
        self.check_blending(blending)?;
        if self.level0.is_empty() {
            return Ok((R::ZERO, 0));
        }
        let top = self.max_level();
        let mut sum = R::ZERO;
        let mut count = 0u32;
        // Scans lights[start..end] of `level` and adds what they contribute.
        let mut scan = |level: u8,
                        lights: &LevelLights,
                        start: usize,
                        end: usize,
                        inner2: f32,
                        outer2: f32| {
            let mut hits = LevelHits {
                f: &mut f,
                ramp: blending.ramp(level),
                level,
                lights,
            };
            let (r, n) = lights.scan(start, end, x, inner2, outer2, &mut hits);
            sum = sum.add(r);
            count += n;
        };

        // Level 0: lights in the level-1 cells that meet the ball of radius r_1 = α h_1. The cells of
        // a brick are contiguous, and so are their lights.
        if top == 0 {
            scan(0, &self.level0, 0, self.level0.len(), -1.0, f32::INFINITY);
            return Ok((sum, count));
        }
        let (_, outer) = blending.support(0);
        let outer2 = outer * outer;
        self.for_each_range(0, x, outer, |s, e| {
            scan(0, &self.level0, s, e, -1.0, outer2)
        });

        // Levels 0 < ℓ < ℓ_max: lights within 2 r_ℓ of x; a centre lies within h_ℓ of its vertex.
        for l in 1..top {
            let level = &self.levels[l as usize - 1];
            let (inner, outer) = blending.support(l);
            let (inner2, outer2) = (inner * inner, outer * outer);
            self.for_each_range(l, x, outer, |s, e| {
                scan(l, &level.lights, s, e, inner2, outer2)
            });
        }

        // The top level has no outer cutoff: every light beyond r_{ℓmax−1}.
        let (inner, _) = blending.support(top);
        let level = &self.levels[top as usize - 1];
        scan(
            top,
            &level.lights,
            0,
            level.lights.len(),
            inner * inner,
            f32::INFINITY,
        );
        Ok((sum, count))
    }
}

/// Weak-light pruning applies to every level but the top one.
fn level_threshold(level: u8, max_level: u8, prune_below: f32) -> f32 {
    if level == max_level {
        0.0
    } else {
        prune_below
    }
}

/// Hands one level's contributing lights to the caller's closure.
struct LevelHits<'a, F> {
    f: &'a mut F,
    ramp: Ramp,
    level: u8,
    lights: &'a LevelLights,
}

impl<R: Contribution, F: FnMut(&LightSample) -> R> Hit for LevelHits<'_, F> {
    type Out = R;

    /// Reports light `index` at distance `d` unless its weight is zero. (Dark and pruned lights
    /// never get here: their scanned positions are NaN.)
    #[inline(always)]
    fn hit(&mut self, index: usize, d: f32) -> Option<R> {
        let w = self.ramp.weight(d);
        if w <= 0.0 {
            return None;
        }
        let l = self.lights;
        Some((self.f)(&LightSample {
            level: self.level,
            index: index as u32,
            position: l.position(index),
            intensity: l.intensity(index) * w,
            variance: l.variance(index),
            size: l.size(index),
            distance: d,
            weight: w,
            lobe: Lobe::All,
        }))
    }
}
