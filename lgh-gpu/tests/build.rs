//! The hierarchy built on the GPU (`GpuBuilder`, `build.wgsl`) against lgh-core's build on the
//! same placement (`GpuGrid::settings`), level by level and vertex by vertex; its update and
//! rebuild against a fresh build, bit for bit; eq. (1)'s partition of unity and energy; and the
//! query through it against the CPU.
//!
//! **The tolerance, derived.** Both builds sum the same terms `w_i·I_i` (and `w_i·‖I_i‖·o`,
//! …) over the lights of a vertex's eight cells, in different orders, and the weights `w_i`
//! come from each light's place in its cell, which the GPU computes in f32 — `(p − o) / h1`,
//! two roundings, so off by at most `2u·t` for `t ≤ 2^bits` cells — and the CPU in f64, rounded
//! once. A place off by `δ` (in the level's cell units) moves a trilinear weight, a product of
//! three factors in `[0, 1]`, by at most `3δ`. With `δ = 2u(2^bits + 2)` and `n` the lights
//! summed, each sum is within `ε·S` of the other, `ε = 3δ + 2(n + 8)u` and `S` the same sum
//! with every weight 1. The centre (eq. 2) is a quotient of two such sums with offsets in
//! `[−1, 1]`: within `2ε·κ` cells, `κ = Σ‖I_i‖ / Σ w_i‖I_i‖`; the variance (eq. 4) within `8εκ`
//! cells², the size (eq. 5) within `4√3·εκ` cells; and the world position within a further
//! `3u` of its magnitude (the CPU places it in f64, the GPU in f32). Measured differences are
//! far below (printed, as a fraction of the bound).

mod common;

use std::collections::HashMap;

use common::{flicker, g_buffer, gpu};
use lgh_core::glam::Vec3;
use lgh_core::testsets::{clumped_lights, explosion_shell, uniform_cube};
use lgh_core::{luminance, LightingGridHierarchy, PointLight};
use lgh_gpu::reference;
use lgh_gpu::{BuiltLight, GpuBuilder, GpuError, GpuGrid};
use proptest::prelude::*;

const U: f64 = 1.0 / (1u64 << 24) as f64;

/// Per vertex of `level`: the sums with every weight 1 (`S` per channel, `Σ‖I‖`) and the
/// lights summed, from the input lights' level-ℓ cells.
fn unweighted(
    grid: &GpuGrid,
    lights: &[PointLight],
    level: u8,
) -> HashMap<[u32; 3], (Vec3, f32, u32)> {
    let h = grid.h(level) as f64;
    let mut sums = HashMap::new();
    for l in lights {
        let cell: [u32; 3] = core::array::from_fn(|a| {
            let t = (l.position[a] as f64 - grid.origin[a] as f64) / grid.h1 as f64;
            let c1 = t.floor().clamp(0.0, grid.max_cell() as f64) as u32;
            let _ = h;
            c1 >> (level - 1)
        });
        for k in 0..8u32 {
            let v = [
                cell[0] + (k & 1),
                cell[1] + ((k >> 1) & 1),
                cell[2] + (k >> 2),
            ];
            let e = sums.entry(v).or_insert((Vec3::ZERO, 0.0, 0));
            e.0 += l.intensity;
            e.1 += luminance(l.intensity);
            e.2 += 1;
        }
    }
    sums
}

/// Builds `lights` on the GPU and on the CPU with the same placement and checks every level's
/// every light within the derived bound; returns the largest difference over its bound.
fn levels_agree(name: &str, lights: &[PointLight]) -> f64 {
    let Some(gpu) = gpu() else { return 0.0 };
    let grid = GpuGrid::fitting(lights).unwrap();
    let mut builder = GpuBuilder::new(gpu, grid, 2.0).unwrap();
    builder.rebuild(lights).unwrap();
    let cpu = LightingGridHierarchy::build(lights, &grid.settings()).unwrap();
    assert_eq!(cpu.max_level(), grid.max_level());
    let delta = 2.0 * U * ((1u64 << grid.bits) as f64 + 2.0);
    let mut worst = 0.0f64;
    // Level 0: the input lights themselves, the same bits.
    let level0 = builder.read_level(0).unwrap();
    assert_eq!(level0.len(), lights.len());
    for l in &level0 {
        let input = lights[l.vertex[0] as usize];
        assert_eq!((l.position, l.intensity), (input.position, input.intensity));
    }
    for level in 1..=grid.max_level() {
        let built: HashMap<[u32; 3], BuiltLight> = builder
            .read_level(level)
            .unwrap()
            .into_iter()
            .map(|l| (l.vertex, l))
            .collect();
        let want = cpu.level(level);
        assert_eq!(built.len(), want.len(), "{name}: level {level}'s vertices");
        let sums = unweighted(&grid, lights, level);
        let h = grid.h(level) as f64;
        for (i, w) in want.iter().enumerate() {
            let vertex = cpu.vertex(level, i as u32).unwrap();
            let got = built
                .get(&vertex)
                .unwrap_or_else(|| panic!("{name}: vertex {vertex:?}"));
            let (s, s_lum, n) = sums[&vertex];
            let eps = 3.0 * delta + 2.0 * (n as f64 + 8.0) * U;
            let kappa = if w.luminance > 0.0 {
                (s_lum as f64 / w.luminance as f64).max(1.0)
            } else {
                1.0
            };
            let mut check = |what: &str, a: f64, b: f64, bound: f64| {
                let diff = (a - b).abs();
                assert!(
                    diff <= bound,
                    "{name}: level {level} vertex {vertex:?} {what}: GPU {a} against CPU {b}: \
                     {diff:e} over {bound:e}"
                );
                if bound > 0.0 {
                    worst = worst.max(diff / bound);
                }
            };
            for a in 0..3 {
                let (g, c) = (got.intensity[a] as f64, w.intensity[a] as f64);
                check("intensity", g, c, eps * s[a] as f64 + U * c.abs());
                let place = 3.0 * U * (w.position[a].abs() as f64 + h);
                let (g, c) = (got.position[a] as f64, w.position[a] as f64);
                check("centre", g, c, 2.0 * eps * kappa * h + place);
                let (g, c) = (got.variance[a] as f64, w.variance[a] as f64);
                check(
                    "variance",
                    g,
                    c,
                    8.0 * eps * kappa * h * h + 4.0 * U * c.abs(),
                );
            }
            let (g, c) = (got.size as f64, w.size as f64);
            check(
                "size",
                g,
                c,
                4.0 * 3f64.sqrt() * eps * kappa * h + 4.0 * U * c.abs(),
            );
        }
    }
    eprintln!("{name}: largest difference {worst:.3} of the bound");
    worst
}

#[test]
fn levels_agree_with_lgh_core_on_uniform_lights() {
    levels_agree("uniform", &uniform_cube(3000, 1));
}

#[test]
fn levels_agree_with_lgh_core_on_clumped_lights() {
    levels_agree("clumped", &clumped_lights(3000, 2));
}

/// Over 4096 lights the coarse levels split each vertex's sums over several workgroups.
#[test]
fn levels_agree_with_lgh_core_when_vertices_split_their_sums() {
    levels_agree("uniform, split", &uniform_cube(9000, 3));
}

#[test]
fn levels_agree_with_lgh_core_on_an_explosion() {
    levels_agree("explosion", &explosion_shell(20));
}

/// Every level of `builder`, read back.
fn all_levels(builder: &GpuBuilder) -> Vec<Vec<BuiltLight>> {
    (0..=builder.grid().max_level())
        .map(|l| builder.read_level(l).unwrap())
        .collect()
}

/// New intensities through `update_intensities` give the bits of a rebuild with them, and the
/// same lights give the same bits on every run; lights that moved (and changed in number)
/// rebuild to the bits of a fresh builder.
#[test]
fn updates_and_rebuilds_give_the_bits_of_a_fresh_build() {
    let Some(gpu) = gpu() else { return };
    let lights = clumped_lights(2000, 3);
    let grid = GpuGrid::fitting(&lights).unwrap();
    let points = g_buffer(&lights, 300, 4);
    let fresh = |lights: &[PointLight]| {
        let mut b = GpuBuilder::new(gpu, grid, 2.0).unwrap();
        b.rebuild(lights).unwrap();
        b
    };
    let mut builder = fresh(&lights);
    for frame in 1..4 {
        let flicker = flicker(&lights, frame);
        builder.update_intensities(&flicker).unwrap();
        let relit: Vec<PointLight> = lights
            .iter()
            .zip(&flicker)
            .map(|(l, &i)| PointLight::new(l.position, i))
            .collect();
        let other = fresh(&relit);
        let (a, b) = (all_levels(&builder), all_levels(&other));
        for (level, (x, y)) in a.iter().zip(&b).enumerate() {
            assert_eq!(x.len(), y.len(), "frame {frame}, level {level}: lights");
            if let Some(k) = (0..x.len()).find(|&k| x[k] != y[k]) {
                panic!(
                    "frame {frame}, level {level}, light {k}: {:?} against {:?}",
                    x[k], y[k]
                );
            }
        }
        let shade = builder.hierarchy().shade(&points).unwrap();
        assert_eq!(shade, other.hierarchy().shade(&points).unwrap());
        assert_eq!(shade, fresh(&relit).hierarchy().shade(&points).unwrap());
    }
    for frame in 1..4 {
        let moved: Vec<PointLight> = lights[..2000 - 300 * frame]
            .iter()
            .map(|l| PointLight::new(l.position + Vec3::splat(0.05 * frame as f32), l.intensity))
            .collect();
        builder.rebuild(&moved).unwrap();
        assert_eq!(
            all_levels(&builder),
            all_levels(&fresh(&moved)),
            "moved {frame}"
        );
    }
}

/// The query through the GPU's build at `points` against lgh-core's query on `cpu`, within
/// 1e-3 of each point; returns the largest relative difference.
fn query_agrees(
    name: &str,
    builder: &GpuBuilder,
    cpu: &LightingGridHierarchy,
    alpha: f32,
    points: &[lgh_gpu::ShadingPoint],
) -> f32 {
    let got = builder.hierarchy().shade(points).unwrap();
    let blending = cpu.blending(alpha).unwrap();
    let mut worst = 0.0f32;
    for (p, g) in points.iter().zip(&got) {
        let want = reference::shade(cpu, &blending, p).unwrap();
        let diff = (Vec3::from(*g) - want).abs().max_element();
        let scale = want.max_element().max(1e-30);
        worst = worst.max(diff / scale);
        assert!(
            diff <= 1e-3 * scale,
            "{name} α {alpha}: {g:?} against {want}"
        );
    }
    worst
}

/// The query through the GPU's build against lgh-core's query on lgh-core's build: the build's
/// differences (above) move each term by a relative ~1e-4 at most (a centre off by `2εκ h_ℓ`
/// at a distance of at least `r_{ℓ−1} = α h_ℓ / 2`), so each point within 1e-3 of the CPU.
#[test]
fn the_query_through_the_gpu_build_agrees_with_the_cpu() {
    let Some(gpu) = gpu() else { return };
    for (name, lights) in [
        ("uniform", uniform_cube(2000, 5)),
        ("clumped", clumped_lights(2000, 6)),
    ] {
        let grid = GpuGrid::fitting(&lights).unwrap();
        let cpu = LightingGridHierarchy::build(&lights, &grid.settings()).unwrap();
        let points = g_buffer(&lights, 1000, 7);
        for alpha in [1.0, 2.0, 4.0] {
            let mut builder = GpuBuilder::new(gpu, grid, alpha).unwrap();
            builder.rebuild(&lights).unwrap();
            let worst = query_agrees(name, &builder, &cpu, alpha, &points);
            eprintln!("{name}, α = {alpha}: largest relative difference {worst:e}");
        }
    }
}

/// The same, frame after frame, for flickering lights (the GPU's and lgh-core's
/// `update_intensities`) and moving ones (both rebuilt), on a grid that holds every frame.
#[test]
fn the_query_through_the_gpu_build_agrees_with_the_cpu_on_flickering_and_moving_lights() {
    let Some(gpu) = gpu() else { return };
    let lights = clumped_lights(2000, 8);
    let step = Vec3::new(0.05, -0.03, 0.02);
    let (lo, hi) = lgh_core::bounds(&lights);
    let fitted = GpuGrid::fitting(&lights).unwrap();
    let grid = GpuGrid::enclosing(lo - step.abs() * 4.0, hi + step.abs() * 4.0, fitted.h1).unwrap();
    let points = g_buffer(&lights, 400, 9);
    let mut builder = GpuBuilder::new(gpu, grid, 2.0).unwrap();
    builder.rebuild(&lights).unwrap();
    // The moving lights' own builder, rebuilt each frame (any count: a few fewer each frame).
    let mut mover = GpuBuilder::new(gpu, grid, 2.0).unwrap();
    let mut cpu = LightingGridHierarchy::build(&lights, &grid.settings()).unwrap();
    let mut worst = 0.0f32;
    for frame in 1..4 {
        let flicker = flicker(&lights, frame);
        builder.update_intensities(&flicker).unwrap();
        cpu.update_intensities(&flicker).unwrap();
        worst = worst.max(query_agrees("flickering", &builder, &cpu, 2.0, &points));
        let moved: Vec<PointLight> = lights[..2000 - 100 * frame]
            .iter()
            .zip(&flicker)
            .map(|(l, &i)| PointLight::new(l.position + step * frame as f32, i))
            .collect();
        mover.rebuild(&moved).unwrap();
        let rebuilt = LightingGridHierarchy::build(&moved, &grid.settings()).unwrap();
        worst = worst.max(query_agrees("moving", &mover, &rebuilt, 2.0, &points));
    }
    eprintln!("flickering and moving: largest relative difference {worst:e}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Eq. (1)'s weights are a partition of unity, so every level holds all the input
    /// intensity (within the summation's `(8n + 8)u` of it); one light alone is its own light
    /// at every vertex's total.
    #[test]
    fn every_level_holds_all_the_light(
        seed in 0u64..1000,
        n in 1usize..400,
    ) {
        let Some(gpu) = gpu() else { return Ok(()) };
        let lights = clumped_lights(n, seed);
        let mut builder = GpuBuilder::new(gpu, GpuGrid::fitting(&lights).unwrap(), 2.0).unwrap();
        builder.rebuild(&lights).unwrap();
        let total: Vec3 = lights.iter().map(|l| l.intensity).sum();
        for level in 0..=builder.grid().max_level() {
            let sum: Vec3 = builder.read_level(level).unwrap().iter().map(|l| l.intensity).sum();
            let bound = (8 * n + 8) as f32 * U as f32 * 4.0 * total.max_element();
            prop_assert!((sum - total).abs().max_element() <= bound, "level {level}: {sum} of {total}");
        }
    }
}

#[test]
fn bad_lights_are_refused_and_nothing_is_lost() {
    let Some(gpu) = gpu() else { return };
    let lights = uniform_cube(50, 9);
    let grid = GpuGrid::fitting(&lights).unwrap();
    let mut builder = GpuBuilder::new(gpu, grid, 2.0).unwrap();
    builder.rebuild(&lights).unwrap();
    let before = all_levels(&builder);
    let mut bad = lights.clone();
    bad[7].position.y = f32::NAN;
    assert!(matches!(builder.rebuild(&bad), Err(GpuError::Build(_))));
    // A negative luminance (a negative channel alone is a colour outside Rec. 709's gamut,
    // which the build takes, as lgh-core's).
    let mut dim = vec![Vec3::ONE; 50];
    dim[3] = Vec3::new(0.0, -1.0, 0.0);
    assert!(matches!(
        builder.update_intensities(&dim),
        Err(GpuError::Build(_))
    ));
    assert!(matches!(
        builder.update_intensities(&dim[..10]),
        Err(GpuError::Build(_))
    ));
    assert_eq!(
        all_levels(&builder),
        before,
        "a refused call changes nothing"
    );
    assert!(matches!(
        GpuBuilder::new(gpu, grid, 0.0),
        Err(GpuError::Query(_))
    ));
    assert!(GpuGrid::enclosing(Vec3::ZERO, Vec3::splat(f32::INFINITY), 1.0).is_err());
    let mut out_of_gamut = vec![Vec3::ONE; 50];
    out_of_gamut[3] = Vec3::new(3.264, 0.434, -0.064);
    builder.update_intensities(&out_of_gamut).unwrap();
    // No lights: every point dark.
    builder.rebuild(&[]).unwrap();
    let dark = builder.hierarchy().shade(&g_buffer(&lights, 5, 1)).unwrap();
    assert!(dark.iter().all(|c| *c == [0.0; 3]));
}
