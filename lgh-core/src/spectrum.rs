//! Blackbody colour: Planck's law through the CIE 1931 2° observer to linear sRGB (Rec. 709
//! primaries, D65 white).
//!
//! The colour-matching functions are the analytic multi-lobe fit of Wyman, Sloan & Shirley,
//! "Simple Analytic Approximations to the CIE XYZ Color Matching Functions" (JCGT 2013), which is
//! within about 1% of the tabulated CIE 1931 data; the spectrum is integrated from 360 to 830 nm
//! in 1 nm steps.

use alloc::vec::Vec;
use glam::Vec3;

const H: f64 = 6.626_070_15e-34; // Planck constant, J s
const C: f64 = 2.997_924_58e8; // speed of light, m/s
const K: f64 = 1.380_649e-23; // Boltzmann constant, J/K

#[inline]
fn lobe(x: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let t = (x - mu) / if x < mu { s1 } else { s2 };
    libm::exp(-0.5 * t * t)
}

/// CIE 1931 colour-matching functions at wavelength `nm` (Wyman et al. 2013, multi-lobe fit).
#[must_use]
pub fn cie1931(nm: f64) -> [f64; 3] {
    let x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7)
        - 0.065 * lobe(nm, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
    [x, y, z]
}

/// Planck's spectral radiance `B(λ, T)` in W / (sr m² m) at wavelength `nm` and temperature `kelvin`.
#[must_use]
pub fn planck(nm: f64, kelvin: f64) -> f64 {
    let l = nm * 1e-9;
    let e = libm::expm1(H * C / (l * K * kelvin));
    2.0 * H * C * C / (l * l * l * l * l) / e
}

/// The wavelengths the blackbody's integral sums over, in nm: 360 to 830 by 1.
const WAVELENGTHS: core::ops::RangeInclusive<u16> = 360..=830;

/// CIE XYZ of a blackbody at `kelvin`: `∫ B(λ, T) x̄(λ) dλ` etc., in W / (sr m²). Zero for T ≤ 0.
#[must_use]
pub fn blackbody_xyz(kelvin: f32) -> [f64; 3] {
    xyz_with(kelvin, WAVELENGTHS.map(|nm| cie1931(f64::from(nm))))
}

/// [`blackbody_xyz`] with the colour-matching functions at each of [`WAVELENGTHS`] given (the
/// same for every temperature: a table computes them once, not once per entry — seven of
/// every eight exponentials of an integral).
fn xyz_with(kelvin: f32, cmf: impl IntoIterator<Item = [f64; 3]>) -> [f64; 3] {
    let t = kelvin as f64;
    if t.is_nan() || t <= 0.0 {
        return [0.0; 3];
    }
    let mut xyz = [0.0; 3];
    for (nm, c) in WAVELENGTHS.zip(cmf) {
        let b = planck(f64::from(nm), t) * 1e-9; // per nm step
        for a in 0..3 {
            xyz[a] += b * c[a];
        }
    }
    xyz
}

/// Linear sRGB (Rec. 709 primaries) of XYZ; negative (out-of-gamut) channels are clamped to 0.
#[must_use]
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> Vec3 {
    let [x, y, z] = xyz;
    let r = 3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z;
    let g = -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z;
    let b = 0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z;
    Vec3::new(r.max(0.0) as f32, g.max(0.0) as f32, b.max(0.0) as f32)
}

/// Blackbody radiance at `kelvin` as linear sRGB, in W / (sr m²) (luminance channel = CIE Y).
#[must_use]
pub fn blackbody_rgb(kelvin: f32) -> Vec3 {
    xyz_to_linear_srgb(blackbody_xyz(kelvin))
}

/// Blackbody radiance ([`blackbody_rgb`]) tabulated every `step` kelvin over `[min, max]` and
/// interpolated linearly: integrating Planck's law against the CIE functions costs about 500
/// exponentials, which a per-voxel emission cannot afford. Outside the table it is evaluated
/// exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct BlackbodyTable {
    min: f32,
    step: f32,
    values: Vec<Vec3>,
}

impl BlackbodyTable {
    /// A table over `[min, max]` kelvin with the given step (all finite, `0 < min < max`,
    /// `step > 0`; at most a million entries).
    #[must_use]
    pub fn new(min: f32, max: f32, step: f32) -> Option<Self> {
        let valid = min > 0.0 && max > min && step > 0.0 && max.is_finite();
        let n = ((max - min) / step) as usize + 2;
        if !valid || n > 1_000_000 {
            return None;
        }
        let cmf: Vec<[f64; 3]> = WAVELENGTHS.map(|nm| cie1931(f64::from(nm))).collect();
        let values = (0..n)
            .map(|i| xyz_to_linear_srgb(xyz_with(min + i as f32 * step, cmf.iter().copied())))
            .collect();
        Some(BlackbodyTable { min, step, values })
    }

    /// Radiance at `kelvin` (linear sRGB, W / (sr m²)); zero for T ≤ 0 or NaN.
    #[must_use]
    pub fn radiance(&self, kelvin: f32) -> Vec3 {
        let t = (kelvin - self.min) / self.step;
        if t.is_nan() || t < 0.0 || t >= (self.values.len() - 1) as f32 {
            return blackbody_rgb(kelvin);
        }
        let i = t as usize;
        let f = t - i as f32;
        self.values[i].lerp(self.values[i + 1], f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::luminance;
    use wasm_bindgen_test::wasm_bindgen_test;

    #[wasm_bindgen_test(unsupported = test)]
    fn hotter_is_brighter_and_bluer() {
        let a = blackbody_rgb(1500.0);
        let b = blackbody_rgb(3000.0);
        let c = blackbody_rgb(6500.0);
        assert!(luminance(a) < luminance(b) && luminance(b) < luminance(c));
        assert!(a.x > a.z && b.x > b.z, "low temperatures are red: {a} {b}");
        // Near 6500 K a blackbody is close to the D65 white: channels within 15% of each other.
        let n = c / c.max_element();
        assert!(n.min_element() > 0.85, "{n}");
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn table_matches_the_integral() {
        let table = BlackbodyTable::new(800.0, 4000.0, 1.0).unwrap();
        for k in [800.0f32, 1234.5, 2500.0, 3999.9, 500.0, 6000.0] {
            let exact = blackbody_rgb(k);
            let got = table.radiance(k);
            // Linear interpolation over 1 K of a smooth curve: far below 0.1% (T⁴-like growth).
            assert!(
                (got - exact).abs().max_element() <= 1e-3 * exact.max_element(),
                "{k}: {got} vs {exact}"
            );
        }
        // Its entries are the integral itself, bit for bit (the functions computed once).
        for k in [800.0f32, 801.0, 2345.0, 4000.0] {
            assert_eq!(table.radiance(k), blackbody_rgb(k), "{k}");
        }
        assert_eq!(table.radiance(-5.0), Vec3::ZERO);
        assert!(BlackbodyTable::new(0.0, 10.0, 1.0).is_none());
        assert!(BlackbodyTable::new(1.0, 1e9, 1.0).is_none());
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn wien_displacement() {
        // Peak of B(λ, 5000 K) is at b / T = 579.6 nm.
        let peak = (300..1000)
            .max_by(|&a, &b| planck(a as f64, 5000.0).total_cmp(&planck(b as f64, 5000.0)));
        assert!((peak.unwrap() as f64 - 579.6).abs() < 1.5);
    }
}
