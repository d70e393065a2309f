//! # lgh-vpl — surfaces lit by many lights
//!
//! What is here today is the surface half of the crate: triangle meshes with Lambert and Phong
//! materials, vertex normals and diffuse textures ([`texture`]), built in code or read from
//! OBJ + MTL ([`mesh`], [`obj`]; what a file asks for and is not rendered is listed,
//! [`statements`]), with mirrors and glass that camera and light paths follow ([`specular`]); our own triangle BVH with
//! closest-hit and any-hit queries ([`bvh`]), a mesh with its BVH and the surface point a
//! camera ray sees ([`scene`]); a pinhole [`Camera`] (lgh-image's
//! [`Pinhole`](lgh_image::camera::Pinhole), shared with the volume renderer); and a renderer that
//! shades the surface each pixel sees through any [`lgh_core::ManyLights`] backend — the lighting
//! grid hierarchy, brute force, or the error-bounded ones — with Paquette et al.'s Phong model
//! eq. (1) and, as in that paper, no occlusion between lights and surfaces
//! ([`render`](mod@render)); [`paquette`] rebuilds that paper's three test scenes and its
//! Tables 2 and 3.
//!
//! The primary lights of a scene — emissive faces (MTL `Ke`) as area lights, or point, spot and
//! sun lights given on the command line — are [`primary`], and their direct light with shadow
//! rays (area lights through a stratified pattern fixed per surface point) is [`direct`], with
//! the energy-conserving Lambert and Phong reflection of every GI path in [`brdf`]; the
//! virtual point lights traced from them, deterministic and energy-conserving, are [`vpl`];
//! [`indirect`] shades them at surface points through any backend — the hierarchy, brute force
//! over every VPL (the exact answer of the same model) or Lightcuts — with shadow rays through
//! the BVH, restored cosine lobes and the singularity clamp. [`gi`] puts them together:
//! [`GiScene`] traces a mesh's VPLs once and renders them through any [`GiMethod`] (the
//! pipeline of `lgh gi`). [`reference`](mod@reference) is an independent check on the VPL model
//! itself: one-bounce path tracing.
//!
//! The paper shades a coarse light as an isotropic point with Gaussian shadow samples
//! (Fig. 11d); on surfaces that loses the VPLs' cosine lobes and puts samples inside walls, and
//! errs by tens of percent. Beyond the paper, [`representatives`] shades each coarse light
//! through a few of the VPLs it stands for, drawn once per light in proportion to what they
//! carry, as many at each point as the light brings there ([`indirect::Coarse::Adaptive`]),
//! leaving out the lights whose every VPL faces away from the point ([`facing`]):
//! 2.3–2.7% at α = 4 and 0.4% at α = 16 on the Cornell box and Sponza with 365K VPLs, at 112×
//! and 57× brute force at α = 4 (`docs/gi.md`). [`indirect::NormalBuckets`]
//! (one hierarchy per dominant normal axis) is the other orientation-aware option.
//!
//! ```
//! use lgh_core::glam::Vec3;
//! use lgh_core::{BruteForce, Material, PointLight};
//! use lgh_vpl::{render, Camera, Mesh, Scene};
//!
//! // A grey floor and a red box on it, lit by two lights.
//! let grey = Material::Lambert { albedo: Vec3::splat(0.6) };
//! let red = Material::Phong { kd: Vec3::new(0.6, 0.1, 0.1), ks: Vec3::splat(0.3), exponent: 40.0 };
//! let mut mesh = Mesh::quad(
//!     [Vec3::new(-4.0, 0.0, 4.0), Vec3::new(4.0, 0.0, 4.0), Vec3::new(4.0, 0.0, -4.0), Vec3::new(-4.0, 0.0, -4.0)],
//!     grey,
//! )?;
//! mesh.append(Mesh::cuboid(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 1.5, 1.0), red)?)?;
//! let scene = Scene::new(mesh);
//!
//! let lights = [
//!     PointLight::new(Vec3::new(2.0, 3.0, 2.0), Vec3::splat(10.0)),
//!     PointLight::new(Vec3::new(-3.0, 2.0, 1.0), Vec3::new(4.0, 4.0, 8.0)),
//! ];
//! let backend = BruteForce::new(&lights)?;
//! let camera = Camera::new(Vec3::new(0.0, 4.0, 8.0), Vec3::ZERO, Vec3::Y, 45.0, 64, 48)?;
//! let rendered = render(&scene, &camera, &backend, |_rows| {})?;
//! assert!(rendered.pixels_shaded > 0);
//! assert_eq!(rendered.mean_lights(), 2.0);
//! // rendered.image is linear RGB: write it with lgh_image::write_exr / write_png.
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// No unsafe code but the one cache hint of `prefetch`, which allows itself.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod brdf;
pub mod bvh;
pub mod direct;
pub mod facing;
pub mod gi;
pub mod indirect;
pub mod mesh;
pub mod obj;
pub mod paquette;
mod prefetch;
pub mod primary;
pub mod reference;
pub mod render;
pub mod representatives;
pub mod scene;
pub mod specular;
pub mod statements;
pub mod texture;
pub mod vpl;

pub use bvh::{Bvh, Hit, Ray};
pub use gi::{GiError, GiMethod, GiScene, GiSettings};
pub use lgh_core;
pub use lgh_image::camera::{CameraError, Pinhole as Camera};
pub use mesh::{Mesh, MeshError, Triangle, DEFAULT_MATERIAL, MAX_LINE_BYTES};
pub use obj::{MissingTextures, Normals, ObjOptions};
pub use render::{render, render_with_shader, RenderError, Rendered};
pub use scene::Scene;
pub use statements::Unhonoured;
pub use texture::Texture;
