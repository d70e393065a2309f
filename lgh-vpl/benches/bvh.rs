//! Criterion benches of our BVH against the `bvh` crate (0.13, nalgebra-based, binned SAH) on
//! the Sponza atrium (`../shared/data/meshes/sponza_dabrovic`, 66,454 triangles; skipped with a
//! message when absent): build time (theirs serial and with rayon), and closest hits of 8,192
//! camera rays through the atrium (coherent) and of 8,192 random rays between random points
//! inside it (incoherent).
//!
//! Both closest-hit loops run the same watertight triangle test ([`Ray::hit_triangle`]), so what
//! is compared is the hierarchy and its traversal. The `bvh` crate's traversal yields every
//! triangle whose box the ray enters (its distance-ordered iterators are "best effort", so a
//! closest hit cannot stop early on them); ours shrinks `t_max` as hits are found. Both loops'
//! answers are checked equal before timing.

use criterion::{criterion_group, criterion_main, Criterion};
use lgh_vpl::lgh_core::glam::Vec3;
use lgh_vpl::lgh_core::random::SplitMix64;
use lgh_vpl::{Bvh, Camera, Mesh, Ray};

use bvh::aabb::{Aabb, Bounded};
use bvh::bounding_hierarchy::{BHShape, BoundingHierarchy};
use nalgebra::{Point3, Vector3};

/// A triangle as the `bvh` crate wants it.
struct Shape {
    corners: [Vec3; 3],
    node: usize,
}

impl Bounded<f32, 3> for Shape {
    fn aabb(&self) -> Aabb<f32, 3> {
        let [a, b, c] = self.corners;
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        Aabb::with_bounds(Point3::from(lo.to_array()), Point3::from(hi.to_array()))
    }
}

impl BHShape<f32, 3> for Shape {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node = index;
    }

    fn bh_node_index(&self) -> usize {
        self.node
    }
}

fn shapes(mesh: &Mesh) -> Vec<Shape> {
    (0..mesh.triangles().len() as u32)
        .map(|t| Shape {
            corners: mesh.corners(t),
            node: 0,
        })
        .collect()
}

/// 128×64 camera rays down the atrium and 8,192 random segments' directions inside it.
/// Rays as (origin, direction).
type Rays = Vec<(Vec3, Vec3)>;

fn rays(mesh: &Mesh) -> (Rays, Rays) {
    let camera = Camera::new(
        Vec3::new(-14.0, 2.5, 0.5),
        Vec3::new(10.0, 5.0, -0.5),
        Vec3::Y,
        70.0,
        128,
        64,
    )
    .unwrap();
    let coherent = (0..64)
        .flat_map(|y| (0..128).map(move |x| (x, y)))
        .map(|(x, y)| camera.ray(x, y))
        .collect();
    let (lo, hi) = mesh.bounds();
    let (lo, hi) = (lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo));
    let mut rng = SplitMix64(1);
    let random = (0..8192)
        .map(|_| {
            let o = rng.next_in(lo, hi);
            (o, rng.next_in(lo, hi) - o)
        })
        .collect();
    (coherent, random)
}

/// Sum of the closest hits' t over `rays` through our BVH, and how many hit.
fn ours(bvh: &Bvh, rays: &[(Vec3, Vec3)]) -> (f64, usize) {
    rays.iter()
        .filter_map(|&(o, d)| bvh.intersect(&Ray::new(o, d)))
        .fold((0.0, 0), |(s, n), h| (s + f64::from(h.t), n + 1))
}

/// The same through the `bvh` crate's hierarchy.
fn theirs(bvh: &bvh::bvh::Bvh<f32, 3>, shapes: &[Shape], rays: &[(Vec3, Vec3)]) -> (f64, usize) {
    rays.iter()
        .filter_map(|&(o, d)| {
            let ray = Ray::new(o, d);
            let query = bvh::ray::Ray::new(Point3::from(o.to_array()), Vector3::from(d.to_array()));
            let mut best = f32::INFINITY;
            for s in bvh.traverse_iterator(&query, shapes) {
                if let Some((t, _, _)) = ray.hit_triangle(&s.corners, best) {
                    best = t;
                }
            }
            best.is_finite().then_some(best)
        })
        .fold((0.0, 0), |(s, n), t| (s + f64::from(t), n + 1))
}

fn sponza() -> Option<Mesh> {
    let path = lgh_tests::shared_data().join("meshes/sponza_dabrovic/sponza.obj");
    if !path.exists() {
        eprintln!("SKIPPED: {} is not here", path.display());
        return None;
    }
    Some(Mesh::load_obj(&path).unwrap())
}

fn bvh_vs_bvh_crate(c: &mut Criterion) {
    let Some(mesh) = sponza() else {
        return;
    };
    let n = mesh.triangles().len();
    let mut g = c.benchmark_group(format!("sponza_{n}_build"));
    g.sample_size(10);
    g.bench_function("ours", |b| b.iter(|| Bvh::new(&mesh)));
    g.bench_function("bvh_crate", |b| {
        b.iter_batched_ref(
            || shapes(&mesh),
            |s| bvh::bvh::Bvh::build(s),
            criterion::BatchSize::LargeInput,
        )
    });
    g.bench_function("bvh_crate_rayon", |b| {
        b.iter_batched_ref(
            || shapes(&mesh),
            |s| bvh::bvh::Bvh::build_par(s),
            criterion::BatchSize::LargeInput,
        )
    });
    g.finish();

    let ours_bvh = Bvh::new(&mesh);
    let mut their_shapes = shapes(&mesh);
    let their_bvh = bvh::bvh::Bvh::build(&mut their_shapes);
    println!(
        "ours: {} nodes, depth {}; bvh crate: {} nodes",
        ours_bvh.node_count(),
        ours_bvh.depth(),
        their_bvh.nodes.len()
    );
    let (coherent, random) = rays(&mesh);
    let mut g = c.benchmark_group(format!("sponza_{n}_closest_hit_8192_rays"));
    g.sample_size(10);
    for (name, rays) in [("camera", &coherent), ("random", &random)] {
        let (a, b) = (
            ours(&ours_bvh, rays),
            theirs(&their_bvh, &their_shapes, rays),
        );
        assert_eq!(a, b, "{name} rays: the two hierarchies disagree");
        println!("{name} rays: {} of {} hit", a.1, rays.len());
        g.bench_function(format!("ours_{name}"), |b| b.iter(|| ours(&ours_bvh, rays)));
        g.bench_function(format!("bvh_crate_{name}"), |b| {
            b.iter(|| theirs(&their_bvh, &their_shapes, rays))
        });
    }
    g.finish();
}

criterion_group!(benches, bvh_vs_bvh_crate);
criterion_main!(benches);
