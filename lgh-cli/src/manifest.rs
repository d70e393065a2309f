//! Sequence manifests (`lgh explosion --prepare`): what every frame's render takes from the
//! whole sequence, written once, so that a render-farm task renders frames `A..B` reading only
//! those frames (issue 15).
//!
//! An explosion's frames are not independent: its lights sit at every voxel hot in *any* frame
//! and its grid is the box that covers every frame (paper Sec. 6.1: fixed positions on a fixed
//! grid are what keep the animation from flickering), and the default camera frames the smoke
//! of all frames. A run over the whole sequence finds them in one pass over the frames; the
//! manifest keeps what that pass found:
//!
//! - `grid`: the frames' transform and common box ([`SequenceLayout`]);
//! - `framing`: the box the default camera frames;
//! - `lights`: the rule and the light voxels themselves (linear indices into the common grid,
//!   delta-coded as LEB128 varints, deflated, base64), with their count;
//! - `files`: every frame's file (and Blender config file) with its size and SHA-256, which a
//!   task checks before it renders the frame, so a file changed since `--prepare` is an error,
//!   not a silently different frame;
//! - `settings`: the flags `--prepare` was given, replayed through the same parser by every
//!   task, so a task cannot render with other settings than the sequence's;
//! - `scene`: the files `--scene` read (the OBJ, then its MTL files), with the size and SHA-256
//!   of the text parsed, which a task checks against the scene it reads.
//!
//! Every render, with a manifest or not, goes through a `Manifest` (a run without one makes it
//! in memory), so a frame has the same pixels, bit for bit, rendered alone, in a range or in a
//! whole-sequence run. Each image's EXR header carries `lgh:sequence`, the SHA-256 of the
//! manifest's JSON, which `--resume` checks before it skips a frame.

use std::io::Read;
use std::path::{Path, PathBuf};

use base64::Engine as _;
use lgh_core::glam::Vec3;
use lgh_volume::cache::SequenceLayout;
use serde_json::{json, Value};
use sha2::{Digest, Sha256};

/// The `format` key of a manifest.
pub const FORMAT: &str = "lgh-sequence-manifest";
/// The manifest version this build writes and reads.
pub const VERSION: u64 = 2;
/// The rule by which the lights were placed (the `lights.rule` key).
pub const LIGHT_RULE: &str = "the centre of every voxel of the common grid that emits in any \
     frame (temperature above --min-temperature, times flame when present)";
/// Largest manifest read (bytes): a 19M-voxel grid's light list deflates to a few megabytes.
const MAX_MANIFEST_BYTES: u64 = 256 << 20;

/// One frame's file, as `--prepare` found it.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameFile {
    /// The frame number (`None`: a single file without `--frames`).
    pub frame: Option<u32>,
    /// The OpenVDB file, absolute.
    pub path: PathBuf,
    /// Its size and SHA-256 (hex).
    pub bytes: u64,
    /// SHA-256 of the file, lowercase hex.
    pub sha256: String,
    /// Blender's `config/config_NNNN.uni` placing the frame, and its SHA-256, when it was read.
    pub config: Option<(PathBuf, String)>,
}

/// A file of `--scene` (the OBJ, one of its MTL files or a texture), as read: what a task checks the scene
/// it reads against.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFile {
    /// The file, absolute.
    pub path: PathBuf,
    /// Its size.
    pub bytes: u64,
    /// SHA-256 of its bytes, lowercase hex.
    pub sha256: String,
}

impl SceneFile {
    /// The record of `bytes`, read from `path`.
    #[must_use]
    pub fn of(path: &Path, bytes: &[u8]) -> Self {
        SceneFile {
            path: path.to_path_buf(),
            bytes: bytes.len() as u64,
            sha256: hex(&Sha256::digest(bytes)),
        }
    }

    /// Checks that the scene a task read, `read`, is the one `--prepare` read, `prepared`.
    pub fn check(read: &[SceneFile], prepared: &[SceneFile]) -> Result<(), crate::Error> {
        // A changed file first: an edited OBJ is what makes a scene read other MTL files.
        if let Some((r, p)) = read.iter().zip(prepared).find(|(r, p)| r != p) {
            return Err(format!(
                "{}: changed since the manifest was prepared (SHA-256 {}, the manifest says {} \
                 of {}); run --prepare again",
                r.path.display(),
                r.sha256,
                p.sha256,
                p.path.display()
            )
            .into());
        }
        if read.len() != prepared.len() {
            return Err(format!(
                "--scene: the scene now reads {} file(s), {} when the manifest was prepared; \
                 run --prepare again",
                read.len(),
                prepared.len()
            )
            .into());
        }
        Ok(())
    }
}

/// What a frame's render takes from the whole sequence (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Manifest {
    /// The frames, in order.
    pub files: Vec<FrameFile>,
    /// The frames' transform and common box.
    pub layout: SequenceLayout,
    /// The box the default camera frames (`None`: the grid's box).
    pub framing: Option<(Vec3, Vec3)>,
    /// The light voxels (`None` for the path tracer, which takes no lights).
    pub lights: Option<Vec<usize>>,
    /// Why no frame has a light, if none has.
    pub all_dark: Option<String>,
    /// The flags given to `lgh explosion`, by long name, with their values as given.
    pub settings: Vec<(String, Vec<String>)>,
    /// The files of `--scene` (empty without one).
    pub scene: Vec<SceneFile>,
}

/// SHA-256 of a file, lowercase hex, and its size.
pub fn file_sha256(path: &Path) -> Result<(u64, String), crate::Error> {
    let mut file =
        std::fs::File::open(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let mut hash = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    let mut bytes = 0u64;
    loop {
        let n = file
            .read(&mut buf)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        if n == 0 {
            break;
        }
        bytes += n as u64;
        hash.update(&buf[..n]);
    }
    Ok((bytes, hex(&hash.finalize())))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

impl FrameFile {
    /// Hashes `path` (and `config`, Blender's placement of it, when it was read).
    pub fn hash(
        frame: Option<u32>,
        path: &Path,
        config: Option<&Path>,
    ) -> Result<Self, crate::Error> {
        let path = absolute(path)?;
        let (bytes, sha256) = file_sha256(&path)?;
        let config = match config {
            Some(c) => {
                let c = absolute(c)?;
                let (_, sha) = file_sha256(&c)?;
                Some((c, sha))
            }
            None => None,
        };
        Ok(FrameFile {
            frame,
            path,
            bytes,
            sha256,
            config,
        })
    }

    /// Checks that the file (and its config) are still those `--prepare` hashed.
    pub fn verify(&self) -> Result<(), crate::Error> {
        let (bytes, sha) = file_sha256(&self.path)?;
        if bytes != self.bytes || sha != self.sha256 {
            return Err(format!(
                "{}: changed since the manifest was prepared (SHA-256 {sha}, the manifest says \
                 {}); run --prepare again",
                self.path.display(),
                self.sha256
            )
            .into());
        }
        if let Some((c, want)) = &self.config {
            let (_, sha) = file_sha256(c)?;
            if &sha != want {
                return Err(format!(
                    "{}: changed since the manifest was prepared; run --prepare again",
                    c.display()
                )
                .into());
            }
        }
        Ok(())
    }
}

/// `path` made absolute against the working directory (not resolving links: a farm's shared
/// storage is often reached through one).
pub fn absolute(path: &Path) -> Result<PathBuf, crate::Error> {
    std::path::absolute(path).map_err(|e| format!("{}: {e}", path.display()).into())
}

/// The light voxels as text: strictly ascending indices, delta-coded as LEB128 varints,
/// deflated, base64.
#[must_use]
pub fn encode_voxels(voxels: &[usize]) -> String {
    let mut raw = Vec::with_capacity(voxels.len() * 2);
    let mut prev = 0usize;
    for (i, &v) in voxels.iter().enumerate() {
        // The first index is itself; each next one is its gap to the one before.
        let mut d = if i == 0 { v } else { v - prev } as u64;
        prev = v;
        loop {
            let byte = (d & 0x7f) as u8;
            d >>= 7;
            if d == 0 {
                raw.push(byte);
                break;
            }
            raw.push(byte | 0x80);
        }
    }
    let deflated = miniz_oxide::deflate::compress_to_vec(&raw, 9);
    base64::engine::general_purpose::STANDARD.encode(deflated)
}

/// [`encode_voxels`] undone; `count` voxels, each below `limit`, strictly ascending, or an error.
pub fn decode_voxels(text: &str, count: usize, limit: usize) -> Result<Vec<usize>, String> {
    let bad = |why: &str| format!("lights.voxels: {why}");
    if count > limit {
        return Err(bad(&format!(
            "lights.count {count} is more than the grid's {limit} voxels"
        )));
    }
    let deflated = base64::engine::general_purpose::STANDARD
        .decode(text)
        .map_err(|e| bad(&format!("not base64 ({e})")))?;
    // At most 10 bytes per varint.
    let raw = miniz_oxide::inflate::decompress_to_vec_with_limit(
        &deflated,
        count.saturating_mul(10).max(16),
    )
    .map_err(|e| bad(&format!("corrupt deflate data ({e:?})")))?;
    // Each varint is at least one byte.
    let mut out = Vec::with_capacity(count.min(raw.len()));
    let (mut d, mut shift) = (0u64, 0u32);
    for &byte in &raw {
        if shift > 63 {
            return Err(bad("a varint is too long"));
        }
        d |= u64::from(byte & 0x7f) << shift;
        shift += 7;
        if byte & 0x80 == 0 {
            let v = match out.last() {
                None => Some(d),
                Some(&p) if d > 0 => (p as u64).checked_add(d),
                Some(_) => None,
            }
            .filter(|&v| v < limit as u64)
            .ok_or_else(|| bad("not strictly ascending indices into the grid"))?;
            out.push(v as usize);
            d = 0;
            shift = 0;
        }
    }
    if shift != 0 || out.len() != count {
        return Err(bad(&format!(
            "{} voxels where lights.count says {count}",
            out.len()
        )));
    }
    Ok(out)
}

impl Manifest {
    /// The manifest as JSON (what `--prepare` writes, and what its digest is of).
    #[must_use]
    pub fn to_json(&self) -> String {
        let files: Vec<Value> = self
            .files
            .iter()
            .map(|f| {
                json!({
                    "frame": f.frame,
                    "path": f.path.to_string_lossy(),
                    "bytes": f.bytes,
                    "sha256": f.sha256,
                    "config": f.config.as_ref().map(|(p, sha)| json!({
                        "path": p.to_string_lossy(), "sha256": sha
                    })),
                })
            })
            .collect();
        let settings: serde_json::Map<String, Value> = self
            .settings
            .iter()
            .map(|(k, v)| (k.clone(), json!(v)))
            .collect();
        let v = json!({
            "format": FORMAT,
            "version": VERSION,
            "lgh_version": env!("CARGO_PKG_VERSION"),
            "frames": {
                "first": self.files.first().and_then(|f| f.frame),
                "last": self.files.last().and_then(|f| f.frame),
                "files": files,
            },
            "grid": {
                "transform": self.layout.transform,
                "lo": self.layout.lo,
                "hi": self.layout.hi,
            },
            "framing": self.framing.map(|(lo, hi)| json!({
                "lo": lo.to_array(), "hi": hi.to_array()
            })),
            "lights": self.lights.as_ref().map(|v| json!({
                "rule": LIGHT_RULE,
                "count": v.len(),
                "encoding": "delta-leb128-deflate-base64",
                "voxels": encode_voxels(v),
            })),
            "all_dark": self.all_dark,
            "settings": settings,
            "scene": self.scene.iter().map(|f| json!({
                "path": f.path.to_string_lossy(), "bytes": f.bytes, "sha256": f.sha256
            })).collect::<Vec<_>>(),
        });
        let mut text = serde_json::to_string_pretty(&v).expect("a JSON value prints");
        text.push('\n');
        text
    }

    /// SHA-256 of [`to_json`](Self::to_json), hex: the `lgh:sequence` of every frame's header.
    #[must_use]
    pub fn digest(&self) -> String {
        hex(&Sha256::digest(self.to_json().as_bytes()))
    }

    /// Reads a manifest written by `--prepare`, checking every field.
    pub fn read(path: &Path) -> Result<Self, crate::Error> {
        let bytes = lgh_image::read_limited(path, MAX_MANIFEST_BYTES).map_err(|e| {
            crate::usage(format!("--manifest {}: cannot read: {e}", path.display()))
        })?;
        Manifest::parse(&bytes)
            .map_err(|e| crate::usage(format!("--manifest {}: {e}", path.display())))
    }

    /// [`read`](Self::read) from bytes.
    pub fn parse(bytes: &[u8]) -> Result<Self, String> {
        let v: Value = serde_json::from_slice(bytes).map_err(|e| format!("not JSON: {e}"))?;
        check_header(&v)?;
        let layout = parse_layout(&v["grid"])?;
        let voxels = layout.voxels().ok_or_else(|| malformed("grid.lo/hi"))?;
        let framing = match &v["framing"] {
            Value::Null => None,
            f => Some((
                parse_vec3(&f["lo"], "framing.lo")?,
                parse_vec3(&f["hi"], "framing.hi")?,
            )),
        };
        let lights = match &v["lights"] {
            Value::Null => None,
            l => Some(parse_lights(l, voxels)?),
        };
        let all_dark = match &v["all_dark"] {
            Value::Null => None,
            d => Some(d.as_str().ok_or_else(|| malformed("all_dark"))?.to_string()),
        };
        let files = parse_frame_files(&v["frames"]["files"])?;
        let settings = parse_settings(&v["settings"])?;
        let scene = parse_scene(&v["scene"])?;
        if scene.is_empty() == settings.iter().any(|(k, _)| k == "scene") {
            return Err(malformed("scene (its files and --scene go together)"));
        }
        Ok(Manifest {
            files,
            layout,
            framing,
            lights,
            all_dark,
            settings,
            scene,
        })
    }

    /// The frame numbers, first and last (`None` for a single file without `--frames`).
    #[must_use]
    pub fn range(&self) -> Option<(u32, u32)> {
        Some((self.files.first()?.frame?, self.files.last()?.frame?))
    }
}

/// The error of a manifest whose `key` is missing or malformed.
#[must_use]
fn malformed(key: &str) -> String {
    format!("\"{key}\" is missing or malformed")
}

/// Checks that `v` is a manifest of this [`VERSION`], prepared by this build of lgh.
fn check_header(v: &Value) -> Result<(), String> {
    if v["format"] != FORMAT {
        return Err(format!(
            "not an lgh sequence manifest (no \"format\": \"{FORMAT}\")"
        ));
    }
    if v["version"] != VERSION {
        return Err(format!(
            "manifest version {} (this lgh reads version {VERSION}): prepare it again",
            v["version"]
        ));
    }
    // Defaults of flags not given at --prepare are this build's; another version may
    // render other pixels.
    let version = env!("CARGO_PKG_VERSION");
    if v["lgh_version"] != version {
        return Err(format!(
            "prepared by lgh {} and this is lgh {version}: render with the version that \
             prepared it, or prepare it again",
            v["lgh_version"]
        ));
    }
    Ok(())
}

/// The `grid` record: the frames' transform and common box.
fn parse_layout(grid: &Value) -> Result<SequenceLayout, String> {
    let transform: [[f64; 4]; 4] = serde_json::from_value(grid["transform"].clone())
        .map_err(|_| malformed("grid.transform"))?;
    let lo: [i32; 3] =
        serde_json::from_value(grid["lo"].clone()).map_err(|_| malformed("grid.lo"))?;
    let hi: [i32; 3] =
        serde_json::from_value(grid["hi"].clone()).map_err(|_| malformed("grid.hi"))?;
    Ok(SequenceLayout { transform, lo, hi })
}

/// A point `[x, y, z]` at `key`.
fn parse_vec3(x: &Value, key: &str) -> Result<Vec3, String> {
    let a: [f32; 3] = serde_json::from_value(x.clone()).map_err(|_| malformed(key))?;
    Ok(Vec3::from(a))
}

/// The `lights` record: its light voxels, indices below `voxels`.
fn parse_lights(l: &Value, voxels: usize) -> Result<Vec<usize>, String> {
    let count = l["count"]
        .as_u64()
        .ok_or_else(|| malformed("lights.count"))?;
    let text = l["voxels"]
        .as_str()
        .ok_or_else(|| malformed("lights.voxels"))?;
    decode_voxels(text, count as usize, voxels)
}

/// The `frames.files` list: one file without a frame number, or consecutive frames.
fn parse_frame_files(files: &Value) -> Result<Vec<FrameFile>, String> {
    let files = files
        .as_array()
        .filter(|f| !f.is_empty())
        .ok_or_else(|| malformed("frames.files"))?
        .iter()
        .map(parse_frame_file)
        .collect::<Result<Vec<_>, String>>()?;
    let consecutive = match files[0].frame {
        None => files.len() == 1,
        Some(first) => files
            .iter()
            .enumerate()
            .all(|(i, f)| f.frame.map(u64::from) == Some(u64::from(first) + i as u64)),
    };
    if !consecutive {
        return Err(malformed("frames.files (consecutive frames)"));
    }
    Ok(files)
}

/// One record of `frames.files`.
fn parse_frame_file(f: &Value) -> Result<FrameFile, String> {
    let s = |key: &str| {
        f[key]
            .as_str()
            .map(str::to_string)
            .ok_or_else(|| malformed(&format!("frames.files[].{key}")))
    };
    let frame = match &f["frame"] {
        Value::Null => None,
        n => Some(
            n.as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| malformed("frames.files[].frame"))?,
        ),
    };
    let config = match &f["config"] {
        Value::Null => None,
        c => Some((
            PathBuf::from(c["path"].as_str().ok_or_else(|| malformed("config.path"))?),
            c["sha256"]
                .as_str()
                .ok_or_else(|| malformed("config.sha256"))?
                .to_string(),
        )),
    };
    Ok(FrameFile {
        frame,
        path: PathBuf::from(s("path")?),
        bytes: f["bytes"]
            .as_u64()
            .ok_or_else(|| malformed("frames.files[].bytes"))?,
        sha256: s("sha256")?,
        config,
    })
}

/// The `settings` record: each flag's long name and its values as given.
fn parse_settings(settings: &Value) -> Result<Vec<(String, Vec<String>)>, String> {
    settings
        .as_object()
        .ok_or_else(|| malformed("settings"))?
        .iter()
        .map(|(k, vals)| {
            let vals: Vec<String> = serde_json::from_value(vals.clone())
                .map_err(|_| malformed(&format!("settings.{k}")))?;
            Ok((k.clone(), vals))
        })
        .collect()
}

/// The `scene` list: the files of `--scene`.
fn parse_scene(scene: &Value) -> Result<Vec<SceneFile>, String> {
    scene
        .as_array()
        .ok_or_else(|| malformed("scene"))?
        .iter()
        .map(|f| {
            Ok(SceneFile {
                path: PathBuf::from(
                    f["path"]
                        .as_str()
                        .ok_or_else(|| malformed("scene[].path"))?,
                ),
                bytes: f["bytes"]
                    .as_u64()
                    .ok_or_else(|| malformed("scene[].bytes"))?,
                sha256: f["sha256"]
                    .as_str()
                    .ok_or_else(|| malformed("scene[].sha256"))?
                    .to_string(),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_voxels_survive_the_text_and_bad_text_is_refused() {
        let voxels: Vec<usize> = vec![0, 1, 2, 130, 131, 20_000, 1 << 40];
        let text = encode_voxels(&voxels);
        assert_eq!(decode_voxels(&text, 7, 1 << 41).unwrap(), voxels);
        // Wrong count, an index past the grid, not base64, not deflate.
        assert!(decode_voxels(&text, 6, 1 << 41).is_err());
        assert!(decode_voxels(&text, 7, 1 << 40).is_err());
        assert!(decode_voxels("#!", 7, 1 << 41).is_err());
        // A count past the grid is refused before anything is allocated for it.
        assert!(decode_voxels(&text, 1 << 60, 1 << 41).is_err());
        assert!(decode_voxels("AAAA", 7, 1 << 41).is_err());
        assert_eq!(
            decode_voxels(&encode_voxels(&[]), 0, 1).unwrap(),
            Vec::<usize>::new()
        );
        // A repeated index (a gap of zero) is not ascending.
        let raw = miniz_oxide::deflate::compress_to_vec(&[5, 0], 9);
        let repeated = base64::engine::general_purpose::STANDARD.encode(raw);
        assert!(decode_voxels(&repeated, 2, 100).is_err());
    }

    #[test]
    fn a_manifest_reads_back_as_written_and_its_digest_follows_its_content() {
        let m = Manifest {
            files: vec![FrameFile {
                frame: Some(50),
                path: "/data/f_0050.vdb".into(),
                bytes: 12,
                sha256: "ab".repeat(32),
                config: Some(("/data/config_0050.uni".into(), "cd".repeat(32))),
            }],
            layout: SequenceLayout {
                transform: [
                    [0.1, 0.0, 0.0, 0.0],
                    [0.0, 0.1, 0.0, 0.0],
                    [0.0, 0.0, 0.1, 0.0],
                    [1.5, -2.0, 0.25, 1.0],
                ],
                lo: [-3, 0, 4],
                hi: [10, 20, 30],
            },
            framing: Some((Vec3::new(0.1, -0.3, 1e-7), Vec3::new(2.5, 3.0, 4.0))),
            lights: Some(vec![3, 4, 900]),
            all_dark: None,
            settings: vec![
                ("alpha".into(), vec!["4".into()]),
                ("camera".into(), vec!["-1,2,3,0,0,0".into()]),
                ("no-domain-offset".into(), vec![]),
                ("scene".into(), vec!["/data/room.obj".into()]),
            ],
            scene: vec![
                SceneFile::of(Path::new("/data/room.obj"), b"mtllib room.mtl\n"),
                SceneFile::of(Path::new("/data/room.mtl"), b"newmtl grey\n"),
            ],
        };
        let back = Manifest::parse(m.to_json().as_bytes()).unwrap();
        assert_eq!(back, m);
        assert_eq!(back.digest(), m.digest());
        assert_eq!(back.range(), Some((50, 50)));
        let mut other = m.clone();
        other.settings[0].1[0] = "2".into();
        assert_ne!(other.digest(), m.digest());
        // Refusals name what is wrong.
        let text = m.to_json();
        let e = Manifest::parse(text.replace("\"version\": 2", "\"version\": 9").as_bytes());
        assert!(e.unwrap_err().contains("version"));
        let e = Manifest::parse(
            text.replace(env!("CARGO_PKG_VERSION"), "0.0.0-other")
                .as_bytes(),
        );
        assert!(e.unwrap_err().contains("prepared by lgh"));
        let e = Manifest::parse(
            text.replace("\"lo\": [\n      -3", "\"lo\": [\n      \"x\"")
                .as_bytes(),
        );
        assert!(e.unwrap_err().contains("grid.lo"), "{text}");
        // --scene without its files (or files without --scene) is refused.
        let mut sceneless = m.clone();
        sceneless.scene.clear();
        let e = Manifest::parse(sceneless.to_json().as_bytes()).unwrap_err();
        assert!(e.contains("scene"), "{e}");
        assert!(Manifest::parse(b"{}").unwrap_err().contains("not an lgh"));
        assert!(Manifest::parse(b"\x00").unwrap_err().contains("not JSON"));
    }

    #[test]
    fn a_changed_scene_is_caught() {
        let obj = SceneFile::of(Path::new("/r/room.obj"), b"mtllib room.mtl\n");
        // SHA-256("mtllib room.mtl\n"), computed independently (coreutils' sha256sum).
        assert_eq!(
            obj.sha256,
            "312e1c2004a714c7805527f7a196a39bf2e6098e2c4a6f39a9deccc9552d47f9"
        );
        let mtl = SceneFile::of(Path::new("/r/room.mtl"), b"newmtl grey\nKd 0.5 0.5 0.5\n");
        let prepared = [obj.clone(), mtl.clone()];
        SceneFile::check(&prepared, &prepared).unwrap();
        let edited = SceneFile::of(Path::new("/r/room.mtl"), b"newmtl grey\nKd 0.9 0.5 0.5\n");
        let e = SceneFile::check(&[obj.clone(), edited], &prepared).unwrap_err();
        assert!(e.to_string().contains("room.mtl: changed"), "{e}");
        let e = SceneFile::check(&[obj], &prepared).unwrap_err();
        assert!(e.to_string().contains("1 file(s), 2"), "{e}");
    }

    #[test]
    fn a_changed_file_is_caught() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("f_0001.vdb");
        std::fs::write(&p, b"frame one").unwrap();
        let f = FrameFile::hash(Some(1), &p, None).unwrap();
        assert_eq!(f.bytes, 9);
        // SHA-256("frame one"), computed independently (Python's hashlib).
        assert_eq!(
            f.sha256,
            "fb7ea6b53396d2b744742eb3808eda216c6baa80f8144f4601b5a04ce508a92c"
        );
        f.verify().unwrap();
        std::fs::write(&p, b"frame 0ne").unwrap();
        assert!(f
            .verify()
            .unwrap_err()
            .to_string()
            .contains("changed since"));
    }
}
