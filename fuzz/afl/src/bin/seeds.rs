//! `seeds OUT_DIR [SHARED_DATA]`: the seed inputs of every target in `OUT_DIR/TARGET/` (for
//! `vdb`, those the official library cannot write; `make_vdb_seeds.py` adds crops of a real
//! frame). Real files from `SHARED_DATA` (default
//! `../../shared/data`, beside the checkout) where there are some: Blender's configs, the
//! Cornell box; made here where there are none: PLY in its three encodings, EXR in every
//! compression the `exr` crate writes.

use std::path::{Path, PathBuf};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().ok_or("usage: seeds OUT_DIR [SHARED_DATA]")?);
    let shared = args.next().map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
        PathBuf::from,
    );
    for t in ["vdb", "uni", "ply", "obj", "exr"] {
        std::fs::create_dir_all(out.join(t))?;
    }
    vdb(&out.join("vdb"))?;
    uni(&out.join("uni"), &shared)?;
    ply(&out.join("ply"))?;
    obj(&out.join("obj"), &shared)?;
    exr(&out.join("exr"))?;
    Ok(())
}

/// What the official library does not write (the crops of a real frame are
/// `make_vdb_seeds.py`'s): raw and zip node values, root tiles at the ends of the index space.
fn vdb(dir: &Path) -> Result<()> {
    use lgh_volume::vdb::synthetic::{tiled_file, Storage};
    let ends = [[i32::MIN; 3], [i32::MAX - 4095; 3]];
    std::fs::write(
        dir.join("tiled-raw.vdb"),
        tiled_file(Storage::Raw, &[], 1, 1),
    )?;
    std::fs::write(
        dir.join("tiled-zip.vdb"),
        tiled_file(Storage::Zip, &ends, 2, 2),
    )?;
    std::fs::write(
        dir.join("root-tiles.vdb"),
        tiled_file(Storage::Zip, &ends, 0, 0),
    )?;
    Ok(())
}

/// Blender's fluid configs of the dev fire, and one made up (gzip with every header field).
fn uni(dir: &Path, shared: &Path) -> Result<()> {
    let configs = shared.join("volumes/blender_fire_pesichra/config");
    match std::fs::read_dir(&configs) {
        Ok(entries) => {
            for e in entries {
                let p = e?.path();
                std::fs::copy(&p, dir.join(p.file_name().unwrap()))?;
            }
        }
        Err(e) => eprintln!("seeds: no real .uni configs ({}: {e})", configs.display()),
    }
    Ok(())
}

/// Ten lights in ASCII, binary little- and big-endian PLY, with a face element to skip and
/// properties of several types.
fn ply(dir: &Path) -> Result<()> {
    let header = |format: &str| {
        format!(
            "ply\nformat {format} 1.0\ncomment lgh seed\nelement vertex 10\nproperty float x\n\
             property float y\nproperty float z\nproperty double r\nproperty float g\n\
             property uchar b\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        )
    };
    let rows: Vec<[f64; 6]> = (0..10)
        .map(|i| {
            let t = f64::from(i);
            [
                t * 0.1,
                1.0 - t * 0.05,
                t * t * 0.01,
                t,
                0.5,
                f64::from(i * 20),
            ]
        })
        .collect();
    let mut ascii = header("ascii");
    for r in &rows {
        ascii += &format!("{} {} {} {} {} {}\n", r[0], r[1], r[2], r[3], r[4], r[5]);
    }
    ascii += "3 0 1 2\n";
    std::fs::write(dir.join("ascii.ply"), ascii)?;
    for (name, big) in [("binary_little_endian", false), ("binary_big_endian", true)] {
        let mut b = header(name).into_bytes();
        for r in &rows {
            for (k, v) in r.iter().enumerate() {
                match k {
                    3 => b.extend(if big {
                        v.to_be_bytes()
                    } else {
                        v.to_le_bytes()
                    }),
                    5 => b.push(*v as u8),
                    _ => {
                        let f = *v as f32;
                        b.extend(if big {
                            f.to_be_bytes()
                        } else {
                            f.to_le_bytes()
                        });
                    }
                }
            }
        }
        b.push(3);
        for i in 0..3i32 {
            b.extend(if big {
                i.to_be_bytes()
            } else {
                i.to_le_bytes()
            });
        }
        std::fs::write(dir.join(format!("{name}.ply")), b)?;
    }
    Ok(())
}

/// The Cornell box (OBJ, then the separator, then its MTL), and a small made-up scene with
/// normals, texture coordinates, negative indices and a Phong material.
fn obj(dir: &Path, shared: &Path) -> Result<()> {
    let sep = lgh_fuzz::MTL_SEPARATOR;
    let cornell = shared.join("meshes/cornellbox_original");
    match (
        std::fs::read(cornell.join("CornellBox-Original.obj")),
        std::fs::read(cornell.join("CornellBox-Original.mtl")),
    ) {
        (Ok(o), Ok(m)) => std::fs::write(dir.join("cornell.obj"), [&o[..], sep, &m[..]].concat())?,
        _ => eprintln!("seeds: no Cornell box in {}", cornell.display()),
    }
    let scene = "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n\
                 usemtl shiny\nf 1/1/1 2/2/1 3/1/1 4/2/1\nusemtl matte\nf -4//-1 -3//-1 -2//-1\n\
                 o second\ng group\nf 1 3 4\n";
    let mtl = "newmtl shiny\nKd 0.5 0.4 0.3\nKs 0.2 0.2 0.2\nNs 40\nnewmtl matte\nKd 0.8 0.8 0.8\n";
    std::fs::write(
        dir.join("scene.obj"),
        [scene.as_bytes(), sep, mtl.as_bytes()].concat(),
    )?;
    Ok(())
}

/// An 8×6 RGB gradient in every compression, as scan lines and as tiles.
fn exr(dir: &Path) -> Result<()> {
    use exr::prelude::*;
    let compressions = [
        ("none", Compression::Uncompressed),
        ("rle", Compression::RLE),
        ("zip1", Compression::ZIP1),
        ("zip16", Compression::ZIP16),
        ("piz", Compression::PIZ),
        ("pxr24", Compression::PXR24),
        ("b44", Compression::B44),
    ];
    for (name, compression) in compressions {
        for (blocks_name, blocks) in [
            ("lines", Blocks::ScanLines),
            ("tiles", Blocks::Tiles(Vec2(4, 4))),
        ] {
            let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
                (
                    p.0 as f32 * 0.25,
                    p.1 as f32 * 0.5,
                    (p.0 * p.1) as f32 * 0.01,
                )
            });
            let encoding = Encoding {
                compression,
                blocks,
                line_order: LineOrder::Increasing,
            };
            let layer = Layer::new((8, 6), LayerAttributes::named("rgb"), encoding, channels);
            Image::from_layer(layer)
                .write()
                .to_file(dir.join(format!("{name}-{blocks_name}.exr")))?;
        }
    }
    Ok(())
}
