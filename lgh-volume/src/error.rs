//! The one error type of lgh-volume: what went wrong, with the data to say so (the path, the
//! grid, the setting and its value) and, where another crate's error is the cause, that error as
//! [`source`](std::error::Error::source). The CLI turns it into one line of text; a library user
//! can match on it.

use std::fmt;
use std::path::PathBuf;

use lgh_core::glam::Vec3;
use lgh_core::{BuildError, QueryError};
use lgh_image::camera::CameraError;

use crate::vdb::VdbError;

/// Why reading, lighting or rendering a volume failed.
#[derive(Debug)]
#[non_exhaustive]
pub enum VolumeError {
    /// A real-valued setting outside its range: "`name` `value` `rule`", e.g. "march settings:
    /// step 100 must be 0.01 to 64 voxels".
    InvalidSetting {
        /// The setting, as a user would name it.
        name: &'static str,
        /// The rejected value.
        value: f32,
        /// What is allowed ("must be …" or "is outside …").
        rule: &'static str,
    },
    /// A count outside its range (resolution, samples per pixel).
    InvalidCount {
        /// The setting, as a user would name it.
        name: &'static str,
        /// The rejected value.
        value: usize,
        /// What is allowed.
        rule: &'static str,
    },
    /// The path tracer's environment radiance is negative or not finite.
    InvalidEnvironment {
        /// The rejected radiance.
        radiance: Vec3,
    },
    /// No frames were given.
    NoFrames,
    /// A frame's flame grid does not lie on its temperature grid (frame index if known).
    FlameOffGrid {
        /// Index of the frame in the sequence.
        frame: Option<usize>,
    },
    /// A frame's temperature grid has another layout (dimensions, voxel size, origin) than the
    /// sequence's first frame (`frame: Some`) or than the lights (`frame: None`).
    FrameOffGrid {
        /// Index of the frame in the sequence.
        frame: Option<usize>,
    },
    /// The light hierarchy (or brute force's light set) could not be built.
    Lights(BuildError),
    /// A many-lights query failed at a shading point.
    Query(QueryError),
    /// The camera could not be set up.
    Camera(CameraError),
    /// A requested pixel lies outside the image.
    PixelOutside {
        /// The pixel `(x, y)`.
        pixel: [usize; 2],
        /// Image width.
        width: usize,
        /// Image height.
        height: usize,
    },
    /// A grid cannot be sampled: its dimensions do not match its values.
    GridShape {
        /// Which grid ("density", "temperature").
        grid: &'static str,
        /// Its dimensions.
        dims: [usize; 3],
        /// How many values it holds.
        values: usize,
    },
    /// A grid cannot be sampled: its voxel size or origin is not finite (or the size ≤ 0).
    GridGeometry {
        /// Which grid.
        grid: &'static str,
        /// Its voxel size.
        voxel_size: f32,
        /// Its origin.
        origin: Vec3,
    },
    /// The path tracer's extinction majorant is not finite or too large to track.
    Majorant {
        /// The majorant σ̄ per unit length.
        sigma: f32,
        /// The voxel size.
        voxel_size: f32,
    },
    /// A VDB grid's transform is not axis-aligned with cubic voxels.
    UnsupportedTransform {
        /// The grid's name.
        grid: String,
    },
    /// Making a grid (or a sequence's common box) dense would exceed
    /// [`MAX_DENSE_VOXELS`](crate::grid::MAX_DENSE_VOXELS).
    TooManyVoxels {
        /// The grid's name, or `None` for a sequence's common box.
        grid: Option<String>,
        /// Its dimensions, where known.
        dims: Option<[usize; 3]>,
    },
    /// The deep-shadow cube maps a render asks for would not fit in the memory allowed them
    /// (found before any map is traced).
    ShadowMemory {
        /// Bytes the maps would take.
        needed: u64,
        /// Bytes allowed.
        budget: u64,
        /// The paper's α they were planned for.
        alpha: f32,
    },
    /// Multiple scattering needs the density on the lights' grid (scattered lights sit at the
    /// density's voxel centres and merge with the emission light of the same voxel).
    DensityOffGrid,
    /// The lights of a multiple-scattering pass would not fit in the memory allowed (found
    /// before any work).
    ScatterMemory {
        /// Bytes the pass's lights would take.
        needed: u64,
        /// Bytes allowed (the cube maps' budget).
        budget: u64,
        /// The scattering depth asked for.
        depth: usize,
    },
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
    /// A grid is not scalar.
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
    /// A sequence's stored layout (a farm manifest's) that no sequence can have: a box with a
    /// side below one voxel or past [`crate::cache::MAX_VOXELS`].
    BadLayout {
        /// The box's low corner, inclusive, in index space.
        lo: [i32; 3],
        /// Its high corner, inclusive.
        hi: [i32; 3],
    },
    /// Light voxels (a farm manifest's) that are not strictly ascending indices into the grid.
    BadLightVoxels {
        /// The first offending position in the list.
        at: usize,
        /// Voxels of the grid.
        voxels: usize,
    },
}

impl fmt::Display for VolumeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use VolumeError as E;
        match self {
            E::InvalidSetting { name, value, rule } => write!(f, "{name} {value} {rule}"),
            E::InvalidCount { name, value, rule } => write!(f, "{name} {value} {rule}"),
            E::InvalidEnvironment { radiance } => write!(
                f,
                "path tracer: environment radiance {radiance} must be finite and ≥ 0"
            ),
            E::NoFrames => write!(f, "no frames given"),
            E::FlameOffGrid { frame: Some(i) } => write!(
                f,
                "frame {i}: the flame grid is on another grid than the temperature"
            ),
            E::FlameOffGrid { frame: None } => {
                write!(f, "the flame grid is on another grid than the temperature")
            }
            E::FrameOffGrid { frame: Some(i) } => write!(
                f,
                "frame {i}'s temperature is on another grid than frame 0's: a sequence's lights \
                 need one grid (dimensions, voxel size, origin)"
            ),
            E::FrameOffGrid { frame: None } => {
                write!(f, "frame is on another grid than the lights")
            }
            E::Lights(e) => write!(f, "cannot build the lights: {e}"),
            E::Query(e) => write!(f, "lighting query failed: {e}"),
            E::Camera(e) => write!(f, "{e}"),
            E::PixelOutside {
                pixel,
                width,
                height,
            } => write!(f, "pixel {pixel:?} is outside the {width}x{height} image"),
            E::GridShape { grid, dims, values } => write!(
                f,
                "{grid} grid: dimensions {dims:?} do not match its {values} values"
            ),
            E::GridGeometry {
                grid,
                voxel_size,
                origin,
            } => write!(
                f,
                "{grid} grid: voxel size {voxel_size} and origin {origin} must be finite (size > 0)"
            ),
            E::Majorant { sigma, voxel_size } => write!(
                f,
                "path tracer: extinction majorant {sigma} per unit length is not finite or too \
                 large to track (voxel size {voxel_size})"
            ),
            E::UnsupportedTransform { grid } => {
                write!(f, "grid '{grid}' has a non-uniform or rotated transform")
            }
            E::TooManyVoxels { grid, dims } => {
                let max = crate::grid::MAX_DENSE_VOXELS;
                match (grid, dims) {
                    (Some(g), _) => write!(f, "grid '{g}' is too large to make dense"),
                    (None, Some([x, y, z])) => write!(
                        f,
                        "the frames span {x}x{y}x{z} voxels, more than the {max} a dense grid may hold"
                    ),
                    (None, None) => write!(f, "more than the {max} voxels a dense grid may hold"),
                }
            }
            E::ShadowMemory {
                needed,
                budget,
                alpha,
            } => write!(
                f,
                "the deep-shadow cube maps at alpha {alpha} would need {:.2} GB, more than the \
                 {:.2} GB allowed them: lower --alpha, raise --shadow-memory, or use --shadows \
                 raymarch",
                *needed as f64 / 1e9,
                *budget as f64 / 1e9
            ),
            E::DensityOffGrid => write!(
                f,
                "multiple scattering needs the density on the temperature's grid (dimensions, \
                 voxel size, origin): its lights sit at voxel centres"
            ),
            E::ScatterMemory {
                needed,
                budget,
                depth,
            } => write!(
                f,
                "multiple scattering to depth {depth} would need {:.2} GB for its lights, more \
                 than the {:.2} GB allowed: lower --scatter-depth or raise --shadow-memory",
                *needed as f64 / 1e9,
                *budget as f64 / 1e9
            ),
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
            E::NotScalar {
                path,
                grid,
                value_type,
            } => write!(
                f,
                "{}: grid '{grid}' is a {value_type} grid; density, emission and flame must be scalar",
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
            E::BadLayout { lo, hi } => write!(
                f,
                "a sequence box from {lo:?} to {hi:?} (inclusive) is empty or too large"
            ),
            E::BadLightVoxels { at, voxels } => write!(
                f,
                "light voxel list: entry {at} is not above the one before it or not below the \
                 grid's {voxels} voxels"
            ),
        }
    }
}

impl std::error::Error for VolumeError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            VolumeError::Lights(e) => Some(e),
            VolumeError::Query(e) => Some(e),
            VolumeError::Camera(e) => Some(e),
            VolumeError::Io { source, .. } => Some(source),
            VolumeError::Vdb { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<BuildError> for VolumeError {
    fn from(e: BuildError) -> Self {
        VolumeError::Lights(e)
    }
}

impl From<QueryError> for VolumeError {
    fn from(e: QueryError) -> Self {
        VolumeError::Query(e)
    }
}

impl From<CameraError> for VolumeError {
    fn from(e: CameraError) -> Self {
        VolumeError::Camera(e)
    }
}

/// `Ok(value)` if `ok`, else [`VolumeError::InvalidSetting`]: the one shape of every range
/// check of a real-valued setting.
pub(crate) fn check_setting(
    ok: bool,
    name: &'static str,
    value: f32,
    rule: &'static str,
) -> Result<f32, VolumeError> {
    if ok {
        Ok(value)
    } else {
        Err(VolumeError::InvalidSetting { name, value, rule })
    }
}
