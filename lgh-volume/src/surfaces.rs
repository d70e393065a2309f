//! Opaque surfaces in a volume render: the explosion over a ground, or in a box (the paper's
//! Figs. 5, 8 and 11: "rendering the box surrounding the explosions took only a few seconds per
//! frame").
//!
//! The camera ray stops at the first surface it meets; the smoke in front of it is marched as
//! before, and the surface adds its reflected light through the smoke's transmittance. A
//! surface point is shaded like a point of the medium, through the same many-lights backend
//! and the same smoke visibility (cube maps or ray-marched), with a Lambertian BRDF `ρ/π`, the
//! cosine towards each light, and an opaque shadow test against the surfaces themselves:
//! `L = Σ_j (ρ/π) max(0, n·ω_j) I_j g(d_j) T_smoke(x, p_j) V_surfaces(x, p_j)`. Surfaces do not
//! shadow the smoke (inside a box the fire and its smoke are on the same side of every wall).
//!
//! A renderer of meshes implements [`Surfaces`] (lgh-vpl's BVH scenes do, through the CLI);
//! [`Ground`] is the built-in infinite plane.

use lgh_core::glam::Vec3;

use crate::camera::Up;

/// What a camera ray meets first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the (unit) ray.
    pub t: f32,
    /// Unit normal, on the side the ray came from.
    pub normal: Vec3,
    /// Diffuse albedo ρ (RGB, each in [0, 1]).
    pub albedo: Vec3,
}

/// Opaque Lambertian surfaces: where a ray meets them, and whether they block a segment.
pub trait Surfaces: Sync {
    /// The first surface along `origin + t dir` (`dir` a unit vector), `t > 0`, if any.
    fn hit(&self, origin: Vec3, dir: Vec3) -> Option<SurfaceHit>;

    /// Whether a surface blocks the open segment from `a` to `b`.
    fn occluded(&self, a: Vec3, b: Vec3) -> bool;
}

/// The infinite plane `up · x = height` (its normal the `up` axis), grey by default: the
/// ground under `lgh demo`'s explosion.
///
/// ```
/// use lgh_volume::lgh_core::glam::Vec3;
/// use lgh_volume::render::Up;
/// use lgh_volume::surfaces::{Ground, Surfaces};
///
/// let ground = Ground::new(Up::Y, -1.0, Vec3::splat(0.5))?;
/// let hit = ground.hit(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 0.0)).unwrap();
/// assert_eq!(hit.t, 2.0);
/// assert_eq!(hit.normal, Vec3::Y);
/// assert!(ground.hit(Vec3::ZERO, Vec3::Y).is_none()); // looking up
/// assert!(ground.occluded(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, -2.0, 0.0)));
/// assert!(!ground.occluded(Vec3::new(0.0, 0.0, 0.0), Vec3::new(5.0, 0.5, 0.0)));
/// assert!(Ground::new(Up::Y, 0.0, Vec3::splat(1.5)).is_err()); // albedo above 1
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    up: Vec3,
    height: f32,
    albedo: Vec3,
}

impl Ground {
    /// The plane `up · x = height` with diffuse albedo `albedo` (each channel in [0, 1]).
    pub fn new(up: Up, height: f32, albedo: Vec3) -> Result<Self, crate::error::RenderError> {
        crate::error::check_setting(
            height.is_finite(),
            "ground height",
            height,
            "must be finite",
        )?;
        for c in albedo.to_array() {
            crate::error::check_setting(
                (0.0..=1.0).contains(&c),
                "ground albedo",
                c,
                "must be in 0..=1",
            )?;
        }
        Ok(Ground {
            up: up.vector(),
            height,
            albedo,
        })
    }

    /// Signed height of `x` above the plane.
    fn above(&self, x: Vec3) -> f32 {
        self.up.dot(x) - self.height
    }
}

impl Surfaces for Ground {
    fn hit(&self, origin: Vec3, dir: Vec3) -> Option<SurfaceHit> {
        let (h, rate) = (self.above(origin), self.up.dot(dir));
        let t = -h / rate;
        // From either side; a ray along the plane or away from it misses.
        (t > 0.0 && t.is_finite()).then(|| SurfaceHit {
            t,
            normal: if h >= 0.0 { self.up } else { -self.up },
            albedo: self.albedo,
        })
    }

    fn occluded(&self, a: Vec3, b: Vec3) -> bool {
        let (ha, hb) = (self.above(a), self.above(b));
        (ha > 0.0 && hb < 0.0) || (ha < 0.0 && hb > 0.0)
    }
}
