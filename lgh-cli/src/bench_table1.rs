//! `lgh bench table1`: the paper's Table 1 for one frame of the procedural explosion (the
//! demo's scene, [`lgh_volume::procedural::explosion`]) — lights per level, deep-shadow
//! cube-map bytes per level, precompute and render seconds — and the same frame rendered with
//! the other shadows (ray-marched, none) in the same run, so that the speed-ups are ratios of
//! one machine's times. JSON on stdout (and `--out`), a markdown table with `--markdown`.

use std::path::PathBuf;
use std::time::Instant;

use lgh_volume::lighting_cache::{CacheStats, LightingCacheSettings, RenderedLights};
use lgh_volume::render::MarchSettings;
use lgh_volume::{FrameRender, Method, Shadows};
use serde_json::{json, Value};

use crate::demo::{Scene, SceneArgs};
use crate::output::{MarchArgs, ScatterArgs, ShadowsArg};

/// Arguments of `lgh bench table1`.
#[derive(Debug, clap::Args)]
pub struct Table1Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The frame is also rendered with these shadows, without the lighting cache, for the
    /// ratios; ray-marched shadows (the exact image) always are. The cube maps' run gives the
    /// Table-1 rows.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "cubemap,raymarch,none"
    )]
    pub compare: Vec<ShadowsArg>,
    #[command(flatten)]
    pub march: MarchArgs,
    /// Print a markdown table after the JSON.
    #[arg(long)]
    pub markdown: bool,
    /// Write the JSON here (atomically) as well as to stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// One shadow choice's render of the frame.
struct Run {
    shadows: Shadows,
    /// The lighting cache's work, if the run had one.
    cache: Option<CacheStats>,
    /// Seconds making the visibility (the cube maps' tracing).
    precompute: f64,
    /// Seconds rendering.
    render: f64,
    image: lgh_image::Image,
    /// The cube maps' Table-1 rows, for cube maps.
    table: Option<Vec<lgh_volume::shadow::LevelMaps>>,
    stats: lgh_volume::render::RenderStats,
}

impl Run {
    fn total(&self) -> f64 {
        self.precompute + self.render
    }

    /// The run's key in the JSON: the shadows' name, `_cached` through the lighting cache.
    fn name(&self) -> String {
        let cached = if self.cache.is_some() { "_cached" } else { "" };
        format!("{}{cached}", self.shadows.name())
    }
}

/// Peak resident memory of this process so far, bytes (Linux; `None` elsewhere).
fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    Some(line.split_whitespace().nth(1)?.parse::<u64>().ok()? * 1024)
}

/// Runs the benchmark.
pub fn run(args: &Table1Args) -> Result<(), crate::Error> {
    args.scene.check()?;
    let march = args
        .march
        .settings(crate::demo::DEMO_DEFAULTS, &ScatterArgs::default())?;
    let mut scene = args.scene.build(args.march.near_field.into())?;
    scene
        .lights
        .set_coarse_spread(args.march.coarse_spread.into());
    let march = scene.for_camera(&args.march, march);
    scene.lights.set_prune(args.march.prune)?;
    scene.lights.set_coarse_shadows(args.march.coarse_shadows());
    // The args' settings first, then each comparison without the cache (the exact image, the
    // ray-marched one, always among them).
    let uncached = |shadows| MarchSettings {
        shadows,
        lighting_cache: LightingCacheSettings::default(),
        ..march
    };
    let mut choices = vec![march];
    let compare = args.compare.iter().map(|&s| Shadows::from(s));
    for settings in compare.chain([Shadows::RayMarch]).map(uncached) {
        if !choices.contains(&settings) {
            choices.push(settings);
        }
    }
    let runs = choices
        .iter()
        .map(|settings| Run::of(&scene, args.scene.alpha, settings))
        .collect::<Result<Vec<_>, _>>()?;
    let report = report(args, &scene, &runs, &march);
    let text = serde_json::to_string_pretty(&report)?;
    say!("{text}");
    if let Some(out) = &args.out {
        lgh_image::write_atomic(out, |w| std::io::Write::write_all(w, text.as_bytes()))?;
    }
    if args.markdown {
        markdown(&runs)?;
    }
    Ok(())
}

impl Run {
    /// The scene's frame through the hierarchy at `alpha` with `settings`' shadows.
    fn of(scene: &Scene, alpha: f32, settings: &MarchSettings) -> Result<Run, crate::Error> {
        let (volume, medium) = (&scene.volume, &scene.medium);
        let lgh = Method::Lgh { alpha };
        let frame = FrameRender::new(&scene.lights, lgh, volume, medium, settings, &())?;
        let precompute = frame.seconds().shadows;
        let table = frame.cube_maps().map(|m| m.table().to_vec());
        let t = Instant::now();
        let (image, stats) = frame.render(&scene.camera, &())?;
        let render = t.elapsed().as_secs_f64();
        let shadows = settings.shadows;
        let cache = frame.lighting_cache().map(|c| c.stats());
        let run = Run {
            shadows,
            cache,
            precompute,
            render,
            image,
            table,
            stats,
        };
        eprintln!(
            "  {}: precompute {precompute:.2} s, render {render:.2} s",
            run.name()
        );
        Ok(run)
    }
}

/// The benchmark's JSON; `march`, the first run's settings (its cube maps' are every run's).
fn report(args: &Table1Args, scene: &Scene, runs: &[Run], march: &MarchSettings) -> Value {
    let storage = &march.cube_maps;
    let first = &runs[0];
    let mut shadows = serde_json::Map::new();
    for r in runs {
        let mut o = json!({
            "precompute_seconds": r.precompute,
            "render_seconds": r.render,
            "total_seconds": r.total(),
            "lights_per_shading_point": r.stats.lights_per_point(),
        });
        if !std::ptr::eq(r, first) {
            let err = lgh_image::compare(&first.image, &r.image).map(|e| e.rel_rmse);
            o["rel_rmse_of_first_against_this"] = json!(err);
            o["first_speedup"] = json!(r.total() / first.total());
        }
        shadows.insert(r.name(), o);
    }
    let vs = |r: &Run| lgh_image::compare(&first.image, &r.image).map(|e| e.rel_rmse);
    let uncached = |s: Shadows| runs.iter().find(|r| r.shadows == s && r.cache.is_none());
    let exact = uncached(Shadows::RayMarch).expect("always rendered");
    let maps = runs.iter().find_map(|r| r.table.as_ref());
    let levels: Vec<Value> = maps.map_or(Vec::new(), |table| {
        table
            .iter()
            .map(|l| {
                json!({
                    "level": l.level,
                    "lights": l.lights,
                    "cells": l.cells,
                    "texels": l.texels,
                    "tiles": l.tiles,
                    "shadow_bytes": l.bytes,
                    "density_samples": l.samples,
                    "precompute_seconds": l.seconds,
                })
            })
            .collect()
    });
    let (lights, volume, table) = (&scene.lights, &scene.volume, &args.scene);
    let h = lights.hierarchy();
    let lights_per_level: Vec<usize> = (0..=h.max_level())
        .map(|l| h.level(l).iter().filter(|g| h.is_active(l, g)).count())
        .collect();
    json!({
        "scene": {
            "kind": "procedural explosion",
            "resolution": table.resolution,
            "voxels": volume.density.data.len(),
            "time": table.time,
            "lights": lights.lit(),
        },
        "alpha": table.alpha,
        "prune": args.march.prune,
        "width": table.width,
        "height": table.height,
        "threads": rayon::current_num_threads(),
        "volume_seconds": scene.volume_seconds,
        "hierarchy_seconds": scene.lights_seconds,
        "lights_per_level": lights_per_level,
        "shadows": shadows,
        "first": first.name(),
        "exact": { "seconds": exact.total() },
        "speedup_vs_exact": exact.total() / first.total(),
        "rel_rmse_vs_exact": vs(exact),
        "core_seconds": first.total() * rayon::current_num_threads() as f64,
        "lighting_cache": first.cache.map(|c| json!({
            "first_level": march.lighting_cache.first_level,
            // No multiple scattering here: `auto` is the emission lights' form.
            "level0": march.lighting_cache.level0.for_lights(RenderedLights::Emission).name(),
            "level0_near": march.lighting_cache.near_reach,
            "vertices": c.vertices,
            "seconds": c.cpu_seconds,
            "rel_rmse_vs_uncached": uncached(first.shadows).and_then(vs),
        })),
        "cube_maps": levels,
        "shadow_storage": { "kind": storage.depths.name(), "per_texel": storage.depth_count },
        "shadow_bytes": maps.map(|t| t.iter().map(|l| l.bytes).sum::<u64>()),
        "peak_memory_bytes": peak_memory(),
    })
}

/// The markdown table: the cube maps per level, then each shadow choice's seconds.
fn markdown(runs: &[Run]) -> Result<(), crate::Error> {
    {
        say!("");
        say!("| level | lights | tiles | cube-map bytes | precompute s |");
        say!("|---|---|---|---|---|");
        for l in runs
            .iter()
            .find_map(|r| r.table.as_ref())
            .into_iter()
            .flatten()
        {
            say!(
                "| S{} | {} | {} | {:.1} MB | {:.2} |",
                l.level,
                l.lights,
                l.tiles,
                l.bytes as f64 / 1e6,
                l.seconds
            );
        }
        for r in runs {
            say!(
                "| {} | | | precompute {:.1} s | render {:.1} s |",
                r.name(),
                r.precompute,
                r.render
            );
        }
    }
    Ok(())
}
