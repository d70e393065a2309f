//! Reading Wavefront OBJ + MTL files into a [`Mesh`] ([`Mesh::load_obj`], [`Mesh::parse_obj`],
//! through `tobj`): files read up to [`lgh_image::MAX_INPUT_BYTES`] and lines up to
//! [`MAX_LINE_BYTES`], face indices and colour statements checked before `tobj` sees them, and
//! MTL materials mapped to ours, their diffuse textures read ([`crate::texture`]), and every
//! statement the renderer does not honour named ([`crate::statements`]).

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use lgh_core::glam::{Vec2, Vec3};
use lgh_core::Material;

use crate::mesh::{
    check_exponent, check_material, Mesh, MeshError, Triangle, DEFAULT_ALBEDO, DEFAULT_MATERIAL,
    MAX_LINE_BYTES,
};
use crate::specular::Specular;
use crate::statements::{scan_mtl, scan_obj, Report};
use crate::texture::Texture;

/// What to do where a material's texture file is missing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MissingTextures {
    /// An error naming the file.
    #[default]
    Error,
    /// The material's diffuse colour becomes [`DEFAULT_MATERIAL`]'s grey (0.5, `Kd` not
    /// applied), and the missing file is named in [`Mesh::unhonoured`].
    Grey,
}

/// Which normals shade a face.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Normals {
    /// The OBJ's vertex normals (`vn`), interpolated, where a face names one at every corner;
    /// its face normal elsewhere.
    #[default]
    Vertex,
    /// Every face its own face normal, whatever `vn` the file gives (named in
    /// [`Mesh::unhonoured`] at its first use): for meshes whose vertex normals are poor,
    /// such as Sponza's, a tenth of whose corners lean more than 68° from their face.
    Face,
}

/// How [`Mesh::load_obj_with`] reads a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ObjOptions {
    /// What a missing texture file does.
    pub missing_textures: MissingTextures,
    /// Which normals shade a face.
    pub normals: Normals,
}

impl Mesh {
    /// Reads a Wavefront OBJ file and the MTL files it names (`mtllib`, relative to the OBJ's
    /// folder). `tobj` reads the rest of an `mtllib` line as a single path (so names may contain
    /// spaces): `mtllib a.mtl b.mtl` names one file, `a.mtl b.mtl`; write one `mtllib` line per
    /// file. Polygons are triangulated as fans; points and lines are not rendered. A face whose
    /// every corner names a vertex normal is shaded with the interpolated normals, the others
    /// with their face normals; a face whose every corner names texture coordinates reads its
    /// material's diffuse texture there. A face's position, texture and normal indices
    /// must each be 1 to `n` or −`n` to −1 (counting back), where `n` is the number of
    /// positions, texture coordinates or normals before the face in the file.
    ///
    /// MTL mapping: `Kd` → diffuse reflectance, `Ks` → specular reflectance, `Ns` → Phong
    /// exponent; `Ks` absent or zero (or `illum` 0 or 1, which have no highlight) gives
    /// [`Material::Lambert`] with albedo `Kd`, otherwise
    /// [`Material::Phong`]; `Ke` → emitted radiance ([`Mesh::emission`], area lights); `map_Kd`
    /// → a diffuse texture multiplying `Kd` ([`Mesh::set_diffuse_texture`]; PNG, JPEG or TGA,
    /// named relative to its MTL file's folder; texture options such as `-s` are skipped);
    /// `map_Ks` → a texture multiplying a Phong material's `Ks`; `map_d` → a coverage map
    /// cutting holes where it is under ½ ([`Mesh::set_coverage_texture`]: alpha, or the first
    /// channel of an image without one; `d` itself is not a cut-out, and is named). A
    /// missing `Kd` is [`DEFAULT_MATERIAL`]'s albedo; a missing `Ns` is 1. Faces without
    /// `usemtl`, or naming a material no MTL file defines, get [`DEFAULT_MATERIAL`]. Every
    /// statement not honoured (`Ka`, `illum 7`, `map_Bump`, …) is listed in
    /// [`Mesh::unhonoured`] with the file and line of its first use, and so, once with their
    /// count, are the triangles of zero area, which are dropped ([`ZERO_AREA`]).
    ///
    /// Errors: a missing or unreadable OBJ, MTL or texture file (see [`ObjOptions`] for
    /// textures), a texture that is not an image or is too large, a file larger than
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
        Mesh::load_obj_with(path, &ObjOptions::default(), |_, _| {})
    }

    /// [`load_obj`](Self::load_obj) with `options`, showing `seen` the path and bytes of every
    /// file as it is read, the OBJ first and then each MTL and texture: what a caller hashes to
    /// know exactly which bytes made the mesh (a render farm's manifest does).
    ///
    /// ```
    /// use lgh_vpl::obj::ObjOptions;
    /// use lgh_vpl::Mesh;
    ///
    /// let dir = tempfile::tempdir()?;
    /// std::fs::write(dir.path().join("m.mtl"), "newmtl grey\nKd 0.5 0.5 0.5\n")?;
    /// let obj = dir.path().join("t.obj");
    /// std::fs::write(&obj, "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl grey\nf 1 2 3\n")?;
    /// let mut read = Vec::new();
    /// let options = ObjOptions::default();
    /// Mesh::load_obj_with(&obj, &options, |path, bytes| read.push((path.to_owned(), bytes.len())))?;
    /// assert_eq!(read, [(obj.clone(), 57), (dir.path().join("m.mtl"), 27)]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn load_obj_with(
        path: &Path,
        options: &ObjOptions,
        mut seen: impl FnMut(&Path, &[u8]),
    ) -> Result<Mesh, MeshError> {
        let text = read_text(path)?;
        seen(path, text.as_bytes());
        let seen = RefCell::new(seen);
        let folder = path.parent().unwrap_or(Path::new(""));
        Mesh::parse_obj(path, &text, options, |name| {
            let file = folder.join(name);
            let bytes = read_file(&file)?;
            (seen.borrow_mut())(&file, &bytes);
            Ok((file, bytes))
        })
    }

    /// [`load_obj_with`](Self::load_obj_with) of OBJ `text` already in memory, named `path` in
    /// errors; `read(name)` gives the path (for errors) and bytes of each file the scene names,
    /// relative to the OBJ's folder: its `mtllib` files and their textures. The same checks, the
    /// same errors: what the fuzz target `obj` drives.
    ///
    /// ```
    /// use lgh_core::Material;
    /// use lgh_vpl::obj::ObjOptions;
    /// use lgh_vpl::{Mesh, MeshError};
    /// use std::path::{Path, PathBuf};
    ///
    /// let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl grey\nf 1 2 3\n";
    /// let options = ObjOptions::default();
    /// let mtl = |name: &Path| Ok((name.to_owned(), b"newmtl grey\nKd 0.5 0.5 0.5\nKa 1 1 1\n".to_vec()));
    /// let mesh = Mesh::parse_obj(Path::new("memory.obj"), obj, &options, mtl)?;
    /// assert_eq!(mesh.triangles().len(), 1);
    /// assert_eq!(mesh.unhonoured()[0].to_string(), "m.mtl:3: `Ka` ambient colour has no meaning \
    ///     in a physically based renderer: ignored");
    /// // tobj would panic on `Kd 0.5`; this is a parse error naming the line.
    /// let bad = |name: &Path| Ok((name.to_owned(), b"newmtl grey\nKd 0.5\n".to_vec()));
    /// let e = Mesh::parse_obj(Path::new("memory.obj"), obj, &options, bad).unwrap_err();
    /// assert!(e.to_string().contains("line 2: Kd needs three numbers"), "{e}");
    /// # Ok::<(), MeshError>(())
    /// ```
    pub fn parse_obj(
        path: &Path,
        text: &str,
        options: &ObjOptions,
        read: impl Fn(&Path) -> Result<(PathBuf, Vec<u8>), MeshError>,
    ) -> Result<Mesh, MeshError> {
        // Before tobj, which panics on some indices out of range.
        let faces = check_faces(path, text)?;
        let mut report = Report::default();
        let vertex_normals = options.normals == Normals::Vertex;
        let some_flat = faces.iter().any(|f| !f.normals);
        scan_obj(path, text, some_flat, vertex_normals, &mut report);
        let report = RefCell::new(report);
        // Each MTL file's folder (relative to the OBJ's) and how many materials it defines, in
        // the order tobj appends them.
        let libraries: RefCell<Vec<(PathBuf, usize)>> = RefCell::new(Vec::new());
        // The first MTL error, with its path: tobj only keeps a bare error code.
        let mtl_error: RefCell<Option<MeshError>> = RefCell::new(None);
        let load_options = tobj::LoadOptions {
            single_index: false,
            triangulate: true,
            ignore_points: true,
            ignore_lines: true,
        };
        // Lines (`l`) are not surfaces: tobj would read one of three or more corners as a
        // polygon, and never checks its indices. They go to tobj as comments.
        let surfaces = without_lines(text);
        let loaded = tobj::load_obj_buf(&mut surfaces.as_bytes(), &load_options, |name| {
            let keep = |e: MeshError| {
                mtl_error.borrow_mut().get_or_insert(e);
            };
            let text = read(name).and_then(|(path, bytes)| {
                let text = utf8(&path, bytes)?;
                check_mtl(&path, text).map(|t| (path, t))
            });
            match text {
                Ok((file, text)) => {
                    let loaded = tobj::load_mtl_buf(&mut text.as_bytes()).inspect_err(|e| {
                        keep(MeshError::Parse {
                            path: file.clone(),
                            message: e.to_string(),
                        })
                    });
                    if let Ok((materials, _)) = &loaded {
                        scan_mtl(&file, &text, &mut report.borrow_mut());
                        let folder = name.parent().unwrap_or(Path::new("")).to_owned();
                        libraries.borrow_mut().push((folder, materials.len()));
                    }
                    loaded
                }
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
        let mut report = report.into_inner();
        let mut mesh = from_tobj(&models, &materials, &faces, vertex_normals, &mut report)?;
        note_zero_area(path, &mesh, &mut report);
        let folders = libraries
            .into_inner()
            .into_iter()
            .flat_map(|(folder, n)| std::iter::repeat_n(folder, n));
        let mut textures: HashMap<(PathBuf, bool), Option<u32>> = HashMap::new();
        for ((i, m), folder) in materials.iter().enumerate().zip(folders) {
            let maps = [
                (&m.diffuse_texture, Map::Diffuse),
                (&m.specular_texture, Map::Specular),
                (&m.dissolve_texture, Map::Coverage),
            ];
            for (map, kind) in maps {
                let Some(map) = map else {
                    continue;
                };
                // map_Ks of a mirror or glass, map_d of glass: named by the scan, not read.
                let specular = mesh.specular_of(i as u32);
                let glass = matches!(specular, Specular::Dielectric { .. });
                if (kind == Map::Specular && specular != Specular::None)
                    || (kind == Map::Coverage && glass)
                {
                    continue;
                }
                let name = folder.join(texture_file(map));
                // A file read as a coverage decodes differently from one read as a colour.
                let key = (name, kind == Map::Coverage);
                let index = match textures.get(&key) {
                    Some(&index) => index,
                    None => {
                        let index =
                            read_texture(&key.0, kind, options, &read, &mut mesh, &mut report)?;
                        textures.insert(key, index);
                        index
                    }
                };
                match (index, kind) {
                    (Some(index), Map::Diffuse) => mesh.use_texture(i as u32, index),
                    (Some(index), Map::Specular) => mesh.use_specular_texture(i as u32, index),
                    (Some(index), Map::Coverage) => mesh.use_coverage_texture(i as u32, index),
                    // Missing, and `MissingTextures::Grey`: the grey of the default material
                    // (a missing map_Ks leaves Ks as it is, a missing map_d cuts no holes).
                    (None, Map::Diffuse) => mesh.set_material(i as u32, grey(mesh.materials()[i])),
                    (None, _) => {}
                }
            }
        }
        mesh.set_unhonoured(report.into_entries());
        Ok(mesh)
    }
}

/// Notes in `report`, once, how many of the triangles of `mesh` (read from `path`) had zero
/// area and were dropped ([`Mesh::degenerate_skipped`]): right to drop (they have nothing to
/// render), wrong to drop without a word (a scanned room had 53,627 of 331,179).
fn note_zero_area(path: &Path, mesh: &Mesh, report: &mut Report) {
    let dropped = mesh.degenerate_skipped();
    if dropped == 0 {
        return;
    }
    let total = dropped + mesh.triangles().len();
    let why = format!(
        "{dropped} of {total} triangles have zero area (repeated or collinear corners): \
         dropped, as they have nothing to render"
    );
    report.note(ZERO_AREA, path, 0, &why);
}

/// The statement under which [`Mesh::unhonoured`] names the zero-area triangles dropped.
pub const ZERO_AREA: &str = "f of zero area";

/// `obj` with its line statements (`l`) turned into comments, line numbers kept; borrowed
/// where there are none.
fn without_lines(obj: &str) -> std::borrow::Cow<'_, str> {
    let is_line = |l: &str| l.split_whitespace().next() == Some("l");
    if !obj.lines().any(is_line) {
        return std::borrow::Cow::Borrowed(obj);
    }
    let mut out = String::with_capacity(obj.len());
    for line in obj.split_inclusive('\n') {
        if is_line(line) {
            out.push('#');
        }
        out.push_str(line);
    }
    std::borrow::Cow::Owned(out)
}

/// The file name of a `map_Kd` statement's value: its options (`-s 2 2 1`, `-clamp on`, …)
/// and their arguments skipped, the rest (which may contain spaces) the name.
fn texture_file(value: &str) -> &str {
    let mut rest = value.trim();
    while let Some(option) = rest.strip_prefix('-') {
        let (name, after) = option
            .split_once(char::is_whitespace)
            .unwrap_or((option, ""));
        // Options of one word (`-clamp on`) and of up to three numbers (`-s u v w`).
        let words = match name {
            "o" | "s" | "t" => 3,
            "mm" => 2,
            _ => 1,
        };
        rest = after.trim_start();
        for k in 0..words {
            let (word, after) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
            if k > 0 && word.parse::<f32>().is_err() {
                break;
            }
            rest = after.trim_start();
        }
    }
    rest
}

/// The texture `name` (relative to the OBJ's folder) added to `mesh`: its index, or `None`
/// where the file is missing and `options` say grey (noted in `report`).
fn read_texture(
    name: &Path,
    kind: Map,
    options: &ObjOptions,
    read: &impl Fn(&Path) -> Result<(PathBuf, Vec<u8>), MeshError>,
    mesh: &mut Mesh,
    report: &mut Report,
) -> Result<Option<u32>, MeshError> {
    let (path, bytes) = match read(name) {
        Ok(file) => file,
        Err(MeshError::Io { path, error })
            if error.kind() == std::io::ErrorKind::NotFound
                && options.missing_textures == MissingTextures::Grey =>
        {
            let why = format!(
                "texture {} is missing: the material is grey (map_Kd), its Ks plain (map_Ks) \
                 or solid (map_d)",
                path.display()
            );
            report.note(&format!("texture {}", name.display()), &path, 0, &why);
            return Ok(None);
        }
        Err(e) => return Err(e),
    };
    let texture = match kind {
        Map::Coverage => Texture::decode_coverage(&bytes),
        Map::Diffuse | Map::Specular => Texture::decode(&bytes),
    }
    .map_err(|error| MeshError::Texture { path, error })?;
    mesh.add_texture(texture).map(Some)
}

/// Which of a material's texture maps a file is read for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Map {
    /// `map_Kd`: sRGB colours.
    Diffuse,
    /// `map_Ks`: sRGB colours.
    Specular,
    /// `map_d`: coverage ([`Texture::decode_coverage`]).
    Coverage,
}

/// `material` with its diffuse colour the default material's grey; one without a diffuse
/// part (a mirror's, glass's, `Kd 0`) is left as it is, as its texture would have left it.
fn grey(material: Material) -> Material {
    match material {
        Material::Lambert { albedo } if albedo == Vec3::ZERO => material,
        Material::Phong { kd, .. } if kd == Vec3::ZERO => material,
        Material::Phong { ks, exponent, .. } => Material::Phong {
            kd: DEFAULT_ALBEDO,
            ks,
            exponent,
        },
        _ => DEFAULT_MATERIAL,
    }
}

/// The text of `path`, read up to [`lgh_image::MAX_INPUT_BYTES`]; bytes that are not UTF-8 are
/// a parse error.
fn read_text(path: &Path) -> Result<String, MeshError> {
    utf8(path, read_line_limited(path, MAX_LINE_BYTES)?)
}

/// The bytes of a file the OBJ names (an MTL file, a texture), read up to
/// [`lgh_image::MAX_INPUT_BYTES`]; no line limit, as a texture has no lines ([`check_mtl`]
/// checks an MTL's).
fn read_file(path: &Path) -> Result<Vec<u8>, MeshError> {
    lgh_image::read_limited(path, lgh_image::MAX_INPUT_BYTES).map_err(|error| {
        if error.kind() == std::io::ErrorKind::FileTooLarge {
            MeshError::TooLarge {
                path: path.to_owned(),
            }
        } else {
            MeshError::Io {
                path: path.to_owned(),
                error,
            }
        }
    })
}

/// `bytes` of `path` as text; bytes that are not UTF-8 are a parse error.
fn utf8(path: &Path, bytes: Vec<u8>) -> Result<String, MeshError> {
    String::from_utf8(bytes).map_err(|e| MeshError::Parse {
        path: path.to_owned(),
        message: format!("not UTF-8 text ({e})"),
    })
}

/// The bytes of `path`, read up to [`lgh_image::MAX_INPUT_BYTES`], stopping as soon as a line
/// is longer than `max_line` bytes.
fn read_line_limited(path: &Path, max_line: usize) -> Result<Vec<u8>, MeshError> {
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
    let bytes = read_lines_limited(limited, max_line).map_err(|e| match e {
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
    Ok(bytes)
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

/// The MTL `text` of `path`, its lines checked against [`MAX_LINE_BYTES`] and its colour
/// statements for their three numbers: `tobj` 4.0.5 panics on `Kd 0.5`.
fn check_mtl(path: &Path, text: String) -> Result<String, MeshError> {
    for (i, line) in text.lines().enumerate() {
        if line.len() > MAX_LINE_BYTES {
            return Err(MeshError::Parse {
                path: path.to_owned(),
                message: format!("line {} is longer than {MAX_LINE_BYTES} bytes", i + 1),
            });
        }
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

/// The index of refraction of a refracting MTL material without `Ni`: 1.5, glass's (the MTL
/// format's own default, 1, would make it invisible).
pub const DEFAULT_IOR: f32 = 1.5;

/// Our material and specular part for an MTL material (the mapping of [`Mesh::load_obj`]).
fn from_mtl(m: &tobj::Material) -> Result<(Material, Specular), MeshError> {
    let invalid = |reason| MeshError::InvalidMaterial {
        name: m.name.clone(),
        reason,
    };
    let illum = m.illumination_model.unwrap_or(2);
    let mirror = matches!(illum, 3 | 5 | 8);
    let refracting = matches!(illum, 4 | 6 | 7 | 9);
    // A mirror or glass without Kd has no diffuse part (not the default grey).
    let kd = m.diffuse.map_or(
        if mirror || refracting {
            Vec3::ZERO
        } else {
            DEFAULT_ALBEDO
        },
        Vec3::from,
    );
    let ks = m.specular.map_or(Vec3::ZERO, Vec3::from);
    let exponent = m.shininess.unwrap_or(1.0);
    // Checked even where `Ks` is zero and the exponent unused.
    check_exponent(exponent).map_err(invalid)?;
    let (material, specular) = if mirror {
        let reflectance = ks;
        (
            Material::Lambert { albedo: kd },
            Specular::Mirror { reflectance },
        )
    } else if refracting {
        let ior = m.optical_density.unwrap_or(DEFAULT_IOR);
        let transmittance = match m.unknown_param.get("Tf") {
            None => Vec3::ONE,
            Some(value) => {
                transmission_filter(value).ok_or(invalid("Tf needs one or three numbers"))?
            }
        };
        let glass = Specular::Dielectric { ior, transmittance };
        (Material::Lambert { albedo: Vec3::ZERO }, glass)
    } else if ks == Vec3::ZERO || illum <= 1 {
        // illum 0 and 1 have no highlight: Ks is not part of their model.
        (Material::Lambert { albedo: kd }, Specular::None)
    } else {
        (Material::Phong { kd, ks, exponent }, Specular::None)
    };
    check_material(&material).map_err(invalid)?;
    specular.check().map_err(invalid)?;
    Ok((material, specular))
}

/// The colour of an MTL `Tf` value: `r g b`, or one number for all three.
fn transmission_filter(value: &str) -> Option<Vec3> {
    let numbers: Vec<f32> = value
        .split('#')
        .next()?
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    match numbers[..] {
        [g] => Some(Vec3::splat(g)),
        [r, g, b] => Some(Vec3::new(r, g, b)),
        _ => None,
    }
}

/// What one face (`f`) of an OBJ file names at every corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct FaceCorners {
    /// The triangles of its fan: corners − 2 (none for fewer than three corners).
    triangles: usize,
    /// Every corner names a normal (`v//n`, `v/t/n`).
    normals: bool,
    /// Every corner names texture coordinates (`v/t`, `v/t/n`).
    texcoords: bool,
}

/// Checks the indices of the faces (`f`) of the OBJ text `obj` read from `path`, and returns
/// what each face names, in the order of the file (which is the order of `tobj`'s triangles).
///
/// Each position, texture and normal index must be 1 to `n` or −`n` to −1, where `n` is the
/// number of positions (`v`), texture coordinates (`vt`) or normals (`vn`) before the face:
/// `tobj` 4.0.5 overflows on others (a panic in debug builds) and takes 0 for "no index".
fn check_faces(path: &Path, obj: &str) -> Result<Vec<FaceCorners>, MeshError> {
    const WHAT: [&str; 3] = ["position", "texture coordinate", "normal"];
    // Positions, texture coordinates and normals so far.
    let mut counts = [0i64; 3];
    let mut faces = Vec::new();
    for (line, text) in obj.lines().enumerate() {
        let mut words = text.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") => {
                let mut face = FaceCorners {
                    triangles: 0,
                    normals: true,
                    texcoords: true,
                };
                let named = |corner: &str, k: usize| {
                    corner.split('/').nth(k).is_some_and(|n| !n.is_empty())
                };
                let mut corners = 0usize;
                for corner in words {
                    corners += 1;
                    face.normals &= named(corner, 2);
                    face.texcoords &= named(corner, 1);
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
                face.triangles = corners.saturating_sub(2);
                faces.push(face);
            }
            _ => {}
        }
    }
    Ok(faces)
}

/// The mesh of `tobj`'s models and materials; faces without a known material get
/// [`DEFAULT_MATERIAL`], appended after the MTL materials. A triangle takes its vertex normals
/// and texture coordinates only where its face (`faces`, in file order, which is the order of
/// `tobj`'s triangles) names them at every corner: `tobj` makes up indices for the corners that
/// name none (copying another corner's). A material's texture on faces without texture
/// coordinates is noted in `report`. Without `vertex_normals`, no triangle takes any
/// ([`Normals::Face`]).
fn from_tobj(
    models: &[tobj::Model],
    mtls: &[tobj::Material],
    faces: &[FaceCorners],
    vertex_normals: bool,
    report: &mut Report,
) -> Result<Mesh, MeshError> {
    let parsed = mtls.iter().map(from_mtl).collect::<Result<Vec<_>, _>>()?;
    let mut materials: Vec<Material> = parsed.iter().map(|p| p.0).collect();
    let default = u32::try_from(materials.len()).map_err(|_| MeshError::TooMany)?;
    materials.push(DEFAULT_MATERIAL);
    // Each triangle's face, in order.
    let mut per_triangle = faces
        .iter()
        .flat_map(|f| std::iter::repeat_n(f, f.triangles));
    let (mut positions, mut normals, mut texcoords) = (Vec::new(), Vec::new(), Vec::new());
    let mut triangles = Vec::new();
    let mut untextured = 0usize;
    for model in models {
        let mesh = &model.mesh;
        let offset = |base: usize| u32::try_from(base).map_err(|_| MeshError::TooMany);
        let (p0, n0, t0) = (
            offset(positions.len())?,
            offset(normals.len())?,
            offset(texcoords.len())?,
        );
        positions.extend(mesh.positions.chunks_exact(3).map(Vec3::from_slice));
        normals.extend(mesh.normals.chunks_exact(3).map(Vec3::from_slice));
        texcoords.extend(mesh.texcoords.chunks_exact(2).map(Vec2::from_slice));
        let material = mesh
            .material_id
            .filter(|&i| i < mtls.len())
            .map_or(default, |i| i as u32);
        let textured = mtls
            .get(material as usize)
            .is_some_and(|m| m.diffuse_texture.is_some());
        let has_normals = vertex_normals && mesh.normal_indices.len() == mesh.indices.len();
        let has_texcoords = mesh.texcoord_indices.len() == mesh.indices.len();
        for (k, corners) in mesh.indices.chunks_exact(3).enumerate() {
            let triangle = triangles.len();
            let face = per_triangle.next().ok_or(MeshError::Parse {
                path: PathBuf::new(),
                message: "tobj returned more triangles than the faces make".into(),
            })?;
            let shift3 = |base: u32, c: &[u32]| -> Result<[u32; 3], MeshError> {
                let shift = |i: u32| {
                    base.checked_add(i)
                        .ok_or(MeshError::IndexOutOfRange { triangle })
                };
                Ok([shift(c[0])?, shift(c[1])?, shift(c[2])?])
            };
            let corners_of = |named: bool, present: bool, base: u32, indices: &[u32]| {
                (named && present)
                    .then(|| shift3(base, &indices[3 * k..3 * k + 3]))
                    .transpose()
            };
            let texcoords = corners_of(face.texcoords, has_texcoords, t0, &mesh.texcoord_indices)?;
            untextured += usize::from(textured && texcoords.is_none());
            triangles.push(Triangle {
                vertices: shift3(p0, corners)?,
                normals: corners_of(face.normals, has_normals, n0, &mesh.normal_indices)?,
                texcoords,
                material,
            });
        }
    }
    if untextured > 0 {
        let why = format!(
            "{untextured} triangles of textured materials have no texture coordinates (vt): \
             their Kd is not textured"
        );
        report.note("f without vt", Path::new(""), 0, &why);
    }
    let mut mesh = Mesh::with_texcoords(positions, normals, texcoords, triangles, materials)?;
    for (i, &(_, specular)) in parsed.iter().enumerate() {
        // Checked in `from_mtl`.
        mesh.set_specular(i as u32, specular)?;
    }
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
    use crate::statements::Unhonoured;
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
        // Named once, with the count, as the statements not honoured are.
        let zero: Vec<&Unhonoured> = m
            .unhonoured()
            .iter()
            .filter(|u| u.statement == ZERO_AREA)
            .collect();
        assert_eq!(zero.len(), 1);
        assert!(
            zero[0]
                .to_string()
                .contains("`f of zero area` 1 of 6 triangles have zero area"),
            "{}",
            zero[0]
        );
        let materials: Vec<Material> = (0..5).map(|t| m.material(t)).collect();
        assert_eq!(
            materials,
            [DEFAULT_MATERIAL, matte, matte, shiny, DEFAULT_MATERIAL]
        );
        // Only the face that names a normal at every corner (`shiny`'s) has vertex normals.
        let with_normals: Vec<bool> = m.triangles().iter().map(|t| t.normals.is_some()).collect();
        assert_eq!(with_normals, [false, false, false, true, false]);
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
    fn face_normals_leave_the_files_vn_unused_and_say_so() {
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 1\nvn 0 1 1\nvn 1 1 1\nf 1//1 2//2 3//3\n";
        let dir = tempfile::tempdir().unwrap();
        let path = write(dir.path(), "scene.obj", obj);
        let options = ObjOptions {
            normals: Normals::Face,
            ..ObjOptions::default()
        };
        let m = Mesh::load_obj_with(&path, &options, |_, _| {}).unwrap();
        assert_eq!(m.triangles()[0].normals, None);
        // Shaded by the face's own normal everywhere.
        assert_eq!(m.shading_normal(0, 0.2, 0.3), Vec3::Z);
        let vn = m.unhonoured().iter().find(|u| u.statement == "vn").unwrap();
        assert_eq!((vn.line, vn.uses), (4, 3));
        assert!(vn.why.contains("normals: face"), "{}", vn.why);
        // The default uses them, and names nothing.
        let m = Mesh::load_obj(&path).unwrap();
        assert_eq!(m.triangles()[0].normals, Some([0, 1, 2]));
        assert!(m.unhonoured().iter().all(|u| u.statement != "vn"));
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
            // Glass: an index of refraction of 0 (or below, or not finite), a bad Tf.
            "newmtl a\nillum 7\nNi 0\n",
            "newmtl a\nillum 4\nNi -1.5\n",
            "newmtl a\nillum 6\nNi inf\n",
            "newmtl a\nillum 7\nTf 1 1\n",
            "newmtl a\nillum 7\nTf -1 1 1\n",
            "newmtl a\nillum 3\nKs 1 -1 1\n",
            "newmtl a\nillum 3\nKs 1.2 1 1\n",
            "newmtl a\nillum 7\nTf 1.5 1 1\n",
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
    fn lines_of_any_length_are_named_and_not_rendered() {
        // tobj reads `l` of three or more corners as a polygon (and never checks its indices);
        // lines are not surfaces: only the face is a triangle, and `l` is named.
        let m = load(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nl 1 2 3\nl 1 2 3 4 999\nf 1 2 3\nl 4 3\n",
            None,
        )
        .unwrap();
        assert_eq!(m.triangles().len(), 1);
        let named: Vec<(&str, usize, usize)> = m
            .unhonoured()
            .iter()
            .map(|u| (u.statement.as_str(), u.line, u.uses))
            .collect();
        assert_eq!(named, [("l", 5, 3)]);
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
        let Some(path) = lgh_tests::cornell_box() else {
            return;
        };
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
        // Ka is the one statement not honoured (Ni 1.5 with illum 2 changes nothing).
        let named: Vec<(&str, usize, usize)> = m
            .unhonoured()
            .iter()
            .map(|u| (u.statement.as_str(), u.line, u.uses))
            .collect();
        assert_eq!(named, [("Ka", 16, 8)]);
    }
}
