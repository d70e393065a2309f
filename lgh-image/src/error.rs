//! [`ImageError`], the one error type of lgh-image's image checks, reads and writes.

use std::fmt;
use std::path::PathBuf;

use crate::limits::MAX_IMAGE_SIDE;

/// Why an image could not be checked, read or written. Each variant carries the data of the
/// failure (the path, the sizes) and, where one exists, the underlying error as its
/// [`source`](std::error::Error::source).
#[derive(Debug)]
pub enum ImageError {
    /// An image side is outside 1 to [`MAX_IMAGE_SIDE`] pixels ([`check_image_size`]).
    ///
    /// [`check_image_size`]: crate::check_image_size
    Size {
        /// The width asked for.
        width: usize,
        /// The height asked for.
        height: usize,
    },
    /// An image without pixels cannot be written.
    Empty {
        /// The file it was to be written to.
        path: PathBuf,
    },
    /// An image holding a NaN or infinite pixel is never written: a file with one would poison
    /// every compositing step after it.
    NonFinite {
        /// The file it was to be written to.
        path: PathBuf,
        /// The first such pixel, `(x, y)`, in rows from the top.
        pixel: (usize, usize),
        /// Its value.
        value: lgh_core::glam::Vec3,
    },
    /// Two images compared pixel by pixel differ in size ([`difference_png`]).
    ///
    /// [`difference_png`]: crate::difference_png
    SizeMismatch {
        /// `(width, height)` of the image.
        image: (usize, usize),
        /// `(width, height)` of the reference.
        reference: (usize, usize),
    },
    /// The temporary file beside the target of an atomic write could not be created.
    TempFile {
        /// The folder it was to be created in.
        dir: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// Writing, syncing or renaming the file failed.
    Write {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The image could not be encoded as OpenEXR.
    EncodeExr {
        /// The file it was to be written to.
        path: PathBuf,
        /// What the encoder said.
        source: exr::error::Error,
    },
    /// The image could not be encoded as PNG.
    EncodePng {
        /// The file it was to be written to.
        path: PathBuf,
        /// What the encoder said.
        source: png::EncodingError,
    },
    /// An OpenEXR file could not be read or decoded.
    ReadExr {
        /// The file.
        path: PathBuf,
        /// What the decoder said.
        source: exr::error::Error,
    },
    /// An OpenEXR file has no header.
    NoHeader {
        /// The file.
        path: PathBuf,
    },
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageError::Size { width, height } => write!(
                f,
                "image size {width}x{height}: width and height must be 1 to {MAX_IMAGE_SIDE}"
            ),
            ImageError::Empty { path } => {
                write!(f, "cannot write {}: the image is empty", path.display())
            }
            ImageError::NonFinite { path, pixel, value } => write!(
                f,
                "cannot write {}: pixel ({}, {}) is {value}, not finite (the render overflowed, \
                 or its input holds non-finite values)",
                path.display(),
                pixel.0,
                pixel.1
            ),
            ImageError::SizeMismatch { .. } => write!(f, "the images differ in size"),
            ImageError::TempFile { dir, source } => write!(
                f,
                "cannot create a temporary file in {}: {}",
                dir.display(),
                system_reason(source)
            ),
            ImageError::Write { path, source } => {
                write!(f, "cannot write {}: {source}", path.display())
            }
            ImageError::EncodeExr { path, source } => {
                write!(f, "cannot encode {}: {source}", path.display())
            }
            // The wording of the PNG encoder's errors when they went through the file writer.
            ImageError::EncodePng { path, source } => {
                write!(f, "cannot write {}: {source}", path.display())
            }
            ImageError::ReadExr { path, source } => {
                write!(f, "cannot read {}: {source}", path.display())
            }
            ImageError::NoHeader { path } => write!(f, "{}: no header", path.display()),
        }
    }
}

/// What the system said, without the name of the temporary file `tempfile` adds to it (a file
/// that was never created means nothing to the reader).
fn system_reason(e: &std::io::Error) -> String {
    let text = e.to_string();
    match text.split_once(" at path \"") {
        Some((reason, _)) => reason.to_string(),
        None => text,
    }
}

impl std::error::Error for ImageError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ImageError::TempFile { source, .. } | ImageError::Write { source, .. } => Some(source),
            ImageError::EncodeExr { source, .. } | ImageError::ReadExr { source, .. } => {
                Some(source)
            }
            ImageError::EncodePng { source, .. } => Some(source),
            ImageError::Size { .. }
            | ImageError::Empty { .. }
            | ImageError::NonFinite { .. }
            | ImageError::SizeMismatch { .. }
            | ImageError::NoHeader { .. } => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error;

    #[test]
    fn messages_keep_their_wording_and_sources_are_the_underlying_errors() {
        let size = ImageError::Size {
            width: 0,
            height: 7,
        };
        assert_eq!(
            size.to_string(),
            format!("image size 0x7: width and height must be 1 to {MAX_IMAGE_SIDE}")
        );
        assert!(size.source().is_none());
        let write = ImageError::Write {
            path: "a/b.png".into(),
            source: std::io::Error::other("disk full"),
        };
        assert_eq!(write.to_string(), "cannot write a/b.png: disk full");
        assert_eq!(write.source().unwrap().to_string(), "disk full");
        let mismatch = ImageError::SizeMismatch {
            image: (2, 2),
            reference: (8, 4),
        };
        assert_eq!(mismatch.to_string(), "the images differ in size");
    }
}
