//! `lgh bench gpu` on a small swarm: the JSON's keys, and the GPU's image against the CPU's
//! within the GPU path's summation bound (lgh-gpu/tests/shade.rs derives it per point; the
//! measured image-wide relative RMSE on this case is about 1.5·10⁻⁷). Without a GPU adapter
//! (nor lavapipe) it says SKIPPED, unless `LGH_REQUIRE_GPU` or `LGH_REQUIRE_ALL` is set.

use std::process::Command;

#[test]
fn bench_gpu_prints_its_keys_and_agrees_with_the_cpu() {
    let out = Command::new(env!("CARGO_BIN_EXE_lgh"))
        .args([
            "bench", "gpu", "--lights", "20000", "--width", "64", "--height", "36",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() && stderr.contains("no GPU adapter") {
        lgh_tests::Piece::Gpu.missing(stderr.trim());
        return;
    }
    assert!(out.status.success(), "{stderr}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "adapter",
        "lights",
        "width",
        "height",
        "alpha",
        "build_ms",
        "update_ms",
        "rebuild_ms",
        "shade_ms",
        "gather_ms",
        "k",
        "cpu_threads",
        "cpu_shade_ms",
        "speedup_vs_cpu",
        "rel_rmse_vs_cpu",
    ] {
        assert!(v.get(key).is_some(), "no {key} in {v}");
    }
    assert_eq!(v["lights"], 20000);
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(64), Some(36))
    );
    assert!(v["shade_ms"].as_f64().unwrap() > 0.0, "{v}");
    // Measured 1.46e-7 on lavapipe. The bound is the per-point one of lgh-gpu/tests/shade.rs,
    // (2N + 32)·2⁻²⁴ of the point's light with N its lights (hundreds here: about 2·10⁻⁵ at
    // worst), which an image-wide RMSE cannot exceed; 10⁻⁵ holds any adapter's rounding.
    let err = v["rel_rmse_vs_cpu"].as_f64().unwrap();
    assert!((0.0..1e-5).contains(&err), "{err}");
    // And each channel on its own: luminance could hide one channel's error.
    for c in 0..3 {
        let err = v["rel_rmse_vs_cpu_rgb"][c].as_f64().unwrap();
        assert!((0.0..1e-5).contains(&err), "channel {c}: {err}");
    }
}
