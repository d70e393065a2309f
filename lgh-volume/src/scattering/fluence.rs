//! One depth's fluence (paper Sec. 5): `I^k = h³ σ_s/(4π) · Φ^{k−1}` at every voxel with
//! smoke, `Φ^{k−1}` the shadowed fluence of the depth before, in fixed chunks of voxels.

use lgh_core::glam::Vec3;
use rayon::prelude::*;

use crate::error::RenderError;
use crate::lighting::LightScratch;
use crate::lighting_cache::{CachedLights, LightingCache};
use crate::lights::ExplosionLights;
use crate::medium::{Medium, Volume};
use crate::method::{FrameBackend, Method};
use crate::settings::MarchSettings;
use crate::shading::Shading;
use crate::stats::RenderStats;

use super::lattice::{self, Corrections, NearLights};
use super::pilot::Pilot;
use super::plan::nothing_to_scatter;
use super::stop::power;

/// Voxels per parallel job of the fluence pass: a fixed split, so that nothing depends on the
/// thread count, large enough that a job's scratch is reused over many voxels.
pub const CHUNK_VOXELS: usize = 1024;

/// One depth's fluence pass: what stays the same from depth to depth.
pub(super) struct Fluence<'a> {
    pub(super) method: Method,
    pub(super) frame: &'a Volume,
    pub(super) medium: &'a Medium,
    pub(super) settings: &'a MarchSettings,
    /// The voxels with smoke, ascending.
    pub(super) voxels: &'a [usize],
    /// Where the level-0 lights near each voxel are taken ([`lattice`]): at the
    /// cell's mean for the depths lit by scattered light.
    pub(super) near_lights: NearLights,
    pub(super) progress: &'a (dyn Fn(usize) + Sync),
}

impl Fluence<'_> {
    /// `out[i] = h³ σ_s(x_i)/(4π) · Φ(x_i)` for each voxel `x_i`, with `Φ` the shadowed fluence
    /// of `source` (shadows built here, as the settings ask). Returns the queries' counts and
    /// the seconds spent on the shadows.
    ///
    /// With a `pilot`, the fluence is first computed at a systematic sample of the voxels
    /// ([`Pilot`]); if the depth's power predicted from it is below the pilot's bar, nothing
    /// more is done and the prediction is returned ([`Ran::Skipped`]). Each voxel's fluence
    /// depends on the voxel alone (the lighting cache fills each of its bricks once, the same
    /// whoever asks first), so a depth the pilot lets through is the same bit for bit.
    pub(super) fn run(
        &self,
        source: &ExplosionLights,
        out: &mut [Vec3],
        pilot: Option<Pilot>,
    ) -> Result<Ran, RenderError> {
        let shading = Shading::new(
            source,
            self.method,
            self.frame,
            self.medium,
            self.settings,
            &(),
        )?;
        let (visibility, shadow_seconds) = (&shading.visibility, shading.shadow_seconds);
        // Refused by `check_pass` before any work; never met here.
        let Some(lights) = shading.prepared.lights(source)? else {
            return Err(nothing_to_scatter(1));
        };
        // The fluence at the voxel's centre, but for the level-0 lights within two voxels of
        // the depths lit by scattered light, taken at the cell's mean (`lattice`). The
        // spherically averaged cell means (`near_field::cell_falloff`, `Volume::cell_density`)
        // took the path-tracer test's ball 3% further from the path tracer (docs/shadows.md,
        // "Cell means in the pass").
        let grid = &self.frame.density;
        // With a lighting cache, the coarse levels' fluence comes from it, as in the render —
        // where some grid is coarser than the voxels: the pass queries every voxel, so a cache
        // whose vertices are all at least as dense as the voxels would only add work.
        let sparse = |c: &&LightingCache| c.tiers().iter().any(|&(_, voxels)| voxels > 1.0);
        let cache = shading.cache.as_ref().filter(sparse);
        let cached = CachedLights::of(cache, grid, &lights);
        // The level-0 lights near each voxel at the cell's mean (`lattice`): the hierarchy's
        // level 0 within reach, or a brute-force sum's every light (weighted 0 beyond it).
        let h = grid.voxel_size;
        let near = match (self.near_lights, &lights.backend) {
            (NearLights::CellMeans, FrameBackend::Lgh(b)) => Some(FrameBackend::Lgh(
                b.with_levels(0..=0).within(lattice::REACH_VOXELS * h),
            )),
            (NearLights::CellMeans, FrameBackend::Brute(b)) => Some(FrameBackend::Brute(b)),
            _ => None,
        };
        let lattice = near.map(|b| lights.with_backend(b));
        let shade = |voxels: &[usize], out: &mut [Vec3], progress: bool| {
            shade_voxels(voxels, out, |out, voxels| {
                let mut scratch = LightScratch::default();
                let mut stats = RenderStats::default();
                for (o, &v) in out.iter_mut().zip(voxels) {
                    let [i, j, k] = grid.voxel(v);
                    let (x, rho) = (grid.centre(i, j, k), grid.data[v]);
                    let scale = self.medium.voxel_scattering(rho, grid.voxel_size);
                    let sigma_t = self.medium.extinction(rho);
                    let s = (&mut scratch, &mut stats);
                    *o = match &cached {
                        Some(c) => c.in_scattered(x, scale, sigma_t, visibility, s.0, s.1)?,
                        None => lights.in_scattered(x, scale, sigma_t, visibility, s.0, s.1)?,
                    };
                    if let Some(near) = &lattice {
                        // In the table's uniform smoke, at the voxel's extinction: unshadowed,
                        // times `e^{−σ_t d}` (module docs of `lattice`).
                        let q = Corrections::at(sigma_t * h);
                        let w = |d: f32| q.weight(d, h) * (-sigma_t * d).exp();
                        *o += near.unshadowed_part(x, scale, sigma_t, w, s.0, s.1)?;
                    }
                }
                if progress {
                    (self.progress)(voxels.len());
                }
                Ok(stats)
            })
        };
        let mut stats = RenderStats::default();
        if let Some(pilot) = pilot {
            let sample = pilot.sample(self.voxels);
            let mut fluence = vec![Vec3::ZERO; sample.len()];
            stats.add(&shade(&sample, &mut fluence, false)?);
            let predicted = power(&fluence) * self.voxels.len() as f64 / sample.len() as f64;
            if predicted < pilot.bar() {
                return Ok(Ran::Skipped {
                    predicted,
                    sampled: sample.len(),
                    shading: Box::new(shading),
                });
            }
        }
        stats.add(&shade(self.voxels, out, true)?);
        // One shading point per voxel, whether it shaded lights or only read the cache; the
        // cache's vertices are this depth's work too: their lights and shadow samples count
        // with the voxels' (a depth through a cache of every level shades no light per voxel).
        stats.shading_points = self.voxels.len() as u64;
        if let Some(c) = cache {
            let filled = c.stats();
            stats.lights_evaluated += filled.lights_evaluated;
            stats.shadow_samples += filled.shadow_samples;
        }
        Ok(Ran::Done(stats, shadow_seconds))
    }
}

/// `shade(out, voxels)` over `voxels` and `out` in fixed chunks of [`CHUNK_VOXELS`], in
/// parallel; the chunks' counts summed in order.
fn shade_voxels(
    voxels: &[usize],
    out: &mut [Vec3],
    shade: impl Fn(&mut [Vec3], &[usize]) -> Result<RenderStats, RenderError> + Sync,
) -> Result<RenderStats, RenderError> {
    let chunks: Vec<Result<RenderStats, RenderError>> = out
        .par_chunks_mut(CHUNK_VOXELS)
        .zip(voxels.par_chunks(CHUNK_VOXELS))
        .map(|(out, voxels)| shade(out, voxels))
        .collect();
    let mut stats = RenderStats::default();
    for c in chunks {
        stats.add(&c?);
    }
    Ok(stats)
}

/// What [`Fluence::run`] did.
pub(super) enum Ran {
    /// The depth, with its counts and the seconds of its shadows.
    Done(RenderStats, f64),
    /// Skipped by the pilot: its predicted power, from `sampled` voxels, and the source's
    /// shading it made.
    Skipped {
        predicted: f64,
        sampled: usize,
        shading: Box<Shading>,
    },
}

#[cfg(test)]
mod tests {
    use crate::lights::ExplosionLights;
    use crate::medium::Medium;
    use crate::method::Method;
    use crate::scattering::tests::{bits, blob, pass};
    use crate::scattering::Scattered;
    use crate::settings::MarchSettings;
    use crate::shadow::Shadows;

    #[test]
    fn through_a_lighting_cache_depth_one_is_exact_at_its_vertices_and_dense_caches_are_skipped() {
        // Cells two voxels wide on the voxel centres' lattice: an eighth of the voxels are
        // vertices, where the cache holds the coarse levels' fluence computed exactly as the
        // uncached query computes it, and a vertex's own value comes back through the
        // interpolation with weight 1 and a zero offset. What may differ there is the order of
        // the sums (fine and coarse levels apart, then added) and e^{ln L}: a few ulps,
        // relative 1e-5 at most. Between vertices the cache interpolates: those voxels differ
        // (the cache is used), by an amount printed as each depth's power. A cache one voxel
        // apart has no vertex fewer than the voxels: the pass skips it, bit for bit.
        use crate::lighting_cache::{
            CacheMode, CacheSpacing, LightingCacheSettings, ScatteredLight,
        };
        let volume = blob(20);
        let medium = Medium::new(4.0, 6.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        let lgh = Method::Lgh { alpha: 2.0 };
        let with = |spacing| {
            let settings = MarchSettings {
                shadows: Shadows::RayMarch,
                lighting_cache: LightingCacheSettings {
                    mode: CacheMode::Coarse,
                    spacing,
                    // Depth 2 at every voxel too, as depth 1: what this test compares.
                    scattered_spacing: 1,
                    scattered_light: ScatteredLight::Merged,
                    ..Default::default()
                },
                ..Default::default()
            };
            pass(&emission, 2, lgh, &volume, &medium, &settings)
        };
        let plain = pass(
            &emission,
            2,
            lgh,
            &volume,
            &medium,
            &MarchSettings::with_shadows(Shadows::RayMarch),
        );
        let (dense, coarse) = (
            with(CacheSpacing::Voxels(1.0)),
            with(CacheSpacing::Voxels(2.0)),
        );
        for depth in 1..=2 {
            let a = plain.intensities(depth).unwrap();
            assert_eq!(
                bits(a),
                bits(dense.intensities(depth).unwrap()),
                "depth {depth}"
            );
        }
        let (a, b) = (
            plain.intensities(1).unwrap(),
            coarse.intensities(1).unwrap(),
        );
        let lit = a.iter().filter(|v| v.max_element() > 0.0).count();
        let same = a
            .iter()
            .zip(b)
            .filter(|(x, y)| {
                x.max_element() > 0.0 && (**x - **y).abs().max_element() <= 1e-5 * x.max_element()
            })
            .count();
        assert!(lit > 1000, "{lit}");
        assert!(10 * same >= lit && same < lit, "{same} of {lit}");
        for depth in 1..=2 {
            let power = |s: &Scattered| s.depths()[depth - 1].power;
            eprintln!(
                "depth {depth}: power {:.6e} uncached, {:.6e} through 2-voxel cells",
                power(&plain),
                power(&coarse)
            );
        }
    }
}
