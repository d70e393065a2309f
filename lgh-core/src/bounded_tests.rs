//! The error-bounded backends against brute force, on the same random scenes: the light octree
//! and Ward's method keep their absolute bound at every point, Lightcuts keeps each cluster within
//! its bound, and all three converge to the exact answer as their thresholds shrink.

use alloc::vec::Vec;
use glam::Vec3;
use proptest::prelude::*;

use crate::backend::{BruteForce, ManyLights, ShadingPoint};
use crate::light::PointLight;
use crate::lightcuts::{LightTree, LightcutsBackend, LightcutsSettings, Representative};
use crate::octree::{LightOctree, OctreeBackend, OctreeSettings};
use crate::reflection::{reflected, Lobe};
use crate::testsets::{clumped_lights, shading_points};
use crate::ward::WardBackend;

/// Eq. (1) summed over every light in f64: the exact answer.
fn exact(point: &ShadingPoint, lights: &[PointLight]) -> [f64; 3] {
    lights.iter().fold([0.0; 3], |acc, l| {
        let r = reflected(point, l.position, l.intensity, Lobe::All);
        [0, 1, 2].map(|a| acc[a] + f64::from(r[a]))
    })
}

/// The shader every test uses: eq. (1), unoccluded.
fn shade<B: ManyLights>(backend: &B, point: &ShadingPoint) -> (Vec3, u32) {
    let mut shader = |s: &crate::LightSample| reflected(point, s.position, s.intensity, s.lobe);
    let r = backend.illuminate(point, &mut shader).unwrap();
    (r.radiance, r.lights)
}

/// Rounding allowance for a sum of `n` f32 terms of total `sum`: the first-order worst case
/// `n · 2⁻²⁴ · sum` of recursive summation (Higham, eq. 4.4). Anything beyond is a real error.
fn rounding(n: usize, sum: f64) -> f64 {
    n as f64 * f64::from(f32::EPSILON) * 0.5 * sum
}

/// The scene: clumped lights and shading points inside and around them.
fn scene(n: usize, seed: u64) -> (Vec<PointLight>, Vec<ShadingPoint>) {
    let lights = clumped_lights(n, seed);
    let (lo, hi) = crate::grid::bounds(&lights);
    let points = shading_points(lo, hi, 60, seed ^ 0x5EED);
    (lights, points)
}

/// The number of terms of eq. (1) the octree bounds separately at `point` (diffuse, specular).
fn terms(point: &ShadingPoint) -> f64 {
    match point.material {
        crate::Material::Phong { .. } => 2.0,
        _ => 1.0,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// The octree's guarantee (§4.2.2, §4.3.2): each term's error is at most T, so a point's
    /// error is at most T per term, per channel.
    #[test]
    fn octree_error_never_exceeds_the_threshold(
        n in 4usize..1500, seed in any::<u64>(), t_exp in -5.0f32..-1.0, max_leaf in 1usize..6,
    ) {
        let (lights, points) = scene(n, seed);
        let tree = LightOctree::build(&lights, &OctreeSettings { max_leaf, ..Default::default() })
            .unwrap();
        let t = libm::powf(10.0, t_exp);
        let backend = OctreeBackend::new(&tree, t).unwrap();
        for p in &points {
            let want = exact(p, &lights);
            let (got, _) = shade(&backend, p);
            for a in 0..3 {
                let err = (f64::from(got[a]) - want[a]).abs();
                let allowed = terms(p) * f64::from(t) + rounding(n, want[a]);
                prop_assert!(err <= allowed, "error {err} > {allowed} at {p:?}");
            }
        }
    }

    /// Ward's method with an absolute bound (Paquette's variant): error ≤ T per channel.
    #[test]
    fn ward_error_never_exceeds_the_threshold(
        n in 1usize..800, seed in any::<u64>(), t_exp in -5.0f32..-1.0,
    ) {
        let (lights, points) = scene(n, seed);
        let brute = BruteForce::new(&lights).unwrap();
        let t = libm::powf(10.0, t_exp);
        let backend = WardBackend::new(&brute, t).unwrap();
        for p in &points {
            let want = exact(p, &lights);
            let (got, _) = shade(&backend, p);
            for a in 0..3 {
                let err = (f64::from(got[a]) - want[a]).abs();
                prop_assert!(err <= f64::from(t) + rounding(n, want[a]));
            }
        }
    }
}

/// The octree, Ward and Lightcuts converge to brute force as their thresholds shrink: the largest
/// error over the points falls with the threshold and reaches rounding level.
#[test]
fn all_bounded_backends_converge_to_brute_force() {
    let n = 2000;
    let (lights, points) = scene(n, 7);
    let brute = BruteForce::new(&lights).unwrap();
    let tree = LightOctree::build(&lights, &OctreeSettings::default()).unwrap();
    let cuts = LightTree::build(&lights, Representative::Stochastic { seed: 1 }).unwrap();
    let largest_error = |backend: &dyn Fn(&ShadingPoint) -> (Vec3, u32)| {
        let (mut worst, mut lights_shaded) = (0.0f64, 0u64);
        for p in &points {
            let want = exact(p, &lights);
            let (got, count) = backend(p);
            lights_shaded += u64::from(count);
            for a in 0..3 {
                worst = worst.max((f64::from(got[a]) - want[a]).abs() / want[a].max(1e-3));
            }
        }
        (worst, lights_shaded as f64 / points.len() as f64)
    };
    let mut last = (0.0, 0.0, 0.0);
    for t in [1e-1f32, 1e-2, 1e-3, 1e-4, 1e-6] {
        let octree = OctreeBackend::new(&tree, t).unwrap();
        let ward = WardBackend::new(&brute, t).unwrap();
        let lc = LightcutsBackend::new(
            &cuts,
            LightcutsSettings {
                relative_error: t,
                max_cut: usize::MAX,
            },
        )
        .unwrap();
        let (eo, lo) = largest_error(&|p| shade(&octree, p));
        let (ew, _) = largest_error(&|p| shade(&ward, p));
        let (el, ll) = largest_error(&|p| shade(&lc, p));
        std::println!("T = {t:e}: relative error octree {eo:.2e} ({lo:.0} lights), ward {ew:.2e}, lightcuts {el:.2e} ({ll:.0} shader calls)");
        if t == 1e-1 {
            // The loose end approximates: far fewer lights than brute force, a visible error.
            assert!(lo < 0.5 * n as f64 && ll < 0.5 * n as f64, "{lo} {ll}");
            assert!(eo > 1e-3 && el > 1e-3, "{eo} {el}");
        }
        last = (eo, ew, el);
    }
    // At T = 10⁻⁶ every backend is at rounding level: a relative 2000 · 2⁻²⁴ ≈ 1.2·10⁻⁴ at most.
    let floor = rounding(n, 1.0);
    assert!(
        last.0 <= floor && last.1 <= floor && last.2 <= floor,
        "{last:?} > {floor}"
    );
}

/// Lightcuts' per-cluster bound: the exact value of a cluster and its estimate both lie in
/// `[0, bound]`, so their difference does too. Checked on every cluster of a tree, at many points.
#[test]
fn lightcuts_cluster_bounds_hold() {
    for representative in [
        Representative::Brightest,
        Representative::Stochastic { seed: 3 },
    ] {
        let (lights, points) = scene(300, 11);
        let tree = LightTree::build(&lights, representative).unwrap();
        for p in &points {
            for (k, c) in tree.clusters().iter().enumerate() {
                let Some(_) = c.children else { continue };
                let members: Vec<PointLight> = members(&tree, k);
                let want = exact(p, &members);
                let bound = c.error_bound(p);
                let rep = tree.lights()[c.representative as usize].position;
                let estimate = reflected(p, rep, c.intensity, Lobe::All);
                for a in 0..3 {
                    let b = f64::from(bound) * (1.0 + 1e-5);
                    assert!(want[a] <= b, "exact {} > bound {b}", want[a]);
                    assert!(
                        f64::from(estimate[a]) <= b,
                        "estimate {} > bound {b}",
                        estimate[a]
                    );
                }
            }
        }
    }
}

/// The lights of cluster `k`.
fn members(tree: &LightTree, k: usize) -> Vec<PointLight> {
    let mut out = Vec::new();
    let mut stack = alloc::vec![k];
    while let Some(i) = stack.pop() {
        let c = &tree.clusters()[i];
        match c.children {
            Some([a, b]) => stack.extend([a as usize, b as usize]),
            None => out.push(tree.lights()[c.representative as usize]),
        }
    }
    out
}
