//! Specular paths against closed forms: what a camera sees in a mirror and through a glass
//! slab (Fresnel's transmittance, internal reflections included), and the flux light paths
//! carry past mirrors and glass (energy conservation).

use lgh_core::glam::Vec3;
use lgh_core::{luminance, Illumination, Material};
use lgh_vpl::primary::PrimaryLight;
use lgh_vpl::render::render_surfaces;
use lgh_vpl::specular::{fresnel, Specular, MIN_WEIGHT};
use lgh_vpl::vpl::{trace, VplSettings};
use lgh_vpl::{Camera, Mesh, Scene};

const GREY: Material = Material::Lambert {
    albedo: Vec3::splat(0.5),
};

/// The square `|x|, |z| ≤ half` of the plane `y`, facing up (`up`) or down, of `material`.
fn square(y: f32, half: f32, up: bool, material: Material) -> Mesh {
    let c = |x: f32, z: f32| Vec3::new(x * half, y, z * half);
    let mut corners = [c(-1.0, 1.0), c(1.0, 1.0), c(1.0, -1.0), c(-1.0, -1.0)];
    if !up {
        corners.reverse();
    }
    Mesh::quad(corners, material).unwrap()
}

/// Renders `scene` with the radiance `emitted` leaving triangles of material `lamp` and
/// nothing from the others (so a pixel is what its specular paths carry from the lamp).
fn render_lamp(scene: &Scene, camera: &Camera, lamp: u32, emitted: Vec3) -> lgh_image::Image {
    let mesh = scene.mesh();
    render_surfaces(
        scene,
        camera,
        |_, t| {
            let on = mesh.triangles()[t as usize].material == lamp;
            Ok(Illumination {
                radiance: if on { emitted } else { Vec3::ZERO },
                lights: 1,
            })
        },
        |_| {},
    )
    .unwrap()
    .image
}

#[test]
fn a_mirror_shows_ks_times_what_lies_along_the_reflected_ray() {
    // A mirror floor (y = 0, |x|, |z| ≤ 4) and a lamp (y = 2, |x|, |z| ≤ 1, facing down);
    // the camera looks down at the floor beside the lamp.
    let ks = Vec3::new(0.9, 0.8, 0.7);
    let mut mesh = square(0.0, 4.0, true, GREY);
    mesh.set_specular(0, Specular::Mirror { reflectance: ks })
        .unwrap();
    mesh.append(square(2.0, 1.0, false, GREY)).unwrap();
    let mut scene = Scene::new(mesh);
    let emitted = Vec3::new(3.0, 2.0, 1.0);
    let camera = Camera::new(
        Vec3::new(0.5, 1.0, 3.0),
        Vec3::new(0.0, 0.0, -0.5),
        Vec3::Y,
        70.0,
        40,
        30,
    )
    .unwrap();
    let image = render_lamp(&scene, &camera, 1, emitted);
    let (mut lit, mut dark) = (0, 0);
    for y in 0..30 {
        for x in 0..40 {
            let (o, d) = camera.ray(x, y);
            // The floor at t = −o.y/d.y; the reflected ray (d.x, −d.y, d.z) meets y = 2 at
            // s = 2/(−d.y) beyond it.
            let p = o - o.y / d.y * d;
            let q = p + 2.0 / -d.y * Vec3::new(d.x, -d.y, d.z);
            let on_floor = d.y < 0.0 && p.x.abs() < 4.0 && p.z.abs() < 4.0;
            // Where the camera sees the lamp itself, or the floor at its edge: left out.
            let direct = o + (2.0 - o.y) / d.y * d;
            let sees_lamp = d.y > 0.0 && direct.x.abs() <= 1.0 && direct.z.abs() <= 1.0;
            let edge = (q.x.abs() - 1.0).abs().min((q.z.abs() - 1.0).abs()) < 1e-3;
            if !on_floor || sees_lamp || edge {
                continue;
            }
            let want = if q.x.abs() < 1.0 && q.z.abs() < 1.0 {
                lit += 1;
                ks * emitted
            } else {
                dark += 1;
                Vec3::ZERO
            };
            assert_eq!(image.get(x, y), want, "pixel ({x}, {y})");
        }
    }
    assert!(lit > 50 && dark > 50, "{lit} lit, {dark} dark");
    // A specular depth of 0 stops at the mirror: its Kd, zero, is all there is.
    scene.set_specular_depth(0);
    let image = render_lamp(&scene, &camera, 1, emitted);
    assert!(image
        .pixels
        .iter()
        .all(|&p| p == Vec3::ZERO || p == emitted));
}

#[test]
fn a_glass_slab_transmits_fresnels_share_with_its_internal_reflections() {
    // A slab of glass (η = 1.5, Tf) 0.5 thick and 40 wide over a lamp 40 wide (y = −1,
    // facing up); the camera looks down through the slab.
    let (eta, tf) = (1.5f32, Vec3::new(1.0, 0.9, 0.8));
    let mut mesh = Mesh::cuboid(
        Vec3::new(-20.0, 0.0, -20.0),
        Vec3::new(20.0, 0.5, 20.0),
        GREY,
    )
    .unwrap();
    let glass = Specular::Dielectric {
        ior: eta,
        transmittance: tf,
    };
    mesh.set_specular(0, glass).unwrap();
    mesh.append(square(-1.0, 20.0, true, GREY)).unwrap();
    let scene = Scene::new(mesh);
    let emitted = Vec3::splat(2.0);
    let camera = Camera::new(
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::new(0.3, 0.0, 0.1),
        Vec3::Z,
        80.0,
        24,
        24,
    )
    .unwrap();
    let image = render_lamp(&scene, &camera, 1, emitted);
    let mut worst = 0.0f32;
    for y in 0..24 {
        for x in 0..24 {
            let (_, d) = camera.ray(x, y);
            // Parallel faces: the angle of incidence is the same at every face a path meets,
            // inside (θ_t) and out (θ_i), so every interface reflects the same F (Fresnel is
            // reciprocal). Straight through: (1 − F)²; once reflected inside and back:
            // (1 − F)² F²; the η² of going in and out cancel; Tf once, on the way in. The next
            // term, (1 − F)² F⁴, is below MIN_WEIGHT and not followed.
            let f = fresnel(-d.y, 1.0, eta);
            let through = (1.0 - f).powi(2) * tf;
            let mut want = through;
            // Followed if the flux reflected twice inside, (1 − F) Tf F², is not below
            // MIN_WEIGHT (here it never is: F ≥ 0.04); the next reflection never is.
            assert!(luminance((1.0 - f) * tf * f * f) >= MIN_WEIGHT);
            want += through * f * f;
            assert!(f.powi(4) < MIN_WEIGHT);
            let got = image.get(x, y) / emitted;
            worst = worst.max(((got - want).abs() / want).max_element());
        }
    }
    // Each pixel's paths are a handful of refractions and reflections in f32: 1e-5 relative.
    assert!(worst < 1e-5, "largest relative difference {worst}");
}

/// The cube `[−1, 1]³` without its floor (`y = −1`), grey.
fn walls() -> Mesh {
    let cube = Mesh::cuboid(Vec3::splat(-1.0), Vec3::splat(1.0), GREY).unwrap();
    // Triangles 4 and 5 are the −y face.
    let mut walls = cube.triangles().to_vec();
    walls.drain(4..6);
    Mesh::new(cube.positions().to_vec(), vec![], walls, vec![GREY]).unwrap()
}

/// The flux of the first-bounce VPLs of `mesh` lit by a point light at the origin, over what
/// the light emits, with paths following up to `depth` specular surfaces.
fn first_bounce_flux(mesh: Mesh, depth: u32) -> f32 {
    let mut scene = Scene::new(mesh);
    scene.set_specular_depth(depth);
    let lights = [PrimaryLight::Point {
        position: Vec3::ZERO,
        intensity: Vec3::ONE,
    }];
    let settings = VplSettings {
        count: 20_000,
        max_bounces: 1,
        seed: 7,
    };
    let vpls = trace(&scene, &lights, &settings).unwrap();
    // Summed in f64: 20,000 f32 terms would round by ~1e-4.
    let flux: f64 = vpls.vpls.iter().map(|v| f64::from(v.power.x)).sum();
    (flux / f64::from(vpls.emitted.x)) as f32
}

#[test]
fn light_paths_carry_their_flux_past_mirrors_and_glass() {
    // A closed grey cube: every path deposits its share on the first wall it meets.
    let cube = Mesh::cuboid(Vec3::splat(-1.0), Vec3::splat(1.0), GREY).unwrap();
    let diffuse = first_bounce_flux(cube.clone(), 6);
    assert!((diffuse - 1.0).abs() < 1e-4, "{diffuse}");
    // A glass slab (closed, η = 1.5, clear) inside it under the light: a path through glass
    // is chosen by Fresnel at each face and carries its flux whole, so every path still
    // reaches a wall, up to those that take more than 24 specular surfaces (TIR between the
    // slab's faces): the flux stays 1 within 1e-3.
    let mut with_slab = cube;
    let mut slab =
        Mesh::cuboid(Vec3::new(-0.9, -0.8, -0.9), Vec3::new(0.9, -0.5, 0.9), GREY).unwrap();
    slab.set_specular(
        0,
        Specular::Dielectric {
            ior: 1.5,
            transmittance: Vec3::ONE,
        },
    )
    .unwrap();
    with_slab.append(slab).unwrap();
    let glass = first_bounce_flux(with_slab, 24);
    assert!(glass > 0.999 && glass < 1.0 + 1e-4, "{glass}");
    // A mirror floor reflecting half, without a diffuse part: the floor takes 1/6 of the
    // flux from the centre (symmetry) and gives half of it to the walls, 5/6 + 1/12 in all,
    // up to the binomial noise of which paths meet the floor first (σ = ½ √((1/6)(5/6)/20000)
    // ≈ 0.0013; 5σ allowed).
    let black = Material::Lambert { albedo: Vec3::ZERO };
    let mut with_mirror = walls();
    with_mirror.append(square(-1.0, 1.0, true, black)).unwrap();
    with_mirror
        .set_specular(
            1,
            Specular::Mirror {
                reflectance: Vec3::splat(0.5),
            },
        )
        .unwrap();
    let mirror = first_bounce_flux(with_mirror, 6);
    let want = 5.0 / 6.0 + 1.0 / 12.0;
    assert!((mirror - want).abs() < 0.0065, "{mirror} vs {want}");
}

#[test]
fn the_specular_cornell_boxes_load_with_nothing_unhonoured() {
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/cornell-specular");
    let mesh = Mesh::load_obj(&dir.join("cornell-specular.obj")).unwrap();
    assert!(mesh.unhonoured().is_empty(), "{:?}", mesh.unhonoured());
    let kinds: Vec<Specular> = (0..mesh.materials().len() as u32)
        .filter_map(|m| {
            let t = mesh.triangles().iter().position(|t| t.material == m)?;
            Some(mesh.specular(t as u32))
        })
        .collect();
    assert!(kinds.contains(&Specular::Mirror {
        reflectance: Vec3::splat(0.95)
    }));
    assert!(kinds.contains(&Specular::Dielectric {
        ior: 1.5,
        transmittance: Vec3::ONE
    }));
    // Smooth spheres: every sphere triangle has vertex normals.
    assert!(mesh
        .triangles()
        .iter()
        .filter(|t| mesh.specular_of(t.material) != Specular::None)
        .all(|t| t.normals.is_some()));
    for (ns, name) in [(10, "10"), (100, "100"), (1000, "1000"), (1000, "mirror")] {
        let phong = Mesh::load_obj(&dir.join(format!("cornell-phong-{name}.obj"))).unwrap();
        assert!(phong.unhonoured().is_empty(), "{:?}", phong.unhonoured());
        assert!(phong
            .materials()
            .iter()
            .any(|m| matches!(m, Material::Phong { exponent, .. } if *exponent == ns as f32)));
    }
}

#[test]
fn specular_and_split_renders_are_the_same_on_any_thread_count() {
    // The mirror and glass box and the glossy one, through the hierarchy (lobes split) and
    // brute force, direct light included: the same bits on one thread and on three.
    use lgh_vpl::gi::{GiMethod, GiScene, GiSettings};
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/cornell-specular");
    for name in ["cornell-specular", "cornell-phong-1000"] {
        let render = || {
            let mesh = Mesh::load_obj(&dir.join(format!("{name}.obj"))).unwrap();
            let settings = GiSettings {
                vpls: VplSettings {
                    count: 3000,
                    ..VplSettings::default()
                },
                ..GiSettings::default()
            };
            let scene = GiScene::prepare(mesh, [], &settings).unwrap();
            let camera = Camera::new(
                Vec3::new(0.0, 1.0, 3.9),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::Y,
                39.0,
                20,
                20,
            )
            .unwrap();
            let lgh = scene
                .render(GiMethod::Lgh { alpha: 4.0 }, &camera, &())
                .unwrap();
            let brute = scene.render(GiMethod::Brute, &camera, &()).unwrap();
            (
                lgh.rendered.image,
                brute.rendered.image,
                lgh.lobe_split_points,
            )
        };
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let one = pool(1).install(render);
        let three = pool(3).install(render);
        assert_eq!(one, three, "{name}");
        // The glossy box splits its spheres' points; the mirror and glass one has none to split.
        assert_eq!(one.2 > 0, name == "cornell-phong-1000", "{name}: {}", one.2);
    }
}
