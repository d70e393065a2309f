//! Triangle meshes with materials: built in code ([`Mesh::quad`], [`Mesh::cuboid`],
//! [`Mesh::append`]) or read from Wavefront OBJ + MTL files ([`Mesh::load_obj`], through `tobj`).
//!
//! A mesh is always valid: every position and normal is finite, every index is in range, every
//! material is a surface material ([`Material::Lambert`] or [`Material::Phong`]) with finite,
//! non-negative coefficients, and there is at least one triangle. **Zero-area triangles are
//! skipped**, never rejected: they cannot be hit and have no normal, and real meshes carry a few
//! (slivers from triangulated polygons, collapsed edges); [`Mesh::degenerate_skipped`] says how
//! many were dropped.
//!
//! A material may carry a diffuse texture ([`Mesh::set_diffuse_texture`], MTL `map_Kd`): at a
//! point of a triangle with texture coordinates, [`Mesh::material_at`] multiplies the
//! material's `Kd` (Lambert albedo, Phong `k_d`) by the texture's colour there, as the MTL
//! format defines `map_Kd`. Triangles without texture coordinates keep the plain `Kd`.
use std::fmt;
use std::path::PathBuf;

use lgh_core::glam::{Vec2, Vec3};
use lgh_core::Material;

use crate::specular::Specular;
use crate::statements::Unhonoured;
use crate::texture::{Texture, TextureError};

/// The material of faces that name none (an OBJ without `usemtl`, or naming a material its MTL
/// files do not define) and of MTL materials without `Kd`: a grey Lambertian surface of albedo 0.5.
pub const DEFAULT_MATERIAL: Material = Material::Lambert {
    albedo: DEFAULT_ALBEDO,
};

/// The albedo of [`DEFAULT_MATERIAL`].
pub(crate) const DEFAULT_ALBEDO: Vec3 = Vec3::splat(0.5);

/// The longest line an OBJ or MTL file may have: 1 MiB (the longest statement of a real file is
/// a face of a few hundred corners, a few kilobytes).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// One triangle of a [`Mesh`]: indices into its positions, normals and materials.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Triangle {
    /// Indices of the three corners in [`Mesh::positions`], counter-clockwise seen from the front.
    pub vertices: [u32; 3],
    /// Indices of the corners' normals in [`Mesh::normals`]; `None` shades with the face normal.
    pub normals: Option<[u32; 3]>,
    /// Indices of the corners' texture coordinates in [`Mesh::texcoords`]; `None` leaves the
    /// material's diffuse texture unused on this triangle.
    pub texcoords: Option<[u32; 3]>,
    /// Index of the triangle's material in [`Mesh::materials`].
    pub material: u32,
}

/// Why a mesh could not be built or read.
#[derive(Debug)]
pub enum MeshError {
    /// A file could not be opened or read (missing OBJ, missing MTL named by `mtllib`, …).
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// A file is larger than [`lgh_image::MAX_INPUT_BYTES`].
    TooLarge {
        /// The file.
        path: PathBuf,
    },
    /// A file is not valid OBJ or MTL (not UTF-8 text, a malformed statement, a face index out
    /// of range, …).
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// No triangle with a non-zero area.
    NoTriangles {
        /// Zero-area triangles that were skipped.
        degenerate: usize,
    },
    /// A vertex position is NaN or infinite.
    NonFiniteVertex {
        /// Index of the position.
        index: usize,
    },
    /// A vertex normal is NaN or infinite.
    NonFiniteNormal {
        /// Index of the normal.
        index: usize,
    },
    /// A texture coordinate is NaN or infinite.
    NonFiniteTexcoord {
        /// Index of the texture coordinate.
        index: usize,
    },
    /// A texture file could not be decoded (not an image, damaged, too large).
    Texture {
        /// The texture file, or the material's name for textures given in code.
        path: PathBuf,
        /// What is wrong.
        error: TextureError,
    },
    /// A triangle refers to a position, normal or material that does not exist.
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
    },
    /// A material is not a surface material, or has a negative or non-finite coefficient.
    InvalidMaterial {
        /// Its name in the MTL file, or its index for meshes built in code.
        name: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// More positions, normals, triangles or materials than 32-bit indices address.
    TooMany,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::Io { path, error } => write!(f, "cannot read {}: {error}", path.display()),
            MeshError::TooLarge { path } => write!(
                f,
                "{} is larger than the {} bytes an input may have",
                path.display(),
                lgh_image::MAX_INPUT_BYTES
            ),
            MeshError::Parse { path, message } => {
                write!(f, "{} is not valid: {message}", path.display())
            }
            MeshError::NoTriangles { degenerate } => write!(
                f,
                "the mesh has no triangle of non-zero area ({degenerate} zero-area triangles skipped)"
            ),
            MeshError::NonFiniteVertex { index } => {
                write!(f, "vertex {index} has a NaN or infinite coordinate")
            }
            MeshError::NonFiniteNormal { index } => {
                write!(f, "normal {index} has a NaN or infinite coordinate")
            }
            MeshError::NonFiniteTexcoord { index } => {
                write!(f, "texture coordinate {index} is NaN or infinite")
            }
            MeshError::Texture { path, error } => write!(f, "texture {}: {error}", path.display()),
            MeshError::IndexOutOfRange { triangle } => write!(
                f,
                "triangle {triangle} refers to a vertex, normal or material that does not exist"
            ),
            MeshError::InvalidMaterial { name, reason } => {
                write!(f, "material {name:?}: {reason}")
            }
            MeshError::TooMany => write!(f, "the mesh has more than 2^32 - 1 elements of a kind"),
        }
    }
}

impl std::error::Error for MeshError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            MeshError::Io { error, .. } => Some(error),
            MeshError::Texture { error, .. } => Some(error),
            _ => None,
        }
    }
}

/// A valid triangle mesh (see the module docs for what valid means).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    texcoords: Vec<Vec2>,
    triangles: Vec<Triangle>,
    materials: Vec<Material>,
    /// Emitted radiance `L_e` of each material (W / (sr m²), MTL `Ke`): zero for most.
    emission: Vec<Vec3>,
    /// Each material's texture maps, indices into `textures`.
    maps: Vec<Maps>,
    /// Each material's specular part (mirror, glass), followed by paths ([`crate::specular`]).
    specular: Vec<Specular>,
    textures: Vec<Texture>,
    degenerate_skipped: usize,
    unhonoured: Vec<Unhonoured>,
}

/// A material's texture maps: indices into a mesh's textures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Maps {
    /// MTL `map_Kd`, multiplying `Kd`.
    diffuse: Option<u32>,
    /// MTL `map_Ks`, multiplying a Phong material's `Ks`.
    specular: Option<u32>,
    /// MTL `map_d`, the coverage that cuts holes ([`Mesh::covers`]).
    coverage: Option<u32>,
}

impl Maps {
    /// The same maps in a mesh whose textures start `by` further on.
    fn offset(self, by: u32) -> Maps {
        let shift = |i: Option<u32>| i.map(|i| i + by);
        Maps {
            diffuse: shift(self.diffuse),
            specular: shift(self.specular),
            coverage: shift(self.coverage),
        }
    }
}

/// The coverage (MTL `map_d`) under which a surface is a hole: ½, the alpha test of real-time
/// renderers' cut-outs (leaves, fences, grilles); coverage is not blended.
pub const COVERAGE_CUTOFF: f32 = 0.5;

impl Mesh {
    /// Checks and assembles a mesh; zero-area triangles are dropped and counted. Triangles
    /// must not name texture coordinates (see [`with_texcoords`](Self::with_texcoords)).
    pub fn new(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        triangles: Vec<Triangle>,
        materials: Vec<Material>,
    ) -> Result<Mesh, MeshError> {
        Mesh::with_texcoords(positions, normals, Vec::new(), triangles, materials)
    }

    /// [`new`](Self::new) with texture coordinates `texcoords` for the triangles to name.
    ///
    /// ```
    /// use lgh_core::glam::{Vec2, Vec3};
    /// use lgh_vpl::{Mesh, Triangle, DEFAULT_MATERIAL};
    ///
    /// let corners = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    /// let uv = vec![Vec2::ZERO, Vec2::X, Vec2::Y];
    /// let t = Triangle { vertices: [0, 1, 2], normals: None, texcoords: Some([0, 1, 2]), material: 0 };
    /// let mesh = Mesh::with_texcoords(corners, vec![], uv, vec![t], vec![DEFAULT_MATERIAL])?;
    /// assert_eq!(mesh.texcoord(0, 0.25, 0.5), Some(Vec2::new(0.25, 0.5)));
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    pub fn with_texcoords(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        texcoords: Vec<Vec2>,
        triangles: Vec<Triangle>,
        materials: Vec<Material>,
    ) -> Result<Mesh, MeshError> {
        let limit = u32::MAX as usize;
        if [
            positions.len(),
            normals.len(),
            texcoords.len(),
            triangles.len(),
            materials.len(),
        ]
        .iter()
        .any(|&n| n > limit)
        {
            return Err(MeshError::TooMany);
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFiniteVertex { index });
        }
        if let Some(index) = normals.iter().position(|n| !n.is_finite()) {
            return Err(MeshError::NonFiniteNormal { index });
        }
        if let Some(index) = texcoords.iter().position(|t| !t.is_finite()) {
            return Err(MeshError::NonFiniteTexcoord { index });
        }
        for (i, m) in materials.iter().enumerate() {
            check_material(m).map_err(|reason| MeshError::InvalidMaterial {
                name: format!("#{i}"),
                reason,
            })?;
        }
        let in_range = |t: &Triangle| {
            t.vertices.iter().all(|&v| (v as usize) < positions.len())
                && t.normals
                    .is_none_or(|n| n.iter().all(|&v| (v as usize) < normals.len()))
                && t.texcoords
                    .is_none_or(|n| n.iter().all(|&v| (v as usize) < texcoords.len()))
                && (t.material as usize) < materials.len()
        };
        if let Some(triangle) = triangles.iter().position(|t| !in_range(t)) {
            return Err(MeshError::IndexOutOfRange { triangle });
        }
        let total = triangles.len();
        let triangles: Vec<Triangle> = triangles
            .into_iter()
            .filter(|t| face_normal(t.vertices.map(|v| positions[v as usize])) != Vec3::ZERO)
            .collect();
        let degenerate_skipped = total - triangles.len();
        if triangles.is_empty() {
            return Err(MeshError::NoTriangles {
                degenerate: degenerate_skipped,
            });
        }
        let emission = vec![Vec3::ZERO; materials.len()];
        let maps = vec![Maps::default(); materials.len()];
        let specular = vec![Specular::None; materials.len()];
        Ok(Mesh {
            positions,
            normals,
            texcoords,
            triangles,
            materials,
            emission,
            maps,
            specular,
            textures: Vec::new(),
            degenerate_skipped,
            unhonoured: Vec::new(),
        })
    }

    /// The quad `corners[0..4]` (in order around its edge, counter-clockwise seen from the front)
    /// as two triangles sharing the diagonal `corners[0]`–`corners[2]`, with face normals.
    pub fn quad(corners: [Vec3; 4], material: Material) -> Result<Mesh, MeshError> {
        Mesh::new(
            corners.to_vec(),
            Vec::new(),
            vec![flat([0, 1, 2], 0), flat([0, 2, 3], 0)],
            vec![material],
        )
    }

    /// The axis-aligned box `lo..hi` as twelve triangles with outward face normals.
    pub fn cuboid(lo: Vec3, hi: Vec3, material: Material) -> Result<Mesh, MeshError> {
        // Corner i has x from bit 0, y from bit 1, z from bit 2.
        let positions = (0..8)
            .map(|i: u32| Vec3::select(glam_mask(i), hi, lo))
            .collect();
        // Each face counter-clockwise seen from outside.
        const FACES: [[u32; 4]; 6] = [
            [0, 4, 6, 2], // −x
            [1, 3, 7, 5], // +x
            [0, 1, 5, 4], // −y
            [2, 6, 7, 3], // +y
            [0, 2, 3, 1], // −z
            [4, 5, 7, 6], // +z
        ];
        let triangles = FACES
            .iter()
            .flat_map(|&[a, b, c, d]| [flat([a, b, c], 0), flat([a, c, d], 0)])
            .collect();
        Mesh::new(positions, Vec::new(), triangles, vec![material])
    }

    /// Adds `other`'s positions, normals, triangles and materials to this mesh. Materials are not
    /// deduplicated: one that both meshes have is listed twice.
    pub fn append(&mut self, other: Mesh) -> Result<(), MeshError> {
        let counts = [
            self.positions.len() + other.positions.len(),
            self.normals.len() + other.normals.len(),
            self.texcoords.len() + other.texcoords.len(),
            self.triangles.len() + other.triangles.len(),
            self.materials.len() + other.materials.len(),
            self.textures.len() + other.textures.len(),
        ];
        if counts.iter().any(|&n| n > u32::MAX as usize) {
            return Err(MeshError::TooMany);
        }
        let (p, n, uv, m, tex) = (
            self.positions.len() as u32,
            self.normals.len() as u32,
            self.texcoords.len() as u32,
            self.materials.len() as u32,
            self.textures.len() as u32,
        );
        self.triangles
            .extend(other.triangles.iter().map(|t| Triangle {
                vertices: t.vertices.map(|v| v + p),
                normals: t.normals.map(|ns| ns.map(|v| v + n)),
                texcoords: t.texcoords.map(|ts| ts.map(|v| v + uv)),
                material: t.material + m,
            }));
        self.positions.extend(other.positions);
        self.normals.extend(other.normals);
        self.texcoords.extend(other.texcoords);
        self.materials.extend(other.materials);
        self.emission.extend(other.emission);
        self.maps.extend(other.maps.iter().map(|m| m.offset(tex)));
        self.specular.extend(other.specular);
        self.textures.extend(other.textures);
        self.degenerate_skipped += other.degenerate_skipped;
        self.unhonoured.extend(other.unhonoured);
        Ok(())
    }

    /// Makes material `material` emit radiance `radiance` (W / (sr m²)) from the front of its
    /// faces, as MTL's `Ke`: its triangles become area lights (`crate::primary`).
    ///
    /// Errors: [`MeshError::InvalidMaterial`] for a material the mesh does not have, or a
    /// negative or non-finite radiance.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::Material;
    /// use lgh_vpl::Mesh;
    ///
    /// let white = Material::Lambert { albedo: Vec3::splat(0.8) };
    /// let corners = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z];
    /// let mut lamp = Mesh::quad(corners, white)?;
    /// lamp.set_emission(0, Vec3::splat(5.0))?;
    /// assert_eq!(lamp.emission(0), Vec3::splat(5.0));
    /// assert!(lamp.set_emission(0, Vec3::new(1.0, -1.0, 0.0)).is_err());
    /// assert!(lamp.set_emission(1, Vec3::ONE).is_err()); // one material only
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    pub fn set_emission(&mut self, material: u32, radiance: Vec3) -> Result<(), MeshError> {
        if !(radiance.is_finite() && radiance.min_element() >= 0.0) {
            return Err(MeshError::InvalidMaterial {
                name: format!("#{material}"),
                reason: "emission must be finite and not negative",
            });
        }
        let slot = self
            .emission
            .get_mut(material as usize)
            .ok_or(MeshError::InvalidMaterial {
                name: format!("#{material}"),
                reason: "the mesh has no such material",
            })?;
        *slot = radiance;
        Ok(())
    }

    /// Gives material `material` the diffuse texture `texture` (MTL `map_Kd`): its `Kd` is
    /// multiplied by the texture's colour wherever a triangle has texture coordinates
    /// ([`material_at`](Self::material_at)).
    ///
    /// Errors: [`MeshError::InvalidMaterial`] for a material the mesh does not have.
    ///
    /// ```
    /// use lgh_core::glam::{Vec2, Vec3};
    /// use lgh_core::Material;
    /// use lgh_vpl::texture::Texture;
    /// use lgh_vpl::{Mesh, Triangle};
    ///
    /// let white = Material::Lambert { albedo: Vec3::splat(0.8) };
    /// let t = Triangle { vertices: [0, 1, 2], normals: None, texcoords: Some([0, 1, 2]), material: 0 };
    /// let uv = vec![Vec2::ZERO, Vec2::X, Vec2::Y];
    /// let mut mesh = Mesh::with_texcoords(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![], uv, vec![t], vec![white])?;
    /// // A one-texel texture: red everywhere.
    /// mesh.set_diffuse_texture(0, Texture::from_linear(1, 1, vec![Vec3::new(1.0, 0.0, 0.0)]).unwrap())?;
    /// assert_eq!(mesh.material_at(0, 0.2, 0.2), Material::Lambert { albedo: Vec3::new(0.8, 0.0, 0.0) });
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    pub fn set_diffuse_texture(
        &mut self,
        material: u32,
        texture: Texture,
    ) -> Result<(), MeshError> {
        let index = self.add_texture_for(material, texture)?;
        self.use_texture(material, index);
        Ok(())
    }

    /// Adds `texture` for material `material`, which must exist: its index.
    fn add_texture_for(&mut self, material: u32, texture: Texture) -> Result<u32, MeshError> {
        if material as usize >= self.materials.len() {
            return Err(MeshError::InvalidMaterial {
                name: format!("#{material}"),
                reason: "the mesh has no such material",
            });
        }
        self.add_texture(texture)
    }

    /// Adds `texture` for materials to share ([`use_texture`](Self::use_texture)): its index.
    pub(crate) fn add_texture(&mut self, texture: Texture) -> Result<u32, MeshError> {
        let index = u32::try_from(self.textures.len()).map_err(|_| MeshError::TooMany)?;
        self.textures.push(texture);
        Ok(index)
    }

    /// Makes texture `index` material `material`'s diffuse texture (both must exist).
    pub(crate) fn use_texture(&mut self, material: u32, index: u32) {
        self.maps[material as usize].diffuse = Some(index);
    }

    /// Makes texture `index` material `material`'s specular texture (both must exist).
    pub(crate) fn use_specular_texture(&mut self, material: u32, index: u32) {
        self.maps[material as usize].specular = Some(index);
    }

    /// The specular texture of material `material` (MTL `map_Ks`), if it has one: it
    /// multiplies a Phong material's `Ks` where a triangle has texture coordinates.
    #[must_use]
    pub fn specular_texture(&self, material: u32) -> Option<&Texture> {
        let index = self.maps.get(material as usize)?.specular?;
        self.textures.get(index as usize)
    }

    /// Makes texture `index` material `material`'s coverage map (MTL `map_d`; both must
    /// exist).
    pub(crate) fn use_coverage_texture(&mut self, material: u32, index: u32) {
        self.maps[material as usize].coverage = Some(index);
    }

    /// Gives material `material` a coverage map (MTL `map_d`, decoded with
    /// [`Texture::decode_coverage`]): where a triangle of it has texture coordinates and the
    /// map's coverage there is under [`COVERAGE_CUTOFF`], the triangle is not there — rays pass
    /// through it ([`covers`](Self::covers)).
    ///
    /// Errors: [`MeshError::InvalidMaterial`] for a material the mesh does not have.
    ///
    /// ```
    /// use lgh_core::glam::{Vec2, Vec3};
    /// use lgh_vpl::texture::Texture;
    /// use lgh_vpl::{Mesh, Triangle, DEFAULT_MATERIAL};
    ///
    /// let t = Triangle { vertices: [0, 1, 2], normals: None, texcoords: Some([0, 1, 2]), material: 0 };
    /// let uv = vec![Vec2::ZERO, Vec2::X, Vec2::Y];
    /// let mut mesh = Mesh::with_texcoords(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![], uv, vec![t], vec![DEFAULT_MATERIAL])?;
    /// assert!(mesh.covers(0, 0.2, 0.2) && !mesh.has_coverage());
    /// // Two texels: a hole on the left (u < 1/2), solid on the right.
    /// mesh.set_coverage_texture(0, Texture::from_linear(2, 1, vec![Vec3::ZERO, Vec3::ONE]).unwrap())?;
    /// assert!(mesh.has_coverage());
    /// assert!(!mesh.covers(0, 0.1, 0.1)); // u = 0.1: the hole
    /// assert!(mesh.covers(0, 0.8, 0.1)); // u = 0.8: solid
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    pub fn set_coverage_texture(
        &mut self,
        material: u32,
        texture: Texture,
    ) -> Result<(), MeshError> {
        let index = self.add_texture_for(material, texture)?;
        self.use_coverage_texture(material, index);
        Ok(())
    }

    /// Whether any material has a coverage map ([`set_coverage_texture`](Self::set_coverage_texture)).
    #[must_use]
    pub fn has_coverage(&self) -> bool {
        self.maps.iter().any(|m| m.coverage.is_some())
    }

    /// Whether triangle `t` is there at barycentric `(u, v)`: false only where its material's
    /// coverage map (MTL `map_d`), read at the triangle's texture coordinates, is under
    /// [`COVERAGE_CUTOFF`]; true without a map or without texture coordinates.
    #[must_use]
    pub fn covers(&self, t: u32, u: f32, v: f32) -> bool {
        let material = self.triangles[t as usize].material as usize;
        let Some(index) = self.maps.get(material).and_then(|m| m.coverage) else {
            return true;
        };
        let (Some(map), Some(uv)) = (self.textures.get(index as usize), self.texcoord(t, u, v))
        else {
            return true;
        };
        map.sample(uv).x >= COVERAGE_CUTOFF
    }

    /// Replaces material `material` by `with` (checked by the caller).
    pub(crate) fn set_material(&mut self, material: u32, with: Material) {
        self.materials[material as usize] = with;
    }

    /// The diffuse texture of material `material`, if it has one.
    #[must_use]
    pub fn diffuse_texture(&self, material: u32) -> Option<&Texture> {
        let index = self.maps.get(material as usize)?.diffuse?;
        self.textures.get(index as usize)
    }

    /// The material at barycentric `(u, v)` of triangle `t`: its material, with `Kd` (Lambert
    /// albedo, Phong `k_d`) multiplied by the diffuse texture's bilinear colour at the point's
    /// texture coordinates, and a Phong `k_s` by the specular texture's, where the material has
    /// them and the triangle has texture coordinates; otherwise [`material`](Self::material).
    #[must_use]
    pub fn material_at(&self, t: u32, u: f32, v: f32) -> Material {
        let material = self.material(t);
        let index = self.triangles[t as usize].material;
        let diffuse = self.diffuse_texture(index);
        let specular = self.specular_texture(index);
        if diffuse.is_none() && specular.is_none() {
            return material;
        }
        let Some(uv) = self.texcoord(t, u, v) else {
            return material;
        };
        let at = |texture: Option<&Texture>| texture.map_or(Vec3::ONE, |t| t.sample(uv));
        match material {
            Material::Lambert { albedo } => Material::Lambert {
                albedo: albedo * at(diffuse),
            },
            Material::Phong { kd, ks, exponent } => Material::Phong {
                kd: kd * at(diffuse),
                ks: ks * at(specular),
                exponent,
            },
            Material::Isotropic => Material::Isotropic,
        }
    }

    /// The texture coordinates at barycentric `(u, v)` of triangle `t`, if it has them: its
    /// corners' interpolated.
    #[must_use]
    pub fn texcoord(&self, t: u32, u: f32, v: f32) -> Option<Vec2> {
        let [a, b, c] = self.triangles[t as usize].texcoords?;
        let at = |i: u32| self.texcoords[i as usize];
        Some(at(a) * (1.0 - u - v) + at(b) * u + at(c) * v)
    }

    /// Texture coordinates.
    #[must_use]
    pub fn texcoords(&self) -> &[Vec2] {
        &self.texcoords
    }

    /// What the files this mesh was read from ask for and the renderer does not honour, each
    /// statement once at its first use ([`crate::statements`]); empty for meshes built in code.
    #[must_use]
    pub fn unhonoured(&self) -> &[Unhonoured] {
        &self.unhonoured
    }

    /// Records what the mesh's files ask for and is not honoured.
    pub(crate) fn set_unhonoured(&mut self, unhonoured: Vec<Unhonoured>) {
        self.unhonoured = unhonoured;
    }

    /// Gives material `material` the specular part `specular` (a mirror, glass), which camera
    /// and light paths follow ([`crate::specular`]); a [`Specular::Dielectric`] is shaded by
    /// its specular part alone.
    ///
    /// Errors: [`MeshError::InvalidMaterial`] for a material the mesh does not have, or a
    /// specular part [`Specular::check`] refuses.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::specular::Specular;
    /// use lgh_vpl::{Mesh, DEFAULT_MATERIAL};
    ///
    /// let mut glass = Mesh::cuboid(Vec3::ZERO, Vec3::ONE, DEFAULT_MATERIAL)?;
    /// let clear = Specular::Dielectric { ior: 1.5, transmittance: Vec3::ONE };
    /// glass.set_specular(0, clear)?;
    /// assert_eq!(glass.specular(0), clear);
    /// assert!(glass.set_specular(0, Specular::Dielectric { ior: 0.0, transmittance: Vec3::ONE }).is_err());
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    pub fn set_specular(&mut self, material: u32, specular: Specular) -> Result<(), MeshError> {
        let invalid = |reason| MeshError::InvalidMaterial {
            name: format!("#{material}"),
            reason,
        };
        specular.check().map_err(invalid)?;
        let slot = self
            .specular
            .get_mut(material as usize)
            .ok_or(invalid("the mesh has no such material"))?;
        *slot = specular;
        Ok(())
    }

    /// The specular part of triangle `t`'s material ([`Specular::None`] for most).
    #[must_use]
    pub fn specular(&self, t: u32) -> Specular {
        self.specular_of(self.triangles[t as usize].material)
    }

    /// The specular part of material `material` (panics if it is out of range).
    #[must_use]
    pub fn specular_of(&self, material: u32) -> Specular {
        self.specular[material as usize]
    }

    /// Radiance emitted by triangle `t` (its material's `Ke`; zero for most).
    #[must_use]
    pub fn emission(&self, t: u32) -> Vec3 {
        self.emission[self.triangles[t as usize].material as usize]
    }

    /// Area of triangle `t`.
    #[must_use]
    pub fn area(&self, t: u32) -> f32 {
        let [a, b, c] = self.corners(t);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Vertex positions.
    #[must_use]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Vertex normals (as given; not necessarily unit length).
    #[must_use]
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// The triangles, none of zero area.
    #[must_use]
    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// The materials.
    #[must_use]
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Zero-area triangles dropped when the mesh was built (summed over [`append`](Self::append)).
    #[must_use]
    pub fn degenerate_skipped(&self) -> usize {
        self.degenerate_skipped
    }

    /// The three corners of triangle `t` (panics if `t` is out of range).
    #[must_use]
    pub fn corners(&self, t: u32) -> [Vec3; 3] {
        self.triangles[t as usize]
            .vertices
            .map(|v| self.positions[v as usize])
    }

    /// The material of triangle `t` (panics if `t` is out of range).
    #[must_use]
    pub fn material(&self, t: u32) -> Material {
        self.materials[self.triangles[t as usize].material as usize]
    }

    /// The unit face normal of triangle `t`, on the side its corners turn counter-clockwise.
    #[must_use]
    pub fn face_normal(&self, t: u32) -> Vec3 {
        face_normal(self.corners(t))
    }

    /// The unit shading normal of triangle `t` at barycentric `(u, v)` (the weights of corners 1
    /// and 2): the interpolated vertex normals, or the face normal where the triangle has none or
    /// they interpolate to zero. Not oriented: the renderer turns it towards the viewer.
    #[must_use]
    pub fn shading_normal(&self, t: u32, u: f32, v: f32) -> Vec3 {
        let Some([a, b, c]) = self.triangles[t as usize].normals else {
            return self.face_normal(t);
        };
        let n = self.normals[a as usize] * (1.0 - u - v)
            + self.normals[b as usize] * u
            + self.normals[c as usize] * v;
        let n = unit_or_zero(n);
        if n == Vec3::ZERO {
            self.face_normal(t)
        } else {
            n
        }
    }

    /// The point at barycentric `(u, v)` of triangle `t` (the weights of corners 1 and 2).
    #[must_use]
    pub fn point(&self, t: u32, u: f32, v: f32) -> Vec3 {
        let [a, b, c] = self.corners(t);
        a * (1.0 - u - v) + b * u + c * v
    }

    /// The point of triangle `t` at `(s, r)` of the unit square, mapped so that uniform `(s, r)`
    /// give points uniform in area (`u = √s (1 − r)`, `v = √s r`): how light paths leave an
    /// area light and how its direct light is sampled.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::{Mesh, DEFAULT_MATERIAL};
    ///
    /// // A unit square; its triangle 0 has corners 0, x and x + y.
    /// let square = Mesh::quad([Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y], DEFAULT_MATERIAL)?;
    /// assert_eq!(square.sample_point(0, 0.0, 0.5), Vec3::ZERO); // s = 0: corner 0
    /// assert_eq!(square.sample_point(0, 1.0, 0.0), Vec3::X); // s = 1, r = 0: corner 1
    /// assert_eq!(square.sample_point(0, 1.0, 1.0), Vec3::X + Vec3::Y); // corner 2
    /// # Ok::<(), lgh_vpl::MeshError>(())
    /// ```
    #[must_use]
    pub fn sample_point(&self, t: u32, s: f32, r: f32) -> Vec3 {
        let su = s.sqrt();
        self.point(t, su * (1.0 - r), su * r)
    }

    /// The bounding box `(lo, hi)` of the vertices the triangles use.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.triangles
            .iter()
            .flat_map(|t| t.vertices)
            .map(|v| self.positions[v as usize])
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p), hi.max(p))
            })
    }
}

/// A triangle with face normals only.
fn flat(vertices: [u32; 3], material: u32) -> Triangle {
    Triangle {
        vertices,
        normals: None,
        texcoords: None,
        material,
    }
}

/// The mask selecting `hi` on the axes whose bit is set in `i`.
fn glam_mask(i: u32) -> lgh_core::glam::BVec3 {
    lgh_core::glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0)
}

/// The unit normal of a triangle, or zero if the cross product of its edges is zero (no area in
/// f32) or an edge is not finite. Each edge is scaled to a largest component of 1 first, so the
/// cross product of a huge triangle cannot overflow nor that of a tiny one underflow.
fn face_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    let scaled = |e: Vec3| e / e.abs().max_element();
    unit_or_zero(scaled(b - a).cross(scaled(c - a)))
}

/// `v` at unit length, or zero if `v` is zero or not finite. `v` is divided by its largest
/// component first, so its squared length can neither overflow nor underflow.
fn unit_or_zero(v: Vec3) -> Vec3 {
    // A zero `v` becomes NaN here, which `normalize_or_zero` turns into zero.
    (v / v.abs().max_element()).normalize_or_zero()
}
/// Why `m` cannot be a surface material, if it cannot.
pub(crate) fn check_material(m: &Material) -> Result<(), &'static str> {
    let colour = |c: Vec3| c.is_finite() && c.min_element() >= 0.0;
    match *m {
        Material::Isotropic => Err("a phase function is not a surface material"),
        Material::Lambert { albedo } if !colour(albedo) => {
            Err("the albedo must be finite and non-negative")
        }
        Material::Phong { kd, ks, .. } if !colour(kd) || !colour(ks) => {
            Err("Kd and Ks must be finite and non-negative")
        }
        Material::Phong { exponent, .. } => check_exponent(exponent),
        _ => Ok(()),
    }
}

/// Why `exponent` cannot be a Phong exponent, if it cannot.
pub(crate) fn check_exponent(exponent: f32) -> Result<(), &'static str> {
    if exponent.is_finite() && exponent >= 0.0 {
        Ok(())
    } else {
        Err("the Phong exponent Ns must be finite and non-negative")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GREY: Material = Material::Lambert {
        albedo: Vec3::splat(0.7),
    };

    #[test]
    fn cuboid_faces_point_outwards_and_quads_follow_their_winding() {
        let (lo, hi) = (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.0, 4.0));
        let m = Mesh::cuboid(lo, hi, GREY).unwrap();
        assert_eq!(m.triangles().len(), 12);
        assert_eq!(m.bounds(), (lo, hi));
        let centre = 0.5 * (lo + hi);
        for t in 0..12 {
            let [a, b, c] = m.corners(t);
            let n = m.face_normal(t);
            // Unit, axis-aligned, pointing away from the centre.
            assert_eq!(n.abs().max_element(), 1.0, "{n}");
            assert!(n.dot((a + b + c) / 3.0 - centre) > 0.0, "triangle {t}: {n}");
            assert_eq!(m.shading_normal(t, 0.2, 0.3), n);
        }
        let q = Mesh::quad(
            [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            GREY,
        )
        .unwrap();
        assert_eq!(q.triangles().len(), 2);
        assert!((0..2).all(|t| q.face_normal(t) == Vec3::Z));
        assert_eq!(q.point(0, 1.0, 0.0), Vec3::X);
    }

    #[test]
    fn append_keeps_each_triangle_with_its_own_material() {
        let red = Material::Lambert {
            albedo: Vec3::new(0.8, 0.1, 0.1),
        };
        let mut m = Mesh::cuboid(Vec3::ZERO, Vec3::ONE, GREY).unwrap();
        let floor = Mesh::quad(
            [Vec3::ZERO, Vec3::Z, Vec3::new(1.0, 0.0, 1.0), Vec3::X].map(|p| p * 4.0),
            red,
        )
        .unwrap();
        m.append(floor.clone()).unwrap();
        assert_eq!(m.triangles().len(), 14);
        assert_eq!(m.materials(), &[GREY, red]);
        assert_eq!(m.material(11), GREY);
        assert_eq!(m.material(12), red);
        assert_eq!(m.corners(13), floor.corners(1));
    }

    #[test]
    fn invalid_meshes_are_errors_and_zero_area_triangles_are_skipped() {
        let tri = |vertices, material| Triangle {
            vertices,
            normals: None,
            texcoords: None,
            material,
        };
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(2.0, 0.0, 0.0)];
        // Triangle 1 is a sliver of zero area (collinear corners).
        let m = Mesh::new(
            p.clone(),
            vec![],
            vec![tri([0, 1, 2], 0), tri([0, 1, 3], 0)],
            vec![GREY],
        )
        .unwrap();
        assert_eq!((m.triangles().len(), m.degenerate_skipped()), (1, 1));
        let new = |p: Vec<Vec3>, n: Vec<Vec3>, t: Triangle, m: Material| {
            Mesh::new(p, n, vec![t], vec![m])
        };
        let ok = tri([0, 1, 2], 0);
        assert!(matches!(
            new(p.clone(), vec![], tri([0, 1, 3], 0), GREY),
            Err(MeshError::NoTriangles { degenerate: 1 })
        ));
        let mut bad = p.clone();
        bad[2].y = f32::NAN;
        assert!(matches!(
            new(bad, vec![], ok, GREY),
            Err(MeshError::NonFiniteVertex { index: 2 })
        ));
        let with_normals = Triangle {
            normals: Some([0, 0, 1]),
            ..ok
        };
        assert!(matches!(
            new(p.clone(), vec![Vec3::Z, Vec3::INFINITY], with_normals, GREY),
            Err(MeshError::NonFiniteNormal { index: 1 })
        ));
        for t in [tri([0, 1, 4], 0), tri([0, 1, 2], 1), with_normals] {
            assert!(
                matches!(
                    new(p.clone(), vec![Vec3::Z], t, GREY),
                    Err(MeshError::IndexOutOfRange { triangle: 0 })
                ),
                "{t:?}"
            );
        }
        let phong = |kd: f32, ks: f32, exponent: f32| Material::Phong {
            kd: Vec3::splat(kd),
            ks: Vec3::splat(ks),
            exponent,
        };
        for m in [
            Material::Isotropic,
            Material::Lambert {
                albedo: Vec3::new(0.5, -0.1, 0.5),
            },
            Material::Lambert {
                albedo: Vec3::splat(f32::NAN),
            },
            phong(-1.0, 0.5, 10.0),
            phong(0.5, f32::INFINITY, 10.0),
            phong(0.5, 0.5, -1.0),
            phong(0.5, 0.5, f32::NAN),
        ] {
            assert!(
                matches!(
                    new(p.clone(), vec![], ok, m),
                    Err(MeshError::InvalidMaterial { .. })
                ),
                "{m:?}"
            );
        }
        for e in [
            Mesh::quad([Vec3::ZERO; 4], GREY).unwrap_err(),
            Mesh::cuboid(Vec3::ZERO, Vec3::splat(f32::NAN), GREY).unwrap_err(),
        ] {
            assert!(!e.to_string().is_empty());
        }
    }

    #[test]
    fn huge_and_tiny_triangles_and_normals_are_kept_and_normalised() {
        // Edges of 1e20: the cross product (1e40) overflows f32; of 1e-20, its square underflows.
        for size in [1e20f32, 1e-20] {
            let big = Vec3::new(size, 0.0, size);
            let m = Mesh::new(
                vec![Vec3::ZERO, Vec3::X * size, Vec3::Y * size],
                vec![big],
                vec![Triangle {
                    vertices: [0, 1, 2],
                    normals: Some([0, 0, 0]),
                    texcoords: None,
                    material: 0,
                }],
                vec![GREY],
            )
            .unwrap();
            assert_eq!(m.face_normal(0), Vec3::Z, "{size}");
            let n = m.shading_normal(0, 0.3, 0.3);
            assert!(
                (n - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6,
                "{size}: {n}"
            );
        }
    }
}
