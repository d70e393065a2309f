//! Criterion benches of `lgh gi`'s indirect light ([`lgh_vpl::gi`]): one group a scene, each
//! rendering the same 16 × 12 frame of indirect light with shadow rays through
//!
//! - `lgh_alpha4`: the hierarchy at α = 4 with the default shading (representatives shared per
//!   point, resampled draws, the 10% per-point bound);
//! - `lgh_alpha4_unbounded`: the same without the per-point bound (`--point-error off`), so
//!   that the bound's refinement rounds show as the difference;
//! - `brute_force`: every VPL at every pixel, the exact answer of the same model.
//!
//! The scenes: the repository's Cornell box with a mirror and a glass sphere and its glossy
//! variant (`tests/data/cornell-specular`), and the Sponza atrium lit by a sun
//! (`../shared/data/meshes/sponza_dabrovic`; skipped with a message when absent), each with
//! 50,000 VPLs (`lgh bench gi` measures the 365,000 of the figures, with the errors). Only the
//! render is timed: the VPLs, their hierarchy and the representatives are built before.
//! Throughput is in pixels; compare the functions within a group.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use lgh_vpl::gi::{AdaptiveShading, CoarseShading, DirectLight, GiMethod, GiScene, GiSettings};
use lgh_vpl::lgh_core::glam::Vec3;
use lgh_vpl::primary::PrimaryLight;
use lgh_vpl::vpl::VplSettings;
use lgh_vpl::{Camera, Mesh};

/// The frame every function renders.
const WIDTH: usize = 16;
const HEIGHT: usize = 12;

fn bench_scene(
    c: &mut Criterion,
    name: &str,
    obj: &Path,
    lights: Vec<PrimaryLight>,
    (eye, target, fov): (Vec3, Vec3, f32),
) {
    if !obj.is_file() {
        eprintln!("SKIPPED {name}: {} is not here", obj.display());
        return;
    }
    let mesh = Mesh::load_obj(obj).expect("the scene's OBJ loads");
    let settings = GiSettings {
        vpls: VplSettings {
            count: 50_000,
            ..VplSettings::default()
        },
        direct: DirectLight::Off,
        ..GiSettings::default()
    };
    let unbounded = GiSettings {
        coarse: CoarseShading::Adaptive(AdaptiveShading {
            point_error: None,
            ..AdaptiveShading::default()
        }),
        ..settings
    };
    let camera = Camera::new(eye, target, Vec3::Y, fov, WIDTH, HEIGHT).expect("a valid camera");
    let lgh = GiMethod::Lgh { alpha: 4.0 };
    let prepare = |s: &GiSettings| {
        let scene = GiScene::prepare(mesh.clone(), lights.clone(), s).expect("the scene lights");
        scene.build_for(lgh).expect("the representatives build");
        scene
    };
    let (bounded, plain) = (prepare(&settings), prepare(&unbounded));
    let render = |scene: &GiScene, method| scene.render(method, &camera, &()).expect("renders");

    let mut g = c.benchmark_group(format!("gi_{name}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements((WIDTH * HEIGHT) as u64));
    g.bench_function("lgh_alpha4", |b| b.iter(|| render(&bounded, lgh)));
    g.bench_function("lgh_alpha4_unbounded", |b| b.iter(|| render(&plain, lgh)));
    g.bench_function("brute_force", |b| {
        b.iter(|| render(&bounded, GiMethod::Brute))
    });
    g.finish();
}

fn gi_scenes(c: &mut Criterion) {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let specular = here.join("../tests/data/cornell-specular");
    // `lgh gi`'s view of the Cornell box (`--camera 0,1,3.9,0,1,0,39`); its ceiling lamp lights it.
    let cornell = (Vec3::new(0.0, 1.0, 3.9), Vec3::new(0.0, 1.0, 0.0), 39.0);
    bench_scene(
        c,
        "cornell_mirror_glass",
        &specular.join("cornell-specular.obj"),
        Vec::new(),
        cornell,
    );
    bench_scene(
        c,
        "cornell_phong_100",
        &specular.join("cornell-phong-100.obj"),
        Vec::new(),
        cornell,
    );
    // The figures' Sponza: `--light sun:0.25,-1,0.1,5,5,5 --camera -13,3,0,10,5,0,60`.
    let sun: PrimaryLight = "sun:0.25,-1,0.1,5,5,5".parse().expect("a valid sun");
    bench_scene(
        c,
        "sponza",
        &lgh_tests::shared_data().join("meshes/sponza_dabrovic/sponza.obj"),
        vec![sun],
        (Vec3::new(-13.0, 3.0, 0.0), Vec3::new(10.0, 5.0, 0.0), 60.0),
    );
}

criterion_group!(benches, gi_scenes);
criterion_main!(benches);
