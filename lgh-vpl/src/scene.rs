//! A scene: a mesh and the hierarchy over it, and the surface point a camera ray sees.

use lgh_core::glam::Vec3;
use lgh_core::ShadingPoint;

use crate::bvh::{Bvh, Hit, Ray};
use crate::mesh::Mesh;
use crate::specular::DEFAULT_SPECULAR_DEPTH;

/// A mesh with its BVH, ready for rays.
#[derive(Clone, Debug)]
pub struct Scene {
    mesh: Mesh,
    bvh: Bvh,
    specular_depth: u32,
    /// Half the diagonal of the mesh's bounding box.
    radius: f32,
    /// Whether the mesh has cut-outs (MTL `map_d`), which rays must test (kept: every ray
    /// asks, and the mesh does not change).
    coverage: bool,
}

impl Scene {
    /// Builds the BVH over `mesh`; paths follow up to [`DEFAULT_SPECULAR_DEPTH`] specular
    /// surfaces.
    #[must_use]
    pub fn new(mesh: Mesh) -> Scene {
        let bvh = Bvh::new(&mesh);
        let (lo, hi) = mesh.bounds();
        Scene {
            bvh,
            specular_depth: DEFAULT_SPECULAR_DEPTH,
            radius: (hi - lo).length() * 0.5,
            coverage: mesh.has_coverage(),
            mesh,
        }
    }

    /// The most specular surfaces (mirrors, glass) a camera or light path follows
    /// ([`crate::specular`]); 0 stops every path at its first surface.
    #[must_use]
    pub fn specular_depth(&self) -> u32 {
        self.specular_depth
    }

    /// Sets [`specular_depth`](Self::specular_depth).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::{Mesh, Scene, DEFAULT_MATERIAL};
    ///
    /// let quad = Mesh::quad([Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y], DEFAULT_MATERIAL)?;
    /// let mut scene = Scene::new(quad);
    /// assert_eq!(scene.specular_depth(), lgh_vpl::specular::DEFAULT_SPECULAR_DEPTH);
    /// scene.set_specular_depth(2);
    /// assert_eq!(scene.specular_depth(), 2);
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    pub fn set_specular_depth(&mut self, depth: u32) {
        self.specular_depth = depth;
    }

    /// How far a ray leaving a surface starts off it, along the face normal: 10⁻⁴ of the
    /// scene's bounding radius (at least 10⁻¹⁰), so that it does not hit its own triangle.
    #[must_use]
    pub fn ray_offset(&self) -> f32 {
        1e-4 * self.radius.max(1e-6)
    }

    /// The diagonal of the mesh's bounding box: no two points of the mesh are farther apart.
    #[must_use]
    pub fn diameter(&self) -> f32 {
        2.0 * self.radius
    }

    /// The mesh.
    #[must_use]
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The BVH over the mesh.
    #[must_use]
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// The closest hit along `ray`, through the holes of cut-outs (MTL `map_d`,
    /// [`Mesh::covers`]).
    #[must_use]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if self.coverage {
            self.bvh
                .intersect_where(ray, |t, u, v| self.mesh.covers(t, u, v))
        } else {
            self.bvh.intersect(ray)
        }
    }

    /// Whether the surfaces hide `to` from `from` ([`Bvh::occluded`]), light passing through
    /// the holes of cut-outs (MTL `map_d`, [`Mesh::covers`]).
    #[must_use]
    pub fn occluded(&self, from: Vec3, to: Vec3) -> bool {
        if self.coverage {
            self.bvh
                .occluded_where(from, to, |t, u, v| self.mesh.covers(t, u, v))
        } else {
            self.bvh.occluded(from, to)
        }
    }

    /// The surface point seen along the ray from `origin` in direction `dir`, if any: see
    /// [`surface`](Self::surface).
    #[must_use]
    pub fn first_hit(&self, origin: Vec3, dir: Vec3) -> Option<ShadingPoint> {
        self.trace(origin, dir).map(|(point, _)| point)
    }

    /// The surface point seen along the ray from `origin` in direction `dir` and its triangle,
    /// if any.
    #[must_use]
    pub fn trace(&self, origin: Vec3, dir: Vec3) -> Option<(ShadingPoint, u32)> {
        let ray = Ray::new(origin, dir);
        let hit = self.intersect(&ray)?;
        Some((self.surface(&ray, &hit), hit.triangle))
    }

    /// The shading point of `hit` seen along `ray`: the point on the triangle at the hit's
    /// barycentrics, the unit view direction `−dir`, the triangle's material there (its diffuse
    /// texture applied, [`Mesh::material_at`]), the face normal as the geometric normal
    /// (`ShadingPoint::geometric`: shadow rays and VPLs' hemispheres) and the shading
    /// normal, both turned to the viewer's side of the surface. Which side that is, the face normal
    /// decides (flipped when `n·dir > 0`); the shading normal is first turned into the face
    /// normal's hemisphere, so vertex normals that disagree with the winding cannot put it on
    /// the other side.
    #[must_use]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> ShadingPoint {
        let (mesh, t) = (&self.mesh, hit.triangle);
        let mut face = mesh.face_normal(t);
        let mut normal = mesh.shading_normal(t, hit.u, hit.v);
        if normal.dot(face) < 0.0 {
            normal = -normal;
        }
        if face.dot(ray.dir()) > 0.0 {
            normal = -normal;
            face = -face;
        }
        ShadingPoint {
            position: mesh.point(t, hit.u, hit.v),
            normal: Some(normal),
            geometric: Some(face),
            view: Some(-ray.dir().normalize()),
            material: mesh.material_at(t, hit.u, hit.v),
        }
    }
}

/// Where a shadow ray leaving `point` (unit shading `normal`) starts: `epsilon` off the surface
/// along its geometric normal (`ShadingPoint::geometric`), so that it does not hit its own
/// triangle even where the shading normal leans far from the face.
#[must_use]
pub(crate) fn shadow_origin(point: &ShadingPoint, normal: Vec3, epsilon: f32) -> Vec3 {
    point.position + point.geometric_normal().unwrap_or(normal) * epsilon
}

/// Whether the offset `to` from `point` (unit shading `normal`) lies in front of the surface:
/// in front of its shading plane, where the BRDF's cosine is positive, and of its geometric
/// plane, behind which the surface itself hides it.
#[must_use]
pub(crate) fn in_front(point: &ShadingPoint, normal: Vec3, to: Vec3) -> bool {
    normal.dot(to) > 0.0 && point.geometric.is_none_or(|g| g.dot(to) > 0.0)
}
