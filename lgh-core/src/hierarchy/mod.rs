//! The lighting grid hierarchy (paper Sec. 3): the type and what it knows of itself. Its build
//! and cheap rebuild are in `build`, the radius query in `query`.

use alloc::vec::Vec;
use glam::Vec3;

use crate::bricks::BrickIndex;
use crate::error::BuildError;
use crate::grid::{LevelSource, Placement};
use crate::level::{self, Topology};
use crate::light::{is_reported, GridLight, LevelLights};
use crate::math::level_scale;
use crate::morton;

mod backend;
mod build;
mod query;

pub use backend::LghBackend;
pub use query::Reaching;

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

impl LightingGridHierarchy {
    /// Number of input lights.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// assert_eq!(lgh.len(), 2);
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn len(&self) -> usize {
        self.level0.len()
    }

    /// True if the hierarchy has no lights.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lgh = LightingGridHierarchy::build(&[], &GridSettings::default())?;
    /// assert!(lgh.is_empty());
    /// assert_eq!(lgh.query(Vec3::ZERO, &lgh.blending(2.0)?, |_| {})?, 0); // nothing to report
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.level0.is_empty()
    }

    /// The top level `ℓ_max`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let settings = GridSettings { max_level: Some(3), ..Default::default() };
    /// let lgh = LightingGridHierarchy::build(&lights, &settings)?;
    /// assert_eq!(lgh.max_level(), 3);
    /// assert!(lgh.level(4).is_empty()); // no level above the top
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn max_level(&self) -> u8 {
        self.placement.max_level
    }

    /// Level-1 spacing `h_1`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let settings = GridSettings { h1: Some(0.25), ..Default::default() };
    /// assert_eq!(LightingGridHierarchy::build(&lights, &settings)?.h1(), 0.25);
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn h1(&self) -> f32 {
        self.placement.h1 as f32
    }

    /// Spacing `h_ℓ = 2^(ℓ−1) h_1` of level ℓ (`h_0 = h_1 / 2`).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// assert_eq!(lgh.h(1), lgh.h1());
    /// assert_eq!(lgh.h(3), 4.0 * lgh.h1()); // doubling per level
    /// assert_eq!(lgh.h(0), lgh.h1() / 2.0);
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn h(&self, level: u8) -> f32 {
        self.h64(level) as f32
    }

    /// `h_ℓ` in f64, as the grids are placed.
    fn h64(&self, level: u8) -> f64 {
        self.placement.h1 * level_scale(level)
    }

    /// `h_0 = h_1 / 2`, the clamp distance of the fall-off [`falloff`](crate::falloff).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{falloff, GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// assert_eq!(lgh.h0(), lgh.h1() / 2.0);
    /// // Nearer than h0, the fall-off stays at 1 / h0².
    /// assert_eq!(falloff(0.0, lgh.h0()), 1.0 / (lgh.h0() * lgh.h0()));
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn h0(&self) -> f32 {
        self.h(0)
    }

    /// The grids' shared origin (a vertex of every level).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ONE, Vec3::ONE), PointLight::new(Vec3::splat(2.0), Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// assert_eq!(lgh.origin(), Vec3::ONE); // by default the lights' bounding-box minimum
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn origin(&self) -> Vec3 {
        let o = self.placement.origin;
        Vec3::new(o[0] as f32, o[1] as f32, o[2] as f32)
    }

    /// Weak-light threshold of this hierarchy (0 = no pruning).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// assert_eq!(LightingGridHierarchy::build(&lights, &GridSettings::default())?.prune_below(), 0.0);
    /// let settings = GridSettings { prune_below: 0.5, ..Default::default() };
    /// assert_eq!(LightingGridHierarchy::build(&lights, &settings)?.prune_below(), 0.5);
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn prune_below(&self) -> f32 {
        self.prune_below
    }

    /// Changes the weak-light threshold
    /// ([`GridSettings::prune_below`](crate::GridSettings::prune_below); the paper prunes "lights
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
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// assert_eq!(lgh.level(0).len(), 2); // the input lights
    /// // Each level carries the whole intensity (eq. 1).
    /// let total: Vec3 = lgh.level(1).iter().map(|l| l.intensity).sum();
    /// assert!((total - Vec3::splat(2.0)).abs().max_element() < 1e-6);
    /// assert!(lgh.level(lgh.max_level() + 1).is_empty());
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
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
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights: Vec<PointLight> = (0..64u32)
    ///     .map(|i| Vec3::new((i % 4) as f32, (i / 4 % 4) as f32, (i / 16) as f32))
    ///     .map(|p| PointLight::new(p, Vec3::ONE))
    ///     .collect();
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// for i in 0..lgh.level(2).len() as u32 {
    ///     let v = Vec3::from(lgh.vertex(2, i).unwrap().map(|c| c as f32));
    ///     // A light's illumination centre lies within h_ℓ of its vertex.
    ///     let centre = lgh.level(2).position(i as usize);
    ///     assert!((lgh.origin() + v * lgh.h(2) - centre).abs().max_element() <= lgh.h(2));
    /// }
    /// assert_eq!(lgh.vertex(0, 0), None); // level 0 has no grid
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn vertex(&self, level: u8, index: u32) -> Option<[u32; 3]> {
        let l = self.levels.get((level as usize).checked_sub(1)?)?;
        l.topo
            .vertex_codes
            .get(index as usize)
            .map(|&c| morton::decode(c))
    }

    /// Index, in the slice given to [`build`](Self::build), of level-0 light `index`.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::X, Vec3::ONE), PointLight::new(Vec3::ZERO, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default())?;
    /// for k in 0..lgh.len() {
    ///     let i = lgh.input_index(k as u32).unwrap();
    ///     assert_eq!(lgh.level(0).position(k), lights[i].position);
    /// }
    /// assert_eq!(lgh.input_index(2), None);
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
    #[must_use]
    pub fn input_index(&self, index: u32) -> Option<usize> {
        self.input.perm.get(index as usize).map(|&i| i as usize)
    }

    /// True if `light` of `level` is reported by queries: not dark, and not weaker than the
    /// weak-light threshold unless it is on the top level (which is never pruned).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::splat(0.1))];
    /// let settings = GridSettings { prune_below: 0.5, ..Default::default() };
    /// let lgh = LightingGridHierarchy::build(&lights, &settings)?;
    /// let active: Vec<bool> = lgh.level(0).iter().map(|l| lgh.is_active(0, &l)).collect();
    /// assert_eq!(active.iter().filter(|&&a| a).count(), 1); // the dim light is pruned
    /// // The top level is never pruned: only its dark lights are inactive.
    /// let top = lgh.max_level();
    /// assert!(lgh.level(top).iter().all(|l| lgh.is_active(top, &l) == (l.luminance > 0.0)));
    /// # Ok::<(), lgh_core::BuildError>(())
    /// ```
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
}

/// Weak-light pruning applies to every level but the top one.
fn level_threshold(level: u8, max_level: u8, prune_below: f32) -> f32 {
    if level == max_level {
        0.0
    } else {
        prune_below
    }
}
