//! The C++ example (`examples/c`) built against the static library and run, and one of its
//! frames compared with the same frame rendered through the Rust API, pixel for pixel: the
//! floats of its PFM image are the Rust reference's, bit for bit.
//!
//! Needs `make` and a C++ compiler (`apt-get install make g++`): without them the test says
//! SKIPPED and passes, unless `LGH_REQUIRE_CXX` is set (`.ci/run` installs them and sets it),
//! where it fails ([`lgh_tests::Piece`]).

use std::path::{Path, PathBuf};
use std::process::Command;

use lgh_core::glam::Vec3;
use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};

/// The example's scene (`examples/c/swarm.h`), transcribed in Rust by the web page's crate:
/// the same operations in the same order, so the same floats.
use lgh_web::swarm;

/// `0.6f / 3.14159265358979f` in C: that literal rounds to the f32 nearest π.
const BRDF: f32 = 0.6 / std::f32::consts::PI;

/// The folder of the static library cargo built with this test: beside the test's binary
/// (`target/<profile>/deps`, where a test build leaves it) or above it (`target/<profile>`).
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap().to_path_buf();
    let above = deps.parent().unwrap().to_path_buf();
    [deps.clone(), above]
        .into_iter()
        .find(|d| d.join("liblgh_capi.a").exists())
        .unwrap_or_else(|| panic!("no liblgh_capi.a beside or above {}", deps.display()))
}

/// Frame `frame` of `count` lights at `size`² through the Rust API: the example's callback,
/// transcribed, summed by `query_sum`.
fn rust_frame(count: usize, frame: i32, size: i32) -> Vec<f32> {
    let moved = frame - frame % 4;
    let lights: Vec<PointLight> = (0..count)
        .map(|i| {
            let (p, _) = swarm::light(i, moved);
            let (_, intensity) = swarm::light(i, frame);
            PointLight::new(Vec3::from(p), Vec3::from(intensity))
        })
        .collect();
    let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
    let blending = lgh.blending(2.0).unwrap();
    let h0 = lgh.h0();
    let mut image = Vec::with_capacity(3 * (size * size) as usize);
    for py in 0..size {
        for px in 0..size {
            let x = swarm::ground_point(px, py, size);
            let shade = |s: &lgh_core::LightSample| {
                let d = s.distance;
                let cosine = (s.position.y - x[1]) / d;
                if cosine.is_nan() || cosine <= 0.0 {
                    return Vec3::ZERO;
                }
                let dd = if d > h0 { d } else { h0 };
                let k = BRDF * cosine * (1.0 / (dd * dd));
                Vec3::new(s.intensity.x * k, s.intensity.y * k, s.intensity.z * k)
            };
            let (rgb, _) = lgh.query_sum(Vec3::from(x), &blending, shade).unwrap();
            image.extend(rgb.to_array());
        }
    }
    image
}

/// The floats of a PFM image the example wrote.
fn read_pfm(path: &Path, size: usize) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = format!("PF\n{size} {size}\n-1.0\n");
    assert!(bytes.starts_with(header.as_bytes()), "{}", path.display());
    let data = &bytes[header.len()..];
    assert_eq!(data.len(), 12 * size * size);
    data.chunks(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

#[test]
fn the_cpp_example_renders_the_rust_apis_frame_pixel_for_pixel() {
    if let Some(tool) = ["make", "c++"]
        .into_iter()
        .find(|t| !lgh_tests::runs(t, &["--version"]))
    {
        return lgh_tests::Piece::Cxx.missing(&format!("no {tool} on the PATH"));
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let example = root.join("examples/c");
    let dir = tempfile::tempdir().unwrap();
    let binary = dir.path().join("swarm");
    let hello = dir.path().join("hello");
    let make = Command::new("make")
        .arg("-C")
        .arg(&example)
        .arg(format!("LGH_LIB={}", library_dir().display()))
        .arg(format!("BIN={}", binary.display()))
        .arg(format!("HELLO={}", hello.display()))
        .arg("-B")
        .status()
        .expect("the C++ example needs make and a C++ compiler (apt-get install make g++)");
    assert!(make.success(), "make -C examples/c failed");
    // The C example of docs/embedding.md: its three numbers are the Rust API's (printed with 9 digits,
    // enough to give back every float).
    let said = Command::new(&hello).output().unwrap();
    assert!(said.status.success());
    let got: Vec<f32> = String::from_utf8_lossy(&said.stdout)
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    let lights = [
        PointLight::new(Vec3::ZERO, Vec3::ONE),
        PointLight::new(Vec3::X, Vec3::new(2.0, 0.0, 0.0)),
        PointLight::new(Vec3::Y, Vec3::new(0.0, 0.0, 3.0)),
    ];
    let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
    let h0 = lgh.h0();
    let shade = |s: &lgh_core::LightSample| {
        let d = if s.distance > h0 { s.distance } else { h0 };
        s.intensity / (d * d)
    };
    let x = Vec3::new(0.5, 0.5, 2.0);
    let (want, _) = lgh
        .query_sum(x, &lgh.blending(2.0).unwrap(), shade)
        .unwrap();
    assert_eq!(got, want.to_array());
    let (count, frames, size) = (20_000usize, 6, 48);
    let out = Command::new(&binary)
        .args([
            "--lights",
            &count.to_string(),
            "--frames",
            &frames.to_string(),
        ])
        .args(["--size", &size.to_string(), "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{log}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Frames built, updated in place and rebuilt.
    for how in ["built", "updated", "rebuilt"] {
        assert!(log.contains(how), "{log}");
    }
    // Frame 5: rebuilt at frame 4, then updated in place — against a fresh build in Rust.
    let got = read_pfm(&dir.path().join("frame_005.pfm"), size);
    let want = rust_frame(count, 5, size as i32);
    let differ = got
        .iter()
        .zip(&want)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differ, 0, "{differ} of {} floats differ", want.len());
    assert!(want.iter().any(|&v| v > 0.0), "a lit frame");
}
