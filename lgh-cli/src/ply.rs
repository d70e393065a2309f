//! A small, strict PLY reader and writer for point clouds.
//!
//! Reads ASCII and binary (little- and big-endian) PLY. Only the `vertex` element is kept, with its
//! scalar properties as columns; other elements are skipped (list properties included). Every count
//! in the header is checked against the bytes actually present before anything is allocated, so a
//! malformed, truncated or lying file gives an error, never a panic or a giant allocation.

use std::io::Write;
use std::path::Path;

/// Files larger than this are refused, and never read past ([`lgh_image::read_limited`]).
pub use lgh_image::MAX_INPUT_BYTES as MAX_FILE_BYTES;

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn name(self) -> &'static str {
        match self {
            Scalar::I8 => "char",
            Scalar::U8 => "uchar",
            Scalar::I16 => "short",
            Scalar::U16 => "ushort",
            Scalar::I32 => "int",
            Scalar::U32 => "uint",
            Scalar::F32 => "float",
            Scalar::F64 => "double",
        }
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }

    fn read(self, b: &[u8], big: bool) -> f64 {
        macro_rules! get {
            ($t:ty, $n:expr) => {{
                let a: [u8; $n] = b[..$n].try_into().unwrap();
                (if big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }) as f64
            }};
        }
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => get!(i16, 2),
            Scalar::U16 => get!(u16, 2),
            Scalar::I32 => get!(i32, 4),
            Scalar::U32 => get!(u32, 4),
            Scalar::F32 => get!(f32, 4),
            Scalar::F64 => get!(f64, 8),
        }
    }

    fn write_le(self, v: f64, out: &mut Vec<u8>) {
        match self {
            Scalar::I8 => out.push(v as i8 as u8),
            Scalar::U8 => out.push(v as u8),
            Scalar::I16 => out.extend((v as i16).to_le_bytes()),
            Scalar::U16 => out.extend((v as u16).to_le_bytes()),
            Scalar::I32 => out.extend((v as i32).to_le_bytes()),
            Scalar::U32 => out.extend((v as u32).to_le_bytes()),
            Scalar::F32 => out.extend((v as f32).to_le_bytes()),
            Scalar::F64 => out.extend(v.to_le_bytes()),
        }
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar { name: String, ty: Scalar },
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Format {
    Ascii,
    Binary { big: bool },
}

/// The `vertex` element of a PLY file: named scalar columns.
#[derive(Clone, Debug, Default)]
pub struct PointCloud {
    /// Property names and types, in file order.
    pub props: Vec<(String, Scalar)>,
    /// `columns[k][i]`: property `k` of vertex `i`.
    pub columns: Vec<Vec<f64>>,
}

impl PointCloud {
    /// Number of vertices.
    #[must_use]
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, |c| c.len())
    }

    /// True if there are no vertices.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The column of property `name`, which must exist and be a float or double.
    pub fn float_column(&self, name: &str) -> Result<&[f64], String> {
        match self.props.iter().position(|(n, _)| n == name) {
            None => Err(format!("vertex property '{name}' is missing")),
            Some(k) if !self.props[k].1.is_float() => Err(format!(
                "vertex property '{name}' is {}, expected float or double",
                self.props[k].1.name()
            )),
            Some(k) => Ok(&self.columns[k]),
        }
    }
}

/// Reads the vertex element of the PLY file at `path`.
pub fn read(path: &Path) -> Result<PointCloud, String> {
    let bytes = lgh_image::read_limited(path, MAX_FILE_BYTES)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    parse(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses PLY bytes (see the module documentation).
pub fn parse(bytes: &[u8]) -> Result<PointCloud, String> {
    let (format, elements, body) = parse_header(bytes)?;
    let mut cloud = None;
    let mut pos = 0usize;
    let mut ascii = match format {
        Format::Ascii => Some(AsciiTokens::new(body)),
        Format::Binary { .. } => None,
    };
    for el in &elements {
        let keep = el.name == "vertex";
        if el.props.is_empty() && !keep {
            continue; // nothing to read, whatever the count
        }
        let mut columns: Vec<Vec<f64>> = Vec::new();
        if keep {
            // Each vertex needs at least one byte per property (binary) or two (ASCII), so this
            // bounds the allocation by the file's size.
            let remaining = match &ascii {
                Some(t) => t.remaining() / 2,
                None => body.len() - pos,
            } as u64;
            let min_record = el.props.len().max(1) as u64;
            if el.count.saturating_mul(min_record) > remaining {
                return Err(format!(
                    "header announces {} vertices but the file is too short to hold them",
                    el.count
                ));
            }
            columns = el
                .props
                .iter()
                .filter(|p| matches!(p, Property::Scalar { .. }))
                .map(|_| Vec::with_capacity(el.count as usize))
                .collect();
        }
        for i in 0..el.count {
            let mut col = 0;
            for p in &el.props {
                match (p, &mut ascii, format) {
                    (Property::Scalar { ty, .. }, Some(t), _) => {
                        let v = t.number(*ty).ok_or_else(|| truncated(&el.name, i))?;
                        if keep {
                            columns[col].push(v);
                        }
                        col += 1;
                    }
                    (Property::Scalar { ty, .. }, None, Format::Binary { big }) => {
                        let b = body
                            .get(pos..pos + ty.size())
                            .ok_or_else(|| truncated(&el.name, i))?;
                        pos += ty.size();
                        if keep {
                            columns[col].push(ty.read(b, big));
                        }
                        col += 1;
                    }
                    (Property::List { count, item }, Some(t), _) => {
                        let n = t.number(*count).ok_or_else(|| truncated(&el.name, i))?;
                        if n.is_nan() || n < 0.0 {
                            return Err(format!("negative list length in element '{}'", el.name));
                        }
                        for _ in 0..n as u64 {
                            t.number(*item).ok_or_else(|| truncated(&el.name, i))?;
                        }
                    }
                    (Property::List { count, item }, None, Format::Binary { big }) => {
                        let b = body
                            .get(pos..pos + count.size())
                            .ok_or_else(|| truncated(&el.name, i))?;
                        pos += count.size();
                        let n = count.read(b, big);
                        if n.is_nan() || n < 0.0 {
                            return Err(format!("negative list length in element '{}'", el.name));
                        }
                        let skip = (n as u64).saturating_mul(item.size() as u64);
                        if skip > (body.len() - pos) as u64 {
                            return Err(truncated(&el.name, i));
                        }
                        pos += skip as usize;
                    }
                    (_, None, Format::Ascii) => {
                        unreachable!("ASCII bodies always have a tokenizer")
                    }
                }
            }
        }
        if keep {
            let props = el
                .props
                .iter()
                .filter_map(|p| match p {
                    Property::Scalar { name, ty } => Some((name.clone(), *ty)),
                    Property::List { .. } => None,
                })
                .collect();
            cloud = Some(PointCloud { props, columns });
            break;
        }
    }
    cloud.ok_or_else(|| "no 'vertex' element".to_string())
}

fn truncated(element: &str, i: u64) -> String {
    format!("file is truncated or malformed in element '{element}' (record {i})")
}

fn parse_header(bytes: &[u8]) -> Result<(Format, Vec<Element>, &[u8]), String> {
    if !bytes.starts_with(b"ply") {
        return Err("not a PLY file (it does not start with 'ply')".into());
    }
    let end = find(bytes, b"end_header").ok_or("PLY header has no 'end_header'")?;
    let mut body = end + b"end_header".len();
    // The header ends with the line break after end_header (LF or CRLF).
    if bytes.get(body) == Some(&b'\r') {
        body += 1;
    }
    if bytes.get(body) == Some(&b'\n') {
        body += 1;
    }
    let header = std::str::from_utf8(&bytes[..end]).map_err(|_| "PLY header is not text")?;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in header.lines().enumerate().skip(1) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let bad = || format!("malformed PLY header line {}: '{}'", n + 1, line.trim());
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", f, _version] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Binary { big: false },
                    "binary_big_endian" => Format::Binary { big: true },
                    other => return Err(format!("unknown PLY format '{other}'")),
                })
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count.parse().map_err(|_| bad())?,
                props: Vec::new(),
            }),
            ["property", "list", c, i, _name] => {
                let el = elements.last_mut().ok_or_else(bad)?;
                let (count, item) = (
                    Scalar::parse(c).ok_or_else(bad)?,
                    Scalar::parse(i).ok_or_else(bad)?,
                );
                if count.is_float() {
                    return Err(bad());
                }
                el.props.push(Property::List { count, item });
            }
            ["property", ty, name] => {
                let el = elements.last_mut().ok_or_else(bad)?;
                el.props.push(Property::Scalar {
                    name: name.to_string(),
                    ty: Scalar::parse(ty).ok_or_else(bad)?,
                });
            }
            _ => return Err(bad()),
        }
    }
    let format = format.ok_or("PLY header has no 'format' line")?;
    Ok((format, elements, &bytes[body.min(bytes.len())..]))
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

struct AsciiTokens<'a> {
    text: &'a [u8],
    pos: usize,
}

impl<'a> AsciiTokens<'a> {
    fn new(text: &'a [u8]) -> Self {
        AsciiTokens { text, pos: 0 }
    }

    fn remaining(&self) -> usize {
        self.text.len() - self.pos
    }

    fn number(&mut self, ty: Scalar) -> Option<f64> {
        while self.pos < self.text.len() && self.text[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.text.len() && !self.text[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let word = std::str::from_utf8(&self.text[start..self.pos]).ok()?;
        if word.is_empty() {
            return None;
        }
        if ty.is_float() {
            word.parse::<f64>().ok()
        } else {
            word.parse::<i64>().ok().map(|v| v as f64)
        }
    }
}

/// Writes a binary little-endian PLY with one `vertex` element.
pub fn write(out: &mut dyn Write, cloud: &PointCloud) -> std::io::Result<()> {
    let mut header = String::from("ply\nformat binary_little_endian 1.0\ncomment written by lgh\n");
    header += &format!("element vertex {}\n", cloud.len());
    for (name, ty) in &cloud.props {
        header += &format!("property {} {name}\n", ty.name());
    }
    header += "end_header\n";
    out.write_all(header.as_bytes())?;
    let mut buf = Vec::with_capacity(1 << 16);
    for i in 0..cloud.len() {
        for (k, (_, ty)) in cloud.props.iter().enumerate() {
            ty.write_le(cloud.columns[k][i], &mut buf);
        }
        if buf.len() > 1 << 15 {
            out.write_all(&buf)?;
            buf.clear();
        }
    }
    out.write_all(&buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary(n: u64, values: &[f32]) -> Vec<u8> {
        let mut b = format!(
            "ply\r\nformat binary_little_endian 1.0\r\nelement vertex {n}\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
        )
        .into_bytes();
        for v in values {
            b.extend(v.to_le_bytes());
        }
        b
    }

    #[test]
    fn reads_ascii_and_binary_and_round_trips() {
        let ascii = b"ply\nformat ascii 1.0\ncomment hi\nelement vertex 2\nproperty float x\nproperty float y\nproperty double z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n1 2 3 255\n4 5 6.5 0\n3 0 1 1\n";
        let c = parse(ascii).unwrap();
        assert_eq!(c.len(), 2);
        assert_eq!(c.float_column("z").unwrap(), &[3.0, 6.5]);
        assert!(c.float_column("red").unwrap_err().contains("uchar"));
        assert!(c.float_column("r").unwrap_err().contains("missing"));
        let mut out = Vec::new();
        write(&mut out, &c).unwrap();
        let back = parse(&out).unwrap();
        assert_eq!(back.columns, c.columns);
        let b = parse(&binary(2, &[1., 2., 3., 4., 5., 6.])).unwrap();
        assert_eq!(b.float_column("y").unwrap(), &[2.0, 5.0]);
    }

    #[test]
    fn bad_files_are_errors() {
        assert!(parse(b"").is_err());
        assert!(parse(b"hello").is_err());
        assert!(parse(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n").is_err());
        // Truncated binary body.
        assert!(parse(&binary(2, &[1., 2., 3., 4.]))
            .unwrap_err()
            .contains("truncated"));
        // A header that lies about a huge count: refused before allocating.
        assert!(parse(&binary(1 << 60, &[1., 2., 3.]))
            .unwrap_err()
            .contains("too short"));
        assert!(parse(
            b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1 x\n"
        )
        .is_err());
        assert!(
            parse(b"ply\nformat ascii 1.0\nelement vertex -2\nproperty float x\nend_header\n")
                .is_err()
        );
        assert!(parse(b"ply\nformat weird 1.0\nend_header\n").is_err());
        assert!(
            parse(b"ply\nformat ascii 1.0\nelement face 0\nend_header\n")
                .unwrap_err()
                .contains("vertex")
        );
        // An element without properties but with an absurd count is skipped at once.
        let c = parse(b"ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551615\nelement vertex 1\nproperty float x\nend_header\n\0\0\x80\x3f").unwrap();
        assert_eq!(c.float_column("x").unwrap(), &[1.0]);
    }
}
