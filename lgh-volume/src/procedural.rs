//! The embedded procedural explosions, with no download: [`procedural`], a soft turbulent
//! fireball (kept as it is: many tests' bounds are justified on its exact field), and
//! [`explosion`], a billowing fireball in a shell of soot (the default scene of `lgh demo` and
//! the benchmarks), with its parameters in [`Explosion`].

use lgh_core::glam::Vec3;
use lgh_core::random::{fractal_noise, value_noise, value_noise_gradient, SplitMix64};

use crate::error::{check_setting, RenderError};
use crate::grid::DenseGrid;
use crate::medium::Volume;

/// Checks a generator's resolution (`32..=512`) and time (`0..=10` s).
fn check_grid(res: usize, time: f32) -> Result<(), RenderError> {
    if !(32..=512).contains(&res) {
        return Err(RenderError::InvalidCount {
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
    Ok(())
}

/// A `res³` frame filling the cube `[-1, 1]³` whose voxel at centre `p` holds
/// `voxel(p) = (density, temperature)`; z-slabs in parallel, each voxel on its own, so the
/// result does not depend on the thread count.
fn fill(res: usize, voxel: impl Fn(Vec3) -> (f32, f32) + Sync) -> Volume {
    use rayon::prelude::*;
    let h = 2.0 / res as f32;
    let origin = Vec3::splat(-1.0 + 0.5 * h);
    let mut density = DenseGrid::zeros([res; 3], h, origin);
    let mut temperature = DenseGrid::zeros([res; 3], h, origin);
    let slab = res * res;
    density
        .data
        .par_chunks_mut(slab)
        .zip(temperature.data.par_chunks_mut(slab))
        .enumerate()
        .for_each(|(k, (rho, temp))| {
            for j in 0..res {
                for i in 0..res {
                    let p = origin + Vec3::new(i as f32, j as f32, k as f32) * h;
                    (rho[j * res + i], temp[j * res + i]) = voxel(p);
                }
            }
        });
    Volume::new(density, temperature)
}

/// Radius of a ball of [`bouncing_balls`] in `[-1, 1]³` units.
pub const BALL_RADIUS: f32 = 0.06;

/// Animated lights in general (the paper's Fig. 12 class): `count` glowing balls bouncing on the
/// floor of `[-1, 1]³` on a `res³` grid at `time` seconds, over a thin layer of smoke on the
/// floor that their light falls on. Each ball is a translucent volume (density 0.5, so they
/// shadow one another) hot at its centre (3000 K, falling to 1000 K at its rim, where the
/// demo's medium stops glowing), bouncing with its own height and period and drifting
/// sideways between the walls; the smoke layer (density 1.5 below y = −0.8) does not glow. Its
/// lights move every frame, so a hierarchy over them is rebuilt every frame: what the paper's
/// smooth splat and blending must keep from flickering. Deterministic; `count` at most 100,000.
///
/// ```
/// use lgh_volume::procedural::bouncing_balls;
///
/// let (a, b) = (bouncing_balls(48, 200, 0.0)?, bouncing_balls(48, 200, 0.1)?);
/// assert_ne!(a.temperature.data, b.temperature.data); // they move
/// assert_eq!(a.temperature.data, bouncing_balls(48, 200, 0.0)?.temperature.data);
/// assert!(a.temperature.data.iter().any(|&t| t > 2000.0));
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
pub fn bouncing_balls(res: usize, count: usize, time: f32) -> Result<Volume, RenderError> {
    check_grid(res, time)?;
    if count > 100_000 {
        return Err(RenderError::InvalidCount {
            name: "balls",
            value: count,
            rule: "is above 100,000",
        });
    }
    let h = 2.0 / res as f32;
    let origin = Vec3::splat(-1.0 + 0.5 * h);
    let mut density = DenseGrid::zeros([res; 3], h, origin);
    let mut temperature = DenseGrid::zeros([res; 3], h, origin);
    // The smoke on the floor.
    for k in 0..res {
        for j in 0..res {
            if origin.y + j as f32 * h < -0.8 {
                for i in 0..res {
                    density.data[(k * res + j) * res + i] = 1.5;
                }
            }
        }
    }
    let r = BALL_RADIUS;
    let mut rng = SplitMix64(0xBA11_5EED);
    for _ in 0..count {
        let start = rng.next_in(Vec3::new(-0.9, 0.0, -0.9), Vec3::new(0.9, 0.0, 0.9));
        let drift = rng.next_in(Vec3::new(-0.4, 0.0, -0.4), Vec3::new(0.4, 0.0, 0.4));
        let height = 0.3 + 1.3 * rng.next_f32();
        let period = 0.6 + 0.8 * rng.next_f32();
        let phase = rng.next_f32();
        // A bounce is a parabola: y = floor + height · 4s(1 − s) over each period.
        let s = (time / period + phase).fract();
        let y = -1.0 + r + height * 4.0 * s * (1.0 - s);
        // Sideways, reflected at the walls (a triangle wave over [-0.9, 0.9]).
        let wall = |x: f32| {
            let u = (x + 0.9).rem_euclid(3.6);
            if u > 1.8 {
                3.6 - u - 0.9
            } else {
                u - 0.9
            }
        };
        let moved = start + drift * time;
        let c = Vec3::new(wall(moved.x), y.min(1.0 - r), wall(moved.z));
        let lo = ((c - Vec3::splat(r) - origin) / h).floor().max(Vec3::ZERO);
        let hi = ((c + Vec3::splat(r) - origin) / h)
            .ceil()
            .min(Vec3::splat((res - 1) as f32));
        for k in lo.z as usize..=hi.z as usize {
            for j in lo.y as usize..=hi.y as usize {
                for i in lo.x as usize..=hi.x as usize {
                    let p = origin + Vec3::new(i as f32, j as f32, k as f32) * h;
                    let d = (p - c).length() / r;
                    if d < 1.0 {
                        let v = (k * res + j) * res + i;
                        density.data[v] = density.data[v].max(0.5);
                        let t = 3000.0 - 2000.0 * d;
                        temperature.data[v] = temperature.data[v].max(t);
                    }
                }
            }
        }
    }
    Ok(Volume::new(density, temperature))
}

/// A smooth test scene: a ball of smoke on `n³` voxels over `[-1, 1]³`, density 1 at the centre
/// falling linearly to 0 at radius 0.8, around a hot core of `core_kelvin` at the centre falling
/// linearly to 0 K at radius `core_radius`. Small and exactly reproducible: what the scattering
/// tests and their path-traced comparison shade.
///
/// ```
/// use lgh_volume::procedural::ball;
///
/// let v = ball(16, 0.35, 2500.0);
/// assert_eq!(v.density.dims, [16; 3]);
/// // The voxel centres nearest the middle are √3·h/2 from it (h = 1/8).
/// let hottest = v.temperature.data.iter().fold(0.0f32, |a, &t| a.max(t));
/// assert!((hottest - 2500.0 * (1.0 - 0.0625 * 3f32.sqrt() / 0.35)).abs() < 0.01);
/// ```
#[must_use]
pub fn ball(n: usize, core_radius: f32, core_kelvin: f32) -> Volume {
    let h = 2.0 / n as f32;
    let origin = Vec3::splat(-1.0 + 0.5 * h);
    let mut density = DenseGrid::zeros([n; 3], h, origin);
    let mut temperature = density.clone();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let r = density.centre(i, j, k).length();
                let idx = density.index(i, j, k);
                density.data[idx] = (1.0 - r / 0.8).max(0.0);
                temperature.data[idx] = core_kelvin * (1.0 - r / core_radius).max(0.0);
            }
        }
    }
    Volume::new(density, temperature)
}

/// A deterministic procedural fireball on a `res³` grid filling the cube `[-1, 1]³`, at time
/// `time` (0 = ignition, 1 = one second later): a turbulent ball of smoke whose radius grows
/// from 0.35 to 0.7 while its hot core (up to 3400 K) expands and cools. `res` must be in
/// `32..=512`.
pub fn procedural(res: usize, time: f32) -> Result<Volume, RenderError> {
    check_grid(res, time)?;
    let radius = 0.35 + 0.35 * time.min(1.0);
    let t_max = 3400.0 - 800.0 * time.min(1.0);
    let drift = Vec3::new(0.3, 1.1, -0.2) * time;
    Ok(fill(res, |p| {
        let q = p * 3.0 + drift;
        let r = p.length() * (1.0 + 0.35 * fractal_noise(q, 4, 17));
        let shell = 1.0 - (r / radius).powi(4);
        if shell <= 0.0 {
            return (0.0, 0.0);
        }
        let n = 0.65 + 0.35 * fractal_noise(p * 7.0 + drift * 2.0, 3, 29);
        let core = (1.0 - r / (0.8 * radius)).max(0.0);
        let heat = core.powf(0.6) * (0.8 + 0.2 * fractal_noise(p * 5.0 - drift, 3, 41));
        ((shell * n).clamp(0.0, 1.0), t_max * heat.clamp(0.0, 1.0))
    }))
}

/// The parameters of [`explosion`]: a fireball of several smooth-joined lobes whose surface
/// billows (multi-octave cauliflower noise, displaced along a curl-noise flow), a hot core that
/// breaks out through a dense rim of soot, growing and cooling smoothly with time. Lengths are
/// in world units (the grid spans `[-1, 1]³`) or fractions of the radius, as each field says;
/// [`Default`] is the demo's explosion. [`validate`](Self::validate) says which values are
/// allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct Explosion {
    /// Seed of every noise and of the lobes' placement.
    pub seed: u32,
    /// Radius the fireball grows to, world units (`0.05..=0.75`).
    pub radius: f32,
    /// Radius at ignition, as a fraction of [`radius`](Self::radius) (`0.05..=1`).
    pub initial_radius: f32,
    /// Time constant of the growth, seconds (`0.01..=10`): the radius is
    /// `radius · (1 − (1 − initial) e^{−t/τ})`.
    pub expansion_time: f32,
    /// Secondary lobes around the main ball (`0..=12`).
    pub lobes: usize,
    /// Height of the billows, a fraction of the radius (`0..=1`).
    pub billow: f32,
    /// Displacement along the curl-noise flow, a fraction of the radius (`0..=0.5`).
    pub turbulence: f32,
    /// How far the centre rises as the fireball grows, a fraction of the radius (`0..=1`).
    pub rise: f32,
    /// Peak density ρ of the soot (`0.01..=100`); the medium's κ turns it into extinction.
    pub soot: f32,
    /// Density left inside the burning core, a fraction of [`soot`](Self::soot) (`0..=1`).
    pub core_soot: f32,
    /// Depth of the soot rim before the fire begins, a fraction of the radius (`0..=1`).
    pub shell: f32,
    /// Temperature of the core at ignition, kelvin (`0..=20000`).
    pub core_temperature: f32,
    /// Time constant of the cooling, seconds (`0.01..=100`): the core's temperature is
    /// `core_temperature / sqrt(1 + t/τ)`.
    pub cooling_time: f32,
}

impl Default for Explosion {
    fn default() -> Self {
        Explosion {
            seed: 7,
            radius: 0.55,
            initial_radius: 0.3,
            expansion_time: 0.35,
            lobes: 6,
            billow: 0.5,
            turbulence: 0.06,
            rise: 0.2,
            soot: 6.0,
            core_soot: 0.05,
            shell: 0.15,
            core_temperature: 3200.0,
            cooling_time: 1.0,
        }
    }
}

/// One ball of the fireball: centre and radius as fractions of the fireball's radius, relative
/// to its centre.
#[derive(Clone, Copy, Debug)]
struct Lobe {
    offset: Vec3,
    radius: f32,
}

/// The polynomial smooth maximum of `a` and `b` over a blend width `k`: `max(a, b)` where they
/// are `k` apart or more, a rounded join nearer (continuous, never below the max).
fn smooth_max(a: f32, b: f32, k: f32) -> f32 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.max(b) + 0.25 * k * h * h
}

/// `0` below `a`, `1` above `b`, Hermite in between (`a < b`).
fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The curl of three value-noise potentials at `p`: a divergence-free flow (no sources or
/// sinks, so displacing along it swirls the smoke without bunching it).
fn curl_noise(p: Vec3, seed: u32) -> Vec3 {
    let (_, a) = value_noise_gradient(p, seed);
    let (_, b) = value_noise_gradient(p, seed.wrapping_add(1));
    let (_, c) = value_noise_gradient(p, seed.wrapping_add(2));
    Vec3::new(c.y - b.z, a.z - c.x, b.x - a.y)
}

/// Octaves of [`billows`].
const BILLOW_OCTAVES: u32 = 5;
/// The largest value of [`billows`]: twice the sum of its octaves' amplitudes.
const BILLOW_MAX: f32 = 2.0 * (1.0 - 1.0 / (1 << BILLOW_OCTAVES) as f32);
/// About the mean of [`billows`]: subtracted, so billows push the surface out and in alike.
const BILLOW_MEAN: f32 = 0.35;
/// The width of the smooth join of the lobes, in inside-ness.
const LOBE_BLEND: f32 = 0.25;
/// The longest curl-noise flow vector, before the turbulence scales it.
const FLOW_MAX: f32 = 2.0;

/// Billow noise: octaves of `|noise|`, rounded on top and creased between, as cauliflower
/// smoke is; `0..=BILLOW_MAX`, mean about [`BILLOW_MEAN`]. Each octave drifts on its own as
/// time passes.
fn billows(p: Vec3, seed: u32, drift: Vec3) -> f32 {
    let (mut sum, mut amp, mut freq) = (0.0, 0.5, 1.0);
    for o in 0..BILLOW_OCTAVES {
        sum += amp * value_noise(p * freq + drift * (1.0 + o as f32), seed.wrapping_add(o)).abs();
        amp *= 0.5;
        freq *= 2.03;
    }
    2.0 * sum
}

/// A setting's range: its name, its value, the lowest and highest valid values, and the rule
/// an error states.
type SettingRange = (&'static str, f32, f32, f32, &'static str);

impl Explosion {
    /// Checks every field (see each one's range); non-finite values are refused.
    ///
    /// ```
    /// use lgh_volume::procedural::Explosion;
    ///
    /// assert!(Explosion::default().validate().is_ok());
    /// let bad = Explosion { soot: f32::NAN, ..Explosion::default() };
    /// assert!(bad.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), RenderError> {
        for (name, value, lo, hi, rule) in self.setting_ranges() {
            check_setting(
                value.is_finite() && (lo..=hi).contains(&value),
                name,
                value,
                rule,
            )?;
        }
        Ok(())
    }

    /// Every field with its allowed range, in the order [`validate`](Self::validate) checks
    /// them: `(name, value, lo, hi, rule)`, the value valid when finite and in `lo..=hi`, the
    /// rule naming the range in an error.
    #[must_use]
    fn setting_ranges(&self) -> [SettingRange; 12] {
        [
            (
                "explosion radius",
                self.radius,
                0.05,
                0.75,
                "is outside 0.05..=0.75",
            ),
            (
                "explosion initial radius",
                self.initial_radius,
                0.05,
                1.0,
                "is outside 0.05..=1",
            ),
            (
                "explosion expansion time",
                self.expansion_time,
                0.01,
                10.0,
                "is outside 0.01..=10 s",
            ),
            (
                "explosion billow",
                self.billow,
                0.0,
                1.0,
                "is outside 0..=1",
            ),
            (
                "explosion turbulence",
                self.turbulence,
                0.0,
                0.5,
                "is outside 0..=0.5",
            ),
            ("explosion rise", self.rise, 0.0, 1.0, "is outside 0..=1"),
            (
                "explosion soot",
                self.soot,
                0.01,
                100.0,
                "is outside 0.01..=100",
            ),
            (
                "explosion core soot",
                self.core_soot,
                0.0,
                1.0,
                "is outside 0..=1",
            ),
            ("explosion shell", self.shell, 0.0, 1.0, "is outside 0..=1"),
            (
                "explosion core temperature",
                self.core_temperature,
                0.0,
                20_000.0,
                "is outside 0..=20000 K",
            ),
            (
                "explosion cooling time",
                self.cooling_time,
                0.01,
                100.0,
                "is outside 0.01..=100 s",
            ),
            (
                "explosion lobes",
                self.lobes as f32,
                0.0,
                12.0,
                "is outside 0..=12",
            ),
        ]
    }

    /// The fireball's radius at `time` (world units).
    fn radius_at(&self, time: f32) -> f32 {
        let grown = 1.0 - (1.0 - self.initial_radius) * (-time / self.expansion_time).exp();
        self.radius * grown
    }

    /// The lobes: the main ball first, then the seeded secondary ones.
    fn lobes(&self) -> Vec<Lobe> {
        let mut rng = SplitMix64(u64::from(self.seed) ^ 0x5EED_10BE);
        let mut lobes = vec![Lobe {
            offset: Vec3::ZERO,
            radius: 0.8,
        }];
        for _ in 0..self.lobes {
            let d = rng.next_unit();
            // Upward-leaning: hot gas rises, and a flat bottom reads as ground.
            let d = Vec3::new(d.x, 0.5 * d.y.abs() + 0.2 * d.y, d.z).normalize();
            let reach = 0.35 + 0.2 * rng.next_f32();
            lobes.push(Lobe {
                offset: d * reach,
                radius: 0.4 + 0.2 * rng.next_f32(),
            });
        }
        lobes
    }

    /// The explosion on a `res³` grid filling the cube `[-1, 1]³` at `time` seconds after
    /// ignition: [`explosion`] with these parameters.
    ///
    /// ```
    /// use lgh_volume::procedural::Explosion;
    ///
    /// let small = Explosion { radius: 0.3, ..Explosion::default() };
    /// let v = small.generate(32, 0.5)?;
    /// assert_eq!(v.density.dims, [32; 3]);
    /// // Nothing reaches the grid's faces.
    /// assert_eq!(v.density.get(0, 16, 16), 0.0);
    /// # Ok::<(), lgh_volume::RenderError>(())
    /// ```
    pub fn generate(&self, res: usize, time: f32) -> Result<Volume, RenderError> {
        check_grid(res, time)?;
        self.validate()?;
        let radius = self.radius_at(time);
        let grown = radius / self.radius;
        let centre = Vec3::new(0.0, -0.25 * self.radius + self.rise * radius, 0.0);
        let lobes = self.lobes();
        // No smoke beyond the farthest a lobe's surface can be pushed (the highest billow and
        // the smooth join lift `inside` by at most `lift`) plus the longest flow displacement:
        // a conservative bound, so skipping the voxels past it changes nothing.
        let lift = self.billow * (BILLOW_MAX - BILLOW_MEAN) + 0.25 * LOBE_BLEND;
        let reach = lobes
            .iter()
            .map(|l| l.offset.length() + l.radius * (1.0 + lift))
            .fold(0.0f32, f32::max)
            + self.turbulence * FLOW_MAX;
        let core_t = self.core_temperature / (1.0 + time / self.cooling_time).sqrt();
        let seed = self.seed.wrapping_mul(97);
        // The noise drifts slowly with time (seconds): the smoke keeps churning once grown.
        let drift = Vec3::new(0.11, -0.23, 0.07) * time;
        Ok(fill(res, |p| {
            // In fractions of the current radius: the billows grow with the fireball.
            let q = (p - centre) / radius;
            if q.length() > reach {
                return (0.0, 0.0);
            }
            let flow = curl_noise(q * 1.3 + drift, seed)
                + 0.5 * curl_noise(q * 2.7 + drift * 2.0, seed + 3);
            let warp = q + self.turbulence * flow.clamp_length_max(FLOW_MAX);
            // Inside-ness: 1 at a lobe's centre, 0 on its sphere, negative outside.
            let mut inside = f32::NEG_INFINITY;
            for l in &lobes {
                let f = 1.0 - (warp - l.offset).length() / l.radius;
                inside = if inside.is_finite() {
                    smooth_max(inside, f, LOBE_BLEND)
                } else {
                    f
                };
            }
            let bumps = billows(warp * 1.6, seed + 10, drift);
            let f = inside + self.billow * (bumps - BILLOW_MEAN);
            if f <= 0.0 {
                return (0.0, 0.0);
            }
            // Fire: deeper than the soot rim, with tongues of flame that reach out through it.
            let tongues = fractal_noise(warp * 1.7 + drift * 1.5, 3, seed + 20);
            // Where the large-scale breach noise is high, the fire reaches the surface.
            let breach = fractal_noise(warp * 0.9 - drift, 2, seed + 50);
            let depth = f + 0.25 * tongues + 0.7 * breach;
            // Where it burns (the soot thins there), and how hot: from 40% of the core's
            // temperature at the fire's edge up to all of it deep inside.
            let heat = smoothstep(self.shell, self.shell + 0.15, depth);
            let ramp = ((depth - self.shell) / 0.8).clamp(0.0, 1.0);
            let flicker = 0.8 + 0.4 * fractal_noise(warp * 5.0 - drift * 3.0, 3, seed + 30);
            // Zero at the smoke's surface, so that nothing jumps where the smoke ends.
            let edge = smoothstep(0.0, 0.04, f);
            let temperature =
                core_t * edge * heat * (0.4 + 0.6 * ramp) * flicker * (0.8 + 0.2 * grown);
            // Soot: dense in the rim, thinner where it burns, with its own fine grain.
            let grain = 0.75 + 0.5 * fractal_noise(warp * 6.0 + drift * 2.0, 2, seed + 40);
            // Clumps: thick soot over some of the fire, thin over the rest.
            let clumps =
                0.4 + 1.2 * smoothstep(-0.2, 0.3, fractal_noise(warp * 2.5 + drift, 2, seed + 60));
            let soot = self.soot * edge * grain * clumps * (1.0 - (1.0 - self.core_soot) * heat);
            (soot.max(0.0), temperature)
        }))
    }
}

/// The demo's explosion ([`Explosion::default`]) on a `res³` grid filling the cube `[-1, 1]³`,
/// `time` seconds after ignition (`0..=10`): a billowing fireball whose hot core (3200 K at
/// ignition, cooling) breaks through a dense shell of soot. Deterministic (the same arguments
/// give the same grids on any thread count) and continuous in `time` (a sequence of frames does
/// not pop). `res` must be in `32..=512`.
///
/// ```
/// use lgh_volume::procedural::explosion;
/// use lgh_volume::Medium;
///
/// let v = explosion(32, 0.5)?;
/// let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
/// let smoky = v.density.data.iter().filter(|&&d| d > 0.0).count();
/// // The fire is a part of the smoke.
/// assert!(v.emitting_voxels(&medium) > 0 && v.emitting_voxels(&medium) < smoky);
/// assert_eq!(v, explosion(32, 0.5)?);
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
pub fn explosion(res: usize, time: f32) -> Result<Volume, RenderError> {
    Explosion::default().generate(res, time)
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

    /// The demo's medium (`lgh demo`): κ_a, κ_s, k_e, T_min.
    fn demo_medium() -> crate::Medium {
        crate::Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap()
    }

    fn max_change(a: &DenseGrid, b: &DenseGrid) -> f32 {
        a.data
            .iter()
            .zip(&b.data)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f32::max)
    }

    #[test]
    fn explosion_is_deterministic_on_any_thread_count() {
        let a = explosion(48, 0.4).unwrap();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| explosion(48, 0.4).unwrap());
        let three = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap()
            .install(|| explosion(48, 0.4).unwrap());
        assert_eq!(a, one);
        assert_eq!(a, three);
        // Another seed is another explosion.
        let other = Explosion {
            seed: 8,
            ..Explosion::default()
        };
        assert_ne!(a, other.generate(48, 0.4).unwrap());
    }

    /// Continuity in time, the bound: over 10⁻⁴ s (1/417 of a 24-fps frame) no voxel's density
    /// changes by more than 0.3 (5% of the peak of about 6.7) and no temperature by more than
    /// 50 K (measured at 64³: 0.19 and 29 K at ignition, the fastest moment; 0.05 and 11 K at
    /// 0.5 s); and ten times closer in time, the changes are at most 0.15 of those (Lipschitz,
    /// measured 0.1): the fields move, they never jump.
    #[test]
    fn explosion_is_continuous_in_time() {
        for t in [0.0f32, 0.5, 2.0, 9.9] {
            let a = explosion(64, t).unwrap();
            let b = explosion(64, t + 1e-4).unwrap();
            let (d_rho, d_t) = (
                max_change(&a.density, &b.density),
                max_change(&a.temperature, &b.temperature),
            );
            assert!(d_rho <= 0.3, "t = {t}: density changed by {d_rho}");
            assert!(d_t <= 50.0, "t = {t}: temperature changed by {d_t} K");
            if t < 5.0 {
                let c = explosion(64, t + 1e-5).unwrap();
                let (c_rho, c_t) = (
                    max_change(&a.density, &c.density),
                    max_change(&a.temperature, &c.temperature),
                );
                assert!(c_rho <= 0.15 * d_rho, "t = {t}: {c_rho} against {d_rho}");
                assert!(c_t <= 0.15 * d_t, "t = {t}: {c_t} K against {d_t} K");
            }
        }
    }

    /// At the demo's 128³ and 0.5 s: 30 to 100 thousand lights (what the demo's render time
    /// follows), a fraction of the smoke; a hot core fading to cold soot at the rim; soot dense
    /// enough to shadow the fire (the demo's medium: optical depth from the core outwards).
    #[test]
    fn explosion_at_128_has_a_hot_core_in_dense_soot() {
        let v = explosion(128, 0.5).unwrap();
        let medium = demo_medium();
        let lights = v.emitting_voxels(&medium);
        let smoke = v.density.data.iter().filter(|&&d| d > 0.0).count();
        assert!((30_000..=100_000).contains(&lights), "{lights} lights");
        assert!(
            lights * 5 > smoke && lights * 3 < smoke * 2,
            "{lights} lights in {smoke} smoky voxels"
        );
        // The hot centre: the hot voxels' centroid.
        let hot: Vec<usize> = (0..v.temperature.data.len())
            .filter(|&i| v.voxel_emits(&medium, i))
            .collect();
        let centre_of = |i: usize| {
            let [nx, ny, _] = v.density.dims;
            v.density.centre(i % nx, (i / nx) % ny, i / (nx * ny))
        };
        let centre = hot.iter().map(|&i| centre_of(i)).sum::<Vec3>() / hot.len() as f32;
        // Mean temperature of the smoke by distance from the centre: hot inside, cold outside.
        let mean_t = |lo: f32, hi: f32| {
            let (sum, n) = (0..v.density.data.len())
                .filter(|&i| v.density.data[i] > 0.0)
                .filter(|&i| (lo..hi).contains(&centre_of(i).distance(centre)))
                .fold((0.0f64, 0usize), |(s, n), i| {
                    (s + f64::from(v.temperature.data[i]), n + 1)
                });
            sum / n.max(1) as f64
        };
        let (inner, outer) = (mean_t(0.0, 0.15), mean_t(0.45, 2.0));
        assert!(
            inner > 1400.0 && outer < 600.0,
            "{inner} K inside, {outer} K outside"
        );
        // Optical depth from the centre outwards along the 6 axes and 8 diagonals: the soot
        // hides the core (transmittance below e^-2 = 14%) in most directions.
        let mut depths: Vec<f32> = (0..27)
            .filter(|&d| d != 13)
            .map(|d| {
                Vec3::new(
                    (d % 3) as f32 - 1.0,
                    ((d / 3) % 3) as f32 - 1.0,
                    (d / 9) as f32 - 1.0,
                )
            })
            .filter(|d| d.length_squared() != 2.0)
            .map(|d| {
                let (d, step) = (d.normalize(), 0.5 * v.density.voxel_size);
                (0..800)
                    .map(|k| {
                        medium.extinction(v.density.sample(centre + d * (k as f32 + 0.5) * step))
                            * step
                    })
                    .sum()
            })
            .collect();
        depths.sort_by(f32::total_cmp);
        assert_eq!(depths.len(), 14);
        assert!(depths[7] > 2.0, "optical depths {depths:?}");
    }

    #[test]
    fn explosion_parameters_are_validated() {
        assert!(Explosion::default().validate().is_ok());
        let d = Explosion::default;
        let bad = [
            Explosion {
                radius: f32::NAN,
                ..d()
            },
            Explosion { radius: 0.9, ..d() },
            Explosion {
                initial_radius: 0.0,
                ..d()
            },
            Explosion {
                expansion_time: f32::INFINITY,
                ..d()
            },
            Explosion { lobes: 13, ..d() },
            Explosion {
                billow: -0.1,
                ..d()
            },
            Explosion {
                turbulence: f32::NAN,
                ..d()
            },
            Explosion { rise: 2.0, ..d() },
            Explosion { soot: 0.0, ..d() },
            Explosion {
                core_soot: f32::NEG_INFINITY,
                ..d()
            },
            Explosion { shell: 1.5, ..d() },
            Explosion {
                core_temperature: -1.0,
                ..d()
            },
            Explosion {
                cooling_time: 0.0,
                ..d()
            },
        ];
        for e in &bad {
            assert!(
                matches!(e.validate(), Err(RenderError::InvalidSetting { .. })),
                "{e:?}"
            );
            assert!(e.generate(32, 0.5).is_err());
        }
        // The grid and time are checked as `procedural` checks them.
        assert!(matches!(
            explosion(16, 0.5),
            Err(RenderError::InvalidCount {
                name: "resolution",
                ..
            })
        ));
        for t in [f32::NAN, -0.1, 10.5] {
            assert!(matches!(
                explosion(32, t),
                Err(RenderError::InvalidSetting { name: "time", .. })
            ));
        }
        // Nothing reaches the grid's faces, even fully grown.
        let late = explosion(64, 10.0).unwrap();
        let [n, _, _] = late.density.dims;
        for a in 0..n {
            for b in 0..n {
                for (i, j, k) in [
                    (0, a, b),
                    (n - 1, a, b),
                    (a, 0, b),
                    (a, n - 1, b),
                    (a, b, 0),
                    (a, b, n - 1),
                ] {
                    assert_eq!(late.density.get(i, j, k), 0.0);
                }
            }
        }
    }
}
