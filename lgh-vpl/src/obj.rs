//! Reading Wavefront OBJ + MTL files into a [`Mesh`] ([`Mesh::load_obj`], [`Mesh::parse_obj`],
//! through `tobj`): files read up to [`lgh_image::MAX_INPUT_BYTES`] and lines up to
//! [`MAX_LINE_BYTES`], face indices and colour statements checked before `tobj` sees them, and
//! MTL materials mapped to ours.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use lgh_core::glam::Vec3;
use lgh_core::Material;

use crate::mesh::{
    check_exponent, check_material, Mesh, MeshError, Triangle, DEFAULT_ALBEDO, DEFAULT_MATERIAL,
    MAX_LINE_BYTES,
};

impl Mesh {
    /// Reads a Wavefront OBJ file and the MTL files it names (`mtllib`, relative to the OBJ's
    /// folder). `tobj` reads the rest of an `mtllib` line as a single path (so names may contain
    /// spaces): `mtllib a.mtl b.mtl` names one file, `a.mtl b.mtl`; write one `mtllib` line per
    /// file. Polygons are triangulated as fans; points, lines and texture coordinates are
    /// ignored. Vertex normals are used if every corner of every face names one; otherwise
    /// every face is shaded with its face normal. A face's position, texture and normal indices
    /// must each be 1 to `n` or −`n` to −1 (counting back), where `n` is the number of
    /// positions, texture coordinates or normals before the face in the file.
    ///
    /// MTL mapping: `Kd` → diffuse reflectance, `Ks` → specular reflectance, `Ns` → Phong
    /// exponent; `Ks` absent or zero gives [`Material::Lambert`] with albedo `Kd`, otherwise
    /// [`Material::Phong`]; `Ke` → emitted radiance ([`Mesh::emission`], area lights). Other MTL
    /// statements (`Ka`, `Ni`, `illum`, textures) are ignored. A missing `Kd` is [`DEFAULT_MATERIAL`]'s albedo; a missing `Ns` is 1. Faces
    /// without `usemtl`, or naming a material no MTL file defines, get [`DEFAULT_MATERIAL`].
    ///
    /// Errors: a missing or unreadable OBJ or MTL file, a file larger than
    /// [`lgh_image::MAX_INPUT_BYTES`], a parse error (text that is not UTF-8 included), a face
    /// index out of range, non-finite coordinates, negative or non-finite material values, no
    /// triangle of non-zero area.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_core::Material;
    /// use lgh_vpl::Mesh;
    ///
    /// let dir = tempfile::tempdir()?;
    /// std::fs::write(dir.path().join("red.mtl"), "newmtl red\nKd 0.8 0.1 0.1\n")?;
    /// let obj = dir.path().join("square.obj");
    /// std::fs::write(
    ///     &obj,
    ///     "mtllib red.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf 1 2 3 4\n",
    /// )?;
    /// let mesh = Mesh::load_obj(&obj)?;
    /// // The quad is triangulated as a fan; no Ks makes the material Lambertian.
    /// assert_eq!(mesh.triangles().len(), 2);
    /// assert_eq!(mesh.bounds(), (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)));
    /// assert_eq!(
    ///     mesh.material(0),
    ///     Material::Lambert { albedo: Vec3::new(0.8, 0.1, 0.1) }
    /// );
    /// assert!(Mesh::load_obj(&dir.path().join("missing.obj")).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn load_obj(path: &Path) -> Result<Mesh, MeshError> {
        Mesh::load_obj_seen(path, |_, _| {})
    }

    /// [`load_obj`](Self::load_obj), showing `seen` the path and text of every file as it is
    /// read, the OBJ first and then each MTL: what a caller hashes to know exactly which bytes
    /// made the mesh (a render farm's manifest does).
    ///
    /// ```
    /// use lgh_vpl::Mesh;
    ///
    /// let dir = tempfile::tempdir()?;
    /// std::fs::write(dir.path().join("m.mtl"), "newmtl grey\nKd 0.5 0.5 0.5\n")?;
    /// let obj = dir.path().join("t.obj");
    /// std::fs::write(&obj, "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl grey\nf 1 2 3\n")?;
    /// let mut read = Vec::new();
    /// Mesh::load_obj_seen(&obj, |path, text| read.push((path.to_owned(), text.len())))?;
    /// assert_eq!(read, [(obj.clone(), 57), (dir.path().join("m.mtl"), 27)]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn load_obj_seen(
        path: &Path,
        mut seen: impl FnMut(&Path, &str),
    ) -> Result<Mesh, MeshError> {
        let text = read_text(path)?;
        seen(path, &text);
        let seen = RefCell::new(seen);
        let folder = path.parent().unwrap_or(Path::new(""));
        Mesh::parse_obj(path, &text, |name| {
            let mtl = folder.join(name);
            let text = read_text(&mtl)?;
            (seen.borrow_mut())(&mtl, &text);
            Ok((mtl, text))
        })
    }

    /// [`load_obj`](Self::load_obj) of OBJ `text` already in memory, named `path` in errors;
    /// `mtl(name)` gives each `mtllib` file's path (for errors) and text. The same checks, the
    /// same errors: what the fuzz target `obj` drives.
    ///
    /// ```
    /// use lgh_core::Material;
    /// use lgh_vpl::{Mesh, MeshError};
    /// use std::path::{Path, PathBuf};
    ///
    /// let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl grey\nf 1 2 3\n";
    /// let mtl = |name: &str| Ok((PathBuf::from(name), "newmtl grey\nKd 0.5 0.5 0.5\n".into()));
    /// let mesh = Mesh::parse_obj(Path::new("memory.obj"), obj, mtl)?;
    /// assert_eq!(mesh.triangles().len(), 1);
    /// // tobj would panic on `Kd 0.5`; this is a parse error naming the line.
    /// let bad = |name: &str| Ok((PathBuf::from(name), "newmtl grey\nKd 0.5\n".into()));
    /// let e = Mesh::parse_obj(Path::new("memory.obj"), obj, bad).unwrap_err();
    /// assert!(e.to_string().contains("line 2: Kd needs three numbers"), "{e}");
    /// # Ok::<(), MeshError>(())
    /// ```
    pub fn parse_obj(
        path: &Path,
        text: &str,
        mtl: impl Fn(&str) -> Result<(PathBuf, String), MeshError>,
    ) -> Result<Mesh, MeshError> {
        // Before tobj, which panics on some indices out of range.
        let normals_everywhere = check_faces(path, text)?;
        // The first MTL error, with its path: tobj only keeps a bare error code.
        let mtl_error: RefCell<Option<MeshError>> = RefCell::new(None);
        let options = tobj::LoadOptions {
            single_index: false,
            triangulate: true,
            ignore_points: true,
            ignore_lines: true,
        };
        let loaded = tobj::load_obj_buf(&mut text.as_bytes(), &options, |name| {
            let keep = |e: MeshError| {
                mtl_error.borrow_mut().get_or_insert(e);
            };
            let name = name.to_string_lossy();
            match mtl(&name).and_then(|(path, text)| check_mtl(&path, text).map(|t| (path, t))) {
                Ok((path, text)) => tobj::load_mtl_buf(&mut text.as_bytes()).inspect_err(|e| {
                    keep(MeshError::Parse {
                        path,
                        message: e.to_string(),
                    })
                }),
                Err(e) => {
                    keep(e);
                    Err(tobj::LoadError::GenericFailure)
                }
            }
        });
        if let Some(e) = mtl_error.into_inner() {
            return Err(e);
        }
        let (models, materials) = loaded.map_err(|e| MeshError::Parse {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        // Every MTL file loaded (their errors returned above), so this is Ok or "none named".
        let materials = materials.unwrap_or_default();
        from_tobj(&models, &materials, normals_everywhere)
    }
}

/// The text of `path`, read up to [`lgh_image::MAX_INPUT_BYTES`]; bytes that are not UTF-8 are
/// a parse error.
fn read_text(path: &Path) -> Result<String, MeshError> {
    let io = |error: std::io::Error| MeshError::Io {
        path: path.to_owned(),
        error,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    if file.metadata().map_err(io)?.len() > lgh_image::MAX_INPUT_BYTES {
        return Err(MeshError::TooLarge {
            path: path.to_owned(),
        });
    }
    // `take`: what reports no size (a FIFO) is still never read past the limit.
    let limited = std::io::Read::take(file, lgh_image::MAX_INPUT_BYTES + 1);
    let bytes = read_lines_limited(limited, MAX_LINE_BYTES).map_err(|e| match e {
        LineError::Io(error) => io(error),
        LineError::TooLong { line } => MeshError::Parse {
            path: path.to_owned(),
            message: format!("line {line} is longer than {MAX_LINE_BYTES} bytes"),
        },
    })?;
    if bytes.len() as u64 > lgh_image::MAX_INPUT_BYTES {
        return Err(MeshError::TooLarge {
            path: path.to_owned(),
        });
    }
    String::from_utf8(bytes).map_err(|e| MeshError::Parse {
        path: path.to_owned(),
        message: format!("not UTF-8 text ({e})"),
    })
}
/// Why [`read_lines_limited`] stopped.
enum LineError {
    Io(std::io::Error),
    /// Line `line` (from 1) is longer than the limit.
    TooLong {
        line: usize,
    },
}

/// Reads `r` to the end in blocks, stopping as soon as a line is longer than `max_line` bytes:
/// a file of one 4 GiB line is refused after 1 MiB of it, not after reading it all.
fn read_lines_limited(mut r: impl std::io::Read, max_line: usize) -> Result<Vec<u8>, LineError> {
    let mut out = Vec::new();
    let mut block = vec![0u8; 1 << 16];
    let (mut line, mut run) = (1usize, 0usize);
    loop {
        let n = match r.read(&mut block) {
            Ok(0) => return Ok(out),
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(LineError::Io(e)),
        };
        for &b in &block[..n] {
            if b == b'\n' {
                line += 1;
                run = 0;
            } else {
                run += 1;
                if run > max_line {
                    return Err(LineError::TooLong { line });
                }
            }
        }
        out.extend_from_slice(&block[..n]);
    }
}

/// The MTL `text` of `path`, its colour statements checked for their three numbers: `tobj`
/// 4.0.5 panics on `Kd 0.5`.
fn check_mtl(path: &Path, text: String) -> Result<String, MeshError> {
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            if words.count() < 3 {
                return Err(MeshError::Parse {
                    path: path.to_owned(),
                    message: format!("line {}: {key} needs three numbers", i + 1),
                });
            }
        }
    }
    Ok(text)
}

/// Our material for an MTL material (the mapping of [`Mesh::load_obj`]).
fn from_mtl(m: &tobj::Material) -> Result<Material, MeshError> {
    let invalid = |reason| MeshError::InvalidMaterial {
        name: m.name.clone(),
        reason,
    };
    let kd = m.diffuse.map_or(DEFAULT_ALBEDO, Vec3::from);
    let ks = m.specular.map_or(Vec3::ZERO, Vec3::from);
    let exponent = m.shininess.unwrap_or(1.0);
    // Checked even where `Ks` is zero and the exponent unused.
    check_exponent(exponent).map_err(invalid)?;
    let material = if ks == Vec3::ZERO {
        Material::Lambert { albedo: kd }
    } else {
        Material::Phong { kd, ks, exponent }
    };
    check_material(&material).map_err(invalid)?;
    Ok(material)
}

/// Checks the indices of the faces (`f`) of the OBJ text `obj` read from `path`, and returns
/// true if every corner of every face names a normal (`v//n`, `v/t/n`).
///
/// Each position, texture and normal index must be 1 to `n` or −`n` to −1, where `n` is the
/// number of positions (`v`), texture coordinates (`vt`) or normals (`vn`) before the face:
/// `tobj` 4.0.5 overflows on others (a panic in debug builds) and takes 0 for "no index".
fn check_faces(path: &Path, obj: &str) -> Result<bool, MeshError> {
    const WHAT: [&str; 3] = ["position", "texture coordinate", "normal"];
    // Positions, texture coordinates and normals so far.
    let mut counts = [0i64; 3];
    let mut normals_everywhere = true;
    for (line, text) in obj.lines().enumerate() {
        let mut words = text.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") => {
                for corner in words {
                    normals_everywhere &= corner.split('/').nth(2).is_some_and(|n| !n.is_empty());
                    for (k, index) in corner.split('/').take(3).enumerate() {
                        // An empty index is an absent one (`v//n`).
                        let problem = match index.parse::<i64>() {
                            _ if index.is_empty() => continue,
                            Ok(i) if (1..=counts[k]).contains(&i) => continue,
                            Ok(i) if (-counts[k]..=-1).contains(&i) => continue,
                            Err(_) => "is not an integer".to_string(),
                            Ok(_) if counts[k] == 0 => format!("has no {} before it", WHAT[k]),
                            Ok(_) => format!(
                                "is not 1 to {0} or -1 to -{0} ({1}s before it: {0})",
                                counts[k], WHAT[k]
                            ),
                        };
                        return Err(MeshError::Parse {
                            path: path.to_owned(),
                            message: format!(
                                "line {}: {} index {index} in `{corner}` {problem}",
                                line + 1,
                                WHAT[k]
                            ),
                        });
                    }
                }
            }
            _ => {}
        }
    }
    Ok(normals_everywhere)
}

/// The mesh of `tobj`'s models and materials; faces without a known material get
/// [`DEFAULT_MATERIAL`], appended after the MTL materials. Vertex normals are used only if
/// `normals_everywhere`: where some faces lack them, `tobj` makes up normals for those faces
/// (copying another corner's), and which faces they are is lost.
fn from_tobj(
    models: &[tobj::Model],
    mtls: &[tobj::Material],
    normals_everywhere: bool,
) -> Result<Mesh, MeshError> {
    let mut materials = mtls.iter().map(from_mtl).collect::<Result<Vec<_>, _>>()?;
    let default = u32::try_from(materials.len()).map_err(|_| MeshError::TooMany)?;
    materials.push(DEFAULT_MATERIAL);
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for model in models {
        let mesh = &model.mesh;
        let offset = |base: usize| u32::try_from(base).map_err(|_| MeshError::TooMany);
        let (p0, n0) = (offset(positions.len())?, offset(normals.len())?);
        positions.extend(mesh.positions.chunks_exact(3).map(Vec3::from_slice));
        normals.extend(mesh.normals.chunks_exact(3).map(Vec3::from_slice));
        let material = mesh
            .material_id
            .filter(|&i| i < mtls.len())
            .map_or(default, |i| i as u32);
        let with_normals = normals_everywhere && mesh.normal_indices.len() == mesh.indices.len();
        for (k, corners) in mesh.indices.chunks_exact(3).enumerate() {
            let triangle = triangles.len();
            let shift = |base: u32, i: u32| {
                base.checked_add(i)
                    .ok_or(MeshError::IndexOutOfRange { triangle })
            };
            let shift3 = |base: u32, c: &[u32]| -> Result<[u32; 3], MeshError> {
                Ok([shift(base, c[0])?, shift(base, c[1])?, shift(base, c[2])?])
            };
            triangles.push(Triangle {
                vertices: shift3(p0, corners)?,
                normals: match with_normals {
                    true => Some(shift3(n0, &mesh.normal_indices[3 * k..3 * k + 3])?),
                    false => None,
                },
                material,
            });
        }
    }
    let mut mesh = Mesh::new(positions, normals, triangles, materials)?;
    for (i, m) in mtls.iter().enumerate() {
        if let Some(ke) = m.emissive {
            mesh.set_emission(i as u32, Vec3::from(ke)).map_err(|_| {
                MeshError::InvalidMaterial {
                    name: m.name.clone(),
                    reason: "emission (Ke) must be finite and not negative",
                }
            })?;
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    /// `obj` written as `scene.obj` beside `mtl` as `scene.mtl` (if given), then loaded.
    fn load(obj: &str, mtl: Option<&str>) -> Result<Mesh, MeshError> {
        let dir = tempfile::tempdir().unwrap();
        if let Some(mtl) = mtl {
            write(dir.path(), "scene.mtl", mtl);
        }
        Mesh::load_obj(&write(dir.path(), "scene.obj", obj))
    }
    #[test]
    fn obj_and_mtl_load_with_the_documented_mapping() {
        let obj = "\
# before any usemtl: the default material
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
vn 0 0 1
vn 0 0 2
f 1 2 3
mtllib scene.mtl
usemtl matte
f 1 2 3 4
usemtl shiny
f 1//1 2//1 3//2
# zero area: skipped
f 1 2 5
usemtl undefined
f 1 3 4
";
        let mtl = "\
newmtl matte
Kd 0.25 0.5 0.75
Ks 0 0 0
Ns 10
newmtl shiny
Kd 0.1 0.2 0.3
Ks 0.4 0.4 0.4
Ns 32
newmtl unused
";
        let m = load(obj, Some(mtl)).unwrap();
        let matte = Material::Lambert {
            albedo: Vec3::new(0.25, 0.5, 0.75),
        };
        let shiny = Material::Phong {
            kd: Vec3::new(0.1, 0.2, 0.3),
            ks: Vec3::splat(0.4),
            exponent: 32.0,
        };
        let unused = Material::Lambert {
            albedo: Vec3::splat(0.5),
        };
        assert_eq!(m.materials(), &[matte, shiny, unused, DEFAULT_MATERIAL]);
        // 1 + 2 (the quad) + 1 + 0 (skipped) + 1.
        assert_eq!(m.triangles().len(), 5);
        assert_eq!(m.degenerate_skipped(), 1);
        let materials: Vec<Material> = (0..5).map(|t| m.material(t)).collect();
        assert_eq!(
            materials,
            [DEFAULT_MATERIAL, matte, matte, shiny, DEFAULT_MATERIAL]
        );
        // Some faces have no vertex normals: face normals everywhere.
        assert!(m.triangles().iter().all(|t| t.normals.is_none()));
        assert_eq!(
            m.corners(2),
            [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]
        );
        // Every face has them: used, and normalised when interpolated.
        let m = load(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 2\nvn 1 0 0\nf 1//1 2//2 3//3\n",
            None,
        )
        .unwrap();
        assert_eq!(m.triangles()[0].normals, Some([0, 1, 2]));
        assert_eq!(m.shading_normal(0, 0.5, 0.0), Vec3::Z);
        let n = m.shading_normal(0, 0.0, 0.5);
        assert!(
            (n - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6,
            "{n}"
        );
    }

    #[test]
    fn bad_obj_and_mtl_files_are_clear_errors() {
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        let with_mtl = |mtl: &str| {
            load(
                &format!("mtllib scene.mtl\n{tri}usemtl a\nf 1 2 3\n"),
                Some(mtl),
            )
        };
        let missing = Mesh::load_obj(Path::new("/nonexistent/scene.obj")).unwrap_err();
        assert!(
            matches!(&missing, MeshError::Io { error, .. } if error.kind() == std::io::ErrorKind::NotFound),
            "{missing}"
        );
        let no_mtl = load(&format!("mtllib gone.mtl\n{tri}f 1 2 3\n"), None).unwrap_err();
        assert!(
            matches!(&no_mtl, MeshError::Io { path, .. } if path.ends_with("gone.mtl")),
            "{no_mtl}"
        );
        for (obj, what) in [
            ("v 0 0\nf 1 2 3\n", "a vertex with two coordinates"),
            (&format!("{tri}f 1 2 7\n"), "an index past the end"),
            (&format!("{tri}f 1 2 x\n"), "a non-numeric index"),
        ] {
            let e = load(obj, None).unwrap_err();
            assert!(matches!(e, MeshError::Parse { .. }), "{what}: {e}");
        }
        for mtl in [
            "newmtl a\nKd 0.5\n",
            "newmtl a\nKs 1 1\n",
            "newmtl a\nNs x\n",
        ] {
            let e = with_mtl(mtl).unwrap_err();
            assert!(
                matches!(&e, MeshError::Parse { path, .. } if path.ends_with("scene.mtl")),
                "{mtl:?}: {e}"
            );
        }
        for mtl in [
            "newmtl a\nKd -0.5 0.5 0.5\n",
            "newmtl a\nKd 0.5 nan 0.5\n",
            "newmtl a\nKd 0.5 0.5 0.5\nKs inf 0 0\n",
            "newmtl a\nKs 0.5 0.5 0.5\nNs -3\n",
            "newmtl a\nNs nan\n",
        ] {
            let e = with_mtl(mtl).unwrap_err();
            assert!(
                matches!(&e, MeshError::InvalidMaterial { name, .. } if name == "a"),
                "{mtl:?}: {e}"
            );
        }
        assert!(matches!(
            load("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", None),
            Err(MeshError::NonFiniteVertex { index: 0 })
        ));
        assert!(matches!(
            load(&format!("{tri}vn 0 inf 1\nf 1//1 2//1 3//1\n"), None),
            Err(MeshError::NonFiniteNormal { index: 0 })
        ));
        for obj in [
            "",
            "# nothing\n",
            &format!("{tri}l 1 2\np 3\n"),
            "v 0 0 0\nf 1 1 1\n",
        ] {
            assert!(
                matches!(load(obj, None), Err(MeshError::NoTriangles { .. })),
                "{obj:?}"
            );
        }
    }

    #[test]
    fn face_indices_out_of_range_or_zero_are_errors_naming_the_line() {
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        for (obj, line) in [
            // tobj 4.0.5 overflows on the first two, and reads index 0 as "missing".
            (format!("{tri}vn 0 0 1\nf 1//-3 2//-3 3//-3\n"), 5),
            (
                format!("{tri}vn 0 0 1\nf 1//9000000000000000000 2//1 3//1\n"),
                5,
            ),
            (format!("{tri}vn 0 0 1\nf 1//0 2//0 3//0\n"), 5),
            (format!("{tri}vt 0 0\nf 1/-2 2/1 3/1\n"), 5),
            (format!("{tri}vt 0 0\nf 1/0 2/1 3/1\n"), 5),
            (format!("{tri}f 0 2 3\n"), 4),
            (format!("{tri}f 1 2 -4\n"), 4),
            (format!("{tri}f 1 2 -9223372036854775808\n"), 4),
            // Counted so far: a face cannot name an element defined after it.
            (format!("f 1 2 3\n{tri}"), 1),
            (format!("{tri}vn 0 0 1\nf 1//1 2//1 3//2\nvn 0 0 1\n"), 5),
        ] {
            let e = load(&obj, None).unwrap_err();
            let prefix = format!("line {line}: ");
            assert!(
                matches!(&e, MeshError::Parse { message, .. } if message.starts_with(&prefix)),
                "{obj:?}: {e}"
            );
        }
        // Negative indices count back from the last element read so far.
        let m = load(
            &format!(
                "{tri}vn 0 0 1\nvt 0 0\nf -3/-1/-1 -2/-1/-1 -1/-1/-1\n\
                 v 5 5 5\nv 6 5 5\nv 5 6 5\nvn 1 0 0\nf -3//-1 -2//-1 -1//-1\n"
            ),
            None,
        )
        .unwrap();
        assert_eq!(m.triangles().len(), 2);
        assert_eq!(
            m.corners(1),
            [
                Vec3::splat(5.0),
                Vec3::new(6.0, 5.0, 5.0),
                Vec3::new(5.0, 6.0, 5.0)
            ]
        );
        assert_eq!(
            (m.shading_normal(0, 0.2, 0.2), m.shading_normal(1, 0.2, 0.2)),
            (Vec3::Z, Vec3::X)
        );
    }

    #[test]
    fn non_utf8_obj_and_mtl_files_are_parse_errors() {
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join("scene.obj");
        let tri = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        std::fs::write(&obj, [&tri[..], b"# caf\xe9\n"].concat()).unwrap();
        let e = Mesh::load_obj(&obj).unwrap_err();
        assert!(
            matches!(&e, MeshError::Parse { path, .. } if *path == obj),
            "{e}"
        );
        std::fs::write(&obj, [b"mtllib scene.mtl\n", &tri[..]].concat()).unwrap();
        std::fs::write(dir.path().join("scene.mtl"), b"newmtl caf\xe9\n").unwrap();
        let e = Mesh::load_obj(&obj).unwrap_err();
        assert!(
            matches!(&e, MeshError::Parse { path, .. } if path.ends_with("scene.mtl")),
            "{e}"
        );
    }

    #[test]
    fn the_cornell_box_loads() {
        let path =
            lgh_tests::shared_data().join("meshes/cornellbox_original/CornellBox-Original.obj");
        if !path.exists() {
            eprintln!("SKIPPED: {} is not here", path.display());
            return;
        }
        let m = Mesh::load_obj(&path).unwrap();
        // 18 quads, no zero-area triangles; 8 MTL materials, all Lambertian, and the default.
        assert_eq!((m.triangles().len(), m.degenerate_skipped()), (36, 0));
        assert_eq!(m.materials().len(), 9);
        assert!(m
            .materials()
            .iter()
            .all(|m| matches!(m, Material::Lambert { .. })));
        let (lo, hi) = m.bounds();
        assert_eq!(
            (lo, hi),
            (Vec3::new(-1.02, 0.0, -1.04), Vec3::new(1.0, 1.99, 0.99))
        );
        let red = Material::Lambert {
            albedo: Vec3::new(0.63, 0.065, 0.05),
        };
        assert!(m.materials().contains(&red));
    }
}
