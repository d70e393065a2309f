//! `lgh bench table1`: the paper's Table 1 for one frame of the procedural explosion (the
//! demo's scene, [`lgh_volume::procedural::explosion`]) — lights per level, deep-shadow
//! cube-map bytes per level, precompute and render seconds — and the same frame rendered with
//! the other shadows (ray-marched, none) in the same run, so that the speed-ups are ratios of
//! one machine's times. JSON on stdout (and `--out`), a markdown table with `--markdown`.

use std::path::PathBuf;
use std::time::Instant;

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
    /// The frame is also rendered with these shadows, for the ratios (empty: none).
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "raymarch,none"
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
        .settings(crate::demo::DEMO_SHADOW_STEP, &ScatterArgs::default())?;
    let mut scene = args.scene.build()?;
    scene.lights.set_prune(args.march.prune)?;
    scene.lights.set_coarse_shadows(args.march.coarse_shadows());
    let mut choices = vec![march.shadows];
    let compare = args.compare.iter().map(|&s| Shadows::from(s));
    choices.extend(compare.filter(|&s| s != march.shadows));
    let runs = choices
        .into_iter()
        .map(|shadows| {
            Run::of(
                &scene,
                args.scene.alpha,
                &MarchSettings { shadows, ..march },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let report = report(args, &scene, &runs);
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
        eprintln!(
            "  {}: precompute {precompute:.2} s, render {render:.2} s",
            shadows.name()
        );
        Ok(Run {
            shadows,
            precompute,
            render,
            image,
            table,
            stats,
        })
    }
}

/// The benchmark's JSON.
fn report(args: &Table1Args, scene: &Scene, runs: &[Run]) -> Value {
    let first = &runs[0];
    let mut shadows = serde_json::Map::new();
    for r in runs {
        let mut o = json!({
            "precompute_seconds": r.precompute,
            "render_seconds": r.render,
            "total_seconds": r.total(),
            "lights_per_shading_point": r.stats.lights_per_point(),
        });
        if r.shadows != first.shadows {
            let err = lgh_image::compare(&first.image, &r.image).map(|e| e.rel_rmse);
            o["rel_rmse_of_first_against_this"] = json!(err);
            o["first_speedup"] = json!(r.total() / first.total());
        }
        shadows.insert(r.shadows.name().to_string(), o);
    }
    let levels: Vec<Value> = first.table.as_ref().map_or(Vec::new(), |table| {
        table
            .iter()
            .map(|l| {
                json!({
                    "level": l.level,
                    "lights": l.lights,
                    "cells": l.cells,
                    "texels": l.texels,
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
        "first": first.shadows.name(),
        "cube_maps": levels,
        "shadow_bytes": first.table.as_ref().map(|t| t.iter().map(|l| l.bytes).sum::<u64>()),
        "peak_memory_bytes": peak_memory(),
    })
}

/// The markdown table: the cube maps per level, then each shadow choice's seconds.
fn markdown(runs: &[Run]) -> Result<(), crate::Error> {
    let first = &runs[0];
    {
        say!("");
        say!("| level | lights | cube-map bytes | precompute s |");
        say!("|---|---|---|---|");
        for l in first.table.iter().flatten() {
            say!(
                "| S{} | {} | {:.1} MB | {:.2} |",
                l.level,
                l.lights,
                l.bytes as f64 / 1e6,
                l.seconds
            );
        }
        for r in runs {
            say!(
                "| {} | | precompute {:.1} s | render {:.1} s |",
                r.shadows.name(),
                r.precompute,
                r.render
            );
        }
    }
    Ok(())
}
