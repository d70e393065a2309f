//! # lgh-fuzz — the fuzz targets of lgh's input parsers
//!
//! One function per parser of a file that comes from another program, each taking the file's
//! bytes and doing with them what `lgh` does, up to the point where the input has been checked:
//!
//! | target | parser | what `lgh` reads with it |
//! |---|---|---|
//! | `vdb` | [`lgh_volume::vdb::parse`], then each grid's statistics and its dense copy | `lgh explosion`, `lgh inspect` |
//! | `uni` | [`lgh_volume::cache::parse_blender_offset`] | Blender's `config_NNNN.uni` |
//! | `ply` | [`lgh_ply::parse`], then the light columns | `lgh probes` |
//! | `obj` | [`lgh_vpl::Mesh::parse_obj`] (lgh's checks, then tobj) | `lgh paquette --obj` |
//! | `exr` | [`lgh_image::decode_exr`] | `lgh compare` |
//!
//! A target must return for every input: an `Err` is a pass, a panic, an abort, a hang or a
//! giant allocation is a bug. The AFL++ driver (`fuzz/afl`, outside the workspace: it needs
//! `cargo afl`) runs them coverage-guided; `tests/corpus.rs` replays the saved corpus
//! (`fuzz/corpus/TARGET/`) in the ordinary test suite, so what fuzzing found stays fixed.
//! `fuzz/README.md` has the commands and the figures.

#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};

/// A fuzz target: a parser's whole path over one input.
pub type Target = fn(&[u8]);

/// Every target, by name (the name is the corpus folder's).
pub const TARGETS: [(&str, Target); 5] = [
    ("vdb", vdb),
    ("uni", uni),
    ("ply", ply),
    ("obj", obj),
    ("exr", exr),
];

/// The target called `name`.
#[must_use]
pub fn target(name: &str) -> Option<Target> {
    TARGETS.iter().find(|(n, _)| *n == name).map(|&(_, t)| t)
}

/// Dense copies larger than this are not made while fuzzing (a gigabyte per input would make
/// each execution slow, not find more); the limit itself (`MAX_DENSE_VOXELS`) is a test of its
/// own.
const FUZZ_DENSE_VOXELS: i64 = 1 << 15;

/// An OpenVDB file: parsed, then every grid's statistics (all leaves and tiles visited) and,
/// when small enough, its active box copied to a dense grid as `lgh explosion` does.
pub fn vdb(data: &[u8]) {
    let Ok(file) = lgh_volume::vdb::parse(data) else {
        return;
    };
    for grid in &file.grids {
        let stats = grid.stats();
        let Some((lo, hi)) = stats.bbox else { continue };
        let voxels = (0..3)
            .map(|k| i64::from(hi[k]) - i64::from(lo[k]) + 1)
            .product::<i64>();
        if voxels <= FUZZ_DENSE_VOXELS {
            let _ = lgh_volume::DenseGrid::from_vdb(grid, lo, hi);
        }
    }
}

/// A Blender fluid config (`config_NNNN.uni`, gzip).
pub fn uni(data: &[u8]) {
    let _ = lgh_volume::cache::parse_blender_offset(Path::new("fuzz.uni"), data);
}

/// A PLY point cloud (ASCII, binary little- or big-endian), then the columns `lgh probes` asks
/// for.
pub fn ply(data: &[u8]) {
    let Ok(cloud) = lgh_ply::parse(data) else {
        return;
    };
    for name in ["x", "y", "z", "r", "g", "b"] {
        let _ = cloud.float_column(name);
    }
}

/// What separates the OBJ file from its MTL file in an `obj` input.
pub const MTL_SEPARATOR: &[u8] = b"\n#--mtl--\n";

/// An OBJ file and, after [`MTL_SEPARATOR`], the MTL file every `mtllib` names.
pub fn obj(data: &[u8]) {
    let (obj, mtl) = split_obj(data);
    let Ok(obj) = std::str::from_utf8(obj) else {
        return;
    };
    // Every file the scene names reads as the MTL part: as an MTL file, and as a texture (so
    // the image decoders see those bytes too).
    let options = lgh_vpl::ObjOptions::default();
    let _ = lgh_vpl::Mesh::parse_obj(Path::new("fuzz.obj"), obj, &options, |name| {
        Ok((PathBuf::from(name), mtl.to_vec()))
    });
}

/// `(obj, mtl)` of an `obj` input.
#[must_use]
pub fn split_obj(data: &[u8]) -> (&[u8], &[u8]) {
    match data
        .windows(MTL_SEPARATOR.len())
        .position(|w| w == MTL_SEPARATOR)
    {
        Some(i) => (&data[..i], &data[i + MTL_SEPARATOR.len()..]),
        None => (data, &[]),
    }
}

/// An OpenEXR file, read as `lgh compare` reads it.
///
/// Under AFL++ (`cfg(fuzzing)`) files compressed with B44 are skipped: `cargo afl` forces
/// overflow checks onto every crate, and exr's B44 decoder computes in wrapping `u32`
/// arithmetic on purpose, as OpenEXR's C++ does, so every corrupt B44 block "crashes". That is
/// what the first campaign found (`corpus/exr/crash-*`); lgh's own builds run that decoder
/// without overflow checks (the root `Cargo.toml`), and the replay test decodes those inputs in
/// full.
pub fn exr(data: &[u8]) {
    #[cfg(fuzzing)]
    if is_b44(data) {
        return;
    }
    let _ = lgh_image::decode_exr(Path::new("fuzz.exr"), data);
}

/// Whether a header of `data` names B44 or B44A compression.
#[cfg(fuzzing)]
fn is_b44(data: &[u8]) -> bool {
    use exr::compression::Compression;
    exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(data), false).is_ok_and(|m| {
        m.headers
            .iter()
            .any(|h| matches!(h.compression, Compression::B44 | Compression::B44A))
    })
}
