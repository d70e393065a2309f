//! Simulation caches on disk: one OpenVDB file per frame, as Blender (Mantaflow) and Houdini
//! write them, turned into [`Volume`]s on one common grid so that a sequence's lights stay put.
//!
//! Blender's *adaptive domain* starts each frame's index space at the corner of that frame's
//! sub-box; the corner (`res_min`) is in the frame's `config/config_NNNN.uni` beside the
//! `data/` folder, and `base index = VDB index + res_min` puts every frame on the full domain's
//! grid. Without a config file the offset is zero (Houdini, or a non-adaptive domain).

use std::path::{Path, PathBuf};

use crate::error::ReadError;
use crate::medium::Volume;
use lgh_core::glam::Vec3;

use crate::grid::DenseGrid;
use crate::vdb;

/// Largest dense grid a cache may expand to (voxels).
pub use crate::grid::MAX_DENSE_VOXELS as MAX_VOXELS;

/// Voxels of background (zero) a [`Sequence`]'s common box keeps around the frames' active
/// voxels. OpenVDB's grids are zero outside their active voxels, and a trilinear lookup there
/// (Cycles', through NanoVDB) falls from the last active voxel's value to zero over the next
/// voxel; [`DenseGrid::sample`] instead holds an outermost voxel's value to its face. One voxel
/// of zeros makes the two the same field: without it, flames that touch the active box (a
/// domain's walls) shone over the half voxel beyond, 1.8% of the dev fire's image against
/// Cycles 3.4.1, most of it at its two side walls (docs/cycles.md, "Voxel placement").
pub const BACKGROUND_MARGIN: i32 = 1;

/// Which grids of the files hold what.
#[derive(Clone, Debug, PartialEq)]
pub struct GridNames {
    /// Smoke density (Blender: `density`).
    pub density: String,
    /// The grid emission follows (Blender: `temperature`; also `flame` or `heat`).
    pub emission: String,
    /// A grid multiplying the emission (Blender: `flame`), if any; a missing grid of this name
    /// is an error only when `flame_required`.
    pub flame: Option<String>,
    /// Whether a missing `flame` grid is an error (it is when the user named it).
    pub flame_required: bool,
    /// How the emission grid's values become the temperature grid's.
    pub emission_values: EmissionValues,
}

/// How a scalar emission grid's values become [`Volume::temperature`]'s.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum EmissionValues {
    /// As written.
    #[default]
    AsWritten,
    /// A Blender fluid domain's `flame` (0..1), read as Cycles reads the domain's `temperature`
    /// attribute (Blender's `rna_FluidModifier_temperature_grid_get`): `ignition + flame ×
    /// (max_temperature − ignition)` where `flame > 0.01`, else 0. The two are the domain's
    /// Fire > Ignition and Maximum temperature settings (Blender's defaults: 1.5 and 3), in
    /// units of the Principled Volume's Temperature (the medium's temperature scale).
    ///
    /// ```
    /// use lgh_volume::cache::EmissionValues;
    ///
    /// let domain = EmissionValues::BlenderFlame { ignition: 1.5, max_temperature: 3.0 };
    /// assert_eq!(domain.value(0.5), 2.25);
    /// assert_eq!(domain.value(0.01), 0.0); // no flame: no temperature
    /// assert_eq!(EmissionValues::AsWritten.value(0.01), 0.01);
    /// ```
    BlenderFlame {
        /// The temperature of the least flame.
        ignition: f32,
        /// The temperature of a whole flame (`flame` = 1).
        max_temperature: f32,
    },
}

impl EmissionValues {
    /// The temperature grid's value for the emission grid's `v`.
    #[must_use]
    pub fn value(self, v: f32) -> f32 {
        match self {
            EmissionValues::AsWritten => v,
            EmissionValues::BlenderFlame {
                ignition,
                max_temperature,
            } => {
                if v > 0.01 {
                    ignition + v * (max_temperature - ignition)
                } else {
                    0.0
                }
            }
        }
    }
}

impl Default for GridNames {
    /// Blender's grid names; `flame` is used when the file has it.
    fn default() -> Self {
        GridNames {
            density: "density".into(),
            emission: "temperature".into(),
            flame: Some("flame".into()),
            flame_required: false,
            emission_values: EmissionValues::AsWritten,
        }
    }
}

/// The file of frame `frame` in a cache whose file `example` is any frame: the last run of
/// digits in the file name is replaced by `frame`, zero-padded to the same width
/// (`fluid_data_0056.vdb` → `fluid_data_0050.vdb`).
pub fn frame_path(example: &Path, frame: u32) -> Result<PathBuf, ReadError> {
    let bad = || ReadError::FrameName {
        path: example.to_path_buf(),
    };
    let name = example
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(bad)?;
    let (start, end) = frame_digits(name).ok_or_else(bad)?;
    let width = end - start;
    let renamed = format!("{}{:0width$}{}", &name[..start], frame, &name[end..]);
    Ok(example.with_file_name(renamed))
}

/// Byte range of the frame number in a file name: its last run of digits.
fn frame_digits(name: &str) -> Option<(usize, usize)> {
    let end = name.rfind(|c: char| c.is_ascii_digit())? + 1;
    let start = name[..end]
        .rfind(|c: char| !c.is_ascii_digit())
        .map_or(0, |i| i + 1);
    Some((start, end))
}

/// Reads `res_min` from a Blender fluid config file (`config_NNNN.uni`: gzip of a 204-byte
/// little-endian record ending in `C01\0`, `res_min` as three i32 at byte 160).
pub fn read_blender_offset(path: &Path) -> Result<[i32; 3], ReadError> {
    let bytes = std::fs::read(path).map_err(|source| ReadError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_blender_offset(path, &bytes)
}

/// [`read_blender_offset`] of a config file's `bytes` already in memory, named `path` in
/// errors: what the fuzz target `uni` drives.
///
/// ```
/// use lgh_volume::cache::parse_blender_offset;
/// use std::path::Path;
///
/// let e = parse_blender_offset(Path::new("config_0001.uni"), b"not gzip").unwrap_err();
/// assert!(e.to_string().contains("not a gzip file"), "{e}");
/// ```
pub fn parse_blender_offset(path: &Path, bytes: &[u8]) -> Result<[i32; 3], ReadError> {
    let bad = |reason: String| ReadError::BlenderConfig {
        path: path.to_path_buf(),
        reason,
    };
    let raw = gunzip(bytes).map_err(bad)?;
    if raw.len() != 204 || &raw[200..204] != b"C01\0" {
        return Err(bad(
            "not a Blender fluid config (expected 204 bytes ending in C01)".into(),
        ));
    }
    let i32_at = |o: usize| i32::from_le_bytes([raw[o], raw[o + 1], raw[o + 2], raw[o + 3]]);
    let res_min = [i32_at(160), i32_at(164), i32_at(168)];
    if res_min.iter().any(|v| !(0..=1 << 16).contains(v)) {
        return Err(bad(format!("implausible domain offset {res_min:?}")));
    }
    Ok(res_min)
}

/// The config file Blender writes beside a frame: `…/data/fluid_data_NNNN.vdb` →
/// `…/config/config_NNNN.uni`.
#[must_use]
pub fn blender_config_path(vdb_path: &Path) -> Option<PathBuf> {
    let name = vdb_path.file_name()?.to_str()?;
    let (start, end) = frame_digits(name)?;
    let config = format!("config_{}.uni", &name[start..end]);
    Some(vdb_path.parent()?.parent()?.join("config").join(config))
}

/// Inflates a gzip member (RFC 1952); the error says what is wrong with it.
fn gunzip(bytes: &[u8]) -> Result<Vec<u8>, String> {
    if bytes.len() < 18 || bytes[0] != 0x1f || bytes[1] != 0x8b || bytes[2] != 8 {
        return Err("not a gzip file".into());
    }
    let flags = bytes[3];
    let mut at = 10usize;
    let past = |at: usize| -> Result<usize, String> {
        if at > bytes.len() {
            Err("truncated gzip header".into())
        } else {
            Ok(at)
        }
    };
    if flags & 4 != 0 {
        let n = u16::from_le_bytes([bytes[at], bytes[at + 1]]) as usize;
        at = past(at + 2 + n)?;
    }
    for bit in [8u8, 16] {
        if flags & bit != 0 {
            let nul = bytes[at..]
                .iter()
                .position(|&b| b == 0)
                .ok_or("truncated gzip header")?;
            at = past(at + nul + 1)?;
        }
    }
    if flags & 2 != 0 {
        at = past(at + 2)?;
    }
    miniz_oxide::inflate::decompress_to_vec_with_limit(&bytes[at..], 1 << 20)
        .map_err(|e| format!("corrupt gzip data: {e:?}"))
}

/// One frame's file as read, with the positions of its grids, before they are placed on the
/// common grid.
struct RawFrame {
    file: vdb::VdbFile,
    density: usize,
    emission: usize,
    flame: Option<usize>,
    offset: [i32; 3],
}

impl RawFrame {
    fn density(&self) -> &vdb::Grid {
        &self.file.grids[self.density]
    }

    fn emission(&self) -> &vdb::Grid {
        &self.file.grids[self.emission]
    }

    fn flame(&self) -> Option<&vdb::Grid> {
        self.flame.map(|i| &self.file.grids[i])
    }
}

/// Position of the grid `name` in `file`, or an error that lists the grids there are.
fn find_grid(file: &vdb::VdbFile, name: &str, path: &Path) -> Result<usize, ReadError> {
    file.grids
        .iter()
        .position(|g| g.name == name)
        .ok_or_else(|| ReadError::NoGrid {
            path: path.to_path_buf(),
            name: name.to_string(),
            available: file.grids.iter().map(|g| g.name.clone()).collect(),
        })
}

/// Where a cache's frames sit in index space.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Placement {
    /// In Blender's whole domain: each frame moved by the adaptive domain's offset in its
    /// `config/config_NNNN.uni`, when that file exists (Blender's caches move the domain with
    /// the smoke; without the offset a sequence's frames would not share one grid).
    #[default]
    BlenderDomain,
    /// Where the files put them, no offset read.
    AsWritten,
}

/// Which frames a sequence's scan keeps in memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Keep {
    /// Every frame, as read.
    All,
    /// The last frame read.
    Last,
}

impl RawFrame {
    /// Reads `path` and finds its grids (and its domain offset as `placement` says).
    fn read(path: &Path, names: &GridNames, placement: Placement) -> Result<Self, ReadError> {
        let file = vdb::read(path).map_err(|source| ReadError::Vdb {
            path: path.to_path_buf(),
            source,
        })?;
        let density = find_grid(&file, &names.density, path)?;
        let emission = find_grid(&file, &names.emission, path)?;
        let flame = match &names.flame {
            Some(n) => match find_grid(&file, n, path) {
                Ok(g) => Some(g),
                Err(e) if names.flame_required => return Err(e),
                Err(_) => None,
            },
            None => None,
        };
        // The flame factor scales the blackbody; an RGB emission is its own colour and
        // strength: Blender's `flame`, found by default, is not used, and one named is refused.
        let rgb = file.grids[emission].value_type.components() == 3;
        let flame = match flame {
            Some(g) if rgb && names.flame_required => {
                return Err(ReadError::FlameWithColour {
                    path: path.to_path_buf(),
                    flame: file.grids[g].name.clone(),
                    emission: names.emission.clone(),
                })
            }
            Some(_) if rgb => None,
            flame => flame,
        };
        if rgb && names.emission_values != EmissionValues::AsWritten {
            return Err(ReadError::TemperatureOfColour {
                path: path.to_path_buf(),
                emission: names.emission.clone(),
            });
        }
        let offset = match blender_config_path(path)
            .filter(|c| placement == Placement::BlenderDomain && c.is_file())
        {
            Some(c) => read_blender_offset(&c)?,
            None => [0; 3],
        };
        Ok(RawFrame {
            file,
            density,
            emission,
            flame,
            offset,
        })
    }

    /// Index-space box (inclusive, in the full domain's index space) of the active voxels of
    /// the frame's grids; empty (lo > hi) when none is active.
    fn index_box(&self) -> ([i32; 3], [i32; 3]) {
        let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
        for (a, b) in self.grids().filter_map(|g| g.active_bbox()) {
            for k in 0..3 {
                lo[k] = lo[k].min(a[k].saturating_add(self.offset[k]));
                hi[k] = hi[k].max(b[k].saturating_add(self.offset[k]));
            }
        }
        (lo, hi)
    }

    /// The grids that make the volume.
    fn grids(&self) -> impl Iterator<Item = &vdb::Grid> {
        [self.density(), self.emission()]
            .into_iter()
            .chain(self.flame())
    }
}

/// Frames of a cache opened for streaming: every file read once to check it and to find the one
/// dense box that covers every frame's active voxels of the three grids (in the full domain's
/// index space with [`Placement::BlenderDomain`], reading each frame's config file if it
/// exists); then
/// [`frame`](Self::frame) reads one frame at a time onto that box, so a long sequence never
/// needs more than one frame in memory.
#[derive(Clone, Debug)]
pub struct Sequence {
    paths: Vec<PathBuf>,
    names: GridNames,
    placement: Placement,
    transform: [[f64; 4]; 4],
    /// The common box, inclusive, in index space.
    lo: [i32; 3],
    hi: [i32; 3],
}

/// Where a [`Sequence`]'s frames land: the transform of their grids and the common box, in
/// index space. What a task rendering some frames of a sequence needs to place them exactly as
/// a run over the whole sequence does, without reading the other frames
/// ([`Sequence::with_layout`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SequenceLayout {
    /// Index to world, the first frame's density grid's (every grid of every frame shares it).
    pub transform: [[f64; 4]; 4],
    /// The common box's low corner, inclusive, in index space.
    pub lo: [i32; 3],
    /// Its high corner, inclusive.
    pub hi: [i32; 3],
}

impl SequenceLayout {
    /// Voxels of the common box, or `None` for a box with a side below one voxel or past
    /// [`MAX_VOXELS`]: what [`Sequence::with_layout`] and a manifest's reader refuse.
    #[must_use]
    pub fn voxels(&self) -> Option<usize> {
        (0..3)
            .try_fold(1usize, |a, k| {
                let side = i64::from(self.hi[k]) - i64::from(self.lo[k]) + 1;
                usize::try_from(side)
                    .ok()
                    .filter(|&s| s >= 1)
                    .and_then(|s| a.checked_mul(s))
            })
            .filter(|&v| v <= MAX_VOXELS)
    }
}

impl Sequence {
    /// The frames' transform and common box: with [`with_layout`](Self::with_layout), the
    /// same sequence without reading every frame again.
    #[must_use]
    pub fn layout(&self) -> SequenceLayout {
        SequenceLayout {
            transform: self.transform,
            lo: self.lo,
            hi: self.hi,
        }
    }

    /// The sequence of `paths` on a `layout` found before (by [`open`](Self::open) over the
    /// same files, kept in a farm manifest): no file is read until [`frame`](Self::frame),
    /// which checks each against the layout. A box with no voxels or too many is an error.
    ///
    /// ```
    /// use lgh_volume::cache::{GridNames, Placement, Sequence, SequenceLayout};
    ///
    /// let layout = SequenceLayout { transform: [[0.5, 0.0, 0.0, 0.0], [0.0, 0.5, 0.0, 0.0],
    ///     [0.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.0, 1.0]], lo: [0; 3], hi: [7; 3] };
    /// let seq = Sequence::with_layout(&["f_0001.vdb".into()], &GridNames::default(), Placement::BlenderDomain,
    ///     layout.clone())?;
    /// assert_eq!(seq.dims(), [8; 3]);
    /// assert_eq!(seq.layout(), layout);
    /// assert!(seq.frame(0).is_err()); // no such file
    /// let empty = SequenceLayout { hi: [-1; 3], ..layout };
    /// assert!(Sequence::with_layout(&[], &GridNames::default(), Placement::BlenderDomain, empty).is_err());
    /// # Ok::<(), lgh_volume::ReadError>(())
    /// ```
    pub fn with_layout(
        paths: &[PathBuf],
        names: &GridNames,
        placement: Placement,
        layout: SequenceLayout,
    ) -> Result<Self, ReadError> {
        if layout.voxels().is_none() {
            return Err(ReadError::BadLayout {
                lo: layout.lo,
                hi: layout.hi,
            });
        }
        let SequenceLayout { transform, lo, hi } = layout;
        Ok(Sequence {
            paths: paths.to_vec(),
            names: names.clone(),
            placement,
            transform,
            lo,
            hi,
        })
    }

    /// Opens the frames `paths`. All frames must share one voxel size and transform.
    pub fn open(
        paths: &[PathBuf],
        names: &GridNames,
        placement: Placement,
    ) -> Result<Self, ReadError> {
        Ok(Sequence::scan(paths, names, placement, Keep::Last)?.0)
    }

    /// [`open`](Self::open), and the last frame, which opening has just read, placed on the
    /// common box: a caller that goes over every frame again can start with it and read it once.
    pub fn open_with_last(
        paths: &[PathBuf],
        names: &GridNames,
        placement: Placement,
    ) -> Result<(Self, Volume), ReadError> {
        let (seq, kept) = Sequence::scan(paths, names, placement, Keep::Last)?;
        let last = kept.last().ok_or(ReadError::NoFrames)?;
        let volume = seq.place(last)?;
        Ok((seq, volume))
    }

    /// Reads every frame once, checks it and grows the common box; keeps the frames `keep`
    /// says, as read.
    fn scan(
        paths: &[PathBuf],
        names: &GridNames,
        placement: Placement,
        keep: Keep,
    ) -> Result<(Self, Vec<RawFrame>), ReadError> {
        let mut seq: Option<Sequence> = None;
        let mut kept = Vec::new();
        for path in paths {
            let raw = RawFrame::read(path, names, placement)?;
            let s = seq.get_or_insert_with(|| Sequence {
                paths: paths.to_vec(),
                names: names.clone(),
                placement,
                transform: raw.density().index_to_world,
                lo: [i32::MAX; 3],
                hi: [i32::MIN; 3],
            });
            s.check(&raw, path)?;
            let (lo, hi) = raw.index_box();
            for k in 0..3 {
                s.lo[k] = s.lo[k].min(lo[k]);
                s.hi[k] = s.hi[k].max(hi[k]);
            }
            if keep == Keep::Last {
                kept.clear();
            }
            kept.push(raw);
        }
        let mut seq = seq.ok_or(ReadError::NoFrames)?;
        if seq.lo[0] > seq.hi[0] {
            return Err(ReadError::NoActiveVoxels);
        }
        for k in 0..3 {
            seq.lo[k] = seq.lo[k].saturating_sub(BACKGROUND_MARGIN);
            seq.hi[k] = seq.hi[k].saturating_add(BACKGROUND_MARGIN);
        }
        let dims = seq.dims();
        let voxels = dims.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
        if voxels.is_none_or(|v| v > MAX_VOXELS) {
            return Err(ReadError::TooManyVoxels {
                max: MAX_VOXELS,
                grid: None,
                dims: Some(dims),
            });
        }
        Ok((seq, kept))
    }

    /// Voxels of the common grid per axis.
    #[must_use]
    pub fn dims(&self) -> [usize; 3] {
        [0, 1, 2].map(|k| (i64::from(self.hi[k]) - i64::from(self.lo[k]) + 1) as usize)
    }

    /// Voxel size (the x axis of the transform; a frame whose voxels are not cubes is an error
    /// when it is read).
    #[must_use]
    pub fn voxel_size(&self) -> f32 {
        self.transform[0][0] as f32
    }

    /// Checks that every grid of `raw` (read from `path`) is scalar and placed by the
    /// sequence's transform, the first frame's density grid's.
    fn check(&self, raw: &RawFrame, path: &Path) -> Result<(), ReadError> {
        for g in raw.grids() {
            if g.index_to_world != self.transform {
                return Err(ReadError::GridTransform {
                    path: path.to_path_buf(),
                    grid: g.name.clone(),
                    reference: self.names.density.clone(),
                    reference_path: self.paths[0].clone(),
                });
            }
            // The emission may be an RGB vec3 grid (Volume::colour); the others are scalar.
            let rgb = std::ptr::eq(g, raw.emission()) && g.value_type.components() == 3;
            if g.value_type.components() != 1 && !rgb {
                return Err(ReadError::NotScalar {
                    path: path.to_path_buf(),
                    grid: g.name.clone(),
                    value_type: g.value_type.name(),
                });
            }
        }
        Ok(())
    }

    /// Number of frames.
    #[must_use]
    pub fn len(&self) -> usize {
        self.paths.len()
    }

    /// Whether there are no frames (never: [`open`](Self::open) refuses none).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.paths.is_empty()
    }

    /// The frames' files.
    #[must_use]
    pub fn paths(&self) -> &[PathBuf] {
        &self.paths
    }

    /// World box of the common grid (voxel faces): every frame's grids cover it.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let h = self.voxel_size();
        let lo = DenseGrid::world_position(&self.transform, self.lo);
        let size = Vec3::from(self.dims().map(|d| d as f32)) * h;
        (lo - Vec3::splat(0.5 * h), lo - Vec3::splat(0.5 * h) + size)
    }

    /// Reads frame `i` onto the common box (checked again: the file may have changed since
    /// [`open`](Self::open)).
    pub fn frame(&self, i: usize) -> Result<Volume, ReadError> {
        let path = self.paths.get(i).ok_or(ReadError::NoSuchFrame {
            index: i,
            len: self.len(),
        })?;
        let raw = RawFrame::read(path, &self.names, self.placement)?;
        self.check(&raw, path)?;
        let (lo, hi) = raw.index_box();
        if (0..3).any(|k| lo[k] < self.lo[k] || hi[k] > self.hi[k]) {
            return Err(ReadError::FrameChanged {
                path: path.to_path_buf(),
            });
        }
        self.place(&raw)
    }

    /// `raw` on the common box: every frame lands at the box's place, whatever its own domain
    /// offset.
    fn place(&self, raw: &RawFrame) -> Result<Volume, ReadError> {
        let origin = DenseGrid::world_position(&self.transform, self.lo);
        let a = [0, 1, 2].map(|k| self.lo[k] - raw.offset[k]);
        let b = [0, 1, 2].map(|k| self.hi[k] - raw.offset[k]);
        let place = |g: &vdb::Grid| DenseGrid::from_vdb_at(g, a, b, origin);
        let (density, emission) = (place(raw.density())?, raw.emission());
        if emission.value_type.components() == 3 {
            // An RGB emission: its three channels, placed as every grid is.
            let channel = |c| DenseGrid::component_from_vdb_at(emission, c, a, b, origin);
            let colour = [channel(0)?, channel(1)?, channel(2)?];
            return Ok(Volume::coloured(density, colour));
        }
        let mut temperature = place(emission)?;
        if self.names.emission_values != EmissionValues::AsWritten {
            let values = self.names.emission_values;
            temperature
                .data
                .iter_mut()
                .for_each(|v| *v = values.value(*v));
        }
        Ok(Volume {
            density,
            temperature,
            flame: raw.flame().map(place).transpose()?,
            colour: None,
        })
    }
}

/// Loads the frames `paths` onto one dense grid ([`Sequence`]), all at once, reading each file
/// once.
pub fn load(
    paths: &[PathBuf],
    names: &GridNames,
    placement: Placement,
) -> Result<Vec<Volume>, ReadError> {
    let (seq, raws) = Sequence::scan(paths, names, placement, Keep::All)?;
    raws.iter().map(|raw| seq.place(raw)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_paths_keep_the_padding() {
        let p = Path::new("/c/data/fluid_data_0056.vdb");
        assert_eq!(
            frame_path(p, 50).unwrap(),
            Path::new("/c/data/fluid_data_0050.vdb")
        );
        assert_eq!(
            frame_path(Path::new("f7.vdb"), 123).unwrap(),
            Path::new("f123.vdb")
        );
        assert!(frame_path(Path::new("fire.vdb"), 1).is_err());
        assert_eq!(
            blender_config_path(p).unwrap(),
            Path::new("/c/config/config_0056.uni")
        );
    }

    #[test]
    fn bad_config_files_are_errors() {
        let dir = std::env::temp_dir().join(format!("lgh-cache-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("config_0001.uni");
        std::fs::write(&p, b"not gzip at all, clearly").unwrap();
        assert!(read_blender_offset(&p).is_err());
        std::fs::write(
            &p,
            [0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8],
        )
        .unwrap();
        assert!(read_blender_offset(&p).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
