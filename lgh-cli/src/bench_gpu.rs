//! `lgh bench gpu`: the hierarchy's per-frame path on the GPU (lgh-gpu: build, intensity
//! update, rebuild of moved lights, query, gather) against the CPU path on every core of the
//! same machine, on the same frame of the web page's ember swarm, in one run; JSON.
//!
//! Each GPU time is the kernels' own by timestamp queries where the adapter has them, else
//! submission to fence, the best of three. The CPU path is lgh-core's build on the GPU's
//! placement and its query with the same response (`lgh_gpu::reference`).

use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::metrics::ErrorStats;
use lgh_core::{GridSettings, LightingGridHierarchy, PointLight};
use lgh_gpu::{Gpu, GpuBuilder, GpuGrid, GpuTiming, ShadingPoint};
use lgh_web::swarm;
use rayon::prelude::*;
use serde_json::json;

/// Arguments of `lgh bench gpu`.
#[derive(Debug, clap::Args)]
pub struct GpuBenchArgs {
    /// Embers of the swarm (the web page's scene), each a point light.
    #[arg(long, default_value_t = 1_000_000)]
    pub lights: usize,
    /// Image width: one shading point a pixel, the swarm's ground and spheres seen from above
    /// (a band of the page's square view where the image is not square).
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 720)]
    pub height: u32,
    /// The paper's α.
    #[arg(long, default_value_t = 2.0)]
    pub alpha: f32,
    /// Lights drawn per point by the gather.
    #[arg(long, default_value_t = 4)]
    pub k: u32,
    /// The swarm's frame (48 a second; it grows and cools over the first second).
    #[arg(long, default_value_t = 12)]
    pub frame: i32,
    /// CPU worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Time each kernel of the GPU's rebuild and update too (where the adapter has timestamps
    /// inside passes): the JSON's `profile`.
    #[arg(long)]
    pub profile: bool,
    /// Write the JSON here (atomically) as well as to stdout.
    #[arg(long)]
    pub out: Option<std::path::PathBuf>,
}

/// The swarm's G-buffer at `width × height`: the page's view, from above.
fn g_buffer(width: u32, height: u32) -> Vec<ShadingPoint> {
    swarm::view(width, height)
        .map(|(p, n, albedo)| ShadingPoint::new(Vec3::from(p), Vec3::from(n), Vec3::from(albedo)))
        .collect()
}

/// The CPU path: the same query through lgh-core (`lgh_gpu::reference`), on every thread of
/// the pool.
fn cpu_shade(
    lgh: &LightingGridHierarchy,
    alpha: f32,
    points: &[ShadingPoint],
) -> Result<Vec<Vec3>, crate::Error> {
    let blending = lgh.blending(alpha)?;
    let image: Result<Vec<Vec3>, _> = points
        .par_iter()
        .map(|p| lgh_gpu::reference::shade(lgh, &blending, p))
        .collect();
    Ok(image?)
}

/// The GPU's image against the CPU's: the relative RMSE of luminance, and of each channel on
/// its own (luminance can hide a channel's error).
fn rel_rmse(gpu: &[Vec3], cpu: &[Vec3]) -> (f64, [f64; 3]) {
    let of = |a: &[Vec3], r: &[Vec3]| ErrorStats::compare(a, r).map_or(f64::NAN, |s| s.rel_rmse);
    // A grey pixel's luminance is its value (the weights sum to one): each channel as grey.
    let channel =
        |img: &[Vec3], c: usize| -> Vec<Vec3> { img.iter().map(|v| Vec3::splat(v[c])).collect() };
    let rgb = [0, 1, 2].map(|c| of(&channel(gpu, c), &channel(cpu, c)));
    (of(gpu, cpu), rgb)
}

/// The embers of the swarm's frame `frame`, each a point light.
fn swarm_lights(count: usize, frame: i32) -> Vec<PointLight> {
    (0..count)
        .map(|i| {
            let (p, c) = swarm::light(i, frame);
            PointLight::new(Vec3::from(p), Vec3::from(c))
        })
        .collect()
}

/// The GPU's runs of each step, its image of the frame, and the rebuild's and the update's
/// profiles (empty unless profiling).
struct Runs {
    rebuilds: Vec<GpuTiming>,
    updates: Vec<GpuTiming>,
    shades: Vec<GpuTiming>,
    gathers: Vec<GpuTiming>,
    image: Vec<Vec3>,
    profile: (Profile, Profile),
}

/// Each kernel's label and milliseconds ([`GpuBuilder::profile`]).
type Profile = Vec<(String, f64)>;

/// Times `on_gpu` (built on `lights`) on the frame and the next one (`next`: the embers moved,
/// a rebuild, or only their colours, an update), at `points`, the gather drawing `k`: two
/// seconds of queries first (a GPU's clocks rise under load), then several runs of each.
fn time_frames(
    on_gpu: &mut GpuBuilder,
    (lights, next): (&[PointLight], &[PointLight]),
    points: &[ShadingPoint],
    k: u32,
) -> Result<Runs, crate::Error> {
    let recoloured: Vec<Vec3> = next.iter().map(|l| l.intensity).collect();
    let own: Vec<Vec3> = lights.iter().map(|l| l.intensity).collect();
    let hierarchy = on_gpu.hierarchy();
    let warm = Instant::now();
    while warm.elapsed().as_secs_f64() < 2.0 {
        hierarchy.shade_timed(points)?;
    }
    let (mut rebuilds, mut updates) = (Vec::new(), Vec::new());
    for _ in 0..5 {
        rebuilds.push(on_gpu.rebuild(next)?);
        rebuilds.push(on_gpu.rebuild(lights)?);
    }
    let rebuild_profile = on_gpu.profile();
    for _ in 0..5 {
        updates.push(on_gpu.update_intensities(&recoloured)?);
        updates.push(on_gpu.update_intensities(&own)?);
    }
    let update_profile = on_gpu.profile();
    let hierarchy = on_gpu.hierarchy();
    let (image, _) = hierarchy.shade_timed(points)?;
    let (mut shades, mut gathers) = (Vec::new(), Vec::new());
    for seed in 0..5 {
        shades.push(hierarchy.shade_timed(points)?.1);
        gathers.push(hierarchy.gather_timed(points, k, seed)?.1);
    }
    Ok(Runs {
        rebuilds,
        updates,
        shades,
        gathers,
        image: image.into_iter().map(Vec3::from).collect(),
        profile: (rebuild_profile, update_profile),
    })
}

/// The best of `runs`: the kernels' milliseconds (timestamp queries, else the wall), the
/// wall's, and which timer gave the first.
fn best(runs: &[GpuTiming]) -> (f64, f64, &'static str) {
    let wall = runs.iter().map(|t| t.wall_ms).fold(f64::INFINITY, f64::min);
    match runs.iter().filter_map(|t| t.kernel_ms).reduce(f64::min) {
        Some(kernel) => (kernel, wall, "timestamp queries"),
        None => (wall, wall, "submission to fence"),
    }
}

/// Runs the benchmark and prints its JSON report.
pub fn run(args: &GpuBenchArgs) -> Result<(), crate::Error> {
    crate::check_alpha(args.alpha)?;
    if args.lights == 0 || args.width == 0 || args.height == 0 {
        return Err("--lights, --width and --height must be at least 1".into());
    }
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(t) = args.threads {
        builder = builder.num_threads(t);
    }
    let pool = builder.build()?;
    let lights = swarm_lights(args.lights, args.frame);
    let points = g_buffer(args.width, args.height);
    let gpu = Gpu::new()?;
    let adapter = gpu.adapter();
    eprintln!(
        "lgh bench gpu: {} ({:?}, {:?}); {} lights, {} points",
        adapter.name,
        adapter.backend,
        adapter.device_type,
        lights.len(),
        points.len()
    );
    // The GPU's grid at lgh-core's own spacing where it fits (else a coarser one), and the
    // CPU's build on the same placement: the same levels on both sides.
    let auto = pool.install(|| LightingGridHierarchy::build(&lights, &GridSettings::default()))?;
    let (lo, hi) = lgh_core::bounds(&lights);
    let grid = GpuGrid::enclosing(lo, hi, auto.h1()).or_else(|_| GpuGrid::fitting(&lights))?;
    drop(auto);
    let start = Instant::now();
    let lgh = pool.install(|| LightingGridHierarchy::build(&lights, &grid.settings()))?;
    let cpu_build_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut on_gpu = GpuBuilder::new(&gpu, grid, args.alpha)?.with_profiling(args.profile);
    let build = on_gpu.rebuild(&lights)?;
    let next = swarm_lights(args.lights, args.frame + 1);
    let Runs {
        rebuilds,
        updates,
        shades,
        gathers,
        image: gpu_image,
        profile,
    } = time_frames(&mut on_gpu, (&lights, &next), &points, args.k)?;
    let (shade_ms, shade_wall_ms, timer) = best(&shades);
    eprintln!(
        "lgh bench gpu: GPU shade {shade_ms:.2} ms; the CPU path on {} threads…",
        pool.current_num_threads()
    );
    let start = Instant::now();
    let cpu_image = pool.install(|| cpu_shade(&lgh, args.alpha, &points))?;
    let cpu_shade_ms = start.elapsed().as_secs_f64() * 1e3;
    let (rel_rmse_vs_cpu, rel_rmse_vs_cpu_rgb) = rel_rmse(&gpu_image, &cpu_image);
    let report = json!({
        "benchmark": "lgh bench gpu",
        "adapter": adapter.name,
        "backend": format!("{:?}", adapter.backend),
        "device_type": format!("{:?}", adapter.device_type),
        "lights": lights.len(),
        "width": args.width,
        "height": args.height,
        "alpha": args.alpha,
        "frame": args.frame,
        "k": args.k,
        "h1": grid.h1,
        "levels": grid.max_level() + 1,
        "build_ms": best(&[build]).0,
        "update_ms": best(&updates).0,
        "rebuild_ms": best(&rebuilds).0,
        "rebuild_wall_ms": best(&rebuilds).1,
        "shade_ms": shade_ms,
        "shade_wall_ms": shade_wall_ms,
        "gather_ms": best(&gathers).0,
        "timer": timer,
        "cpu_build_ms": cpu_build_ms,
        "cpu_threads": pool.current_num_threads(),
        "cpu_shade_ms": cpu_shade_ms,
        "speedup_vs_cpu": cpu_shade_ms / shade_ms,
        "rel_rmse_vs_cpu": rel_rmse_vs_cpu,
        "rel_rmse_vs_cpu_rgb": rel_rmse_vs_cpu_rgb,
    });
    let mut report = report;
    if args.profile {
        report["profile"] = json!({ "rebuild": profile.0, "update": profile.1 });
    }
    let text = serde_json::to_string_pretty(&report)?;
    say!("{text}");
    if let Some(out) = &args.out {
        lgh_image::write_atomic(out, |w| w.write_all(text.as_bytes()))?;
    }
    Ok(())
}
