//! `lgh bench core`: build and query speed and accuracy of the LGH against brute force, as JSON.

use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::metrics::ErrorStats;
use lgh_core::testsets;
use lgh_core::{falloff, BruteForce, GridSettings, LightingGridHierarchy, PointLight};
use rayon::prelude::*;
use serde_json::{json, Value};

/// Arguments of `lgh bench core`.
#[derive(Debug, clap::Args)]
pub struct CoreBenchArgs {
    /// Light sets: a = 100k uniform, b = ~1M explosion shell on 128³, c = 16,384 light strings.
    #[arg(long, value_delimiter = ',', default_value = "a,b,c")]
    pub sets: Vec<String>,
    /// Query points per set (half inside the lights' bounding box, half around it out to 3× its
    /// size). Each α is timed twice: with the points in random order (every query starts with cold
    /// caches) and sorted along a Morton curve (coherent, as a renderer visits them).
    #[arg(long, default_value_t = 20_000)]
    pub points: usize,
    /// α values to measure.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8")]
    pub alphas: Vec<f32>,
    /// Query points timed for the single-thread brute-force throughput.
    #[arg(long, default_value_t = 500)]
    pub brute_timing_points: usize,
    /// Repetitions of each build and query timing (the minimum is reported).
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Write the JSON here (atomically) as well as to stdout.
    #[arg(long)]
    pub out: Option<std::path::PathBuf>,
    /// Also write the results as a Markdown table (those of `docs/benchmarks.md`) to this file.
    #[arg(long)]
    pub markdown: Option<std::path::PathBuf>,
}

struct Set {
    name: &'static str,
    description: &'static str,
    lights: Vec<PointLight>,
    settings: GridSettings,
}

fn make_set(key: &str) -> Result<Set, crate::Error> {
    Ok(match key {
        "a" => Set {
            name: "a_uniform_100k",
            description: "100,000 lights uniform in the unit cube, random RGB",
            lights: testsets::uniform_cube(100_000, 1),
            settings: GridSettings::default(),
        },
        "b" => Set {
            name: "b_explosion_128",
            description: "explosion-like lights at voxel centres of a turbulent fireball shell on a 128^3 lattice, blackbody colours; h1 = 2 voxels, level-1 vertices on voxel centres",
            lights: testsets::explosion_shell(128),
            settings: GridSettings {
                h1: Some(2.0 / 128.0),
                origin: Some(Vec3::splat(0.5 / 128.0)),
                ..Default::default()
            },
        },
        "c" => Set {
            name: "c_strings_16k",
            description: "16,384 equal lights along 8 long curves (light strings)",
            lights: testsets::light_strings(16_384),
            settings: GridSettings::default(),
        },
        other => return Err(format!("unknown light set '{other}' (use a, b or c)").into()),
    })
}

/// `f()` and the seconds it took.
pub(crate) fn time<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t = Instant::now();
    let v = f();
    (v, t.elapsed().as_secs_f64())
}

fn pool(threads: usize) -> Result<rayon::ThreadPool, crate::Error> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(Into::into)
}

/// Runs the benchmark and prints its JSON report.
pub fn run(args: &CoreBenchArgs) -> Result<(), crate::Error> {
    if args.points == 0 {
        return Err("--points must be at least 1".into());
    }
    for &a in &args.alphas {
        crate::check_alpha(a)?;
    }
    let mut sets = Vec::new();
    for key in &args.sets {
        let (set, gen_s) = time(|| make_set(key));
        let set = set?;
        eprintln!(
            "{}: {} lights generated in {gen_s:.2} s",
            set.name,
            set.lights.len()
        );
        sets.push(bench_set(&set, args)?);
    }
    let report = json!({
        "benchmark": "lgh bench core",
        "threads_available": std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1),
        "sets": sets,
    });
    let text = serde_json::to_string_pretty(&report)?;
    say!("{text}");
    if let Some(out) = &args.out {
        lgh_image::write_atomic(out, |w| w.write_all(text.as_bytes()))?;
    }
    if let Some(md) = &args.markdown {
        let table = markdown(&report);
        lgh_image::write_atomic(md, |w| w.write_all(table.as_bytes()))?;
    }
    Ok(())
}

/// The report as Markdown tables: one row per set for the build, one per set and α for queries.
fn markdown(report: &Value) -> String {
    let f = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let mut out = String::from(
        "| set | lights | levels | build, 1 thread | build, 2 threads | rebuild (new intensities), 2 threads |\n|---|---:|---:|---:|---:|---:|\n",
    );
    let sets = report["sets"].as_array().cloned().unwrap_or_default();
    for s in &sets {
        out += &format!(
            "| {} | {} | 0..={} | {:.3} s | {:.3} s | {:.3} s |\n",
            s["name"].as_str().unwrap_or("?"),
            s["lights"],
            s["max_level"],
            f(&s["build_seconds"]["1"]),
            f(&s["build_seconds"]["2"]),
            f(&s["rebuild_intensities_seconds_2_threads"]),
        );
    }
    out += "\n| set | α | points/s/thread, random order | coherent order | lights per point | relative RMSE | max relative error | speed-up vs brute force |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for s in &sets {
        out += &format!(
            "| {} | brute force | {:.0} | | {} | 0 | 0 | 1× |\n",
            s["name"].as_str().unwrap_or("?"),
            f(&s["brute_force_points_per_second_per_thread"]),
            s["lights"],
        );
        for a in s["alphas"].as_array().cloned().unwrap_or_default() {
            out += &format!(
                "| | {} | {:.0} | {:.0} | {:.0} | {:.2}% | {:.2}% | {:.1}× |\n",
                a["alpha"],
                f(&a["points_per_second_per_thread"]),
                f(&a["points_per_second_per_thread_coherent"]),
                f(&a["lights_per_point"]),
                100.0 * f(&a["rel_rmse"]),
                100.0 * f(&a["max_rel_error"]),
                f(&a["speedup_vs_brute"]),
            );
        }
    }
    out
}

/// Benchmarks one light set: build and rebuild times, brute force, and each α's speed and error.
fn bench_set(set: &Set, args: &CoreBenchArgs) -> Result<Value, crate::Error> {
    let lights = &set.lights;
    let (mut lgh, build_s) = time_builds(set, args.repeat)?;
    let rebuild_s = time_rebuild(&mut lgh, lights, args.repeat)?;
    let levels: Vec<usize> = (0..=lgh.max_level()).map(|l| lgh.level(l).len()).collect();
    let queries = Queries::new(set, lgh.h0(), args)?;
    let per_alpha = args
        .alphas
        .iter()
        .map(|&alpha| queries.measure_alpha(set.name, &lgh, alpha, args.repeat))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(json!({
        "name": set.name,
        "description": set.description,
        "lights": lights.len(),
        "query_points": queries.points.len(),
        "h1": lgh.h1(),
        "max_level": lgh.max_level(),
        "lights_per_level": levels,
        "build_seconds": build_s,
        "rebuild_intensities_seconds_2_threads": rebuild_s,
        "brute_force_points_per_second_per_thread": queries.brute_pps,
        "alphas": per_alpha,
    }))
}

/// Builds the set's hierarchy on 1 and on 2 threads, the best of `repeat` builds each; returns
/// the last hierarchy built and the best seconds by thread count.
fn time_builds(
    set: &Set,
    repeat: usize,
) -> Result<(LightingGridHierarchy, serde_json::Map<String, Value>), crate::Error> {
    let build = || LightingGridHierarchy::build(&set.lights, &set.settings);
    let mut build_s = serde_json::Map::new();
    let mut lgh = None;
    for threads in [1usize, 2] {
        let p = pool(threads)?;
        let mut best = f64::INFINITY;
        for _ in 0..repeat.max(1) {
            let (h, s) = p.install(|| time(build));
            best = best.min(s);
            lgh = Some(h?);
        }
        build_s.insert(threads.to_string(), json!(best));
    }
    Ok((lgh.expect("built at least once"), build_s))
}

/// The best of `repeat` rebuilds of `lgh` with new intensities (the same positions) on 2
/// threads, in seconds; `lgh` is left with the `lights`' own intensities.
fn time_rebuild(
    lgh: &mut LightingGridHierarchy,
    lights: &[PointLight],
    repeat: usize,
) -> Result<f64, crate::Error> {
    let scaled: Vec<Vec3> = lights.iter().map(|l| l.intensity * 1.5).collect();
    let p2 = pool(2)?;
    let mut rebuild_s = f64::INFINITY;
    for _ in 0..repeat.max(1) {
        let (r, s) = p2.install(|| time(|| lgh.update_intensities(&scaled)));
        r?;
        rebuild_s = rebuild_s.min(s);
    }
    let unscaled: Vec<Vec3> = lights.iter().map(|l| l.intensity).collect();
    lgh.update_intensities(&unscaled)?;
    Ok(rebuild_s)
}

/// A set's query points, in random and in coherent order, with brute force's answer at each
/// and its single-thread throughput.
struct Queries {
    points: Vec<Vec3>,
    /// The same points in a spatially coherent order, as a renderer visits them (tiles of
    /// pixels, steps along rays): sorted along a Morton curve.
    coherent: Vec<Vec3>,
    /// Brute force's `L(x)` at each of `points`.
    reference: Vec<Vec3>,
    /// Brute force's points per second on one thread.
    brute_pps: f64,
}

impl Queries {
    /// The query points around `set`'s lights; brute force (fall-off clamped at `h0`) timed on
    /// one thread over a prefix of them, then its reference at every point.
    fn new(set: &Set, h0: f32, args: &CoreBenchArgs) -> Result<Self, crate::Error> {
        let (lo, hi) = lgh_core::bounds(&set.lights);
        let points = testsets::query_points(lo, hi, args.points, 42);
        let brute = BruteForce::new(&set.lights)?;
        let timed = &points[..args.brute_timing_points.clamp(1, points.len())];
        let (_, brute_s) = time(|| {
            timed
                .iter()
                .map(|&x| brute.falloff_sum(x, h0).map(|v| v.x))
                .sum::<Result<f32, _>>()
        });
        let brute_pps = timed.len() as f64 / brute_s;
        eprintln!(
            "{}: brute force {:.0} points/s/thread; computing the reference on {} points",
            set.name,
            brute_pps,
            points.len()
        );
        let reference: Vec<Vec3> = points
            .par_iter()
            .map(|&x| brute.falloff_sum(x, h0))
            .collect::<Result<_, _>>()?;
        let coherent = morton_sorted(&points);
        Ok(Queries {
            points,
            coherent,
            reference,
            brute_pps,
        })
    }

    /// One α's record: single-thread throughput (the best of `repeat` passes over all points,
    /// in each order), lights evaluated per point, and the error against brute force.
    fn measure_alpha(
        &self,
        name: &str,
        lgh: &LightingGridHierarchy,
        alpha: f32,
        repeat: usize,
    ) -> Result<Value, crate::Error> {
        let points = &self.points;
        let b = lgh.blending(alpha)?;
        let (values, evaluated, secs) = time_queries(lgh, &b, points, repeat)?;
        let (_, _, coherent_secs) = time_queries(lgh, &b, &self.coherent, repeat)?;
        let err = ErrorStats::compare(&values, &self.reference).ok_or("empty comparison")?;
        let pps = points.len() as f64 / secs;
        let coherent_pps = points.len() as f64 / coherent_secs;
        eprintln!(
            "{name}: alpha {alpha}: {pps:.0} points/s/thread ({coherent_pps:.0} in coherent order), {:.0} lights/point, rel RMSE {:.3e}",
            evaluated as f64 / points.len() as f64,
            err.rel_rmse
        );
        Ok(json!({
            "alpha": alpha,
            "points_per_second_per_thread": pps,
            "points_per_second_per_thread_coherent": coherent_pps,
            "lights_per_point": evaluated as f64 / points.len() as f64,
            "rel_rmse": err.rel_rmse,
            "max_rel_error": err.max_rel,
            "speedup_vs_brute": pps / self.brute_pps,
        }))
    }
}

/// Probe values `L(x) = Σ B·I·g(d)` at `points` on one thread, the lights evaluated in all, and
/// the best time of `repeat` passes.
fn time_queries(
    lgh: &LightingGridHierarchy,
    blending: &lgh_core::Blending,
    points: &[Vec3],
    repeat: usize,
) -> Result<(Vec<Vec3>, u64, f64), crate::Error> {
    let h0 = lgh.h0();
    let mut best = (Vec::new(), 0, f64::INFINITY);
    for _ in 0..repeat.max(1) {
        let (r, secs) = time(|| -> Result<(Vec<Vec3>, u64), crate::Error> {
            let mut values = Vec::with_capacity(points.len());
            let mut evaluated = 0u64;
            for &x in points {
                let (sum, n) =
                    lgh.query_sum(x, blending, |s| s.intensity * falloff(s.distance, h0))?;
                evaluated += n as u64;
                values.push(sum);
            }
            Ok((values, evaluated))
        });
        let (values, evaluated) = r?;
        if secs < best.2 {
            best = (values, evaluated, secs);
        }
    }
    Ok(best)
}

/// `points` sorted along a Morton (Z-order) curve over their bounding box, 2^10 cells per axis.
fn morton_sorted(points: &[Vec3]) -> Vec<Vec3> {
    let (lo, hi) = points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let scale = 1023.0 / (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let key = |p: Vec3| lgh_core::morton::encode(((p - lo) * scale).to_array().map(|v| v as u32));
    let mut sorted = points.to_vec();
    sorted.sort_by_key(|&p| key(p));
    sorted
}
