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

pub use camera::{CameraError, Pinhole};
pub use error::ImageError;

use std::io::{BufWriter, Read, Write};
use std::path::Path;

use lgh_core::glam::Vec3;
use lgh_core::luminance;
use lgh_core::metrics::ErrorStats;

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

/// The largest image side, in pixels: a 16384² image of RGB floats takes 3 GiB.
pub const MAX_IMAGE_SIDE: usize = 16384;

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

/// Input files (VDB caches, PLY point sets, OBJ and MTL files) larger than this are refused, by
/// [`read_limited`]: 8 GiB, a third of a 24 GiB machine.
pub const MAX_INPUT_BYTES: u64 = 8 << 30;

/// The bytes of the file at `path`, refused with an [`ErrorKind::FileTooLarge`] error if there
/// are more than `max_bytes`. The size a regular file reports refuses it before reading; what
/// reports none (a FIFO, a device) is read through `take(max_bytes + 1)`, so never past the limit.
///
/// [`ErrorKind::FileTooLarge`]: std::io::ErrorKind::FileTooLarge
pub fn read_limited(path: &Path, max_bytes: u64) -> std::io::Result<Vec<u8>> {
    let too_large = || {
        std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!("the file is larger than the limit of {max_bytes} bytes"),
        )
    };
    let file = std::fs::File::open(path)?;
    let size = file.metadata()?.len();
    if size > max_bytes {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0));
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}

/// Held by every [`write_atomic`] while its file is written, and by [`hold_writes`].
static WRITING: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Waits for the file [`write_atomic`] is writing, if any, and keeps any other write from
/// starting while the guard lives: a program that exits holding it (on SIGINT, say) leaves
/// neither a temporary file nor half a file behind. Writes from several threads also take
/// turns through it.
///
/// ```
/// let dir = tempfile::tempdir()?;
/// {
///     let _held = lgh_image::hold_writes();
///     // ... exiting here would leave every file whole.
/// }
/// lgh_image::write_atomic(&dir.path().join("a.txt"), |w| w.write_all(b"after"))?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn hold_writes() -> std::sync::MutexGuard<'static, ()> {
    WRITING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Writes `path` atomically: `write` fills a temporary file beside it, which replaces `path` only
/// if everything succeeded. On any error the temporary file is removed and `path` is untouched.
///
/// The file gets the permissions a plain [`File::create`](std::fs::File::create) would give it
/// (on Unix `0o666 & !umask`), not the temporary file's private `0o600`: frames written on a
/// render farm must be readable by the compositor's user.
///
/// Errors: [`ImageError::TempFile`] if the temporary file cannot be created,
/// [`ImageError::Write`] if `write`, the flush, the sync or the rename fails.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), ImageError> {
    let _writing = hold_writes();
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".lgh-").suffix(".tmp");
    // `open(2)` masks the mode with the umask, exactly as for a plain `File::create`.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let tmp = builder
        .tempfile_in(dir)
        .map_err(|source| ImageError::TempFile {
            dir: dir.to_path_buf(),
            source,
        })?;
    let write_error = |source| ImageError::Write {
        path: path.to_path_buf(),
        source,
    };
    {
        let mut w = BufWriter::new(tmp.as_file());
        write(&mut w).and_then(|_| w.flush()).map_err(write_error)?;
    }
    tmp.as_file().sync_all().map_err(write_error)?;
    tmp.persist(path).map_err(|e| write_error(e.error))?;
    Ok(())
}

/// Whether `image` may be written to `path`: [`ImageError::Empty`] if it has no pixels,
/// [`ImageError::NonFinite`] naming the first NaN or infinite pixel.
fn check_writable(path: &Path, image: &Image) -> Result<(), ImageError> {
    if image.width == 0 || image.height == 0 {
        return Err(ImageError::Empty {
            path: path.to_path_buf(),
        });
    }
    match first_non_finite(image) {
        Some((pixel, value)) => Err(ImageError::NonFinite {
            path: path.to_path_buf(),
            pixel,
            value,
        }),
        None => Ok(()),
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

/// An exposure for [`tonemap`] that puts the 99th percentile of the non-black pixels' luminance
/// at 4 (tone-mapped to 80% of white), so a few blazing pixels do not darken the whole image;
/// 1 for a black image.
#[must_use]
pub fn auto_exposure(image: &Image) -> f32 {
    let mut l: Vec<f32> = image
        .pixels
        .iter()
        .map(|&p| luminance(p))
        .filter(|&l| l > 0.0 && l.is_finite())
        .collect();
    if l.is_empty() {
        return 1.0;
    }
    let k = (l.len() - 1) * 99 / 100;
    let (_, p99, _) = l.select_nth_unstable_by(k, f32::total_cmp);
    4.0 / *p99
}

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
            |resolution, _| crate::Image::new(resolution.width(), resolution.height()),
            |img: &mut crate::Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
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

/// How [`tonemap_with`] compresses linear radiance (after the exposure) into display values
/// `0..=1`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ToneCurve {
    /// `v / (1 + L)` on luminance `L`: keeps every hue, never reaches white, flattens bright
    /// highlights (a luminance of 4 shows at 80%, 8 at 89%).
    #[default]
    Reinhard,
    /// [`filmic`] on each channel: a toe that deepens the shadows, a long shoulder that keeps
    /// the highlights apart and reaches white at [`FILMIC_WHITE`]; saturated colours desaturate
    /// towards white as they brighten, as film does with fire.
    Filmic,
}

/// The linear value that [`filmic`] maps to white (1).
pub const FILMIC_WHITE: f32 = 11.2;

/// The filmic shape before normalisation: a ratio of quadratics (J. Hable's form of a film
/// response: toe, near-linear middle, shoulder), `0` at `0`, strictly increasing for `x ≥ 0`.
fn filmic_shape(x: f32) -> f32 {
    // Shoulder strength, linear strength, linear angle, toe strength, toe numerator and
    // denominator.
    const SHOULDER: f32 = 0.15;
    const LINEAR: f32 = 0.5;
    const ANGLE: f32 = 0.1;
    const TOE: f32 = 0.2;
    const TOE_NUM: f32 = 0.02;
    const TOE_DEN: f32 = 0.3;
    (x * (SHOULDER * x + ANGLE * LINEAR) + TOE * TOE_NUM)
        / (x * (SHOULDER * x + LINEAR) + TOE * TOE_DEN)
        - TOE_NUM / TOE_DEN
}

/// The filmic tone curve of [`ToneCurve::Filmic`], linear `x ≥ 0` to a linear display value in
/// `0..=1`: `0 → 0`, increasing, `1` from [`FILMIC_WHITE`] on (negative and NaN input give 0).
/// Its middle is steeper than Reinhard's over the highlights a 99th-percentile exposure puts at
/// 2 to 8 ([`auto_exposure`]), so a fireball's core keeps its detail.
///
/// ```
/// use lgh_image::{filmic, FILMIC_WHITE};
///
/// assert_eq!(filmic(0.0), 0.0);
/// assert!(filmic(0.5) < filmic(1.0) && filmic(1.0) < filmic(4.0));
/// assert_eq!(filmic(FILMIC_WHITE), 1.0);
/// assert_eq!(filmic(1e6), 1.0);
/// ```
#[must_use]
pub fn filmic(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    (filmic_shape(x.min(FILMIC_WHITE)) / filmic_shape(FILMIC_WHITE)).min(1.0)
}

/// Linear to sRGB-encoded 8 bits, after multiplying by `exposure` and the Reinhard curve on
/// luminance (which keeps hue while compressing highlights): [`tonemap_with`] and
/// [`ToneCurve::Reinhard`].
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::tonemap;
///
/// assert_eq!(tonemap(Vec3::ZERO, 1.0), [0, 0, 0]);
/// // Grey stays grey; brighter is lighter but never clips to white.
/// let [r, g, b] = tonemap(Vec3::splat(0.5), 1.0);
/// assert!(r == g && g == b);
/// let [bright, ..] = tonemap(Vec3::splat(100.0), 1.0);
/// assert!(r < bright && bright < 255);
/// ```
#[must_use]
pub fn tonemap(v: Vec3, exposure: f32) -> [u8; 3] {
    tonemap_with(v, exposure, ToneCurve::Reinhard)
}

/// Linear to sRGB-encoded 8 bits: multiplies by `exposure`, compresses with `curve`, encodes
/// with the sRGB transfer function. Negative values are black.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{tonemap_with, ToneCurve};
///
/// let fire = Vec3::new(8.0, 3.0, 0.5);
/// let [r, g, b] = tonemap_with(fire, 1.0, ToneCurve::Filmic);
/// assert!(r > g && g > b);
/// // Exposure is a factor on the radiance, before the curve.
/// assert_eq!(tonemap_with(fire, 2.0, ToneCurve::Filmic), tonemap_with(fire * 2.0, 1.0, ToneCurve::Filmic));
/// // Filmic reaches white; Reinhard never does.
/// assert_eq!(tonemap_with(Vec3::splat(50.0), 1.0, ToneCurve::Filmic), [255; 3]);
/// assert!(tonemap_with(Vec3::splat(50.0), 1.0, ToneCurve::Reinhard)[0] < 255);
/// ```
#[must_use]
pub fn tonemap_with(v: Vec3, exposure: f32, curve: ToneCurve) -> [u8; 3] {
    let v = (v * exposure).max(Vec3::ZERO);
    let v = match curve {
        ToneCurve::Reinhard => {
            let l = luminance(v);
            if l > 0.0 {
                v * (1.0 / (1.0 + l))
            } else {
                v
            }
        }
        ToneCurve::Filmic => Vec3::new(filmic(v.x), filmic(v.y), filmic(v.z)),
    };
    let encode = |c: f32| {
        let c = c.clamp(0.0, 1.0);
        let s = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0 + 0.5) as u8
    };
    [encode(v.x), encode(v.y), encode(v.z)]
}

/// Encodes 8-bit sRGB `rgb` as PNG in memory, then writes it to `path` atomically.
fn write_png_rgb8(path: &Path, width: usize, height: usize, rgb: &[u8]) -> Result<(), ImageError> {
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

/// Writes a tone-mapped sRGB PNG (see [`tonemap`]) atomically: [`write_png_with`] and
/// [`ToneCurve::Reinhard`].
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

/// Compares `a` against the reference `r` on luminance (ARCHITECTURE.md, "Measuring": relative RMSE,
/// max and mean absolute error). `None` if their sizes differ or they are empty.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{compare, Image};
///
/// let mut r = Image::new(2, 2);
/// r.pixels.fill(Vec3::ONE);
/// let mut a = r.clone();
/// a.set(1, 0, Vec3::splat(3.0));
/// // One pixel of four off by 2: RMSE sqrt(4 / 4) = 1 over a mean of 1.
/// let s = compare(&a, &r).unwrap();
/// assert!((s.rel_rmse - 1.0).abs() < 1e-6);
/// assert!((s.max_abs - 2.0).abs() < 1e-6 && (s.mean_abs - 0.5).abs() < 1e-6);
/// assert!(compare(&a, &Image::new(4, 1)).is_none());
/// ```
#[must_use]
pub fn compare(a: &Image, r: &Image) -> Option<ErrorStats> {
    if (a.width, a.height) != (r.width, r.height) {
        return None;
    }
    ErrorStats::compare(&a.pixels, &r.pixels)
}

/// Temporal flicker of the sequence `a` against the reference sequence `r` (ARCHITECTURE.md,
/// "Measuring"): `mean_t mean_px |(A_t − R_t) − (A_{t−1} − R_{t−1})| / mean |R|` on luminance,
/// the change of the error from one frame to the next, so a constant bias does not flicker.
/// `None` with fewer than two frames, sequences or frames of different sizes, or a black
/// reference.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{flicker, Image};
///
/// let frame = |v: f32| Image { width: 2, height: 1, pixels: vec![Vec3::splat(v); 2] };
/// let r = [frame(1.0), frame(1.0), frame(1.0)];
/// // A constant bias: no flicker.
/// assert_eq!(flicker(&[frame(1.5), frame(1.5), frame(1.5)], &r), Some(0.0));
/// // An error that alternates by ±0.5: it changes by 1 every frame, over a mean of 1.
/// let f = flicker(&[frame(1.5), frame(0.5), frame(1.5)], &r).unwrap();
/// assert!((f - 1.0).abs() < 1e-6);
/// assert_eq!(flicker(&r[..1], &r[..1]), None);
/// ```
#[must_use]
pub fn flicker(a: &[Image], r: &[Image]) -> Option<f64> {
    let same = |x: &Image, y: &Image| (x.width, x.height) == (y.width, y.height);
    if a.len() != r.len() || a.len() < 2 || a.iter().chain(r).any(|i| !same(i, &r[0])) {
        return None;
    }
    let lum = |p: Vec3| f64::from(lgh_core::luminance(p));
    let pixels = r[0].pixels.len();
    let mean_r = r
        .iter()
        .flat_map(|i| i.pixels.iter())
        .map(|&p| lum(p).abs())
        .sum::<f64>()
        / (pixels * r.len()) as f64;
    if mean_r.is_nan() || mean_r <= 0.0 || pixels == 0 {
        return None;
    }
    let mut sum = 0.0;
    for t in 1..a.len() {
        let s: f64 = (0..pixels)
            .map(|i| {
                let e1 = lum(a[t].pixels[i]) - lum(r[t].pixels[i]);
                let e0 = lum(a[t - 1].pixels[i]) - lum(r[t - 1].pixels[i]);
                (e1 - e0).abs()
            })
            .sum();
        sum += s / pixels as f64;
    }
    Some(sum / (a.len() - 1) as f64 / mean_r)
}

/// The error of an image as an 8-bit display would show it (Paquette et al. §5.1): every channel
/// quantised linearly, `round(255 · clamp(v, 0, 1))`, no gamma — the scale on which their
/// threshold of 2.55 and their observed errors of (1, 1, 1) are stated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Error8Bit {
    /// The largest difference of any channel of any pixel, in levels of 255.
    pub max: u8,
    /// The mean difference over all channels of all pixels.
    pub mean: f64,
}

/// `v` quantised to 8 bits as [`Error8Bit`] does it.
#[must_use]
pub fn quantize_8bit(v: f32) -> u8 {
    // NaN goes to 0 (`as` saturates and maps NaN to 0).
    (255.0 * v.clamp(0.0, 1.0)).round() as u8
}

/// [`Error8Bit`] of `a` against `r`; `None` if their sizes differ or they are empty.
///
/// ```
/// use lgh_core::glam::Vec3;
/// use lgh_image::{error_8bit, Error8Bit, Image};
///
/// let r = Image::new(2, 1);
/// let mut a = r.clone();
/// // 2/255 in red is two levels; 10 is clamped to 1, so 255 levels in blue.
/// a.set(0, 0, Vec3::new(2.0 / 255.0, 0.0, 10.0));
/// assert_eq!(error_8bit(&a, &r), Some(Error8Bit { max: 255, mean: 257.0 / 6.0 }));
/// assert_eq!(error_8bit(&a, &Image::new(1, 2)), None);
/// ```
#[must_use]
pub fn error_8bit(a: &Image, r: &Image) -> Option<Error8Bit> {
    if (a.width, a.height) != (r.width, r.height) || a.pixels.is_empty() {
        return None;
    }
    let (mut max, mut sum) = (0u8, 0u64);
    for (p, q) in a.pixels.iter().zip(&r.pixels) {
        for c in 0..3 {
            let e = quantize_8bit(p[c]).abs_diff(quantize_8bit(q[c]));
            max = max.max(e);
            sum += u64::from(e);
        }
    }
    Some(Error8Bit {
        max,
        mean: sum as f64 / (3 * a.pixels.len()) as f64,
    })
}

/// A false-colour map of `|a − r|` on luminance: black for no error, through blue, green and
/// yellow to red at `max_error` and above. Written atomically.
///
/// Errors: [`ImageError::SizeMismatch`] if `a` and `r` differ in size, [`ImageError::EncodePng`],
/// and those of [`write_atomic`].
pub fn difference_png(path: &Path, a: &Image, r: &Image, max_error: f32) -> Result<(), ImageError> {
    if (a.width, a.height) != (r.width, r.height) {
        return Err(ImageError::SizeMismatch {
            image: (a.width, a.height),
            reference: (r.width, r.height),
        });
    }
    let ramp = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
    ];
    let rgb: Vec<u8> = a
        .pixels
        .iter()
        .zip(&r.pixels)
        .flat_map(|(&x, &y)| {
            let e = (luminance(x) - luminance(y)).abs();
            let t = if max_error > 0.0 {
                (e / max_error).clamp(0.0, 1.0)
            } else {
                0.0
            } * 4.0;
            let i = (t as usize).min(3);
            let c = ramp[i].lerp(ramp[i + 1], t - i as f32);
            [0, 1, 2].map(|k| (c[k] * 255.0 + 0.5) as u8)
        })
        .collect();
    write_png_rgb8(path, a.width, a.height, &rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gradient() -> Image {
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

    #[test]
    fn error_8bit_quantises_linearly_and_clamps() {
        let mut a = Image::new(2, 1);
        let mut r = Image::new(2, 1);
        // 0.5 → 128 (127.5 rounds away from zero), 0.5 + 1.4/255 → 129: one level apart.
        a.set(0, 0, Vec3::new(0.5, 0.0, 2.0));
        r.set(0, 0, Vec3::new(0.5 + 1.4 / 255.0, 0.0, 7.0));
        // Below zero and NaN both count as 0; 3/255 apart → 3 levels.
        a.set(1, 0, Vec3::new(-1.0, f32::NAN, 3.0 / 255.0));
        r.set(1, 0, Vec3::new(0.0, 0.0, 0.0));
        let e = error_8bit(&a, &r).unwrap();
        assert_eq!(e.max, 3);
        assert!((e.mean - 4.0 / 6.0).abs() < 1e-12);
        assert_eq!(error_8bit(&a, &Image::new(1, 2)), None);
    }

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

    /// The written file's mode is a plain `File::create`'s in the same folder under the same
    /// umask, whatever that umask is; the CLI tests pin it under umasks 022 and 027.
    #[cfg(unix)]
    #[test]
    fn written_files_get_the_permissions_of_a_plain_create() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let plain = dir.path().join("plain");
        std::fs::File::create(&plain).unwrap();
        let written = dir.path().join("written.png");
        write_png(&written, &gradient(), 1.0).unwrap();
        assert_eq!(mode(&written), mode(&plain));
        // Replacing a file gives it the same mode again, not the temporary file's 0600.
        write_png(&written, &gradient(), 2.0).unwrap();
        assert_eq!(mode(&written), mode(&plain));
    }

    #[test]
    fn auto_exposure_maps_the_99th_percentile_to_4() {
        let mut img = Image::new(100, 1);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            *p = Vec3::splat(i as f32);
        }
        // 99 non-black pixels of luminance 1..=99; the 99th percentile (index 97) is 98.
        assert!((auto_exposure(&img) - 4.0 / 98.0).abs() < 1e-6);
        assert_eq!(auto_exposure(&Image::new(3, 3)), 1.0);
    }

    #[test]
    fn tonemap_is_monotone_and_black_stays_black() {
        assert_eq!(tonemap(Vec3::ZERO, 1.0), [0, 0, 0]);
        let a = tonemap(Vec3::splat(0.2), 1.0);
        let b = tonemap(Vec3::splat(2.0), 1.0);
        assert!(a[0] < b[0] && b[0] < 255);
    }

    #[test]
    fn filmic_curve_is_monotone_from_black_to_white() {
        assert_eq!(filmic(0.0), 0.0);
        assert_eq!(filmic(-1.0), 0.0);
        assert_eq!(filmic(f32::NAN), 0.0);
        // Strictly increasing up to the white point, then exactly white.
        let mut last = 0.0;
        for i in 1..=11_200 {
            let y = filmic(i as f32 * 1e-3);
            assert!(y > last, "not increasing at {}", i as f32 * 1e-3);
            assert!(y <= 1.0);
            last = y;
        }
        assert_eq!(filmic(FILMIC_WHITE), 1.0);
        assert_eq!(filmic(f32::INFINITY), 1.0);
    }

    #[test]
    fn filmic_keeps_highlights_apart_and_scales_with_exposure() {
        // The highlights an automatic exposure puts at luminance 2 to 8: more distinct 8-bit
        // greys with the filmic curve than with Reinhard's.
        let levels = |curve| {
            let mut codes: Vec<u8> = (0..=600)
                .map(|i| tonemap_with(Vec3::splat(2.0 + i as f32 * 0.01), 1.0, curve)[0])
                .collect();
            codes.dedup();
            codes.len()
        };
        let (filmic_levels, reinhard_levels) =
            (levels(ToneCurve::Filmic), levels(ToneCurve::Reinhard));
        assert!(
            filmic_levels > reinhard_levels + 20,
            "{filmic_levels} vs {reinhard_levels}"
        );
        // Exposure multiplies the radiance before the curve.
        for v in [Vec3::new(0.3, 0.1, 0.02), Vec3::new(6.0, 2.5, 0.4)] {
            for e in [0.25f32, 1.0, 3.0] {
                let scaled = tonemap_with(v * e, 1.0, ToneCurve::Filmic);
                assert_eq!(tonemap_with(v, e, ToneCurve::Filmic), scaled);
            }
        }
        // Negative radiance is black; the old entry point is Reinhard.
        assert_eq!(
            tonemap_with(Vec3::splat(-2.0), 1.0, ToneCurve::Filmic),
            [0; 3]
        );
        assert_eq!(
            tonemap(Vec3::splat(0.7), 1.3),
            tonemap_with(Vec3::splat(0.7), 1.3, ToneCurve::Reinhard)
        );
    }

    #[test]
    fn read_limited_refuses_files_and_streams_past_the_limit() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("ten");
        std::fs::write(&p, b"0123456789").unwrap();
        assert_eq!(read_limited(&p, 10).unwrap(), b"0123456789");
        let e = read_limited(&p, 9).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
        assert!(
            e.to_string().contains("larger than the limit of 9 bytes"),
            "{e}"
        );
        let missing = read_limited(&dir.path().join("none"), 10).unwrap_err();
        assert_eq!(missing.kind(), std::io::ErrorKind::NotFound);
        // An endless stream whose metadata says 0 bytes: refused after max + 1 bytes.
        #[cfg(unix)]
        assert_eq!(
            read_limited(Path::new("/dev/zero"), 1000)
                .unwrap_err()
                .kind(),
            std::io::ErrorKind::FileTooLarge
        );
    }

    #[test]
    fn comparison_metrics() {
        let r = gradient();
        let mut a = r.clone();
        assert_eq!(compare(&a, &r).unwrap().rel_rmse, 0.0);
        a.pixels[5] += Vec3::ONE;
        let s = compare(&a, &r).unwrap();
        assert!((s.max_abs - 1.0).abs() < 1e-6);
        assert!(compare(&Image::new(3, 3), &r).is_none());
        let dir = tempfile::tempdir().unwrap();
        difference_png(&dir.path().join("d.png"), &a, &r, 1.0).unwrap();
    }
}
