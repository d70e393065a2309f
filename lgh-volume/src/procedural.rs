//! The embedded procedural explosion: a deterministic, turbulent fireball with no download,
//! the default scene of `lgh demo` and the benchmarks.

use lgh_core::glam::Vec3;
use lgh_core::random::fractal_noise;

use crate::error::{check_setting, VolumeError};
use crate::medium::Volume;
use crate::DenseGrid;

/// A deterministic procedural fireball on a `res³` grid filling the cube `[-1, 1]³`, at time
/// `time` (0 = ignition, 1 = one second later): a turbulent ball of smoke whose radius grows
/// from 0.35 to 0.7 while its hot core (up to 3400 K) expands and cools. `res` must be in
/// `32..=512`.
pub fn procedural(res: usize, time: f32) -> Result<Volume, VolumeError> {
    if !(32..=512).contains(&res) {
        return Err(VolumeError::InvalidCount {
            name: "resolution",
            value: res,
            rule: "is outside 32..=512",
        });
    }
    check_setting(
        time.is_finite() && (0.0..=10.0).contains(&time),
        "time",
        time,
        "is outside 0..=10 s",
    )?;
    let h = 2.0 / res as f32;
    let origin = Vec3::splat(-1.0 + 0.5 * h);
    let mut density = DenseGrid::zeros([res; 3], h, origin);
    let mut temperature = DenseGrid::zeros([res; 3], h, origin);
    let radius = 0.35 + 0.35 * time.min(1.0);
    let t_max = 3400.0 - 800.0 * time.min(1.0);
    let drift = Vec3::new(0.3, 1.1, -0.2) * time;
    let slab = res * res;
    let fill = |k: usize, rho: &mut [f32], temp: &mut [f32]| {
        for j in 0..res {
            for i in 0..res {
                let p = origin + Vec3::new(i as f32, j as f32, k as f32) * h;
                let q = p * 3.0 + drift;
                let r = p.length() * (1.0 + 0.35 * fractal_noise(q, 4, 17));
                let shell = 1.0 - (r / radius).powi(4);
                if shell <= 0.0 {
                    continue;
                }
                let n = 0.65 + 0.35 * fractal_noise(p * 7.0 + drift * 2.0, 3, 29);
                rho[j * res + i] = (shell * n).clamp(0.0, 1.0);
                let core = (1.0 - r / (0.8 * radius)).max(0.0);
                let heat = core.powf(0.6) * (0.8 + 0.2 * fractal_noise(p * 5.0 - drift, 3, 41));
                temp[j * res + i] = t_max * heat.clamp(0.0, 1.0);
            }
        }
    };
    {
        use rayon::prelude::*;
        density
            .data
            .par_chunks_mut(slab)
            .zip(temperature.data.par_chunks_mut(slab))
            .enumerate()
            .for_each(|(k, (rho, temp))| fill(k, rho, temp));
    }
    Ok(Volume::new(density, temperature))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn procedural_explosion_is_deterministic_and_grows() {
        let a = procedural(32, 0.2).unwrap();
        let b = procedural(32, 0.2).unwrap();
        assert_eq!(a, b);
        let later = procedural(32, 0.9).unwrap();
        let count = |g: &DenseGrid| g.data.iter().filter(|&&v| v > 0.0).count();
        assert!(count(&later.density) > count(&a.density), "the smoke grows");
        assert!(a
            .temperature
            .data
            .iter()
            .all(|&t| (0.0..=2600.0).contains(&t)));
        assert!(count(&a.temperature) > 0 && count(&a.temperature) < count(&a.density));
        assert!(procedural(16, 0.0).is_err());
        assert!(procedural(64, f32::NAN).is_err());
    }
}
