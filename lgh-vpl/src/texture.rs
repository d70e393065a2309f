//! Texture maps of materials (MTL `map_Kd`): an image of linear RGB texels looked up at a
//! surface point's texture coordinates `(u, v)` with bilinear filtering.
//!
//! Conventions, those of Wavefront OBJ: `v = 0` is the image's bottom row and `v = 1` its top;
//! coordinates outside `[0, 1]` repeat the image (a tiling texture: `u = 1.25` reads what
//! `u = 0.25` reads). Texel `(i, j)` has its centre at `((i + ½)/w, 1 − (j + ½)/h)`. The 8- and
//! 16-bit values of PNG, JPEG and TGA files are sRGB-encoded colours, decoded to linear RGB with
//! the sRGB transfer function (IEC 61966-2-1) once, when the texture is read.

use std::fmt;

use lgh_core::glam::{Vec2, Vec3};

/// The widest or tallest texture read: 16,384 texels (the largest texture of real-time
/// engines; a 16K² texture is 3 GiB of linear RGB floats).
pub const MAX_TEXTURE_SIDE: u32 = 16_384;

/// The most memory a texture's file may decode to before it becomes texels: 1 GiB (a 16K²
/// 8-bit RGB or RGBA image fits; a 16-bit RGBA one of that size does not).
pub const MAX_DECODED_BYTES: u64 = 1 << 30;

/// A texture: `width × height` linear RGB texels, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
}

/// Why a texture could not be made or read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TextureError {
    /// The bytes are not a PNG, JPEG or TGA image, or are a damaged one.
    NotAnImage(String),
    /// Wider or taller than [`MAX_TEXTURE_SIDE`], or decoding to more than
    /// [`MAX_DECODED_BYTES`].
    TooLarge {
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
    },
    /// No texel, or texels that do not fill `width × height`, or one that is negative or not
    /// finite.
    Invalid(&'static str),
}

impl fmt::Display for TextureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TextureError::NotAnImage(why) => {
                write!(
                    f,
                    "not a PNG, JPEG or TGA image this reader can decode ({why})"
                )
            }
            TextureError::TooLarge { width, height } => write!(
                f,
                "{width}×{height} texels: larger than a texture may be ({MAX_TEXTURE_SIDE} a \
                 side, {MAX_DECODED_BYTES} bytes decoded)"
            ),
            TextureError::Invalid(why) => f.write_str(why),
        }
    }
}

impl std::error::Error for TextureError {}

impl Texture {
    /// A texture of `width × height` linear RGB texels, rows from the top.
    ///
    /// Errors: [`TextureError::Invalid`] if a side is zero, `texels` is not `width × height`
    /// long, or a texel is negative or not finite; [`TextureError::TooLarge`] past
    /// [`MAX_TEXTURE_SIDE`].
    ///
    /// ```
    /// use lgh_core::glam::{Vec2, Vec3};
    /// use lgh_vpl::texture::Texture;
    ///
    /// // Two texels side by side: black on the left, white on the right.
    /// let t = Texture::from_linear(2, 1, vec![Vec3::ZERO, Vec3::ONE])?;
    /// assert_eq!(t.sample(Vec2::new(0.25, 0.5)), Vec3::ZERO); // the left texel's centre
    /// assert_eq!(t.sample(Vec2::new(0.5, 0.5)), Vec3::splat(0.5)); // half way between
    /// assert!(Texture::from_linear(2, 1, vec![Vec3::ONE]).is_err());
    /// # Ok::<(), lgh_vpl::texture::TextureError>(())
    /// ```
    pub fn from_linear(
        width: usize,
        height: usize,
        texels: Vec<Vec3>,
    ) -> Result<Texture, TextureError> {
        let side = MAX_TEXTURE_SIDE as usize;
        if width > side || height > side {
            return Err(TextureError::TooLarge {
                width: width.min(u32::MAX as usize) as u32,
                height: height.min(u32::MAX as usize) as u32,
            });
        }
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err(TextureError::Invalid(
                "a texture needs width × height texels, and at least one",
            ));
        }
        if !texels
            .iter()
            .all(|t| t.is_finite() && t.min_element() >= 0.0)
        {
            return Err(TextureError::Invalid(
                "texels must be finite and not negative",
            ));
        }
        Ok(Texture {
            width,
            height,
            texels,
        })
    }

    /// Decodes a PNG, JPEG or TGA file's `bytes` (the format found from the bytes, not a file
    /// name), sRGB-encoded values decoded to linear RGB; an alpha channel is dropped.
    ///
    /// Errors: [`TextureError::NotAnImage`] for anything else or a damaged file,
    /// [`TextureError::TooLarge`] for a side over [`MAX_TEXTURE_SIDE`] (refused from the
    /// header, before the texels are decoded) or an image that decodes to more than
    /// [`MAX_DECODED_BYTES`].
    ///
    /// ```
    /// use lgh_vpl::texture::{Texture, TextureError};
    ///
    /// let e = Texture::decode(b"newmtl grey\nKd 0.5 0.5 0.5\n").unwrap_err();
    /// assert!(matches!(e, TextureError::NotAnImage(_)));
    /// ```
    pub fn decode(bytes: &[u8]) -> Result<Texture, TextureError> {
        let image = decode_image(bytes)?.to_rgb32f();
        let texels = image
            .pixels()
            .map(|p| Vec3::from(p.0).map(lgh_image::srgb_to_linear))
            .collect();
        Texture::from_linear(image.width() as usize, image.height() as usize, texels)
    }

    /// Decodes a coverage map's `bytes` (MTL `map_d`, [`Mesh::covers`](crate::Mesh::covers)):
    /// each texel's alpha where the image has an alpha channel, its first channel otherwise,
    /// as stored (a coverage is a fraction, not an sRGB colour), in every component.
    ///
    /// Errors: as [`decode`](Self::decode).
    ///
    /// ```
    /// use lgh_core::glam::{Vec2, Vec3};
    /// use lgh_vpl::texture::Texture;
    ///
    /// // A 2×1 grey PNG: 0 on the left, 255 on the right.
    /// let mut png = Vec::new();
    /// image::GrayImage::from_raw(2, 1, vec![0, 255]).unwrap()
    ///     .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
    /// let t = Texture::decode_coverage(&png)?;
    /// assert_eq!(t.sample(Vec2::new(0.25, 0.5)), Vec3::ZERO);
    /// assert_eq!(t.sample(Vec2::new(0.75, 0.5)), Vec3::ONE);
    /// # Ok::<(), lgh_vpl::texture::TextureError>(())
    /// ```
    pub fn decode_coverage(bytes: &[u8]) -> Result<Texture, TextureError> {
        let image = decode_image(bytes)?;
        let alpha = image.color().has_alpha();
        let image = image.to_rgba32f();
        let texels = image
            .pixels()
            .map(|p| Vec3::splat(if alpha { p.0[3] } else { p.0[0] }))
            .collect();
        Texture::from_linear(image.width() as usize, image.height() as usize, texels)
    }

    /// Width in texels.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in texels.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// Texel `(i, j)`: column `i` from the left, row `j` from the top (panics out of range).
    #[must_use]
    pub fn texel(&self, i: usize, j: usize) -> Vec3 {
        assert!(
            i < self.width && j < self.height,
            "texel ({i}, {j}) is outside"
        );
        self.texels[j * self.width + i]
    }

    /// The bilinearly filtered colour at texture coordinates `uv`, repeating outside `[0, 1]`
    /// (module docs). A coordinate that is not finite reads texel `(0, 0)`'s row or column.
    #[must_use]
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        // Continuous texel coordinates, texel centres at integers.
        let x = uv.x * self.width as f32 - 0.5;
        let y = (1.0 - uv.y) * self.height as f32 - 0.5;
        let (fx, fy) = (x.floor(), y.floor());
        let (tx, ty) = (x - fx, y - fy);
        let wrap = |k: f32, n: usize| -> usize {
            // rem_euclid of a finite float is in [0, n); NaN and ±∞ become 0.
            let r = k.rem_euclid(n as f32);
            if r.is_finite() {
                (r as usize).min(n - 1)
            } else {
                0
            }
        };
        let (i0, j0) = (wrap(fx, self.width), wrap(fy, self.height));
        let (i1, j1) = ((i0 + 1) % self.width, (j0 + 1) % self.height);
        let (tx, ty) = (finite_or_zero(tx), finite_or_zero(ty));
        let row = |j: usize| self.texel(i0, j) * (1.0 - tx) + self.texel(i1, j) * tx;
        row(j0) * (1.0 - ty) + row(j1) * ty
    }
}

/// `t`, or zero where it is not finite.
fn finite_or_zero(t: f32) -> f32 {
    if t.is_finite() {
        t
    } else {
        0.0
    }
}

/// A PNG, JPEG or TGA file's `bytes` decoded (the format found from the bytes), within
/// [`MAX_TEXTURE_SIDE`] and [`MAX_DECODED_BYTES`] ([`Texture::decode`]'s errors).
fn decode_image(bytes: &[u8]) -> Result<image::DynamicImage, TextureError> {
    use image::{ImageFormat, ImageReader, Limits};
    let not_image = |e: &dyn fmt::Display| TextureError::NotAnImage(e.to_string());
    let reader = || -> Result<ImageReader<_>, TextureError> {
        let mut reader = ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| not_image(&e))?;
        match reader.format() {
            Some(ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::Tga) => Ok(reader),
            // TGA has no signature to guess it by; try it last.
            None => {
                reader.set_format(ImageFormat::Tga);
                Ok(reader)
            }
            Some(other) => Err(TextureError::NotAnImage(format!(
                "{other:?} is not one of PNG, JPEG and TGA"
            ))),
        }
    };
    let (width, height) = reader()?.into_dimensions().map_err(|e| not_image(&e))?;
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(TextureError::TooLarge { width, height });
    }
    let mut reader = reader()?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(MAX_DECODED_BYTES);
    reader.limits(limits);
    reader.decode().map_err(|e| match e {
        image::ImageError::Limits(_) => TextureError::TooLarge { width, height },
        e => not_image(&e),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 × 2 texture whose texel `(i, j)` is `(i, j, 1)`.
    fn ramp() -> Texture {
        let texels = (0..2)
            .flat_map(|j| (0..4).map(move |i| Vec3::new(i as f32, j as f32, 1.0)))
            .collect();
        Texture::from_linear(4, 2, texels).unwrap()
    }

    #[test]
    fn bilinear_lookup_is_linear_between_texel_centres_and_repeats() {
        let t = ramp();
        // Texel centres: u = (i + ½)/4, v = 1 − (j + ½)/2.
        for (i, j) in [(0, 0), (1, 0), (3, 1), (2, 1)] {
            let uv = Vec2::new((i as f32 + 0.5) / 4.0, 1.0 - (j as f32 + 0.5) / 2.0);
            assert_eq!(t.sample(uv), t.texel(i, j), "texel ({i}, {j})");
        }
        // Between the centres of columns 1 and 2 at a third of the way: x = 1⅓.
        let uv = Vec2::new((1.0 + 1.0 / 3.0 + 0.5) / 4.0, 0.75);
        let got = t.sample(uv);
        assert!(
            (got - Vec3::new(4.0 / 3.0, 0.0, 1.0)).length() < 1e-5,
            "{got}"
        );
        // Repeat: one period off in u and in v reads the same (up to the float rounding of uv).
        for uv in [Vec2::new(0.3, 0.4), Vec2::new(0.9, 0.1)] {
            for shift in [Vec2::new(1.0, 0.0), Vec2::new(-2.0, 3.0)] {
                let (a, b) = (t.sample(uv), t.sample(uv + shift));
                assert!((a - b).length() < 1e-5, "{uv} + {shift}: {a} vs {b}");
            }
        }
        // Across the seam: u = 0 is half way between the last column's centre and the first's.
        assert!((t.sample(Vec2::new(0.0, 0.75)).x - 1.5).abs() < 1e-6);
        // Not finite: still a texel of the image, never a panic.
        for uv in [Vec2::NAN, Vec2::new(f32::INFINITY, 0.5), Vec2::splat(1e30)] {
            assert!(t.sample(uv).is_finite(), "{uv}");
        }
    }

    #[test]
    fn png_files_decode_to_linear_texels_and_bad_ones_are_errors() {
        // A 2 × 1 8-bit sRGB PNG: mid grey (128) and white.
        let mut bytes = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut bytes, 2, 1);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut w = encoder.write_header().unwrap();
            w.write_image_data(&[128, 128, 128, 255, 255, 255]).unwrap();
        }
        let t = Texture::decode(&bytes).unwrap();
        assert_eq!((t.width(), t.height()), (2, 1));
        // sRGB 128/255 is 0.2158605 linear.
        assert!(
            (t.texel(0, 0).x - 0.215_860_5).abs() < 1e-6,
            "{}",
            t.texel(0, 0)
        );
        assert_eq!(t.texel(1, 0), Vec3::ONE);
        // Damaged: the header survives, the data does not.
        let e = Texture::decode(&bytes[..bytes.len() - 20]).unwrap_err();
        assert!(matches!(e, TextureError::NotAnImage(_)), "{e}");
        for bad in [&b""[..], b"\x89PNG\r\n\x1a\n", b"P6 2 1 255\n\0\0\0\0\0\0"] {
            assert!(Texture::decode(bad).is_err(), "{bad:?}");
        }
        // Too large: refused from the header (a 20000 × 1 black PNG).
        let mut huge = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut huge, 20_000, 1);
            encoder.set_color(png::ColorType::Grayscale);
            let mut w = encoder.write_header().unwrap();
            w.write_image_data(&[0; 20_000]).unwrap();
        }
        assert_eq!(
            Texture::decode(&huge).unwrap_err(),
            TextureError::TooLarge {
                width: 20_000,
                height: 1
            }
        );
        for (w, h, n) in [(0, 1, 0), (2, 2, 3)] {
            assert!(Texture::from_linear(w, h, vec![Vec3::ONE; n]).is_err());
        }
        assert!(Texture::from_linear(1, 1, vec![Vec3::new(0.0, -1.0, 0.0)]).is_err());
    }
}
