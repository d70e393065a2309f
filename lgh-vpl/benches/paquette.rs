//! Criterion benches of the error-bounded backends on Paquette et al.'s test scenes
//! ([`lgh_vpl::paquette`]): brute force (the paper's RT), Ward's adaptive shadow testing and the
//! light octree at the paper's threshold of 1 %, Lightcuts (2 %, brightest representatives) and
//! the lighting grid hierarchy at α = 8, each shading the same surface points with the same
//! unoccluded eq. (1).
//!
//! The points are the primary hits of a 48 × 36 camera, so a bench iteration is one small frame
//! without the ray casting; throughput is in shading points. Each group is one scene, surface and
//! light count; compare the functions within a group. `lgh paquette` measures the same backends
//! end to end on whole images, with their 8-bit errors.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use lgh_vpl::lgh_core::glam::Vec3;
use lgh_vpl::lgh_core::lightcuts::{
    LightTree, LightcutsBackend, LightcutsSettings, Representative,
};
use lgh_vpl::lgh_core::octree::{LightOctree, OctreeBackend, OctreeSettings};
use lgh_vpl::lgh_core::reflection::reflected;
use lgh_vpl::lgh_core::ward::WardBackend;
use lgh_vpl::lgh_core::{
    BruteForce, GridSettings, LghBackend, LightSample, LightingGridHierarchy, ManyLights,
    ShadingPoint,
};
use lgh_vpl::paquette::{self, Surface, TestScene, PAPER_THRESHOLD};

/// Shades every point through `backend` with eq. (1); returns the summed radiance.
fn shade_all<B: ManyLights>(backend: &B, points: &[ShadingPoint]) -> Vec3 {
    points.iter().fold(Vec3::ZERO, |acc, p| {
        let mut shade = |l: &LightSample| reflected(p, l.position, l.intensity, l.lobe);
        acc + backend.illuminate(p, &mut shade).unwrap().radiance
    })
}

fn bench_case(c: &mut Criterion, scene: TestScene, surface: Surface, lights: usize) {
    let built = paquette::build(scene, lights, surface, 48, 36).unwrap();
    let cam = &built.camera;
    let points: Vec<ShadingPoint> = (0..cam.height())
        .flat_map(|y| (0..cam.width()).map(move |x| (x, y)))
        .filter_map(|(x, y)| {
            let (origin, dir) = cam.ray(x, y);
            built.scene.first_hit(origin, dir)
        })
        .collect();
    let brute = BruteForce::new(&built.lights).unwrap();
    let ward = WardBackend::new(&brute, PAPER_THRESHOLD).unwrap();
    let tree = LightOctree::build(&built.lights, &OctreeSettings::default()).unwrap();
    let octree = OctreeBackend::new(&tree, PAPER_THRESHOLD).unwrap();
    let cuts = LightTree::build(&built.lights, Representative::Brightest).unwrap();
    let lightcuts = LightcutsBackend::new(&cuts, LightcutsSettings::default()).unwrap();
    let grid = LightingGridHierarchy::build(&built.lights, &GridSettings::default()).unwrap();
    let lgh = LghBackend::new(&grid, 8.0).unwrap();

    let mut g = c.benchmark_group(format!("{}_{}_{lights}", scene.name(), surface.name()));
    g.sample_size(10);
    g.throughput(Throughput::Elements(points.len() as u64));
    g.bench_function("brute_force", |b| {
        b.iter(|| shade_all(&brute, black_box(&points)))
    });
    g.bench_function("ward", |b| b.iter(|| shade_all(&ward, black_box(&points))));
    g.bench_function("octree", |b| {
        b.iter(|| shade_all(&octree, black_box(&points)))
    });
    g.bench_function("lightcuts", |b| {
        b.iter(|| shade_all(&lightcuts, black_box(&points)))
    });
    g.bench_function("lgh_alpha8", |b| {
        b.iter(|| shade_all(&lgh, black_box(&points)))
    });
    g.finish();
}

fn paquette_scenes(c: &mut Criterion) {
    for scene in TestScene::ALL {
        for surface in [Surface::Diffuse, Surface::Specular] {
            bench_case(c, scene, surface, 4096);
        }
    }
}

criterion_group!(benches, paquette_scenes);
criterion_main!(benches);
