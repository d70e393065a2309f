//! Building the lighting grid hierarchy (paper Sec. 3): the input lights sorted into a total
//! order, the levels splatted from them or from the level below (eqs. 1, 2, 4, 5), and the cheap
//! rebuild when only the intensities change.

use alloc::vec::Vec;
use core::cmp::Ordering;
use glam::Vec3;

use super::{level_threshold, Level, LightingGridHierarchy, SortedInput};
use crate::bricks::BrickIndex;
use crate::error::BuildError;
use crate::grid::{self, GridSettings, LevelSource, Placement};
use crate::level::{self, SplatInput, Topology};
use crate::light::{
    luminance, validate_intensity, validate_lights, Channels, GridLight, LevelKind, LevelLights,
    PointLight,
};
use crate::math::floor64;
use crate::morton;
use crate::radix;

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
    /// Errors on non-finite positions, non-finite intensities or ones with a negative luminance
    /// (a negative channel alone is taken: [`Channels`]), invalid settings, or a grid too fine
    /// for the lights' extent. An empty light set gives an empty hierarchy whose
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
        validate_lights(lights, Channels::OutOfGamut)?;
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
            LevelKind::Input,
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
            validate_intensity(i, v, Channels::OutOfGamut)?;
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
}
