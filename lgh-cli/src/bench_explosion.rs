//! `lgh bench explosion`: the explosion renderer against its two references, as JSON.
//!
//! Per scene: the lights and the hierarchy's build time; per α, a full image rendered with the
//! hierarchy (seconds, lights evaluated per shading point) and, on a regular subset of its
//! pixels, brute force over every light (the exact answer of the same light model: relative
//! RMSE and speed-up) and the path tracer (how many paths, and seconds, until its noise against
//! its own converged image falls to the hierarchy's error). Brute force and the path tracer run
//! on the pixel subset only, because on whole images they take hours; the hierarchy's subset
//! time is measured too, so every ratio compares the same pixels.

use crate::bench::time;
use std::path::PathBuf;

use lgh_core::glam::Vec3;
use lgh_core::metrics::ErrorStats;
use lgh_volume::cache::{self, GridNames, Placement};
use lgh_volume::explosion;
use lgh_volume::lighting_cache::LightingCacheSettings;
use lgh_volume::medium::{framing_bounds, EmissionModel, Medium, Volume};
use lgh_volume::pathtrace::{self, PathSettings};
use lgh_volume::render::{Camera, Framing, MarchSettings, RenderStats, Up};
use lgh_volume::{ExplosionLights, FrameRender, Method, Shadows};
use serde_json::{json, Value};

/// Arguments of `lgh bench explosion`.
#[derive(Debug, clap::Args)]
pub struct ExplosionBenchArgs {
    /// Scenes: pN (the demo's procedural explosion at t = 0.5 s on N³ voxels, N = 32 to 512:
    /// p128, p256), fire56 (the dev Blender frame 0056 from ../shared/data, skipped with a
    /// message when absent).
    #[arg(long, value_delimiter = ',', default_value = "p128,p256,fire56")]
    pub scenes: Vec<String>,
    /// α values.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4")]
    pub alphas: Vec<f32>,
    /// Full-image width.
    #[arg(long, default_value_t = 160)]
    pub width: usize,
    /// Full-image height.
    #[arg(long, default_value_t = 90)]
    pub height: usize,
    /// Pixels of the subset the references render: evenly strided among the pixels whose
    /// emission (a cheap render without lights) is above 1% of the brightest.
    #[arg(long, default_value_t = 64)]
    pub pixels: usize,
    /// Paths per pixel of the path tracer's converged image (its ladder goes up to 1/16 of it).
    #[arg(long, default_value_t = 1 << 18)]
    pub reference_spp: u32,
    /// Folder of the dev cache.
    #[arg(
        long,
        default_value = "../shared/data/volumes/blender_fire_pesichra/data"
    )]
    pub data: PathBuf,
    /// Write the JSON here (atomically) as well as to stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The dev fire's medium in the benchmarks: Blender's defaults (what `lgh explosion` uses)
/// with smoke 100× denser, so that scattering, what the hierarchy approximates, and the smoke's
/// shadows are a visible part of the image.
pub(crate) fn fire_medium() -> Result<Medium, crate::Error> {
    Ok(Medium::new(50.0, 50.0, 1.0, 800.0)?
        .with_temperature_scale(1000.0)?
        .with_model(EmissionModel::Blender))
}

struct Scene {
    name: String,
    volume: Volume,
    medium: Medium,
    up: Up,
}

fn scene(key: &str, data: &std::path::Path) -> Result<Option<Scene>, crate::Error> {
    if let Some(n) = procedural(key) {
        return Ok(Some(Scene {
            name: format!("explosion_{n}"),
            volume: explosion(n, 0.5)?,
            medium: crate::demo::demo_medium(),
            up: Up::Y,
        }));
    }
    Ok(Some(match key {
        "fire56" => {
            let path = data.join("fluid_data_0056.vdb");
            if !path.is_file() {
                eprintln!("fire56: SKIPPED, {} is not here", path.display());
                return Ok(None);
            }
            let medium = fire_medium()?;
            Scene {
                name: "blender_fire_0056".into(),
                volume: cache::load(&[path], &GridNames::default(), Placement::BlenderDomain)?
                    .remove(0),
                medium,
                up: Up::Z,
            }
        }
        other => return Err(unknown_scene(other)),
    }))
}

/// The voxels a side of a procedural scene key `pN` (N = 32 to 512).
fn procedural(key: &str) -> Option<usize> {
    key.strip_prefix('p')
        .and_then(|n| n.parse::<usize>().ok())
        .filter(|n| (32..=512).contains(n))
}

fn unknown_scene(key: &str) -> crate::Error {
    format!("--scenes: unknown scene '{key}' (pN for N = 32 to 512, such as p128; fire56)").into()
}

/// Up to `n` pixels, evenly strided among those whose emission-only luminance is above 1% of
/// the brightest: the references' time goes to pixels that show the explosion.
fn pick_pixels(
    s: &Scene,
    lights: &ExplosionLights,
    camera: &Camera,
    n: usize,
) -> Result<Vec<[usize; 2]>, crate::Error> {
    let march = MarchSettings::default();
    let emission = Method::Emission;
    let (emission, _) = FrameRender::new(lights, emission, &s.volume, &s.medium, &march, &())?
        .render(camera, &())?;
    let lum: Vec<f32> = emission
        .pixels
        .iter()
        .map(|&p| lgh_core::luminance(p))
        .collect();
    let max = lum.iter().copied().fold(0.0f32, f32::max);
    let bright: Vec<[usize; 2]> = (0..lum.len())
        .filter(|&i| max > 0.0 && lum[i] > 0.01 * max)
        .map(|i| [i % camera.width(), i / camera.width()])
        .collect();
    let step = bright.len().div_ceil(n.max(1)).max(1);
    Ok(bright.into_iter().step_by(step).collect())
}

fn rel_rmse(a: &[Vec3], r: &[Vec3]) -> Option<f64> {
    ErrorStats::compare(a, r).map(|e| e.rel_rmse)
}

/// Runs the benchmark and prints its JSON report.
pub fn run(args: &ExplosionBenchArgs) -> Result<(), crate::Error> {
    for &a in &args.alphas {
        crate::check_alpha(a)?;
    }
    lgh_volume::render::check_image_size(args.width, args.height)?;
    if args.pixels == 0 {
        return Err("--pixels must be at least 1".into());
    }
    if args.reference_spp < 64 {
        return Err("--reference-spp must be at least 64".into());
    }
    if let Some(bad) = args
        .scenes
        .iter()
        .find(|k| procedural(k).is_none() && k.as_str() != "fire56")
    {
        return Err(unknown_scene(bad));
    }
    let mut scenes = Vec::new();
    for key in &args.scenes {
        if let Some(s) = scene(key, &args.data)? {
            scenes.push(bench_scene(&s, args)?);
        }
    }
    let report = json!({
        "benchmark": "lgh bench explosion",
        "threads": rayon::current_num_threads(),
        "image": [args.width, args.height],
        "scenes": scenes,
    });
    let text = serde_json::to_string_pretty(&report)?;
    say!("{text}");
    if let Some(out) = &args.out {
        lgh_image::write_atomic(out, |w| std::io::Write::write_all(w, text.as_bytes()))?;
    }
    Ok(())
}

/// A scene made ready: its lights, the camera and the pixels the references render.
struct Bench<'a> {
    s: &'a Scene,
    lights: ExplosionLights,
    camera: Camera,
    pixels: Vec<[usize; 2]>,
}

/// The path tracer on the pixel subset: a converged image and the ladder of doubling paths
/// (spp, seconds, relative RMSE against the converged image).
struct Ladder {
    converged_s: f64,
    rungs: Vec<(u32, f64, f64)>,
}

impl Bench<'_> {
    /// `method` on the pixel subset with ray-marched shadows, timed (the lights' preparation
    /// and shadows included).
    fn subset(&self, method: Method) -> Result<(Vec<Vec3>, RenderStats, f64), crate::Error> {
        let (s, march) = (self.s, MarchSettings::default());
        let (out, seconds) = time(|| {
            FrameRender::new(&self.lights, method, &s.volume, &s.medium, &march, &())?
                .render_pixels(&self.camera, &self.pixels)
        });
        let (pixels, stats) = out?;
        Ok((pixels, stats, seconds))
    }

    /// The path tracer's converged image of the subset, then doubling paths until 1/16 of it
    /// (the reference's own noise then inflates the measured error by at most
    /// sqrt(1 + 1/16) - 1 = 3%).
    fn ladder(&self, reference_spp: u32) -> Result<Ladder, crate::Error> {
        let s = self.s;
        let pt = |spp: u32| {
            let settings = PathSettings {
                spp,
                max_scatter: 1,
                seed: u64::from(spp),
                ..Default::default()
            };
            let (c, p) = (&self.camera, &self.pixels);
            time(|| pathtrace::render_pixels(&s.volume, &s.medium, c, &settings, p))
        };
        let (converged, converged_s) = pt(reference_spp);
        let converged = converged?;
        let mut rungs = Vec::new();
        let mut spp = 1;
        while spp <= reference_spp / 16 {
            let (img, t) = pt(spp);
            rungs.push((spp, t, rel_rmse(&img?, &converged).unwrap_or(f64::NAN)));
            spp *= 2;
        }
        eprintln!(
            "{}: path tracer, {reference_spp} spp reference in {converged_s:.1} s",
            s.name
        );
        Ok(Ladder { converged_s, rungs })
    }

    /// The row of `alpha`: the whole image with each shadow choice, the subset against brute
    /// force (`brute`, rendered in `brute_s`) and the path tracer's paths to the same error.
    fn alpha_row(
        &self,
        alpha: f32,
        (brute, brute_s): (&[Vec3], f64),
        ladder: &Ladder,
    ) -> Result<Value, crate::Error> {
        // The whole image with ray-marched shadows is one of the shadow choices.
        let choices = shadow_choices(self, alpha)?;
        let (stats, image_s) = (choices.ray_marched, choices.exact_seconds);
        let (sub, _, sub_s) = self.subset(Method::Lgh { alpha })?;
        let err = rel_rmse(&sub, brute).unwrap_or(f64::NAN);
        let matched = ladder.rungs.iter().find(|(_, _, e)| *e <= err);
        // Not reached within the ladder: where the 1/sqrt(spp) noise law puts it, from the
        // last rung (an estimate, reported as such).
        let extrapolated = ladder
            .rungs
            .last()
            .filter(|_| matched.is_none() && err > 0.0)
            .map(|&(spp, t, e)| {
                let k = (e / err).powi(2);
                (f64::from(spp) * k, t * k)
            });
        eprintln!(
            "{}: alpha {alpha}: {image_s:.1} s, {:.0} lights per point, rel RMSE {:.4}",
            self.s.name,
            stats.lights_per_point(),
            err
        );
        let mut row = json!({
            "alpha": alpha,
            "render_seconds": image_s,
            "shading_points": stats.shading_points,
            "lights_per_shading_point": stats.lights_per_point(),
            "shadow_samples_per_light": stats.shadow_samples as f64 / stats.lights_evaluated.max(1) as f64,
            "subset_seconds": sub_s,
            "rel_rmse_vs_brute": err,
            "speedup_vs_brute": brute_s / sub_s,
            "pathtrace_spp_to_match": matched.map(|m| m.0),
            "pathtrace_seconds_to_match": matched.map(|m| m.1),
            "pathtrace_time_ratio": matched.map(|m| m.1 / sub_s),
            "pathtrace_spp_to_match_extrapolated": extrapolated.map(|x| x.0),
            "pathtrace_time_ratio_extrapolated": extrapolated.map(|x| x.1 / sub_s),
            "shadows": choices.shadows,
        });
        if let (Value::Object(row), Value::Object(extra)) = (&mut row, choices.default_path) {
            row.extend(extra);
        }
        Ok(row)
    }
}

fn bench_scene(s: &Scene, args: &ExplosionBenchArgs) -> Result<Value, crate::Error> {
    let (lights, build_s) = time(|| ExplosionLights::new(&[&s.volume], &s.medium));
    let lights = lights?;
    let (lo, hi) = framing_bounds(&[&s.volume]).expect("one frame");
    let camera = Camera::frame_up(lo, hi, args.width, args.height, s.up)?;
    let pixels = pick_pixels(s, &lights, &camera, args.pixels)?;
    if pixels.is_empty() {
        return Err(format!("{}: the image shows no emission", s.name).into());
    }
    eprintln!(
        "{}: {} lights, hierarchy built in {build_s:.3} s",
        s.name,
        lights.lit()
    );
    let b = Bench {
        s,
        lights,
        camera,
        pixels,
    };
    let (brute, brute_stats, brute_s) = b.subset(Method::Brute)?;
    eprintln!(
        "{}: brute force on {} pixels in {brute_s:.1} s",
        s.name,
        b.pixels.len()
    );
    let ladder = b.ladder(args.reference_spp)?;
    let rows = args
        .alphas
        .iter()
        .map(|&alpha| b.alpha_row(alpha, (&brute, brute_s), &ladder))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(json!({
        "scene": s.name,
        "grid": s.volume.density.dims,
        "lights": b.lights.lit(),
        "levels": b.lights.hierarchy().max_level() + 1,
        "build_seconds": build_s,
        "reference_pixels": b.pixels.len(),
        "brute": {
            "subset_seconds": brute_s,
            "lights_per_shading_point": brute_stats.lights_per_point(),
        },
        "pathtrace": {
            "max_scatter": 1,
            "reference_spp": args.reference_spp,
            "reference_seconds": ladder.converged_s,
            "ladder": ladder.rungs.iter().map(|(spp, t, e)| json!({"spp": spp, "seconds": t, "rel_rmse_vs_converged": e})).collect::<Vec<_>>(),
        },
        "alphas": rows,
    }))
}

/// The whole image at `alpha` with each shadow choice of `lgh demo` and `lgh explosion`, in
/// one run: the deep-shadow cube maps (their precompute and the render apart), ray-marched
/// shadows (`MarchSettings::default()`'s: the exact image, uncached), none, and the default
/// path — ray-marched shadows through the lighting cache; the cube maps' and the default path's
/// relative RMSE against the exact image, and the ratios the targets are stated in
/// (`docs/shadows.md`).
/// Also returns the ray-marched render's statistics and seconds, and the default path's
/// comparison with the exact image (`exact`, `speedup_vs_exact`, `rel_rmse_vs_exact`,
/// `lighting_cache`).
fn shadow_choices(b: &Bench, alpha: f32) -> Result<Choices, crate::Error> {
    let (s, lights, camera) = (b.s, &b.lights, &b.camera);
    let mut out = serde_json::Map::new();
    let mut totals = Vec::new();
    let mut images = Vec::new();
    let mut ray_marched = RenderStats::default();
    let mut cache = None;
    let cached = MarchSettings {
        lighting_cache: LightingCacheSettings::coarse(),
        ..MarchSettings::with_shadows(Shadows::RayMarch)
    };
    for (key, settings) in [
        ("cubemap", MarchSettings::with_shadows(Shadows::CubeMap)),
        ("raymarch", MarchSettings::with_shadows(Shadows::RayMarch)),
        ("none", MarchSettings::with_shadows(Shadows::None)),
        ("raymarch_cached", cached),
    ] {
        let lgh = Method::Lgh { alpha };
        let (frame, precompute_s) =
            time(|| FrameRender::new(lights, lgh, &s.volume, &s.medium, &settings, &()));
        let frame = frame?;
        let (image, render_s) = time(|| frame.render(camera, &()));
        let (image, stats) = image?;
        if key == "raymarch" {
            ray_marched = stats;
        }
        if let Some(c) = frame.lighting_cache() {
            cache = Some(c.stats());
        }
        images.push(image);
        totals.push(precompute_s + render_s);
        out.insert(
            key.into(),
            json!({
                "precompute_seconds": precompute_s,
                "render_seconds": render_s,
                "total_seconds": precompute_s + render_s,
            }),
        );
    }
    let vs_exact = |k: usize| rel_rmse(&images[k].pixels, &images[1].pixels);
    out.insert("cubemap_rel_rmse_vs_raymarch".into(), json!(vs_exact(0)));
    out.insert(
        "cubemap_speedup_vs_raymarch".into(),
        json!(totals[1] / totals[0]),
    );
    out.insert("cubemap_over_none".into(), json!(totals[0] / totals[2]));
    let cache = cache.unwrap_or_default();
    let default_path = json!({
        "exact": { "seconds": totals[1] },
        "speedup_vs_exact": totals[1] / totals[3],
        "rel_rmse_vs_exact": vs_exact(3),
        "lighting_cache": {
            "vertices": cache.vertices,
            "seconds": cache.cpu_seconds,
            "rel_rmse_vs_uncached": vs_exact(3),
        },
    });
    Ok(Choices {
        shadows: Value::Object(out),
        ray_marched,
        exact_seconds: totals[1],
        default_path,
    })
}

/// What [`shadow_choices`] measured.
struct Choices {
    /// Each shadow choice's seconds and the ratios between them.
    shadows: Value,
    /// The ray-marched render's statistics.
    ray_marched: RenderStats,
    /// The ray-marched (exact) render's seconds.
    exact_seconds: f64,
    /// The default path (ray-marched shadows through the lighting cache) against the exact
    /// image: `exact`, `speedup_vs_exact`, `rel_rmse_vs_exact`, `lighting_cache`.
    default_path: Value,
}
