//! The pinhole camera: rays from the eye through pixel centres.

use std::fmt;

use lgh_core::glam::Vec3;

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
    /// The image size is outside 1 to [`lgh_image::MAX_IMAGE_SIDE`] pixels per side.
    ImageSize(String),
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
            CameraError::ImageSize(message) => write!(f, "camera: {message}"),
        }
    }
}

impl std::error::Error for CameraError {}

/// A pinhole camera with a vertical field of view and square pixels; image rows top first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_fov: f32,
    width: usize,
    height: usize,
}

impl Camera {
    /// A camera at `eye` looking at `target`, with `up` roughly up (any vector not parallel to
    /// the view), a vertical field of view of `fov_y_degrees` and a `width × height` image.
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_degrees: f32,
        width: usize,
        height: usize,
    ) -> Result<Camera, CameraError> {
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
        lgh_image::check_image_size(width, height).map_err(CameraError::ImageSize)?;
        let right = side.normalize();
        Ok(Camera {
            eye,
            forward,
            right,
            up: right.cross(forward),
            tan_half_fov,
            width,
            height,
        })
    }

    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// Image width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The ray `(origin, unit direction)` through the centre of pixel `(px, py)` (x right, y down;
    /// pixels outside the image give rays outside the field of view, not an error).
    pub fn ray(&self, px: usize, py: usize) -> (Vec3, Vec3) {
        let aspect = self.width as f32 / self.height as f32;
        let x = (2.0 * (px as f32 + 0.5) / self.width as f32 - 1.0) * self.tan_half_fov * aspect;
        let y = (1.0 - 2.0 * (py as f32 + 0.5) / self.height as f32) * self.tan_half_fov;
        let dir = (self.forward + x * self.right + y * self.up).normalize();
        (self.eye, dir)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_at_the_target_and_corners_span_the_field_of_view() {
        let target = Vec3::new(1.0, 2.0, -3.0);
        let c = Camera::new(Vec3::new(1.0, 2.0, 2.0), target, Vec3::Y, 90.0, 3, 3).unwrap();
        let (o, d) = c.ray(1, 1);
        assert_eq!(o, c.eye());
        assert!((d - (-Vec3::Z)).length() < 1e-6, "{d}");
        // With 90° vertically on a 3×3 image, the top-left pixel centre is at x, y = ∓2/3.
        let (_, d) = c.ray(0, 0);
        let want = Vec3::new(-2.0 / 3.0, 2.0 / 3.0, -1.0).normalize();
        assert!((d - want).length() < 1e-6, "{d} vs {want}");
        // Non-square: the horizontal extent scales with the aspect ratio.
        let wide = Camera::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 4, 2).unwrap();
        let (_, d) = wide.ray(0, 0);
        let want = Vec3::new(-1.5, 0.5, -1.0).normalize();
        assert!((d - want).length() < 1e-6, "{d} vs {want}");
    }

    #[test]
    fn degenerate_cameras_are_errors() {
        let ok = |eye, target, up, fov, w, h| Camera::new(eye, target, up, fov, w, h);
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
        for (w, h) in [(0, 8), (8, 0), (lgh_image::MAX_IMAGE_SIDE + 1, 8)] {
            assert!(
                matches!(ok(e, t, up, 60.0, w, h), Err(CameraError::ImageSize(_))),
                "{w}x{h}"
            );
        }
        let nan = Vec3::splat(f32::NAN);
        for (eye, target, up) in [(nan, t, up), (e, nan, up), (e, t, nan)] {
            assert_eq!(ok(eye, target, up, 60.0, 8, 8), Err(CameraError::NonFinite));
        }
    }
}
