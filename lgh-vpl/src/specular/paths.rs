//! The paths themselves ([`super`]'s module docs): the branches leaving a specular surface,
//! and the camera's path through them to the surfaces that are shaded.

use lgh_core::glam::Vec3;
use lgh_core::{luminance, Illumination, Material, QueryError, ShadingPoint};

use super::{fresnel, reflect, refract, Specular, MIN_WEIGHT};
use crate::bvh::Ray;
use crate::scene::Scene;

/// One way a path leaves a specular surface: its direction, what it carries (per channel),
/// and the face normal of the side it leaves on (for the next ray's offset).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Branch {
    pub(crate) dir: Vec3,
    /// The fraction of flux it carries.
    pub(crate) weight: Vec3,
    /// Radiance's `(η_i/η_t)²` on refraction (1 otherwise): kept apart from `weight`, as it
    /// cancels when the path leaves the medium, so that [`MIN_WEIGHT`] judges flux alone.
    pub(crate) radiance_scale: f32,
    pub(crate) side: Vec3,
    /// The probability a light path takes it: its share of what leaves.
    pub(crate) share: f32,
}

/// The branches leaving triangle `t`'s specular part at `point`, for a path arriving along
/// the unit `dir`: none, the mirror's, or a dielectric's reflection and refraction (one of
/// them where the reflection is total). `camera`: whether the path runs against the light (a
/// camera's) or with it (a light path's); `Tf` filters where the *light* enters the material,
/// which for a camera path is where it leaves.
pub(crate) fn branches(
    scene: &Scene,
    t: u32,
    point: &ShadingPoint,
    dir: Vec3,
    camera: bool,
) -> ([Option<Branch>; 2], Specular) {
    let mesh = scene.mesh();
    let specular = mesh.specular(t);
    if specular == Specular::None {
        // The common case, in every light path's every bounce: nothing to compute.
        return ([None, None], specular);
    }
    let face = mesh.face_normal(t);
    let entering = face.dot(dir) < 0.0;
    // Towards the side the path arrived from.
    let front = if entering { face } else { -face };
    // The shading normal on that side; the face normal where interpolation turned it away.
    let n = point.normal.filter(|n| n.dot(dir) < 0.0).unwrap_or(front);
    let mirror = |weight: Vec3, share: f32| Branch {
        dir: reflect(dir, n),
        weight,
        radiance_scale: 1.0,
        side: front,
        share,
    };
    let out = match specular {
        Specular::None => [None, None],
        Specular::Mirror { reflectance } => [Some(mirror(reflectance, 1.0)), None],
        Specular::Dielectric { ior, transmittance } => {
            let (eta_i, eta_t) = if entering { (1.0, ior) } else { (ior, 1.0) };
            let f = fresnel(-dir.dot(n), eta_i, eta_t);
            let reflected = Some(mirror(Vec3::splat(f), f));
            let refracted = refract(dir, n, eta_i, eta_t).filter(|_| f < 1.0).map(|d| {
                let filter = if entering != camera {
                    transmittance
                } else {
                    Vec3::ONE
                };
                Branch {
                    dir: d,
                    weight: filter * (1.0 - f),
                    radiance_scale: (eta_i / eta_t).powi(2),
                    side: -front,
                    share: 1.0 - f,
                }
            });
            [reflected, refracted]
        }
    };
    (out, specular)
}

/// What the camera sees along `ray`, whose first hit is `hit` of triangle `t`: `shade(point,
/// triangle)` at every surface the path reaches that is not purely specular, weighted by what
/// the specular surfaces before it pass on (module docs), summed with the lights each shaded.
pub(crate) fn camera_path<F>(
    scene: &Scene,
    ray: &Ray,
    point: ShadingPoint,
    t: u32,
    shade: &F,
) -> Result<Illumination, QueryError>
where
    F: Fn(&ShadingPoint, u32) -> Result<Illumination, QueryError>,
{
    if scene.mesh().specular(t) == Specular::None {
        // No specular surface: the shaded point alone, exactly as without this module.
        return shade(&point, t);
    }
    let mut sum = Illumination {
        radiance: Vec3::ZERO,
        lights: 0,
    };
    let carried = Carried {
        weight: Vec3::ONE,
        radiance_scale: 1.0,
        depth: 0,
    };
    follow(scene, ray.dir(), point, t, carried, shade, &mut sum)?;
    Ok(sum)
}

/// What a camera path carries to a surface.
#[derive(Clone, Copy, Debug)]
struct Carried {
    /// The fraction of flux (per channel) the specular surfaces before pass on.
    weight: Vec3,
    /// The product of their radiance scales `(η_i/η_t)²`.
    radiance_scale: f32,
    /// How many specular surfaces it met.
    depth: u32,
}

/// [`camera_path`] from `point` on triangle `t`, reached along `dir` with `carried`.
fn follow<F>(
    scene: &Scene,
    dir: Vec3,
    point: ShadingPoint,
    t: u32,
    carried: Carried,
    shade: &F,
    sum: &mut Illumination,
) -> Result<(), QueryError>
where
    F: Fn(&ShadingPoint, u32) -> Result<Illumination, QueryError>,
{
    let (out, specular) = branches(scene, t, &point, dir, true);
    // A mirror without a diffuse part, or glass: nothing to shade beside the branches, unless
    // it emits (its emission is the shader's to add).
    let emits = scene.mesh().emission(t) != Vec3::ZERO;
    let black = point.material == Material::Lambert { albedo: Vec3::ZERO };
    if emits || !(specular.is_pure() || black) {
        let lit = shade(&point, t)?;
        sum.radiance += carried.weight * carried.radiance_scale * lit.radiance;
        sum.lights += lit.lights;
    }
    if carried.depth >= scene.specular_depth() {
        return Ok(());
    }
    for branch in out.into_iter().flatten() {
        let next = Carried {
            weight: carried.weight * branch.weight,
            radiance_scale: carried.radiance_scale * branch.radiance_scale,
            depth: carried.depth + 1,
        };
        if luminance(next.weight) < MIN_WEIGHT {
            continue;
        }
        let ray = Ray::new(
            point.position + branch.side * scene.ray_offset(),
            branch.dir,
        );
        let Some(hit) = scene.intersect(&ray) else {
            continue;
        };
        let surface = scene.surface(&ray, &hit);
        follow(scene, branch.dir, surface, hit.triangle, next, shade, sum)?;
    }
    Ok(())
}
