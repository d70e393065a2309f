//! # lgh-ply — a small, strict PLY point-cloud reader and writer
//!
//! Reads ASCII and binary (little- and big-endian) PLY. Only the `vertex` element is kept, with its
//! scalar properties as columns; other elements are skipped (list properties included). Every count
//! in the header is checked against the bytes actually present before anything is allocated, so a
//! malformed, truncated or lying file gives a [`PlyError`], never a panic or a giant allocation.
//! `lgh probes` reads its lights and probe points with it and writes its results with [`write()`];
//! the fuzz target `ply` (`fuzz/`) drives [`parse`].
//!
//! ```
//! use lgh_ply::{parse, write, PlyError};
//!
//! let text = b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty uchar red\nend_header\n1.5 255\n-2 0\n";
//! let cloud = parse(text)?;
//! assert_eq!(cloud.len(), 2);
//! assert_eq!(cloud.float_column("x")?, &[1.5, -2.0]);
//! // Only float and double columns are positions or intensities.
//! assert!(matches!(cloud.float_column("red"), Err(PlyError::NotFloat { .. })));
//!
//! // Written back as binary little-endian, read back the same.
//! let mut bytes = Vec::new();
//! write(&mut bytes, &cloud)?;
//! assert_eq!(parse(&bytes)?.columns, cloud.columns);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Files larger than this are refused, and never read past ([`lgh_image::read_limited`]).
pub use lgh_image::MAX_INPUT_BYTES as MAX_FILE_BYTES;

/// What went wrong reading a PLY file. Its `Display` is one line of text; `source()` is the I/O
/// error of [`PlyError::Io`].
#[derive(Debug)]
#[non_exhaustive]
pub enum PlyError {
    /// The file could not be read (missing, unreadable, a directory…).
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is larger than [`MAX_FILE_BYTES`]; nothing past the limit was read.
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The limit, in bytes.
        limit: u64,
    },
    /// The PLY data of the file at `path` is wrong: `error` says how.
    InFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with its contents (never another `InFile`, `Io` or `TooLarge`).
        error: Box<PlyError>,
    },
    /// The bytes do not start with `ply`.
    NotPly,
    /// The header has no `end_header` line.
    NoEndHeader,
    /// The header is not UTF-8 text.
    HeaderNotText,
    /// The header has no `format` line.
    NoFormat,
    /// A header line that is not `comment`, `obj_info`, `format`, `element` or `property` as
    /// PLY writes them (a count that is not a number, a property before any element…).
    BadHeaderLine {
        /// The line's number, from 1.
        line: usize,
        /// The line, trimmed.
        text: String,
    },
    /// The format is not `ascii`, `binary_little_endian` or `binary_big_endian`.
    UnsupportedFormat(String),
    /// A property's type is not a PLY scalar type (or is a float as a list's count).
    UnsupportedType {
        /// The header line's number, from 1.
        line: usize,
        /// The line, trimmed.
        text: String,
    },
    /// The header announces more vertices than the rest of the file could hold.
    TooManyVertices {
        /// The announced count.
        count: u64,
    },
    /// The data ends (or stops being numbers) before the header's counts are met.
    Truncated {
        /// The element being read.
        element: String,
        /// Its record being read, from 0.
        record: u64,
    },
    /// A list property announces a negative length.
    NegativeListLength {
        /// The element holding the list.
        element: String,
    },
    /// The file has no `vertex` element.
    NoVertexElement,
    /// The `vertex` element has no property of this name.
    MissingProperty {
        /// The property asked for.
        name: String,
    },
    /// The property is an integer, where a float or double is needed.
    NotFloat {
        /// The property.
        name: String,
        /// Its type in the file.
        found: Scalar,
    },
}

impl fmt::Display for PlyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlyError::Io { path, source } => write!(f, "cannot read {}: {source}", path.display()),
            PlyError::TooLarge { path, limit } => write!(
                f,
                "cannot read {}: the file is larger than the limit of {limit} bytes",
                path.display()
            ),
            PlyError::InFile { path, error } => write!(f, "{}: {error}", path.display()),
            PlyError::NotPly => f.write_str("not a PLY file (it does not start with 'ply')"),
            PlyError::NoEndHeader => f.write_str("PLY header has no 'end_header'"),
            PlyError::HeaderNotText => f.write_str("PLY header is not text"),
            PlyError::NoFormat => f.write_str("PLY header has no 'format' line"),
            PlyError::BadHeaderLine { line, text } | PlyError::UnsupportedType { line, text } => {
                write!(f, "malformed PLY header line {line}: '{text}'")
            }
            PlyError::UnsupportedFormat(format) => write!(f, "unknown PLY format '{format}'"),
            PlyError::TooManyVertices { count } => write!(
                f,
                "header announces {count} vertices but the file is too short to hold them"
            ),
            PlyError::Truncated { element, record } => write!(
                f,
                "file is truncated or malformed in element '{element}' (record {record})"
            ),
            PlyError::NegativeListLength { element } => {
                write!(f, "negative list length in element '{element}'")
            }
            PlyError::NoVertexElement => f.write_str("no 'vertex' element"),
            PlyError::MissingProperty { name } => write!(f, "vertex property '{name}' is missing"),
            PlyError::NotFloat { name, found } => write!(
                f,
                "vertex property '{name}' is {}, expected float or double",
                found.name()
            ),
        }
    }
}

impl std::error::Error for PlyError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            PlyError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    /// `char` or `int8`.
    I8,
    /// `uchar` or `uint8`.
    U8,
    /// `short` or `int16`.
    I16,
    /// `ushort` or `uint16`.
    U16,
    /// `int` or `int32`.
    I32,
    /// `uint` or `uint32`.
    U32,
    /// `float` or `float32`.
    F32,
    /// `double` or `float64`.
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
    ///
    /// ```
    /// let cloud = lgh_ply::parse(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1 2 3\n")?;
    /// assert_eq!(cloud.len(), 3);
    /// # Ok::<(), lgh_ply::PlyError>(())
    /// ```
    #[must_use]
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, |c| c.len())
    }

    /// True if there are no vertices.
    ///
    /// ```
    /// let cloud = lgh_ply::parse(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nend_header\n")?;
    /// assert!(cloud.is_empty());
    /// assert!(lgh_ply::PointCloud::default().is_empty());
    /// # Ok::<(), lgh_ply::PlyError>(())
    /// ```
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The column of property `name`, which must exist ([`PlyError::MissingProperty`]) and be a
    /// float or double ([`PlyError::NotFloat`]).
    ///
    /// ```
    /// use lgh_ply::{parse, PlyError, Scalar};
    ///
    /// let cloud = parse(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty int id\nend_header\n0.25 7\n")?;
    /// assert_eq!(cloud.float_column("x")?, &[0.25]);
    /// assert!(matches!(cloud.float_column("id"), Err(PlyError::NotFloat { found: Scalar::I32, .. })));
    /// let missing = cloud.float_column("y").unwrap_err();
    /// assert_eq!(missing.to_string(), "vertex property 'y' is missing");
    /// # Ok::<(), PlyError>(())
    /// ```
    pub fn float_column(&self, name: &str) -> Result<&[f64], PlyError> {
        match self.props.iter().position(|(n, _)| n == name) {
            None => Err(PlyError::MissingProperty {
                name: name.to_string(),
            }),
            Some(k) if !self.props[k].1.is_float() => Err(PlyError::NotFloat {
                name: name.to_string(),
                found: self.props[k].1,
            }),
            Some(k) => Ok(&self.columns[k]),
        }
    }
}

/// Reads the vertex element of the PLY file at `path`: [`PlyError::Io`] or
/// [`PlyError::TooLarge`] if the file cannot be read, [`PlyError::InFile`] (naming the file) if
/// its contents are wrong.
///
/// ```
/// use lgh_ply::PlyError;
///
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("points.ply");
/// std::fs::write(&path, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n4\n")?;
/// assert_eq!(lgh_ply::read(&path)?.float_column("x")?, &[4.0]);
///
/// // A missing file is an I/O error, with its cause as `source()`.
/// let missing = lgh_ply::read(&dir.path().join("none.ply")).unwrap_err();
/// assert!(matches!(missing, PlyError::Io { .. }));
/// assert!(std::error::Error::source(&missing).is_some());
///
/// // A bad file names itself.
/// std::fs::write(&path, "hello")?;
/// let e = lgh_ply::read(&path).unwrap_err();
/// assert!(matches!(&e, PlyError::InFile { error, .. } if matches!(**error, PlyError::NotPly)));
/// assert!(e.to_string().ends_with("points.ply: not a PLY file (it does not start with 'ply')"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read(path: &Path) -> Result<PointCloud, PlyError> {
    let bytes = lgh_image::read_limited(path, MAX_FILE_BYTES).map_err(|source| {
        if source.kind() == std::io::ErrorKind::FileTooLarge {
            PlyError::TooLarge {
                path: path.to_path_buf(),
                limit: MAX_FILE_BYTES,
            }
        } else {
            PlyError::Io {
                path: path.to_path_buf(),
                source,
            }
        }
    })?;
    parse(&bytes).map_err(|error| PlyError::InFile {
        path: path.to_path_buf(),
        error: Box::new(error),
    })
}

/// Parses PLY bytes (see the crate documentation): the `vertex` element's scalar columns.
///
/// ```
/// use lgh_ply::{parse, PlyError};
///
/// // Binary little-endian: one vertex of three floats, and a face list that is skipped.
/// let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
/// for v in [1.0f32, 2.0, 3.0] {
///     bytes.extend(v.to_le_bytes());
/// }
/// bytes.extend([1, 0, 0, 0, 0]);
/// assert_eq!(parse(&bytes)?.float_column("z")?, &[3.0]);
///
/// // A header that announces more than the file holds is refused before any allocation.
/// let lying = b"ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nend_header\n1\n";
/// assert!(matches!(parse(lying), Err(PlyError::TooManyVertices { count: 1_000_000_000_000 })));
/// # Ok::<(), PlyError>(())
/// ```
pub fn parse(bytes: &[u8]) -> Result<PointCloud, PlyError> {
    let (format, elements, body) = parse_header(bytes)?;
    let mut body = Body::new(format, body);
    for el in &elements {
        if el.name == "vertex" {
            return read_vertices(&mut body, el);
        }
        // Elements before the vertices are read past (nothing to read without properties,
        // whatever the count).
        if !el.props.is_empty() {
            for i in 0..el.count {
                for p in &el.props {
                    body.skip(p, &el.name, i)?;
                }
            }
        }
    }
    Err(PlyError::NoVertexElement)
}

/// The vertex element `el`'s scalar properties, read from `body` as columns; its lists are read
/// past. Refused before any allocation when the body cannot hold the announced count.
fn read_vertices(body: &mut Body<'_>, el: &Element) -> Result<PointCloud, PlyError> {
    // Each vertex needs at least one byte per property (binary) or two (ASCII), so this bounds
    // the allocation by the file's size.
    let min_record = el.props.len().max(1) as u64;
    if el.count.saturating_mul(min_record) > body.values_left() {
        return Err(PlyError::TooManyVertices { count: el.count });
    }
    let props: Vec<(String, Scalar)> = el
        .props
        .iter()
        .filter_map(|p| match p {
            Property::Scalar { name, ty } => Some((name.clone(), *ty)),
            Property::List { .. } => None,
        })
        .collect();
    let mut columns: Vec<Vec<f64>> = props
        .iter()
        .map(|_| Vec::with_capacity(el.count as usize))
        .collect();
    for i in 0..el.count {
        let mut col = 0;
        for p in &el.props {
            match p {
                Property::Scalar { ty, .. } => {
                    let v = body.scalar(*ty).ok_or_else(|| truncated(&el.name, i))?;
                    columns[col].push(v);
                    col += 1;
                }
                Property::List { .. } => body.skip(p, &el.name, i)?,
            }
        }
    }
    Ok(PointCloud { props, columns })
}

/// A PLY body read value by value: ASCII tokens, or binary values of one byte order.
struct Body<'a> {
    bytes: &'a [u8],
    /// The next binary value's offset.
    pos: usize,
    big: bool,
    /// The tokenizer of an ASCII body.
    ascii: Option<AsciiTokens<'a>>,
}

impl<'a> Body<'a> {
    fn new(format: Format, bytes: &'a [u8]) -> Self {
        let (ascii, big) = match format {
            Format::Ascii => (Some(AsciiTokens::new(bytes)), false),
            Format::Binary { big } => (None, big),
        };
        Body {
            bytes,
            pos: 0,
            big,
            ascii,
        }
    }

    /// A bound on the values still to read: the bytes left (binary) or half of them (ASCII: a
    /// value and a separator at least).
    fn values_left(&self) -> u64 {
        (match &self.ascii {
            Some(t) => t.remaining() / 2,
            None => self.bytes.len() - self.pos,
        }) as u64
    }

    /// The next value, of type `ty`; `None` at the end of the body.
    fn scalar(&mut self, ty: Scalar) -> Option<f64> {
        match &mut self.ascii {
            Some(t) => t.number(ty),
            None => {
                let b = self.bytes.get(self.pos..self.pos + ty.size())?;
                self.pos += ty.size();
                Some(ty.read(b, self.big))
            }
        }
    }

    /// Reads past property `p` of record `i` of `element`.
    fn skip(&mut self, p: &Property, element: &str, i: u64) -> Result<(), PlyError> {
        let (count, item) = match p {
            Property::Scalar { ty, .. } => {
                return self
                    .scalar(*ty)
                    .map(|_| ())
                    .ok_or_else(|| truncated(element, i));
            }
            Property::List { count, item } => (*count, *item),
        };
        let n = self.scalar(count).ok_or_else(|| truncated(element, i))?;
        if n.is_nan() || n < 0.0 {
            return Err(PlyError::NegativeListLength {
                element: element.to_string(),
            });
        }
        match &mut self.ascii {
            Some(t) => {
                for _ in 0..n as u64 {
                    t.number(item).ok_or_else(|| truncated(element, i))?;
                }
            }
            None => {
                let skip = (n as u64).saturating_mul(item.size() as u64);
                if skip > (self.bytes.len() - self.pos) as u64 {
                    return Err(truncated(element, i));
                }
                self.pos += skip as usize;
            }
        }
        Ok(())
    }
}

fn truncated(element: &str, record: u64) -> PlyError {
    PlyError::Truncated {
        element: element.to_string(),
        record,
    }
}

fn parse_header(bytes: &[u8]) -> Result<(Format, Vec<Element>, &[u8]), PlyError> {
    if !bytes.starts_with(b"ply") {
        return Err(PlyError::NotPly);
    }
    let end = find(bytes, b"end_header").ok_or(PlyError::NoEndHeader)?;
    let mut body = end + b"end_header".len();
    // The header ends with the line break after end_header (LF or CRLF).
    if bytes.get(body) == Some(&b'\r') {
        body += 1;
    }
    if bytes.get(body) == Some(&b'\n') {
        body += 1;
    }
    let header = std::str::from_utf8(&bytes[..end]).map_err(|_| PlyError::HeaderNotText)?;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in header.lines().enumerate().skip(1) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let bad = || PlyError::BadHeaderLine {
            line: n + 1,
            text: line.trim().to_string(),
        };
        let unsupported = || PlyError::UnsupportedType {
            line: n + 1,
            text: line.trim().to_string(),
        };
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", f, _version] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Binary { big: false },
                    "binary_big_endian" => Format::Binary { big: true },
                    other => return Err(PlyError::UnsupportedFormat(other.to_string())),
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
                    Scalar::parse(c).ok_or_else(unsupported)?,
                    Scalar::parse(i).ok_or_else(unsupported)?,
                );
                if count.is_float() {
                    return Err(unsupported());
                }
                el.props.push(Property::List { count, item });
            }
            ["property", ty, name] => {
                let el = elements.last_mut().ok_or_else(bad)?;
                el.props.push(Property::Scalar {
                    name: name.to_string(),
                    ty: Scalar::parse(ty).ok_or_else(unsupported)?,
                });
            }
            _ => return Err(bad()),
        }
    }
    let format = format.ok_or(PlyError::NoFormat)?;
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

/// Writes a binary little-endian PLY with one `vertex` element, each property in its type.
///
/// ```
/// use lgh_ply::{PointCloud, Scalar};
///
/// let cloud = PointCloud {
///     props: vec![("x".into(), Scalar::F32), ("id".into(), Scalar::U16)],
///     columns: vec![vec![0.5, 1.5], vec![7.0, 9.0]],
/// };
/// let mut bytes = Vec::new();
/// lgh_ply::write(&mut bytes, &cloud)?;
/// assert!(bytes.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
/// let back = lgh_ply::parse(&bytes)?;
/// assert_eq!(back.props, cloud.props);
/// assert_eq!(back.columns, cloud.columns);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
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
        let red = c.float_column("red").unwrap_err();
        assert!(matches!(
            red,
            PlyError::NotFloat {
                found: Scalar::U8,
                ..
            }
        ));
        assert_eq!(
            red.to_string(),
            "vertex property 'red' is uchar, expected float or double"
        );
        let r = c.float_column("r").unwrap_err();
        assert!(matches!(&r, PlyError::MissingProperty { name } if name == "r"));
        assert!(r.to_string().contains("missing"));
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
        let e = parse(&binary(2, &[1., 2., 3., 4.])).unwrap_err();
        assert!(matches!(&e, PlyError::Truncated { element, record: 1 } if element == "vertex"));
        assert_eq!(
            e.to_string(),
            "file is truncated or malformed in element 'vertex' (record 1)"
        );
        // A header that lies about a huge count: refused before allocating.
        let e = parse(&binary(1 << 60, &[1., 2., 3.])).unwrap_err();
        assert!(matches!(e, PlyError::TooManyVertices { count } if count == 1 << 60));
        assert!(e.to_string().contains("too short"));
        assert!(parse(
            b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1 x\n"
        )
        .is_err());
        assert!(
            parse(b"ply\nformat ascii 1.0\nelement vertex -2\nproperty float x\nend_header\n")
                .is_err()
        );
        let e = parse(b"ply\nformat weird 1.0\nend_header\n").unwrap_err();
        assert!(matches!(&e, PlyError::UnsupportedFormat(f) if f == "weird"));
        assert_eq!(e.to_string(), "unknown PLY format 'weird'");
        let e = parse(b"ply\nformat ascii 1.0\nelement face 0\nend_header\n").unwrap_err();
        assert!(matches!(e, PlyError::NoVertexElement));
        assert!(e.to_string().contains("vertex"));
        // An element without properties but with an absurd count is skipped at once.
        let c = parse(b"ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551615\nelement vertex 1\nproperty float x\nend_header\n\0\0\x80\x3f").unwrap();
        assert_eq!(c.float_column("x").unwrap(), &[1.0]);
    }

    /// The messages `lgh` prints (and its CLI tests look for), one per kind of error.
    #[test]
    fn each_error_has_its_message() {
        let msg = |b: &[u8]| parse(b).unwrap_err().to_string();
        assert_eq!(
            msg(b"hello"),
            "not a PLY file (it does not start with 'ply')"
        );
        assert_eq!(
            msg(b"ply\nformat ascii 1.0\n"),
            "PLY header has no 'end_header'"
        );
        assert_eq!(msg(b"ply\n\xff\nend_header\n"), "PLY header is not text");
        assert_eq!(msg(b"ply\nend_header\n"), "PLY header has no 'format' line");
        assert_eq!(
            msg(b"ply\nformat ascii 1.0\nelement vertex x\nend_header\n"),
            "malformed PLY header line 3: 'element vertex x'"
        );
        let e = parse(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\nend_header\n")
            .unwrap_err();
        assert!(matches!(e, PlyError::UnsupportedType { line: 4, .. }));
        assert_eq!(
            e.to_string(),
            "malformed PLY header line 4: 'property half x'"
        );
        let e =
            parse(b"ply\nformat ascii 1.0\nelement f 1\nproperty list float int i\nend_header\n")
                .unwrap_err();
        assert!(matches!(e, PlyError::UnsupportedType { line: 4, .. }));
        let e = parse(
            b"ply\nformat ascii 1.0\nelement f 1\nproperty list char int i\nelement vertex 0\nend_header\n-1\n",
        )
        .unwrap_err();
        assert!(matches!(&e, PlyError::NegativeListLength { element } if element == "f"));
        assert_eq!(e.to_string(), "negative list length in element 'f'");
        let missing = Path::new("/nonexistent/lights.ply");
        let e = read(missing).unwrap_err();
        assert!(matches!(e, PlyError::Io { .. }));
        assert!(e
            .to_string()
            .starts_with("cannot read /nonexistent/lights.ply: "));
        assert!(std::error::Error::source(&e).is_some());
        let large = PlyError::TooLarge {
            path: missing.to_path_buf(),
            limit: 9,
        };
        assert_eq!(
            large.to_string(),
            "cannot read /nonexistent/lights.ply: the file is larger than the limit of 9 bytes"
        );
    }
}
