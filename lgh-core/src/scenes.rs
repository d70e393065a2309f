//! Light sets of published test scenes, built always (not test data): production code renders
//! them.
//!
//! - [`light_strings`]: the lights of Paquette, Poulin & Drettakis' "Light Strings" scene
//!   (Eurographics 1998, Fig. 7a; `lgh paquette`, lgh-vpl's `paquette` module). The same curve is
//!   lgh-core's benchmark set (c) (`testsets::light_strings` with the feature `testsets`, which
//!   calls this one): one implementation for the scene, the benches and the tests.

use alloc::vec::Vec;
use glam::Vec3;

use crate::light::PointLight;

/// `n` equal lights (intensity 1) along 8 long curves ("light strings") spanning about
/// 20 × 4 × 10 units, sagging between their ends like strings of lights between poles; light `i`
/// is on string `i % 8`.
///
/// ```
/// let lights = lgh_core::scenes::light_strings(64);
/// assert_eq!(lights.len(), 64);
/// assert!(lights.iter().all(|l| l.position.x >= -10.0 && l.position.x <= 10.0));
/// ```
#[must_use]
pub fn light_strings(n: usize) -> Vec<PointLight> {
    const STRINGS: usize = 8;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let s = i % STRINGS;
        let t = (i / STRINGS) as f32 / (n.div_ceil(STRINGS).max(2) - 1) as f32;
        let sf = s as f32;
        let x = -10.0 + 20.0 * t;
        let sag = 4.0 * t * (1.0 - t); // catenary-like droop between poles
        let y = 4.0 - 1.5 * sag + 0.3 * libm::sinf(3.0 * x + sf);
        let z = -5.0 + 10.0 * sf / (STRINGS - 1) as f32 + 0.8 * libm::sinf(0.7 * x + 2.0 * sf);
        out.push(PointLight::new(Vec3::new(x, y, z), Vec3::ONE));
    }
    out
}
