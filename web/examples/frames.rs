//! The page's frames rendered natively, timed: what the browser's frame times
//! (`LGH_WEB_BENCH=1` in web/tests/browser.rs) are set against.
//! `cargo run --release -p lgh-web --example frames -- [LIGHTS] [SIZE] [FRAMES]` (100000, 256, 8
//! by default).

use std::time::Instant;

fn main() {
    let arg = |i: usize, default: usize| {
        std::env::args()
            .nth(i)
            .map_or(default, |v| v.parse().expect("a number"))
    };
    let (count, size, frames) = (arg(1, 100_000), arg(2, 256), arg(3, 8));
    let mut renderer = lgh_web::Renderer::new();
    let mut ms = Vec::new();
    for frame in 0..frames as i32 {
        let t = Instant::now();
        let stats = renderer.frame(count, frame, size, 2.0).unwrap_or_else(|e| {
            eprintln!("frames: {e}");
            std::process::exit(1);
        });
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        println!(
            "frame {frame}: {:?}, {:.1} ms, {:.1} lights a pixel",
            stats.update,
            ms[ms.len() - 1],
            stats.lights_shaded as f64 / (size * size) as f64
        );
    }
    println!(
        "native, {count} lights, {size}²: frames 0-{} in {ms:.1?} ms",
        frames - 1
    );
}
