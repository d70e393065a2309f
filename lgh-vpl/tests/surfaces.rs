//! Textures and smooth normals read from OBJ + MTL files, against closed forms: a textured
//! quad's albedo where the camera sees it and where light paths deposit VPLs (Kd times the
//! bilinear texture at the point's texture coordinates), and a tessellated sphere's shading
//! normals against the sphere's (second-order convergence); bad texture inputs as clear errors.

use std::path::{Path, PathBuf};

use lgh_core::glam::{Vec2, Vec3};
use lgh_core::reflection::{reflected, Lobe};
use lgh_core::{BruteForce, Material, PointLight, ShadingPoint};
use lgh_vpl::primary::PrimaryLight;
use lgh_vpl::vpl::{trace, VplSettings};
use lgh_vpl::{render, Camera, Mesh, MeshError, MissingTextures, ObjOptions, Scene};

/// The MTL's `Kd` of the textured floor.
const KD: Vec3 = Vec3::new(0.8, 0.6, 1.0);

/// The 2 × 2 texture's 8-bit sRGB texels, rows from the top: red, green / blue, white-ish.
const TEXELS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [200, 200, 200]];

/// The sRGB transfer function's inverse, written out from IEC 61966-2-1 for this test.
fn decode(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The texture's bilinear colour at `uv` by hand: texel centres at ¼ and ¾, `v` up, repeating.
fn texture_at(uv: Vec2) -> Vec3 {
    let texel = |i: i64, j: i64| {
        let [r, g, b] = TEXELS[(j.rem_euclid(2) * 2 + i.rem_euclid(2)) as usize];
        Vec3::new(decode(r), decode(g), decode(b))
    };
    let (x, y) = (uv.x * 2.0 - 0.5, (1.0 - uv.y) * 2.0 - 0.5);
    let (i, j) = (x.floor() as i64, y.floor() as i64);
    let (s, t) = (x - x.floor(), y - y.floor());
    let row = |j| texel(i, j) * (1.0 - s) + texel(i + 1, j) * s;
    row(j) * (1.0 - t) + row(j + 1) * t
}

/// A folder with `floor.obj` (the square 0 ≤ x ≤ 4, −4 ≤ z ≤ 0 of y = 0, facing up, texture
/// coordinates `(x/4, −z/4)` at its corners), `floor.mtl` (`Kd` [`KD`], `map_Kd floor.png`)
/// and, if `png`, `floor.png` ([`TEXELS`]).
fn textured_floor(png: bool) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("floor.obj");
    std::fs::write(
        &obj,
        "mtllib floor.mtl\nv 0 0 0\nv 4 0 0\nv 4 0 -4\nv 0 0 -4\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl floor\nf 1/1 2/2 3/3 4/4\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("floor.mtl"),
        format!(
            "newmtl floor\nKd {} {} {}\nmap_Kd floor.png\n",
            KD.x, KD.y, KD.z
        ),
    )
    .unwrap();
    if png {
        textured_floor_png(dir.path());
    }
    (dir, obj)
}

/// The albedo of the textured floor at `p`: `Kd` times the texture at `(x/4, −z/4)`.
fn albedo_at(p: Vec3) -> Vec3 {
    KD * texture_at(Vec2::new(p.x / 4.0, -p.z / 4.0))
}

#[test]
fn a_textured_quad_has_kd_times_the_bilinear_texture_where_seen_and_where_lit() {
    let (_dir, obj) = textured_floor(true);
    let mesh = Mesh::load_obj(&obj).unwrap();
    assert!(mesh.unhonoured().is_empty(), "{:?}", mesh.unhonoured());
    let scene = Scene::new(mesh);
    // Seen: one light above, brute force, eq. (1) per pixel with the closed-form albedo.
    let light = PointLight::new(Vec3::new(2.0, 3.0, -2.0), Vec3::splat(10.0));
    let backend = BruteForce::new(&[light]).unwrap();
    let camera = Camera::new(
        Vec3::new(2.0, 5.0, 1.0),
        Vec3::new(2.0, 0.0, -2.0),
        Vec3::Y,
        60.0,
        32,
        32,
    )
    .unwrap();
    let got = render(&scene, &camera, &backend, |_| {}).unwrap();
    let (mut seen, mut worst) = (0, 0.0f32);
    for y in 0..32 {
        for x in 0..32 {
            let (o, d) = camera.ray(x, y);
            let p = o - o.y / d.y * d;
            if !(0.0..=4.0).contains(&p.x) || !(-4.0..=0.0).contains(&p.z) {
                continue;
            }
            let point = ShadingPoint {
                position: p,
                normal: Some(Vec3::Y),
                geometric: None,
                view: Some(-d),
                material: Material::Lambert {
                    albedo: albedo_at(p),
                },
            };
            let want = reflected(&point, light.position, light.intensity, Lobe::All);
            let px = got.image.get(x, y);
            // Pixels on the square's edge may miss it by rounding: only those well inside.
            if p.x.min(4.0 - p.x).min(-p.z).min(4.0 + p.z) < 1e-3 {
                continue;
            }
            seen += 1;
            worst = worst.max(((px - want).abs() / want.max(Vec3::splat(1e-3))).max_element());
        }
    }
    // The hit point and its texture coordinates come from barycentrics instead of o + t·d
    // (rounding ≈ 1e-7 of |p| ≤ 6); through the texture's slope (texels change by up to 1 per
    // half unit) and 1/d², 1e-4 relative bounds it with room.
    assert!(seen > 300, "{seen} of the 1024 pixels see the floor");
    assert!(worst < 1e-4, "largest relative difference {worst}");

    // Lit: every VPL a path deposits on the floor carries the albedo there.
    let lights = [PrimaryLight::Point {
        position: light.position,
        intensity: light.intensity,
    }];
    let settings = VplSettings {
        count: 2000,
        max_bounces: 1,
        seed: 3,
    };
    let vpls = trace(&scene, &lights, &settings).unwrap();
    assert!(vpls.vpls.len() >= 2000);
    for v in &vpls.vpls {
        let want = albedo_at(v.position);
        assert!(
            (v.albedo - want).abs().max_element() < 1e-5,
            "VPL at {}: albedo {} instead of {want}",
            v.position,
            v.albedo
        );
    }
}

#[test]
fn texture_inputs_that_are_wrong_are_clear_errors_or_a_documented_grey() {
    // Missing: an error naming the file; with `MissingTextures::Grey`, grey and a note.
    let (dir, obj) = textured_floor(false);
    let e = Mesh::load_obj(&obj).unwrap_err();
    assert!(
        matches!(&e, MeshError::Io { path, .. } if path.ends_with("floor.png")),
        "{e}"
    );
    assert!(e.to_string().contains("floor.png"), "{e}");
    let grey = ObjOptions {
        missing_textures: MissingTextures::Grey,
        ..ObjOptions::default()
    };
    let mesh = Mesh::load_obj_with(&obj, &grey, |_, _| {}).unwrap();
    assert_eq!(mesh.material_at(0, 0.2, 0.2), lgh_vpl::DEFAULT_MATERIAL);
    let notes: Vec<String> = mesh.unhonoured().iter().map(|u| u.to_string()).collect();
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].contains("floor.png") && notes[0].contains("grey"),
        "{notes:?}"
    );
    // Not an image: an error naming the file, whatever the option.
    std::fs::write(dir.path().join("floor.png"), "newmtl x\n").unwrap();
    for options in [ObjOptions::default(), grey] {
        let e = Mesh::load_obj_with(&obj, &options, |_, _| {}).unwrap_err();
        assert!(
            matches!(&e, MeshError::Texture { path, .. } if path.ends_with("floor.png")),
            "{e}"
        );
    }
    // Too large: refused from its header, naming the file.
    {
        let file = std::fs::File::create(dir.path().join("floor.png")).unwrap();
        let mut encoder = png::Encoder::new(file, 1, 40_000);
        encoder.set_color(png::ColorType::Grayscale);
        let mut w = encoder.write_header().unwrap();
        w.write_image_data(&vec![0; 40_000]).unwrap();
    }
    let e = Mesh::load_obj(&obj).unwrap_err();
    assert!(
        e.to_string().contains("floor.png") && e.to_string().contains("40000"),
        "{e}"
    );
    // Texture coordinates out of [0, 1] repeat (documented); non-finite ones are an error.
    let tiled = std::fs::read_to_string(&obj)
        .unwrap()
        .replace("vt 1 1", "vt 3 -2");
    std::fs::write(&obj, &tiled).unwrap();
    textured_floor_png(dir.path());
    let mesh = Mesh::load_obj(&obj).unwrap();
    assert_eq!(mesh.texcoords()[2], Vec2::new(3.0, -2.0));
    std::fs::write(&obj, tiled.replace("vt 3 -2", "vt nan 0")).unwrap();
    assert!(matches!(
        Mesh::load_obj(&obj),
        Err(MeshError::NonFiniteTexcoord { index: 2 })
    ));
}

/// Writes [`TEXELS`] as `floor.png` into `dir`.
fn textured_floor_png(dir: &Path) {
    let file = std::fs::File::create(dir.join("floor.png")).unwrap();
    let mut encoder = png::Encoder::new(file, 2, 2);
    encoder.set_color(png::ColorType::Rgb);
    let mut w = encoder.write_header().unwrap();
    w.write_image_data(TEXELS.as_flattened()).unwrap();
}

/// A unit sphere at the origin as an OBJ of `n` rings and `2n` segments, its vertex normals
/// the sphere's (`vn` = the vertex's position).
fn sphere_obj(n: usize) -> String {
    use std::f32::consts::PI;
    use std::fmt::Write;
    let mut obj = String::new();
    for i in 0..=n {
        let theta = PI * i as f32 / n as f32;
        for j in 0..2 * n {
            let phi = PI * j as f32 / n as f32;
            let p = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            writeln!(obj, "v {} {} {}\nvn {} {} {}", p.x, p.y, p.z, p.x, p.y, p.z).unwrap();
        }
    }
    let index = |i: usize, j: usize| i * 2 * n + j % (2 * n) + 1;
    for i in 0..n {
        for j in 0..2 * n {
            let [a, b, c, d] = [
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            ];
            writeln!(
                obj,
                "f {a}//{a} {d}//{d} {c}//{c}\nf {a}//{a} {c}//{c} {b}//{b}"
            )
            .unwrap();
        }
    }
    obj
}

/// The largest angle (radians) between the shading normal and the sphere's normal at the
/// radial projection of the point hit, over rays from a ring of cameras at the sphere, and the
/// same for the face normal.
fn normal_errors(n: usize) -> (f32, f32) {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("sphere.obj");
    std::fs::write(&obj, sphere_obj(n)).unwrap();
    let mesh = Mesh::load_obj(&obj).unwrap();
    assert!(mesh.triangles().iter().all(|t| t.normals.is_some()));
    let scene = Scene::new(mesh);
    let (mut shading, mut face, mut hits) = (0.0f32, 0.0f32, 0);
    for k in 0..8 {
        let a = k as f32 * 0.7 + 0.1;
        let eye = Vec3::new(3.0 * a.cos(), 0.8 * a.sin(), 3.0 * a.sin());
        let camera = Camera::new(eye, Vec3::ZERO, Vec3::Y, 40.0, 24, 24).unwrap();
        for y in 0..24 {
            for x in 0..24 {
                let (o, d) = camera.ray(x, y);
                let ray = lgh_vpl::Ray::new(o, d);
                let Some(hit) = scene.bvh().intersect(&ray) else {
                    continue;
                };
                hits += 1;
                let point = scene.surface(&ray, &hit);
                let truth = point.position.normalize();
                // The angle from |a × b| (not acos(a·b), which turns a rounding of 1e-7 in the
                // cosine into 5e-4 rad); both unit, and on the same side here.
                let angle = |n: Vec3| n.cross(truth).length().min(1.0).asin();
                assert!(point.normal.unwrap().dot(truth) > 0.0);
                shading = shading.max(angle(point.normal.unwrap()));
                face = face.max(angle(scene.mesh().face_normal(hit.triangle)));
            }
        }
    }
    assert!(hits > 1000, "{hits} rays hit the sphere");
    (shading, face)
}

#[test]
fn a_tessellated_spheres_shading_normals_are_the_spheres() {
    // With the sphere's own normals at the vertices (n_i = v_i, unit sphere at the origin), the
    // barycentric blend of the normals at a hit p = Σ w_i v_i is p itself: normalised, the
    // sphere's normal at p's radial projection, exactly; what is left is f32 rounding (a few
    // 1e-7 in each of the blend and the normalisations), which 1e-5 rad bounds with room. The
    // face normal errs by O(h): at a quad's far corner by half the angle its diagonal
    // subtends, √2·π/2n at the equator (measured: 1.39·π/2n at n = 8 and 16).
    for n in [8, 16] {
        let (shading, face) = normal_errors(n);
        assert!(
            shading < 1e-5,
            "n = {n}: shading normals off by {shading} rad"
        );
        let half_edge = std::f32::consts::PI / (2 * n) as f32;
        assert!(
            face > half_edge && face < 1.6 * half_edge,
            "n = {n}: face normal {face}"
        );
    }
}

#[test]
fn a_specular_map_multiplies_ks_and_leaves_kd() {
    let (dir, obj) = textured_floor(true);
    std::fs::write(
        dir.path().join("floor.mtl"),
        "newmtl floor\nKd 0.2 0.2 0.2\nKs 0.5 0.5 0.5\nNs 50\nmap_Ks floor.png\n",
    )
    .unwrap();
    let mesh = Mesh::load_obj(&obj).unwrap();
    assert!(mesh.unhonoured().is_empty(), "{:?}", mesh.unhonoured());
    for (u, v) in [(0.1, 0.2), (0.45, 0.45), (0.7, 0.1)] {
        for t in 0..2 {
            let p = mesh.point(t, u, v);
            let Material::Phong { kd, ks, exponent } = mesh.material_at(t, u, v) else {
                panic!("not Phong");
            };
            let want = Vec3::splat(0.5) * texture_at(Vec2::new(p.x / 4.0, -p.z / 4.0));
            assert_eq!((kd, exponent), (Vec3::splat(0.2), 50.0));
            assert!((ks - want).abs().max_element() < 1e-5, "{ks} vs {want}");
        }
    }
}

/// A floor quad (`|x|, |z| ≤ 1`, y = 0, face normal +y) whose vertex normals all lean 45°
/// towards +z: smooth shading says "tilted", the face says "up".
fn leaning_floor() -> (tempfile::TempDir, Scene) {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("leaning.obj");
    std::fs::write(
        &obj,
        "v -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 0 -1\nvn 0 1 1\nf 1//1 2//1 3//1 4//1\n",
    )
    .unwrap();
    let scene = Scene::new(Mesh::load_obj(&obj).unwrap());
    (dir, scene)
}

/// The geometric normal: where smooth shading leans away from the face, what the camera sees
/// is shaded with the leaning normal, but the face decides where light can come from and
/// leave to. On a floor whose vertex normals lean 45°:
/// - the surface point carries both (`ShadingPoint::geometric` is the face's, +y);
/// - every VPL deposited on it keeps both: its lobe about the leaning normal, the face's for
///   the hemisphere it emits into (`Vpl::lobe`, whose doctest shows nothing goes below);
/// - a lamp below the floor's plane but in front of the leaning shading plane, seen from the
///   floor's edge (where no shadow ray would cross the quad), gives no direct light and a VPL
///   there no indirect light; with the geometric normal left out they would light it, which
///   shows the test can fail.
#[test]
fn light_leaves_and_reaches_the_face_not_the_shading_normal() {
    use lgh_vpl::direct::{Direct, DirectSettings};
    use lgh_vpl::indirect::{Indirect, IndirectSettings};
    let (_dir, scene) = leaning_floor();
    let leaning = Vec3::new(0.0, 1.0, 1.0).normalize();
    // Seen from above: both normals, on the viewer's side.
    let ray = lgh_vpl::Ray::new(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y);
    let hit = scene.bvh().intersect(&ray).unwrap();
    let seen = scene.surface(&ray, &hit);
    assert!((seen.normal.unwrap() - leaning).length() < 1e-6, "{seen:?}");
    assert_eq!(seen.geometric, Some(Vec3::Y));

    let lamp = PrimaryLight::Point {
        position: Vec3::new(0.2, 1.5, -0.3),
        intensity: Vec3::splat(3.0),
    };
    let settings = VplSettings {
        count: 500,
        max_bounces: 1,
        seed: 7,
    };
    let vpls = trace(&scene, &[lamp], &settings).unwrap().vpls;
    assert!(vpls.len() >= 100, "{}", vpls.len());
    for v in &vpls {
        assert!((v.normal - leaning).length() < 1e-6, "{v:?}");
        assert_eq!(v.geometric, Vec3::Y, "{v:?}");
    }

    // At the floor's front edge (z = 1), a source at (0, −0.1, 2): below the face's plane, in
    // front of the leaning plane (0.9/√2 > 0).
    let edge = |geometric| ShadingPoint {
        position: Vec3::new(0.0, 0.0, 1.0),
        normal: Some(leaning),
        geometric,
        view: Some(Vec3::Y),
        material: Material::Lambert {
            albedo: Vec3::splat(0.8),
        },
    };
    let below = Vec3::new(0.0, -0.1, 2.0);
    let source = [PrimaryLight::Point {
        position: below,
        intensity: Vec3::ONE,
    }];
    let d = DirectSettings {
        area_strata: 1,
        epsilon: 1e-4,
    };
    let direct = Direct::new(&scene, &source, d);
    assert_eq!(direct.shade(&edge(Some(Vec3::Y))), Vec3::ZERO);
    assert!(direct.shade(&edge(None)).x > 0.0, "the test cannot fail");

    let towards = (Vec3::new(0.0, 0.1, 1.0) * -1.0).normalize();
    let vpl = lgh_vpl::vpl::Vpl {
        position: below,
        normal: towards,
        geometric: towards,
        power: Vec3::ONE,
        albedo: Vec3::ONE,
        bounce: 1,
    };
    let shading = IndirectSettings {
        h0: 1e-3,
        gaussian_samples: 0,
        epsilon: 1e-4,
        shadows: true,
        lobe_error: None,
        point_error: None,
    };
    let indirect = Indirect::new(&scene, std::slice::from_ref(&vpl), shading);
    let lights = lgh_vpl::indirect::point_lights(&[vpl]);
    let sample = |p: &ShadingPoint| {
        lgh_core::LightSample::point(
            0,
            lights[0].position,
            lights[0].intensity,
            p.position,
            Lobe::All,
        )
    };
    let (flat, smooth) = (edge(Some(Vec3::Y)), edge(None));
    assert_eq!(indirect.shade(&flat, &sample(&flat), Some(0)), Vec3::ZERO);
    assert!(
        indirect.shade(&smooth, &sample(&smooth), Some(0)).x > 0.0,
        "the test cannot fail"
    );
}

/// A cut-out (MTL `map_d`): a screen at y = 1 over a floor at y = 0, its coverage map two
/// texels wide — a hole on the left (alpha 0), solid on the right (alpha 255) — bilinear, so
/// the coverage crosses ½ at the screen's middle (x = 0). A lamp at (0, 3, 0): the shadow ray of
/// a floor point at x meets the screen at 2x/3. Checked: a camera ray down at x = −0.6 passes
/// through the hole to the floor, one at x = 0.6 stops on the screen; the floor at x = −0.9 (its
/// shadow ray through the hole, u = 0.2) has exactly the lamp's unshadowed direct light,
/// `I cos / d² · ρ/π`, and at x = 0.9 (through the solid half) none; nothing is named as not
/// honoured; a missing coverage map is an error naming it.
#[test]
fn a_coverage_map_cuts_holes_for_camera_and_shadow_rays() {
    use lgh_vpl::direct::{Direct, DirectSettings};
    let dir = tempfile::tempdir().unwrap();
    let mut png = Vec::new();
    image::RgbaImage::from_raw(2, 1, vec![9, 9, 9, 0, 9, 9, 9, 255])
        .unwrap()
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    std::fs::write(dir.path().join("holes.png"), &png).unwrap();
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl screen\nKd 0.8 0.8 0.8\nmap_d holes.png\n",
    )
    .unwrap();
    let obj = dir.path().join("cutout.obj");
    std::fs::write(
        &obj,
        "mtllib m.mtl\n\
         v -2 0 2\nv 2 0 2\nv 2 0 -2\nv -2 0 -2\n\
         v -1 1 1\nv 1 1 1\nv 1 1 -1\nv -1 1 -1\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         usemtl floor\nf 1 2 3 4\n\
         usemtl screen\nf 5/1 6/2 7/3 8/4\n",
    )
    .unwrap();
    let mesh = Mesh::load_obj(&obj).unwrap();
    assert!(mesh.has_coverage());
    assert!(mesh.unhonoured().is_empty(), "{:?}", mesh.unhonoured());
    let scene = Scene::new(mesh);
    let down = |x: f32| scene.trace(Vec3::new(x, 5.0, 0.0), Vec3::NEG_Y).unwrap().0;
    assert!(down(-0.6).position.y.abs() < 1e-5, "{:?}", down(-0.6));
    assert!((down(0.6).position.y - 1.0).abs() < 1e-5, "{:?}", down(0.6));

    let (position, intensity) = (Vec3::new(0.0, 3.0, 0.0), Vec3::splat(2.0));
    let lamp = [PrimaryLight::Point {
        position,
        intensity,
    }];
    let settings = DirectSettings {
        area_strata: 1,
        epsilon: 1e-4,
    };
    let direct = Direct::new(&scene, &lamp, settings);
    let floor = |x: f32| ShadingPoint {
        position: Vec3::new(x, 0.0, 0.0),
        normal: Some(Vec3::Y),
        geometric: Some(Vec3::Y),
        view: Some(Vec3::Y),
        material: Material::Lambert {
            albedo: Vec3::splat(0.5),
        },
    };
    let to = position - floor(-0.9).position;
    let want = intensity * (to.normalize().y / to.length_squared()) * (0.5 / std::f32::consts::PI);
    let got = direct.shade(&floor(-0.9));
    assert!(
        (got - want).abs().max_element() < 1e-5 * want.x,
        "{got} against {want}"
    );
    assert_eq!(direct.shade(&floor(0.9)), Vec3::ZERO);

    std::fs::remove_file(dir.path().join("holes.png")).unwrap();
    let e = Mesh::load_obj(&obj).unwrap_err().to_string();
    assert!(e.contains("holes.png"), "{e}");
}
