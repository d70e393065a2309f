//! The web page's ember swarm lit through `lgh-gpu`, headless, to a PNG: the hierarchy built on
//! the GPU from the embers (`GpuBuilder`), and queried there at every pixel of the swarm's
//! ground and spheres seen from above (eq. 1 with a Lambertian response, unshadowed).
//!
//! `cargo run --release -p lgh-gpu --example gpu -- swarm.png [LIGHTS] [SIZE] [FRAME]`
//! (100000 embers, 512², frame 12 by default). Any Vulkan, Metal or DX12 adapter; Mesa's
//! lavapipe without a GPU.

use std::path::PathBuf;

use lgh_core::glam::Vec3;
use lgh_core::PointLight;
use lgh_gpu::{Gpu, GpuBuilder, GpuGrid, ShadingPoint};
use lgh_web::swarm;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .ok_or("usage: gpu OUT.png [LIGHTS] [SIZE] [FRAME]")?,
    );
    let mut number = |default: usize| -> Result<usize, Box<dyn std::error::Error>> {
        Ok(args
            .next()
            .map(|a| a.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let (count, size, frame) = (number(100_000)?, number(512)?, number(12)?);
    let lights: Vec<PointLight> = (0..count)
        .map(|i| {
            let (p, c) = swarm::light(i, frame as i32);
            PointLight::new(Vec3::from(p), Vec3::from(c))
        })
        .collect();
    let points: Vec<ShadingPoint> = swarm::view(size as u32, size as u32)
        .map(|(p, n, albedo)| ShadingPoint::new(Vec3::from(p), Vec3::from(n), Vec3::from(albedo)))
        .collect();
    let gpu = Gpu::new()?;
    let mut builder = GpuBuilder::new(&gpu, GpuGrid::fitting(&lights)?, 2.0)?;
    let build = builder.rebuild(&lights)?;
    let (radiance, timing) = builder.hierarchy().shade_timed(&points)?;
    let pixels: Vec<Vec3> = radiance.into_iter().map(Vec3::from).collect();
    let mean = pixels
        .iter()
        .map(|c| c.dot(Vec3::new(0.2126, 0.7152, 0.0722)))
        .sum::<f32>()
        / pixels.len() as f32;
    let image = lgh_image::Image {
        width: size,
        height: size,
        pixels,
    };
    lgh_image::write_png(&out, &image, 0.18 / mean.max(f32::MIN_POSITIVE))?;
    let ms = |t: lgh_gpu::GpuTiming| {
        t.kernel_ms
            .map_or("no timestamps".into(), |ms| format!("{ms:.2} ms"))
    };
    println!(
        "{}: {count} embers at {size}² on {} (the build: {}, the query: {})",
        out.display(),
        gpu.adapter().name,
        ms(build),
        ms(timing)
    );
    Ok(())
}
