//! Why reading a volume failed: an OpenVDB file, a cache's frames placed on one grid, Blender's
//! fluid config, a farm manifest's stored layout.

use std::fmt;
use std::path::PathBuf;

use crate::vdb::VdbError;

/// Why reading a volume (a VDB file, a cache's sequence of frames, Blender's config) failed.
#[derive(Debug)]
#[non_exhaustive]
pub enum ReadError {
    /// No frames were given to a sequence.
    NoFrames,
    /// A file could not be read.
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A file is not a readable OpenVDB file.
    Vdb {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: VdbError,
    },
    /// A Blender fluid config file (`config_NNNN.uni`) is not one or is damaged.
    BlenderConfig {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A file has no grid of the asked-for name.
    NoGrid {
        /// The file.
        path: PathBuf,
        /// The missing name.
        name: String,
        /// The grids the file has.
        available: Vec<String>,
    },
    /// A grid has another transform than the sequence's first density grid.
    GridTransform {
        /// The file.
        path: PathBuf,
        /// The grid.
        grid: String,
        /// The reference grid's name.
        reference: String,
        /// The reference grid's file.
        reference_path: PathBuf,
    },
    /// A flame grid was named ([`GridNames::flame`](crate::cache::GridNames::flame)) with an
    /// RGB emission grid, which it cannot scale: the flame factor scales the blackbody.
    FlameWithColour {
        /// The file.
        path: PathBuf,
        /// The flame grid named.
        flame: String,
        /// The vec3 emission grid.
        emission: String,
    },
    /// The emission grid's values were to be read as a temperature
    /// ([`EmissionValues`](crate::cache::EmissionValues)), but the grid is an RGB emission.
    TemperatureOfColour {
        /// The file.
        path: PathBuf,
        /// The vec3 emission grid.
        emission: String,
    },
    /// A grid is not scalar (density, flame), or the emission neither scalar nor vec3.
    NotScalar {
        /// The file.
        path: PathBuf,
        /// The grid.
        grid: String,
        /// Its value type.
        value_type: &'static str,
    },
    /// None of a sequence's frames has an active voxel.
    NoActiveVoxels,
    /// A frame file changed since its sequence was opened.
    FrameChanged {
        /// The file.
        path: PathBuf,
    },
    /// A frame index past the end of a sequence.
    NoSuchFrame {
        /// The index.
        index: usize,
        /// Frames in the sequence.
        len: usize,
    },
    /// A path has no file name, or its file name has no frame number.
    FrameName {
        /// The path.
        path: PathBuf,
    },
    /// A VDB grid's transform is not axis-aligned with cubic voxels.
    UnsupportedTransform {
        /// The grid's name.
        grid: String,
    },
    /// Making a grid (or a sequence's common box) dense would exceed `max` voxels
    /// ([`MAX_DENSE_VOXELS`](crate::grid::MAX_DENSE_VOXELS)).
    TooManyVoxels {
        /// The most voxels a dense grid may hold.
        max: usize,
        /// The grid's name, or `None` for a sequence's common box.
        grid: Option<String>,
        /// Its dimensions, where known.
        dims: Option<[usize; 3]>,
    },
    /// A sequence's stored layout (a farm manifest's) that no sequence can have: a box with a
    /// side below one voxel or past [`crate::cache::MAX_VOXELS`].
    BadLayout {
        /// The box's low corner, inclusive, in index space.
        lo: [i32; 3],
        /// Its high corner, inclusive.
        hi: [i32; 3],
    },
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ReadError as E;
        match self {
            E::NoFrames => write!(f, "no frames given"),
            E::Io { path, source } => write!(f, "{}: {source}", path.display()),
            E::Vdb { path, source } => write!(f, "{}: {source}", path.display()),
            E::BlenderConfig { path, reason } => write!(f, "{}: {reason}", path.display()),
            E::NoGrid {
                path,
                name,
                available,
            } => write!(
                f,
                "{}: no grid named '{name}' (grids: {})",
                path.display(),
                available.join(", ")
            ),
            E::GridTransform {
                path,
                grid,
                reference,
                reference_path,
            } => write!(
                f,
                "{}: grid '{grid}' has another transform (voxel size or placement) than \
                 '{reference}' of {}",
                path.display(),
                reference_path.display()
            ),
            E::FlameWithColour {
                path,
                flame,
                emission,
            } => write!(
                f,
                "{}: '{emission}' is an RGB (vec3) emission grid, read as it is; the flame grid \
                 '{flame}' scales a blackbody emission and cannot scale it: name no flame grid \
                 (GridNames::flame None)",
                path.display()
            ),
            E::TemperatureOfColour { path, emission } => write!(
                f,
                "{}: '{emission}' is an RGB (vec3) emission grid, read as it is; it has no \
                 flame to read as a Blender domain's temperature (EmissionValues::AsWritten)",
                path.display()
            ),
            E::NotScalar {
                path,
                grid,
                value_type,
            } => write!(
                f,
                "{}: grid '{grid}' is a {value_type} grid; density and flame must be scalar, emission scalar or vec3 (RGB)",
                path.display()
            ),
            E::NoActiveVoxels => write!(f, "the frames have no active voxels"),
            E::FrameChanged { path } => write!(
                f,
                "{}: changed since the sequence was opened (its voxels leave the common box)",
                path.display()
            ),
            E::NoSuchFrame { index, len } => {
                write!(f, "frame {index} is past the end of a {len}-frame sequence")
            }
            E::FrameName { path } => write!(
                f,
                "{}: no frame number in the file name",
                path.display()
            ),
            E::UnsupportedTransform { grid } => {
                write!(f, "grid '{grid}' has a non-uniform or rotated transform")
            }
            E::TooManyVoxels { max, grid, dims } => {
                match (grid, dims) {
                    (Some(g), _) => write!(f, "grid '{g}' is too large to make dense"),
                    (None, Some([x, y, z])) => write!(
                        f,
                        "the frames span {x}x{y}x{z} voxels, more than the {max} a dense grid may hold"
                    ),
                    (None, None) => write!(f, "more than the {max} voxels a dense grid may hold"),
                }
            }
            E::BadLayout { lo, hi } => write!(
                f,
                "a sequence box from {lo:?} to {hi:?} (inclusive) is empty or too large"
            ),
        }
    }
}

impl std::error::Error for ReadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ReadError::Io { source, .. } => Some(source),
            ReadError::Vdb { source, .. } => Some(source),
            _ => None,
        }
    }
}
