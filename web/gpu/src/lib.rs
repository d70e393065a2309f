//! The web page's WebGPU path (`web/main.js` loads it where the browser has WebGPU): each frame
//! of the ember swarm lit by lgh-gpu's query — the same WGSL kernel as natively (`walk.wgsl` +
//! `shade.wgsl`) — on the browser's WebGPU, over the hierarchy that the page's wasm core builds
//! and updates ([`lgh_web::Renderer::light_frame`]). The image is tone-mapped as the CPU path's
//! ([`lgh_web::Renderer::finish`]), so the page shows either the same way.
//!
//! The build stays on the CPU here: lgh-gpu's build waits for a readback between its two
//! submissions, and a page may not wait (lgh-gpu has no asynchronous build yet).
//!
//! Natively the same [`GpuFrames`] runs on any wgpu adapter (lavapipe in CI): its test holds it
//! to the CPU path's frames within the query's tolerance.

#![warn(missing_docs)]

use lgh_core::glam::Vec3;
use lgh_gpu::{Gpu, GpuError, GpuHierarchy, ShadingPoint};
use lgh_web::{swarm, Renderer, WebError};

/// Why a WebGPU frame was not rendered.
#[derive(Clone, Debug, PartialEq)]
pub enum FrameError {
    /// The frame's settings or lights, refused as the CPU path refuses them.
    Web(WebError),
    /// The GPU refused or failed.
    Gpu(GpuError),
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FrameError::Web(e) => write!(f, "{e}"),
            FrameError::Gpu(e) => write!(f, "WebGPU: {e}"),
        }
    }
}

impl std::error::Error for FrameError {}

impl From<WebError> for FrameError {
    fn from(e: WebError) -> Self {
        FrameError::Web(e)
    }
}

impl From<GpuError> for FrameError {
    fn from(e: GpuError) -> Self {
        FrameError::Gpu(e)
    }
}

/// The page's frames on the GPU: the wasm core's hierarchy, queried by lgh-gpu.
pub struct GpuFrames {
    gpu: Gpu,
    renderer: Renderer,
}

impl GpuFrames {
    /// Frames on `gpu`.
    #[must_use]
    pub fn new(gpu: Gpu) -> GpuFrames {
        GpuFrames {
            gpu,
            renderer: Renderer::new(),
        }
    }

    /// The adapter's name.
    #[must_use]
    pub fn adapter(&self) -> &str {
        &self.gpu.adapter().name
    }

    /// Renders frame `frame` of `count` embers at `size` × `size` with the paper's `alpha`, as
    /// [`Renderer::frame`] does but with the query on the GPU: [`rgb`](Self::rgb) and
    /// [`rgba`](Self::rgba). Errors as [`Renderer::frame`] does, or where the GPU fails.
    pub async fn frame(
        &mut self,
        count: usize,
        frame: i32,
        size: usize,
        alpha: f32,
    ) -> Result<(), FrameError> {
        let (_, lgh) = self.renderer.light_frame(count, frame, size, alpha)?;
        let on_gpu = GpuHierarchy::upload(&self.gpu, lgh, alpha)?;
        let rgb = on_gpu.shade_async(&g_buffer(size)).await?;
        self.renderer
            .finish(rgb.into_iter().flatten().collect(), count);
        Ok(())
    }

    /// The last frame's linear RGB, 3 floats a pixel ([`Renderer::rgb`]).
    #[must_use]
    pub fn rgb(&self) -> &[f32] {
        self.renderer.rgb()
    }

    /// The last frame tone-mapped, 8-bit RGBA ([`Renderer::rgba`]).
    #[must_use]
    pub fn rgba(&self) -> &[u8] {
        self.renderer.rgba()
    }
}

/// The swarm's ground and spheres at `size` × `size`, seen from above, as shading points.
#[must_use]
pub fn g_buffer(size: usize) -> Vec<ShadingPoint> {
    swarm::view(size as u32, size as u32)
        .map(|(p, n, albedo)| ShadingPoint::new(Vec3::from(p), Vec3::from(n), Vec3::from(albedo)))
        .collect()
}

#[cfg(target_arch = "wasm32")]
mod exports {
    //! The page's interface (wasm-bindgen): one set of frames per module instance.

    use super::*;
    use std::cell::RefCell;
    use wasm_bindgen::prelude::*;

    std::thread_local! {
        static FRAMES: RefCell<Option<GpuFrames>> = const { RefCell::new(None) };
    }

    /// Opens the browser's WebGPU; the adapter's name (an error where there is none).
    #[wasm_bindgen]
    pub async fn lgh_gpu_start() -> Result<String, JsValue> {
        let gpu = Gpu::new_async()
            .await
            .map_err(|e| JsValue::from_str(&e.to_string()))?;
        let frames = GpuFrames::new(gpu);
        let name = frames.adapter().to_string();
        FRAMES.with(|f| *f.borrow_mut() = Some(frames));
        Ok(name)
    }

    /// Renders a frame ([`GpuFrames::frame`]).
    #[wasm_bindgen]
    pub async fn lgh_gpu_frame(
        count: u32,
        frame: i32,
        size: u32,
        alpha: f32,
    ) -> Result<(), JsValue> {
        let mut frames = FRAMES
            .with(|f| f.borrow_mut().take())
            .ok_or_else(|| JsValue::from_str("lgh_gpu_start first"))?;
        let done = frames
            .frame(count as usize, frame, size as usize, alpha)
            .await;
        FRAMES.with(|f| *f.borrow_mut() = Some(frames));
        done.map_err(|e| JsValue::from_str(&e.to_string()))
    }

    /// The last frame's RGBA bytes.
    #[wasm_bindgen]
    pub fn lgh_gpu_rgba() -> Vec<u8> {
        FRAMES.with(|f| {
            f.borrow()
                .as_ref()
                .map_or(Vec::new(), |f| f.rgba().to_vec())
        })
    }

    /// The last frame's linear RGB floats.
    #[wasm_bindgen]
    pub fn lgh_gpu_rgb() -> Vec<f32> {
        FRAMES.with(|f| f.borrow().as_ref().map_or(Vec::new(), |f| f.rgb().to_vec()))
    }
}
