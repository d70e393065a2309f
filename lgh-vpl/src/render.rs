//! The surface renderer: one camera ray per pixel centre, the closest surface it hits shaded
//! through any [`ManyLights`] backend.
//!
//! Each light is shaded with Paquette et al.'s Phong model eq. (1)
//! ([`lgh_core::reflection::reflected`]), the model the error-bounded backends bound. **Lights
//! are not occluded**: no shadow rays, as in the paper's experiments, where every light reaches
//! every point; only the reflection model's `N·L > 0` hides a light behind a surface's own
//! plane. Pixels whose ray hits nothing are black.
//!
//! Rows render in parallel with rayon. Every pixel is computed on its own, in the same order of
//! operations whatever the thread, and the statistics are integer sums, so the image and the
//! counts are bit-identical for any number of threads.

use std::fmt;

use lgh_core::glam::Vec3;
use lgh_core::reflection::reflected;
use lgh_core::{Illumination, LightSample, ManyLights, QueryError, ShadingPoint};
use lgh_image::Image;
use rayon::prelude::*;

use crate::bvh::Ray;
use crate::scene::Scene;
use lgh_image::camera::Pinhole as Camera;

/// A rendered image and what it took.
#[derive(Clone, Debug, PartialEq)]
pub struct Rendered {
    /// Linear RGB radiance, top row first.
    pub image: Image,
    /// Pixels whose ray hit a surface (each one shading point).
    pub pixels_shaded: u64,
    /// Lights (or clusters) shaded at each pixel ([`lgh_core::Illumination::lights`]), top row
    /// first: the backend's cost map (0 where the ray hits nothing).
    pub lights_map: Vec<u32>,
}

impl Rendered {
    /// Lights (or clusters) shaded, summed over the pixels.
    #[must_use]
    pub fn lights_shaded(&self) -> u64 {
        self.lights_map.iter().map(|&c| u64::from(c)).sum()
    }

    /// Mean lights shaded per shaded pixel (0 when no pixel was shaded).
    #[must_use]
    pub fn mean_lights(&self) -> f64 {
        if self.pixels_shaded == 0 {
            0.0
        } else {
            self.lights_shaded() as f64 / self.pixels_shaded as f64
        }
    }
}

/// Why a render failed.
#[derive(Clone, Debug, PartialEq)]
pub enum RenderError {
    /// The backend refused a shading point (the first such pixel in row-major order).
    Query {
        /// Pixel column.
        x: usize,
        /// Pixel row.
        y: usize,
        /// What the backend said.
        error: QueryError,
    },
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Query { x, y, error } => {
                write!(f, "render: pixel ({x}, {y}): {error}")
            }
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RenderError::Query { error, .. } => Some(error),
        }
    }
}

/// Renders `scene` through `backend` with eq. (1), unoccluded (see the module docs).
/// `progress(rows)` is called as rows finish, with the number just finished.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::{BruteForce, PointLight};
/// use lgh_vpl::{render, Camera, Mesh, Scene, DEFAULT_MATERIAL};
///
/// // A floor filling the view of a camera looking straight down, one light above it.
/// let floor = Mesh::quad(
///     [Vec3::new(-9.0, 0.0, 9.0), Vec3::new(9.0, 0.0, 9.0), Vec3::new(9.0, 0.0, -9.0), Vec3::new(-9.0, 0.0, -9.0)],
///     DEFAULT_MATERIAL,
/// )?;
/// let scene = Scene::new(floor);
/// let light = [PointLight::new(Vec3::new(0.0, 2.0, 0.0), Vec3::splat(10.0))];
/// let backend = BruteForce::new(&light)?;
/// let camera = Camera::new(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0, 8, 6)?;
/// let rows = std::sync::atomic::AtomicUsize::new(0);
/// let rendered = render(&scene, &camera, &backend, |n| {
///     rows.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
/// })?;
/// assert_eq!(rows.into_inner(), 6);
/// assert_eq!((rendered.image.width, rendered.image.height), (8, 6));
/// // Every pixel sees the lit floor, through its one light.
/// assert_eq!(rendered.pixels_shaded, 48);
/// assert_eq!(rendered.mean_lights(), 1.0);
/// assert!(rendered.image.pixels.iter().all(|p| p.min_element() > 0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render<B: ManyLights + Sync>(
    scene: &Scene,
    camera: &Camera,
    backend: &B,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    render_with_shader(
        scene,
        camera,
        backend,
        |point, light| reflected(point, light.position, light.intensity, light.lobe),
        progress,
    )
}

/// [`render`] with another shader: `shade(point, light)` is the radiance `light` sends towards
/// the viewer from `point` (add visibility here, for instance).
pub fn render_with_shader<B, F>(
    scene: &Scene,
    camera: &Camera,
    backend: &B,
    shade: F,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError>
where
    B: ManyLights + Sync,
    F: Fn(&ShadingPoint, &LightSample) -> Vec3 + Sync,
{
    render_points(
        scene,
        camera,
        |point| backend.illuminate(point, &mut |light: &LightSample| shade(point, light)),
        progress,
    )
}

/// The render loop of a many-lights backend: `illuminate(point)` is what each pixel's surface
/// point receives (a backend's sum, or several backends' together).
pub fn render_points<F>(
    scene: &Scene,
    camera: &Camera,
    illuminate: F,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError>
where
    F: Fn(&ShadingPoint) -> Result<Illumination, QueryError> + Sync,
{
    render_surfaces(scene, camera, |point, _| illuminate(point), progress)
}

/// The render loop itself: `illuminate(point, triangle)` is what each pixel's surface point,
/// on mesh triangle `triangle`, sends to the camera.
pub fn render_surfaces<F>(
    scene: &Scene,
    camera: &Camera,
    illuminate: F,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError>
where
    F: Fn(&ShadingPoint, u32) -> Result<Illumination, QueryError> + Sync,
{
    let width = camera.width();
    let mut image = Image::new(width, camera.height());
    let mut lights_map = vec![0u32; image.pixels.len()];
    let rows: Vec<Result<u64, RenderError>> = image
        .pixels
        .par_chunks_mut(width)
        .zip(lights_map.par_chunks_mut(width))
        .enumerate()
        .map(|(y, (row, costs))| {
            let mut pixels = 0u64;
            for (x, (px, cost)) in row.iter_mut().zip(costs.iter_mut()).enumerate() {
                let (origin, dir) = camera.ray(x, y);
                let ray = Ray::new(origin, dir);
                let Some(hit) = scene.intersect(&ray) else {
                    continue;
                };
                let point = scene.surface(&ray, &hit);
                let sum =
                    crate::specular::camera_path(scene, &ray, point, hit.triangle, &illuminate)
                        .map_err(|error| RenderError::Query { x, y, error })?;
                *px = sum.radiance;
                *cost = sum.lights;
                pixels += 1;
            }
            progress(1);
            Ok(pixels)
        })
        .collect();
    let mut pixels_shaded = 0;
    for row in rows {
        pixels_shaded += row?;
    }
    Ok(Rendered {
        image,
        pixels_shaded,
        lights_map,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use lgh_core::random::SplitMix64;
    use lgh_core::reflection::Lobe;
    use lgh_core::{BruteForce, Illumination, Material, PointLight, Shader};

    const FLOOR: Material = Material::Phong {
        kd: Vec3::new(0.5, 0.4, 0.3),
        ks: Vec3::splat(0.2),
        exponent: 30.0,
    };

    /// The square `|x|, |z| ≤ 10` of the plane y = 0, front face up.
    fn floor() -> Mesh {
        let c = |x: f32, z: f32| Vec3::new(x, 0.0, z);
        Mesh::quad(
            [
                c(-10.0, 10.0),
                c(10.0, 10.0),
                c(10.0, -10.0),
                c(-10.0, -10.0),
            ],
            FLOOR,
        )
        .unwrap()
    }

    /// `n` lights over the floor, a quarter of them below it.
    fn lights(n: usize) -> Vec<PointLight> {
        let mut rng = SplitMix64(5);
        (0..n)
            .map(|_| {
                let p = rng.next_in(Vec3::new(-6.0, -1.0, -6.0), Vec3::new(6.0, 3.0, 6.0));
                PointLight::new(p, rng.next_in(Vec3::ZERO, Vec3::splat(5.0)))
            })
            .collect()
    }

    #[test]
    fn brute_force_render_matches_eq_1_summed_per_pixel() {
        let scene = Scene::new(floor());
        let lights = lights(40);
        let backend = BruteForce::new(&lights).unwrap();
        // Looking down at the floor; the top rows see the sky.
        let camera =
            Camera::new(Vec3::new(0.0, 3.0, 5.0), Vec3::ZERO, Vec3::Y, 60.0, 24, 16).unwrap();
        let rows = std::sync::atomic::AtomicUsize::new(0);
        let got = render(&scene, &camera, &backend, |n| {
            rows.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(rows.into_inner(), 16);
        // The reference: the ray meets y = 0 at t = −o.y / d.y, inside the square or not; eq. (1)
        // summed over the lights in order, as brute force sums them.
        let mut hits = 0;
        let mut worst = 0.0f32;
        for y in 0..16 {
            for x in 0..24 {
                let (o, d) = camera.ray(x, y);
                let t = -o.y / d.y;
                let p = o + t * d;
                let want = if t > 0.0 && p.x.abs() <= 10.0 && p.z.abs() <= 10.0 {
                    hits += 1;
                    let point = ShadingPoint {
                        position: p,
                        normal: Some(Vec3::Y),
                        geometric: None,
                        view: Some(-d),
                        material: FLOOR,
                    };
                    lights.iter().fold(Vec3::ZERO, |sum, l| {
                        sum + reflected(&point, l.position, l.intensity, Lobe::All)
                    })
                } else {
                    Vec3::ZERO
                };
                let px = got.image.get(x, y);
                if want == Vec3::ZERO {
                    assert_eq!(px, want, "pixel ({x}, {y})");
                } else {
                    worst =
                        worst.max(((px - want).abs() / want.max(Vec3::splat(1e-6))).max_element());
                }
            }
        }
        // Same lights, same order, same shader: what differs is the hit point, interpolated from
        // the triangle's corners (rounding ≈ 1e-7 relative of |p| ≤ 10) instead of o + t·d, and
        // the view direction normalised once more. Through 1/d² and the cosines that is ~1e-6
        // relative; the Phong lobe (R·E)^30 multiplies the cosine's error by 30, so 1e-4 bounds
        // it with room (measured: 5.7e-6).
        assert!(worst < 1e-4, "largest relative difference {worst}");
        assert!(
            hits > 100 && hits < 24 * 16,
            "{hits} of the pixels see the floor"
        );
        assert_eq!(got.pixels_shaded, hits);
        assert_eq!(got.lights_shaded(), hits * 40);
        assert_eq!(got.mean_lights(), 40.0);
        // The cost map: every light at each pixel that sees the floor, none at the sky's.
        let counted: Vec<u32> = got.lights_map.iter().copied().filter(|&c| c > 0).collect();
        assert_eq!(counted.len() as u64, hits);
        assert!(counted.iter().all(|&c| c == 40));
    }

    #[test]
    fn images_are_bit_identical_for_any_thread_count() {
        let mut mesh = floor();
        let red = Material::Phong {
            kd: Vec3::new(0.7, 0.1, 0.1),
            ks: Vec3::splat(0.5),
            exponent: 80.0,
        };
        mesh.append(Mesh::cuboid(Vec3::new(-1.0, 0.0, -1.0), Vec3::ONE, red).unwrap())
            .unwrap();
        let scene = Scene::new(mesh);
        let backend = BruteForce::new(&lights(64)).unwrap();
        let camera =
            Camera::new(Vec3::new(3.0, 4.0, 6.0), Vec3::ZERO, Vec3::Y, 50.0, 40, 30).unwrap();
        let in_pool = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| render(&scene, &camera, &backend, |_| {}).unwrap())
        };
        let (one, two) = (in_pool(1), in_pool(2));
        assert!(one.pixels_shaded > 0);
        let bits = |r: &Rendered| -> Vec<[u32; 3]> {
            r.image
                .pixels
                .iter()
                .map(|p| p.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&one), bits(&two));
        assert_eq!(one, two);
    }

    /// Brute force over one unit light at (0, 5, 0), refusing points with x > 0.
    struct RefusesPositiveX(BruteForce);

    impl RefusesPositiveX {
        fn new() -> Self {
            let light = PointLight::new(Vec3::new(0.0, 5.0, 0.0), Vec3::ONE);
            RefusesPositiveX(BruteForce::new(&[light]).unwrap())
        }
    }

    impl ManyLights for RefusesPositiveX {
        fn name(&self) -> &'static str {
            "refuses"
        }

        fn illuminate<S: Shader>(
            &self,
            point: &ShadingPoint,
            shader: &mut S,
        ) -> Result<Illumination, QueryError> {
            if point.position.x > 0.0 {
                return Err(QueryError::NonFinitePoint);
            }
            self.0.illuminate(point, shader)
        }
    }

    #[test]
    fn the_first_refused_pixel_is_the_error_and_custom_shaders_are_used() {
        let scene = Scene::new(floor());
        // Straight down at the floor: every pixel hits, the right half at x > 0.
        let camera =
            Camera::new(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, Vec3::Z, 60.0, 8, 6).unwrap();
        let e = render(&scene, &camera, &RefusesPositiveX::new(), |_| {}).unwrap_err();
        let first_right = (0..8).find(|&x| camera.ray(x, 0).1.x > 0.0).unwrap();
        assert_eq!(
            e,
            RenderError::Query {
                x: first_right,
                y: 0,
                error: QueryError::NonFinitePoint
            }
        );
        assert!(e.to_string().contains(&format!("({first_right}, 0)")));
        // A shader that returns the light's intensity, on the left half only: every pixel is 1.
        let left = Camera::new(
            Vec3::new(-5.0, 4.0, 0.0),
            Vec3::new(-5.0, 0.0, 0.0),
            Vec3::Z,
            60.0,
            8,
            6,
        )
        .unwrap();
        let r = render_with_shader(
            &scene,
            &left,
            &RefusesPositiveX::new(),
            |_, l| l.intensity,
            |_| {},
        )
        .unwrap();
        assert!(r.image.pixels.iter().all(|&p| p == Vec3::ONE));
        assert_eq!((r.pixels_shaded, r.lights_shaded()), (48, 48));
    }
}
