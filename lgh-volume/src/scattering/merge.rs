//! The paper's merge (Sec. 5): every light of every depth sits at a voxel centre, so the lights
//! of one voxel become one light — the voxel's emission light plus its scattered lights, summed
//! in depth order, on the emission lights' grid.

use std::sync::Arc;

use lgh_core::glam::Vec3;

use crate::error::RenderError;
use crate::grid::DenseGrid;
use crate::lights::ExplosionLights;
use crate::voxel_smoke::VoxelSmoke;

/// The sorted union of `hot` and `dense` (both ascending), with each one's slot in it.
pub(super) fn merge(hot: &[usize], dense: &[usize]) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let mut voxels = Vec::with_capacity(hot.len() + dense.len());
    let (mut hot_slots, mut dense_slots) = (Vec::with_capacity(hot.len()), Vec::new());
    dense_slots.reserve(dense.len());
    let (mut a, mut b) = (0, 0);
    while a < hot.len() || b < dense.len() {
        let v = match (hot.get(a), dense.get(b)) {
            (Some(&h), Some(&d)) => h.min(d),
            (Some(&h), None) => h,
            (None, Some(&d)) => d,
            (None, None) => unreachable!("the loop runs while one is left"),
        };
        if hot.get(a) == Some(&v) {
            hot_slots.push(voxels.len());
            a += 1;
        }
        if dense.get(b) == Some(&v) {
            dense_slots.push(voxels.len());
            b += 1;
        }
        voxels.push(v);
    }
    (voxels, hot_slots, dense_slots)
}

/// Voxels that emit (`hot`, ascending) or have smoke (`density > 0`).
pub(super) fn merge_count(hot: &[usize], density: &[f32]) -> usize {
    let dense = density.iter().filter(|&&r| r > 0.0).count();
    dense + hot.iter().filter(|&&v| density[v] <= 0.0).count()
}

/// `len` intensities, `values` at their `slots` and zero elsewhere.
pub(super) fn on_slots(
    len: usize,
    values: impl Iterator<Item = Vec3>,
    slots: &[usize],
) -> Vec<Vec3> {
    let mut out = vec![Vec3::ZERO; len];
    for (v, &s) in values.zip(slots) {
        out[s] = v;
    }
    out
}

/// The emission lights' intensities, in their order.
pub(super) fn emission_intensities(emission: &ExplosionLights) -> Vec<Vec3> {
    emission.lights().iter().map(|l| l.intensity).collect()
}

/// The geometric tail's intensities on the merged voxels
/// ([`ScatterTail::Geometric`](crate::scattering::ScatterTail::Geometric)): the last depth's
/// (`per_depth`'s, depth 0 the emission's) times the tail's factor `tail`; `None` without a
/// tail or a scattered depth. The merged lights and
/// [`Scattered::tail_lights`](super::Scattered::tail_lights) take the same.
pub(super) fn tail_intensities(per_depth: &[Vec<Vec3>], tail: Option<f64>) -> Option<Vec<Vec3>> {
    let (Some(f), [_, .., last]) = (tail, per_depth) else {
        return None;
    };
    let f = f as f32;
    Some(last.iter().map(|&i| i * f).collect())
}

/// The paper's merge: one light per voxel of `voxels`, its depths' intensities (`per_depth`, on
/// the same voxels) summed in order — the last depth `1 + tail` times where the depths beyond
/// it are its geometric tail ([`super::ScatterTail::Geometric`]) — on the emission lights'
/// grid (their top level `max_level`) and with their settings ([`carry_over`]).
pub(super) fn merged_lights(
    emission: &ExplosionLights,
    grid: &DenseGrid,
    voxels: Vec<usize>,
    per_depth: &[Vec<Vec3>],
    tail: Option<f64>,
    max_level: u8,
) -> Result<ExplosionLights, RenderError> {
    let tail = tail_intensities(per_depth, tail);
    let merged_intensities: Vec<Vec3> = (0..voxels.len())
        .map(|s| {
            let sum = per_depth.iter().fold(Vec3::ZERO, |a, d| a + d[s]);
            match &tail {
                Some(t) => sum + t[s],
                None => sum,
            }
        })
        .collect();
    // Each merged light's near field is centred at its emission's centroid scaled by the
    // emission's share of its light (luminance): the mean of its depths' centres, the scattered
    // depths' being their voxels' (`crate::voxel_light`, "The near field's centre").
    let centroids: Vec<(usize, Vec3)> = match emission.smoke() {
        Some(smoke) => voxels
            .iter()
            .enumerate()
            .filter_map(|(s, &v)| {
                let c = smoke.centroid_of_voxel(v)?;
                let all = lgh_core::luminance(merged_intensities[s]);
                let own = lgh_core::luminance(per_depth[0][s]);
                (all > 0.0).then(|| (v, c * (own / all).clamp(0.0, 1.0)))
            })
            .collect(),
        None => Vec::new(),
    };
    let mut merged =
        ExplosionLights::at_voxels(grid, voxels, &merged_intensities, Some(max_level))?;
    carry_over(emission, &mut merged, centroids)?;
    Ok(merged)
}

/// The emission lights' weak-light pruning, near field, coarse lights' spread, the smoke of their voxels (each
/// light's near field centred at its voxel's offset in `centroids`, on its voxel where none is
/// given: each scattered depth gives none) and coarse lights' shadows, set on `lights` (each
/// scattered depth's, and the merged ones).
pub(super) fn carry_over(
    emission: &ExplosionLights,
    lights: &mut ExplosionLights,
    centroids: Vec<(usize, Vec3)>,
) -> Result<(), RenderError> {
    lights.set_prune(emission.prune())?;
    lights.set_near_field(emission.near_field());
    lights.set_coarse_spread(emission.coarse_spread());
    let smoke = |s: &Arc<VoxelSmoke>| Arc::new(s.without_centroids().with_centroids(centroids));
    lights.set_smoke(emission.smoke().map(smoke));
    let coarse = emission.variants().coarse_shadows;
    lights.set_coarse_shadows(coarse);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::Medium;
    use crate::method::Method;
    use crate::render::{Camera, Framing};
    use crate::scattering::tests::{bits, blob, pass};
    use crate::settings::MarchSettings;
    use crate::shadow::Shadows;

    #[test]
    fn the_emission_lights_pruning_carries_over_to_the_merged_lights() {
        let volume = blob(16);
        let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let mut emission = ExplosionLights::new(&[&volume], &medium).unwrap();
        emission.set_prune(1e-3).unwrap();
        let settings = MarchSettings {
            shadows: Shadows::RayMarch,
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
        let merged = s.lights();
        assert_eq!(merged.prune(), 1e-3);
        let brightest = merged.brightest();
        assert_eq!(merged.hierarchy().prune_below(), 1e-3 * brightest);
        assert!(brightest > 0.0);
    }

    #[test]
    fn with_albedo_zero_the_merged_lights_render_single_scattering_bit_for_bit() {
        // The pass runs in a medium that does not scatter (κ_s = 0, the same extinction as the
        // render's, so the same shadows): every scattered light is computed — one fluence query
        // per voxel with smoke, per depth — and is exactly dark. The merged set then holds
        // those dark lights beside the emission lights (more lights, another hierarchy and
        // other cube maps over it); rendered in a medium that *does* scatter, it must give the
        // single-scattering image bit for bit. (Rendered in the albedo-0 medium itself the
        // marcher would never query the lights, and the test would prove nothing.)
        //
        // The smoke reaches far beyond the fire (radius 0.8 against 0.35), so that lights
        // chosen on their own would take a higher top level (5 against 3) and another image:
        // the merged set must keep the emission lights' grid.
        let volume = blob(24);
        let render_medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let pass_medium = Medium::new(8.0, 0.0, 1e-4, 1000.0).unwrap();
        let emission = ExplosionLights::new(&[&volume], &render_medium).unwrap();
        let (lo, hi) = volume.active_bounds().unwrap();
        let camera = Camera::frame(lo, hi, 20, 12).unwrap();
        let smoke = volume.density.data.iter().filter(|&&r| r > 0.0).count() as u64;
        for (method, shadows) in [
            (Method::Lgh { alpha: 2.0 }, Shadows::CubeMap),
            (Method::Lgh { alpha: 2.0 }, Shadows::RayMarch),
            (Method::Brute, Shadows::RayMarch),
        ] {
            let settings = MarchSettings {
                shadows,
                ..Default::default()
            };
            let s = pass(&emission, 2, method, &volume, &pass_medium, &settings);
            for d in s.depths() {
                assert_eq!(
                    d.stats.shading_points, smoke,
                    "{method:?}: every voxel queried"
                );
                assert_eq!(d.power, 0.0);
            }
            assert!(s.lights().lights().len() as u64 >= smoke);
            let own = ExplosionLights::at_voxels(
                &volume.density,
                s.lights().voxels().to_vec(),
                &vec![Vec3::ZERO; s.lights().lights().len()],
                None,
            )
            .unwrap();
            assert!(own.hierarchy().max_level() > emission.hierarchy().max_level());
            assert!(s.lights().lights().len() > emission.lights().len());
            assert_eq!(s.lights().lit(), emission.lit());
            let render = |lights: &ExplosionLights| {
                let frame = &volume;
                crate::FrameRender::new(lights, method, frame, &render_medium, &settings, &())
                    .and_then(|f| f.render(&camera, &()))
                    .unwrap()
                    .0
            };
            let single = render(&emission);
            assert!(single.pixels.iter().any(|p| p.max_element() > 0.0));
            assert!(
                bits(&render(s.lights()).pixels) == bits(&single.pixels),
                "{method:?}, {shadows:?}: the images differ"
            );
        }
    }
}
