//! Typed errors of building and querying.

use core::fmt;

/// The most input lights a hierarchy takes: every level's vertices (at most eight per light) must
/// have 32-bit indices.
pub const MAX_LIGHTS: usize = (u32::MAX / 8) as usize;

/// Why a hierarchy (or a backend) could not be built from the given lights and settings.
#[derive(Clone, Debug, PartialEq)]
pub enum BuildError {
    /// Light `index` has a NaN or infinite position coordinate.
    NonFinitePosition {
        /** Index of the offending light. */
        index: usize,
    },
    /// Light `index` has a NaN or infinite intensity channel, or a negative luminance.
    InvalidIntensity {
        /** Index of the offending light. */
        index: usize,
    },
    /// Light `index` has a negative channel (a colour outside Rec. 709's gamut), which this
    /// backend does not take ([`Channels::NonNegative`](crate::Channels)).
    NegativeChannel {
        /** Index of the offending light. */
        index: usize,
    },
    /// The level-1 spacing `h1` is unusable: not finite and > 0, `h0 = h1 / 2` below the smallest
    /// normal f32, or the square of the coarsest level's spacing `h1·2^(ℓmax−1)` not finite in f32
    /// (lights spread over more than about 10^19 units).
    InvalidSpacing {
        /** The rejected spacing. */
        h1: f32,
    },
    /// The grid origin is not finite.
    NonFiniteOrigin,
    /// More levels were requested than the hierarchy supports.
    TooManyLevels {
        /** Requested `ℓ_max`. */
        requested: u8,
        /** Largest supported `ℓ_max`. */
        max: u8,
    },
    /// The lights lie too many level-1 cells from the given origin for f64 cell coordinates.
    OriginTooFar {
        /// Distance in level-1 cells.
        cells: f64,
    },
    /// The lights span more level-1 cells along one axis than the hierarchy can address.
    GridTooFine {
        /** Cells spanned. */
        cells: f64,
        /** Most cells per axis. */
        max: u32,
    },
    /// More lights than a 32-bit index can address.
    TooManyLights {
        /** Number of lights given. */
        count: usize,
    },
    /// The weak-light threshold is negative or not finite.
    InvalidThreshold {
        /** The rejected threshold. */
        threshold: f32,
    },
    /// A rebuild was given a different number of intensities than the hierarchy has lights.
    LengthMismatch {
        /** Lights in the hierarchy. */
        expected: usize,
        /** Intensities given. */
        got: usize,
    },
    /// Light-octree settings out of range: `max_leaf` must be at least 1 and `max_depth` at most
    /// `max` (the octree's `MAX_OCTREE_DEPTH`).
    InvalidOctreeSettings {
        /** The rejected `max_leaf`. */
        max_leaf: usize,
        /** The rejected `max_depth`. */
        max_depth: u8,
        /** The deepest `max_depth` allowed. */
        max: u8,
    },
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BuildError::NonFinitePosition { index } => {
                write!(f, "light {index} has a non-finite position")
            }
            BuildError::InvalidIntensity { index } => write!(
                f,
                "light {index} has a non-finite intensity or a negative luminance (intensities are W/sr, their luminance ≥ 0)"
            ),
            BuildError::NegativeChannel { index } => write!(
                f,
                "light {index} has a negative colour channel, which the light octree and Lightcuts do not take (their bounds assume channels ≥ 0); the hierarchy and brute force do"
            ),
            BuildError::InvalidSpacing { h1 } => write!(
                f,
                "grid spacing h1 = {h1} is unusable: it must be > 0 with h1/2 a normal f32 and (h1·2^(ℓmax−1))² finite in f32"
            ),
            BuildError::OriginTooFar { cells } => write!(
                f,
                "the lights lie {cells:.3e} level-1 cells from the grid origin (at most 2^29); move the origin closer"
            ),
            BuildError::NonFiniteOrigin => write!(f, "grid origin must be finite"),
            BuildError::TooManyLevels { requested, max } => write!(
                f,
                "{requested} levels requested; at most {max} are supported"
            ),
            BuildError::GridTooFine { cells, max } => write!(
                f,
                "the lights span {cells:.3e} level-1 cells along one axis (at most {max}); use a larger h1"
            ),
            BuildError::TooManyLights { count } => {
                write!(f, "{count} lights exceed the limit of {MAX_LIGHTS}")
            }
            BuildError::InvalidThreshold { threshold } => write!(
                f,
                "weak-light threshold {threshold} must be finite and ≥ 0"
            ),
            BuildError::LengthMismatch { expected, got } => write!(
                f,
                "expected {expected} intensities (one per light), got {got}"
            ),
            BuildError::InvalidOctreeSettings {
                max_leaf,
                max_depth,
                max,
            } => write!(
                f,
                "light octree: max_leaf {max_leaf} must be ≥ 1 and max_depth {max_depth} ≤ {max}"
            ),
        }
    }
}

impl core::error::Error for BuildError {}

/// Why a query could not run.
#[derive(Clone, Debug, PartialEq)]
pub enum QueryError {
    /// α is not a finite number > 0 (or makes a radius overflow).
    InvalidAlpha {
        /** The rejected α. */
        alpha: f32,
    },
    /// The shading point has a NaN or infinite coordinate.
    NonFinitePoint,
    /// The [`Blending`](crate::Blending) was made for another hierarchy (other `h1` or `ℓ_max`).
    BlendingMismatch,
    /// An error threshold (the octree's and Ward's absolute `T`, Lightcuts' relative ε) is not a
    /// finite number > 0.
    InvalidThreshold {
        /** The rejected threshold. */
        threshold: f32,
    },
    /// A surface material without a finite unit normal, or a specular one without a unit view
    /// direction: the error-bounded backends cannot bound eq. (1) there.
    InvalidSurface,
}

impl QueryError {
    /// `x` if every coordinate is finite, [`QueryError::NonFinitePoint`] otherwise: the one check
    /// every query makes of its point.
    pub fn check_point(x: glam::Vec3) -> Result<glam::Vec3, QueryError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(QueryError::NonFinitePoint)
        }
    }

    /// `threshold` if it is a finite number > 0, the error otherwise: the one rule for the
    /// octree's and Ward's absolute `T` and Lightcuts' relative ε.
    pub fn check_threshold(threshold: f32) -> Result<f32, QueryError> {
        if threshold.is_finite() && threshold > 0.0 {
            Ok(threshold)
        } else {
            Err(QueryError::InvalidThreshold { threshold })
        }
    }
}

impl fmt::Display for QueryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            QueryError::InvalidAlpha { alpha } => {
                write!(f, "alpha = {alpha} must be a finite number > 0")
            }
            QueryError::NonFinitePoint => write!(f, "shading point is not finite"),
            QueryError::BlendingMismatch => write!(
                f,
                "blending parameters were made for a hierarchy with another h1 or level count"
            ),
            QueryError::InvalidThreshold { threshold } => write!(
                f,
                "error threshold {threshold} must be a finite number > 0"
            ),
            QueryError::InvalidSurface => write!(
                f,
                "a surface point needs a finite unit normal (and a unit view direction for a specular material)"
            ),
        }
    }
}

impl core::error::Error for QueryError {}
