//! `lgh bench flicker`: temporal flicker of a sequence (the paper's Figs. 9, 10, Sec. 6.1),
//! the hierarchy against Lightcuts and against the paper's flickering variants, as JSON (and a
//! markdown table).
//!
//! Every method renders the same frames and pixels; brute force over every light with
//! ray-marched shadows is the reference of each frame (the exact answer of the same light
//! model). Flicker is `mean_t mean_px |(A_t − R_t) − (A_{t−1} − R_{t−1})| / mean |R|`
//! (ARCHITECTURE.md "Measuring", [`lgh_image::flicker`]): the change of the error from frame to frame, so a
//! constant bias does not count; the error is the mean over frames of the relative RMSE.

use std::path::PathBuf;
use std::time::Instant;

use lgh_core::{Clustering, LightPosition, LightcutsSettings, Representative};
use lgh_image::Image;
use lgh_volume::cache::{self, GridNames, Placement};
use lgh_volume::lighting_cache::{CacheMode, LightingCacheSettings, RenderedLights};

use crate::output::CacheArgs;
use lgh_volume::medium::{framing_bounds, Medium, Volume};
use lgh_volume::render::{Camera, Framing, MarchSettings, Up};
use lgh_volume::shadow::{CoarseShadows, CubeMapSettings, Depths};
use lgh_volume::surfaces::Ground;
use lgh_volume::{
    bouncing_balls, explosion, ExplosionLights, FrameRender, Method, Shadows, Variants,
};
use serde_json::{json, Value};

/// Arguments of `lgh bench flicker`.
#[derive(Debug, clap::Args)]
pub struct FlickerArgs {
    /// The lighting cache of `lgh_cached` (the others have none).
    #[command(flatten)]
    pub cache: CacheArgs,
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

impl Run {
    /// The run's method on frame `t`: its entry's, at the run's α or ε (Lightcuts' largest cut
    /// `max_cut`), stochastic Lightcuts with a new tree every frame, as the paper ran it.
    fn method(&self, entries: &[Entry], t: usize, max_cut: usize) -> Method {
        let settings = LightcutsSettings {
            relative_error: self.lightcuts_error,
            max_cut,
            ..Default::default()
        };
        match entries[self.entry].method {
            Kind::Lgh => Method::Lgh { alpha: self.alpha },
            Kind::Lightcuts => Method::Lightcuts {
                settings,
                representative: Representative::Stochastic { seed: t as u64 },
            },
            Kind::LightcutsDeterministic => Method::Lightcuts {
                settings,
                representative: Representative::Brightest,
            },
        }
    }
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

/// The many-lights method of an entry, its parameters (α, ε, the seed) the run's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Lgh,
    Lightcuts,
    LightcutsDeterministic,
}

/// One measured method: its JSON key, what it is, how it renders.
struct Entry {
    key: &'static str,
    what: &'static str,
    method: Kind,
    variants: Variants,
    shadows: Shadows,
    /// Through the lighting cache (from `--cache-level`, levels ≥ 1 at small images).
    cached: bool,
    /// What cube-map texels hold (with cube-map shadows).
    depths: Depths,
}

impl Entry {
    /// The march settings of the entry (`cache`, the cache's settings, if it is cached, for
    /// camera rays `footprint` voxels apart at the volume).
    fn march(&self, cache: &CacheArgs, footprint: f32) -> MarchSettings {
        let cache = if self.cached {
            LightingCacheSettings {
                mode: CacheMode::Coarse,
                first_level: cache.first_level(footprint),
                ..cache.settings()
            }
        } else {
            LightingCacheSettings::default()
        };
        let plain = MarchSettings::with_shadows(self.shadows);
        MarchSettings {
            lighting_cache: cache,
            cube_maps: CubeMapSettings {
                depths: self.depths,
                ..plain.cube_maps
            },
            ..plain
        }
    }
}

fn entries() -> Vec<Entry> {
    let lgh = |key, what, variants| Entry {
        key,
        what,
        method: Kind::Lgh,
        variants,
        shadows: Shadows::CubeMap,
        cached: false,
        depths: Depths::default(),
    };
    let paper = Variants::default();
    let ray_marched = |key, what, method| Entry {
        key,
        what,
        method,
        variants: paper,
        shadows: Shadows::RayMarch,
        cached: false,
        depths: Depths::default(),
    };
    vec![
        lgh(
            "lgh",
            "LGH, cube-map shadows (the paper's method), four adaptive knots a texel",
            paper,
        ),
        Entry {
            depths: Depths::Fitted,
            ..lgh(
                "lgh_fixed_depths",
                "LGH, cube-map shadows with the paper's four fixed depths (fitted)",
                paper,
            )
        },
        ray_marched("lgh_ray_marched", "LGH, ray-marched shadows", Kind::Lgh),
        Entry {
            cached: true,
            ..ray_marched(
                "lgh_cached",
                "LGH, ray-marched shadows through the lighting cache (levels from --cache-level: 1 at small images)",
                Kind::Lgh,
            )
        },
        ray_marched(
            "lightcuts",
            "Lightcuts at --lightcuts-error (2%), random representatives, a new tree every frame",
            Kind::Lightcuts,
        ),
        ray_marched(
            "lightcuts_deterministic",
            "Lightcuts at --lightcuts-error (2%), brightest representatives",
            Kind::LightcutsDeterministic,
        ),
        lgh(
            "nearest_vertex",
            "LGH with nearest-vertex clustering instead of trilinear splatting",
            Variants {
                clustering: Clustering::NearestVertex,
                ..paper
            },
        ),
        lgh(
            "hard_switches",
            "LGH with hard level switches instead of blending",
            Variants {
                hard_switches: true,
                ..paper
            },
        ),
        lgh(
            "grid_vertex",
            "LGH with lights at grid vertices instead of illumination centres (Fig. 9)",
            Variants {
                position: LightPosition::GridVertex,
                ..paper
            },
        ),
        lgh(
            "point_shadows",
            "LGH with coarse lights as points for shadows (no prefiltered density)",
            Variants {
                coarse_shadows: CoarseShadows::Points,
                ..paper
            },
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
            for p in &paths {
                crate::files::check_file(p)?;
            }
            if paths.len() < 2 {
                return Err("--frames: flicker needs at least 2 frames".into());
            }
            let volumes = cache::load(&paths, &GridNames::default(), Placement::BlenderDomain)?;
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
    check(args)?;
    let entries = chosen(entries(), &args.methods)?;
    let runs = runs(args, &entries)?;
    let seq = Sequence::new(args)?;
    let rendered = seq.render_all(args, &entries, &runs)?;
    let n = seq.volumes.len() as f64;
    let measured = rendered
        .images
        .iter()
        .zip(&rendered.seconds)
        .map(|(images, &s)| measure(images, &rendered.reference, s))
        .collect::<Result<Vec<_>, _>>()?;
    let (backends, mut table) = backends(&entries, &measured, rendered.reference_seconds / n);
    let equal_error = args.equal_error.then(|| {
        let (value, markdown) = equal_error(args, &entries, &runs, &measured);
        table += &markdown;
        value
    });
    let fig10 = match &args.fig10 {
        Some(dir) => Some(fig10(
            args,
            dir,
            &seq,
            volumes_middle(&seq),
            &rendered.reference,
        )?),
        None => None,
    };
    let report: Value = json!({
        "scene": seq.name,
        "lightcuts_error": args.lightcuts_error,
        "lightcuts_max_cut": args.lightcuts_max_cut,
        "fig10": fig10,
        "frames": seq.volumes.len(),
        "alpha": args.alpha,
        "frame_step_seconds": args.procedural.map(|_| args.frame_step.unwrap_or(1.0 / 24.0)),
        "width": args.width,
        "height": args.height,
        "reference": "brute force over every light, ray-marched shadows",
        "reference_seconds_per_frame": rendered.reference_seconds / n,
        "lights_rebuilt_every_frame": seq.rebuild,
        "floor": seq.floor.is_some(),
        "lighting_cache_first_level": args.cache.first_level(seq.footprint),
        // No multiple scattering here: `auto` is the emission lights' form.
        "lighting_cache_level0": lgh_volume::lighting_cache::Level0Form::from(args.cache.cache_level0)
            .for_lights(RenderedLights::Emission)
            .name(),
        "lighting_cache_level0_near": args.cache.cache_near.0,
        "lights_per_frame": rendered.lit as f64 / n,
        "build_seconds_per_frame": rendered.build_seconds / n,
        "backends": backends,
        "equal_error": equal_error,
    });
    say!("{}", serde_json::to_string_pretty(&report)?);
    if let Some(path) = &args.markdown {
        lgh_image::write_atomic(path, |w| w.write_all(table.as_bytes()))
            .map_err(|e| format!("--markdown {}: {e}", path.display()))?;
    }
    if !args.quiet {
        eprintln!("{}, α = {}:\n{table}", seq.name, args.alpha);
    }
    Ok(())
}

/// Every setting, checked before any frame is read.
fn check(args: &FlickerArgs) -> Result<(), crate::Error> {
    crate::check_alpha(args.alpha)?;
    lgh_volume::render::check_image_size(args.width, args.height)?;
    lgh_core::QueryError::check_threshold(args.lightcuts_error)
        .map_err(|e| format!("--lightcuts-error: {e}"))?;
    if !(1..=1 << 24).contains(&args.lightcuts_max_cut) {
        return Err(format!(
            "--lightcuts-max-cut {}: expected 1 to 16777216",
            args.lightcuts_max_cut
        )
        .into());
    }
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
    Ok(())
}

/// The JSON `backends` and the markdown table of the runs at --alpha and --lightcuts-error
/// (the first runs, in the entries' order), after the reference's row.
fn backends(
    entries: &[Entry],
    measured: &[Measured],
    reference_seconds_per_frame: f64,
) -> (serde_json::Map<String, Value>, String) {
    let mut backends = serde_json::Map::new();
    let mut table = format!(
        "| method | flicker | relative RMSE | seconds per frame |\n|---|---:|---:|---:|\n| brute force, ray-marched (the reference) | – | – | {reference_seconds_per_frame:.2} |\n",
    );
    for (e, m) in entries.iter().zip(measured) {
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
    (backends, table)
}

/// The sequence every method renders: its frames, medium, camera and floor, and whether its
/// lights move (a new hierarchy every frame).
struct Sequence {
    name: String,
    volumes: Vec<Volume>,
    medium: Medium,
    camera: Camera,
    /// A camera ray's footprint at the frames' middle, in voxels (`--cache-level auto`).
    footprint: f32,
    /// The bouncing balls' floor: an opaque ground at the bottom of their box, which their
    /// light falls on (surfaces through the same lights and shadows, "The explosion in a box").
    floor: Option<Ground>,
    rebuild: bool,
    lightcuts: LightcutsSettings,
}

/// What the renders of the sequence gave: the reference's images and every run's, their
/// seconds, the reference lights' build seconds and the lights that shone, summed over frames.
struct Rendered {
    reference: Vec<Image>,
    images: Vec<Vec<Image>>,
    seconds: Vec<f64>,
    reference_seconds: f64,
    build_seconds: f64,
    lit: usize,
}

impl Sequence {
    fn new(args: &FlickerArgs) -> Result<Self, crate::Error> {
        let (name, volumes, medium, up) = frames(args)?;
        let refs: Vec<&Volume> = volumes.iter().collect();
        let (lo, hi) = framing_bounds(&refs).ok_or("the frames have no smoke to frame")?;
        let camera = Camera::frame_up(lo, hi, args.width, args.height, up)?;
        let footprint = lgh_volume::render::pixel_footprint(
            &camera,
            0.5 * (lo + hi),
            volumes[0].density.voxel_size,
        );
        let floor = match args.balls {
            Some(_) => Some(Ground::new(Up::Y, -1.0, lgh_core::glam::Vec3::splat(0.5))?),
            None => None,
        };
        Ok(Sequence {
            name,
            volumes,
            medium,
            camera,
            footprint,
            floor,
            rebuild: args.balls.is_some(),
            lightcuts: LightcutsSettings {
                relative_error: args.lightcuts_error,
                max_cut: args.lightcuts_max_cut,
                ..Default::default()
            },
        })
    }

    /// The paper's lights: moving lights start as the first frame's (each frame makes its
    /// own); fixed lights sit at every frame's hot voxels.
    fn paper_lights(&self) -> Result<ExplosionLights, crate::Error> {
        let refs: Vec<&Volume> = self.volumes.iter().collect();
        let frames = if self.rebuild { &refs[..1] } else { &refs[..] };
        Ok(ExplosionLights::new(frames, &self.medium)?)
    }

    /// The reference's lights at `frame`: moving lights a new hierarchy over that frame's hot
    /// voxels alone; fixed lights the same ones with that frame's intensities.
    fn lights_at(&self, l: &mut ExplosionLights, frame: &Volume) -> Result<(), crate::Error> {
        if self.rebuild {
            *l = ExplosionLights::new(&[frame], &self.medium)?;
        } else {
            l.set_frame(frame, &self.medium)?;
        }
        Ok(())
    }

    /// Frame `t` of `lights` through `method` with `march`'s shadows, over the floor if
    /// there is one.
    fn render(
        &self,
        t: usize,
        lights: &ExplosionLights,
        method: Method,
        march: &MarchSettings,
    ) -> Result<Image, crate::Error> {
        let frame = &self.volumes[t];
        let mut render = FrameRender::new(lights, method, frame, &self.medium, march, &())?;
        if let Some(f) = &self.floor {
            render = render.with_surfaces(f);
        }
        Ok(render.render(&self.camera, &())?.0)
    }

    /// Every frame with brute force (the reference) and with every run, timed.
    fn render_all(
        &self,
        args: &FlickerArgs,
        entries: &[Entry],
        runs: &[Run],
    ) -> Result<Rendered, crate::Error> {
        let mut reference_lights = self.paper_lights()?;
        // Each run's lights: the paper's with the run's variants.
        let fresh =
            |l: &ExplosionLights, r: &Run| l.clone().with_variants(entries[r.entry].variants);
        let mut lights: Vec<ExplosionLights> = runs
            .iter()
            .map(|r| fresh(&reference_lights, r))
            .collect::<Result<_, _>>()?;
        let mut out = Rendered {
            reference: Vec::new(),
            images: vec![Vec::new(); runs.len()],
            seconds: vec![0.0; runs.len()],
            reference_seconds: 0.0,
            build_seconds: 0.0,
            lit: 0,
        };
        let steps = (self.volumes.len() * (runs.len() + 1)) as u64;
        let bar = crate::progress::bar(steps, "rendering", args.quiet);
        for (t, frame) in self.volumes.iter().enumerate() {
            let start = Instant::now();
            self.lights_at(&mut reference_lights, frame)?;
            out.build_seconds += start.elapsed().as_secs_f64();
            out.lit += reference_lights.lit();
            if self.rebuild {
                // Each method's own rebuild counts in its time (as Lightcuts' tree, built in
                // its render, does); Lightcuts also pays for a hierarchy it does not use.
                for (k, (l, r)) in lights.iter_mut().zip(runs).enumerate() {
                    let start = Instant::now();
                    *l = fresh(&reference_lights, r)?;
                    out.seconds[k] += start.elapsed().as_secs_f64();
                }
            }
            let start = Instant::now();
            let reference = MarchSettings::with_shadows(Shadows::RayMarch);
            let image = self.render(t, &reference_lights, Method::Brute, &reference)?;
            out.reference_seconds += start.elapsed().as_secs_f64();
            out.reference.push(image);
            bar.inc(1);
            for (k, r) in runs.iter().enumerate() {
                let e = &entries[r.entry];
                let start = Instant::now();
                lights[k].set_frame(frame, &self.medium)?;
                let method = r.method(entries, t, self.lightcuts.max_cut);
                let image =
                    self.render(t, &lights[k], method, &e.march(&args.cache, self.footprint))?;
                out.seconds[k] += start.elapsed().as_secs_f64();
                out.images[k].push(image);
                bar.inc(1);
            }
        }
        bar.finish_and_clear();
        Ok(out)
    }
}

/// Which frame --fig10 shows: the middle one.
fn volumes_middle(seq: &Sequence) -> usize {
    seq.volumes.len() / 2
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
    let lightcuts = swept_runs(args, entries, runs, measured, "lightcuts");
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
    value.insert("lightcuts".into(), lightcuts_json(&lightcuts));
    for key in SWEPT_HIERARCHIES {
        let mut points = Vec::new();
        for run in swept_runs(args, entries, runs, measured, key) {
            let (point, row) = at_equal_error(key, run, &curve, &lightcuts);
            points.push(point);
            markdown += &row;
        }
        value.insert(key.into(), Value::Array(points));
    }
    markdown += &lightcuts_table(&lightcuts, monotone);
    (Value::Object(value), markdown)
}

/// The runs of method `key` at the settings --equal-error sweeps, with their measurements, in
/// the order of the setting: Lightcuts' ε from the largest, a hierarchy's α from the smallest,
/// so both go from the largest error down.
#[must_use]
fn swept_runs<'a>(
    args: &FlickerArgs,
    entries: &[Entry],
    runs: &'a [Run],
    measured: &'a [Measured],
    key: &str,
) -> Vec<(&'a Run, &'a Measured)> {
    let swept = |r: &Run| match key {
        "lightcuts" => args.sweep_lightcuts_errors.contains(&r.lightcuts_error),
        _ => args.sweep_alphas.contains(&r.alpha),
    };
    let mut rows: Vec<(&Run, &Measured)> = runs
        .iter()
        .zip(measured)
        .filter(|(r, _)| entries[r.entry].key == key)
        .filter(|(r, _)| swept(r))
        .collect();
    match key {
        "lightcuts" => rows.sort_by(|a, b| b.0.lightcuts_error.total_cmp(&a.0.lightcuts_error)),
        _ => rows.sort_by(|a, b| a.0.alpha.total_cmp(&b.0.alpha)),
    }
    rows
}

/// Stochastic Lightcuts' curve over ε as JSON: each run's ε, flicker, error and time.
#[must_use]
fn lightcuts_json(lightcuts: &[(&Run, &Measured)]) -> Value {
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
        .collect()
}

/// One run of hierarchy `key` against Lightcuts at the same error: its JSON point and its
/// markdown row, Lightcuts' flicker read off `curve` ([`flicker_at_error`]) between two of the
/// `lightcuts` runs (`null` where the error lies outside the curve).
#[must_use]
fn at_equal_error(
    key: &str,
    (r, m): (&Run, &Measured),
    curve: &[(f64, f64)],
    lightcuts: &[(&Run, &Measured)],
) -> (Value, String) {
    let at = flicker_at_error(curve, m.rel_rmse);
    // No ratio to a hierarchy that does not flicker at all (its cell says so).
    let ratio = at.map(|(f, _)| f / m.flicker).filter(|q| q.is_finite());
    let between = at.map(|(_, [a, b])| {
        [
            lightcuts[a].0.lightcuts_error,
            lightcuts[b].0.lightcuts_error,
        ]
    });
    let point = json!({
        "alpha": r.alpha,
        "flicker": m.flicker,
        "rel_rmse": m.rel_rmse,
        "seconds_per_frame": m.seconds_per_frame,
        "lightcuts_flicker_at_same_error": at.map(|(f, _)| f),
        "lightcuts_over_lgh": ratio,
        "between_lightcuts_errors": between,
    });
    let cell = |x: Option<f64>, f: &dyn Fn(f64) -> String| {
        x.map_or_else(|| "outside Lightcuts' errors".to_string(), f)
    };
    let row = format!(
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
    (point, row)
}

/// Stochastic Lightcuts' curve over ε as a markdown table, with a note where its error or
/// flicker does not fall monotonically with ε.
#[must_use]
fn lightcuts_table(lightcuts: &[(&Run, &Measured)], monotone: bool) -> String {
    let mut markdown = String::from(
        "\n| Lightcuts ε | relative RMSE | flicker | seconds per frame |\n|---:|---:|---:|---:|\n",
    );
    for (r, m) in lightcuts {
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
    markdown
}

/// The paper's Fig. 10 on frame `t` of `seq`, into `dir`: two stochastic Lightcuts renders
/// (seeds 1 and 2) and their difference ×4 (false colour, red at a quarter of the brightest
/// pixel of scattered light); deterministic Lightcuts, the mean of `--fig10-renders`
/// stochastic renders, and the deterministic one's bias against that mean, likewise ×4;
/// `exact[t]` is the frame's brute-force reference, already rendered. Returns the figures.
fn fig10(
    args: &FlickerArgs,
    dir: &std::path::Path,
    seq: &Sequence,
    t: usize,
    exact: &[Image],
) -> Result<Value, crate::Error> {
    let exact = &exact[t];
    let mut lights = seq.paper_lights()?;
    seq.lights_at(&mut lights, &seq.volumes[t])?;
    let march = MarchSettings::with_shadows(Shadows::RayMarch);
    let lightcuts = |representative| Method::Lightcuts {
        settings: seq.lightcuts,
        representative,
    };
    let render = |representative| seq.render(t, &lights, lightcuts(representative), &march);
    let stochastic = |seed| render(Representative::Stochastic { seed });
    let (one, two) = (stochastic(1)?, stochastic(2)?);
    let deterministic = render(Representative::Brightest)?;
    let n = args.fig10_renders;
    let mut mean = Image::new(seq.camera.width(), seq.camera.height());
    for seed in 1..=u64::from(n) {
        let img = match seed {
            1 => one.clone(),
            2 => two.clone(),
            _ => stochastic(seed)?,
        };
        for (m, p) in mean.pixels.iter_mut().zip(&img.pixels) {
            *m += *p / n as f32;
        }
    }
    // The differences are of the scattered light (the emission is the same in every render):
    // red at a quarter of its brightest pixel. The emission alone, without the floor.
    let (frame, medium) = (&seq.volumes[t], &seq.medium);
    let (emission, _) = FrameRender::new(&lights, Method::Emission, frame, medium, &march, &())?
        .render(&seq.camera, &())?;
    let brightest = exact
        .pixels
        .iter()
        .zip(&emission.pixels)
        .map(|(&p, &e)| lgh_core::luminance(p - e))
        .fold(0.0f32, f32::max);
    let images = Fig10 {
        exact,
        one: &one,
        two: &two,
        deterministic: &deterministic,
        mean: &mean,
    };
    images.write(dir, brightest)?;
    Ok(images.report(args, dir))
}

/// The images of Fig. 10.
struct Fig10<'a> {
    exact: &'a Image,
    one: &'a Image,
    two: &'a Image,
    deterministic: &'a Image,
    mean: &'a Image,
}

impl Fig10<'_> {
    /// The PNGs into `dir`, differences red at a quarter of `brightest`.
    fn write(&self, dir: &std::path::Path, brightest: f32) -> Result<(), crate::Error> {
        let exposure = lgh_image::auto_exposure(self.exact);
        let png = |name: &str, img: &Image| -> Result<(), crate::Error> {
            Ok(lgh_image::write_png(&dir.join(name), img, exposure)?)
        };
        png("fig10-brute.png", self.exact)?;
        png("fig10-lightcuts-seed-1.png", self.one)?;
        png("fig10-lightcuts-seed-2.png", self.two)?;
        png("fig10-lightcuts-deterministic.png", self.deterministic)?;
        png("fig10-lightcuts-mean.png", self.mean)?;
        lgh_image::difference_png(
            &dir.join("fig10-seed-difference-x4.png"),
            self.one,
            self.two,
            brightest / 4.0,
        )?;
        lgh_image::difference_png(
            &dir.join("fig10-deterministic-bias-x4.png"),
            self.deterministic,
            self.mean,
            brightest / 4.0,
        )?;
        Ok(())
    }

    /// The JSON `fig10`.
    fn report(&self, args: &FlickerArgs, dir: &std::path::Path) -> Value {
        let rel = |a: &Image, r: &Image| lgh_image::compare(a, r).map(|s| s.rel_rmse);
        let mean_lum = |img: &Image| {
            img.pixels
                .iter()
                .map(|&p| f64::from(lgh_core::luminance(p)))
                .sum::<f64>()
                / img.pixels.len() as f64
        };
        let (one, two, exact) = (self.one, self.two, self.exact);
        let (deterministic, mean) = (self.deterministic, self.mean);
        json!({
            "frame": volumes_label(args),
            "stochastic_renders": args.fig10_renders,
            "seed_1_vs_seed_2_rel_rmse": rel(one, two),
            "stochastic_vs_brute_rel_rmse": rel(one, exact),
            "mean_of_stochastic_vs_brute_rel_rmse": rel(mean, exact),
            "deterministic_vs_mean_rel_rmse": rel(deterministic, mean),
            "deterministic_vs_brute_rel_rmse": rel(deterministic, exact),
            "deterministic_mean_bias": mean_lum(deterministic) / mean_lum(mean) - 1.0,
            "images": dir.display().to_string(),
        })
    }
}

/// Which frame --fig10 shows: the middle one.
fn volumes_label(args: &FlickerArgs) -> String {
    match (&args.frames, args.procedural) {
        (Some(range), _) => format!("the middle frame of {range}"),
        (_, Some(n)) => format!("frame {} of {n}", n / 2),
        _ => String::new(),
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
