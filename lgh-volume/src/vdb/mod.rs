//! A compact, pure-Rust reader of OpenVDB files as Blender and Houdini write them.
//!
//! File format 222–224: grid descriptors with offsets, per-grid compression flags (blosc with LZ4
//! or zlib inside and byte shuffle, zip, and the "active values" mask compression), float, double,
//! int32, int64, vec3s and vec3d trees with the standard 5-4-3 configuration, half-float storage
//! (`_HalfFloat` trees), tiles at every level and instanced grids. Every malformed or truncated
//! file is an error ([`VdbError`]); no count from the file allocates before it is checked against
//! the bytes that remain.
//!
//! Values are kept as `f32` components (three per voxel for vector grids): what rendering needs.
//! Double and 64-bit integer grids are therefore rounded to `f32` on reading.

mod compress;
mod cursor;
pub mod synthetic;

use std::fmt;
use std::path::Path;

use compress::{read_data, COMPRESS_ACTIVE_MASK};
use cursor::Cursor;

/// Files larger than this are refused, and never read past ([`lgh_image::read_limited`]).
pub use lgh_image::MAX_INPUT_BYTES as MAX_FILE_BYTES;

/// Why a file could not be read.
#[derive(Clone, Debug, PartialEq)]
pub enum VdbError {
    /// The file could not be opened or read.
    Io(String),
    /// The file does not start with the OpenVDB magic number.
    NotVdb,
    /// A file format version this reader does not support (it reads 222–224).
    UnsupportedVersion(u32),
    /// The file ends before the data it announces.
    Truncated {
        /// Byte offset where more data was expected.
        offset: u64,
    },
    /// The bytes at `offset` do not make sense.
    Malformed {
        /// Byte offset of the problem.
        offset: u64,
        /// What was wrong.
        what: &'static str,
    },
    /// A feature of the file this reader does not support (grid type, map type, codec).
    Unsupported(String),
    /// The file holds more tiles or leaves than [`MAX_TILES`] or [`MAX_LEAVES`]: reading it would
    /// take more memory than a machine has, whatever the file's own size.
    TooLarge {
        /// `"tiles"` or `"leaves"`.
        what: &'static str,
        /// The limit it passes.
        limit: usize,
    },
}

/// The most tiles a file may hold, all grids and instances together: 2²², 128 MiB in memory.
/// A tile costs one bit of a node's mask in the file, so a 130 MB file can declare 10⁹ of them;
/// real caches hold thousands.
pub const MAX_TILES: usize = 1 << 22;

/// The most leaves a file may hold, all grids and instances together: 2²¹ leaves of 512
/// values, 2³⁰ voxels (four times the largest dense grid lgh renders, `MAX_DENSE_VOXELS`) and
/// 4 GiB of floats. A leaf of constant values compresses to a few dozen bytes in the file.
pub const MAX_LEAVES: usize = 1 << 21;

impl fmt::Display for VdbError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VdbError::Io(e) => write!(f, "{e}"),
            VdbError::NotVdb => write!(f, "not an OpenVDB file (bad magic number)"),
            VdbError::UnsupportedVersion(v) => {
                write!(
                    f,
                    "OpenVDB file format {v} is not supported (222 to 224 are)"
                )
            }
            VdbError::Truncated { offset } => write!(f, "file is truncated (at byte {offset})"),
            VdbError::Malformed { offset, what } => {
                write!(f, "malformed file at byte {offset}: {what}")
            }
            VdbError::Unsupported(what) => write!(f, "unsupported: {what}"),
            VdbError::TooLarge { what, limit } => write!(
                f,
                "the file holds more than {limit} {what}, more than this reader keeps in memory"
            ),
        }
    }
}

impl std::error::Error for VdbError {}

/// The value type of a grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueType {
    /// 32-bit float (`float`).
    Float,
    /// 64-bit float (`double`), read as f32.
    Double,
    /// 32-bit integer (`int32`).
    Int32,
    /// 64-bit integer (`int64`), read as f32.
    Int64,
    /// Vector of three 32-bit floats (`vec3s`).
    Vec3s,
    /// Vector of three 64-bit floats (`vec3d`), read as f32.
    Vec3d,
}

impl ValueType {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "float" => ValueType::Float,
            "double" => ValueType::Double,
            "int32" => ValueType::Int32,
            "int64" => ValueType::Int64,
            "vec3s" => ValueType::Vec3s,
            "vec3d" => ValueType::Vec3d,
            _ => return None,
        })
    }

    /// The name OpenVDB uses (`float`, `vec3s`, …).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ValueType::Float => "float",
            ValueType::Double => "double",
            ValueType::Int32 => "int32",
            ValueType::Int64 => "int64",
            ValueType::Vec3s => "vec3s",
            ValueType::Vec3d => "vec3d",
        }
    }

    /// Components per value (1 or 3).
    #[must_use]
    pub fn components(self) -> usize {
        match self {
            ValueType::Vec3s | ValueType::Vec3d => 3,
            _ => 1,
        }
    }

    /// Bytes of one stored value (half floats when `half`).
    fn size(self, half: bool) -> usize {
        let c = self.components();
        match self {
            ValueType::Float | ValueType::Vec3s | ValueType::Double | ValueType::Vec3d if half => {
                2 * c
            }
            ValueType::Float | ValueType::Int32 | ValueType::Vec3s => 4 * c,
            ValueType::Double | ValueType::Int64 | ValueType::Vec3d => 8 * c,
        }
    }

    /// Decodes little-endian stored values into f32 components.
    fn decode(self, bytes: &[u8], half: bool, out: &mut Vec<f32>) {
        if half {
            out.extend(
                bytes
                    .chunks_exact(2)
                    .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32()),
            );
            return;
        }
        match self {
            ValueType::Float | ValueType::Vec3s => out.extend(
                bytes
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes(b.try_into().unwrap())),
            ),
            ValueType::Int32 => out.extend(
                bytes
                    .chunks_exact(4)
                    .map(|b| i32::from_le_bytes(b.try_into().unwrap()) as f32),
            ),
            ValueType::Double | ValueType::Vec3d => out.extend(
                bytes
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().unwrap()) as f32),
            ),
            ValueType::Int64 => out.extend(
                bytes
                    .chunks_exact(8)
                    .map(|b| i64::from_le_bytes(b.try_into().unwrap()) as f32),
            ),
        }
    }
}

/// A leaf node: 8×8×8 voxels starting at `origin` (index space).
#[derive(Clone, Debug, PartialEq)]
pub struct Leaf {
    /// Index-space coordinates of voxel (0, 0, 0) of the leaf.
    pub origin: [i32; 3],
    /// Active-voxel mask; voxel `(x, y, z)` is bit `x·64 + y·8 + z`.
    pub mask: [u64; 8],
    /// `512 × components` values, voxel-major in the same order as the mask.
    pub values: Vec<f32>,
}

impl Leaf {
    /// The active voxels: `(voxel index in the leaf, index-space coordinates)`, in mask order.
    pub fn active_voxels(&self) -> impl Iterator<Item = (usize, [i32; 3])> + '_ {
        self.mask.iter().enumerate().flat_map(move |(w, &word)| {
            let mut bits = word;
            std::iter::from_fn(move || {
                if bits == 0 {
                    return None;
                }
                let i = w * 64 + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let o = self.origin;
                Some((
                    i,
                    [
                        o[0] + (i >> 6) as i32,
                        o[1] + ((i >> 3) & 7) as i32,
                        o[2] + (i & 7) as i32,
                    ],
                ))
            })
        })
    }
}

/// A tile: a constant value over a cube of `edge³` voxels.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// Index-space corner of the cube.
    pub origin: [i32; 3],
    /// Edge length in voxels (8, 128 or 4096 in a 5-4-3 tree).
    pub edge: u32,
    /// The value (`components` entries).
    pub value: [f32; 3],
    /// Whether the tile is active.
    pub active: bool,
}

/// One grid of a file.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Grid name.
    pub name: String,
    /// Value type.
    pub value_type: ValueType,
    /// Whether values were stored as half floats.
    pub half_float: bool,
    /// The `class` metadata (`fog volume`, `level set`, …), if any.
    pub class: Option<String>,
    /// Index-to-world transform as a row-major 4×4 affine matrix (world = M · [i j k 1]).
    pub index_to_world: [[f64; 4]; 4],
    /// Voxel size along each axis (world units).
    pub voxel_size: [f64; 3],
    /// Background value.
    pub background: [f32; 3],
    /// Leaf nodes.
    pub leaves: Vec<Leaf>,
    /// Tiles of every level (active or not).
    pub tiles: Vec<Tile>,
}

/// Statistics of a grid's active values (vector grids: of the vector length).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct GridStats {
    /// Number of active voxels (tiles count every voxel they cover).
    pub active_voxels: u64,
    /// Inclusive index-space bounding box of the active voxels, if any.
    pub bbox: Option<([i32; 3], [i32; 3])>,
    /// Smallest active value.
    pub min: f64,
    /// Largest active value.
    pub max: f64,
    /// Sum of the active values (a tile adds its value times its voxel count).
    pub sum: f64,
}

impl Grid {
    /// Components per voxel.
    #[must_use]
    pub fn components(&self) -> usize {
        self.value_type.components()
    }

    /// The scalar a voxel's components stand for: the value itself, or a vector's length
    /// (computed in f64).
    #[must_use]
    pub fn scalar(values: &[f32]) -> f64 {
        match values {
            [v] => *v as f64,
            _ => values
                .iter()
                .map(|&x| (x as f64) * (x as f64))
                .sum::<f64>()
                .sqrt(),
        }
    }

    /// Index-space box `(lo, hi)` (inclusive) of the active voxels and tiles, if any.
    #[must_use]
    pub fn active_bbox(&self) -> Option<([i32; 3], [i32; 3])> {
        let mut bbox: Option<([i32; 3], [i32; 3])> = None;
        let mut grow = |lo: [i32; 3], hi: [i32; 3]| {
            bbox = Some(match bbox {
                None => (lo, hi),
                Some((a, b)) => (
                    [0, 1, 2].map(|k| a[k].min(lo[k])),
                    [0, 1, 2].map(|k| b[k].max(hi[k])),
                ),
            });
        };
        for leaf in &self.leaves {
            for (_, p) in leaf.active_voxels() {
                grow(p, p);
            }
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            let e = t.edge as i32 - 1;
            grow(t.origin, t.origin.map(|o| o + e));
        }
        bbox
    }

    /// Statistics of the active values (vector grids: of [`Grid::scalar`]).
    #[must_use]
    pub fn stats(&self) -> GridStats {
        let c = self.components();
        let scalar = Grid::scalar;
        let mut s = GridStats {
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            bbox: self.active_bbox(),
            ..Default::default()
        };
        let mut add = |v: f64, n: u64| {
            s.active_voxels += n;
            s.sum += v * n as f64;
            s.min = s.min.min(v);
            s.max = s.max.max(v);
        };
        for leaf in &self.leaves {
            for (i, _) in leaf.active_voxels() {
                add(scalar(&leaf.values[i * c..(i + 1) * c]), 1);
            }
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            add(scalar(&t.value[..c]), (t.edge as u64).pow(3));
        }
        if s.active_voxels == 0 {
            s.min = 0.0;
            s.max = 0.0;
        }
        s
    }
}

/// An OpenVDB file.
#[derive(Clone, Debug, PartialEq)]
pub struct VdbFile {
    /// File format version (222–224).
    pub format_version: u32,
    /// Library version that wrote the file (major, minor).
    pub library_version: (u32, u32),
    /// The grids, in file order.
    pub grids: Vec<Grid>,
}

impl VdbFile {
    /// The grid called `name`.
    #[must_use]
    pub fn grid(&self, name: &str) -> Option<&Grid> {
        self.grids.iter().find(|g| g.name == name)
    }
}

/// Reads the OpenVDB file at `path`.
pub fn read(path: &Path) -> Result<VdbFile, VdbError> {
    let io = |e: std::io::Error| VdbError::Io(format!("cannot read {}: {e}", path.display()));
    parse(&lgh_image::read_limited(path, MAX_FILE_BYTES).map_err(io)?)
}

const MAGIC: u64 = 0x5644_4220;

/// Parses the bytes of an OpenVDB file.
pub fn parse(bytes: &[u8]) -> Result<VdbFile, VdbError> {
    let mut c = Cursor::new(bytes);
    if bytes.len() < 8 || c.i64()? as u64 != MAGIC {
        return Err(VdbError::NotVdb);
    }
    let version = c.u32()?;
    if !(222..=224).contains(&version) {
        return Err(VdbError::UnsupportedVersion(version));
    }
    let library_version = (c.u32()?, c.u32()?);
    let has_offsets = c.u8()? != 0;
    if !has_offsets {
        return Err(VdbError::Unsupported("files without grid offsets".into()));
    }
    c.bytes(36)?; // UUID
    skip_metadata(&mut c)?; // file-level metadata
    let count = c.count(16)?;
    let mut grids: Vec<Grid> = Vec::with_capacity(count);
    let mut budget = Budget::default();
    for _ in 0..count {
        let name = strip_unique_suffix(&c.string()?);
        let tree_type = c.string()?;
        let parent = strip_unique_suffix(&c.string()?);
        let (grid_pos, block_pos, end_pos) = (c.i64()?, c.i64()?, c.i64()?);
        let bad = |c: &Cursor<'_>, what| VdbError::Malformed {
            offset: c.pos() as u64,
            what,
        };
        if !(0 <= grid_pos && grid_pos <= block_pos && block_pos <= end_pos) {
            return Err(bad(&c, "grid offsets out of order"));
        }
        // A grid whose end lies past the file's: the file was cut short.
        if end_pos as u64 > bytes.len() as u64 {
            return Err(VdbError::Truncated {
                offset: bytes.len() as u64,
            });
        }
        let tree = parse_tree_type(&tree_type)?;
        let source = if parent.is_empty() {
            TreeSource::Own
        } else {
            TreeSource::Instanced
        };
        c.seek(grid_pos as u64)?;
        // The header says the grid fits in the file: data that runs past the file's end is
        // damaged (a corrupt count or size), not cut short.
        let mut grid = read_grid(&mut c, name, tree, source, budget).map_err(|e| match e {
            VdbError::Truncated { offset } => VdbError::Malformed {
                offset,
                what: "a grid that runs past its end offset",
            },
            e => e,
        })?;
        if !parent.is_empty() {
            let src = grids.iter().find(|g| g.name == parent).ok_or_else(|| {
                VdbError::Unsupported(format!("instance of unknown grid '{parent}'"))
            })?;
            // Checked before the copy: many instances of one big grid would multiply it.
            budget.with(src)?;
            grid.leaves = src.leaves.clone();
            grid.tiles = src.tiles.clone();
        }
        budget = budget.with(&grid)?;
        if c.pos() as u64 > end_pos as u64 {
            return Err(bad(&c, "a grid that runs past its end offset"));
        }
        grids.push(grid);
        c.seek(end_pos as u64)?;
    }
    Ok(VdbFile {
        format_version: version,
        library_version,
        grids,
    })
}

/// Grid names made unique by OpenVDB carry a record separator and a number.
fn strip_unique_suffix(name: &str) -> String {
    name.split('\u{1e}').next().unwrap_or("").to_string()
}

/// A grid's tree type: its value type, and whether values are stored as half floats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct TreeType {
    value_type: ValueType,
    half: bool,
}

/// Whether a grid's descriptor is followed by its own tree or instances another grid's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TreeSource {
    /// The tree follows the grid's transform.
    Own,
    /// No tree: the grid shares a parent grid's (OpenVDB's instanced grids).
    Instanced,
}

/// `Tree_float_5_4_3` or `Tree_vec3s_5_4_3_HalfFloat`.
fn parse_tree_type(t: &str) -> Result<TreeType, VdbError> {
    let unsupported = || VdbError::Unsupported(format!("grid type '{t}'"));
    let rest = t.strip_prefix("Tree_").ok_or_else(unsupported)?;
    let (rest, half) = match rest.strip_suffix("_HalfFloat") {
        Some(r) => (r, true),
        None => (rest, false),
    };
    let value = rest.strip_suffix("_5_4_3").ok_or_else(unsupported)?;
    let value = ValueType::parse(value).ok_or_else(unsupported)?;
    // Writers add the suffix to integer grids too; it only applies to floating-point values.
    let real = !matches!(value, ValueType::Int32 | ValueType::Int64);
    Ok(TreeType {
        value_type: value,
        half: half && real,
    })
}

/// Skips a metadata map, returning its string entries.
fn read_metadata(c: &mut Cursor<'_>) -> Result<Vec<(String, String)>, VdbError> {
    let n = c.count(12)?;
    let mut strings = Vec::new();
    for _ in 0..n {
        let name = c.string()?;
        let ty = c.string()?;
        let size = c.count(1)?;
        let value = c.bytes(size)?;
        if ty == "string" {
            strings.push((name, String::from_utf8_lossy(value).into_owned()));
        }
    }
    Ok(strings)
}

fn skip_metadata(c: &mut Cursor<'_>) -> Result<(), VdbError> {
    read_metadata(c).map(|_| ())
}

/// Reads a map (transform) and returns (row-major index-to-world matrix, voxel size).
fn read_transform(c: &mut Cursor<'_>) -> Result<([[f64; 4]; 4], [f64; 3]), VdbError> {
    let ty = c.string()?;
    let vec3 =
        |c: &mut Cursor<'_>| -> Result<[f64; 3], VdbError> { Ok([c.f64()?, c.f64()?, c.f64()?]) };
    let diagonal = |scale: [f64; 3], t: [f64; 3]| {
        [
            [scale[0], 0.0, 0.0, t[0]],
            [0.0, scale[1], 0.0, t[1]],
            [0.0, 0.0, scale[2], t[2]],
            [0.0, 0.0, 0.0, 1.0],
        ]
    };
    match ty.as_str() {
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let t = vec3(c)?;
            let scale = vec3(c)?;
            let voxel = vec3(c)?;
            c.bytes(3 * 24)?; // inverse scale, inverse scale², inverse twice scale
            Ok((diagonal(scale, t), voxel))
        }
        "UniformScaleMap" | "ScaleMap" => {
            let scale = vec3(c)?;
            let voxel = vec3(c)?;
            c.bytes(3 * 24)?;
            Ok((diagonal(scale, [0.0; 3]), voxel))
        }
        "TranslationMap" => {
            let t = vec3(c)?;
            Ok((diagonal([1.0; 3], t), [1.0; 3]))
        }
        "AffineMap" => {
            // Mat4d stored row by row with the translation in the last row (row vectors).
            let mut m = [[0.0; 4]; 4];
            for row in m.iter_mut() {
                for v in row.iter_mut() {
                    *v = c.f64()?;
                }
            }
            let mut out = [[0.0; 4]; 4];
            for (i, row) in out.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = m[j][i];
                }
            }
            let voxel =
                [0, 1, 2].map(|j| (0..3).map(|i| out[i][j] * out[i][j]).sum::<f64>().sqrt());
            Ok((out, voxel))
        }
        other => Err(VdbError::Unsupported(format!("transform '{other}'"))),
    }
}

/// What a grid's tree readers share.
struct TreeCtx {
    value_type: ValueType,
    half: bool,
    compression: u32,
    background: [f32; 3],
    /// Tiles and leaves of the file's grids before this one.
    before: Budget,
}

/// Tiles and leaves held so far, against [`MAX_TILES`] and [`MAX_LEAVES`].
#[derive(Clone, Copy, Debug, Default)]
struct Budget {
    tiles: usize,
    leaves: usize,
}

impl Budget {
    /// What `grid` adds to `self`, or [`VdbError::TooLarge`].
    fn with(self, grid: &Grid) -> Result<Budget, VdbError> {
        let b = Budget {
            tiles: self.tiles + grid.tiles.len(),
            leaves: self.leaves + grid.leaves.len(),
        };
        if b.tiles > MAX_TILES {
            Err(VdbError::TooLarge {
                what: "tiles",
                limit: MAX_TILES,
            })
        } else if b.leaves > MAX_LEAVES {
            Err(VdbError::TooLarge {
                what: "leaves",
                limit: MAX_LEAVES,
            })
        } else {
            Ok(b)
        }
    }
}

/// A grid from its descriptor on: its metadata, transform and, unless instanced, its tree.
fn read_grid(
    c: &mut Cursor<'_>,
    name: String,
    TreeType { value_type, half }: TreeType,
    source: TreeSource,
    before: Budget,
) -> Result<Grid, VdbError> {
    let compression = c.u32()?;
    let meta = read_metadata(c)?;
    let class = meta
        .iter()
        .find(|(k, _)| k == "class")
        .map(|(_, v)| v.clone());
    let (index_to_world, voxel_size) = read_transform(c)?;
    let mut grid = Grid {
        name,
        value_type,
        half_float: half,
        class,
        index_to_world,
        voxel_size,
        background: [0.0; 3],
        leaves: Vec::new(),
        tiles: Vec::new(),
    };
    if source == TreeSource::Instanced {
        return Ok(grid);
    }
    // Tree::readTopology: buffer count, then the root.
    let _buffers = c.u32()?;
    grid.background = read_full_value(c, value_type)?;
    let ctx = TreeCtx {
        value_type,
        half,
        compression,
        background: grid.background,
        before,
    };
    read_root(c, &ctx, &mut grid)?;
    // Tree::readBuffers: the leaves, in the order their topology was read.
    for leaf in &mut grid.leaves {
        leaf.mask = read_mask8(c)?;
        leaf.values = read_values(c, &ctx, 512, &leaf.mask)?;
    }
    Ok(grid)
}

/// One value of `value_type` stored at full precision (the background, a root tile's value),
/// its unused components 0.
fn read_full_value(c: &mut Cursor<'_>, value_type: ValueType) -> Result<[f32; 3], VdbError> {
    let comps = value_type.components();
    let mut v = Vec::with_capacity(comps);
    value_type.decode(c.bytes(value_type.size(false))?, false, &mut v);
    let mut value = [0.0; 3];
    value[..comps].copy_from_slice(&v);
    Ok(value)
}

/// The root node after its background (Tree::readTopology): its tiles, then its children with
/// their subtrees, into `grid`, against the budget of `ctx`.
fn read_root(c: &mut Cursor<'_>, ctx: &TreeCtx, grid: &mut Grid) -> Result<(), VdbError> {
    let full = ctx.value_type.size(false);
    let num_tiles = c.count(12 + full + 1)?;
    let num_children = c.count(12)?;
    for _ in 0..num_tiles {
        let origin = [c.i32()?, c.i32()?, c.i32()?];
        let value = read_full_value(c, ctx.value_type)?;
        let active = c.u8()? != 0;
        // Aligned like the root's children: then `origin + 4095` never overflows an i32.
        check_root_aligned(c, origin, "a root tile that is not aligned to its size")?;
        grid.tiles.push(Tile {
            origin,
            edge: 4096,
            value,
            active,
        });
        ctx.before.with(grid)?;
    }
    for _ in 0..num_children {
        let origin = [c.i32()?, c.i32()?, c.i32()?];
        check_root_aligned(c, origin, "a root child that is not aligned to its size")?;
        read_internal(c, ctx, origin, 5, grid)?;
    }
    Ok(())
}

/// Refuses a root tile or child whose `origin` is not a multiple of its size (4096), as
/// [`VdbError::Malformed`] at the cursor (`what` says which).
fn check_root_aligned(
    c: &Cursor<'_>,
    origin: [i32; 3],
    what: &'static str,
) -> Result<(), VdbError> {
    if origin.iter().any(|&o| o % 4096 != 0) {
        return Err(VdbError::Malformed {
            offset: c.pos() as u64,
            what,
        });
    }
    Ok(())
}

fn read_mask(c: &mut Cursor<'_>, words: usize) -> Result<Vec<u64>, VdbError> {
    let b = c.bytes(words * 8)?;
    Ok(b.chunks_exact(8)
        .map(|w| u64::from_le_bytes(w.try_into().unwrap()))
        .collect())
}

fn read_mask8(c: &mut Cursor<'_>) -> Result<[u64; 8], VdbError> {
    let v = read_mask(c, 8)?;
    let mut m = [0u64; 8];
    m.copy_from_slice(&v);
    Ok(m)
}

fn bit(mask: &[u64], i: usize) -> bool {
    mask[i >> 6] >> (i & 63) & 1 != 0
}

/// Reads an internal node with `log2` = 5 (32³ children of 128³ voxels) or 4 (16³ leaves).
fn read_internal(
    c: &mut Cursor<'_>,
    ctx: &TreeCtx,
    origin: [i32; 3],
    log2: u32,
    grid: &mut Grid,
) -> Result<(), VdbError> {
    let n = 1usize << (3 * log2);
    let child_mask = read_mask(c, n / 64)?;
    let value_mask = read_mask(c, n / 64)?;
    let values = read_values(c, ctx, n, &value_mask)?;
    let child_log2_total: u32 = if log2 == 5 { 7 } else { 3 };
    let comps = ctx.value_type.components();
    let local = |i: usize| {
        let l = log2 as usize;
        [
            origin[0] + (((i >> (2 * l)) as i32) << child_log2_total),
            origin[1] + ((((i >> l) & ((1 << l) - 1)) as i32) << child_log2_total),
            origin[2] + (((i & ((1 << l) - 1)) as i32) << child_log2_total),
        ]
    };
    // Tiles: slots without a child.
    for i in 0..n {
        if !bit(&child_mask, i) {
            let active = bit(&value_mask, i);
            let v = &values[i * comps..(i + 1) * comps];
            if active || v.iter().zip(&ctx.background).any(|(a, b)| a != b) {
                let mut value = [0.0; 3];
                value[..comps].copy_from_slice(v);
                grid.tiles.push(Tile {
                    origin: local(i),
                    edge: 1 << child_log2_total,
                    value,
                    active,
                });
                ctx.before.with(grid)?;
            }
        }
    }
    for i in 0..n {
        if bit(&child_mask, i) {
            if log2 == 5 {
                read_internal(c, ctx, local(i), 4, grid)?;
            } else {
                let mask = read_mask8(c)?;
                grid.leaves.push(Leaf {
                    origin: local(i),
                    mask,
                    values: Vec::new(),
                });
                ctx.before.with(grid)?;
            }
        }
    }
    Ok(())
}

/// OpenVDB's `readCompressedValues`: a node's `count` values, of which only the active ones may
/// be stored ("active values" mask compression), restored to `count` values (inactive ones get the
/// background; what they were exactly does not matter to readers of active values).
fn read_values(
    c: &mut Cursor<'_>,
    ctx: &TreeCtx,
    count: usize,
    mask: &[u64],
) -> Result<Vec<f32>, VdbError> {
    let at = c.pos() as u64;
    let metadata = c.u8()?;
    if metadata > 6 {
        return Err(VdbError::Malformed {
            offset: at,
            what: "an unknown value-compression code",
        });
    }
    let full = ctx.value_type.size(false);
    if matches!(metadata, 2 | 4 | 5) {
        c.bytes(full)?; // one inactive value
        if metadata == 5 {
            c.bytes(full)?; // a second one
        }
    }
    if matches!(metadata, 3..=5) {
        c.bytes(count / 8)?; // selection mask between the inactive values
    }
    let masked = ctx.compression & COMPRESS_ACTIVE_MASK != 0 && metadata != 6;
    let stored = if masked {
        mask.iter().map(|w| w.count_ones() as usize).sum()
    } else {
        count
    };
    let comps = ctx.value_type.components();
    let mut temp = Vec::with_capacity(stored * comps);
    // Half floats with nothing to store write nothing at all (OpenVDB's HalfReader).
    if !(ctx.half && stored == 0) {
        let size = ctx.value_type.size(ctx.half);
        let bytes = read_data(c, ctx.compression, stored * size)?;
        ctx.value_type.decode(&bytes, ctx.half, &mut temp);
    }
    if !masked || stored == count {
        return Ok(temp);
    }
    let mut out = Vec::with_capacity(count * comps);
    let mut next = 0;
    for i in 0..count {
        if bit(mask, i) {
            out.extend_from_slice(&temp[next * comps..(next + 1) * comps]);
            next += 1;
        } else {
            out.extend_from_slice(&ctx.background[..comps]);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tree_types() {
        assert_eq!(
            parse_tree_type("Tree_float_5_4_3").unwrap(),
            TreeType {
                value_type: ValueType::Float,
                half: false
            }
        );
        assert_eq!(
            parse_tree_type("Tree_vec3s_5_4_3_HalfFloat").unwrap(),
            TreeType {
                value_type: ValueType::Vec3s,
                half: true
            }
        );
        assert!(parse_tree_type("Tree_float_6_5_4").is_err());
        assert!(parse_tree_type("Tree_ptdataidx32_5_4_3").is_err());
        assert_eq!(strip_unique_suffix("density\u{1e}1"), "density");
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        assert_eq!(parse(b""), Err(VdbError::NotVdb));
        assert_eq!(parse(b"hello world, not a vdb"), Err(VdbError::NotVdb));
        let mut h = MAGIC.to_le_bytes().to_vec();
        h.extend(219u32.to_le_bytes());
        assert_eq!(parse(&h), Err(VdbError::UnsupportedVersion(219)));
        let mut h = MAGIC.to_le_bytes().to_vec();
        h.extend(224u32.to_le_bytes());
        assert!(matches!(parse(&h), Err(VdbError::Truncated { .. })));
    }
}
