//! A query allocates nothing: counted with a global allocator that tallies every allocation made
//! on this test's thread while a query runs.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use lgh_core::glam::Vec3;
use lgh_core::{
    testsets, BruteForce, GridSettings, LghBackend, LightingGridHierarchy, ManyLights, ShadingPoint,
};

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

struct Counting;

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(|c| c.get()) {
            ALLOCATIONS.with(|a| a.set(a.get() + 1));
        }
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> u64 {
    ALLOCATIONS.with(|a| a.set(0));
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    ALLOCATIONS.with(|a| a.get())
}

#[test]
fn queries_do_not_allocate() {
    let lights = testsets::explosion_shell(32);
    for settings in [
        GridSettings {
            h1: Some(2.0 / 32.0),
            ..Default::default()
        },
        GridSettings {
            prune_below: 1e-6,
            ..Default::default()
        },
    ] {
        let lgh = LightingGridHierarchy::build(&lights, &settings).unwrap();
        let backend = LghBackend::new(&lgh, 2.0).unwrap();
        let brute = BruteForce::new(&lights).unwrap();
        let points = testsets::query_points(Vec3::ZERO, Vec3::ONE, 200, 5);
        let b = lgh.blending(3.0).unwrap();
        let mut total = Vec3::ZERO;
        let n = allocations_during(|| {
            for &x in &points {
                lgh.query(x, &b, |s| total += s.intensity).unwrap();
                total += lgh.query_sum(x, &b, |s| s.intensity).unwrap().0;
                lgh.lights_within(1, x, 0.2, |_, d| total.x += d).unwrap();
                let mut shader = |s: &lgh_core::LightSample| s.intensity;
                total += backend
                    .illuminate(&ShadingPoint::in_medium(x), &mut shader)
                    .unwrap()
                    .radiance;
                total += brute.falloff_sum(x, lgh.h0()).unwrap();
            }
        });
        assert!(total.x > 0.0);
        assert_eq!(n, 0, "queries allocated {n} times");
    }
}

#[test]
fn the_counter_sees_allocations() {
    // The test above could not fail if the counter were broken: check that it counts.
    let n = allocations_during(|| {
        let v: Vec<u8> = Vec::with_capacity(std::hint::black_box(64));
        std::hint::black_box(&v);
    });
    assert_eq!(n, 1);
}
