//! The camera and the volume ray marcher (DESIGN.md "Rendering").
//!
//! A camera ray marches the smoke from where it enters the grid's box; each step of length `dt`
//! adds `T · [j + σ_s/(4π) Σ_lights V·g·B·I] · (1 − e^{−σ_t dt}) / σ_t` — the exact integral over
//! a step whose medium is constant (evaluated at the step's midpoint) — and multiplies the
//! transmittance `T` by `e^{−σ_t dt}`, until `T` is negligible. The sum over lights goes through
//! any [`ManyLights`] backend; the visibility `V` is a ray-marched transmittance to each light or 1.

use lgh_core::glam::Vec3;
use lgh_core::{falloff, LightSample, ManyLights, ShadingPoint};
use lgh_image::Image;
use rayon::prelude::*;

use crate::explosion::{Medium, Volume};
use crate::shadow::ShadowGrid;

/// The one image-size rule of every renderer (it lives in lgh-image).
pub use lgh_image::{check_image_size, MAX_IMAGE_SIDE};

/// The pinhole camera, shared with the surface renderer: lgh-image's
/// [`Pinhole`](lgh_image::camera::Pinhole). [`Framing`] adds what the volume renderer needs on
/// top: string errors, the automatic framing of a box, and the check of pixel lists.
pub use lgh_image::camera::Pinhole as Camera;

/// The volume renderer's conveniences on [`Camera`] (implemented for it; bring the trait into
/// scope to call `Camera::frame(...)`, `Camera::look_at(...)` or `camera.check_pixels(...)`).
pub trait Framing: Sized {
    /// A camera at `eye` looking at `target`, `up` roughly up, vertical field of view in degrees
    /// and a `width × height` image: [`Camera::new`], its
    /// [`CameraError`](lgh_image::camera::CameraError) as a message.
    fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y: f32,
        width: usize,
        height: usize,
    ) -> Result<Self, String>;

    /// Frames the box `lo..hi` in a +Y-up world: [`frame_up`](Self::frame_up) with [`Up::Y`].
    fn frame(lo: Vec3, hi: Vec3, width: usize, height: usize) -> Result<Self, String>;

    /// Frames the box `lo..hi`: looks at its centre from the front, a little to the right and
    /// above, from the distance where the box's bounding sphere shrunk to 80% fills the narrower
    /// field of view (40° vertically). Smoke rarely fills its box to the corners, and the full
    /// sphere leaves it small in the frame.
    fn frame_up(lo: Vec3, hi: Vec3, width: usize, height: usize, up: Up) -> Result<Self, String>;

    /// Checks that every `(x, y)` of `pixels` is inside the image.
    fn check_pixels(&self, pixels: &[[usize; 2]]) -> Result<(), String>;
}

impl Framing for Camera {
    fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y: f32,
        width: usize,
        height: usize,
    ) -> Result<Self, String> {
        Camera::new(eye, target, up, fov_y, width, height).map_err(|e| e.to_string())
    }

    fn frame(lo: Vec3, hi: Vec3, width: usize, height: usize) -> Result<Self, String> {
        Camera::frame_up(lo, hi, width, height, Up::Y)
    }

    fn frame_up(lo: Vec3, hi: Vec3, width: usize, height: usize, up: Up) -> Result<Self, String> {
        let centre = 0.5 * (lo + hi);
        let radius = 0.8 * 0.5 * (hi - lo).length();
        let fov_y = 40.0f32;
        let aspect = width as f32 / height.max(1) as f32;
        let half = (0.5 * fov_y).to_radians().tan() * aspect.min(1.0);
        let distance = radius / half.atan().sin();
        let (right, upv, front) = up.basis();
        let dir = (0.35 * right + 0.25 * upv + front).normalize();
        Camera::look_at(centre + dir * distance, centre, upv, fov_y, width, height)
    }

    fn check_pixels(&self, pixels: &[[usize; 2]]) -> Result<(), String> {
        match pixels
            .iter()
            .find(|p| p[0] >= self.width() || p[1] >= self.height())
        {
            Some(p) => Err(format!(
                "pixel {p:?} is outside the {}x{} image",
                self.width(),
                self.height()
            )),
            None => Ok(()),
        }
    }
}

/// The world's up axis, for automatic framing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Up {
    /// +Y up, the camera in front on +Z (most engines, Houdini).
    Y,
    /// +Z up, the camera in front on −Y (Blender).
    Z,
}

impl Up {
    /// The up vector.
    pub fn vector(self) -> Vec3 {
        self.basis().1
    }

    /// (right, up, front): the axes as seen by a camera in front of the scene.
    fn basis(self) -> (Vec3, Vec3, Vec3) {
        match self {
            Up::Y => (Vec3::X, Vec3::Y, Vec3::Z),
            Up::Z => (Vec3::X, Vec3::Z, -Vec3::Y),
        }
    }
}

/// How lights are shadowed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shadows {
    /// No shadows (V = 1).
    None,
    /// Transmittance ray-marched from the shading point to each light (exact shadows).
    RayMarch,
}

/// Ray-marching parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchSettings {
    /// Step along camera rays, in voxels.
    pub step_voxels: f32,
    /// Step along shadow rays, in voxels.
    pub shadow_step_voxels: f32,
    /// Camera rays stop when their transmittance falls below this; a light whose shadow-ray
    /// transmittance falls below it counts as hidden (each drops at most this fraction of what
    /// it cuts off).
    pub min_transmittance: f32,
    /// Shadowing of the lights.
    pub shadows: Shadows,
}

impl MarchSettings {
    /// Checks the settings: steps of 0.01 to 64 voxels, a cut-off in [0, 1).
    pub fn check(&self) -> Result<(), String> {
        for (name, v) in [
            ("step", self.step_voxels),
            ("shadow step", self.shadow_step_voxels),
        ] {
            if !(0.01..=64.0).contains(&v) {
                return Err(format!(
                    "march settings: {name} {v} must be 0.01 to 64 voxels"
                ));
            }
        }
        if !(0.0..1.0).contains(&self.min_transmittance) {
            return Err(format!(
                "march settings: minimum transmittance {} must be in [0, 1)",
                self.min_transmittance
            ));
        }
        Ok(())
    }
}

impl Default for MarchSettings {
    fn default() -> Self {
        MarchSettings {
            step_voxels: 1.0,
            shadow_step_voxels: 1.0,
            min_transmittance: 1e-3,
            shadows: Shadows::RayMarch,
        }
    }
}

/// What a render did: the work counts that explain its time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Steps where the lights were evaluated (scattering medium, lights given).
    pub shading_points: u64,
    /// Lights (or clusters) evaluated, summed over shading points.
    pub lights_evaluated: u64,
    /// Density samples taken along shadow rays.
    pub shadow_samples: u64,
}

impl RenderStats {
    /// Adds another count.
    pub fn add(&mut self, o: &RenderStats) {
        self.shading_points += o.shading_points;
        self.lights_evaluated += o.lights_evaluated;
        self.shadow_samples += o.shadow_samples;
    }

    /// Mean lights evaluated per shading point (0 when none).
    pub fn lights_per_point(&self) -> f64 {
        if self.shading_points == 0 {
            0.0
        } else {
            self.lights_evaluated as f64 / self.shading_points as f64
        }
    }
}

/// A frame ready to march: the volume, its medium and the settings, with the shadow grid the
/// settings ask for built once.
pub struct Marcher<'a> {
    /// The volume.
    pub volume: &'a Volume,
    /// Its medium.
    pub medium: &'a Medium,
    /// The march settings.
    pub settings: MarchSettings,
    /// The density laid out for shadow rays, when they are ray-marched.
    shadows: Option<ShadowGrid>,
}

impl<'a> Marcher<'a> {
    /// Prepares `volume` in `medium` for marching with `settings` (checked).
    pub fn new(
        volume: &'a Volume,
        medium: &'a Medium,
        settings: &MarchSettings,
    ) -> Result<Self, String> {
        settings.check()?;
        let shadows = match settings.shadows {
            Shadows::None => None,
            Shadows::RayMarch => Some(ShadowGrid::new(
                volume,
                medium,
                settings.shadow_step_voxels,
                settings.min_transmittance,
            )),
        };
        Ok(Marcher {
            volume,
            medium,
            settings: *settings,
            shadows,
        })
    }

    /// [`new`](Self::new), without the shadow grid when there are no lights to shadow.
    fn for_lights(
        volume: &'a Volume,
        medium: &'a Medium,
        settings: &MarchSettings,
        lights: bool,
    ) -> Result<Self, String> {
        let shadows = if lights {
            settings.shadows
        } else {
            Shadows::None
        };
        Marcher::new(
            volume,
            medium,
            &MarchSettings {
                shadows,
                ..*settings
            },
        )
    }

    /// Radiance arriving at `origin` along `-dir` (the ray `origin + t·dir`), with single
    /// scattering from `lights` (if given; `h0` clamps their fall-off).
    pub fn march<B: ManyLights>(
        &self,
        lights: Option<(&B, f32)>,
        origin: Vec3,
        dir: Vec3,
        stats: &mut RenderStats,
    ) -> Vec3 {
        self.march_with(lights, origin, dir, stats, &mut Scratch::default())
    }

    /// [`march`](Self::march) with buffers that the caller reuses from ray to ray.
    fn march_with<B: ManyLights>(
        &self,
        lights: Option<(&B, f32)>,
        origin: Vec3,
        dir: Vec3,
        stats: &mut RenderStats,
        scratch: &mut Scratch,
    ) -> Vec3 {
        let (volume, medium, settings) = (self.volume, self.medium, &self.settings);
        let h = volume.density.voxel_size;
        let (lo, hi) = volume.density.bounds();
        let Some((t0, t1)) = crate::grid::slab(origin, dir, lo, hi) else {
            return Vec3::ZERO;
        };
        let n = ((t1 - t0) / (settings.step_voxels * h)).ceil().max(1.0) as usize;
        let dt = (t1 - t0) / n as f32;
        let mut radiance = Vec3::ZERO;
        let mut trans = 1.0f32;
        for i in 0..n {
            let x = origin + dir * (t0 + (i as f32 + 0.5) * dt);
            let rho = volume.density.sample(x);
            let sigma_t = medium.extinction(rho);
            let mut source = volume.emission(medium, x);
            let sigma_s = medium.scattering * rho;
            if let (Some((backend, h0)), true) = (lights, sigma_s > 0.0) {
                if let Some(sum) = self.in_scattered(backend, h0, x, scratch, stats) {
                    source += sum * (sigma_s / (4.0 * std::f32::consts::PI));
                }
            }
            // Exact integral over a step of constant medium: ∫ e^{−σ s} ds = (1 − e^{−σ dt}) / σ.
            let step_t = (-sigma_t * dt).exp();
            let weight = if sigma_t > 0.0 {
                (1.0 - step_t) / sigma_t
            } else {
                dt
            };
            radiance += trans * weight * source;
            trans *= step_t;
            if trans < settings.min_transmittance {
                break;
            }
        }
        radiance
    }

    /// `Σ_lights V·g·B·I` at `x` (the backend applies `B`), counted into `stats`; `None` when
    /// the backend can't shade `x`.
    fn in_scattered<B: ManyLights>(
        &self,
        backend: &B,
        h0: f32,
        x: Vec3,
        scratch: &mut Scratch,
        stats: &mut RenderStats,
    ) -> Option<Vec3> {
        let Some(grid) = &self.shadows else {
            let sum = lgh_core::probe(backend, x, h0).ok()?;
            stats.shading_points += 1;
            stats.lights_evaluated += u64::from(sum.lights);
            return Some(sum.radiance);
        };
        // Gather the lights, then march their shadow rays together.
        let point = ShadingPoint::in_medium(x);
        scratch.positions.clear();
        scratch.unshadowed.clear();
        let sum = backend
            .illuminate(&point, &mut |l: &LightSample| {
                scratch.positions.push(l.position);
                scratch
                    .unshadowed
                    .push((l.intensity, falloff(l.distance, h0)));
                Vec3::ZERO
            })
            .ok()?;
        stats.shading_points += 1;
        stats.lights_evaluated += u64::from(sum.lights);
        stats.shadow_samples += grid.transmittances(x, &scratch.positions, &mut scratch.visibility);
        // Summed in the backend's order, as the backend sums what a shader returns.
        let mut radiance = Vec3::ZERO;
        for (&(intensity, g), &v) in scratch.unshadowed.iter().zip(&scratch.visibility) {
            radiance += intensity * (g * v);
        }
        Some(radiance)
    }
}

/// A shading point's lights, gathered so that their shadow rays can be marched together; reused
/// from shading point to shading point and ray to ray.
#[derive(Default)]
struct Scratch {
    positions: Vec<Vec3>,
    /// Intensity and fall-off `g` of each light.
    unshadowed: Vec<(Vec3, f32)>,
    visibility: Vec<f32>,
}

/// Renders an image, rows in parallel (each pixel is independent and the counts are integer
/// sums, so neither depends on the thread count). `progress(rows)` is called as rows finish.
pub fn render<B: ManyLights + Sync>(
    volume: &Volume,
    medium: &Medium,
    lights: Option<(&B, f32)>,
    camera: &Camera,
    settings: &MarchSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<(Image, RenderStats), String> {
    let marcher = Marcher::for_lights(volume, medium, settings, lights.is_some())?;
    let mut image = Image::new(camera.width(), camera.height());
    let stats = image
        .pixels
        .par_chunks_mut(camera.width())
        .enumerate()
        .map(|(y, row)| {
            let mut stats = RenderStats::default();
            let mut scratch = Scratch::default();
            for (x, px) in row.iter_mut().enumerate() {
                let (eye, d) = camera.ray(x, y);
                *px = marcher.march_with(lights, eye, d, &mut stats, &mut scratch);
            }
            progress(1);
            stats
        })
        .reduce(RenderStats::default, |mut a, b| {
            a.add(&b);
            a
        });
    Ok((image, stats))
}

/// The pixels `(x, y)` of `pixels` only, exactly as [`render`] computes them, in parallel: for
/// brute-force references and benchmarks on pixel subsets. Pixels outside the image are an
/// error.
pub fn render_pixels<B: ManyLights + Sync>(
    volume: &Volume,
    medium: &Medium,
    lights: Option<(&B, f32)>,
    camera: &Camera,
    settings: &MarchSettings,
    pixels: &[[usize; 2]],
) -> Result<(Vec<Vec3>, RenderStats), String> {
    camera.check_pixels(pixels)?;
    let marcher = Marcher::for_lights(volume, medium, settings, lights.is_some())?;
    let out: Vec<(Vec3, RenderStats)> = pixels
        .par_iter()
        .map_init(Scratch::default, |scratch, &[x, y]| {
            let mut stats = RenderStats::default();
            let (eye, d) = camera.ray(x, y);
            let radiance = marcher.march_with(lights, eye, d, &mut stats, scratch);
            (radiance, stats)
        })
        .collect();
    let (radiance, per_pixel): (Vec<Vec3>, Vec<RenderStats>) = out.into_iter().unzip();
    let mut stats = RenderStats::default();
    per_pixel.iter().for_each(|s| stats.add(s));
    Ok((radiance, stats))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DenseGrid;
    use lgh_core::BruteForce;

    /// A homogeneous box of density 1 and temperature `kelvin`, 2 units on a side.
    fn slab_volume(kelvin: f32) -> Volume {
        let origin = Vec3::splat(-1.0 + 1.0 / 32.0);
        let mut density = DenseGrid::zeros([32; 3], 1.0 / 16.0, origin);
        density.data.fill(1.0);
        let mut temperature = density.clone();
        temperature.data.fill(kelvin);
        Volume::new(density, temperature)
    }

    #[test]
    fn emitting_absorbing_slab_matches_the_closed_form() {
        // L = j / σ_a (1 − e^{−σ_a ℓ}) through a slab of length ℓ = 2.
        let v = slab_volume(2000.0);
        for sigma in [0.1f32, 1.0, 4.0] {
            let m = Medium::new(sigma, 0.0, 1e-3, 500.0).unwrap();
            let j = m.emission_at(2000.0);
            let got = Marcher::new(&v, &m, &MarchSettings::default())
                .unwrap()
                .march::<BruteForce>(
                    None,
                    Vec3::new(0.0, 0.0, 5.0),
                    -Vec3::Z,
                    &mut RenderStats::default(),
                );
            let want = j / sigma * (1.0 - (-2.0 * sigma).exp());
            // Each step is integrated exactly, so what remains is f32 rounding over 64 steps
            // (1e-4) and the early stop at T < min_transmittance, which drops at most
            // T_stop · j / σ of the tail.
            let s = MarchSettings::default();
            let tol = 1e-4 * want.max_element() + s.min_transmittance * j.max_element() / sigma;
            assert!(
                (got - want).abs().max_element() <= tol,
                "σ {sigma}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn bad_march_settings_are_errors() {
        let v = slab_volume(0.0);
        let m = Medium::new(1.0, 1.0, 0.0, 0.0).unwrap();
        let ok = MarchSettings::default();
        assert!(Marcher::new(&v, &m, &ok).is_ok());
        for bad in [
            MarchSettings {
                step_voxels: 0.0,
                ..ok
            },
            MarchSettings {
                step_voxels: f32::NAN,
                ..ok
            },
            MarchSettings {
                shadow_step_voxels: -1.0,
                ..ok
            },
            MarchSettings {
                shadow_step_voxels: f32::INFINITY,
                ..ok
            },
            MarchSettings {
                min_transmittance: 1.0,
                ..ok
            },
            MarchSettings {
                min_transmittance: -0.1,
                ..ok
            },
        ] {
            assert!(Marcher::new(&v, &m, &bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn camera_frames_the_box_and_rejects_nonsense() {
        let c = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 64, 36).unwrap();
        // The centre pixel looks at the box centre.
        let d = c.direction(32.0, 18.0);
        assert!((c.eye() + d * (c.eye().length())).length() < 1e-3);
        assert!(Camera::look_at(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 40.0, 8, 8).is_err());
        assert!(Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 40.0, 8, 8).is_err());
        assert!(Camera::look_at(Vec3::ZERO, Vec3::X, Vec3::Y, 0.0, 8, 8).is_err());
        assert!(Camera::look_at(Vec3::ZERO, Vec3::X, Vec3::Y, 40.0, 0, 8).is_err());
        // The messages are the shared camera's.
        assert_eq!(
            Camera::look_at(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 40.0, 8, 8),
            Err(lgh_image::camera::CameraError::EyeAtTarget.to_string())
        );
        // Pixel lists are checked against the image size.
        assert!(c.check_pixels(&[[0, 0], [63, 35]]).is_ok());
        for outside in [[64, 0], [0, 36]] {
            let e = c.check_pixels(&[[1, 1], outside]).unwrap_err();
            assert!(e.contains("outside the 64x36 image"), "{e}");
        }
    }
}
