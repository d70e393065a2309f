//! The no_std core lighting a scene live in a web page (`web/index.html`): a swarm of embers
//! (`lgh_core`'s hierarchy over up to [`MAX_LIGHTS`] point lights) shading a ground plane and
//! three spheres, seen from above. The hierarchy is built when the embers move (every fourth
//! frame) and updated in place where they only flicker (the others); every pixel sums its
//! lights through [`lgh_core::LightingGridHierarchy::query_sum`] with a Lambertian response,
//! unshadowed.
//!
//! The page calls a raw `extern "C"` interface (no bindings generator): `lgh_web_frame`
//! renders a frame into buffers that `lgh_web_rgba` and `lgh_web_rgb` point at in the
//! module's memory. The same [`Renderer`] runs natively, and the browser test
//! (`web/tests/browser.rs`) compares the canvas of headless Chromium with it, pixel for pixel.
//!
//! Modules: [`swarm`], the scene (the embers' positions and flicker, the ground and spheres),
//! transcribed from the C++ example (`examples/c/swarm.h`) operation for operation.

#![forbid(unsafe_op_in_unsafe_fn)]
#![warn(missing_docs)]

pub mod swarm;

use lgh_core::glam::Vec3;
use lgh_core::{
    BuildError, GridSettings, LightSample, LightingGridHierarchy, PointLight, QueryError,
};

/// The most embers a frame may have.
pub const MAX_LIGHTS: usize = 1_000_000;
/// The largest image side.
pub const MAX_SIZE: usize = 2048;

/// Why a frame was not rendered.
#[derive(Clone, Debug, PartialEq)]
pub enum WebError {
    /// A light count of 0 or above [`MAX_LIGHTS`], or an image side of 0 or above [`MAX_SIZE`].
    OutOfRange {
        /// What was out of range.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The hierarchy refused the lights.
    Build(BuildError),
    /// A query refused its point or α.
    Query(QueryError),
}

impl core::fmt::Display for WebError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            WebError::OutOfRange { what, value } => write!(f, "{what} {value} is out of range"),
            WebError::Build(e) => write!(f, "building the hierarchy: {e}"),
            WebError::Query(e) => write!(f, "lighting: {e}"),
        }
    }
}

impl From<BuildError> for WebError {
    fn from(e: BuildError) -> Self {
        WebError::Build(e)
    }
}

impl From<QueryError> for WebError {
    fn from(e: QueryError) -> Self {
        WebError::Query(e)
    }
}

/// What a frame did to the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Update {
    /// Built from scratch (the first frame, or a new light count).
    Built,
    /// Rebuilt: the embers moved.
    Rebuilt,
    /// Only their intensities changed, updated in place.
    Updated,
}

/// A frame's numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// What the hierarchy went through.
    pub update: Update,
    /// Lights summed, over all pixels.
    pub lights_shaded: u64,
}

/// Renders the swarm's frames, keeping the hierarchy from frame to frame.
#[derive(Default)]
pub struct Renderer {
    hierarchy: Option<LightingGridHierarchy>,
    /// The light count and the frame the embers' positions are from.
    count: usize,
    moved: i32,
    lights: Vec<PointLight>,
    intensities: Vec<Vec3>,
    rgb: Vec<f32>,
    rgba: Vec<u8>,
}

impl Renderer {
    /// A renderer with nothing rendered yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Renders frame `frame` (0 to 47, then again) of `count` embers at `size` × `size` with
    /// the paper's `alpha`: the linear image ([`rgb`](Self::rgb)) and its tone-mapped 8-bit
    /// RGBA ([`rgba`](Self::rgba)). Nothing changes on an error.
    ///
    /// ```
    /// use lgh_web::{Renderer, Update};
    ///
    /// let mut r = Renderer::new();
    /// assert_eq!(r.frame(2000, 0, 16, 2.0)?.update, Update::Built);
    /// assert_eq!(r.frame(2000, 1, 16, 2.0)?.update, Update::Updated); // flickered only
    /// assert_eq!(r.frame(2000, 4, 16, 2.0)?.update, Update::Rebuilt); // moved
    /// assert_eq!(r.rgba().len(), 16 * 16 * 4);
    /// assert!(r.rgb().iter().any(|&v| v > 0.0));
    /// assert!(r.frame(0, 5, 16, 2.0).is_err());
    /// // A bad α is refused before the embers move: frame 8 still rebuilds afterwards.
    /// let before = r.rgba().to_vec();
    /// assert!(r.frame(2000, 8, 16, f32::NAN).is_err());
    /// assert_eq!(r.rgba(), &before[..]);
    /// assert_eq!(r.frame(2000, 8, 16, 2.0)?.update, Update::Rebuilt);
    /// # Ok::<(), lgh_web::WebError>(())
    /// ```
    pub fn frame(
        &mut self,
        count: usize,
        frame: i32,
        size: usize,
        alpha: f32,
    ) -> Result<FrameStats, WebError> {
        let update = self.light_frame(count, frame, size, alpha)?.0;
        let lgh = self.hierarchy.as_ref().expect("lit above");
        let blending = lgh.blending(alpha)?;
        let h0 = lgh.h0();
        let mut rgb = vec![0.0f32; 3 * size * size];
        let mut lights_shaded = 0u64;
        for py in 0..size {
            for px in 0..size {
                let (p, n, albedo) = swarm::surface(px as i32, py as i32, size as i32);
                let (p, n) = (Vec3::from(p), Vec3::from(n));
                let brdf = Vec3::from(albedo) * core::f32::consts::FRAC_1_PI;
                let shade = |s: &LightSample| {
                    let d = s.distance;
                    let cosine = n.dot(s.position - p) / d;
                    if cosine.is_nan() || cosine <= 0.0 {
                        return Vec3::ZERO;
                    }
                    let dd = if d > h0 { d } else { h0 };
                    s.intensity * brdf * (cosine / (dd * dd))
                };
                let (sum, lights) = lgh.query_sum(p, &blending, shade)?;
                lights_shaded += u64::from(lights);
                rgb[3 * (py * size + px)..][..3].copy_from_slice(&sum.to_array());
            }
        }
        self.finish(rgb, count);
        Ok(FrameStats {
            update,
            lights_shaded,
        })
    }

    /// The hierarchy of frame `frame` of `count` embers, for an image `size` × `size` at
    /// `alpha` ([`frame`](Self::frame)'s checks): built, rebuilt or updated in place as
    /// [`frame`](Self::frame) would, for a renderer that shades it elsewhere (the page's
    /// WebGPU path, `web/gpu`), which then hands its image to [`finish`](Self::finish).
    pub fn light_frame(
        &mut self,
        count: usize,
        frame: i32,
        size: usize,
        alpha: f32,
    ) -> Result<(Update, &LightingGridHierarchy), WebError> {
        let range = |what, ok: bool, value: f64| {
            if ok {
                Ok(())
            } else {
                Err(WebError::OutOfRange { what, value })
            }
        };
        range(
            "light count",
            (1..=MAX_LIGHTS).contains(&count),
            count as f64,
        )?;
        range("image size", (1..=MAX_SIZE).contains(&size), size as f64)?;
        range("frame", frame >= 0, f64::from(frame))?;
        // α before the hierarchy changes, so that a bad one leaves everything as it was.
        lgh_core::check_alpha(alpha)?;
        let frame = frame % 48;
        let moved = frame - frame % 4;
        let update = self.light(count, frame, moved)?;
        Ok((update, self.hierarchy.as_ref().expect("lit above")))
    }

    /// Takes a frame's linear image of `count` embers (3 floats a pixel, row by row) as the
    /// last frame's, tone-mapped as [`frame`](Self::frame)'s.
    pub fn finish(&mut self, rgb: Vec<f32>, count: usize) {
        // The same brightness whatever the light count: each ember carries 1/count of the
        // swarm's 100,000-ember power.
        let exposure = 100_000.0 / count as f32;
        self.rgba = rgb
            .chunks(3)
            .flat_map(|c| {
                let [r, g, b] = [c[0], c[1], c[2]].map(|v| tone(v * exposure));
                [r, g, b, 255]
            })
            .collect();
        self.rgb = rgb;
    }

    /// The hierarchy for `count` embers at `frame`, their positions from `moved`: built,
    /// rebuilt or updated in place.
    fn light(&mut self, count: usize, frame: i32, moved: i32) -> Result<Update, WebError> {
        self.intensities.clear();
        self.intensities
            .extend((0..count).map(|i| Vec3::from(swarm::light(i, frame).1)));
        let fresh = self.hierarchy.is_none() || self.count != count;
        if !fresh && self.moved == moved {
            let lgh = self.hierarchy.as_mut().expect("not fresh");
            lgh.update_intensities(&self.intensities)?;
            return Ok(Update::Updated);
        }
        self.lights.clear();
        self.lights.extend((0..count).map(|i| {
            let position = Vec3::from(swarm::light(i, moved).0);
            PointLight::new(position, self.intensities[i])
        }));
        let lgh = LightingGridHierarchy::build(&self.lights, &GridSettings::default())?;
        self.hierarchy = Some(lgh);
        (self.count, self.moved) = (count, moved);
        Ok(if fresh {
            Update::Built
        } else {
            Update::Rebuilt
        })
    }

    /// The last frame's linear RGB, row by row from the top (`−z`), 3 floats a pixel.
    #[must_use]
    pub fn rgb(&self) -> &[f32] {
        &self.rgb
    }

    /// The last frame tone-mapped ([`tone`]) as 8-bit RGBA, what the page's canvas shows.
    #[must_use]
    pub fn rgba(&self) -> &[u8] {
        &self.rgba
    }
}

/// A linear value to 8 bits: Reinhard's `v / (1 + v)`, then a square root for gamma (IEEE-exact,
/// unlike a power, so the page and a native build agree).
///
/// ```
/// assert_eq!(lgh_web::tone(0.0), 0);
/// assert_eq!(lgh_web::tone(1.0), 180); // √½ · 255 = 180.3
/// assert_eq!(lgh_web::tone(f32::INFINITY), 255);
/// ```
#[must_use]
pub fn tone(v: f32) -> u8 {
    let v = if v.is_nan() || v <= 0.0 { 0.0 } else { v };
    let t = if v.is_infinite() { 1.0 } else { v / (1.0 + v) };
    (255.0 * libm::sqrtf(t) + 0.5) as u8
}

#[cfg(target_arch = "wasm32")]
mod exports {
    //! The page's interface: one renderer per module instance (wasm32 has one thread).

    use super::*;
    use core::cell::RefCell;

    std::thread_local! {
        static RENDERER: RefCell<Renderer> = RefCell::new(Renderer::new());
        static ERROR: RefCell<String> = const { RefCell::new(String::new()) };
        static LIGHTS: RefCell<f64> = const { RefCell::new(0.0) };
    }

    /// Renders a frame ([`Renderer::frame`]); 0 on success, 1 on an error
    /// ([`lgh_web_error`] says which).
    #[no_mangle]
    pub extern "C" fn lgh_web_frame(count: u32, frame: i32, size: u32, alpha: f32) -> u32 {
        let done = RENDERER.with(|r| {
            r.borrow_mut()
                .frame(count as usize, frame, size as usize, alpha)
        });
        match done {
            Ok(stats) => {
                LIGHTS.with(|l| *l.borrow_mut() = stats.lights_shaded as f64);
                0
            }
            Err(e) => {
                ERROR.with(|m| *m.borrow_mut() = e.to_string());
                1
            }
        }
    }

    /// The last frame's RGBA bytes ([`Renderer::rgba`]).
    #[no_mangle]
    pub extern "C" fn lgh_web_rgba() -> *const u8 {
        RENDERER.with(|r| r.borrow().rgba().as_ptr())
    }

    /// The last frame's linear RGB floats ([`Renderer::rgb`]).
    #[no_mangle]
    pub extern "C" fn lgh_web_rgb() -> *const f32 {
        RENDERER.with(|r| r.borrow().rgb().as_ptr())
    }

    /// Lights summed over the last frame's pixels.
    #[no_mangle]
    pub extern "C" fn lgh_web_lights_shaded() -> f64 {
        LIGHTS.with(|l| *l.borrow())
    }

    /// The last error's message: its UTF-8 bytes ([`lgh_web_error_len`] of them).
    #[no_mangle]
    pub extern "C" fn lgh_web_error() -> *const u8 {
        ERROR.with(|m| m.borrow().as_ptr())
    }

    /// The length of [`lgh_web_error`]'s message in bytes.
    #[no_mangle]
    pub extern "C" fn lgh_web_error_len() -> u32 {
        ERROR.with(|m| m.borrow().len() as u32)
    }
}
