//! The linear RGB [`Image`] every renderer fills, and the sizes an image may have.

use lgh_core::glam::Vec3;

use crate::error::ImageError;
use crate::limits::MAX_IMAGE_SIDE;

/// A linear RGB image, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width × height` pixels.
    pub pixels: Vec<Vec3>,
}

impl Image {
    /// A black image.
    #[must_use]
    pub fn new(width: usize, height: usize) -> Self {
        Image {
            width,
            height,
            pixels: vec![Vec3::ZERO; width * height],
        }
    }

    /// Pixel `(x, y)`.
    #[must_use]
    pub fn get(&self, x: usize, y: usize) -> Vec3 {
        self.pixels[y * self.width + x]
    }

    /// Sets pixel `(x, y)`.
    pub fn set(&mut self, x: usize, y: usize, v: Vec3) {
        self.pixels[y * self.width + x] = v;
    }
}

/// Checks an image size: 1 to [`MAX_IMAGE_SIDE`] pixels per side, else [`ImageError::Size`].
///
/// ```
/// use lgh_image::{check_image_size, ImageError, MAX_IMAGE_SIDE};
///
/// assert!(check_image_size(640, 480).is_ok());
/// let e = check_image_size(0, 480).unwrap_err();
/// assert!(matches!(e, ImageError::Size { width: 0, height: 480 }));
/// assert_eq!(
///     e.to_string(),
///     format!("image size 0x480: width and height must be 1 to {MAX_IMAGE_SIDE}")
/// );
/// ```
pub fn check_image_size(width: usize, height: usize) -> Result<(), ImageError> {
    let ok = |n: usize| (1..=MAX_IMAGE_SIDE).contains(&n);
    if ok(width) && ok(height) {
        Ok(())
    } else {
        Err(ImageError::Size { width, height })
    }
}

/// The first pixel, in reading order, holding a NaN or an infinity: `((x, y), value)`.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{first_non_finite, Image};
///
/// let mut img = Image::new(3, 2);
/// assert_eq!(first_non_finite(&img), None);
/// img.set(2, 1, Vec3::new(f32::INFINITY, 0.0, 0.0));
/// assert_eq!(first_non_finite(&img), Some(((2, 1), Vec3::new(f32::INFINITY, 0.0, 0.0))));
/// ```
#[must_use]
pub fn first_non_finite(image: &Image) -> Option<((usize, usize), Vec3)> {
    let i = image.pixels.iter().position(|p| !p.is_finite())?;
    Some(((i % image.width, i / image.width), image.pixels[i]))
}

/// A test image with a different value in every pixel and channel, 37 × 21, for the unit tests
/// of the modules that write, read and compare images.
#[cfg(test)]
pub(crate) fn gradient() -> Image {
    let mut img = Image::new(37, 21);
    for y in 0..21 {
        for x in 0..37 {
            img.set(
                x,
                y,
                Vec3::new(x as f32 * 0.1, y as f32 * 3.7, 1e-3 * (x * y) as f32),
            );
        }
    }
    img
}
