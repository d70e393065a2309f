//! An OBJ scene around an explosion (`lgh explosion --scene ROOM.obj`): lgh-vpl's meshes and
//! BVH as the opaque [`Surfaces`] of the volume render (the paper's explosions in a box, Figs. 5
//! and 8).

use std::path::Path;

use lgh_core::glam::Vec3;
use lgh_core::Material;
use lgh_volume::surfaces::{SurfaceHit, Surfaces};
use lgh_vpl::{Mesh, Scene};

use crate::manifest::SceneFile;

/// The surfaces of an OBJ scene: each triangle's diffuse albedo (a Phong material's `kd`; the
/// smoke render shades surfaces as Lambertian), its shading normal turned towards the viewer,
/// shadows through the BVH.
pub struct Room {
    scene: Scene,
    files: Vec<SceneFile>,
}

impl Room {
    /// Loads `path` (OBJ, its MTL beside it; a triangle without a material is grey, 0.5),
    /// hashing each file's bytes as it is read, and names on stderr what the files ask for
    /// and the renderer does not honour.
    pub fn load(path: &Path) -> Result<Self, crate::Error> {
        let path = crate::manifest::absolute(path)?;
        let mut files = Vec::new();
        let options = lgh_vpl::ObjOptions::default();
        let mesh = Mesh::load_obj_with(&path, &options, |p, bytes| {
            files.push(SceneFile::of(p, bytes))
        })?;
        crate::output::print_unhonoured("lgh explosion --scene", &mesh);
        // The room is shaded where the camera first meets it: mirrors and glass, which `lgh gi`
        // follows (lgh_vpl::specular), are not followed here.
        let specular = (0..mesh.materials().len() as u32)
            .filter(|&m| mesh.specular_of(m) != lgh_vpl::specular::Specular::None)
            .count();
        if specular > 0 {
            eprintln!(
                "lgh explosion --scene: not honoured: {specular} mirror or glass materials \
                 (illum 3-9) are shaded by their diffuse part (Kd) alone: the explosion's \
                 room follows no reflection or refraction"
            );
        }
        if mesh.triangles().is_empty() {
            return Err(format!("--scene {}: no triangles", path.display()).into());
        }
        Ok(Room {
            scene: Scene::new(mesh),
            files,
        })
    }

    /// The files the scene was read from (the OBJ, then its MTL files and textures) and their
    /// SHA-256.
    #[must_use]
    pub fn files(&self) -> &[SceneFile] {
        &self.files
    }

    /// Triangles of the scene.
    #[must_use]
    pub fn triangles(&self) -> usize {
        self.scene.mesh().triangles().len()
    }
}

impl Surfaces for Room {
    fn hit(&self, origin: Vec3, dir: Vec3) -> Option<SurfaceHit> {
        let p = self.scene.first_hit(origin, dir)?;
        let albedo = match p.material {
            Material::Lambert { albedo } => albedo,
            Material::Phong { kd, .. } => kd,
            Material::Isotropic => Vec3::splat(0.5),
        };
        Some(SurfaceHit {
            t: (p.position - origin).length(),
            normal: p.normal?,
            albedo: albedo.clamp(Vec3::ZERO, Vec3::ONE),
        })
    }

    fn occluded(&self, a: Vec3, b: Vec3) -> bool {
        self.scene.occluded(a, b)
    }
}
