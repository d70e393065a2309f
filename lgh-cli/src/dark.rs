//! Why a render is dark: one line naming the grid and the flags that change it, instead of a
//! black image and "0 lights" (issue 16: a smoke plume, whose `flame` grid is zero everywhere,
//! rendered black with the defaults).

use lgh_volume::cache::GridNames;
use lgh_volume::{Medium, Volume};

/// Why `volume` has no lights under `medium`, read with `names`, and, when its smoke is nearly
/// invisible too ([`faint_smoke`]), that as well; `None` if it has lights.
#[must_use]
pub fn why_no_lights(volume: &Volume, medium: &Medium, names: &GridNames) -> Option<String> {
    let n = volume.temperature.data.len();
    if (0..n).any(|i| volume.voxel_emits(medium, i)) {
        return None;
    }
    let why = no_light_cause(volume, medium, names);
    Some(match faint_smoke(volume, medium, names) {
        Some(faint) => format!("{why}; and {faint}"),
        None => why,
    })
}

/// The first reason [`why_no_lights`] gives.
fn no_light_cause(volume: &Volume, medium: &Medium, names: &GridNames) -> String {
    let n = volume.temperature.data.len();
    if medium.emission == 0.0 {
        return "--emission-scale is 0".into();
    }
    let t = &volume.temperature.data;
    if !(0..n).any(|i| volume.value_emits(medium, t[i])) {
        let peak = t
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f32::NEG_INFINITY, f32::max);
        if peak <= 0.0 || peak == f32::NEG_INFINITY {
            return format!(
                "the '{}' grid holds no positive value: name the grid emission follows with \
                 --emission-grid (`lgh inspect FILE` lists them)",
                names.emission
            );
        }
        return format!(
            "the hottest voxel of the '{}' grid holds {peak} ({} K at --temperature-scale {}), \
             not above --min-temperature {}: lower --min-temperature or raise \
             --temperature-scale",
            names.emission,
            peak * medium.temperature_scale,
            medium.temperature_scale,
            medium.min_temperature
        );
    }
    // Hot voxels, and none emits: the flame factor is zero wherever it is hot.
    let flame = names.flame.as_deref().unwrap_or("flame");
    format!(
        "the '{flame}' grid is zero wherever '{}' is above --min-temperature {} (a smoke plume, \
         not a fire?): --flame-grid none lights it by temperature alone",
        names.emission, medium.min_temperature
    )
}

/// Optical depth under which smoke counts as nearly invisible: 95% of the light goes through.
const FAINT_OPTICAL_DEPTH: f32 = 0.05;

/// Said when the smoke of `volume` is nearly invisible: even a ray crossing the whole grid
/// through its densest voxel's density everywhere would keep more than 95% of its light. (Only
/// with no lights: the dev fire's smoke is that thin, and its fire is what one sees.)
#[must_use]
fn faint_smoke(volume: &Volume, medium: &Medium, names: &GridNames) -> Option<String> {
    let g = &volume.density;
    let densest = g
        .data
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    let longest = g.dims.iter().copied().max().unwrap_or(0) as f32 * g.voxel_size;
    let tau = medium.extinction(densest) * longest;
    (tau < FAINT_OPTICAL_DEPTH).then(|| {
        format!(
            "the smoke is nearly invisible: its optical depth across the grid is at most {tau:.3} \
             (the '{}' grid peaks at {densest}); raise --density-scale to see it",
            names.density
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgh_volume::DenseGrid;

    fn grid(values: &[f32]) -> DenseGrid {
        DenseGrid {
            dims: [values.len(), 1, 1],
            voxel_size: 0.1,
            origin: lgh_core::glam::Vec3::ZERO,
            data: values.to_vec(),
        }
    }

    fn fire(temperature: &[f32], flame: Option<&[f32]>) -> Volume {
        let mut v = Volume::new(grid(&[1.0; 4]), grid(temperature));
        v.flame = flame.map(grid);
        v
    }

    #[test]
    fn each_cause_of_darkness_is_named_with_its_flag() {
        let medium = Medium::new(1.0, 1.0, 1.0, 800.0)
            .unwrap()
            .with_temperature_scale(1000.0)
            .unwrap();
        let names = GridNames::default();
        let why = |v: &Volume, m: &Medium| why_no_lights(v, m, &names).unwrap_or_default();
        // A fire: no reason.
        assert_eq!(
            why_no_lights(&fire(&[0.0, 2.0, 3.0, 0.0], None), &medium, &names),
            None
        );
        // A plume: hot, but its flame grid is zero.
        let plume = fire(&[0.0, 2.0, 3.0, 0.0], Some(&[0.0; 4]));
        assert!(
            why(&plume, &medium).contains("--flame-grid none"),
            "{}",
            why(&plume, &medium)
        );
        // Too cold for the minimum temperature.
        let cold = fire(&[0.1, 0.5, 0.2, 0.0], None);
        let w = why(&cold, &medium);
        assert!(
            w.contains("holds 0.5 (500 K") && w.contains("--min-temperature 800"),
            "{w}"
        );
        // A grid without a positive value.
        let w = why(&fire(&[0.0; 4], None), &medium);
        assert!(w.contains("--emission-grid"), "{w}");
        // No emission at all.
        let mut off = medium.clone();
        off.emission = 0.0;
        assert_eq!(why(&plume, &off), "--emission-scale is 0");
        // A plume of thin smoke: both are said, each with its flag.
        let mut thin = plume.clone();
        thin.density.data.fill(0.01);
        let w = why(&thin, &medium);
        assert!(
            w.contains("temperature alone; and the smoke is nearly invisible"),
            "{w}"
        );
        assert!(w.contains("--density-scale"), "{w}");
    }

    #[test]
    fn faint_smoke_is_told_and_visible_smoke_is_not() {
        // Four voxels of 0.1: the grid is 0.4 across; σ_t = 2 per unit density.
        let medium = Medium::new(1.0, 1.0, 1.0, 800.0).unwrap();
        let thin = Volume::new(grid(&[0.0, 0.05, 0.0, 0.0]), grid(&[0.0; 4]));
        let w = faint_smoke(&thin, &medium, &GridNames::default()).unwrap();
        assert!(
            w.contains("at most 0.040") && w.contains("--density-scale"),
            "{w}"
        );
        let thick = Volume::new(grid(&[0.0, 0.1, 0.0, 0.0]), grid(&[0.0; 4]));
        assert_eq!(faint_smoke(&thick, &medium, &GridNames::default()), None);
    }
}
