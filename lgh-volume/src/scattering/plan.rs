//! The plan of a pass (paper Sec. 5): what a scattering pass will hold, its lights and their
//! bytes, found and checked against the memory budget before any work.

use crate::error::RenderError;
use crate::lights::ExplosionLights;
use crate::medium::Volume;
use crate::method::Method;
use crate::settings::{check_depth, MarchSettings};

use super::merge::merge_count;

/// Bytes planned per light of a depth's (or the merged) light set: its voxel index (8), the
/// point light (24), and the hierarchy — level 0 (44 a light), the sorted input (36) and the
/// levels above, planned at one vertex of 72 bytes per light (a level-1 grid of `h1 = 2h` over
/// voxel lights has about one vertex per 8 lights where the smoke is solid, and the levels above
/// fewer still; the test `the_memory_plan_covers_what_the_pass_holds` checks the vertices).
pub const BYTES_PER_LIGHT: u64 = 8 + 24 + 44 + 36 + 72;

/// What a scattering pass will hold, found before any work: its lights and their bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScatterPlan {
    /// Scattered depths `n`.
    pub depth: usize,
    /// Lights of each scattered depth: the voxels with smoke density.
    pub lights_per_depth: usize,
    /// Lights of the merged set: the voxels that emit (in any frame of the emission lights) or
    /// have smoke.
    pub merged_lights: usize,
    /// Bytes of the pass's lights: one depth's light set at a time, the per-depth intensities
    /// of every voxel of the merged set (kept for
    /// [`Scattered::depth_lights`](super::Scattered::depth_lights)) and the merged set.
    pub bytes: u64,
}

impl ScatterPlan {
    /// The plan of [`scatter`](super::scatter) to `depth` scattered depths from `emission` in
    /// `frame`: checks the depth ([`check_depth`]) and that the density lies on the lights' grid
    /// ([`RenderError::DensityOffGrid`]); counts voxels, nothing more.
    ///
    /// ```
    /// use lgh_volume::scattering::ScatterPlan;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
    /// let emission = ExplosionLights::new(&[&volume], &medium)?;
    /// let plan = ScatterPlan::new(&emission, &volume, 4)?;
    /// let smoke = volume.density.data.iter().filter(|&&r| r > 0.0).count();
    /// assert_eq!(plan.lights_per_depth, smoke);
    /// assert!(plan.check(1 << 30).is_ok());
    /// assert!(plan.check(1000).is_err()); // refused before any work
    /// assert!(ScatterPlan::new(&emission, &volume, 17).is_err());
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn new(
        emission: &ExplosionLights,
        frame: &Volume,
        depth: usize,
    ) -> Result<Self, RenderError> {
        check_depth(depth)?;
        if !emission.on_grid(&frame.density) {
            return Err(RenderError::DensityOffGrid);
        }
        let dense = frame.density.data.iter().filter(|&&r| r > 0.0).count();
        let merged = merge_count(emission.voxels(), &frame.density.data);
        let (d, m, n) = (dense as u64, merged as u64, depth as u64);
        let bytes = if depth == 0 {
            0
        } else {
            // One depth's lights and its new intensities; every depth's intensities on the
            // merged voxels, their sum and the merged lights.
            d * (BYTES_PER_LIGHT + 12 + 8) + m * (12 * (n + 2) + BYTES_PER_LIGHT)
        };
        Ok(ScatterPlan {
            depth,
            lights_per_depth: dense,
            merged_lights: merged,
            bytes,
        })
    }

    /// The plan with the scattered light kept as a grid ([`MarchSettings::scattered_grid`]):
    /// its three channels over every voxel of `frame`, and the summed intensities of the
    /// voxels with smoke.
    ///
    /// ```
    /// use lgh_volume::scattering::ScatterPlan;
    /// use lgh_volume::{procedural, ExplosionLights, Medium};
    ///
    /// let volume = procedural(32, 0.5)?;
    /// let emission = ExplosionLights::new(&[&volume], &Medium::new(2.0, 6.0, 1e-4, 1000.0)?)?;
    /// let plan = ScatterPlan::new(&emission, &volume, 2)?;
    /// let grid = plan.with_grid(&volume);
    /// assert_eq!(grid.bytes - plan.bytes, 12 * (32 * 32 * 32 + plan.lights_per_depth as u64));
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    #[must_use]
    pub fn with_grid(self, frame: &Volume) -> Self {
        let extra = 12 * (frame.density.data.len() as u64 + self.lights_per_depth as u64);
        ScatterPlan {
            bytes: self.bytes + extra,
            ..self
        }
    }

    /// `Ok` if the plan fits in `budget` bytes, else [`RenderError::ScatterMemory`].
    ///
    /// ```
    /// use lgh_volume::scattering::ScatterPlan;
    ///
    /// let plan = ScatterPlan { depth: 4, lights_per_depth: 10, merged_lights: 12, bytes: 5000 };
    /// assert!(plan.check(5000).is_ok());
    /// assert!(plan.check(4999).unwrap_err().to_string().contains("MarchSettings::scatter_depth"));
    /// ```
    pub fn check(&self, budget: u64) -> Result<(), RenderError> {
        if self.bytes > budget {
            return Err(RenderError::ScatterMemory {
                needed: self.bytes,
                budget,
                depth: self.depth,
            });
        }
        Ok(())
    }
}

/// Every check of a pass, before any work: the settings, the method (emission alone has no
/// lights to scatter), and the pass's memory; the pass's [`ScatterPlan`].
pub(super) fn check_pass(
    emission: &ExplosionLights,
    method: Method,
    frame: &Volume,
    settings: &MarchSettings,
) -> Result<ScatterPlan, RenderError> {
    let depth = settings.scatter_depth;
    let mut plan = ScatterPlan::new(emission, frame, depth)?;
    if settings.scattered_grid(method) {
        plan = plan.with_grid(frame);
    }
    settings.check()?;
    method.check()?;
    if method == Method::Emission && depth > 0 {
        return Err(nothing_to_scatter(depth));
    }
    plan.check(settings.cube_maps.memory_budget)?;
    Ok(plan)
}

/// The error of a pass of `depth` asked of [`Method::Emission`], which has no lights.
pub(super) fn nothing_to_scatter(depth: usize) -> RenderError {
    RenderError::InvalidCount {
        name: "scatter depth",
        value: depth,
        rule: "needs lights to scatter: emission alone has none",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::Medium;
    use crate::procedural::procedural;
    use crate::progress::Progress;
    use crate::scattering::scatter;
    use crate::scattering::tests::pass;
    use crate::shadow::Shadows;
    use lgh_core::glam::Vec3;

    #[test]
    fn bad_passes_are_refused_before_any_work() {
        let volume = procedural(32, 0.5).unwrap();
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        /// Counts the voxels whose fluence was computed.
        #[derive(Default)]
        struct Work(std::sync::atomic::AtomicU64);
        impl Progress for Work {
            fn advance(&self, steps: u64) {
                self.0
                    .fetch_add(steps, std::sync::atomic::Ordering::Relaxed);
            }
        }
        let work = Work::default();
        let run = |depth, settings: &MarchSettings, frame: &Volume| {
            let settings = MarchSettings {
                scatter_depth: depth,
                ..*settings
            };
            let lgh = Method::Lgh { alpha: 2.0 };
            scatter(&emission, lgh, frame, &medium, &settings, &work).map(|_| ())
        };
        let ok = MarchSettings::default();
        let e = run(17, &ok, &volume).unwrap_err();
        assert!(
            matches!(e, RenderError::InvalidCount { value: 17, .. }),
            "{e}"
        );
        let small = MarchSettings {
            cube_maps: crate::shadow::CubeMapSettings {
                memory_budget: 100_000,
                ..Default::default()
            },
            ..ok
        };
        let e = run(4, &small, &volume).unwrap_err();
        assert!(
            matches!(e, RenderError::ScatterMemory { depth: 4, .. }),
            "{e}"
        );
        let mut moved = volume.clone();
        moved.density.origin += Vec3::splat(0.01);
        assert!(matches!(
            run(1, &ok, &moved).unwrap_err(),
            RenderError::DensityOffGrid
        ));
        assert_eq!(work.0.into_inner(), 0, "no voxel's fluence was computed");
    }

    #[test]
    fn the_memory_plan_covers_what_the_pass_holds() {
        // BYTES_PER_LIGHT plans one vertex of the levels ≥ 1 per light: check it on the
        // procedural explosion's smoke and on a thin scatter of lights (every 5th voxel).
        let volume = procedural(48, 0.5).unwrap();
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let settings = MarchSettings {
            shadows: Shadows::None,
            ..Default::default()
        };
        let s = pass(
            &emission,
            1,
            Method::Lgh { alpha: 2.0 },
            &volume,
            &medium,
            &settings,
        );
        let plan = ScatterPlan::new(&emission, &volume, 1).unwrap();
        assert_eq!(plan.merged_lights, s.lights().lights().len());
        let h = s.lights().hierarchy();
        let vertices: usize = (1..=h.max_level()).map(|l| h.level(l).len()).sum();
        assert!(
            vertices <= h.len(),
            "{vertices} vertices, {} lights",
            h.len()
        );
        let sparse: Vec<usize> = (0..volume.density.data.len()).step_by(5).collect();
        let dark = vec![Vec3::ZERO; sparse.len()];
        let thin = ExplosionLights::at_voxels(&volume.density, sparse, &dark, None).unwrap();
        let h = thin.hierarchy();
        let vertices: usize = (1..=h.max_level()).map(|l| h.level(l).len()).sum();
        assert!(
            vertices <= h.len(),
            "{vertices} vertices, {} lights",
            h.len()
        );
    }
}
