//! `lgh bench table1`: the paper's Table 1 for one frame of the procedural explosion (the
//! demo's scene, [`lgh_volume::procedural::explosion`]) — lights per level, deep-shadow
//! cube-map bytes per level, precompute and render seconds — and the same frame rendered with
//! the other shadows (ray-marched, none) in the same run, so that the speed-ups are ratios of
//! one machine's times. JSON on stdout (and `--out`), a markdown table with `--markdown`.

use std::path::PathBuf;
use std::time::Instant;

use lgh_volume::render::MarchSettings;
use lgh_volume::{Method, Shadows};
use serde_json::{json, Value};

use crate::demo::{Scene, SceneArgs};
use crate::output::{MarchArgs, Shadowing};

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
    pub compare: Vec<Shadows>,
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
    let march = args.march.settings(crate::demo::DEMO_SHADOW_STEP)?;
    let Scene {
        volume,
        medium,
        mut lights,
        camera,
        volume_seconds: volume_s,
        lights_seconds: hierarchy_s,
    } = args.scene.build()?;
    lights.set_prune(args.march.prune)?;
    let scene = &args.scene;

    let mut runs = Vec::new();
    let mut choices = vec![march.shadows];
    choices.extend(args.compare.iter().filter(|&&s| s != march.shadows));
    for shadows in choices {
        let settings = MarchSettings { shadows, ..march };
        let shadowing = Shadowing::prepare(
            &lights,
            Method::Lgh,
            scene.alpha,
            &volume,
            &medium,
            &settings,
            true,
        )?;
        let precompute = shadowing.seconds;
        let table = shadowing.cube_maps().map(|m| m.table().to_vec());
        let t = Instant::now();
        let (image, stats) = shadowing.render(
            &lights,
            Method::Lgh,
            scene.alpha,
            &volume,
            &medium,
            &camera,
            &settings,
            None,
            &|_| {},
        )?;
        let render = t.elapsed().as_secs_f64();
        eprintln!(
            "  {}: precompute {precompute:.2} s, render {render:.2} s",
            shadows.name()
        );
        runs.push(Run {
            shadows,
            precompute,
            render,
            image,
            table,
            stats,
        });
    }

    let first = &runs[0];
    let mut shadows = serde_json::Map::new();
    for r in &runs {
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
    let h = lights.hierarchy();
    let lights_per_level: Vec<usize> = (0..=h.max_level())
        .map(|l| h.level(l).iter().filter(|g| h.is_active(l, g)).count())
        .collect();
    let report = json!({
        "scene": {
            "kind": "procedural explosion",
            "resolution": scene.resolution,
            "voxels": volume.density.data.len(),
            "time": scene.time,
            "lights": lights.lit(),
        },
        "alpha": scene.alpha,
        "prune": args.march.prune,
        "width": scene.width,
        "height": scene.height,
        "threads": rayon::current_num_threads(),
        "volume_seconds": volume_s,
        "hierarchy_seconds": hierarchy_s,
        "lights_per_level": lights_per_level,
        "shadows": shadows,
        "first": first.shadows.name(),
        "cube_maps": levels,
        "shadow_bytes": first.table.as_ref().map(|t| t.iter().map(|l| l.bytes).sum::<u64>()),
        "peak_memory_bytes": peak_memory(),
    });
    let text = serde_json::to_string_pretty(&report)?;
    say!("{text}");
    if let Some(out) = &args.out {
        lgh_image::write_atomic(out, |w| std::io::Write::write_all(w, text.as_bytes()))?;
    }
    if args.markdown {
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
        for r in &runs {
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
