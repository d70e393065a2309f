//! An independent estimate of the indirect light: one-bounce path tracing, the check on the VPL
//! model itself (issue 14; instant radiosity's own bias is the `1/max(d, h0)²` clamp and the
//! finite VPL count, which no many-lights backend can remove, since brute force over the VPLs
//! has them too).
//!
//! At the surface point `x` a pixel sees, `N` directions `ω_j` are drawn from the cosine
//! distribution about the normal (stratified, `√N × √N` strata, jittered from a sequence seeded
//! by `x`); each finds the surface `y_j` it hits, and the direct light `y_j` reflects back
//! towards `x` ([`Direct::shade`], shadow rays included) is averaged:
//!
//! `L_1(x) ≈ ρ_x · (1/N) Σ_j L_direct(y_j → x)`,
//!
//! the rendering equation's one-bounce term with the cosine-weighted estimator (the cosine and
//! the `1/π` of the Lambertian BRDF cancel the density `cos/π`). It is the light the VPLs of
//! the first bounce carry (`VplSettings::max_bounces = 1`): the two agree in expectation when the
//! clamp is off. Only the diffuse reflection at `x` is estimated (`ρ_x` is the Lambert albedo or
//! Phong's `k_d`): compare on Lambertian scenes, such as the Cornell box.

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_core::Illumination;

use crate::brdf::diffuse_albedo;
use crate::direct::{point_seed, Direct};
use crate::render::{render_points, RenderError, Rendered};
use crate::scene::Scene;
use lgh_image::camera::Pinhole as Camera;

/// One-bounce indirect light at every pixel with `strata²` cosine-distributed paths per pixel
/// (module docs). `epsilon` lifts the paths off the surface.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_core::Material;
/// use lgh_vpl::direct::{Direct, DirectSettings};
/// use lgh_vpl::primary::PrimaryLight;
/// use lgh_vpl::reference::one_bounce;
/// use lgh_vpl::{Camera, Mesh, Scene};
///
/// // Inside a closed white box of albedo 1/2 lit by a lamp: one bounce adds light everywhere.
/// let grey = Material::Lambert { albedo: Vec3::splat(0.5) };
/// let scene = Scene::new(Mesh::cuboid(Vec3::splat(-1.0), Vec3::ONE, grey)?);
/// let lamp = [PrimaryLight::Point { position: Vec3::new(0.0, 0.5, 0.0), intensity: Vec3::ONE }];
/// let direct = Direct::new(&scene, &lamp, DirectSettings { area_strata: 1, epsilon: 1e-4 });
/// let camera = Camera::new(Vec3::ZERO, Vec3::NEG_Y, Vec3::Z, 60.0, 4, 4)?;
/// let bounce = one_bounce(&scene, &camera, &direct, 8, 1e-4, |_| {})?;
/// assert_eq!(bounce.pixels_shaded, 16);
/// assert!(bounce.image.pixels.iter().all(|p| p.x > 0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn one_bounce(
    scene: &Scene,
    camera: &Camera,
    direct: &Direct<'_>,
    strata: u32,
    epsilon: f32,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    let n = strata.max(1);
    render_points(
        scene,
        camera,
        |x| {
            let (Some(normal), albedo) = (x.normal, diffuse_albedo(&x.material)) else {
                return Ok(Illumination {
                    radiance: Vec3::ZERO,
                    lights: 0,
                });
            };
            let from = x.position + normal * epsilon;
            let mut rng = SplitMix64(point_seed(x.position, u64::MAX));
            let (a, b) = normal.any_orthonormal_pair();
            let inv = 1.0 / n as f32;
            let mut sum = Vec3::ZERO;
            for i in 0..n {
                for j in 0..n {
                    // Cosine-distributed: a uniform point of the unit disc lifted to the
                    // hemisphere (Malley), the disc stratified in (r², φ).
                    let u = (i as f32 + rng.next_f32()) * inv;
                    let phi = std::f32::consts::TAU * (j as f32 + rng.next_f32()) * inv;
                    let r = u.sqrt();
                    let w = a * (r * phi.cos())
                        + b * (r * phi.sin())
                        + normal * (1.0 - u).max(0.0).sqrt();
                    if let Some(y) = scene.first_hit(from, w) {
                        sum += direct.shade(&y);
                    }
                }
            }
            Ok(Illumination {
                radiance: albedo * sum / (n * n) as f32,
                lights: n * n,
            })
        },
        progress,
    )
}
