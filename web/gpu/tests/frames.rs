//! The page's WebGPU path natively (lavapipe in CI): its frames against the CPU path's
//! ([`lgh_web::Renderer`]) within the query's tolerance. Both sum the same non-negative terms
//! — the lights lgh-core's query reports at a pixel, at most the frame's `count` of them — in
//! different orders, each term with a few roundings on each side: `|gpu − cpu| ≤ (2N + 32)·u`
//! of the pixel (lgh-gpu's `tests/shade.rs` derives it), `N ≤ count`.

use lgh_gpu::Gpu;
use lgh_web::Renderer;
use lgh_web_gpu::GpuFrames;

#[test]
fn the_gpu_frames_are_the_cpu_frames_within_the_tolerance() {
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => return lgh_tests::Piece::Gpu.missing(&e.to_string()),
    };
    let (count, size) = (2000usize, 48usize);
    let bound = (2 * count + 32) as f32 / (1u32 << 24) as f32;
    let mut frames = GpuFrames::new(gpu);
    let mut cpu = Renderer::new();
    let mut worst = 0.0f32;
    for frame in 0..6 {
        pollster::block_on(frames.frame(count, frame, size, 2.0)).unwrap();
        cpu.frame(count, frame, size, 2.0).unwrap();
        for (g, c) in frames.rgb().iter().zip(cpu.rgb()) {
            let diff = (g - c).abs();
            assert!(diff <= bound * c.abs(), "frame {frame}: {g} against {c}");
            if *c > 0.0 {
                worst = worst.max(diff / (bound * c));
            }
        }
        assert_eq!(frames.rgba().len(), cpu.rgba().len());
    }
    eprintln!("largest difference {worst:.3} of the bound");
    // Bad settings are refused as the CPU path refuses them.
    assert!(pollster::block_on(frames.frame(0, 0, size, 2.0)).is_err());
    assert!(pollster::block_on(frames.frame(count, 0, size, f32::NAN)).is_err());
}
