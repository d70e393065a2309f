//! The three test scenes of Paquette, Poulin & Drettakis (1998, `papers/004_…`, §5.1, Fig. 7),
//! rebuilt procedurally, and the paper's Tables 2 and 3 to compare with.
//!
//! - **Light Strings**: eight strings of lights sagging along a street between two façades; the
//!   camera stands in the street and looks down it.
//! - **U de M**: lights along the strokes of the letters "U de M", lying flat half a metre above
//!   a plane; the camera looks down at the plane.
//! - **Cluster**: lights almost uniform in a small cube (independent uniform positions) in a
//!   room; the camera stands just behind the cube, so the lights (invisible, as in the paper) are
//!   between it and the walls.
//!
//! The Light Strings lights are `lgh_core::scenes::light_strings`, which lgh-core builds always
//! (it is also lgh-core's benchmark set (c): `testsets::light_strings` re-exports it), so this
//! scene, `lgh bench core` and lgh-core's own tests and benches all measure one curve; its random
//! numbers (the Cluster scene) come from the production `lgh_core::random`.
//!
//! All lights of a scene are equal (§5.1), and their total intensity does not depend on their
//! number, so the images of 64 and 16384 lights look alike — the paper raises the count by
//! "increasing the density of the light sources". The totals (per scene, one for diffuse and one
//! for specular surfaces) were set once, from brute-force renders with 1024 lights, so that the
//! brightest 0.1 % of pixels sit near 0.85–0.9 of the range the 8-bit error measure maps to 255:
//! the threshold of 1 % then means what it means in the paper. A pure `n = 200` lobe reflects a
//! light only near its mirror direction, so the specular scenes need 11–26× brighter lights. The
//! diffuse surfaces are Lambertian; the specular ones are pure Phong lobes with `n = 200` (§5.1).

use std::fmt;
use std::str::FromStr;

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_core::scenes::light_strings;
use lgh_core::{Material, PointLight};

use crate::mesh::{Mesh, MeshError};
use crate::scene::Scene;
use lgh_image::camera::{CameraError, Pinhole as Camera};

/// The light counts of the paper's tables.
pub const LIGHT_COUNTS: [usize; 5] = [64, 256, 1024, 4096, 16384];

/// The paper's threshold: 1 % of the 8-bit range, (2.55, 2.55, 2.55) of 255, in the linear
/// radiance units where 1 maps to 255.
pub const PAPER_THRESHOLD: f32 = 0.01;

/// The Phong exponent of the paper's specular tests.
pub const SPECULAR_EXPONENT: f32 = 200.0;

/// The most lights a test scene accepts (4× the paper's largest).
pub const MAX_SCENE_LIGHTS: usize = 1 << 16;

/// Which of the paper's scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TestScene {
    /// "Light Strings" (Fig. 7a).
    Strings,
    /// "U de M" (Fig. 7b).
    Udem,
    /// "Cluster" (Fig. 7c).
    Cluster,
}

impl TestScene {
    /// All three, in the tables' order.
    pub const ALL: [TestScene; 3] = [TestScene::Strings, TestScene::Udem, TestScene::Cluster];

    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            TestScene::Strings => "strings",
            TestScene::Udem => "udem",
            TestScene::Cluster => "cluster",
        }
    }

    /// The paper's name.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            TestScene::Strings => "Light Strings",
            TestScene::Udem => "U de M",
            TestScene::Cluster => "Cluster",
        }
    }
}

impl FromStr for TestScene {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        TestScene::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| format!("unknown scene '{s}' (expected strings, udem or cluster)"))
    }
}

/// The surfaces' material.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// Lambertian (Table 2).
    Diffuse,
    /// Phong lobe with `n = 200`, no diffuse term (Table 3).
    Specular,
}

impl Surface {
    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Surface::Diffuse => "diffuse",
            Surface::Specular => "specular",
        }
    }

    /// The material of a surface of reflectance `k`.
    fn material(self, k: f32) -> Material {
        match self {
            Surface::Diffuse => Material::Lambert {
                albedo: Vec3::splat(k),
            },
            Surface::Specular => Material::Phong {
                kd: Vec3::ZERO,
                ks: Vec3::splat(k),
                exponent: SPECULAR_EXPONENT,
            },
        }
    }
}

impl FromStr for Surface {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "diffuse" => Ok(Surface::Diffuse),
            "specular" => Ok(Surface::Specular),
            _ => Err(format!(
                "unknown material '{s}' (expected diffuse or specular)"
            )),
        }
    }
}

/// Why a test scene could not be built.
#[derive(Debug)]
pub enum SceneError {
    /// No lights, or more than [`MAX_SCENE_LIGHTS`].
    LightCount(usize),
    /// The camera refused the image size.
    Camera(CameraError),
    /// The geometry could not be built (a bug if it happens).
    Mesh(MeshError),
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::LightCount(n) => write!(
                f,
                "a test scene needs 1 to {MAX_SCENE_LIGHTS} lights, not {n}"
            ),
            SceneError::Camera(e) => write!(f, "camera: {e}"),
            SceneError::Mesh(e) => write!(f, "scene geometry: {e}"),
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneError::LightCount(_) => None,
            SceneError::Camera(e) => Some(e),
            SceneError::Mesh(e) => Some(e),
        }
    }
}

impl From<MeshError> for SceneError {
    fn from(e: MeshError) -> Self {
        SceneError::Mesh(e)
    }
}

/// A built test scene: geometry, lights and camera.
#[derive(Clone, Debug)]
pub struct Built {
    /// The geometry and its BVH.
    pub scene: Scene,
    /// The lights, all equal.
    pub lights: Vec<PointLight>,
    /// The camera.
    pub camera: Camera,
}

/// A horizontal rectangle at height `y`, facing up.
fn floor(x: (f32, f32), z: (f32, f32), y: f32, m: Material) -> Result<Mesh, MeshError> {
    Mesh::quad(
        [
            Vec3::new(x.0, y, z.1),
            Vec3::new(x.1, y, z.1),
            Vec3::new(x.1, y, z.0),
            Vec3::new(x.0, y, z.0),
        ],
        m,
    )
}

/// A vertical rectangle standing on the ground from `a` to `b` (their `(x, z)`), `height` tall.
fn upright(a: (f32, f32), b: (f32, f32), height: f32, m: Material) -> Result<Mesh, MeshError> {
    Mesh::quad(
        [
            Vec3::new(a.0, 0.0, a.1),
            Vec3::new(b.0, 0.0, b.1),
            Vec3::new(b.0, height, b.1),
            Vec3::new(a.0, height, a.1),
        ],
        m,
    )
}

/// Builds `which` with `lights` equal lights and `surface` materials, seen by a `width × height`
/// camera.
pub fn build(
    which: TestScene,
    lights: usize,
    surface: Surface,
    width: usize,
    height: usize,
) -> Result<Built, SceneError> {
    if lights == 0 || lights > MAX_SCENE_LIGHTS {
        return Err(SceneError::LightCount(lights));
    }
    let ground = surface.material(0.6);
    let wall = surface.material(0.8);
    let (positions, total, mesh, eye, target) = match which {
        TestScene::Strings => {
            let mut mesh = floor((-14.0, 14.0), (-8.0, 8.0), 0.0, ground)?;
            for z in [-8.0f32, 8.0] {
                mesh.append(upright((-14.0, z), (14.0, z), 10.0, wall)?)?;
            }
            let positions = light_strings(lights).iter().map(|l| l.position).collect();
            (
                positions,
                [76.0, 870.0],
                mesh,
                Vec3::new(-13.5, 1.7, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
            )
        }
        TestScene::Udem => {
            let mesh = floor((-9.0, 9.0), (-6.0, 6.0), 0.0, ground)?;
            let positions = logo_lights(lights);
            (
                positions,
                [4.8, 125.0],
                mesh,
                Vec3::new(0.0, 7.0, 10.0),
                Vec3::new(0.0, 0.0, 0.5),
            )
        }
        TestScene::Cluster => {
            let mut mesh = floor((-4.0, 7.0), (-4.0, 4.0), 0.0, ground)?;
            mesh.append(upright((7.0, 4.0), (7.0, -4.0), 5.0, wall)?)?;
            for z in [-4.0f32, 4.0] {
                mesh.append(upright((-4.0, z), (7.0, z), 5.0, wall)?)?;
            }
            // A uniform cube of side 1 centred 1.5 m above the floor.
            let mut rng = SplitMix64(0xC1A5_7E12);
            let positions = (0..lights)
                .map(|_| rng.next_in(Vec3::new(-0.5, 1.0, -0.5), Vec3::new(0.5, 2.0, 0.5)))
                .collect();
            (
                positions,
                [7.0, 88.0],
                mesh,
                Vec3::new(-1.3, 1.6, 0.0),
                Vec3::new(7.0, 1.2, 0.0),
            )
        }
    };
    let total = match surface {
        Surface::Diffuse => total[0],
        Surface::Specular => total[1],
    };
    let intensity = Vec3::splat(total / lights as f32);
    let camera =
        Camera::new(eye, target, Vec3::Y, 60.0, width, height).map_err(SceneError::Camera)?;
    Ok(Built {
        scene: Scene::new(mesh),
        lights: positions
            .into_iter()
            .map(|p| PointLight::new(p, intensity))
            .collect(),
        camera,
    })
}

/// The strokes of "U de M" as polylines in the unit square per letter (x right, y up), before
/// layout.
fn logo_strokes() -> Vec<Vec<(f32, f32)>> {
    let arc = |cx: f32, cy: f32, r: f32, from: f32, to: f32| -> Vec<(f32, f32)> {
        (0..=32)
            .map(|k| {
                let a = (from + (to - from) * k as f32 / 32.0).to_radians();
                (cx + r * a.cos(), cy + r * a.sin())
            })
            .collect()
    };
    let shift = |s: Vec<(f32, f32)>, dx: f32| s.into_iter().map(|(x, y)| (x + dx, y)).collect();
    let mut strokes = Vec::new();
    // U: two stems joined by a half circle.
    let mut u = vec![(0.0, 1.5)];
    u.extend(arc(0.5, 0.5, 0.5, 180.0, 360.0));
    u.push((1.0, 1.5));
    strokes.push(u);
    // d: a bowl and a tall stem.
    strokes.push(shift(arc(0.35, 0.35, 0.35, 0.0, 360.0), 1.6));
    strokes.push(vec![(2.3, 0.0), (2.3, 1.2)]);
    // e: the bar, then the bowl open at the lower right.
    let mut e = vec![(2.6, 0.35), (3.3, 0.35)];
    e.extend(shift(arc(0.35, 0.35, 0.35, 0.0, 320.0), 2.6));
    strokes.push(e);
    // M.
    strokes.push(vec![
        (3.9, 0.0),
        (3.9, 1.5),
        (4.5, 0.6),
        (5.1, 1.5),
        (5.1, 0.0),
    ]);
    strokes
}

/// Height of the logo's lights above the plane, metres.
const LOGO_HEIGHT: f32 = 0.5;

/// `n` lights evenly spaced by arc length along the logo's strokes, laid flat [`LOGO_HEIGHT`]
/// above the ground, the logo 10.2 m wide along x and 3 m deep along z, centred.
fn logo_lights(n: usize) -> Vec<Vec3> {
    let segments: Vec<((f32, f32), (f32, f32))> = logo_strokes()
        .iter()
        .flat_map(|s| s.windows(2).map(|w| (w[0], w[1])).collect::<Vec<_>>())
        .collect();
    let len =
        |(a, b): &((f32, f32), (f32, f32))| ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    let total: f32 = segments.iter().map(len).sum();
    let step = total / n as f32;
    let mut out = Vec::with_capacity(n);
    let (mut along, mut next) = (0.0f32, 0.5 * step);
    for seg in &segments {
        let l = len(seg);
        while next < along + l && out.len() < n {
            let t = (next - along) / l;
            let (x, y) = (
                seg.0 .0 + t * (seg.1 .0 - seg.0 .0),
                seg.0 .1 + t * (seg.1 .1 - seg.0 .1),
            );
            // Letter units → metres: 2 m per unit, x centred, the letters' "up" towards −z.
            out.push(Vec3::new(2.0 * x - 5.1, LOGO_HEIGHT, 1.5 - 2.0 * y));
            next += step;
        }
        along += l;
    }
    // Rounding may leave the last light or two: put them at the end of the last stroke.
    while out.len() < n {
        let (x, y) = segments.last().map_or((0.0, 0.0), |s| s.1);
        out.push(Vec3::new(2.0 * x - 5.1, LOGO_HEIGHT, 1.5 - 2.0 * y));
    }
    out
}

/// One row of the paper's Tables 2 and 3: RT seconds (SGI R10000), Ward's and the light
/// hierarchy's time as a percentage of RT, and the speed-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperRow {
    /// Scene.
    pub scene: TestScene,
    /// Light count.
    pub lights: usize,
    /// Material.
    pub surface: Surface,
    /// Brute-force ray-tracing time, seconds.
    pub rt_seconds: f64,
    /// Ward's time, % of RT.
    pub ward_percent: f64,
    /// The light hierarchy's time, % of RT.
    pub octree_percent: f64,
    /// Speed-up of the light hierarchy over RT.
    pub speedup: f64,
}

/// RT seconds, Ward %, LH %, speed-up.
type PaperNumbers = (f64, f64, f64, f64);

/// The paper's Tables 2 (diffuse) and 3 (specular), as printed.
#[must_use]
pub fn paper_table() -> Vec<PaperRow> {
    use Surface::{Diffuse, Specular};
    use TestScene::{Cluster, Strings, Udem};
    #[rustfmt::skip]
    let rows: [(TestScene, Surface, [PaperNumbers; 5]); 6] = [
        (Strings, Diffuse, [(11.4, 70.2, 91.2, 1.1), (87.5, 70.3, 73.5, 1.4), (550.6, 68.3, 42.4, 2.4), (2716.3, 70.8, 18.4, 5.4), (13157.1, 72.5, 5.7, 17.6)]),
        (Udem, Diffuse, [(14.8, 64.9, 85.1, 1.2), (108.6, 60.0, 44.4, 2.3), (632.6, 57.8, 16.2, 6.2), (3114.9, 58.7, 4.2, 23.6), (14609.3, 59.5, 1.1, 90.1)]),
        (Cluster, Diffuse, [(8.6, 107.0, 95.3, 1.0), (33.9, 112.4, 90.9, 1.1), (136.1, 119.6, 74.1, 1.3), (545.5, 127.6, 47.0, 2.1), (2179.6, 135.6, 33.5, 3.0)]),
        (Strings, Specular, [(12.8, 26.6, 15.6, 6.4), (93.5, 17.2, 8.3, 12.0), (575.4, 13.1, 6.3, 15.8), (2815.3, 12.3, 5.0, 20.1), (13549.3, 11.5, 3.9, 26.0)]),
        (Udem, Specular, [(17.1, 25.1, 7.0, 14.2), (117.9, 16.1, 3.1, 32.8), (670.2, 12.5, 1.8, 55.4), (3261.5, 11.5, 1.3, 76.4), (15195.3, 11.0, 1.1, 91.6)]),
        (Cluster, Specular, [(10.4, 39.4, 5.8, 17.3), (41.0, 43.7, 3.4, 29.3), (164.1, 49.7, 2.6, 39.1), (656.7, 56.0, 2.3, 43.8), (2632.3, 62.4, 1.9, 51.6)]),
    ];
    rows.iter()
        .flat_map(|&(scene, surface, r)| {
            LIGHT_COUNTS
                .iter()
                .zip(r)
                .map(move |(&lights, (rt, ward, lh, su))| PaperRow {
                    scene,
                    lights,
                    surface,
                    rt_seconds: rt,
                    ward_percent: ward,
                    octree_percent: lh,
                    speedup: su,
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error;

    #[test]
    fn scene_errors_give_their_camera_or_mesh_error_as_source() {
        let source = |e: &SceneError| e.source().map(|s| s.to_string());
        let camera = CameraError::EyeAtTarget;
        assert_eq!(
            source(&SceneError::Camera(camera.clone())),
            Some(camera.to_string())
        );
        let mesh = Mesh::quad([Vec3::ZERO; 4], Surface::Diffuse.material(0.5)).unwrap_err();
        let text = mesh.to_string();
        assert_eq!(source(&SceneError::Mesh(mesh)), Some(text));
        assert!(SceneError::LightCount(0).source().is_none());
    }
}
