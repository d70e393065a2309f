//! The camera the volume renderer sees through: lgh-image's pinhole, with typed errors, the
//! automatic framing of a box and the world's up axis.

use lgh_core::glam::Vec3;

use crate::error::RenderError;

/// The one image-size rule of every renderer (it lives in lgh-image).
pub use lgh_image::{check_image_size, MAX_IMAGE_SIDE};

/// The pinhole camera, shared with the surface renderer: lgh-image's
/// [`Pinhole`](lgh_image::camera::Pinhole). [`Framing`] adds what the volume renderer needs on
/// top: typed errors, the automatic framing of a box, and the check of pixel lists.
pub use lgh_image::camera::Pinhole as Camera;

/// The volume renderer's conveniences on [`Camera`] (implemented for it; bring the trait into
/// scope to call `Camera::frame(...)`, `Camera::look_at(...)` or `camera.check_pixels(...)`).
///
/// ```
/// use lgh_volume::lgh_core::glam::Vec3;
/// use lgh_volume::render::{Camera, Framing};
///
/// let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 64, 36)?;
/// assert_eq!((camera.width(), camera.height()), (64, 36));
/// assert!(camera.check_pixels(&[[63, 35]]).is_ok());
/// assert!(camera.check_pixels(&[[64, 0]]).is_err());
/// # Ok::<(), lgh_volume::RenderError>(())
/// ```
pub trait Framing: Sized {
    /// A camera at `eye` looking at `target`, `up` roughly up, vertical field of view in degrees
    /// and a `width × height` image: [`Camera::new`], its
    /// [`CameraError`](lgh_image::camera::CameraError) as a [`RenderError::Camera`].
    fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y: f32,
        width: usize,
        height: usize,
    ) -> Result<Self, RenderError>;

    /// Frames the box `lo..hi` in a +Y-up world: [`frame_up`](Self::frame_up) with [`Up::Y`].
    fn frame(lo: Vec3, hi: Vec3, width: usize, height: usize) -> Result<Self, RenderError>;

    /// Frames the box `lo..hi`: looks at its centre from the front, a little to the right and
    /// above, from the distance where the box's bounding sphere shrunk to 80% fills the narrower
    /// field of view (40° vertically). Smoke rarely fills its box to the corners, and the full
    /// sphere leaves it small in the frame.
    fn frame_up(
        lo: Vec3,
        hi: Vec3,
        width: usize,
        height: usize,
        up: Up,
    ) -> Result<Self, RenderError>;

    /// Checks that every `(x, y)` of `pixels` is inside the image.
    fn check_pixels(&self, pixels: &[[usize; 2]]) -> Result<(), RenderError>;
}

impl Framing for Camera {
    fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y: f32,
        width: usize,
        height: usize,
    ) -> Result<Self, RenderError> {
        Ok(Camera::new(eye, target, up, fov_y, width, height)?)
    }

    fn frame(lo: Vec3, hi: Vec3, width: usize, height: usize) -> Result<Self, RenderError> {
        Camera::frame_up(lo, hi, width, height, Up::Y)
    }

    fn frame_up(
        lo: Vec3,
        hi: Vec3,
        width: usize,
        height: usize,
        up: Up,
    ) -> Result<Self, RenderError> {
        let centre = 0.5 * (lo + hi);
        let radius = 0.8 * 0.5 * (hi - lo).length();
        let fov_y = 40.0f32;
        let aspect = width as f32 / height.max(1) as f32;
        let half = (0.5 * fov_y).to_radians().tan() * aspect.min(1.0);
        let distance = radius / half.atan().sin();
        let (right, upv, front) = up.basis();
        let dir = (0.35 * right + 0.25 * upv + front).normalize();
        Camera::look_at(centre + dir * distance, centre, upv, fov_y, width, height)
    }

    fn check_pixels(&self, pixels: &[[usize; 2]]) -> Result<(), RenderError> {
        match pixels
            .iter()
            .find(|p| p[0] >= self.width() || p[1] >= self.height())
        {
            Some(&pixel) => Err(RenderError::PixelOutside {
                pixel,
                width: self.width(),
                height: self.height(),
            }),
            None => Ok(()),
        }
    }
}

/// The world's up axis, for automatic framing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Up {
    /// +Y up, the camera in front on +Z (most engines, Houdini).
    Y,
    /// +Z up, the camera in front on −Y (Blender).
    Z,
}

impl Up {
    /// The up vector.
    #[must_use]
    pub fn vector(self) -> Vec3 {
        self.basis().1
    }

    /// (right, up, front): the axes as seen by a camera in front of the scene.
    fn basis(self) -> (Vec3, Vec3, Vec3) {
        match self {
            Up::Y => (Vec3::X, Vec3::Y, Vec3::Z),
            Up::Z => (Vec3::X, Vec3::Z, -Vec3::Y),
        }
    }
}
