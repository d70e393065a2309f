//! `lgh probes`: unshadowed light-probe baking, `L(x) = Σ B·I·g(d)` at every point.

use std::path::PathBuf;
use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::{
    BruteForce, GridSettings, LghBackend, LightingGridHierarchy, ManyLights, PointLight,
};
use rayon::prelude::*;

use crate::progress;
use lgh_ply as ply;

/// The many-lights method of the probes (`--backend`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ProbeBackend {
    /// The lighting grid hierarchy (paper Sec. 3) at the paper's α.
    Lgh,
    /// Every light: the exact answer of the same light model.
    Brute,
    /// Lightcuts (Walter et al. 2005) at 2%, representatives drawn at random.
    Lightcuts,
    /// Lightcuts with each cluster's brightest light as its representative: no randomness.
    LightcutsDeterministic,
}

/// Arguments of `lgh probes`.
#[derive(Debug, clap::Args)]
pub struct ProbesArgs {
    /// Lights: PLY point cloud with float x, y, z and r, g, b (radiant intensity, W/sr).
    #[arg(long, value_name = "L.ply")]
    pub lights: PathBuf,
    /// Probe positions: PLY point cloud with float x, y, z (other properties are kept).
    #[arg(long, value_name = "P.ply")]
    pub points: PathBuf,
    /// The paper's α: influence radius r_ℓ = α h_ℓ (larger is more accurate and slower).
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true)]
    pub alpha: f32,
    /// Output: the probe points with float r, g, b added (binary PLY, written atomically).
    #[arg(long, value_name = "OUT.ply")]
    pub out: PathBuf,
    /// Many-lights backend.
    #[arg(long, value_enum, default_value_t = ProbeBackend::Lgh)]
    pub backend: ProbeBackend,
    /// Level-1 grid spacing h1 (default: chosen from the lights, paper Sec. 6.4).
    #[arg(long)]
    pub h1: Option<f32>,
    /// Top level ℓ_max (default: the lowest level holding all lights in one cell).
    #[arg(long)]
    pub max_level: Option<u8>,
    /// Don't show progress.
    #[arg(long)]
    pub quiet: bool,
}

/// Reads the lights of a PLY file.
pub fn read_lights(path: &std::path::Path) -> Result<Vec<PointLight>, crate::Error> {
    let cloud = ply::read(path)?;
    let col = |n: &str| {
        cloud.float_column(n).map_err(|e| {
            format!(
                "{}: {e} (lights need float x, y, z, r, g, b)",
                path.display()
            )
        })
    };
    let (x, y, z, r, g, b) = (
        col("x")?,
        col("y")?,
        col("z")?,
        col("r")?,
        col("g")?,
        col("b")?,
    );
    Ok((0..cloud.len())
        .map(|i| {
            PointLight::new(
                Vec3::new(x[i] as f32, y[i] as f32, z[i] as f32),
                Vec3::new(r[i] as f32, g[i] as f32, b[i] as f32),
            )
        })
        .collect())
}

/// Runs `lgh probes`.
pub fn run(args: &ProbesArgs) -> Result<(), crate::Error> {
    crate::check_alpha(args.alpha)?;
    let t0 = Instant::now();
    let lights = read_lights(&args.lights)?;
    let mut cloud = ply::read(&args.points)?;
    let points = probe_positions(&cloud, &args.points)?;
    let read_s = t0.elapsed().as_secs_f64();
    let settings = GridSettings {
        h1: args.h1,
        max_level: args.max_level,
        ..Default::default()
    };
    let t1 = Instant::now();
    let lgh =
        LightingGridHierarchy::build(&lights, &settings).map_err(|e| in_lights(&args.lights, e))?;
    let build_s = t1.elapsed().as_secs_f64();
    let bar = progress::bar(points.len() as u64, "probes", args.quiet);
    let t2 = Instant::now();
    let (values, evaluated) = evaluate_backend(args, &lights, &lgh, &points, &bar)?;
    bar.finish_and_clear();
    let eval_s = t2.elapsed().as_secs_f64();
    replace_rgb(&mut cloud, &values);
    lgh_image::write_atomic(&args.out, |w| ply::write(w, &cloud))?;
    say!(
        "{} probes from {} lights with {} (alpha {}, h1 {:.4}, levels 0..={}): {:.1} lights per probe; read {:.2} s, build {:.3} s, evaluate {:.3} s -> {}",
        points.len(),
        lights.len(),
        backend_name(args.backend),
        args.alpha,
        lgh.h1(),
        lgh.max_level(),
        evaluated as f64 / points.len().max(1) as f64,
        read_s,
        build_s,
        eval_s,
        args.out.display()
    );
    Ok(())
}

/// The probe positions of `cloud`, read from `path`: its float x, y, z, each finite.
fn probe_positions(
    cloud: &ply::PointCloud,
    path: &std::path::Path,
) -> Result<Vec<Vec3>, crate::Error> {
    let col = |n: &str| {
        cloud
            .float_column(n)
            .map_err(|e| format!("{}: {e} (points need float x, y, z)", path.display()))
    };
    let (x, y, z) = (col("x")?, col("y")?, col("z")?);
    let points: Vec<Vec3> = (0..cloud.len())
        .map(|i| Vec3::new(x[i] as f32, y[i] as f32, z[i] as f32))
        .collect();
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(format!("{}: point {i} is not finite", path.display()).into());
    }
    Ok(points)
}

/// A build error of the lights read from `path`, naming the file.
#[must_use]
fn in_lights(path: &std::path::Path, e: lgh_core::BuildError) -> String {
    format!("{}: {e}", path.display())
}

/// `L(x)` at every point with the `--backend` of `args` (`lgh` at its α, or one built over
/// `lights`), and the total number of lights evaluated.
fn evaluate_backend(
    args: &ProbesArgs,
    lights: &[PointLight],
    lgh: &LightingGridHierarchy,
    points: &[Vec3],
    bar: &indicatif::ProgressBar,
) -> Result<(Vec<Vec3>, u64), crate::Error> {
    let h0 = lgh.h0();
    match args.backend {
        ProbeBackend::Lgh => {
            let backend = LghBackend::new(lgh, args.alpha)?;
            evaluate(&backend, points, h0, bar)
        }
        ProbeBackend::Brute => {
            let backend = BruteForce::new(lights).map_err(|e| in_lights(&args.lights, e))?;
            evaluate(&backend, points, h0, bar)
        }
        ProbeBackend::Lightcuts | ProbeBackend::LightcutsDeterministic => {
            let representative = match args.backend {
                ProbeBackend::Lightcuts => lgh_core::Representative::Stochastic { seed: 0 },
                _ => lgh_core::Representative::Brightest,
            };
            let tree = lgh_core::LightTree::build(lights, representative)
                .map_err(|e| in_lights(&args.lights, e))?;
            let backend = lgh_core::LightcutsBackend::new(&tree, Default::default())?;
            evaluate(&backend, points, h0, bar)
        }
    }
}

/// Replaces `cloud`'s r, g, b properties, if any, with float r, g, b columns of `values`.
fn replace_rgb(cloud: &mut ply::PointCloud, values: &[Vec3]) {
    for name in ["r", "g", "b"] {
        if let Some(k) = cloud.props.iter().position(|(n, _)| n == name) {
            cloud.props.remove(k);
            cloud.columns.remove(k);
        }
    }
    for (c, name) in ["r", "g", "b"].iter().enumerate() {
        cloud.props.push((name.to_string(), ply::Scalar::F32));
        cloud
            .columns
            .push(values.iter().map(|v| v[c] as f64).collect());
    }
}

/// The name of `backend` in the summary line.
#[must_use]
fn backend_name(backend: ProbeBackend) -> &'static str {
    match backend {
        ProbeBackend::Brute => "brute force",
        ProbeBackend::Lgh => "lgh",
        ProbeBackend::Lightcuts => "lightcuts",
        ProbeBackend::LightcutsDeterministic => "lightcuts-deterministic",
    }
}

/// `L(x)` at every point in parallel (deterministic: each point is independent), and the total
/// number of lights evaluated.
pub fn evaluate<B: ManyLights + Sync>(
    backend: &B,
    points: &[Vec3],
    h0: f32,
    bar: &indicatif::ProgressBar,
) -> Result<(Vec<Vec3>, u64), crate::Error> {
    let out: Result<Vec<(Vec3, u32)>, lgh_core::QueryError> = points
        .par_chunks(1024)
        .flat_map_iter(|chunk| {
            let r: Vec<_> = chunk
                .iter()
                .map(|&x| lgh_core::probe(backend, x, h0).map(|i| (i.radiance, i.lights)))
                .collect();
            bar.inc(chunk.len() as u64);
            r
        })
        .collect();
    let out = out?;
    let evaluated = out.iter().map(|v| v.1 as u64).sum();
    Ok((out.into_iter().map(|v| v.0).collect(), evaluated))
}
