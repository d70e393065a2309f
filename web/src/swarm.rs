//! The scene: a shell of glowing embers around an explosion's centre, expanding and
//! flickering over a ground plane (the C++ example's, `examples/c/swarm.h`, transcribed: the
//! same operations in the same order, so the same floats), with three spheres on the ground.
//! Only IEEE-exact operations (`+ − × ÷`, `sqrt`, `floor`), so that every platform agrees bit
//! for bit.

/// SplitMix64: the embers' fixed random numbers.
#[must_use]
pub fn next(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A float in `[0, 1)` from the top 24 bits of [`next`]: exact.
#[must_use]
pub fn unit(state: &mut u64) -> f32 {
    (next(state) >> 40) as f32 * (1.0 / 16_777_216.0)
}

/// A triangle wave in `[0, 1]` of period 1.
#[must_use]
pub fn wave(t: f32) -> f32 {
    let f = t - libm::floorf(t);
    if f < 0.5 {
        2.0 * f
    } else {
        2.0 - 2.0 * f
    }
}

/// Ember `i` at `frame`: its position and RGB intensity (W/sr). The shell's radius grows from
/// 0.5 to 2.5 over 48 frames around `(0, 1.5, 0)`; each ember flickers at its own rate, from
/// a hot core to red.
///
/// ```
/// let (p, i) = lgh_web::swarm::light(7, 0);
/// let r = ((p[0]) * p[0] + (p[1] - 1.5) * (p[1] - 1.5) + p[2] * p[2]).sqrt();
/// assert!((0.4..0.6).contains(&r)); // frame 0: radius 0.5 ± 15%
/// assert!(i[0] >= i[1] && i[1] >= i[2] && i[2] > 0.0);
/// ```
#[must_use]
pub fn light(i: usize, frame: i32) -> ([f32; 3], [f32; 3]) {
    let mut state = 0x5EED_0000u64 + i as u64;
    let (mut d, mut len2);
    loop {
        d = [0.0f32; 3];
        for v in &mut d {
            *v = 2.0 * unit(&mut state) - 1.0;
        }
        len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (1e-4..=1.0).contains(&len2) {
            break;
        }
    }
    let len = libm::sqrtf(len2);
    let t = frame as f32 / 48.0;
    let radius = (0.5 + 2.0 * t) * (0.85 + 0.3 * unit(&mut state));
    let position = [
        d[0] / len * radius,
        1.5 + d[1] / len * radius,
        d[2] / len * radius,
    ];
    let rate = 0.5 + 2.0 * unit(&mut state);
    let phase = unit(&mut state);
    let glow = (0.25 + 0.75 * wave(rate * t + phase)) * (1.0 - 0.7 * t);
    let heat = unit(&mut state);
    let intensity = [
        glow * 0.004,
        glow * 0.004 * (0.35 + 0.5 * heat),
        glow * 0.004 * (0.05 + 0.3 * heat * heat),
    ];
    (position, intensity)
}

/// The point `(x, 0, z)` of the square `[−4, 4]²` that pixel `(px, py)` of a `size` × `size`
/// image looks down on.
#[must_use]
pub fn ground_point(px: i32, py: i32, size: i32) -> [f32; 3] {
    [
        -4.0 + 8.0 * (px as f32 + 0.5) / size as f32,
        0.0,
        -4.0 + 8.0 * (py as f32 + 0.5) / size as f32,
    ]
}

/// A sphere resting on the ground: centre, radius, albedo.
pub struct Sphere {
    /// The centre, in the scene's units (y up; the ground is y = 0).
    pub centre: [f32; 3],
    /// The radius: the sphere touches the ground where `centre[1] == radius`.
    pub radius: f32,
    /// The Lambertian albedo, linear RGB.
    pub albedo: [f32; 3],
}

/// The three spheres on the ground, inside the shell's path.
pub const SPHERES: [Sphere; 3] = [
    Sphere {
        centre: [-1.6, 0.7, 1.1],
        radius: 0.7,
        albedo: [0.8, 0.35, 0.2],
    },
    Sphere {
        centre: [1.4, 0.9, -0.9],
        radius: 0.9,
        albedo: [0.25, 0.5, 0.8],
    },
    Sphere {
        centre: [0.5, 0.45, 2.4],
        radius: 0.45,
        albedo: [0.85, 0.85, 0.85],
    },
];

/// The ground's albedo.
pub const GROUND: [f32; 3] = [0.6, 0.6, 0.6];

/// What pixel `(px, py)` sees, looking straight down: the top of the highest sphere under it
/// or the ground — its position, unit normal and albedo.
///
/// ```
/// use lgh_web::swarm::{surface, GROUND};
///
/// let (p, n, albedo) = surface(0, 0, 64); // a corner: the ground
/// assert_eq!((p[1], n, albedo), (0.0, [0.0, 1.0, 0.0], GROUND));
/// ```
#[must_use]
pub fn surface(px: i32, py: i32, size: i32) -> ([f32; 3], [f32; 3], [f32; 3]) {
    let [x, _, z] = ground_point(px, py, size);
    let mut best = ([x, 0.0, z], [0.0, 1.0, 0.0], GROUND);
    for s in &SPHERES {
        let (dx, dz) = (x - s.centre[0], z - s.centre[2]);
        let h2 = s.radius * s.radius - dx * dx - dz * dz;
        if h2 <= 0.0 {
            continue;
        }
        let dy = libm::sqrtf(h2);
        let y = s.centre[1] + dy;
        if y > best.0[1] {
            let n = [dx / s.radius, dy / s.radius, dz / s.radius];
            best = ([x, y, z], n, s.albedo);
        }
    }
    best
}

/// What each pixel of a `width` × `height` image sees ([`surface`]), row by row from the top:
/// the page's square view of side `max(width, height)`, of which a band where the image is not
/// square.
///
/// ```
/// use lgh_web::swarm::{surface, view};
///
/// let pixels: Vec<_> = view(4, 2).collect();
/// assert_eq!(pixels.len(), 8);
/// assert_eq!(pixels[5], surface(1, 1, 4));
/// ```
pub fn view(width: u32, height: u32) -> impl Iterator<Item = ([f32; 3], [f32; 3], [f32; 3])> {
    let side = width.max(height) as i32;
    (0..height as i32).flat_map(move |py| (0..width as i32).map(move |px| surface(px, py, side)))
}
