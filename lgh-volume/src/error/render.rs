//! Why lighting or rendering a volume failed: a setting out of range, lights that cannot be
//! built, a failed query, shadows that would not fit in memory — or the volume could not be
//! read ([`RenderError::Read`]).

use std::fmt;

use lgh_core::glam::Vec3;
use lgh_core::{BuildError, QueryError};
use lgh_image::camera::CameraError;

use super::ReadError;

/// Why lighting or rendering a volume failed.
#[derive(Debug)]
#[non_exhaustive]
pub enum RenderError {
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
    /// A march's background radiance is negative or not finite.
    InvalidBackground {
        /// The rejected radiance.
        radiance: Vec3,
    },
    /// No frames were given to make lights of.
    NoFrames,
    /// A frame's flame grid does not lie on its temperature grid (frame index if known).
    FlameOffGrid {
        /// Index of the frame in the sequence.
        frame: Option<usize>,
    },
    /// A frame's RGB emission grids ([`Volume::colour`](crate::Volume::colour)) are not all on
    /// the temperature's layout.
    ColourOffGrid {
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
    /// Light voxels (a farm manifest's) that are not strictly ascending indices into the grid.
    BadLightVoxels {
        /// The first offending position in the list.
        at: usize,
        /// Voxels of the grid.
        voxels: usize,
    },
    /// The volume could not be read (a sequence's frame, read as it is rendered).
    Read(ReadError),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use RenderError as E;
        match self {
            E::InvalidSetting { name, value, rule } => write!(f, "{name} {value} {rule}"),
            E::InvalidCount { name, value, rule } => write!(f, "{name} {value} {rule}"),
            E::InvalidEnvironment { radiance } => write!(
                f,
                "path tracer: environment radiance {radiance} must be finite and ≥ 0"
            ),
            E::InvalidBackground { radiance } => write!(
                f,
                "march settings: background radiance {radiance} must be finite and ≥ 0"
            ),
            E::NoFrames => write!(f, "no frames given"),
            E::FlameOffGrid { frame: Some(i) } => write!(
                f,
                "frame {i}: the flame grid is on another grid than the temperature"
            ),
            E::FlameOffGrid { frame: None } => {
                write!(f, "the flame grid is on another grid than the temperature")
            }
            E::ColourOffGrid { frame: Some(i) } => write!(
                f,
                "frame {i}: the RGB emission's channels are not on one grid with its temperature"
            ),
            E::ColourOffGrid { frame: None } => write!(
                f,
                "the RGB emission's channels are not on one grid with the temperature"
            ),
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
            E::ShadowMemory {
                needed,
                budget,
                alpha,
            } => write!(
                f,
                "the deep-shadow cube maps at alpha {alpha} would need {:.2} GB, more than the \
                 {:.2} GB allowed them (CubeMapSettings::memory_budget): lower alpha, raise the \
                 budget, or shade with ray-marched shadows (Shadows::RayMarch)",
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
                 than the {:.2} GB allowed (CubeMapSettings::memory_budget): lower the depth \
                 (MarchSettings::scatter_depth) or raise the budget",
                *needed as f64 / 1e9,
                *budget as f64 / 1e9
            ),
            E::BadLightVoxels { at, voxels } => write!(
                f,
                "light voxel list: entry {at} is not above the one before it or not below the \
                 grid's {voxels} voxels"
            ),
            E::Read(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RenderError::Lights(e) => Some(e),
            RenderError::Query(e) => Some(e),
            RenderError::Camera(e) => Some(e),
            // The read error's own message is this one's: its cause is the next link.
            RenderError::Read(e) => e.source(),
            _ => None,
        }
    }
}

impl From<BuildError> for RenderError {
    fn from(e: BuildError) -> Self {
        RenderError::Lights(e)
    }
}

impl From<QueryError> for RenderError {
    fn from(e: QueryError) -> Self {
        RenderError::Query(e)
    }
}

impl From<CameraError> for RenderError {
    fn from(e: CameraError) -> Self {
        RenderError::Camera(e)
    }
}

impl From<ReadError> for RenderError {
    fn from(e: ReadError) -> Self {
        RenderError::Read(e)
    }
}
