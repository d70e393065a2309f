//! What an OBJ or MTL file asks for that the renderer does not do: each statement it does not
//! honour, named once with the file and line of its first use and why ([`Unhonoured`]), so
//! that nothing a scene asks for is dropped without a word (nor are its triangles of zero
//! area: their count is named once, [`crate::obj::ZERO_AREA`]). `lgh gi` prints them on stderr
//! (with `--quiet`, only the EXR header keeps them).
//!
//! Honoured: OBJ `v`, `vt`, `vn`, `f`, `usemtl`, `mtllib`, `o` and `g` (names, which change
//! nothing in an image); MTL `newmtl`, `Kd`, `Ks`, `Ns`, `Ke`, `map_Kd` and `map_Ks` (of a
//! Phong material) without options,
//! `illum` 1 to 9 (1 without `Ks`; 3, 5 and 8 mirrors, 4, 6, 7 and 9 refracting glass:
//! [`crate::specular`]),
//! and `Ni` and `Tf` of refracting materials. Statements that cannot change what a material
//! renders are honoured trivially: `d 1` and `Tr 0` (opaque), `Ni` and `Tf` of a material that
//! does not refract. Everything else is named, and so are the parts of a mirror or glass the
//! renderer does not use (its `Ns`; glass's `Kd` and `Ks`; illum 5's Fresnel).

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// A statement the renderer does not honour, at its first use.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unhonoured {
    /// The statement's keyword, with its value or option where that is what is not honoured
    /// (`illum 7`, `map_Kd -s`).
    pub statement: String,
    /// The file of its first use (empty where the statement is the scene's as a whole).
    pub path: PathBuf,
    /// Its line there, from 1 (0 where the file as a whole is meant).
    pub line: usize,
    /// How many times the files use it.
    pub uses: usize,
    /// What the renderer does instead.
    pub why: String,
}

impl fmt::Display for Unhonoured {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.path.as_os_str().is_empty(), self.line) {
            (true, _) => {}
            (false, 0) => write!(f, "{}: ", self.path.display())?,
            (false, line) => write!(f, "{}:{line}: ", self.path.display())?,
        }
        write!(f, "`{}` {}", self.statement, self.why)?;
        if self.uses > 1 {
            write!(f, " ({} uses)", self.uses)?;
        }
        Ok(())
    }
}

/// The statements not honoured so far, each once, in the order of their first use.
#[derive(Clone, Debug, Default)]
pub(crate) struct Report {
    entries: Vec<Unhonoured>,
    index: BTreeMap<String, usize>,
}

impl Report {
    /// Notes one use of `statement` at `path`:`line`, keeping the first use's place and `why`.
    pub(crate) fn note(&mut self, statement: &str, path: &Path, line: usize, why: &str) {
        if let Some(&i) = self.index.get(statement) {
            self.entries[i].uses += 1;
            return;
        }
        self.index.insert(statement.to_owned(), self.entries.len());
        self.entries.push(Unhonoured {
            statement: statement.to_owned(),
            path: path.to_owned(),
            line,
            uses: 1,
            why: why.to_owned(),
        });
    }

    /// The statements, in the order of their first use.
    pub(crate) fn into_entries(self) -> Vec<Unhonoured> {
        self.entries
    }
}

/// The words of a line before its comment (`#` to the end).
fn words(line: &str) -> std::str::SplitWhitespace<'_> {
    line.split('#').next().unwrap_or("").split_whitespace()
}

/// Notes what the OBJ `text` of `path` asks for and is not rendered. `faces_without_normals`:
/// whether some face names no vertex normal (then smoothing groups would have mattered);
/// `vertex_normals`: whether the file's `vn` are used at all ([`crate::Normals::Face`] says
/// no: every face is flat, and `vn` is named).
pub(crate) fn scan_obj(
    path: &Path,
    text: &str,
    faces_without_normals: bool,
    vertex_normals: bool,
    report: &mut Report,
) {
    for (i, line) in text.lines().enumerate() {
        let mut w = words(line);
        let Some(key) = w.next() else { continue };
        let why = match key {
            "vn" if !vertex_normals => {
                "vertex normals are not used (normals: face): every face is shaded with its own"
            }
            "v" | "vt" | "vn" | "f" | "usemtl" | "mtllib" | "o" | "g" => {
                if key == "v" && w.count() > 4 {
                    "vertex colours are not rendered: the material's colour is"
                } else {
                    continue;
                }
            }
            "s" => match w.next() {
                Some("off" | "0") => continue,
                // Every face smooth: groups change nothing.
                _ if !faces_without_normals && vertex_normals => continue,
                _ => "smoothing groups are not computed: faces without vertex normals (vn) are shaded flat",
            },
            "l" | "p" => "lines and points are not surfaces: not rendered",
            "vp" | "cstype" | "deg" | "bmat" | "step" | "curv" | "curv2" | "surf" | "parm"
            | "trim" | "hole" | "scrv" | "sp" | "end" | "con" => {
                "free-form geometry is not rendered"
            }
            "usemap" | "maplib" => "per-face texture maps are not used: a material's map_Kd is",
            "mg" | "lod" | "bevel" | "c_interp" | "d_interp" | "shadow_obj" | "trace_obj"
            | "ctech" | "stech" => "not used by this renderer",
            _ => "is not an OBJ statement this reader knows: ignored",
        };
        report.note(key, path, i + 1, why);
    }
}

/// One MTL statement: its keyword, the rest of its words, its line.
struct Statement<'a> {
    key: &'a str,
    args: Vec<&'a str>,
    line: usize,
}

/// Notes what the MTL `text` of `path` asks for and is not rendered, material by material
/// (whether `Ni` matters depends on the material's `illum`).
pub(crate) fn scan_mtl(path: &Path, text: &str, report: &mut Report) {
    let mut material: Vec<Statement> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut w = words(line);
        let Some(key) = w.next() else { continue };
        if key == "newmtl" {
            scan_material(path, &material, report);
            material.clear();
            continue;
        }
        material.push(Statement {
            key,
            args: w.collect(),
            line: i + 1,
        });
    }
    scan_material(path, &material, report);
}

/// The statements of one MTL material (after its `newmtl`).
fn scan_material(path: &Path, statements: &[Statement], report: &mut Report) {
    let illum = statements
        .iter()
        .rev()
        .find(|s| s.key == "illum")
        .and_then(|s| s.args.first()?.parse::<u32>().ok())
        .unwrap_or(2);
    // The mapping of `Mesh::load_obj`: mirrors (3, 5, 8) and refracting glass (4, 6, 7, 9).
    let mirror = matches!(illum, 3 | 5 | 8);
    let refracting = matches!(illum, 4 | 6 | 7 | 9);
    let number = |s: &Statement| s.args.first().and_then(|a| a.parse::<f32>().ok());
    let zero = |s: &Statement| s.args.iter().all(|a| a.parse::<f32>() == Ok(0.0));
    for s in statements {
        let mut statement = s.key.to_owned();
        let why: &str = match s.key {
            "Ke" => continue,
            "Kd" if refracting && !zero(s) => "a refracting material has no diffuse part: not shaded",
            "Ks" if refracting && !zero(s) => "glass reflects by Fresnel (Ni): Ks is not used",
            "Ns" if mirror || refracting => "mirrors and glass are perfectly smooth: Ns is not used",
            "Kd" | "Ks" | "Ns" => continue,
            "map_Ks" if mirror || refracting => {
                "a mirror's or glass's reflectance is not textured: map_Ks is not applied"
            }
            "map_d" if refracting => "glass refracts by Ni: its map_d is not applied",
            "map_Kd" | "map_Ks" | "map_d" => match s.args.iter().find(|a| a.starts_with('-')) {
                None => continue,
                Some(option) => {
                    statement = format!("{} {option}", s.key);
                    "texture options are not applied: the image is mapped by vt as it is"
                }
            },
            "illum" => match illum {
                1..=4 | 6..=9 => continue,
                0 => {
                    statement = "illum 0".into();
                    "a colour without lighting is not rendered: shaded as illum 1 (Kd, lit)"
                }
                5 => {
                    statement = "illum 5".into();
                    "Fresnel reflection is not applied: a mirror reflecting Ks"
                }
                _ => {
                    statement = format!("illum {illum}");
                    "not a model this renderer has: shaded as illum 2 (Kd, Ks, Ns)"
                }
            },
            "Ni" if refracting => continue,
            "Ni" if illum == 5 => "illum 5's Fresnel reflection is not applied: Ni is not used",
            "Ni" | "Tf" => continue,
            "d" if number(s) == Some(1.0) => continue,
            "Tr" if number(s) == Some(0.0) => continue,
            "d" | "Tr" if refracting => {
                "transparency without refraction is not applied: the glass refracts by Ni"
            }
            "d" | "Tr" => {
                "transparency without refraction is not rendered: opaque (illum 4, 6, 7 or 9 refract)"
            }
            "Ka" | "map_Ka" => "ambient colour has no meaning in a physically based renderer: ignored",
            "map_Ns" | "map_Bump" | "map_bump" | "bump" | "norm" | "disp"
            | "decal" | "refl" | "map_Ke" | "map_Pr" | "map_Pm" => "this texture map is not applied",
            "Pr" | "Pm" | "Ps" | "Pc" | "Pcr" | "aniso" | "anisor" | "sharpness" => {
                "not rendered (the material is Lambert or Phong from Kd, Ks, Ns)"
            }
            _ => "is not an MTL statement this reader knows: ignored",
        };
        report.note(&statement, path, s.line, why);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mtl(text: &str) -> Vec<Unhonoured> {
        let mut r = Report::default();
        scan_mtl(Path::new("m.mtl"), text, &mut r);
        r.into_entries()
    }

    #[test]
    fn each_unhonoured_statement_is_named_once_at_its_first_use() {
        let got = mtl("\
newmtl a
Ka 1 1 1 # ambient
Kd 0.5 0.5 0.5
Ni 1.5
illum 2
d 1
newmtl glass
Ka 0 0 0
illum 7
Ni 1.5
Tf 0.9 0.9 0.9
Kd 0 0 0
Ks 1 1 1
d 0.5
map_Kd -s 2 2 1 wood.png
map_Bump n.png
Pr 0.3
newmtl fresnel_mirror
illum 5
Ni 1.3
newmtl other
illum 10
");
        let named: Vec<(&str, usize, usize)> = got
            .iter()
            .map(|u| (u.statement.as_str(), u.line, u.uses))
            .collect();
        // Ni, illum 2 and d 1 of `a` change nothing; glass honours illum 7, Ni, Tf and a zero
        // Kd; Ka is named at its first use, used twice.
        assert_eq!(
            named,
            [
                ("Ka", 2, 2),
                ("Ks", 13, 1),
                ("d", 14, 1),
                ("map_Kd -s", 15, 1),
                ("map_Bump", 16, 1),
                ("Pr", 17, 1),
                ("illum 5", 19, 1),
                ("Ni", 20, 1),
                ("illum 10", 22, 1),
            ]
        );
        assert_eq!(
            got[0].to_string(),
            "m.mtl:2: `Ka` ambient colour has no meaning in a physically based renderer: \
             ignored (2 uses)"
        );
        // Tf on an opaque material and Tr 0 change nothing.
        assert!(mtl("newmtl a\nTf 1 1 1\nTr 0\nillum 1\n").is_empty());
        let mut r = Report::default();
        let obj = "v 0 0 0 1 0 0\nv 1 0 0\nvt 0 0\ns 1\ng x\nl 1 2\nfoo\ns off\n";
        scan_obj(Path::new("s.obj"), obj, true, true, &mut r);
        let named: Vec<String> = r.into_entries().iter().map(|u| u.to_string()).collect();
        assert_eq!(
            named,
            [
                "s.obj:1: `v` vertex colours are not rendered: the material's colour is",
                "s.obj:4: `s` smoothing groups are not computed: faces without vertex normals \
                 (vn) are shaded flat",
                "s.obj:6: `l` lines and points are not surfaces: not rendered",
                "s.obj:7: `foo` is not an OBJ statement this reader knows: ignored",
            ]
        );
        // Smoothing groups are moot where every face has its normals.
        let mut r = Report::default();
        scan_obj(Path::new("s.obj"), "s 1\n", false, true, &mut r);
        assert!(r.into_entries().is_empty());
    }
}
