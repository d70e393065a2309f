//! The size limits every image obeys, apart from the image type and its errors (both name
//! them).

/// The largest image side, in pixels: a 16384² image of RGB floats takes 3 GiB.
pub const MAX_IMAGE_SIDE: usize = 16384;
