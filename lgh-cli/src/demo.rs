//! `lgh demo`: bakes light probes around the built-in explosion-like light set and reports accuracy
//! and speed against brute force. (The explosion rendering demo replaces this once lgh-volume lands.)

use std::path::PathBuf;
use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::metrics::ErrorStats;
use lgh_core::{testsets, BruteForce, GridSettings, LghBackend, LightingGridHierarchy};
use rayon::prelude::*;

use crate::{ply, probes, progress};

/// Arguments of `lgh demo`.
#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// Where to write the baked probes (binary PLY with x, y, z, r, g, b).
    #[arg(long, default_value = "demo-probes.ply")]
    pub out: PathBuf,
    /// Lattice resolution of the built-in fireball (lights at voxel centres).
    #[arg(long, default_value_t = 96)]
    pub resolution: u32,
    /// Probes per axis of the probe grid (which extends 25% beyond the fireball).
    #[arg(long, default_value_t = 48)]
    pub probes: u32,
    /// The paper's α.
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true)]
    pub alpha: f32,
    /// Don't show progress.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs the demo.
pub fn run(args: &DemoArgs) -> Result<(), String> {
    crate::check_alpha(args.alpha)?;
    if !(16..=512).contains(&args.resolution) {
        return Err("--resolution must be in 16..=512".into());
    }
    if !(2..=512).contains(&args.probes) {
        return Err("--probes must be in 2..=512".into());
    }
    let res = args.resolution;
    let t = Instant::now();
    let lights = testsets::explosion_shell(res);
    let gen_s = t.elapsed().as_secs_f64();
    let settings = GridSettings {
        h1: Some(2.0 / res as f32),
        origin: Some(Vec3::splat(0.5 / res as f32)),
        ..Default::default()
    };
    let t = Instant::now();
    let lgh = LightingGridHierarchy::build(&lights, &settings).map_err(|e| e.to_string())?;
    let build_s = t.elapsed().as_secs_f64();

    let n = args.probes;
    let points: Vec<Vec3> = (0..n * n * n)
        .map(|i| {
            let c = Vec3::new((i % n) as f32, ((i / n) % n) as f32, (i / (n * n)) as f32);
            Vec3::splat(-0.25) + c / (n - 1) as f32 * 1.5
        })
        .collect();
    let backend = LghBackend::new(&lgh, args.alpha).map_err(|e| e.to_string())?;
    let bar = progress::bar(points.len() as u64, "probes", args.quiet);
    let t = Instant::now();
    let (values, evaluated) = probes::evaluate(&backend, &points, lgh.h0(), &bar)?;
    let probe_s = t.elapsed().as_secs_f64();
    bar.finish_and_clear();

    // Brute force on an evenly spread subset of the probes.
    let stride = (points.len() / 1000).max(1);
    let subset: Vec<usize> = (0..points.len()).step_by(stride).collect();
    let brute = BruteForce::new(&lights).map_err(|e| e.to_string())?;
    let t = Instant::now();
    let reference: Vec<Vec3> = subset
        .par_iter()
        .map(|&i| brute.falloff_sum(points[i], lgh.h0()))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    let brute_s = t.elapsed().as_secs_f64();
    let approx: Vec<Vec3> = subset.iter().map(|&i| values[i]).collect();
    let err = ErrorStats::compare(&approx, &reference).ok_or("no probes")?;

    let mut cloud = ply::PointCloud::default();
    for (c, name) in ["x", "y", "z", "r", "g", "b"].iter().enumerate() {
        cloud.props.push((name.to_string(), ply::Scalar::F32));
        let col = if c < 3 {
            points.iter().map(|p| p[c] as f64).collect()
        } else {
            values.iter().map(|v| v[c - 3] as f64).collect()
        };
        cloud.columns.push(col);
    }
    lgh_image::write_atomic(&args.out, |w| ply::write(w, &cloud))?;

    let brute_per_probe = brute_s / subset.len() as f64;
    let lgh_per_probe = probe_s / points.len() as f64;
    say!("lgh demo: light probes around a procedural fireball");
    say!(
        "  lights      {} (fireball shell on a {res}^3 lattice, generated in {gen_s:.2} s)",
        lights.len()
    );
    say!(
        "  hierarchy   h1 = {:.5}, levels 0..={}, lights per level {:?}, built in {build_s:.3} s",
        lgh.h1(),
        lgh.max_level(),
        (0..=lgh.max_level())
            .map(|l| lgh.level(l).len())
            .collect::<Vec<_>>()
    );
    say!(
        "  probes      {} on a {n}^3 grid, alpha {}: {:.0} lights evaluated per probe, {probe_s:.2} s",
        points.len(),
        args.alpha,
        evaluated as f64 / points.len() as f64
    );
    say!(
        "  accuracy    relative RMSE {:.3}% and max relative error {:.3}% against brute force on {} probes",
        100.0 * err.rel_rmse,
        100.0 * err.max_rel,
        subset.len()
    );
    say!(
        "  speed       {:.1}x faster than brute force per probe (same threads)",
        brute_per_probe / lgh_per_probe
    );
    say!("  output      {}", args.out.display());
    Ok(())
}
