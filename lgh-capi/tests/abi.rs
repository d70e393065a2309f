//! The C ABI called as C calls it: every function with NULL and out-of-range arguments gets an
//! error code and a message, never a crash; and what it computes is what the Rust API computes,
//! bit for bit.

use std::ffi::{c_void, CStr};
use std::ptr::{null, null_mut};

use lgh_capi::*;
use lgh_core::glam::Vec3;
use lgh_core::{falloff, GridSettings, LightingGridHierarchy, PointLight};

/// 512 lights on a jittered 8³ lattice with varied colours: flat arrays, as C holds them.
fn lights() -> (Vec<f32>, Vec<f32>) {
    let mut rng = lgh_core::random::SplitMix64(7);
    let (mut p, mut i) = (Vec::new(), Vec::new());
    for k in 0..512u32 {
        let c = Vec3::new((k % 8) as f32, (k / 8 % 8) as f32, (k / 64) as f32);
        let q = c + rng.next_in(Vec3::splat(-0.3), Vec3::splat(0.3));
        p.extend(q.to_array());
        i.extend(rng.next_in(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)).to_array());
    }
    (p, i)
}

/// The same lights for the Rust API.
fn point_lights(p: &[f32], i: &[f32]) -> Vec<PointLight> {
    p.chunks(3)
        .zip(i.chunks(3))
        .map(|(p, i)| PointLight::new(Vec3::from_slice(p), Vec3::from_slice(i)))
        .collect()
}

fn last_error() -> String {
    // SAFETY: lgh_last_error returns a live NUL-terminated string.
    unsafe { CStr::from_ptr(lgh_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// A hierarchy and a blending at α = 2 over [`lights`].
fn made() -> (*mut LghHierarchy, *mut LghBlending) {
    let (p, i) = lights();
    let mut h = null_mut();
    let mut b = null_mut();
    // SAFETY: valid arrays and out-pointers.
    unsafe {
        assert_eq!(
            lgh_hierarchy_create(p.as_ptr(), i.as_ptr(), 512, null(), &mut h),
            LghStatus::Ok
        );
        assert_eq!(lgh_blending_create(h, 2.0, &mut b), LghStatus::Ok);
    }
    (h, b)
}

/// A shading callback: the light's blended intensity over `max(d, h0)²`, `h0` read from `user`.
unsafe extern "C" fn lambert_free(light: *const LghLight, user: *mut c_void, out: *mut f32) {
    // SAFETY: lgh_sum passes a live light, our `user` (an f32) and three writable floats.
    unsafe {
        let (l, h0) = (&*light, *(user as *const f32));
        let g = falloff(l.distance, h0);
        for c in 0..3 {
            *out.add(c) = l.intensity[c] * g;
        }
    }
}

#[test]
fn queries_give_the_rust_apis_bits() {
    let (p, i) = lights();
    let rust =
        LightingGridHierarchy::build(&point_lights(&p, &i), &GridSettings::default()).unwrap();
    let blending = rust.blending(2.0).unwrap();
    let (h, b) = made();
    let mut info = LghInfo::default();
    // SAFETY: live objects and valid pointers throughout.
    unsafe {
        assert_eq!(lgh_hierarchy_info(h, &mut info), LghStatus::Ok);
        assert_eq!((info.light_count, info.h0), (512, rust.h0()));
        let mut h0 = info.h0;
        let mut points = Vec::new();
        let mut rng = lgh_core::random::SplitMix64(11);
        for _ in 0..64 {
            points.extend(rng.next_in(Vec3::splat(-4.0), Vec3::splat(12.0)).to_array());
        }
        let mut probes = vec![0.0f32; points.len()];
        assert_eq!(
            lgh_probe_batch(h, b, points.as_ptr(), 64, probes.as_mut_ptr()),
            LghStatus::Ok
        );
        let mut buffer = vec![LghLight::default(); 4096];
        for (k, x) in points.chunks(3).enumerate() {
            let xv = Vec3::from_slice(x);
            let shade = |s: &lgh_core::LightSample| s.intensity * falloff(s.distance, rust.h0());
            let (want, n) = rust.query_sum(xv, &blending, shade).unwrap();
            // The callback's sum and the probe: the Rust API's bits.
            let (mut rgb, mut lights) = ([0.0f32; 3], 0u32);
            let user = (&mut h0 as *mut f32).cast::<c_void>();
            let status = lgh_sum(
                h,
                b,
                x.as_ptr(),
                Some(lambert_free),
                user,
                rgb.as_mut_ptr(),
                &mut lights,
            );
            assert_eq!(status, LghStatus::Ok);
            assert_eq!((Vec3::from(rgb), lights), (want, n));
            assert_eq!(Vec3::from_slice(&probes[3 * k..3 * k + 3]), want);
            // The gathered lights: the same ones, in the same order.
            let mut count = 0;
            let status = lgh_gather(
                h,
                b,
                x.as_ptr(),
                buffer.as_mut_ptr(),
                buffer.len(),
                &mut count,
            );
            assert_eq!(status, LghStatus::Ok);
            assert_eq!(count, n as usize);
            let mut j = 0;
            rust.query(xv, &blending, |s| {
                let got = &buffer[j];
                assert_eq!((got.level, got.index), (u32::from(s.level), s.index));
                assert_eq!(Vec3::from(got.intensity), s.intensity);
                assert_eq!(got.distance, s.distance);
                j += 1;
            })
            .unwrap();
            // Too small a buffer: the count it needs, nothing written.
            if count > 1 {
                let mut small = vec![LghLight::default(); count - 1];
                let mut needed = 0;
                let status = lgh_gather(
                    h,
                    b,
                    x.as_ptr(),
                    small.as_mut_ptr(),
                    small.len(),
                    &mut needed,
                );
                assert_eq!(status, LghStatus::BufferTooSmall);
                assert_eq!(needed, count);
                assert!(small.iter().all(|l| *l == LghLight::default()));
            }
        }
        lgh_blending_destroy(b);
        lgh_hierarchy_destroy(h);
    }
}

#[test]
fn updating_intensities_equals_building_afresh_and_a_rebuild_needs_a_new_blending() {
    let (p, i) = lights();
    let (h, b) = made();
    let hotter: Vec<f32> = i.iter().map(|v| v * 1.5 + 0.25).collect();
    let mut fresh = null_mut();
    let mut fb = null_mut();
    let x = [3.3f32, 4.1, 2.2];
    // SAFETY: live objects and valid pointers throughout.
    unsafe {
        assert_eq!(
            lgh_hierarchy_update_intensities(h, hotter.as_ptr(), 512),
            LghStatus::Ok
        );
        assert_eq!(
            lgh_hierarchy_create(p.as_ptr(), hotter.as_ptr(), 512, null(), &mut fresh),
            LghStatus::Ok
        );
        assert_eq!(lgh_blending_create(fresh, 2.0, &mut fb), LghStatus::Ok);
        let (mut a, mut c) = ([0.0f32; 3], [0.0f32; 3]);
        assert_eq!(
            lgh_probe_batch(h, b, x.as_ptr(), 1, a.as_mut_ptr()),
            LghStatus::Ok
        );
        assert_eq!(
            lgh_probe_batch(fresh, fb, x.as_ptr(), 1, c.as_mut_ptr()),
            LghStatus::Ok
        );
        assert_eq!(a, c);
        // Lights moved far apart: new grids, the old blending refused.
        let spread: Vec<f32> = p.iter().map(|v| v * 40.0).collect();
        assert_eq!(
            lgh_hierarchy_rebuild(h, spread.as_ptr(), i.as_ptr(), 512),
            LghStatus::Ok
        );
        assert_eq!(
            lgh_probe_batch(h, b, x.as_ptr(), 1, a.as_mut_ptr()),
            LghStatus::BlendingMismatch
        );
        assert!(last_error().contains("lgh_probe_batch"), "{}", last_error());
        lgh_blending_destroy(b);
        lgh_blending_destroy(fb);
        lgh_hierarchy_destroy(h);
        lgh_hierarchy_destroy(fresh);
    }
}

/// Every function, given NULL where it needs a pointer and values out of range, returns an
/// error code with a message naming the function, and leaves its outputs as the docs say.
/// `.ci/run` also runs it under Miri (`cargo +nightly miri test -p lgh-capi --test abi --
/// null_and_out_of_range`, about 100 s), where any undefined behaviour in reaching those
/// errors — a read through a bad pointer, an invalid reference — fails it.
#[test]
fn null_and_out_of_range_arguments_get_an_error_never_a_crash() {
    let (p, i) = lights();
    let (h, b) = made();
    let x = [1.0f32, 2.0, 3.0];
    let nan = [f32::NAN, 0.0, 0.0];
    let mut rgb = [7.0f32; 3];
    let mut n = 0u32;
    let mut count = 0usize;
    let mut info = LghInfo::default();
    let mut buffer = [LghLight::default(); 4];
    let expect = |status: LghStatus, want: LghStatus, name: &str| {
        assert_eq!(status, want, "{name}: {}", last_error());
        assert!(last_error().starts_with(name), "{name}: {}", last_error());
    };
    use LghStatus::{InvalidArgument as Bad, NullArgument as Null};
    // SAFETY: every pointer given is NULL or valid; that is what is tested.
    unsafe {
        expect(
            lgh_settings_default(null_mut()),
            Null,
            "lgh_settings_default",
        );
        // Creation: no out-pointer, no arrays, bad lights, bad settings.
        let mut out = null_mut();
        expect(
            lgh_hierarchy_create(p.as_ptr(), i.as_ptr(), 512, null(), null_mut()),
            Null,
            "lgh_hierarchy_create",
        );
        expect(
            lgh_hierarchy_create(null(), i.as_ptr(), 512, null(), &mut out),
            Null,
            "lgh_hierarchy_create",
        );
        expect(
            lgh_hierarchy_create(p.as_ptr(), null(), 512, null(), &mut out),
            Null,
            "lgh_hierarchy_create",
        );
        assert!(out.is_null());
        let mut bad_p = p.clone();
        bad_p[40] = f32::INFINITY;
        expect(
            lgh_hierarchy_create(bad_p.as_ptr(), i.as_ptr(), 512, null(), &mut out),
            Bad,
            "lgh_hierarchy_create",
        );
        assert!(
            last_error().contains("13"),
            "names the light: {}",
            last_error()
        );
        // Light 1 with a negative luminance (a negative channel alone is a colour outside
        // Rec. 709's gamut, which the hierarchy takes).
        let mut neg = i.clone();
        neg[3..6].copy_from_slice(&[0.0, -1.0, 0.0]);
        expect(
            lgh_hierarchy_create(p.as_ptr(), neg.as_ptr(), 512, null(), &mut out),
            Bad,
            "lgh_hierarchy_create",
        );
        let mut out_of_gamut = i.clone();
        out_of_gamut[5] = -0.01;
        let mut taken = null_mut();
        assert_eq!(
            lgh_hierarchy_create(p.as_ptr(), out_of_gamut.as_ptr(), 512, null(), &mut taken),
            LghStatus::Ok,
            "{}",
            last_error()
        );
        lgh_hierarchy_destroy(taken);
        let too_many = lgh_core::MAX_LIGHTS + 1;
        expect(
            lgh_hierarchy_create(p.as_ptr(), i.as_ptr(), too_many, null(), &mut out),
            Bad,
            "lgh_hierarchy_create",
        );
        let misaligned = p.as_ptr().cast::<u8>().add(1).cast::<f32>();
        expect(
            lgh_hierarchy_create(misaligned, i.as_ptr(), 4, null(), &mut out),
            Bad,
            "lgh_hierarchy_create",
        );
        let mut s = std::mem::zeroed::<LghSettings>();
        assert_eq!(lgh_settings_default(&mut s), LghStatus::Ok);
        for (field, bad) in [
            ("h1", LghSettings { h1: -1.0, ..s }),
            ("h1", LghSettings { h1: f32::NAN, ..s }),
            ("max_level", LghSettings { max_level: 22, ..s }),
            ("max_level", LghSettings { max_level: -2, ..s }),
            (
                "threshold",
                LghSettings {
                    prune_below: -1.0,
                    ..s
                },
            ),
            (
                "origin",
                LghSettings {
                    has_origin: 1,
                    origin: [f32::NAN, 0.0, 0.0],
                    ..s
                },
            ),
        ] {
            expect(
                lgh_hierarchy_create(p.as_ptr(), i.as_ptr(), 512, &bad, &mut out),
                Bad,
                "lgh_hierarchy_create",
            );
            assert!(
                last_error().to_lowercase().contains(field),
                "{field}: {}",
                last_error()
            );
        }
        let old = LghSettings {
            struct_size: s.struct_size - 4,
            ..s
        };
        expect(
            lgh_hierarchy_create(p.as_ptr(), i.as_ptr(), 512, &old, &mut out),
            LghStatus::VersionMismatch,
            "lgh_hierarchy_create",
        );
        let newer = LghSettings {
            version: LGH_ABI_VERSION + 1,
            ..s
        };
        expect(
            lgh_hierarchy_create(p.as_ptr(), i.as_ptr(), 512, &newer, &mut out),
            LghStatus::VersionMismatch,
            "lgh_hierarchy_create",
        );
        assert!(out.is_null());
        // No lights at all is a hierarchy (that lights nothing).
        assert_eq!(
            lgh_hierarchy_create(null(), null(), 0, &s, &mut out),
            LghStatus::Ok
        );
        lgh_hierarchy_destroy(out);
        // Info, updates, rebuilds.
        expect(
            lgh_hierarchy_info(null(), &mut info),
            Null,
            "lgh_hierarchy_info",
        );
        expect(
            lgh_hierarchy_info(h, null_mut()),
            Null,
            "lgh_hierarchy_info",
        );
        expect(
            lgh_hierarchy_update_intensities(null_mut(), i.as_ptr(), 512),
            Null,
            "lgh_hierarchy_update_intensities",
        );
        expect(
            lgh_hierarchy_update_intensities(h, null(), 512),
            Null,
            "lgh_hierarchy_update_intensities",
        );
        expect(
            lgh_hierarchy_update_intensities(h, i.as_ptr(), 511),
            Bad,
            "lgh_hierarchy_update_intensities",
        );
        expect(
            lgh_hierarchy_update_intensities(h, neg.as_ptr(), 512),
            Bad,
            "lgh_hierarchy_update_intensities",
        );
        expect(
            lgh_hierarchy_rebuild(null_mut(), p.as_ptr(), i.as_ptr(), 512),
            Null,
            "lgh_hierarchy_rebuild",
        );
        expect(
            lgh_hierarchy_rebuild(h, bad_p.as_ptr(), i.as_ptr(), 512),
            Bad,
            "lgh_hierarchy_rebuild",
        );
        // Blendings.
        let mut bl = null_mut();
        expect(
            lgh_blending_create(null(), 2.0, &mut bl),
            Null,
            "lgh_blending_create",
        );
        expect(
            lgh_blending_create(h, 2.0, null_mut()),
            Null,
            "lgh_blending_create",
        );
        for alpha in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            expect(
                lgh_blending_create(h, alpha, &mut bl),
                Bad,
                "lgh_blending_create",
            );
            assert!(bl.is_null());
        }
        // Queries.
        let user = null_mut();
        let shade = Some(lambert_free as unsafe extern "C" fn(_, _, _));
        expect(
            lgh_sum(null(), b, x.as_ptr(), shade, user, rgb.as_mut_ptr(), &mut n),
            Null,
            "lgh_sum",
        );
        expect(
            lgh_sum(h, null(), x.as_ptr(), shade, user, rgb.as_mut_ptr(), &mut n),
            Null,
            "lgh_sum",
        );
        expect(
            lgh_sum(h, b, null(), shade, user, rgb.as_mut_ptr(), &mut n),
            Null,
            "lgh_sum",
        );
        expect(
            lgh_sum(h, b, x.as_ptr(), None, user, rgb.as_mut_ptr(), &mut n),
            Null,
            "lgh_sum",
        );
        expect(
            lgh_sum(h, b, x.as_ptr(), shade, user, null_mut(), &mut n),
            Null,
            "lgh_sum",
        );
        expect(
            lgh_sum(h, b, nan.as_ptr(), shade, user, rgb.as_mut_ptr(), &mut n),
            Bad,
            "lgh_sum",
        );
        assert_eq!(rgb, [7.0; 3], "untouched on failure");
        expect(
            lgh_gather(null(), b, x.as_ptr(), buffer.as_mut_ptr(), 4, &mut count),
            Null,
            "lgh_gather",
        );
        expect(
            lgh_gather(h, b, x.as_ptr(), null_mut(), 4, &mut count),
            Null,
            "lgh_gather",
        );
        expect(
            lgh_gather(h, b, x.as_ptr(), buffer.as_mut_ptr(), 4, null_mut()),
            Null,
            "lgh_gather",
        );
        expect(
            lgh_gather(h, b, nan.as_ptr(), buffer.as_mut_ptr(), 4, &mut count),
            Bad,
            "lgh_gather",
        );
        expect(
            lgh_gather(h, b, x.as_ptr(), null_mut(), 0, &mut count),
            LghStatus::BufferTooSmall,
            "lgh_gather",
        );
        assert!(count > 0, "the count needed, with no buffer");
        let two = [x, nan].concat();
        let mut out2 = [7.0f32; 6];
        expect(
            lgh_probe_batch(null(), b, two.as_ptr(), 2, out2.as_mut_ptr()),
            Null,
            "lgh_probe_batch",
        );
        expect(
            lgh_probe_batch(h, null(), two.as_ptr(), 2, out2.as_mut_ptr()),
            Null,
            "lgh_probe_batch",
        );
        expect(
            lgh_probe_batch(h, b, null(), 2, out2.as_mut_ptr()),
            Null,
            "lgh_probe_batch",
        );
        expect(
            lgh_probe_batch(h, b, two.as_ptr(), 2, null_mut()),
            Null,
            "lgh_probe_batch",
        );
        expect(
            lgh_probe_batch(h, b, two.as_ptr(), 2, out2.as_mut_ptr()),
            Bad,
            "lgh_probe_batch",
        );
        assert!(last_error().contains("point 1"), "{}", last_error());
        assert_eq!(out2, [7.0; 6], "nothing written when a point is bad");
        // Freeing NULL does nothing.
        lgh_hierarchy_destroy(null_mut());
        lgh_blending_destroy(null_mut());
        lgh_blending_destroy(b);
        lgh_hierarchy_destroy(h);
    }
}

#[test]
fn errors_are_per_thread() {
    // SAFETY: NULL is what is tested.
    unsafe {
        assert_eq!(lgh_settings_default(null_mut()), LghStatus::NullArgument);
    }
    let other = std::thread::spawn(last_error).join().unwrap();
    assert_eq!(other, "");
    assert!(last_error().contains("out is NULL"));
    assert_eq!(lgh_abi_version(), LGH_ABI_VERSION);
}
