//! Tone-mapped sRGB PNG files to look at ([`write_png`], [`write_png_with`]), written
//! atomically.

use std::path::Path;

use crate::error::ImageError;
use crate::files::{check_writable, write_atomic};
use crate::image::Image;
use crate::tone::{tonemap_with, ToneCurve};

/// Encodes 8-bit sRGB `rgb` as PNG in memory, then writes it to `path` atomically.
pub(crate) fn write_png_rgb8(
    path: &Path,
    width: usize,
    height: usize,
    rgb: &[u8],
) -> Result<(), ImageError> {
    let mut bytes = Vec::new();
    let encode = |bytes: &mut Vec<u8>| -> Result<(), png::EncodingError> {
        let mut enc = png::Encoder::new(bytes, width as u32, height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = enc.write_header()?;
        writer.write_image_data(rgb)?;
        writer.finish()
    };
    encode(&mut bytes).map_err(|source| ImageError::EncodePng {
        path: path.to_path_buf(),
        source,
    })?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// Writes a tone-mapped sRGB PNG (see [`tonemap`](crate::tonemap)) atomically:
/// [`write_png_with`] and [`ToneCurve::Reinhard`].
///
/// Errors: [`ImageError::Empty`] for an image without pixels, [`ImageError::NonFinite`] for one
/// holding a NaN or infinite pixel (nothing is written), [`ImageError::EncodePng`], and those of
/// [`write_atomic`].
pub fn write_png(path: &Path, image: &Image, exposure: f32) -> Result<(), ImageError> {
    write_png_with(path, image, exposure, ToneCurve::Reinhard)
}

/// Writes an sRGB PNG tone-mapped with `curve` at `exposure` (see [`tonemap_with`]) atomically.
///
/// Errors: those of [`write_png`].
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{auto_exposure, write_png_with, Image, ToneCurve};
///
/// let dir = tempfile::tempdir()?;
/// let mut img = Image::new(8, 8);
/// img.pixels.fill(Vec3::new(4.0, 1.5, 0.2));
/// let path = dir.path().join("fire.png");
/// write_png_with(&path, &img, auto_exposure(&img), ToneCurve::Filmic)?;
/// assert!(path.is_file());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_png_with(
    path: &Path,
    image: &Image,
    exposure: f32,
    curve: ToneCurve,
) -> Result<(), ImageError> {
    check_writable(path, image)?;
    let rgb: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|&v| tonemap_with(v, exposure, curve))
        .collect();
    write_png_rgb8(path, image.width, image.height, &rgb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::gradient;
    use lgh_core::glam::Vec3;

    #[test]
    fn png_is_valid_and_failures_leave_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.png");
        write_png(&p, &gradient(), 1.0).unwrap();
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&p).unwrap()));
        let reader = decoder.read_info().unwrap();
        assert_eq!((reader.info().width, reader.info().height), (37, 21));
        // A failing writer leaves neither the target nor a temporary file.
        let q = dir.path().join("b.png");
        assert!(write_atomic(&q, |_| Err(std::io::Error::other("boom"))).is_err());
        assert!(!q.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        assert!(write_png(&q, &Image::new(0, 0), 1.0).is_err());
        // An infinite pixel: a one-line error naming it, and nothing written.
        let mut inf = gradient();
        inf.set(36, 20, Vec3::new(f32::INFINITY, 0.0, 0.0));
        inf.set(5, 20, Vec3::new(0.0, 0.0, f32::NEG_INFINITY));
        let e = write_png(&q, &inf, 1.0).unwrap_err();
        assert!(
            e.to_string().starts_with(&format!(
                "cannot write {}: pixel (5, 20) is [0, 0, -inf], not finite",
                q.display()
            )),
            "{e}"
        );
        assert!(!q.exists());
    }
}
