//! One light set made ready to shade a frame: its [`Method`] prepared and the visibility its
//! shadows need, built together and once, so that a light set's cube maps are never used for
//! another (the paper's deep-shadow cube maps are traced per light of every level, Sec. 4).

use std::time::Instant;

use crate::error::RenderError;
use crate::lighting_cache::{CacheMode, LightingCache};
use crate::lights::ExplosionLights;
use crate::medium::{Medium, Volume};
use crate::method::{Method, Prepared};
use crate::progress::{self, Phase, Progress};
use crate::settings::MarchSettings;
use crate::shadow::{Casters, CubeMaps, ShadowGrid, Shadows, Visibility, VolumeRays};

/// A light set's method, visibility and lighting cache for one frame (crate-internal: the light
/// set itself is held by whoever holds this, a [`FrameRender`](crate::FrameRender) or a
/// scattering depth).
pub(crate) struct Shading {
    /// The method made ready.
    pub(crate) prepared: Prepared,
    /// The shadows the settings ask for, of these lights.
    pub(crate) visibility: Visibility,
    /// Seconds spent making the visibility (the cube maps' tracing).
    pub(crate) shadow_seconds: f64,
    /// The coarse levels' lighting cache, if the settings ask for one and the method is the
    /// hierarchy (empty: filled as shading needs it).
    pub(crate) cache: Option<LightingCache>,
}

impl Shading {
    /// `method` prepared over `lights` and the visibility `settings.shadows` asks for: the
    /// deep-shadow cube maps ([`CubeMaps::build`], refused before any work if they would not fit
    /// `settings.cube_maps.memory_budget`; `progress` over their lights) or the cube maps' model
    /// marched ([`VolumeRays`]) for the hierarchy, whose lights they are made for; ray-marched
    /// or none otherwise (brute force and Lightcuts have no hierarchy: they ray-march); none
    /// for emission alone.
    pub(crate) fn new(
        lights: &ExplosionLights,
        method: Method,
        frame: &Volume,
        medium: &Medium,
        settings: &MarchSettings,
        progress: &dyn Progress,
    ) -> Result<Self, RenderError> {
        let prepared = method.prepare(lights)?;
        let t = Instant::now();
        let (step, cutoff) = (settings.shadow_step_voxels, settings.min_transmittance);
        // The lights' own hierarchy and coarse lights' shadows, at the method's blending.
        let casters = |blending| Casters {
            hierarchy: lights.hierarchy(),
            blending,
            coarse: lights.variants().coarse_shadows,
        };
        let visibility = match (&prepared, settings.shadows) {
            (Prepared::Emission, _) => Visibility::None,
            (Prepared::Lgh { blending, .. }, Shadows::CubeMap) => {
                let (maps, casters) = (&settings.cube_maps, casters(blending));
                let total = CubeMaps::plan(casters, &frame.density, maps).lights();
                let maps = progress::phase(progress, Phase::ShadowMaps, total as u64, |p| {
                    CubeMaps::build(casters, frame, medium, maps, p)
                })?;
                Visibility::CubeMaps(maps)
            }
            (Prepared::Lgh { blending, .. }, Shadows::RayMarchVolumes) => Visibility::VolumeRays(
                VolumeRays::new(casters(blending), frame, medium, step, cutoff),
            ),
            (Prepared::Lgh { blending, .. }, Shadows::Volumes) => Visibility::Volumes {
                points: ShadowGrid::new(frame, medium, step, cutoff),
                rays: VolumeRays::new(casters(blending), frame, medium, step, cutoff),
            },
            (_, shadows) => Visibility::new(shadows, frame, medium, step, cutoff),
        };
        let shadow_seconds = t.elapsed().as_secs_f64();
        let cache = match (&prepared, settings.lighting_cache.mode) {
            (Prepared::Lgh { .. }, CacheMode::Coarse) => Some(LightingCache::new(
                &frame.density,
                medium,
                lights.hierarchy(),
                &settings.lighting_cache,
            )?),
            _ => None,
        };
        Ok(Shading {
            prepared,
            visibility,
            shadow_seconds,
            cache,
        })
    }
}
