//! `lgh bench flicker`: temporal flicker of a sequence (the paper's Figs. 9, 10, Sec. 6.1),
//! the hierarchy against Lightcuts and against the paper's flickering variants, as JSON (and a
//! markdown table).
//!
//! Every method renders the same frames and pixels; brute force over every light with
//! ray-marched shadows is the reference of each frame (the exact answer of the same light
//! model). Flicker is `mean_t mean_px |(A_t − R_t) − (A_{t−1} − R_{t−1})| / mean |R|` (ARCHITECTURE.md
//! "Measuring", [`lgh_image::flicker`]): the change of the error from frame to frame, so a
//! constant bias does not count; the error is the mean over frames of the relative RMSE.

use std::path::PathBuf;
use std::time::Instant;

use lgh_core::{Clustering, LightPosition};
use lgh_image::Image;
use lgh_volume::cache::{self, GridNames};
use lgh_volume::medium::{framing_bounds, Medium, Volume};
use lgh_volume::render::{Camera, Framing, MarchSettings, Up};
use lgh_volume::surfaces::Ground;
use lgh_volume::{bouncing_balls, explosion, ExplosionLights, Method, Shadows, Variants};
use serde_json::{json, Value};

/// Arguments of `lgh bench flicker`.
#[derive(Debug, clap::Args)]
pub struct FlickerArgs {
    /// Any frame of an OpenVDB cache, with --frames (Blender's grids and its domain offset).
    #[arg(long, requires = "frames", conflicts_with = "procedural")]
    pub vdb: Option<PathBuf>,
    /// The cache's frames, `A..B` inclusive.
    #[arg(long, requires = "vdb")]
    pub frames: Option<String>,
    /// N frames of the procedural explosion (the demo's scene), --frame-step apart from
    /// t = 0.3 s.
    #[arg(long)]
    pub procedural: Option<usize>,
    /// With --procedural: seconds between frames (1/24 by default). A method whose error
    /// changes continuously with the scene flickers in proportion to it; a method that draws
    /// new random choices every frame does not (so the ratio grows as the step shrinks).
    #[arg(long, requires = "procedural")]
    pub frame_step: Option<f32>,
    /// With --procedural: instead of the explosion, this many glowing balls bouncing on an
    /// opaque floor under a layer of smoke (the paper's Fig. 12 class of animated lights): the
    /// lights move, so every frame rebuilds the hierarchy.
    #[arg(long, requires = "procedural")]
    pub balls: Option<usize>,
    /// Voxels per side of the procedural scene.
    #[arg(long, default_value_t = 48)]
    pub resolution: usize,
    /// The paper's α.
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true)]
    pub alpha: f32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 48)]
    pub width: usize,
    /// Image height in pixels.
    #[arg(long, default_value_t = 27)]
    pub height: usize,
    /// Write a markdown table of the results here (atomically).
    #[arg(long)]
    pub markdown: Option<PathBuf>,
    /// Lightcuts' ε, relative to each point's estimate (Walter's and the paper's 2%).
    #[arg(long, default_value_t = 0.02)]
    pub lightcuts_error: f32,
    /// Lightcuts' largest cut (Walter's and the paper's 1000). Below some ε the cut reaches it
    /// and the error stops falling: a larger cut lets --equal-error reach lower errors.
    #[arg(long, default_value_t = 1000)]
    pub lightcuts_max_cut: usize,
    /// Reproduce the paper's Fig. 10 on the middle frame into this folder: two stochastic
    /// Lightcuts renders and their difference ×4, and deterministic Lightcuts' bias against the
    /// mean of --fig10-renders stochastic renders (PNGs; the JSON gets `fig10`).
    #[arg(long)]
    pub fig10: Option<PathBuf>,
    /// Stochastic renders averaged for --fig10's mean.
    #[arg(long, default_value_t = 32)]
    pub fig10_renders: u32,
    /// Also compare at equal average error: render the hierarchy (`lgh` and `lgh_ray_marched`)
    /// at every α of --sweep-alphas and stochastic Lightcuts at every ε of
    /// --sweep-lightcuts-errors, and read Lightcuts' flicker at each of the hierarchy's errors off
    /// its curve (the JSON gets `equal_error`, the markdown a second table). Each setting keeps
    /// its own lights and images: the default sweep over the dev fire's 7 frames peaks at
    /// about 1 GB.
    #[arg(long)]
    pub equal_error: bool,
    /// With --equal-error: the hierarchy's α values.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.5,1,2,4",
        requires = "equal_error"
    )]
    pub sweep_alphas: Vec<f32>,
    /// With --equal-error: Lightcuts' ε values (at least two).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.64,0.32,0.16,0.08,0.04,0.02,0.01,0.005,0.0025,0.00125",
        requires = "equal_error"
    )]
    pub sweep_lightcuts_errors: Vec<f32>,
    /// Only these methods (JSON keys, comma-separated; all by default). The reference is
    /// always rendered.
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<String>,
    /// Don't show progress.
    #[arg(long)]
    pub quiet: bool,
}

/// One setting measured over the whole sequence: a method (an index into [`entries`]) at an α
/// and a Lightcuts ε (each used only by the methods it concerns).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Run {
    entry: usize,
    alpha: f32,
    lightcuts_error: f32,
}

/// What a run measured over the sequence.
#[derive(Clone, Copy)]
struct Measured {
    flicker: f64,
    rel_rmse: f64,
    seconds_per_frame: f64,
}

/// The flicker of a curve of `(rel_rmse, flicker)` points at the error `e`, interpolated
/// linearly in log–log between the two points of nearest error either side, and the indices of
/// those two points; `None` when `e` lies outside the curve's errors (no extrapolation). This is
/// how "at equal average error" is read: the rival is measured at several settings and its
/// flicker taken at exactly the error of the method it is compared with.
#[must_use]
fn flicker_at_error(curve: &[(f64, f64)], e: f64) -> Option<(f64, [usize; 2])> {
    let mut order: Vec<usize> = (0..curve.len()).collect();
    order.sort_by(|&a, &b| curve[a].0.total_cmp(&curve[b].0));
    order.windows(2).find_map(|w| {
        let ((e0, f0), (e1, f1)) = (curve[w[0]], curve[w[1]]);
        if !(e0..=e1).contains(&e) {
            return None;
        }
        let f = if e1 <= e0 || e0 <= 0.0 || f0 <= 0.0 || f1 <= 0.0 {
            f0 + (f1 - f0) * if e1 > e0 { (e - e0) / (e1 - e0) } else { 0.0 }
        } else {
            let t = (e / e0).ln() / (e1 / e0).ln();
            (f0.ln() + t * (f1 / f0).ln()).exp()
        };
        Some((f, [w[0], w[1]]))
    })
}

/// One measured method: its JSON key, what it is, how it renders.
struct Entry {
    key: &'static str,
    what: &'static str,
    method: Method,
    variants: Variants,
    shadows: Shadows,
    /// Coarse lights' shadows through the prefiltered density (the paper's) or as points.
    prefilter: bool,
}

fn entries() -> Vec<Entry> {
    let lgh = |key, what, variants, prefilter| Entry {
        key,
        what,
        method: Method::Lgh,
        variants,
        shadows: Shadows::CubeMap,
        prefilter,
    };
    let paper = Variants::default();
    let ray_marched = |key, what, method| Entry {
        key,
        what,
        method,
        variants: paper,
        shadows: Shadows::RayMarch,
        prefilter: true,
    };
    vec![
        lgh(
            "lgh",
            "LGH, cube-map shadows (the paper's method)",
            paper,
            true,
        ),
        ray_marched("lgh_ray_marched", "LGH, ray-marched shadows", Method::Lgh),
        ray_marched(
            "lightcuts",
            "Lightcuts at --lightcuts-error (2%), random representatives, a new tree every frame",
            Method::Lightcuts,
        ),
        ray_marched(
            "lightcuts_deterministic",
            "Lightcuts at --lightcuts-error (2%), brightest representatives",
            Method::LightcutsDeterministic,
        ),
        lgh(
            "nearest_vertex",
            "LGH with nearest-vertex clustering instead of trilinear splatting",
            Variants {
                clustering: Clustering::NearestVertex,
                ..paper
            },
            true,
        ),
        lgh(
            "hard_switches",
            "LGH with hard level switches instead of blending",
            Variants {
                hard_switches: true,
                ..paper
            },
            true,
        ),
        lgh(
            "grid_vertex",
            "LGH with lights at grid vertices instead of illumination centres (Fig. 9)",
            Variants {
                position: LightPosition::GridVertex,
                ..paper
            },
            true,
        ),
        lgh(
            "point_shadows",
            "LGH with coarse lights as points for shadows (no prefiltered density)",
            paper,
            false,
        ),
    ]
}

/// The frames, their medium, and the camera's up axis.
fn frames(args: &FlickerArgs) -> Result<(String, Vec<Volume>, Medium, Up), crate::Error> {
    let step = args.frame_step.unwrap_or(1.0 / 24.0);
    if !(step.is_finite() && step > 0.0 && step <= 1.0) {
        return Err(format!("--frame-step {step}: expected seconds in (0, 1]").into());
    }
    let per_second = if args.frame_step.is_some() {
        format!(", {step} s apart")
    } else {
        String::new()
    };
    match (&args.vdb, &args.frames, args.procedural) {
        (Some(vdb), Some(range), None) => {
            let (a, b) = crate::explosion::parse_frames(range)?;
            let paths = (a..=b)
                .map(|f| cache::frame_path(vdb, f))
                .collect::<Result<Vec<_>, _>>()?;
            if let Some(missing) = paths.iter().find(|p| !p.is_file()) {
                return Err(format!("{}: no such file", missing.display()).into());
            }
            if paths.len() < 2 {
                return Err("--frames: flicker needs at least 2 frames".into());
            }
            let volumes = cache::load(&paths, &GridNames::default(), true)?;
            let name = format!("{} frames {a}..{b}", vdb.display());
            Ok((name, volumes, crate::bench_explosion::fire_medium()?, Up::Z))
        }
        (None, None, Some(n)) => {
            if !(2..=1000).contains(&n) {
                return Err(format!("--procedural {n}: expected 2 to 1000 frames").into());
            }
            let res = args.resolution;
            let (volumes, name) = match args.balls {
                Some(balls) => (
                    (0..n)
                        .map(|i| bouncing_balls(res, balls, i as f32 * step))
                        .collect::<Result<Vec<_>, _>>()?,
                    format!(
                        "{balls} bouncing balls on {res}³, {n} frames{per_second} (lights move: rebuilt every frame)"
                    ),
                ),
                None => (
                    (0..n)
                        .map(|i| explosion(res, 0.3 + i as f32 * step))
                        .collect::<Result<Vec<_>, _>>()?,
                    format!("procedural explosion {res}³, {n} frames{per_second}"),
                ),
            };
            Ok((name, volumes, crate::demo::demo_medium(), Up::Y))
        }
        _ => Err("give --vdb FRAME --frames A..B, or --procedural N".into()),
    }
}

/// Runs `lgh bench flicker`.
pub fn run(args: &FlickerArgs) -> Result<(), crate::Error> {
    crate::check_alpha(args.alpha)?;
    lgh_volume::render::check_image_size(args.width, args.height)?;
    // Every setting is checked before any frame is read.
    lgh_core::QueryError::check_threshold(args.lightcuts_error)
        .map_err(|e| format!("--lightcuts-error: {e}"))?;
    if !(1..=1 << 24).contains(&args.lightcuts_max_cut) {
        return Err(format!(
            "--lightcuts-max-cut {}: expected 1 to 16777216",
            args.lightcuts_max_cut
        )
        .into());
    }
    let entries = chosen(entries(), &args.methods)?;
    let runs = runs(args, &entries)?;
    if let Some(dir) = &args.fig10 {
        if !dir.is_dir() {
            return Err(format!("--fig10 {}: no such folder", dir.display()).into());
        }
        if !(2..=4096).contains(&args.fig10_renders) {
            return Err(
                format!("--fig10-renders {}: expected 2 to 4096", args.fig10_renders).into(),
            );
        }
    }
    let (scene, volumes, medium, up) = frames(args)?;
    let refs: Vec<&Volume> = volumes.iter().collect();
    let (lo, hi) = framing_bounds(&refs).ok_or("the frames have no smoke to frame")?;
    let camera = Camera::frame_up(lo, hi, args.width, args.height, up)?;
    // The bouncing balls' floor: an opaque ground at the bottom of their box, which their
    // light falls on (surfaces through the same lights and shadows, "The explosion in a box").
    let floor = match args.balls {
        Some(_) => Some(Ground::new(Up::Y, -1.0, lgh_core::glam::Vec3::splat(0.5))?),
        None => None,
    };
    // Moving lights: a new hierarchy every frame (from that frame's hot voxels alone), so the
    // lights start as the first frame's; fixed lights: every frame's hot voxels.
    let rebuild = args.balls.is_some();
    let mut paper = if rebuild {
        ExplosionLights::new(&refs[..1], &medium)?
    } else {
        ExplosionLights::new(&refs, &medium)?
    };
    paper.set_lightcuts_settings(lgh_core::LightcutsSettings {
        relative_error: args.lightcuts_error,
        max_cut: args.lightcuts_max_cut,
        ..Default::default()
    });
    let march = MarchSettings::with_shadows;
    // Each run's lights: the paper's with the run's variants and Lightcuts' ε.
    let fresh = |l: &ExplosionLights, run: &Run| -> Result<ExplosionLights, crate::Error> {
        let mut l = l.clone().with_variants(entries[run.entry].variants)?;
        l.set_lightcuts_settings(lgh_core::LightcutsSettings {
            relative_error: run.lightcuts_error,
            ..l.lightcuts_settings()
        });
        Ok(l)
    };
    let mut lights: Vec<ExplosionLights> = runs
        .iter()
        .map(|r| fresh(&paper, r))
        .collect::<Result<_, _>>()?;
    let lightcuts = paper.lightcuts_settings();
    // The reference's lights at a frame: moving lights a new hierarchy over that frame's hot
    // voxels alone; fixed lights the same ones with that frame's intensities.
    let lights_at = |l: &mut ExplosionLights, frame: &Volume| -> Result<(), crate::Error> {
        if rebuild {
            *l = ExplosionLights::new(&[frame], &medium)?;
            l.set_lightcuts_settings(lightcuts);
        } else {
            l.set_frame(frame, &medium)?;
        }
        Ok(())
    };
    let mut reference_lights = paper;
    let mut build_seconds = 0.0;
    let mut lit = 0usize;
    let mut reference: Vec<Image> = Vec::new();
    let mut images: Vec<Vec<Image>> = vec![Vec::new(); runs.len()];
    let mut seconds = vec![0.0f64; runs.len()];
    let mut reference_seconds = 0.0;
    let bar = crate::progress::bar(
        (volumes.len() * (runs.len() + 1)) as u64,
        "rendering",
        args.quiet,
    );
    for (t, frame) in volumes.iter().enumerate() {
        let start = Instant::now();
        lights_at(&mut reference_lights, frame)?;
        build_seconds += start.elapsed().as_secs_f64();
        lit += reference_lights.lit();
        if rebuild {
            // Each method's own rebuild counts in its time (as Lightcuts' tree, built in its
            // render, does); Lightcuts also pays for a hierarchy it does not use, a few ms.
            for (k, (l, r)) in lights.iter_mut().zip(&runs).enumerate() {
                let start = Instant::now();
                *l = fresh(&reference_lights, r)?;
                seconds[k] += start.elapsed().as_secs_f64();
            }
        }
        let start = Instant::now();
        let view = View {
            frame,
            medium: &medium,
            camera: &camera,
            floor: floor.as_ref(),
        };
        let image = view.render(
            &reference_lights,
            Method::Brute,
            args.alpha,
            &march(Shadows::RayMarch, true),
        )?;
        reference_seconds += start.elapsed().as_secs_f64();
        reference.push(image);
        bar.inc(1);
        for (k, r) in runs.iter().enumerate() {
            let e = &entries[r.entry];
            let start = Instant::now();
            let l = &mut lights[k];
            l.set_frame(frame, &medium)?;
            // A new random tree every frame, as the paper ran Lightcuts.
            l.set_lightcuts_seed(t as u64);
            let image = view.render(l, e.method, r.alpha, &march(e.shadows, e.prefilter))?;
            seconds[k] += start.elapsed().as_secs_f64();
            images[k].push(image);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let measured = images
        .iter()
        .zip(&seconds)
        .map(|(images, &s)| measure(images, &reference, s))
        .collect::<Result<Vec<_>, _>>()?;
    let mut backends = serde_json::Map::new();
    let mut table = format!(
        "| method | flicker | relative RMSE | seconds per frame |\n|---|---:|---:|---:|\n| brute force, ray-marched (the reference) | – | – | {:.2} |\n",
        reference_seconds / volumes.len() as f64
    );
    // The first runs are the entries at --alpha and --lightcuts-error, in order.
    for (e, m) in entries.iter().zip(&measured) {
        backends.insert(
            e.key.to_string(),
            json!({
                "flicker": m.flicker,
                "rel_rmse": m.rel_rmse,
                "seconds_per_frame": m.seconds_per_frame,
                "method": e.what,
            }),
        );
        table += &format!(
            "| {} (`{}`) | {:.6} | {:.2}% | {:.2} |\n",
            e.what,
            e.key,
            m.flicker,
            100.0 * m.rel_rmse,
            m.seconds_per_frame
        );
    }
    let equal_error = if args.equal_error {
        let (value, markdown) = equal_error(args, &entries, &runs, &measured);
        table += &markdown;
        Some(value)
    } else {
        None
    };
    let fig10 = match &args.fig10 {
        Some(dir) => {
            let t = volumes.len() / 2;
            lights_at(&mut reference_lights, &volumes[t])?;
            Some(fig10(
                args,
                dir,
                &mut reference_lights,
                &volumes[t],
                &reference[t],
                &medium,
                &camera,
                floor.as_ref(),
            )?)
        }
        None => None,
    };
    let report: Value = json!({
        "scene": scene,
        "lightcuts_error": args.lightcuts_error,
        "lightcuts_max_cut": args.lightcuts_max_cut,
        "fig10": fig10,
        "frames": volumes.len(),
        "alpha": args.alpha,
        "frame_step_seconds": args.procedural.map(|_| args.frame_step.unwrap_or(1.0 / 24.0)),
        "width": args.width,
        "height": args.height,
        "reference": "brute force over every light, ray-marched shadows",
        "reference_seconds_per_frame": reference_seconds / volumes.len() as f64,
        "lights_rebuilt_every_frame": rebuild,
        "floor": floor.is_some(),
        "lights_per_frame": lit as f64 / volumes.len() as f64,
        "build_seconds_per_frame": build_seconds / volumes.len() as f64,
        "backends": backends,
        "equal_error": equal_error,
    });
    say!("{}", serde_json::to_string_pretty(&report)?);
    if let Some(path) = &args.markdown {
        lgh_image::write_atomic(path, |w| w.write_all(table.as_bytes()))
            .map_err(|e| format!("--markdown {}: {e}", path.display()))?;
    }
    if !args.quiet {
        eprintln!("{scene}, α = {}:\n{table}", args.alpha);
    }
    Ok(())
}

/// The runs to render: first every entry at --alpha and --lightcuts-error, in order; with
/// --equal-error then the hierarchy at each swept α and stochastic Lightcuts at each swept ε,
/// each setting once (Lightcuts does not depend on α, the hierarchy not on ε).
fn runs(args: &FlickerArgs, entries: &[Entry]) -> Result<Vec<Run>, crate::Error> {
    let index = |key: &str| entries.iter().position(|e| e.key == key);
    let mut runs: Vec<Run> = (0..entries.len())
        .map(|entry| Run {
            entry,
            alpha: args.alpha,
            lightcuts_error: args.lightcuts_error,
        })
        .collect();
    if !args.equal_error {
        return Ok(runs);
    }
    let mut distinct = args.sweep_lightcuts_errors.clone();
    distinct.sort_by(f32::total_cmp);
    distinct.dedup();
    if distinct.len() < 2 {
        return Err("--sweep-lightcuts-errors: give at least two ε to read a curve off".into());
    }
    if !SWEPT_HIERARCHIES.iter().any(|k| index(k).is_some()) {
        return Err(format!(
            "--equal-error: --methods must include {}",
            SWEPT_HIERARCHIES.join(" or ")
        )
        .into());
    }
    let mut add = |run: Run| {
        if !runs.contains(&run) {
            runs.push(run);
        }
    };
    for &alpha in &args.sweep_alphas {
        crate::check_alpha(alpha).map_err(|e| format!("--sweep-alphas: {e}"))?;
        for entry in SWEPT_HIERARCHIES.iter().filter_map(|k| index(k)) {
            add(Run {
                entry,
                alpha,
                lightcuts_error: args.lightcuts_error,
            });
        }
    }
    for &lightcuts_error in &args.sweep_lightcuts_errors {
        lgh_core::QueryError::check_threshold(lightcuts_error)
            .map_err(|e| format!("--sweep-lightcuts-errors: {e}"))?;
        add(Run {
            entry: index("lightcuts").ok_or("--equal-error: --methods must include lightcuts")?,
            alpha: args.alpha,
            lightcuts_error,
        });
    }
    Ok(runs)
}

/// `all` restricted to the `keys` of --methods (all of them when none is given), in their order.
fn chosen(all: Vec<Entry>, keys: &[String]) -> Result<Vec<Entry>, crate::Error> {
    if let Some(k) = keys
        .iter()
        .find(|k| !all.iter().any(|e| e.key == k.as_str()))
    {
        let known: Vec<&str> = all.iter().map(|e| e.key).collect();
        return Err(format!(
            "--methods {k}: no such method (one of {})",
            known.join(", ")
        )
        .into());
    }
    Ok(all
        .into_iter()
        .filter(|e| keys.is_empty() || keys.iter().any(|k| k == e.key))
        .collect())
}

/// The hierarchies --equal-error sweeps over α.
const SWEPT_HIERARCHIES: [&str; 2] = ["lgh", "lgh_ray_marched"];

/// Flicker and mean relative RMSE of one run's `images` against the `reference`, and its
/// seconds per frame from its total `seconds`.
fn measure(images: &[Image], reference: &[Image], seconds: f64) -> Result<Measured, crate::Error> {
    let flicker = lgh_image::flicker(images, reference)
        .ok_or("the reference is black: flicker is undefined")?;
    let errors: Vec<f64> = images
        .iter()
        .zip(reference)
        .map(|(a, r)| lgh_image::compare(a, r).map_or(f64::NAN, |s| s.rel_rmse))
        .collect();
    Ok(Measured {
        flicker,
        rel_rmse: errors.iter().sum::<f64>() / errors.len() as f64,
        seconds_per_frame: seconds / images.len() as f64,
    })
}

/// --equal-error's JSON and markdown: stochastic Lightcuts' curve over ε, and for each swept
/// hierarchy at each α its flicker beside Lightcuts' flicker read off that curve at the same
/// error ([`flicker_at_error`]; `null` where the error lies outside the curve).
fn equal_error(
    args: &FlickerArgs,
    entries: &[Entry],
    runs: &[Run],
    measured: &[Measured],
) -> (Value, String) {
    let of = |key: &'static str| {
        runs.iter()
            .zip(measured)
            .filter(move |(r, _)| entries[r.entry].key == key)
    };
    let swept = |r: &Run, key: &str| match key {
        "lightcuts" => args.sweep_lightcuts_errors.contains(&r.lightcuts_error),
        _ => args.sweep_alphas.contains(&r.alpha),
    };
    // Rows in the order of the setting: Lightcuts' ε from the largest, the hierarchy's α from
    // the smallest, so both go from the largest error down.
    let mut lightcuts: Vec<(&Run, &Measured)> = of("lightcuts")
        .filter(|(r, _)| swept(r, "lightcuts"))
        .collect();
    lightcuts.sort_by(|a, b| b.0.lightcuts_error.total_cmp(&a.0.lightcuts_error));
    let curve: Vec<(f64, f64)> = lightcuts
        .iter()
        .map(|(_, m)| (m.rel_rmse, m.flicker))
        .collect();
    let mut markdown = String::from(
        "\n| method | α | relative RMSE | flicker | Lightcuts' flicker at that error | Lightcuts / hierarchy |\n|---|---:|---:|---:|---:|---:|\n",
    );
    // Whether error and flicker both fall with ε: if not (a cut that reaches its largest size
    // stops refining), one error can be met at several ε, and it is read between the two
    // runs of nearest error.
    let monotone = curve
        .windows(2)
        .all(|w| w[1].0 <= w[0].0 && w[1].1 <= w[0].1);
    let mut value = serde_json::Map::new();
    value.insert("lightcuts_curve_monotone".into(), json!(monotone));
    value.insert(
        "lightcuts".into(),
        lightcuts
            .iter()
            .map(|(r, m)| {
                json!({
                    "relative_error": r.lightcuts_error,
                    "flicker": m.flicker,
                    "rel_rmse": m.rel_rmse,
                    "seconds_per_frame": m.seconds_per_frame,
                })
            })
            .collect(),
    );
    for key in SWEPT_HIERARCHIES {
        let mut points = Vec::new();
        let mut hierarchy: Vec<(&Run, &Measured)> =
            of(key).filter(|(r, _)| swept(r, key)).collect();
        hierarchy.sort_by(|a, b| a.0.alpha.total_cmp(&b.0.alpha));
        for (r, m) in hierarchy {
            let at = flicker_at_error(&curve, m.rel_rmse);
            // No ratio to a hierarchy that does not flicker at all (its cell says so).
            let ratio = at.map(|(f, _)| f / m.flicker).filter(|q| q.is_finite());
            let between = at.map(|(_, [a, b])| {
                [
                    lightcuts[a].0.lightcuts_error,
                    lightcuts[b].0.lightcuts_error,
                ]
            });
            points.push(json!({
                "alpha": r.alpha,
                "flicker": m.flicker,
                "rel_rmse": m.rel_rmse,
                "seconds_per_frame": m.seconds_per_frame,
                "lightcuts_flicker_at_same_error": at.map(|(f, _)| f),
                "lightcuts_over_lgh": ratio,
                "between_lightcuts_errors": between,
            }));
            let cell = |x: Option<f64>, f: &dyn Fn(f64) -> String| {
                x.map_or_else(|| "outside Lightcuts' errors".to_string(), f)
            };
            markdown += &format!(
                "| `{key}` | {} | {:.2}% | {:.6} | {} | {} |\n",
                r.alpha,
                100.0 * m.rel_rmse,
                m.flicker,
                cell(at.map(|(f, _)| f), &|f| format!("{f:.6}")),
                match (ratio, at) {
                    (None, Some(_)) => "the hierarchy does not flicker".to_string(),
                    _ => cell(ratio, &|q| format!("{q:.1}×")),
                },
            );
        }
        value.insert(key.into(), Value::Array(points));
    }
    markdown +=
        "\n| Lightcuts ε | relative RMSE | flicker | seconds per frame |\n|---:|---:|---:|---:|\n";
    for (r, m) in &lightcuts {
        markdown += &format!(
            "| {} | {:.2}% | {:.6} | {:.2} |\n",
            r.lightcuts_error,
            100.0 * m.rel_rmse,
            m.flicker,
            m.seconds_per_frame
        );
    }
    if !monotone {
        markdown += "\n(Lightcuts' error or flicker does not fall monotonically with ε here: each value above is read between the two runs of nearest error.)\n";
    }
    (Value::Object(value), markdown)
}

/// The paper's Fig. 10 on one frame (`lights` set to it), into `dir`: two stochastic Lightcuts
/// renders (seeds 1 and 2) and their difference ×4 (false colour, red at a quarter of the
/// brightest pixel of scattered light); deterministic Lightcuts, the mean of `--fig10-renders` stochastic renders,
/// and the deterministic one's bias against that mean, likewise ×4; `exact` is the frame's
/// brute-force reference, already rendered. Returns the figures.
#[allow(clippy::too_many_arguments)]
fn fig10(
    args: &FlickerArgs,
    dir: &std::path::Path,
    lights: &mut ExplosionLights,
    frame: &Volume,
    exact: &Image,
    medium: &Medium,
    camera: &Camera,
    floor: Option<&Ground>,
) -> Result<Value, crate::Error> {
    let march = MarchSettings::with_shadows(Shadows::RayMarch, true);
    let view = View {
        frame,
        medium,
        camera,
        floor,
    };
    let mut render = |method, seed| -> Result<Image, crate::Error> {
        lights.set_lightcuts_seed(seed);
        view.render(lights, method, args.alpha, &march)
    };
    let (one, two) = (render(Method::Lightcuts, 1)?, render(Method::Lightcuts, 2)?);
    let deterministic = render(Method::LightcutsDeterministic, 0)?;
    let n = args.fig10_renders;
    let mut mean = Image::new(camera.width(), camera.height());
    for seed in 1..=u64::from(n) {
        let img = if seed == 1 {
            one.clone()
        } else if seed == 2 {
            two.clone()
        } else {
            render(Method::Lightcuts, seed)?
        };
        for (m, p) in mean.pixels.iter_mut().zip(&img.pixels) {
            *m += *p / n as f32;
        }
    }
    // The differences are of the scattered light (the emission is the same in every render):
    // red at a quarter of its brightest pixel.
    let (emission, _) = lgh_volume::render::render::<lgh_core::BruteForce>(
        frame,
        medium,
        None,
        camera,
        &march,
        &|_| {},
    )?;
    let brightest = exact
        .pixels
        .iter()
        .zip(&emission.pixels)
        .map(|(&p, &e)| lgh_core::luminance(p - e))
        .fold(0.0f32, f32::max);
    let exposure = lgh_image::auto_exposure(exact);
    let png = |name: &str, img: &Image| -> Result<(), crate::Error> {
        Ok(lgh_image::write_png(&dir.join(name), img, exposure)?)
    };
    png("fig10-brute.png", exact)?;
    png("fig10-lightcuts-seed-1.png", &one)?;
    png("fig10-lightcuts-seed-2.png", &two)?;
    png("fig10-lightcuts-deterministic.png", &deterministic)?;
    png("fig10-lightcuts-mean.png", &mean)?;
    lgh_image::difference_png(
        &dir.join("fig10-seed-difference-x4.png"),
        &one,
        &two,
        brightest / 4.0,
    )?;
    lgh_image::difference_png(
        &dir.join("fig10-deterministic-bias-x4.png"),
        &deterministic,
        &mean,
        brightest / 4.0,
    )?;
    let rel = |a: &Image, r: &Image| lgh_image::compare(a, r).map(|s| s.rel_rmse);
    let mean_lum = |img: &Image| {
        img.pixels
            .iter()
            .map(|&p| f64::from(lgh_core::luminance(p)))
            .sum::<f64>()
            / img.pixels.len() as f64
    };
    Ok(json!({
        "frame": volumes_label(args),
        "stochastic_renders": n,
        "seed_1_vs_seed_2_rel_rmse": rel(&one, &two),
        "stochastic_vs_brute_rel_rmse": rel(&one, exact),
        "mean_of_stochastic_vs_brute_rel_rmse": rel(&mean, exact),
        "deterministic_vs_mean_rel_rmse": rel(&deterministic, &mean),
        "deterministic_vs_brute_rel_rmse": rel(&deterministic, exact),
        "deterministic_mean_bias": mean_lum(&deterministic) / mean_lum(&mean) - 1.0,
        "images": dir.display().to_string(),
    }))
}

/// Which frame --fig10 shows: the middle one.
fn volumes_label(args: &FlickerArgs) -> String {
    match (&args.frames, args.procedural) {
        (Some(range), _) => format!("the middle frame of {range}"),
        (_, Some(n)) => format!("frame {} of {n}", n / 2),
        _ => String::new(),
    }
}

/// What every render of one frame shares: the frame, its medium, the camera and the floor.
struct View<'a> {
    frame: &'a Volume,
    medium: &'a Medium,
    camera: &'a Camera,
    floor: Option<&'a Ground>,
}

impl View<'_> {
    /// `lights` through `method` at `alpha` with `march`'s shadows, over the floor if there is
    /// one.
    fn render(
        &self,
        lights: &ExplosionLights,
        method: Method,
        alpha: f32,
        march: &MarchSettings,
    ) -> Result<Image, crate::Error> {
        let backend = lights.backend(method, alpha)?;
        let mut marcher = lights.marcher(method, alpha, self.frame, self.medium, march)?;
        if let Some(f) = self.floor {
            marcher = marcher.with_surfaces(f);
        }
        Ok(marcher.render(Some(&backend), self.camera, &|_| {})?.0)
    }
}

#[cfg(test)]
mod tests {
    use super::{entries, flicker_at_error, runs, FlickerArgs};
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: FlickerArgs,
    }

    fn args(line: &[&str]) -> FlickerArgs {
        Cli::try_parse_from([&["flicker"], line].concat())
            .unwrap()
            .args
    }

    /// Each setting is rendered once: the main runs, then only the swept settings not among
    /// them (Lightcuts does not depend on α, the hierarchy not on ε).
    #[test]
    fn each_swept_setting_is_rendered_once() {
        let all = entries();
        let main = runs(&args(&["--procedural", "2"]), &all).unwrap();
        assert_eq!(main.len(), all.len());
        let line = [
            "--procedural",
            "2",
            "--equal-error",
            "--sweep-alphas",
            "1,2,2,4",
            "--sweep-lightcuts-errors",
            "0.04,0.02,0.01",
        ];
        let swept = runs(&args(&line), &all).unwrap();
        // α = 1 and 4 for two hierarchies, ε = 0.04 and 0.01: α = 2 and ε = 2% are main runs.
        assert_eq!(swept.len(), all.len() + 2 * 2 + 2, "{}", swept.len());
        assert_eq!(&swept[..all.len()], &main[..]);
        // A curve needs two distinct ε, and a hierarchy to compare.
        let twice = [
            "--procedural",
            "2",
            "--equal-error",
            "--sweep-lightcuts-errors",
            "0.02,0.02",
        ];
        assert!(runs(&args(&twice), &all).is_err());
        let line = [
            "--procedural",
            "2",
            "--equal-error",
            "--methods",
            "lightcuts",
        ];
        let only = super::chosen(entries(), &args(&line).methods).unwrap();
        assert!(runs(&args(&line), &only).is_err());
    }

    #[test]
    fn equal_error_interpolates_in_log_log_and_never_extrapolates() {
        // Flicker ∝ error² on this curve, so log–log interpolation is exact between its points;
        // the points are given out of order.
        let curve = [(0.04, 0.016), (0.01, 0.001), (0.02, 0.004)];
        let (f, pair) = flicker_at_error(&curve, 0.03).unwrap();
        assert!((f - 0.009).abs() < 1e-12, "{f}");
        assert_eq!(pair, [2, 0]);
        let (f, _) = flicker_at_error(&curve, 0.01).unwrap();
        assert!((f - 0.001).abs() < 1e-15, "{f}");
        assert!(flicker_at_error(&curve, 0.05).is_none());
        assert!(flicker_at_error(&curve, 0.005).is_none());
        assert!(flicker_at_error(&curve[..1], 0.01).is_none());
    }
}
