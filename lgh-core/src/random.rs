//! Seeded, deterministic random numbers and noise for production code: Lightcuts' stochastic
//! representatives, the path tracer, the procedural explosion and Paquette's scenes.
//!
//! Everything here is integer hashing (no global RNG, no platform-dependent maths beyond correctly
//! rounded operations), so every machine draws the same numbers from the same seed.

use glam::Vec3;

/// SplitMix64: a small, fast, well-mixed deterministic generator.
///
/// ```
/// use lgh_core::random::SplitMix64;
///
/// let mut a = SplitMix64(42);
/// let mut b = SplitMix64(42);
/// assert_eq!(a.next_u64(), b.next_u64()); // the same seed, the same numbers, on every machine
/// for _ in 0..1000 {
///     let u = a.next_f32();
///     assert!((0.0..1.0).contains(&u));
/// }
/// ```
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        Self::mix(self.0)
    }

    /// SplitMix64's output function: a bijective 64-bit mix, also a good hash of a seed.
    #[must_use]
    pub fn mix(mut z: u64) -> u64 {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// Uniform in `[0, 1)`, with 53 random bits: for probabilities too small for
    /// [`next_f32`](Self::next_f32)'s 24.
    ///
    /// ```
    /// use lgh_core::random::SplitMix64;
    ///
    /// let mut rng = SplitMix64(7);
    /// let u: Vec<f64> = (0..1000).map(|_| rng.next_f64()).collect();
    /// assert!(u.iter().all(|u| (0.0..1.0).contains(u)));
    /// // Finer than 2⁻²⁴: some draw has bits below f32's.
    /// assert!(u.iter().any(|&u| u != f64::from(u as f32)));
    /// ```
    #[must_use]
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[lo, hi)` per axis.
    pub fn next_in(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        let t = Vec3::new(self.next_f32(), self.next_f32(), self.next_f32());
        lo + (hi - lo) * t
    }

    /// A unit vector, uniform on the sphere (by rejection from the cube).
    pub fn next_unit(&mut self) -> Vec3 {
        loop {
            let v = self.next_in(Vec3::splat(-1.0), Vec3::ONE);
            let l2 = v.length_squared();
            if (0.01..1.0).contains(&l2) {
                return v / crate::math::sqrt(l2);
            }
        }
    }
}

fn lattice_hash(x: i32, y: i32, z: i32, seed: u32) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x8DA6_B343)
        ^ (y as u32).wrapping_mul(0xD816_3841)
        ^ (z as u32).wrapping_mul(0xCB1A_B31F)
        ^ seed.wrapping_mul(0x1656_67B1);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297A_2D39);
    h ^= h >> 15;
    (h >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
}

/// Smooth value noise in `[-1, 1]` with unit lattice spacing.
#[must_use]
pub fn value_noise(p: Vec3, seed: u32) -> f32 {
    value_noise_gradient(p, seed).0
}

/// [`value_noise`] and its gradient `∂n/∂p`, in one pass: the value is the same to the bit. The
/// noise is C¹ (its smoothstep weights have zero slope at the lattice planes), so the gradient is
/// continuous; curl noise takes it from three seeds.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::random::{value_noise, value_noise_gradient};
///
/// let p = Vec3::new(0.3, 1.7, -2.2);
/// let (n, g) = value_noise_gradient(p, 5);
/// assert_eq!(n, value_noise(p, 5));
/// // The gradient is the noise's slope: a central difference agrees with it.
/// let e = 1e-3;
/// let dx = (value_noise(p + Vec3::X * e, 5) - value_noise(p - Vec3::X * e, 5)) / (2.0 * e);
/// assert!((dx - g.x).abs() < 1e-2, "{dx} {}", g.x);
/// ```
#[must_use]
pub fn value_noise_gradient(p: Vec3, seed: u32) -> (f32, Vec3) {
    let f = p.floor();
    let t = p - f;
    let s = t * t * (Vec3::splat(3.0) - 2.0 * t);
    // d s / d t of the smoothstep 3t² − 2t³.
    let ds = 6.0 * t * (Vec3::ONE - t);
    let (x, y, z) = (f.x as i32, f.y as i32, f.z as i32);
    let mut acc = 0.0;
    let mut grad = Vec3::ZERO;
    for k in 0..8 {
        let (dx, dy, dz) = (k & 1, (k >> 1) & 1, k >> 2);
        let (wx, gx) = if dx == 1 {
            (s.x, ds.x)
        } else {
            (1.0 - s.x, -ds.x)
        };
        let (wy, gy) = if dy == 1 {
            (s.y, ds.y)
        } else {
            (1.0 - s.y, -ds.y)
        };
        let (wz, gz) = if dz == 1 {
            (s.z, ds.z)
        } else {
            (1.0 - s.z, -ds.z)
        };
        let h = lattice_hash(x + dx, y + dy, z + dz, seed);
        acc += wx * wy * wz * h;
        grad += Vec3::new(gx * wy * wz, wx * gy * wz, wx * wy * gz) * h;
    }
    (acc, grad)
}

/// Fractal (turbulent) noise: `octaves` of value noise, frequency doubling, amplitude halving.
#[must_use]
pub fn fractal_noise(p: Vec3, octaves: u32, seed: u32) -> f32 {
    let mut sum = 0.0;
    let mut amp = 0.5;
    let mut freq = 1.0;
    for o in 0..octaves {
        sum += amp * value_noise(p * freq, seed.wrapping_add(o));
        amp *= 0.5;
        freq *= 2.0;
    }
    sum
}
