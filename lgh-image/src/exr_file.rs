//! Linear OpenEXR files: float RGB, ZIP-compressed (lossless), with the render settings as text
//! attributes in the header ([`write_exr`], [`read_exr`], [`read_exr_attributes`]), and the
//! decoding of untrusted bytes with every size checked before it is allocated ([`decode_exr`]).

use std::path::Path;

use lgh_core::glam::Vec3;

use crate::error::ImageError;
use crate::files::{check_writable, read_limited, write_atomic, MAX_INPUT_BYTES};
use crate::image::{check_image_size, Image};

/// Writes a linear float RGB OpenEXR (ZIP-compressed, lossless) with `attributes` as text
/// attributes in its header, atomically ([`write_atomic`]).
///
/// Errors: [`ImageError::Empty`] for an image without pixels, [`ImageError::NonFinite`] for one
/// holding a NaN or infinite pixel (nothing is written), [`ImageError::EncodeExr`], and those of
/// [`write_atomic`].
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{read_exr, write_exr, Image, ImageError};
///
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("black.exr");
/// write_exr(&path, &Image::new(4, 2), &[])?;
/// assert_eq!(read_exr(&path)?, Image::new(4, 2));
/// // Nothing is written for an empty image.
/// let empty = dir.path().join("empty.exr");
/// let e = write_exr(&empty, &Image::new(0, 0), &[]).unwrap_err();
/// assert!(matches!(e, ImageError::Empty { .. }));
/// assert!(!empty.exists());
/// // Nor for one holding a NaN: the error names the first such pixel.
/// let mut nan = Image::new(4, 2);
/// nan.set(3, 1, Vec3::new(0.0, f32::NAN, 1.0));
/// let e = write_exr(&path, &nan, &[]).unwrap_err();
/// assert!(matches!(e, ImageError::NonFinite { pixel: (3, 1), .. }));
/// assert_eq!(read_exr(&path)?, Image::new(4, 2)); // the file before is untouched
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_exr(
    path: &Path,
    image: &Image,
    attributes: &[(String, String)],
) -> Result<(), ImageError> {
    use exr::meta::attribute::{AttributeValue, Text};
    use exr::prelude::*;
    check_writable(path, image)?;
    let mut layer_attributes = LayerAttributes::named("rgb");
    layer_attributes.software_name = Some(Text::from("lgh"));
    for (k, v) in attributes {
        layer_attributes.other.insert(
            Text::from(k.as_str()),
            AttributeValue::Text(Text::from(v.as_str())),
        );
    }
    let layer = Layer::new(
        (image.width, image.height),
        layer_attributes,
        Encoding::SMALL_LOSSLESS,
        SpecificChannels::rgb(|p: Vec2<usize>| {
            let v = image.get(p.x(), p.y());
            (v.x, v.y, v.z)
        }),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|source| ImageError::EncodeExr {
            path: path.to_path_buf(),
            source,
        })?;
    write_atomic(path, |w| w.write_all(bytes.get_ref()))
}

/// Reads the RGB channels of an OpenEXR file (first layer; missing channels are zero).
///
/// Errors: [`ImageError::ReadExr`], whose [`source`](std::error::Error::source) is the
/// decoder's error.
///
/// ```
/// use std::error::Error;
/// use lgh_image::{read_exr, ImageError};
///
/// let dir = tempfile::tempdir()?;
/// let e = read_exr(&dir.path().join("missing.exr")).unwrap_err();
/// assert!(matches!(e, ImageError::ReadExr { .. }));
/// assert!(e.to_string().starts_with("cannot read "));
/// assert!(e.source().is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_exr(path: &Path) -> Result<Image, ImageError> {
    let bytes = read_limited(path, MAX_INPUT_BYTES)
        .map_err(|e| read_exr_error(path, exr::error::Error::Io(e)))?;
    decode_exr(path, &bytes)
}

/// [`read_exr`] of a file's `bytes` already in memory, named `path` in errors: what the fuzz
/// target `exr` drives. The size the header declares, and its tile size, are checked
/// ([`check_image_size`]) before anything is allocated for the pixels, and the file is read
/// strictly (exr's "pedantic" mode: the first broken block is an error; leniently, a corrupt
/// file of a few hundred bytes kept the decoder busy for seconds over gigabytes).
///
/// ```
/// use lgh_image::{decode_exr, ImageError};
/// use std::path::Path;
///
/// let e = decode_exr(Path::new("junk.exr"), b"not an exr").unwrap_err();
/// assert!(matches!(e, ImageError::ReadExr { .. }));
/// ```
pub fn decode_exr(path: &Path, bytes: &[u8]) -> Result<Image, ImageError> {
    use exr::prelude::*;
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), true)
        .map_err(|source| read_exr_error(path, source))?;
    // Every chunk of pixels takes at least 16 bytes (its offset, its row and its size): a file
    // too short for that many chunks is truncated, and refusing it ties what is allocated for
    // it to its length (found by fuzzing: 384 bytes declaring 16257×16289 pixels, 3 GB).
    let chunks: usize = meta.headers.iter().map(|h| h.chunk_count).sum();
    if chunks.saturating_mul(16) > bytes.len() {
        return Err(read_exr_error(
            path,
            exr::error::Error::Invalid(
                "the file is too short for the pixel chunks it declares".into(),
            ),
        ));
    }
    for header in &meta.headers {
        check_image_size(header.layer_size.width(), header.layer_size.height())?;
        // A tile larger than the largest image is a lie whose buffers would take gigabytes
        // (found by fuzzing: a 567-byte file of 8×6 pixels in tiles of 4×453,050,624).
        if let exr::meta::BlockDescription::Tiles(t) = &header.blocks {
            let (w, h) = (t.tile_size.width(), t.tile_size.height());
            if check_image_size(w, h).is_err() {
                return Err(read_exr_error(
                    path,
                    exr::error::Error::Invalid("tile size larger than any image lgh reads".into()),
                ));
            }
        }
    }
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| crate::image::Image::new(resolution.width(), resolution.height()),
            |img: &mut crate::image::Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                img.set(pos.x(), pos.y(), Vec3::new(r, g, b))
            },
        )
        .first_valid_layer()
        .all_attributes()
        .pedantic()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|source| read_exr_error(path, source))?;
    Ok(img.layer_data.channel_data.pixels)
}

fn read_exr_error(path: &Path, source: exr::error::Error) -> ImageError {
    ImageError::ReadExr {
        path: path.to_path_buf(),
        source,
    }
}

/// The text attributes of an OpenEXR file's first header (what [`write_exr`] stored), sorted by
/// name.
///
/// Errors: [`ImageError::ReadExr`], [`ImageError::NoHeader`].
pub fn read_exr_attributes(path: &Path) -> Result<Vec<(String, String)>, ImageError> {
    use exr::meta::attribute::AttributeValue;
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|source| read_exr_error(path, source))?;
    let header = meta.headers.first().ok_or_else(|| ImageError::NoHeader {
        path: path.to_path_buf(),
    })?;
    let mut out: Vec<(String, String)> = header
        .own_attributes
        .other
        .iter()
        .chain(&header.shared_attributes.other)
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((k.to_string(), t.to_string())),
            _ => None,
        })
        .collect();
    out.sort();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::gradient;

    #[test]
    fn exr_round_trip_is_exact_and_keeps_attributes() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.exr");
        let img = gradient();
        write_exr(&p, &img, &[("alpha".into(), "2".into())]).unwrap();
        assert_eq!(read_exr(&p).unwrap(), img);
        let attrs = read_exr_attributes(&p).unwrap();
        assert_eq!(attrs, [("alpha".to_string(), "2".to_string())]);
    }
}
