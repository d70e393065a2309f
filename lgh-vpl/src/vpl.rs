//! Virtual point lights (Keller's instant radiosity; the paper's Sec. 6.4 and Fig. 13 light a
//! scene with 365K of them through the hierarchy).
//!
//! Light paths leave the primary lights ([`crate::primary`]), each light chosen in proportion to
//! its power; every diffuse surface a path meets deposits a VPL there — its position, the
//! surface normal on the path's side (the shading normal, and the face's, below which it emits
//! nothing), the flux `Φ` arriving with the path and the surface's
//! diffuse albedo `ρ` — and the path goes on in a cosine-distributed direction carrying
//! `Φ ρ`, up to a bounce limit. A VPL reflects what it received: it emits the radiant intensity
//! `I(ω) = Φ ρ / π · max(0, n·ω)` (a Lambertian reflector of flux `Φ ρ`), a cosine lobe about
//! its normal.
//!
//! Everything is deterministic: path `i` draws from its own seeded sequence, so the VPLs do not
//! depend on the thread count, and a frame traced again gives the same lights bit for bit.

use lgh_core::glam::Vec3;
use lgh_core::luminance;
use lgh_core::random::SplitMix64;
use rayon::prelude::*;

use crate::brdf::diffuse_albedo;
use crate::primary::PrimaryLight;
use crate::scene::Scene;
use crate::specular::{branches, Branch, Specular};

/// One virtual point light. Aligned to a cache line (its 64 bytes): a VPL the shading reads
/// at random, or hints to the cache, is one line.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(align(64))]
pub struct Vpl {
    /// Where the path met the surface.
    pub position: Vec3,
    /// Unit surface normal on the side the path arrived from: the shading normal (a smooth
    /// mesh's interpolated normal), about which the VPL's cosine lobe lies.
    pub normal: Vec3,
    /// Unit geometric (face) normal, on the same side: the VPL emits nothing below the face,
    /// whatever its shading normal leans to (`ShadingPoint::geometric`).
    pub geometric: Vec3,
    /// Flux `Φ` arriving with the path (W).
    pub power: Vec3,
    /// Diffuse albedo `ρ` of the surface.
    pub albedo: Vec3,
    /// How many surfaces the path had met, this one included (1: one-bounce light).
    pub bounce: u32,
}

impl Vpl {
    /// Radiant intensity towards the unit direction `w` (away from the VPL):
    /// `Φ ρ / π · max(0, n·w)` in front of the face (`g·w > 0`), 0 behind it, W/sr.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::vpl::Vpl;
    ///
    /// let v = Vpl { position: Vec3::ZERO, normal: Vec3::Y, geometric: Vec3::Y,
    ///               power: Vec3::splat(std::f32::consts::PI), albedo: Vec3::splat(0.5), bounce: 1 };
    /// assert_eq!(v.intensity(Vec3::Y), Vec3::splat(0.5));
    /// assert_eq!(v.intensity(-Vec3::Y), Vec3::ZERO); // nothing behind the surface
    /// // A shading normal leaning 45° from the face: nothing below the face all the same.
    /// let leaning = Vpl { normal: Vec3::new(0.0, 1.0, 1.0).normalize(), ..v };
    /// assert_eq!(leaning.intensity(Vec3::new(0.0, -0.1, 1.0).normalize()), Vec3::ZERO);
    /// ```
    #[must_use]
    pub fn intensity(&self, w: Vec3) -> Vec3 {
        self.power * self.albedo * (self.lobe(w) * 0.5 / std::f32::consts::PI)
    }

    /// The axis its lobe (its shading normal) points along most, with the sign: 0 to 5 for
    /// +x, −x, +y, −y, +z, −z. The buckets of the orientation-aware aggregation and the strata
    /// of the coarse lights' representatives
    /// ([`Representatives::build_stratified`](crate::representatives::Representatives::build_stratified)).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::vpl::Vpl;
    ///
    /// let v = |n: Vec3| Vpl { position: Vec3::ZERO, normal: n.normalize(), geometric: Vec3::Y,
    ///                         power: Vec3::ONE, albedo: Vec3::ONE, bounce: 1 };
    /// assert_eq!(v(Vec3::new(0.2, 0.9, 0.1)).orientation(), 2); // +y: a floor
    /// assert_eq!(v(Vec3::new(-0.9, 0.3, 0.1)).orientation(), 1); // −x: a wall
    /// ```
    #[must_use]
    pub fn orientation(&self) -> u8 {
        let (n, a) = (self.normal, self.normal.abs());
        let axis = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        2 * axis as u8 + u8::from(n[axis] < 0.0)
    }

    /// The VPL's lobe relative to an isotropic emitter of the same flux towards unit `w`:
    /// `2 max(0, n·w)` in front of the face, 0 behind it.
    #[must_use]
    pub fn lobe(&self, w: Vec3) -> f32 {
        if self.geometric.dot(w) <= 0.0 {
            0.0
        } else {
            2.0 * self.normal.dot(w).max(0.0)
        }
    }
}

/// How many VPLs, how deep, from which sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VplSettings {
    /// At least this many VPLs (whole paths are kept, so a few more may come).
    pub count: usize,
    /// Surfaces a path may meet; each deposits a VPL (1: one-bounce indirect light only).
    pub max_bounces: u32,
    /// Seed of the paths' sequences.
    pub seed: u64,
}

impl Default for VplSettings {
    /// 100,000 VPLs of up to 3 bounces.
    fn default() -> Self {
        VplSettings {
            count: 100_000,
            max_bounces: 3,
            seed: 1,
        }
    }
}

/// Why no VPLs could be traced.
#[derive(Clone, Debug, PartialEq)]
pub enum VplError {
    /// The scene has no emissive face and no light was given, or every light is black.
    NoLights,
    /// `count` or `max_bounces` is zero, or `count` is above [`MAX_VPLS`].
    Settings,
    /// `paths` light paths met no surface with a diffuse albedo (every light points away from
    /// the scene, or every surface is black).
    NothingLit {
        /// Paths traced.
        paths: u64,
    },
}

impl std::fmt::Display for VplError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VplError::NoLights => write!(
                f,
                "the scene has no emissive face (MTL Ke) and no primary light was given"
            ),
            VplError::Settings => write!(
                f,
                "the VPL count must be 1 to {MAX_VPLS} and the bounce limit at least 1"
            ),
            VplError::NothingLit { paths } => write!(
                f,
                "{paths} light paths met no diffuse surface: do the lights face the scene?"
            ),
        }
    }
}

impl std::error::Error for VplError {}

/// The most VPLs one call traces: 2²⁶ (64 bytes each, 4 GiB).
pub const MAX_VPLS: usize = 1 << 26;

/// The VPLs of a scene and how they were made.
#[derive(Clone, Debug, PartialEq)]
pub struct Vpls {
    /// The lights, in path order.
    pub vpls: Vec<Vpl>,
    /// Light paths traced (each carries `1/paths` of the emitted power).
    pub paths: u64,
    /// Total power the primary lights emit (W).
    pub emitted: Vec3,
}

impl Vpls {
    /// Puts the VPLs in Morton order of their positions (21 bits an axis over their bounding
    /// box; equal codes keep their path order), so that VPLs near each other in space are
    /// near each other in memory: the representatives of a coarse light
    /// ([`crate::representatives`]) and a point's level-0 lights then share cache lines
    /// instead of each missing it. The set of lights is unchanged, so is every image up to
    /// the order of its sums; the order depends on nothing but the VPLs.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::vpl::{Vpl, Vpls};
    ///
    /// let at = |x: f32| Vpl { position: Vec3::new(x, 0.0, 0.0), normal: Vec3::Y,
    ///     geometric: Vec3::Y, power: Vec3::ONE, albedo: Vec3::ONE, bounce: 1 };
    /// let mut traced = Vpls { vpls: vec![at(3.0), at(0.0), at(2.0), at(1.0)], paths: 2,
    ///     emitted: Vec3::ONE };
    /// traced.sort_spatially();
    /// let xs: Vec<f32> = traced.vpls.iter().map(|v| v.position.x).collect();
    /// assert_eq!(xs, [0.0, 1.0, 2.0, 3.0]);
    /// ```
    pub fn sort_spatially(&mut self) {
        let (lo, hi) = self.vpls.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(v.position), hi.max(v.position)),
        );
        let max = lgh_core::morton::MAX_COORD as f32;
        let scale = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE)).recip() * max;
        let code = |v: &Vpl| {
            let c = ((v.position - lo) * scale).clamp(Vec3::ZERO, Vec3::splat(max));
            lgh_core::morton::encode([c.x as u32, c.y as u32, c.z as u32])
        };
        self.vpls.sort_by_cached_key(code);
    }
}

/// Traces light paths from `lights` through `scene` until at least `settings.count` VPLs are
/// deposited (module docs). Paths are traced in parallel, 4096 at a time, and kept in order.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::Material;
/// use lgh_vpl::primary::PrimaryLight;
/// use lgh_vpl::vpl::{trace, VplSettings};
/// use lgh_vpl::{Mesh, Scene};
///
/// // A closed grey box with a lamp inside: every path meets a wall.
/// let grey = Material::Lambert { albedo: Vec3::splat(0.5) };
/// let scene = Scene::new(Mesh::cuboid(Vec3::splat(-1.0), Vec3::ONE, grey)?);
/// let lamp = PrimaryLight::Point { position: Vec3::ZERO, intensity: Vec3::ONE };
/// let settings = VplSettings { count: 1000, max_bounces: 2, seed: 7 };
/// let traced = trace(&scene, &[lamp], &settings)?;
/// assert!(traced.vpls.len() >= 1000);
/// // The first bounce receives all the lamp's power, 4π W; the second, half of it.
/// let received = |b| traced.vpls.iter().filter(|v| v.bounce == b).map(|v| v.power.x).sum::<f32>();
/// assert!((received(1) / (4.0 * std::f32::consts::PI) - 1.0).abs() < 1e-3);
/// assert!((received(2) / received(1) - 0.5).abs() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn trace(
    scene: &Scene,
    lights: &[PrimaryLight],
    settings: &VplSettings,
) -> Result<Vpls, VplError> {
    if settings.count == 0 || settings.count > MAX_VPLS || settings.max_bounces == 0 {
        return Err(VplError::Settings);
    }
    let mesh = scene.mesh();
    let (lo, hi) = mesh.bounds();
    let (centre, radius) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    let powers: Vec<Vec3> = lights.iter().map(|l| l.power(mesh, radius)).collect();
    let weights: Vec<f32> = powers.iter().map(|&p| luminance(p)).collect();
    let total: f32 = weights.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err(VplError::NoLights);
    }
    let cdf: Vec<f32> = weights
        .iter()
        .scan(0.0, |acc, w| {
            *acc += w / total;
            Some(*acc)
        })
        .collect();
    let eps = scene.ray_offset();
    let emitter = Emitter {
        scene,
        lights,
        powers: &powers,
        weights: &weights,
        total,
        cdf: &cdf,
        centre,
        radius,
        eps,
        max_bounces: settings.max_bounces,
    };
    const BATCH: u64 = 4096;
    // Enough paths that a scene lit at all deposits something; then it is the lights' fault.
    let max_paths = 64 * settings.count as u64 + 1_000_000;
    let mut vpls: Vec<Vpl> = Vec::new();
    let mut paths = 0u64;
    while vpls.len() < settings.count && paths < max_paths {
        let batch: Vec<Vec<Vpl>> = (paths..paths + BATCH)
            .into_par_iter()
            .map(|i| {
                emitter.path(SplitMix64(SplitMix64::mix(
                    settings.seed ^ SplitMix64::mix(i),
                )))
            })
            .collect();
        for path in batch {
            paths += 1;
            vpls.extend(path);
            if vpls.len() >= settings.count {
                break;
            }
        }
    }
    if vpls.is_empty() {
        return Err(VplError::NothingLit { paths });
    }
    let share = 1.0 / paths as f32;
    for v in &mut vpls {
        v.power *= share;
    }
    Ok(Vpls {
        vpls,
        paths,
        emitted: powers.iter().sum(),
    })
}

/// What a path needs to leave a light.
struct Emitter<'a> {
    scene: &'a Scene,
    lights: &'a [PrimaryLight],
    powers: &'a [Vec3],
    weights: &'a [f32],
    total: f32,
    cdf: &'a [f32],
    centre: Vec3,
    radius: f32,
    eps: f32,
    max_bounces: u32,
}

impl Emitter<'_> {
    /// One light path: the VPLs it deposits, with the power it carries not yet divided by the
    /// number of paths.
    fn path(&self, mut rng: SplitMix64) -> Vec<Vpl> {
        let u = rng.next_f32();
        let j = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.lights.len() - 1);
        // The light's power over the probability of choosing it.
        let mut carried = self.powers[j] * (self.total / self.weights[j]);
        let (mut origin, mut dir) = self.emit(&self.lights[j], &mut rng);
        let mut out = Vec::new();
        let (mut bounce, mut specular) = (0u32, 0u32);
        while bounce < self.max_bounces {
            let Some((point, t)) = self.scene.trace(origin, dir) else {
                break;
            };
            let (branches, kind) = branches(self.scene, t, &point, dir, false);
            let albedo = match kind.is_pure() {
                true => Vec3::ZERO,
                false => diffuse_albedo(&point.material),
            };
            // The shading normal for the VPL's lobe and the bounce's cosine, the face's for
            // the hemisphere they leave into (`ShadingPoint::geometric`).
            let normal = point.normal.unwrap_or(-dir);
            let face = point.geometric_normal().unwrap_or(normal);
            if albedo != Vec3::ZERO {
                bounce += 1;
                out.push(Vpl {
                    position: point.position,
                    normal,
                    geometric: face,
                    power: carried,
                    albedo,
                    bounce,
                });
            }
            // The ways on: the specular branches while specular depth is left, and a diffuse
            // bounce while VPLs are left to deposit; one is chosen in proportion to its share
            // (a random choice only where there are several: diffuse paths draw as before).
            // At most three (two specular branches and the diffuse bounce): on the stack.
            let mut all = [(Branch::default(), 0.0f32); 3];
            let mut n = 0;
            if specular < self.scene.specular_depth() {
                let share = |b: &Branch| match kind {
                    Specular::Mirror { .. } => luminance(b.weight),
                    _ => b.share,
                };
                for b in branches.into_iter().flatten() {
                    all[n] = (b, share(&b));
                    n += 1;
                }
            }
            if albedo != Vec3::ZERO && bounce < self.max_bounces {
                let diffuse = Branch {
                    dir: Vec3::ZERO,
                    weight: albedo,
                    radiance_scale: 1.0,
                    side: face,
                    share: 1.0,
                };
                all[n] = (diffuse, luminance(albedo));
                n += 1;
            }
            let ways = &all[..n];
            let total: f32 = ways.iter().map(|w| w.1).sum();
            let chosen = match ways.len() {
                0 => break,
                1 => 0,
                _ => {
                    let u = rng.next_f32() * total;
                    let mut acc = 0.0;
                    ways.iter()
                        .position(|w| {
                            acc += w.1;
                            u < acc
                        })
                        .unwrap_or(ways.len() - 1)
                }
            };
            let (way, importance) = ways[chosen];
            let probability = if ways.len() == 1 {
                1.0
            } else {
                importance / total
            };
            carried *= way.weight / probability;
            origin = point.position + way.side * self.eps;
            if way.dir == Vec3::ZERO {
                dir = cosine(normal, &mut rng);
                if dir.dot(face) <= 0.0 {
                    // Into the surface: a leaning shading normal's cosine reaches below the
                    // face, where no light goes; the path ends there.
                    break;
                }
            } else {
                specular += 1;
                dir = way.dir;
            }
        }
        out
    }

    /// Where and in which direction a path leaves `light`.
    fn emit(&self, light: &PrimaryLight, rng: &mut SplitMix64) -> (Vec3, Vec3) {
        match *light {
            PrimaryLight::Point { position, .. } => (position, rng.next_unit()),
            PrimaryLight::Spot {
                position,
                direction,
                cos_half_angle,
                ..
            } => {
                // Uniform in the cone's solid angle.
                let cos = 1.0 - rng.next_f32() * (1.0 - cos_half_angle);
                (position, around(direction, cos, rng.next_f32()))
            }
            PrimaryLight::Sun { direction, .. } => {
                // Uniform over the scene's disc, from outside its bounding sphere.
                let (a, b) = direction.any_orthonormal_pair();
                let r = self.radius * rng.next_f32().sqrt();
                let phi = std::f32::consts::TAU * rng.next_f32();
                let on_disc = self.centre + r * (phi.cos() * a + phi.sin() * b);
                (on_disc - direction * (2.0 * self.radius), direction)
            }
            PrimaryLight::Area { triangle, .. } => {
                let mesh = self.scene.mesh();
                let p = mesh.sample_point(triangle, rng.next_f32(), rng.next_f32());
                let n = mesh.face_normal(triangle);
                (p + n * self.eps, cosine(n, rng))
            }
        }
    }
}

/// A unit direction at angle `acos(cos)` from the unit `axis`, at azimuth `2π t`.
fn around(axis: Vec3, cos: f32, t: f32) -> Vec3 {
    let (a, b) = axis.any_orthonormal_pair();
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * t;
    (axis * cos + a * (sin * phi.cos()) + b * (sin * phi.sin())).normalize()
}

/// A cosine-distributed unit direction about the unit `normal`.
fn cosine(normal: Vec3, rng: &mut SplitMix64) -> Vec3 {
    let u = rng.next_f32();
    around(normal, (1.0 - u).sqrt(), rng.next_f32())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use lgh_core::Material;
    use std::f32::consts::PI;

    const GREY: Material = Material::Lambert {
        albedo: Vec3::splat(0.5),
    };

    /// The square `|x|, |z| ≤ a` of the plane y = 0.
    fn floor(a: f32) -> Scene {
        let c = |x: f32, z: f32| Vec3::new(x, 0.0, z);
        Scene::new(Mesh::quad([c(-a, a), c(a, a), c(a, -a), c(-a, -a)], GREY).unwrap())
    }

    fn received(t: &Vpls, bounce: u32) -> f64 {
        t.vpls
            .iter()
            .filter(|v| v.bounce == bounce)
            .map(|v| f64::from(v.power.x))
            .sum()
    }

    /// A point light at height h over a square of half-side a sends it the fraction Ω/4π of its
    /// power, Ω = 4 asin(a² / (a² + h²)): a binomial estimate, checked within 4σ.
    #[test]
    fn an_open_floor_receives_its_solid_angle() {
        let (a, h) = (1.0f32, 1.0f32);
        let lamp = PrimaryLight::Point {
            position: Vec3::new(0.0, h, 0.0),
            intensity: Vec3::ONE,
        };
        let settings = VplSettings {
            count: 20_000,
            max_bounces: 1,
            seed: 3,
        };
        let t = trace(&floor(a), &[lamp], &settings).unwrap();
        let p = 4.0 * (a * a / (a * a + h * h)).asin() / (4.0 * PI);
        let got = received(&t, 1) / (4.0 * f64::from(PI));
        let sigma = (f64::from(p) * (1.0 - f64::from(p)) / t.paths as f64).sqrt();
        assert!(
            (got - f64::from(p)).abs() < 4.0 * sigma,
            "{got} against {p} ± {sigma}"
        );
    }

    /// A spot over a floor wider than its cone: the floor receives all of `2π (1 − cos θ) I`.
    #[test]
    fn a_spot_gives_all_its_power_to_what_its_cone_covers() {
        let spot: PrimaryLight = "spot:0,1,0,0,-1,0,30,2,2,2".parse().unwrap();
        let settings = VplSettings {
            count: 2000,
            max_bounces: 1,
            seed: 5,
        };
        let t = trace(&floor(10.0), &[spot], &settings).unwrap();
        let want = 2.0 * PI * (1.0 - 30f32.to_radians().cos()) * 2.0;
        assert!((received(&t, 1) as f32 / want - 1.0).abs() < 1e-4);
    }

    /// The sun straight down on a square floor: the floor receives irradiance × its area
    /// (the paths cross the scene's disc, of which the floor covers 2/π).
    #[test]
    fn the_sun_gives_a_floor_its_irradiance_times_its_area() {
        let sun: PrimaryLight = "sun:0,-1,0,3,3,3".parse().unwrap();
        let settings = VplSettings {
            count: 20_000,
            max_bounces: 1,
            seed: 9,
        };
        let t = trace(&floor(1.0), &[sun], &settings).unwrap();
        let p = 2.0 / f64::from(PI);
        let disc = f64::from(PI) * 2.0 * 3.0; // π R² E, R² = 2
        let sigma = (p * (1.0 - p) / t.paths as f64).sqrt();
        let got = received(&t, 1) / disc;
        assert!((got - p).abs() < 4.0 * sigma, "{got} against {p} ± {sigma}");
    }

    #[test]
    fn the_vpls_do_not_depend_on_the_thread_count() {
        let lamp = PrimaryLight::Point {
            position: Vec3::new(0.2, 0.5, -0.1),
            intensity: Vec3::new(1.0, 2.0, 3.0),
        };
        let scene = Scene::new(Mesh::cuboid(Vec3::splat(-1.0), Vec3::ONE, GREY).unwrap());
        let settings = VplSettings {
            count: 10_000,
            max_bounces: 3,
            seed: 11,
        };
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| trace(&scene, &[lamp], &settings).unwrap())
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn what_cannot_be_traced_says_why() {
        let scene = floor(1.0);
        let down = VplSettings::default();
        assert_eq!(trace(&scene, &[], &down), Err(VplError::NoLights));
        let lamp = PrimaryLight::Point {
            position: Vec3::Y,
            intensity: Vec3::ONE,
        };
        let zero = VplSettings { count: 0, ..down };
        assert_eq!(trace(&scene, &[lamp], &zero), Err(VplError::Settings));
        // A spot pointing up, away from the floor.
        let away: PrimaryLight = "spot:0,1,0,0,1,0,10,1,1,1".parse().unwrap();
        let few = VplSettings { count: 10, ..down };
        assert!(matches!(
            trace(&scene, &[away], &few),
            Err(VplError::NothingLit { .. })
        ));
    }

    /// The Cornell box's ceiling lamp (MTL `Ke 17 12 4`) becomes area lights, and its VPLs
    /// receive at most what it emits (the box is open at the front).
    #[test]
    fn the_cornell_box_lamp_lights_the_box() {
        let Some(dir) = lgh_tests_data() else { return };
        let mesh = Mesh::load_obj(&dir.join("CornellBox-Original.obj")).unwrap();
        let lamps = crate::primary::area_lights(&mesh);
        assert_eq!(lamps.len(), 2, "the lamp is one quad");
        let scene = Scene::new(mesh);
        let settings = VplSettings {
            count: 5000,
            max_bounces: 1,
            seed: 2,
        };
        let t = trace(&scene, &lamps, &settings).unwrap();
        let (got, emitted) = (received(&t, 1), f64::from(t.emitted.x));
        println!("first bounce receives {got:.3} of {emitted:.3} W (red)");
        assert!(
            got > 0.5 * emitted && got <= emitted * 1.0001,
            "{got} of {emitted}"
        );
    }

    /// The Cornell box's folder of the shared data, or `None` after saying SKIPPED.
    fn lgh_tests_data() -> Option<std::path::PathBuf> {
        lgh_tests::data("meshes/cornellbox_original")
    }
}
