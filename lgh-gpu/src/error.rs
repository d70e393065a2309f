//! What can go wrong on the GPU path.

use core::fmt;

/// An error of the GPU path: no adapter, a device that cannot hold the hierarchy, bad input.
#[derive(Clone, Debug, PartialEq)]
pub enum GpuError {
    /// No Vulkan, Metal or DX12 adapter was found (on Linux without a GPU, Mesa's software
    /// Vulkan, lavapipe, is one: `apt-get install mesa-vulkan-drivers`).
    NoAdapter(String),
    /// The adapter would not give a device.
    Device(String),
    /// A level's dense grid of cells would be too large: its lights are spread too thinly for
    /// the cell size its reach asks for.
    TooManyCells {
        /// The level.
        level: u8,
        /// The cells it would take.
        cells: u64,
        /// The most allowed.
        most: u64,
    },
    /// A buffer would be larger than the device allows in one binding.
    TooLarge {
        /// What the buffer holds.
        what: &'static str,
        /// Its bytes.
        bytes: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The query's α or the hierarchy was refused by lgh-core.
    Query(lgh_core::QueryError),
    /// A shading point with a non-finite position, normal or albedo.
    InvalidPoint {
        /// Its index.
        index: usize,
    },
    /// Reading the results back failed.
    Readback(String),
    /// A grid whose box or spacing is not finite and positive.
    InvalidGrid,
    /// A caller's buffer holds fewer elements than the call names.
    BufferTooSmall {
        /// What it holds.
        what: &'static str,
        /// Its bytes.
        bytes: u64,
        /// The bytes the call needs.
        needed: u64,
    },
    /// A light or intensity refused, as lgh-core's build refuses it.
    Build(lgh_core::BuildError),
    /// The gather draws 1 to `most` lights a point (the gather's `MAX_K`).
    InvalidK {
        /// The draws asked for.
        k: u32,
        /// The most it draws.
        most: u32,
    },
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(why) => write!(
                f,
                "no GPU adapter (Vulkan, Metal or DX12): {why}; without a GPU on Linux, \
                 Mesa's software Vulkan works: apt-get install mesa-vulkan-drivers"
            ),
            GpuError::Device(why) => write!(f, "the GPU adapter gave no device: {why}"),
            GpuError::TooManyCells { level, cells, most } => write!(
                f,
                "level {level}'s lights are too spread out for the GPU's dense cells: {cells} \
                 cells, at most {most}"
            ),
            GpuError::TooLarge { what, bytes, limit } => write!(
                f,
                "{what} take {bytes} bytes, more than the device's {limit} in one binding"
            ),
            GpuError::Query(e) => write!(f, "{e}"),
            GpuError::InvalidPoint { index } => write!(
                f,
                "shading point {index} has a non-finite position, normal or albedo"
            ),
            GpuError::Readback(why) => write!(f, "reading the GPU's results back failed: {why}"),
            GpuError::InvalidGrid => write!(
                f,
                "the GPU grid's box and level-1 spacing must be finite, the spacing positive"
            ),
            GpuError::Build(e) => write!(f, "{e}"),
            GpuError::BufferTooSmall {
                what,
                bytes,
                needed,
            } => write!(
                f,
                "the buffer of {what} has {bytes} bytes; the call needs {needed}"
            ),
            GpuError::InvalidK { k, most } => {
                write!(f, "the gather draws 1 to {most} lights a point, not {k}")
            }
        }
    }
}

impl std::error::Error for GpuError {}

impl From<lgh_core::BuildError> for GpuError {
    fn from(e: lgh_core::BuildError) -> Self {
        GpuError::Build(e)
    }
}

impl From<lgh_core::QueryError> for GpuError {
    fn from(e: lgh_core::QueryError) -> Self {
        GpuError::Query(e)
    }
}
