//! Properties of the built hierarchy (eqs. 1, 2, 4, 5) and its query (eq. 3).
#![allow(clippy::needless_range_loop)] // per-axis loops read best indexed

mod common;

use std::collections::HashMap;

use common::*;
use lgh_core::glam::Vec3;
use lgh_core::{
    luminance, BuildError, GridSettings, LevelSource, LightingGridHierarchy, PointLight, QueryError,
};
use proptest::prelude::*;
use wasm_bindgen_test::wasm_bindgen_test;

// In a browser (wasm32), see docs/embedding.md.
wasm_bindgen_test::wasm_bindgen_test_configure!(run_in_browser);

fn settings(h1: f32, levels: u8) -> GridSettings {
    GridSettings {
        h1: Some(h1),
        max_level: Some(levels),
        ..Default::default()
    }
}

/// Eqs. (1), (2), (4), (5) computed directly in f64 with a hash map, one level at a time.
struct NaiveVertex {
    i: [f64; 3],
    v: f64,
    p: [f64; 3],
    p2: [f64; 3],
    s: f64,
    /// Σ I_j over the lights with w_ij > 0: the scale of the absolute rounding error of I_ℓi.
    support: [f64; 3],
    /// Σ ‖I_j‖ over the same lights: the scale of the rounding error of Σ v.
    support_lum: f64,
}

fn naive_level(lights: &[PointLight], origin: Vec3, h: f64) -> HashMap<[i64; 3], NaiveVertex> {
    let mut map: HashMap<[i64; 3], NaiveVertex> = HashMap::new();
    let corners = |p: Vec3| {
        let t: Vec<f64> = (0..3)
            .map(|a| (p[a] as f64 - origin[a] as f64) / h)
            .collect();
        let c: Vec<f64> = t.iter().map(|x| x.floor()).collect();
        (0..8).filter_map(move |k: usize| {
            let mut w = 1.0;
            let mut q = [0i64; 3];
            for a in 0..3 {
                let bit = (k >> a) & 1;
                let f = t[a] - c[a];
                w *= if bit == 1 { f } else { 1.0 - f };
                q[a] = c[a] as i64 + bit as i64;
            }
            (w > 0.0).then_some((q, w))
        })
    };
    for l in lights {
        let lum = luminance(l.intensity) as f64;
        for (q, w) in corners(l.position) {
            let e = map.entry(q).or_insert(NaiveVertex {
                i: [0.0; 3],
                v: 0.0,
                p: [0.0; 3],
                p2: [0.0; 3],
                s: 0.0,
                support: [0.0; 3],
                support_lum: 0.0,
            });
            let v = w * lum;
            e.v += v;
            e.support_lum += lum;
            for a in 0..3 {
                e.i[a] += w * l.intensity[a] as f64;
                e.support[a] += l.intensity[a] as f64;
                e.p[a] += v * l.position[a] as f64;
                e.p2[a] += v * (l.position[a] as f64).powi(2);
            }
        }
    }
    for l in lights {
        let lum = luminance(l.intensity) as f64;
        for (q, w) in corners(l.position) {
            let e = map.get_mut(&q).unwrap();
            if e.v > 0.0 {
                let d2: f64 = (0..3)
                    .map(|a| (l.position[a] as f64 - e.p[a] / e.v).powi(2))
                    .sum();
                e.s += w * lum * d2.sqrt();
            }
        }
    }
    map
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The hierarchy's vertices match eqs. (1), (2), (4), (5) evaluated directly in f64.
    /// Tolerances: each trilinear weight carries an absolute error of a few ε (the in-cell
    /// coordinate is rounded to f32 relative to the cell), and the f32 sums have at most N + 8
    /// non-negative terms in a chain, so |ΔI_ℓi| ≤ (N + 12)·ε·Σ_j I0_j over the lights touching the
    /// vertex (≈ 2e-5 relative to that support for N ≤ 300). Centres, σ² and s are accumulated
    /// relative to their vertex in cell units (offsets o ∈ [−1, 1]); with η = (N + 12)·ε, the
    /// same argument bounds the errors of Σ v o, Σ v o² and Σ v by η·L (L = Σ ‖I_j‖ over the
    /// lights touching the vertex), so the centre is off by at most 2ηL/Σv cells, σ² by 6ηL/Σv
    /// cells² (E[o²] and the square of the centre) and s by 12ηL/Σv cells (|o − p| ≤ 2√3, plus the
    /// centre's error) — all in units of h_ℓ, never of the distance to the origin — plus the final
    /// f32 rounding. Vertices fed by tiny weights (small Σv) are rightly the least precise.
    #[wasm_bindgen_test(unsupported = test)]
    fn levels_match_the_equations(lights in lights_strategy(300, 4.0), h1 in 0.2f32..3.0) {
        let origin = Vec3::new(-5.0, -5.0, -5.0);
        let s = GridSettings { h1: Some(h1), origin: Some(origin), max_level: Some(4), ..Default::default() };
        let lgh = LightingGridHierarchy::build(&lights, &s).unwrap();
        let tol = (lights.len() as f64 + 12.0) * EPS;
        for l in 1..=lgh.max_level() {
            let h = lgh.h(l) as f64;
            let naive = naive_level(&lights, origin, h);
            let shift: Vec<i64> = (0..3)
                .map(|a| ((lgh.origin()[a] as f64 - origin[a] as f64) / h).round() as i64)
                .collect();
            let mut matched = 0;
            for (i, g) in lgh.level(l).iter().enumerate() {
                let v = lgh.vertex(l, i as u32).unwrap();
                let q = [v[0] as i64 + shift[0], v[1] as i64 + shift[1], v[2] as i64 + shift[2]];
                let Some(n) = naive.get(&q) else {
                    // A corner that received zero weight from every light.
                    prop_assert_eq!(g.intensity, Vec3::ZERO);
                    continue;
                };
                matched += 1;
                for a in 0..3 {
                    prop_assert!((g.intensity[a] as f64 - n.i[a]).abs() <= tol * n.support[a] + 1e-30,
                        "I level {} axis {}: {} vs {}", l, a, g.intensity[a], n.i[a]);
                }
                if n.v > 0.0 {
                    let rel = tol * n.support_lum / n.v;
                    for a in 0..3 {
                        let p = n.p[a] / n.v;
                        let var = n.p2[a] / n.v - p * p;
                        prop_assert!((g.position[a] as f64 - p).abs() <= 2.0 * rel * h + 4.0 * EPS * (p.abs() + h),
                            "p level {}: {} vs {}", l, g.position[a], p);
                        prop_assert!((g.variance[a] as f64 - var).abs() <= (6.0 * rel + 4.0 * EPS) * h * h,
                            "var level {}: {} vs {}", l, g.variance[a], var);
                    }
                    prop_assert!((g.size as f64 - n.s / n.v).abs() <= (12.0 * rel + 4.0 * EPS) * h,
                        "s level {}: {} vs {}", l, g.size, n.s / n.v);
                }
            }
            prop_assert_eq!(matched, naive.len());
        }
    }

    /// Per-level energy: Σ_i I_ℓi = Σ_j I0_j. Trilinear weights sum to one per light (each weight
    /// has ≤ 4 roundings) and every sum has non-negative terms and at most N + 8 additions in a chain,
    /// so the relative error is bounded by (N + 12)·ε.
    #[wasm_bindgen_test(unsupported = test)]
    fn energy_is_conserved_per_level(lights in lights_strategy(400, 10.0), h1 in 0.05f32..5.0) {
        let lgh = LightingGridHierarchy::build(&lights, &settings(h1, 6)).unwrap();
        let total: Vec<f64> = (0..3).map(|a| lights.iter().map(|l| l.intensity[a] as f64).sum()).collect();
        let tol = (lights.len() as f64 + 12.0) * EPS;
        for l in 0..=lgh.max_level() {
            for a in 0..3 {
                let sum: f64 = lgh.level(l).iter().map(|g| g.intensity[a] as f64).sum();
                prop_assert!((sum - total[a]).abs() <= tol * total[a] + 1e-30,
                    "level {} axis {}: {} vs {}", l, a, sum, total[a]);
            }
        }
    }

    /// Every illumination centre lies in the 2×2×2 block of cells around its vertex, σ² ≥ 0, s ≥ 0.
    #[wasm_bindgen_test(unsupported = test)]
    fn centres_stay_in_their_block(lights in lights_strategy(300, 50.0), h1 in 0.5f32..20.0,
                                   source in prop_oneof![Just(LevelSource::InputLights), Just(LevelSource::PreviousLevel)]) {
        let s = GridSettings { h1: Some(h1), source, ..Default::default() };
        let lgh = LightingGridHierarchy::build(&lights, &s).unwrap();
        let o = lgh.origin();
        for l in 1..=lgh.max_level() {
            let h = lgh.h(l);
            for (i, g) in lgh.level(l).iter().enumerate() {
                let v = lgh.vertex(l, i as u32).unwrap();
                let q = o + Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32) * h;
                // f32 rounding of the world position: a few ulps of its magnitude.
                let slack = 4.0 * f32::EPSILON * (q.abs().max_element() + h);
                prop_assert!(((g.position - q).abs().max_element()) <= h + slack,
                    "level {} centre {} vertex {} h {}", l, g.position, q, h);
                prop_assert!(g.variance.min_element() >= 0.0 && g.variance.is_finite());
                prop_assert!(g.size >= 0.0 && g.size.is_finite());
            }
        }
    }

    /// Linearity in the intensities: doubling every intensity doubles every level's intensities and
    /// the query result and moves no centre — exactly, since scaling by 2 is exact in floating point.
    #[wasm_bindgen_test(unsupported = test)]
    fn linear_in_intensity(lights in lights_strategy(200, 3.0), alpha in 0.5f32..6.0, x in (-6.0f32..6.0, -6.0f32..6.0, -6.0f32..6.0)) {
        let x = Vec3::new(x.0, x.1, x.2);
        let doubled: Vec<PointLight> = lights.iter().map(|l| PointLight::new(l.position, l.intensity * 2.0)).collect();
        let a = LightingGridHierarchy::build(&lights, &settings(0.7, 5)).unwrap();
        let b = LightingGridHierarchy::build(&doubled, &settings(0.7, 5)).unwrap();
        for l in 0..=a.max_level() {
            for (ga, gb) in a.level(l).iter().zip(b.level(l).iter()) {
                prop_assert_eq!(ga.intensity * 2.0, gb.intensity);
                prop_assert_eq!(ga.position, gb.position);
                prop_assert_eq!(ga.variance, gb.variance);
                prop_assert_eq!(ga.size, gb.size);
            }
        }
        let ba = a.blending(alpha).unwrap();
        prop_assert_eq!(lgh_sum(&a, &ba, x).0 * 2.0, lgh_sum(&b, &ba, x).0);
    }

    /// Additivity (the other half of linearity): levels of A ∪ B carry I(A) + I(B), within the
    /// f32 summation bound used above.
    #[wasm_bindgen_test(unsupported = test)]
    fn additive_in_intensity(lights in lights_strategy(200, 3.0)) {
        let half: Vec<PointLight> = lights.iter().map(|l| PointLight::new(l.position, l.intensity * 0.25)).collect();
        let rest: Vec<PointLight> = lights.iter().map(|l| PointLight::new(l.position, l.intensity * 0.75)).collect();
        let all = LightingGridHierarchy::build(&lights, &settings(0.7, 4)).unwrap();
        let a = LightingGridHierarchy::build(&half, &settings(0.7, 4)).unwrap();
        let b = LightingGridHierarchy::build(&rest, &settings(0.7, 4)).unwrap();
        let tol = 2.0 * (lights.len() as f64 + 12.0) * EPS;
        for l in 1..=all.max_level() {
            for ((g, ga), gb) in all.level(l).iter().zip(a.level(l).iter()).zip(b.level(l).iter()) {
                for c in 0..3 {
                    let want = ga.intensity[c] as f64 + gb.intensity[c] as f64;
                    prop_assert!((g.intensity[c] as f64 - want).abs() <= tol * want + 1e-30);
                }
            }
        }
    }

    /// The order of the input lights does not matter: bit-identical levels and query results.
    #[wasm_bindgen_test(unsupported = test)]
    fn independent_of_input_order(lights in lights_strategy(300, 5.0), seed in any::<u64>(),
                                  x in (-6.0f32..6.0, -6.0f32..6.0, -6.0f32..6.0)) {
        let x = Vec3::new(x.0, x.1, x.2);
        let mut shuffled = lights.clone();
        let mut rng = lgh_core::random::SplitMix64(seed);
        for i in (1..shuffled.len()).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            shuffled.swap(i, j);
        }
        for source in [LevelSource::InputLights, LevelSource::PreviousLevel] {
            let s = GridSettings { source, ..Default::default() };
            let a = LightingGridHierarchy::build(&lights, &s).unwrap();
            let b = LightingGridHierarchy::build(&shuffled, &s).unwrap();
            prop_assert_eq!(a.max_level(), b.max_level());
            for l in 0..=a.max_level() {
                prop_assert_eq!(a.level(l), b.level(l));
            }
            let bl = a.blending(2.0).unwrap();
            let (sa, na) = lgh_sum(&a, &bl, x);
            let (sb, nb) = lgh_sum(&b, &bl, x);
            prop_assert_eq!(sa, sb);
            prop_assert_eq!(na, nb);
        }
    }

    /// The radius query finds exactly the lights with non-zero weight: the same count as a naive
    /// loop over every light of every level, and the same sum up to summation order (f32, ≤ N + L
    /// non-negative terms).
    #[wasm_bindgen_test(unsupported = test)]
    fn query_finds_every_contributing_light(lights in lights_strategy(500, 8.0), h1 in 0.1f32..4.0,
                                            alpha in 0.3f32..9.0, prune in prop_oneof![Just(0.0f32), 0.0f32..3.0],
                                            x in (-15.0f32..15.0, -15.0f32..15.0, -15.0f32..15.0)) {
        let x = Vec3::new(x.0, x.1, x.2);
        let s = GridSettings { h1: Some(h1), prune_below: prune, ..Default::default() };
        let lgh = LightingGridHierarchy::build(&lights, &s).unwrap();
        let b = lgh.blending(alpha).unwrap();
        let (fast, nf) = lgh_sum(&lgh, &b, x);
        let (slow, ns) = naive_lgh(&lgh, &b, x);
        prop_assert_eq!(nf, ns);
        let tol = 2.0 * (ns as f32 + 8.0) * f32::EPSILON;
        prop_assert!((fast - slow).abs().max_element() <= tol * slow.max_element() + 1e-30,
            "{} vs {}", fast, slow);
    }

    /// `lights_within` reports exactly the active lights of a level within the radius.
    #[wasm_bindgen_test(unsupported = test)]
    fn lights_within_matches_a_linear_search(lights in lights_strategy(400, 6.0), h1 in 0.1f32..3.0,
                                             radius in 0.0f32..8.0, level in 0u8..6,
                                             x in (-8.0f32..8.0, -8.0f32..8.0, -8.0f32..8.0)) {
        let x = Vec3::new(x.0, x.1, x.2);
        let lgh = LightingGridHierarchy::build(&lights, &settings(h1, 5)).unwrap();
        let mut got = Vec::new();
        lgh.lights_within(level, x, radius, |i, d| got.push((i, d))).unwrap();
        got.sort_by_key(|t| t.0);
        let want: Vec<u32> = lgh.level(level).iter().enumerate()
            .filter(|(_, g)| lgh.is_active(level, g) && (g.position - x).length_squared() < radius * radius)
            .map(|(i, _)| i as u32)
            .collect();
        prop_assert_eq!(got.iter().map(|t| t.0).collect::<Vec<_>>(), want);
        for (i, d) in got {
            prop_assert!((d - (lgh.level(level).get(i as usize).position - x).length()).abs() <= 1e-5 * (1.0 + d));
        }
    }

    /// A rebuild with new intensities equals a fresh build, bit for bit.
    #[wasm_bindgen_test(unsupported = test)]
    fn rebuild_equals_fresh_build(lights in lights_strategy(300, 4.0), seed in any::<u64>(),
                                  source in prop_oneof![Just(LevelSource::InputLights), Just(LevelSource::PreviousLevel)]) {
        let mut lights = lights;
        // Some coincident lights, whose order depends on intensity.
        if lights.len() > 3 {
            lights[1].position = lights[0].position;
            lights[2].position = lights[0].position;
        }
        let s = GridSettings { source, h1: Some(0.5), ..Default::default() };
        let mut lgh = LightingGridHierarchy::build(&lights, &s).unwrap();
        let mut rng = lgh_core::random::SplitMix64(seed);
        let next: Vec<PointLight> = lights.iter()
            .map(|l| PointLight::new(l.position, Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0))
            .collect();
        let intensities: Vec<Vec3> = next.iter().map(|l| l.intensity).collect();
        lgh.update_intensities(&intensities).unwrap();
        let fresh = LightingGridHierarchy::build(&next, &s).unwrap();
        for l in 0..=fresh.max_level() {
            prop_assert_eq!(lgh.level(l), fresh.level(l));
        }
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn converges_to_brute_force_as_alpha_grows() {
    let lights = lgh_core::testsets::uniform_cube(3000, 5);
    let lgh = LightingGridHierarchy::build(
        &lights,
        &GridSettings {
            h1: Some(0.05),
            ..Default::default()
        },
    )
    .unwrap();
    let points = lgh_core::testsets::query_points(Vec3::ZERO, Vec3::ONE, 200, 9);
    let mut previous = f64::INFINITY;
    for alpha in [0.5f32, 1.0, 2.0, 4.0, 8.0, 40.0] {
        let b = lgh.blending(alpha).unwrap();
        let mut sq = 0.0;
        let mut mean = 0.0;
        for &x in &points {
            let r = lum64(brute_f64(&lights, x, lgh.h0()));
            let a = lgh_core::luminance(lgh_sum(&lgh, &b, x).0) as f64;
            sq += (a - r) * (a - r);
            mean += r;
        }
        let rel = (sq / points.len() as f64).sqrt() / (mean / points.len() as f64);
        eprintln!("alpha {alpha}: relative RMSE {rel:.2e}");
        assert!(
            rel < previous,
            "error must shrink with alpha: {rel} after {previous}"
        );
        previous = rel;
    }
    // α = 40: r_0 = 1 covers the whole unit cube, so every point inside the cube sees level 0 only
    // with B_0 = 1 for lights within r_0; the remaining error is f32 summation order plus far points.
    assert!(previous < 1e-3, "{previous}");
}

#[wasm_bindgen_test(unsupported = test)]
fn continuous_along_a_line() {
    // L(x) along a line must have no jumps at level boundaries: between samples δ apart, the change
    // is bounded by the derivative of a smooth function (the light sum), never a step.
    let lights = lgh_core::testsets::uniform_cube(2000, 3);
    let lgh = LightingGridHierarchy::build(
        &lights,
        &GridSettings {
            h1: Some(0.04),
            ..Default::default()
        },
    )
    .unwrap();
    let b = lgh.blending(2.0).unwrap();
    let from = Vec3::new(-1.0, 0.3, 0.7);
    let to = Vec3::new(2.0, 0.6, 0.2);
    let n = 20_000;
    let vals: Vec<f64> = (0..=n)
        .map(|i| {
            let x = from + (to - from) * (i as f32 / n as f32);
            luminance(lgh_sum(&lgh, &b, x).0) as f64
        })
        .collect();
    // Compare each step with its neighbours: a jump shows up as one step much larger than the
    // steps around it (a smooth function's consecutive differences vary slowly).
    let steps: Vec<f64> = vals.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    let scale = vals.iter().cloned().fold(0.0, f64::max);
    for i in 2..steps.len() - 2 {
        let around = steps[i - 2]
            .max(steps[i - 1])
            .max(steps[i + 1])
            .max(steps[i + 2]);
        assert!(
            steps[i] <= 3.0 * around + 1e-5 * scale,
            "jump at sample {i}: step {} vs neighbours {}",
            steps[i],
            around
        );
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn bad_input_is_a_typed_error_or_a_correct_result() {
    let ok = PointLight::new(Vec3::ZERO, Vec3::ONE);
    let d = GridSettings::default();
    // No lights: an empty hierarchy.
    let empty = LightingGridHierarchy::build(&[], &d).unwrap();
    let b = empty.blending(2.0).unwrap();
    assert_eq!(lgh_sum(&empty, &b, Vec3::ONE), (Vec3::ZERO, 0));
    // One light, and all lights at one point: exact answers.
    for n in [1usize, 50] {
        let lights = vec![PointLight::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, 0.5)); n];
        let lgh = LightingGridHierarchy::build(&lights, &d).unwrap();
        for alpha in [0.5f32, 2.0] {
            let b = lgh.blending(alpha).unwrap();
            for x in [
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(4.0, -2.0, 0.0),
                Vec3::splat(100.0),
            ] {
                let want = brute_f64(&lights, x, lgh.h0());
                let got = lgh_sum(&lgh, &b, x).0;
                for a in 0..3 {
                    assert!(
                        (got[a] as f64 - want[a]).abs() <= 1e-5 * want[a],
                        "{got} vs {want:?}"
                    );
                }
            }
        }
    }
    let bad = |l: PointLight| LightingGridHierarchy::build(&[ok, l], &d).unwrap_err();
    assert_eq!(
        bad(PointLight::new(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ONE)),
        BuildError::NonFinitePosition { index: 1 }
    );
    assert_eq!(
        bad(PointLight::new(
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::ONE
        )),
        BuildError::NonFinitePosition { index: 1 }
    );
    for i in [f32::NAN, f32::INFINITY, -1.0] {
        assert_eq!(
            bad(PointLight::new(Vec3::ZERO, Vec3::new(1.0, i, 1.0))),
            BuildError::InvalidIntensity { index: 1 }
        );
    }
    for h1 in [0.0f32, -1.0, f32::NAN, f32::INFINITY] {
        assert!(matches!(
            LightingGridHierarchy::build(&[ok], &GridSettings { h1: Some(h1), ..d }),
            Err(BuildError::InvalidSpacing { .. })
        ));
    }
    assert!(matches!(
        LightingGridHierarchy::build(
            &[ok],
            &GridSettings {
                max_level: Some(99),
                ..d
            }
        ),
        Err(BuildError::TooManyLevels { .. })
    ));
    assert!(matches!(
        LightingGridHierarchy::build(
            &[ok],
            &GridSettings {
                prune_below: -1.0,
                ..d
            }
        ),
        Err(BuildError::InvalidThreshold { .. })
    ));
    let lgh = LightingGridHierarchy::build(&[ok], &d).unwrap();
    for a in [0.0f32, -2.0, f32::NAN, f32::INFINITY] {
        assert!(matches!(
            lgh.blending(a),
            Err(QueryError::InvalidAlpha { .. })
        ));
    }
    let b = lgh.blending(2.0).unwrap();
    assert_eq!(
        lgh.query(Vec3::new(f32::NAN, 0.0, 0.0), &b, |_| {}),
        Err(QueryError::NonFinitePoint)
    );
    let other = LightingGridHierarchy::build(&[ok], &GridSettings { h1: Some(3.0), ..d }).unwrap();
    assert_eq!(
        other.query(Vec3::ZERO, &b, |_| {}),
        Err(QueryError::BlendingMismatch)
    );

    // Lights 10⁶ units apart: a tiny h1 is refused (it would need 10⁹ cells per axis) rather than
    // allocating a dense grid; a coarser h1 gives a sparse hierarchy and exact answers near each light.
    let far = [ok, PointLight::new(Vec3::new(1e6, 0.0, -1e6), Vec3::ONE)];
    assert!(matches!(
        LightingGridHierarchy::build(
            &far,
            &GridSettings {
                h1: Some(1e-3),
                ..d
            }
        ),
        Err(BuildError::GridTooFine { .. })
    ));
    let lgh = LightingGridHierarchy::build(&far, &GridSettings { h1: Some(2.0), ..d }).unwrap();
    assert!(lgh.level(1).len() <= 16);
    for alpha in [1.0f32, 4.0, 1e3] {
        let b = lgh.blending(alpha).unwrap();
        for x in [
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(5e5, 0.0, -5e5),
            Vec3::new(1e6, 3.0, -1e6),
        ] {
            let want = lum64(brute_f64(&far, x, lgh.h0()));
            let got = luminance(lgh_sum(&lgh, &b, x).0) as f64;
            assert!(
                (got - want).abs() <= 0.05 * want,
                "alpha {alpha} x {x}: {got} vs {want}"
            );
        }
    }
    // Automatic h1 on the same pair must also stay sparse.
    let auto = LightingGridHierarchy::build(&far, &d).unwrap();
    assert!(auto.level(1).len() <= 16);
    // Rebuild with the wrong count or bad values.
    let mut lgh = LightingGridHierarchy::build(&[ok, ok], &d).unwrap();
    assert_eq!(
        lgh.update_intensities(&[Vec3::ONE]),
        Err(BuildError::LengthMismatch {
            expected: 2,
            got: 1
        })
    );
    assert_eq!(
        lgh.update_intensities(&[Vec3::ONE, Vec3::splat(f32::NAN)]),
        Err(BuildError::InvalidIntensity { index: 1 })
    );
}

#[wasm_bindgen_test(unsupported = test)]
fn weak_lights_leave_fine_levels_but_reach_the_top() {
    let mut lights = lgh_core::testsets::uniform_cube(500, 1);
    for l in lights.iter_mut().take(250) {
        l.intensity *= 1e-4;
    }
    let s = GridSettings {
        h1: Some(0.1),
        prune_below: 1e-3,
        ..Default::default()
    };
    let lgh = LightingGridHierarchy::build(&lights, &s).unwrap();
    let top = lgh.max_level();
    let pruned0 = lgh.level(0).iter().filter(|g| !lgh.is_active(0, g)).count();
    assert_eq!(pruned0, 250);
    // The top level is never pruned and still carries all the energy.
    assert!(lgh
        .level(top)
        .iter()
        .all(|g| g.luminance == 0.0 || lgh.is_active(top, &g)));
    let total: f64 = lights.iter().map(|l| luminance(l.intensity) as f64).sum();
    let top_sum: f64 = lgh.level(top).iter().map(|g| g.luminance as f64).sum();
    assert!((top_sum - total).abs() < 1e-4 * total);

    // Setting the threshold afterwards gives the hierarchy built with it, bit for bit, and
    // setting it back to 0 the one built without; before and after new intensities.
    let unpruned = GridSettings {
        prune_below: 0.0,
        ..s
    };
    let mut later = LightingGridHierarchy::build(&lights, &unpruned).unwrap();
    let same_levels = |a: &LightingGridHierarchy, b: &LightingGridHierarchy| {
        (0..=a.max_level()).all(|l| a.level(l) == b.level(l))
    };
    assert!(!same_levels(&later, &lgh));
    later.set_prune_below(1e-3).unwrap();
    assert!(same_levels(&later, &lgh));
    let brighter: Vec<Vec3> = lights.iter().map(|l| l.intensity * 2.0).collect();
    later.update_intensities(&brighter).unwrap();
    let mut rebuilt = lights.clone();
    for (l, &i) in rebuilt.iter_mut().zip(&brighter) {
        l.intensity = i;
    }
    assert!(same_levels(
        &later,
        &LightingGridHierarchy::build(&rebuilt, &s).unwrap()
    ));
    later.set_prune_below(0.0).unwrap();
    assert!(same_levels(
        &later,
        &LightingGridHierarchy::build(&rebuilt, &unpruned).unwrap()
    ));
    assert!(later.set_prune_below(-1.0).is_err());
    assert_eq!(later.prune_below(), 0.0);
}

#[wasm_bindgen_test(unsupported = test)]
fn automatic_h1_follows_section_6_4() {
    // Refine until the non-empty level-1 vertices outnumber the lights.
    let lights = lgh_core::testsets::light_strings(4096);
    let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
    assert!(lgh.level(1).len() > lights.len());
    let coarser = LightingGridHierarchy::build(
        &lights,
        &GridSettings {
            h1: Some(lgh.h1() * 2.0),
            origin: Some(lgh.origin()),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        coarser.level(1).len() <= lights.len(),
        "h1 is not the coarsest such spacing"
    );
    // The automatic top level holds everything in one cell: at most 8 lights.
    assert!(lgh.level(lgh.max_level()).len() <= 8);
}

/// Edge cases found in review: each once panicked, looped, lost lights or produced NaN.
#[wasm_bindgen_test(unsupported = test)]
fn extreme_placements_are_errors_or_correct() {
    let d = GridSettings::default();
    let one = |x: f32| PointLight::new(Vec3::new(x, 0.0, 0.0), Vec3::ONE);

    // An empty hierarchy with levels answers radius queries with nothing.
    let empty = LightingGridHierarchy::build(
        &[],
        &GridSettings {
            max_level: Some(2),
            ..d
        },
    )
    .unwrap();
    for l in 0..=3 {
        empty
            .lights_within(l, Vec3::ZERO, 1.0, |_, _| panic!("no lights"))
            .unwrap();
    }

    // Extents beyond f32 range with automatic h1: no endless refinement; a typed error.
    let wide: Vec<PointLight> = (0..8).map(|i| one(-2e38 + i as f32 * 5e37)).collect();
    assert!(LightingGridHierarchy::build(&wide, &d).is_err());
    assert!(LightingGridHierarchy::build(&wide[..3], &d).is_err());

    // A given origin far from the lights: refused instead of collapsing the lights into one cell,
    // with automatic or explicit h1.
    let near: Vec<PointLight> = (0..8).map(|i| one(i as f32 * 1.3)).collect();
    for h1 in [None, Some(1.0)] {
        let s = GridSettings {
            origin: Some(Vec3::splat(1e30)),
            h1,
            ..d
        };
        assert!(matches!(
            LightingGridHierarchy::build(&near, &s),
            Err(BuildError::OriginTooFar { .. })
        ));
    }

    // Two lights one unit apart straddling 2^20 cells from the origin: accepted, and exact when
    // α makes level 0 cover both (r_0 = 20 units).
    let pair = [one(1048575.5), one(1048576.5)];
    let s = GridSettings {
        origin: Some(Vec3::ZERO),
        h1: Some(1.0),
        ..d
    };
    let lgh = LightingGridHierarchy::build(&pair, &s).unwrap();
    let b = lgh.blending(40.0).unwrap();
    let x = Vec3::new(1048578.0, 0.5, 0.0);
    let want = lum64(brute_f64(&pair, x, lgh.h0()));
    let got = luminance(lgh_sum(&lgh, &b, x).0) as f64;
    assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");

    // Huge spacings: variances stay finite (no inf·0) while they fit f32; beyond, a typed error.
    assert!(matches!(
        LightingGridHierarchy::build(&[one(0.0), one(1e20)], &d),
        Err(BuildError::InvalidSpacing { .. })
    ));
    let far = [one(0.0), one(1e18), one(3e17)];
    let lgh = LightingGridHierarchy::build(&far, &d).unwrap();
    for l in 0..=lgh.max_level() {
        assert!(lgh
            .level(l)
            .iter()
            .all(|g| g.variance.is_finite() && g.position.is_finite() && g.size.is_finite()));
    }
    // A spacing whose coarse levels overflow f32 is refused.
    let s = GridSettings {
        h1: Some(1e37),
        max_level: Some(8),
        ..d
    };
    assert!(matches!(
        LightingGridHierarchy::build(&near, &s),
        Err(BuildError::InvalidSpacing { .. })
    ));
    let s = GridSettings {
        h1: Some(1e-45),
        ..d
    };
    assert!(matches!(
        LightingGridHierarchy::build(&near, &s),
        Err(BuildError::InvalidSpacing { .. })
    ));

    // A query so far away that d² overflows f32 still reports the top-level light (weight 1).
    let lgh = LightingGridHierarchy::build(&[one(0.0)], &d).unwrap();
    let b = lgh.blending(1.0).unwrap();
    let n = lgh
        .query(Vec3::new(2e19, 0.0, 0.0), &b, |s| assert_eq!(s.weight, 1.0))
        .unwrap();
    assert_eq!(n, 1);

    // Blending of a level that does not exist is zero, not a panic.
    assert_eq!(b.weight(30, 1.0), 0.0);
    assert_eq!(b.support(30), (f32::INFINITY, f32::INFINITY));
    assert_eq!(b.radius(30), f32::INFINITY);
}

/// α values whose reciprocal radius rounds down put a tiny non-zero weight just past 2 r_ℓ; the
/// query must still report exactly the lights with non-zero weight (α = 0.21 is one such value).
#[wasm_bindgen_test(unsupported = test)]
fn lights_at_the_outer_radius_are_reported_iff_their_weight_is_positive() {
    for alpha in [0.21f32, 0.3, 0.7, 1.1, 2.0] {
        let lights: Vec<PointLight> = (0..400)
            .map(|i| PointLight::new(Vec3::new(i as f32 * 0.001, 0.0, 0.0), Vec3::ONE))
            .collect();
        let lgh = LightingGridHierarchy::build(&lights, &settings(1.0, 3)).unwrap();
        let b = lgh.blending(alpha).unwrap();
        for l in 0..=lgh.max_level() {
            let (_, outer) = b.support(l);
            if outer.is_finite() {
                // Probe exactly at the nominal outer radius 2 r_ℓ from a light.
                let x = lights[0].position - Vec3::new(2.0 * b.radius(l), 0.0, 0.0);
                let (fast, nf) = lgh_sum(&lgh, &b, x);
                let (slow, ns) = naive_lgh(&lgh, &b, x);
                assert_eq!(nf, ns, "alpha {alpha} level {l}");
                assert!((fast - slow).abs().max_element() <= 1e-5 * slow.max_element() + 1e-30);
            }
        }
    }
}
