//! # lgh-image — the images every lgh renderer writes
//!
//! One place for what the volume and surface renderers and the CLI share: an RGB float
//! [`Image`], atomic file writes ([`write_atomic`]), linear OpenEXR with the render settings as
//! header attributes ([`write_exr`], [`read_exr`]), a tone-mapped sRGB PNG to look at
//! ([`write_png`], or [`write_png_with`] a [`filmic`] curve), the comparison of two images on luminance ([`compare`], [`difference_png`]),
//! input files read up to a size limit ([`read_limited`]), and the pinhole camera the images
//! are seen through ([`Pinhole`], in [`camera`]). Everything that can fail for an image says
//! why with an [`ImageError`].
//!
//! ```
//! use lgh_core::glam::Vec3;
//! use lgh_image::{read_exr, read_exr_attributes, write_exr, write_png, Image};
//!
//! let dir = tempfile::tempdir()?;
//! let mut img = Image::new(64, 32);
//! img.set(10, 5, Vec3::new(1.0, 0.5, 0.25));
//! let exr = dir.path().join("out.exr");
//! write_exr(&exr, &img, &[("renderer".into(), "lgh".into())])?;
//! write_png(&dir.path().join("out.png"), &img, 1.0)?;
//!
//! // EXR is lossless: the same floats come back, and the attributes with them.
//! assert_eq!(read_exr(&exr)?, img);
//! assert_eq!(read_exr_attributes(&exr)?, [("renderer".to_string(), "lgh".to_string())]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod camera;
mod error;
mod exr_file;
mod files;
mod image;
mod limits;
mod metrics;
mod png_file;
mod tone;

pub use camera::{CameraError, Pinhole};
pub use error::ImageError;
pub use exr_file::{decode_exr, read_exr, read_exr_attributes, write_exr};
pub use files::{hold_writes, read_limited, write_atomic, WritesHeld, MAX_INPUT_BYTES};
pub use image::{check_image_size, first_non_finite, Image};
pub use limits::MAX_IMAGE_SIDE;
pub use metrics::{
    compare, compare_rgb, difference_png, error_8bit, flicker, point_errors, quantize_8bit,
    ChannelStats, Error8Bit, PointErrors,
};
pub use png_file::{write_png, write_png_with};
pub use tone::{
    auto_exposure, filmic, linear_to_srgb, srgb_to_linear, tonemap, tonemap_with, ToneCurve,
    FILMIC_WHITE,
};
