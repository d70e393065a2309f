//! Frame ranges on a render farm (issue 15): `lgh explosion --prepare` writes a sequence
//! manifest, tasks render any frames of it with `--manifest … --frames A..B`, and every frame's
//! pixels are the same bits as those of one run over the whole sequence.

mod common;

use common::{assert_refused, exr_bits, lgh, lgh_ok};
use lgh_tests::fire_frame;
use std::path::{Path, PathBuf};

/// The render settings every run of these tests shares: small and without shadows (what a
/// frame takes from the sequence is the lights, the grid and the framing; the shadows are made
/// from the frame alone, and tested bit-identical on any thread count elsewhere), with
/// settings away from their defaults to check they are replayed.
const SETTINGS: [&str; 10] = [
    "--width",
    "24",
    "--height",
    "14",
    "--alpha",
    "4",
    "--albedo",
    "0.7",
    "--shadows",
    "none",
];

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The dev fire's frames 50..56, or None (and a SKIPPED line) without the data.
fn fire() -> Option<PathBuf> {
    fire_frame(56)
}

#[test]
fn farm_tasks_render_the_same_pixels_as_one_run() {
    let Some(f56) = fire() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (whole, farm) = (dir.path().join("whole"), dir.path().join("farm"));
    std::fs::create_dir_all(&whole).unwrap();
    std::fs::create_dir_all(&farm).unwrap();
    let manifest = dir.path().join("fire.json");

    let mut one = vec![
        "explosion",
        "--vdb",
        s(&f56),
        "--frames",
        "50..56",
        "--quiet",
    ];
    one.extend(SETTINGS);
    let whole_out = whole.join("fire.exr");
    let mut a = one.clone();
    a.extend(["--out", s(&whole_out)]);
    lgh_ok(&a);

    let farm_out = farm.join("fire.exr");
    let mut a = one.clone();
    a.extend(["--out", s(&farm_out), "--prepare", s(&manifest)]);
    let o = lgh_ok(&a);
    assert!(String::from_utf8_lossy(&o.stdout).contains("--manifest"));
    // --prepare renders nothing.
    assert_eq!(std::fs::read_dir(&farm).unwrap().count(), 0);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&manifest).unwrap()).unwrap();
    assert_eq!(json["frames"]["first"], 50);
    assert_eq!(json["frames"]["files"].as_array().unwrap().len(), 7);
    assert_eq!(json["settings"]["alpha"], serde_json::json!(["4"]));
    assert!(json["lights"]["count"].as_u64().unwrap() > 1000);

    // Three tasks, in an order no single run would take.
    for frames in ["54..56", "50..50", "51..53"] {
        lgh_ok(&[
            "explosion",
            "--manifest",
            s(&manifest),
            "--frames",
            frames,
            "--quiet",
        ]);
    }
    let mut sequence = None;
    for f in 50..=56 {
        let name = format!("fire_{f:04}.exr");
        let (a, b) = (whole.join(&name), farm.join(&name));
        assert_eq!(
            exr_bits(&a),
            exr_bits(&b),
            "frame {f}: the farm's pixels differ"
        );
        assert!(farm.join(format!("fire_{f:04}.png")).is_file());
        // Every frame says which sequence and settings it is of.
        let attrs = lgh_image::read_exr_attributes(&b).unwrap();
        let seq = attrs.iter().find(|(k, _)| k == "lgh:sequence").unwrap();
        assert_eq!(*sequence.get_or_insert(seq.1.clone()), seq.1);
    }

    // --resume skips the finished frames (their files are not touched) and renders the rest.
    let stamp = |p: &Path| std::fs::metadata(p).unwrap().modified().unwrap();
    let f52 = farm.join("fire_0052.exr");
    let before = stamp(&f52);
    std::fs::remove_file(farm.join("fire_0051.png")).unwrap();
    let o = lgh_ok(&[
        "explosion",
        "--manifest",
        s(&manifest),
        "--frames",
        "51..52",
        "--resume",
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("fire_0052.exr: finished before, skipped"),
        "{text}"
    );
    assert!(!text.contains("fire_0051.exr: finished before"), "{text}");
    assert_eq!(stamp(&f52), before);
    assert!(farm.join("fire_0051.png").is_file());
    assert_eq!(
        exr_bits(&farm.join("fire_0051.exr")),
        exr_bits(&whole.join("fire_0051.exr"))
    );
}

#[test]
fn farm_tasks_refuse_what_would_render_another_sequence() {
    let Some(f56) = fire() else { return };
    // A copy of two frames (and their Blender configs) that the test may change.
    let dir = tempfile::tempdir().unwrap();
    let src = f56.parent().unwrap().parent().unwrap();
    for sub in ["data", "config"] {
        std::fs::create_dir_all(dir.path().join(sub)).unwrap();
    }
    for f in [50, 51] {
        for (sub, name) in [
            ("data", format!("fluid_data_{f:04}.vdb")),
            ("config", format!("config_{f:04}.uni")),
        ] {
            std::fs::copy(src.join(sub).join(&name), dir.path().join(sub).join(&name)).unwrap();
        }
    }
    let vdb = dir.path().join("data/fluid_data_0050.vdb");
    let manifest = dir.path().join("m.json");
    let out = dir.path().join("f.exr");
    // A floor far under the fire, its material in an MTL file: the scene is hashed too.
    let (room, mtl) = (dir.path().join("room.obj"), dir.path().join("room.mtl"));
    std::fs::write(
        &room,
        "mtllib room.mtl\nv -1e3 -1e3 -50\nv 1e3 -1e3 -50\nv 1e3 1e3 -50\nv -1e3 1e3 -50\n\
         usemtl floor\nf 1 2 3 4\n",
    )
    .unwrap();
    std::fs::write(&mtl, "newmtl floor\nKd 0.5 0.5 0.5\n").unwrap();
    let mut a = vec![
        "explosion",
        "--vdb",
        s(&vdb),
        "--frames",
        "50..51",
        "--quiet",
        "--out",
        s(&out),
        "--scene",
        s(&room),
        "--prepare",
        s(&manifest),
    ];
    a.extend(SETTINGS);
    lgh_ok(&a);
    let m = s(&manifest);
    // A setting beside --manifest is the manifest's, not the task's: a usage error (exit 2,
    // which a farm does not retry), as is a damaged manifest below.
    let o = assert_refused(
        dir.path(),
        &["explosion", "--manifest", m, "--alpha", "2"],
        "--alpha",
    );
    assert_eq!(o.status.code(), Some(2));
    assert_refused(
        dir.path(),
        &["explosion", "--manifest", m, "--frames", "49..50"],
        "50..51",
    );
    // Both at once is a usage error (clap's, exit code 2).
    let o = lgh(&["explosion", "--manifest", m, "--prepare", "x.json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--prepare"));
    // A damaged manifest: nothing rendered, one line that says what is wrong.
    let text = std::fs::read_to_string(&manifest).unwrap();
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, text.replace("\"count\"", "\"cnt\"")).unwrap();
    assert_refused(
        dir.path(),
        &["explosion", "--manifest", s(&bad)],
        "lights.count",
    );
    std::fs::write(&bad, &text[..text.len() / 2]).unwrap();
    let o = assert_refused(
        dir.path(),
        &["explosion", "--manifest", s(&bad)],
        "not JSON",
    );
    assert_eq!(o.status.code(), Some(2));
    // A frame changed since --prepare: that frame is refused, the other renders.
    let f51 = dir.path().join("data/fluid_data_0051.vdb");
    let mut bytes = std::fs::read(&f51).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(&f51, bytes).unwrap();
    // A changed frame is a failed frame (exit 1), not a usage error.
    let o = assert_refused(
        dir.path(),
        &["explosion", "--manifest", m, "--frames", "51..51"],
        "changed since",
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(!dir.path().join("f_0051.exr").exists());
    lgh_ok(&[
        "explosion",
        "--manifest",
        m,
        "--frames",
        "50..50",
        "--quiet",
    ]);
    assert!(dir.path().join("f_0050.exr").is_file());
    // The room's material changed since --prepare: the task renders nothing.
    std::fs::remove_file(dir.path().join("f_0050.exr")).unwrap();
    std::fs::write(&mtl, "newmtl floor\nKd 0.9 0.5 0.5\n").unwrap();
    assert_refused(
        dir.path(),
        &["explosion", "--manifest", m, "--frames", "50..50"],
        "room.mtl: changed since",
    );
    assert!(!dir.path().join("f_0050.exr").exists());
}
