//! The pinhole camera every lgh renderer looks through: rays from the eye through pixel
//! positions, image rows top first.
//!
//! lgh-vpl re-exports [`Pinhole`] as its `Camera`; lgh-volume uses it as `render::Camera`, with
//! its automatic framing of a volume on top.

use std::fmt;

use lgh_core::glam::Vec3;

use crate::error::ImageError;

/// Why a camera could not be set up.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraError {
    /// The eye, target or up vector has a NaN or infinite coordinate.
    NonFinite,
    /// The eye is at the target: there is no view direction.
    EyeAtTarget,
    /// The up vector is zero or parallel to the view direction.
    UpAlongView,
    /// The vertical field of view (degrees) is not in (0, 180).
    FieldOfView(f32),
    /// The lens shift (fractions of the image's larger side) has a NaN or infinite coordinate.
    Shift([f32; 2]),
    /// The image size is outside 1 to [`MAX_IMAGE_SIDE`](crate::MAX_IMAGE_SIDE) pixels per side
    /// (the [`ImageError::Size`] of [`check_image_size`](crate::check_image_size)).
    ImageSize {
        /// The width asked for.
        width: usize,
        /// The height asked for.
        height: usize,
    },
}

impl fmt::Display for CameraError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CameraError::NonFinite => {
                write!(f, "camera: eye, target and up must be finite")
            }
            CameraError::EyeAtTarget => write!(f, "camera: the eye is at the target"),
            CameraError::UpAlongView => write!(
                f,
                "camera: the up vector must be non-zero and not parallel to the view direction"
            ),
            CameraError::FieldOfView(fov) => write!(
                f,
                "camera: vertical field of view {fov}° must be in (0, 180) degrees"
            ),
            CameraError::Shift([x, y]) => {
                write!(f, "camera: lens shift ({x}, {y}) must be finite")
            }
            // The message of the image-size check, which is the rule.
            &CameraError::ImageSize { width, height } => {
                write!(f, "camera: {}", ImageError::Size { width, height })
            }
        }
    }
}

impl std::error::Error for CameraError {}

/// A pinhole camera with a vertical field of view and square pixels; image rows top first. Its
/// image plane may be shifted off the view axis ([`with_shift`](Pinhole::with_shift), a camera's
/// lens shift).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pinhole {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_fov: f32,
    /// The lens shift on the image plane at distance 1, along `right` and `up` (zero: none).
    shift: [f32; 2],
    width: usize,
    height: usize,
}

impl Pinhole {
    /// A camera at `eye` looking at `target`, with `up` roughly up (any vector not parallel to
    /// the view), a vertical field of view of `fov_y_degrees` and a `width × height` image
    /// (checked with [`check_image_size`](crate::check_image_size)).
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_image::{CameraError, Pinhole};
    ///
    /// let camera = Pinhole::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 90.0, 3, 3)?;
    /// // The centre pixel's ray leaves the eye straight at the target.
    /// let (origin, dir) = camera.ray(1, 1);
    /// assert_eq!(origin, Vec3::new(0.0, 0.0, 5.0));
    /// assert!((dir - Vec3::NEG_Z).length() < 1e-6);
    /// // The top-left pixel looks left and up.
    /// let (_, corner) = camera.ray(0, 0);
    /// assert!(corner.x < 0.0 && corner.y > 0.0);
    ///
    /// let e = Pinhole::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 90.0, 3, 3).unwrap_err();
    /// assert_eq!(e, CameraError::EyeAtTarget);
    /// let e = Pinhole::new(Vec3::Z, Vec3::ZERO, Vec3::Y, 90.0, 0, 3).unwrap_err();
    /// assert_eq!(e, CameraError::ImageSize { width: 0, height: 3 });
    /// assert!(e.to_string().starts_with("camera: image size 0x3"));
    /// # Ok::<(), CameraError>(())
    /// ```
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_degrees: f32,
        width: usize,
        height: usize,
    ) -> Result<Pinhole, CameraError> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(CameraError::NonFinite);
        }
        let forward = (target - eye).normalize_or_zero();
        if forward == Vec3::ZERO {
            return Err(CameraError::EyeAtTarget);
        }
        // Parallel within about 0.06° (sin < 1e-3) counts as parallel: the frame would be noise.
        let side = forward.cross(up.normalize_or_zero());
        if side.length() < 1e-3 {
            return Err(CameraError::UpAlongView);
        }
        let tan_half_fov = (0.5 * fov_y_degrees).to_radians().tan();
        if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0 && tan_half_fov.is_finite()) {
            return Err(CameraError::FieldOfView(fov_y_degrees));
        }
        crate::check_image_size(width, height)
            .map_err(|_| CameraError::ImageSize { width, height })?;
        let right = side.normalize();
        Ok(Pinhole {
            eye,
            forward,
            right,
            up: right.cross(forward),
            tan_half_fov,
            shift: [0.0; 2],
            width,
            height,
        })
    }

    /// This camera with its image plane shifted off the view axis by `shift` = (x, y) times the
    /// image's larger side, x right and y up: a lens shift, as Blender's camera has it (Shift X
    /// and Y with the sensor fit `Auto`). The eye and the view direction stay; the image shows
    /// what a larger image would show beside the unshifted one — vertical lines stay vertical,
    /// as an architectural camera keeps them. `[0.0, 0.0]` is the unshifted camera, to the bit.
    ///
    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_image::{CameraError, Pinhole};
    ///
    /// // 90° vertically on a 4×2 image: the image plane at distance 1 is 4 wide, 2 high.
    /// let camera = Pinhole::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 4, 2)?;
    /// // Shifted by half its width to the right, the image's left edge looks straight ahead.
    /// let shifted = camera.with_shift([0.5, 0.0])?;
    /// let d = shifted.direction(0.0, 1.0);
    /// assert!((d - Vec3::NEG_Z).length() < 1e-6, "{d}");
    /// assert_eq!(camera.with_shift([0.0, 0.0])?, camera);
    /// let e = camera.with_shift([0.0, f32::INFINITY]).unwrap_err();
    /// assert_eq!(e, CameraError::Shift([0.0, f32::INFINITY]));
    /// # Ok::<(), CameraError>(())
    /// ```
    pub fn with_shift(self, shift: [f32; 2]) -> Result<Pinhole, CameraError> {
        if !(shift[0].is_finite() && shift[1].is_finite()) {
            return Err(CameraError::Shift(shift));
        }
        let aspect = self.width as f32 / self.height as f32;
        let side = 2.0 * self.tan_half_fov * aspect.max(1.0);
        Ok(Pinhole {
            shift: [shift[0] * side, shift[1] * side],
            ..self
        })
    }

    /// The eye position: the origin of every ray.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// Image width in pixels.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Image height in pixels.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// The unit direction of the ray through pixel position `(x, y)`, in pixels from the image's
    /// top-left corner (x right, y down): pixel `(px, py)`'s centre is at `(px + 0.5, py + 0.5)`.
    /// Positions outside the image give directions outside the field of view, not an error.
    #[must_use]
    pub fn direction(&self, x: f32, y: f32) -> Vec3 {
        // The renderers' images depend on this exact arithmetic: keep the order of operations.
        let aspect = self.width as f32 / self.height as f32;
        // Adding a zero shift changes no bit: u and v are never -0.0 (1.0 - 1.0 is +0.0).
        let u = (2.0 * x / self.width as f32 - 1.0) * self.tan_half_fov * aspect + self.shift[0];
        let v = (1.0 - 2.0 * y / self.height as f32) * self.tan_half_fov + self.shift[1];
        (self.forward + u * self.right + v * self.up).normalize()
    }

    /// The ray `(origin, unit direction)` through the centre of pixel `(px, py)` (x right, y down):
    /// the eye and [`direction`](Self::direction)`(px + 0.5, py + 0.5)`. Pixels outside the image
    /// give rays outside the field of view, not an error.
    #[must_use]
    pub fn ray(&self, px: usize, py: usize) -> (Vec3, Vec3) {
        (self.eye, self.direction(px as f32 + 0.5, py as f32 + 0.5))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_at_the_target_and_corners_span_the_field_of_view() {
        let target = Vec3::new(1.0, 2.0, -3.0);
        let c = Pinhole::new(Vec3::new(1.0, 2.0, 2.0), target, Vec3::Y, 90.0, 3, 3).unwrap();
        let (o, d) = c.ray(1, 1);
        assert_eq!(o, c.eye());
        assert!((d - (-Vec3::Z)).length() < 1e-6, "{d}");
        // With 90° vertically on a 3×3 image, the top-left pixel centre is at x, y = ∓2/3.
        let (_, d) = c.ray(0, 0);
        let want = Vec3::new(-2.0 / 3.0, 2.0 / 3.0, -1.0).normalize();
        assert!((d - want).length() < 1e-6, "{d} vs {want}");
        // Non-square: the horizontal extent scales with the aspect ratio.
        let wide = Pinhole::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 4, 2).unwrap();
        let (_, d) = wide.ray(0, 0);
        let want = Vec3::new(-1.5, 0.5, -1.0).normalize();
        assert!((d - want).length() < 1e-6, "{d} vs {want}");
    }

    #[test]
    fn direction_takes_positions_in_pixels_from_the_top_left_corner() {
        // 90° vertically on a 4×2 image: the image plane at distance 1 spans x ∈ [−2, 2],
        // y ∈ [−1, 1]; position (0, 0) is its top-left corner, (4, 2) its bottom-right one.
        let c = Pinhole::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 4, 2).unwrap();
        for ((x, y), want) in [
            ((0.0, 0.0), Vec3::new(-2.0, 1.0, -1.0)),
            ((4.0, 2.0), Vec3::new(2.0, -1.0, -1.0)),
            ((2.0, 1.0), Vec3::new(0.0, 0.0, -1.0)),
            ((3.0, 0.5), Vec3::new(1.0, 0.5, -1.0)),
        ] {
            let d = c.direction(x, y);
            let want = want.normalize();
            assert!((d - want).length() < 1e-6, "({x}, {y}): {d} vs {want}");
        }
    }

    #[test]
    fn an_unshifted_camera_gives_the_former_arithmetics_bits() {
        // The direction before lens shift existed, as the committed images were made with it.
        let former = |c: &Pinhole, x: f32, y: f32| {
            let aspect = c.width as f32 / c.height as f32;
            let u = (2.0 * x / c.width as f32 - 1.0) * c.tan_half_fov * aspect;
            let v = (1.0 - 2.0 * y / c.height as f32) * c.tan_half_fov;
            (c.forward + u * c.right + v * c.up).normalize()
        };
        let c = Pinhole::new(Vec3::new(-7.1, 3.3, 2.9), Vec3::ZERO, Vec3::Z, 75.5, 17, 31).unwrap();
        for c in [c, c.with_shift([0.0, 0.0]).unwrap()] {
            for py in 0..=2 * c.height() {
                for px in 0..=2 * c.width() {
                    let (x, y) = (0.5 * px as f32, 0.5 * py as f32);
                    assert_eq!(
                        c.direction(x, y).to_array().map(f32::to_bits),
                        former(&c, x, y).to_array().map(f32::to_bits),
                        "({x}, {y})"
                    );
                }
            }
        }
    }

    #[test]
    fn a_lens_shift_moves_the_image_plane_by_fractions_of_the_larger_side() {
        // 90° vertically: the image plane at distance 1 is 2 high, 2·aspect wide.
        for (w, h) in [(4, 2), (2, 4)] {
            let c = Pinhole::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, w, h).unwrap();
            let larger = 2.0 * (w as f32 / h as f32).max(1.0);
            for shift in [[0.25, 0.0], [0.0, -0.5], [0.1, 0.3]] {
                let s = c.with_shift(shift).unwrap();
                for (x, y) in [(0.0, 0.0), (1.0, 1.5), (w as f32, h as f32)] {
                    let plane = c.direction(x, y) / -c.direction(x, y).z;
                    let want = plane + Vec3::new(shift[0], shift[1], 0.0) * larger;
                    let d = s.direction(x, y);
                    assert!(
                        (d - want.normalize()).length() < 1e-6,
                        "{w}x{h} {shift:?} ({x}, {y})"
                    );
                }
            }
        }
        assert_eq!(
            Pinhole::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 4, 2)
                .unwrap()
                .with_shift([f32::NAN, 0.0])
                .map_err(|e| e.to_string())
                .unwrap_err(),
            "camera: lens shift (NaN, 0) must be finite"
        );
    }

    #[test]
    fn ray_is_direction_at_the_pixel_centre_exactly() {
        let cameras = [
            Pinhole::new(Vec3::new(1.0, 2.0, 2.0), Vec3::ZERO, Vec3::Y, 90.0, 3, 3).unwrap(),
            Pinhole::new(
                Vec3::new(-7.1, 3.3, 2.9),
                Vec3::new(0.1, -0.4, 1.2),
                Vec3::new(0.2, 1.3, -0.1),
                75.5,
                17,
                31,
            )
            .unwrap(),
            Pinhole::new(Vec3::new(1.0, -9.0, 0.5), Vec3::ZERO, Vec3::Z, 12.0, 64, 36).unwrap(),
        ];
        for c in cameras {
            // One pixel beyond the image on each side too: those are rays, not errors.
            for py in 0..=c.height() {
                for px in 0..=c.width() {
                    let (o, d) = c.ray(px, py);
                    assert_eq!(
                        o.to_array().map(f32::to_bits),
                        c.eye().to_array().map(f32::to_bits)
                    );
                    let want = c.direction(px as f32 + 0.5, py as f32 + 0.5);
                    assert_eq!(
                        d.to_array().map(f32::to_bits),
                        want.to_array().map(f32::to_bits),
                        "pixel ({px}, {py}) of {c:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn degenerate_cameras_are_errors() {
        let ok = |eye, target, up, fov, w, h| Pinhole::new(eye, target, up, fov, w, h);
        let (e, t, up) = (Vec3::ZERO, -Vec3::Z, Vec3::Y);
        assert!(ok(e, t, up, 60.0, 8, 8).is_ok());
        assert_eq!(ok(e, e, up, 60.0, 8, 8), Err(CameraError::EyeAtTarget));
        assert_eq!(ok(e, t, Vec3::Z, 60.0, 8, 8), Err(CameraError::UpAlongView));
        assert_eq!(
            ok(e, t, Vec3::ZERO, 60.0, 8, 8),
            Err(CameraError::UpAlongView)
        );
        for fov in [0.0, -10.0, 180.0, 200.0, f32::NAN, f32::INFINITY] {
            assert!(
                matches!(ok(e, t, up, fov, 8, 8), Err(CameraError::FieldOfView(_))),
                "{fov}"
            );
        }
        for (w, h) in [(0, 8), (8, 0), (crate::limits::MAX_IMAGE_SIDE + 1, 8)] {
            assert_eq!(
                ok(e, t, up, 60.0, w, h),
                Err(CameraError::ImageSize {
                    width: w,
                    height: h
                }),
                "{w}x{h}"
            );
        }
        let nan = Vec3::splat(f32::NAN);
        for (eye, target, up) in [(nan, t, up), (e, nan, up), (e, t, nan)] {
            assert_eq!(ok(eye, target, up, 60.0, 8, 8), Err(CameraError::NonFinite));
        }
    }
}
