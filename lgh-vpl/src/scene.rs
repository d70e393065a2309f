//! A scene: a mesh and the hierarchy over it, and the surface point a camera ray sees.

use lgh_core::glam::Vec3;
use lgh_core::ShadingPoint;

use crate::bvh::{Bvh, Hit, Ray};
use crate::mesh::Mesh;

/// A mesh with its BVH, ready for rays.
#[derive(Clone, Debug)]
pub struct Scene {
    mesh: Mesh,
    bvh: Bvh,
}

impl Scene {
    /// Builds the BVH over `mesh`.
    #[must_use]
    pub fn new(mesh: Mesh) -> Scene {
        let bvh = Bvh::new(&mesh);
        Scene { mesh, bvh }
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

    /// The surface point seen along the ray from `origin` in direction `dir`, if any: see
    /// [`surface`](Self::surface).
    #[must_use]
    pub fn first_hit(&self, origin: Vec3, dir: Vec3) -> Option<ShadingPoint> {
        let ray = Ray::new(origin, dir);
        let hit = self.bvh.intersect(&ray)?;
        Some(self.surface(&ray, &hit))
    }

    /// The shading point of `hit` seen along `ray`: the point on the triangle at the hit's
    /// barycentrics, the unit view direction `−dir`, the triangle's material there (its diffuse
    /// texture applied, [`Mesh::material_at`]), and the shading
    /// normal turned to the viewer's side of the surface. Which side that is, the face normal
    /// decides (flipped when `n·dir > 0`); the shading normal is first turned into the face
    /// normal's hemisphere, so vertex normals that disagree with the winding cannot put it on
    /// the other side.
    #[must_use]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> ShadingPoint {
        let (mesh, t) = (&self.mesh, hit.triangle);
        let face = mesh.face_normal(t);
        let mut normal = mesh.shading_normal(t, hit.u, hit.v);
        if normal.dot(face) < 0.0 {
            normal = -normal;
        }
        if face.dot(ray.dir()) > 0.0 {
            normal = -normal;
        }
        ShadingPoint {
            position: mesh.point(t, hit.u, hit.v),
            normal: Some(normal),
            view: Some(-ray.dir().normalize()),
            material: mesh.material_at(t, hit.u, hit.v),
        }
    }
}
