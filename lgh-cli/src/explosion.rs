//! `lgh explosion`: renders frames of a real simulation cache (OpenVDB), lit by its own fire.

use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::{LightcutsSettings, Representative};
use lgh_volume::cache::{self, EmissionValues, GridNames};
use lgh_volume::medium::{grow_framing, EmissionInterpolation, EmissionModel, Medium, Volume};
use lgh_volume::pathtrace::{self, PathSettings};
use lgh_volume::render::{Camera, Framing, MarchSettings, PixelRefinement, Up};
use lgh_volume::thin_smoke::ThinSmoke;
use lgh_volume::{ExplosionLights, FrameRender, Method, Shadows};

use clap::ArgMatches;

use crate::dark;
use crate::manifest::{self, FrameFile, Manifest, SceneFile};
use crate::output::{
    self, DepthArg, EmissionSamplesArg, MarchArgs, PixelSamplesArg, Rendered, ScatterArgs,
};
use crate::progress::{self, Bars};
use crate::room::Room;

/// The renderer behind the image (`--backend`): the ray marcher with one of the library's
/// many-lights [`Method`]s, or the path tracer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BackendArg {
    /// The lighting grid hierarchy (paper Sec. 3) at the paper's α.
    Lgh,
    /// Every light `S0`: the exact answer of the same light model.
    Brute,
    /// Lightcuts (Walter et al. 2005, the paper's Fig. 10 rival) at 2%: a light tree over the
    /// frame's lights with representatives drawn at random (a new tree every frame, as the
    /// paper ran it), shadows ray-marched.
    Lightcuts,
    /// Lightcuts with each cluster's brightest light as its representative: no randomness.
    LightcutsDeterministic,
    /// Unbiased volumetric path tracer: the physical reference.
    Pathtrace,
}

impl BackendArg {
    /// The ray marcher's method for `frame` (Lightcuts' representatives seeded by the frame's
    /// number, a new tree every frame), or `None` for the path tracer.
    fn method(self, alpha: f32, frame: Option<u32>) -> Option<Method> {
        let lightcuts = |representative| Method::Lightcuts {
            settings: LightcutsSettings::default(),
            representative,
        };
        Some(match self {
            BackendArg::Lgh => Method::Lgh { alpha },
            BackendArg::Brute => Method::Brute,
            BackendArg::Lightcuts => lightcuts(Representative::Stochastic {
                seed: u64::from(frame.unwrap_or(0)),
            }),
            BackendArg::LightcutsDeterministic => lightcuts(Representative::Brightest),
            BackendArg::Pathtrace => return None,
        })
    }

    /// The name in the EXR header and the summary (`lgh`, `brute`, …, `pathtrace`).
    fn name(self) -> &'static str {
        match self {
            BackendArg::Lgh => "lgh",
            BackendArg::Brute => "brute",
            BackendArg::Lightcuts => "lightcuts",
            BackendArg::LightcutsDeterministic => "lightcuts-deterministic",
            BackendArg::Pathtrace => "pathtrace",
        }
    }
}

/// How the emission between voxels follows the grids (`--emission-interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum InterpolationArg {
    /// The emission of the interpolated temperature (Cycles 3.x).
    Temperature,
    /// Each grid interpolated on its own (Cycles 4.x and later).
    Attributes,
}

/// How emission follows the temperature grid (`--emission-model`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ModelArg {
    /// Blender's Principled Volume: blackbody intensity × flame × 10⁻⁶ σT⁴/π × colour(T), the
    /// colour Cycles' volumes emit (below about 1900 K a negative blue, as Cycles keeps it; the
    /// EXR keeps it, the PNG clamps at display).
    Blender,
    /// Planck's law through CIE 1931, times --emission-scale.
    Planck,
}

/// Arguments of `lgh explosion`.
#[derive(Debug, clap::Args)]
pub struct ExplosionArgs {
    /// An OpenVDB file of the cache (with --frames: any frame; its last number is the frame).
    #[arg(long, required_unless_present = "manifest")]
    pub vdb: Option<PathBuf>,
    /// Frames to render, `A..B` inclusive (e.g. 50..56): one image each, `OUT_NNNN.exr`. With
    /// --manifest: the task's frames, within the manifest's (default: all of them).
    #[arg(long)]
    pub frames: Option<String>,
    /// Output image (linear OpenEXR); a tone-mapped PNG is written beside it.
    #[arg(long, required_unless_present = "manifest")]
    pub out: Option<PathBuf>,
    /// Read the frames once and write a sequence manifest here (JSON: the common grid, the
    /// framing, the lights, every setting, the files' SHA-256), rendering nothing: farm tasks
    /// then render any frames with --manifest, to the same pixels as one run over all frames.
    #[arg(long, conflicts_with = "manifest")]
    pub prepare: Option<PathBuf>,
    /// Render frames of a sequence prepared with --prepare, reading only those frames: a farm
    /// task. Takes only --frames, --resume, --quiet and --threads beside it.
    #[arg(long)]
    pub manifest: Option<PathBuf>,
    /// Skip frames whose EXR and PNG exist and whose header says they are of this sequence and
    /// settings (`lgh:sequence`); render the others. Outputs are written whole or not at all.
    #[arg(long)]
    pub resume: bool,
    /// The grid emission follows (Blender: temperature; or flame, heat). A vec3 grid (Houdini's
    /// and Cycles' `emission`) is an RGB emission read as it is: `j = --emission-scale × rgb`
    /// (Cycles' Emission Strength × Emission Color), no blackbody, no temperature cut, no flame.
    #[arg(long, default_value = "temperature")]
    pub emission_grid: String,
    /// Smoke density grid.
    #[arg(long, default_value = "density")]
    pub density_grid: String,
    /// Grid multiplying the emission; `none` for none. Named, it must exist; by default
    /// Blender's `flame` is used when the file has it.
    #[arg(long)]
    pub flame_grid: Option<String>,
    /// Emission model.
    #[arg(long, value_enum, default_value_t = ModelArg::Blender)]
    pub emission_model: ModelArg,
    /// How the emission between voxel centres follows the grids: `temperature`, the emission of
    /// the interpolated temperature (Cycles 3.x), or `attributes`, each grid interpolated on its
    /// own — the voxels' emission interpolated, times the interpolated flame (Cycles 4.x and
    /// later; brighter on thin flames)
    #[arg(long, value_enum, default_value_t = InterpolationArg::Temperature)]
    pub emission_interpolation: InterpolationArg,
    /// Kelvin per unit of the emission grid (Blender's Principled Volume temperature: 1000).
    #[arg(long, default_value_t = 1000.0)]
    pub temperature_scale: f32,
    /// `IGNITION,MAX`: the emission grid is a Blender fluid domain's `flame` (0..1), read as
    /// Cycles reads the domain's `temperature` attribute: `IGNITION + flame × (MAX − IGNITION)`
    /// where the flame exceeds 0.01, else 0, then × --temperature-scale. IGNITION and MAX are
    /// the domain's Fire > Ignition and Maximum temperature (Blender's defaults: 1.5,3). A
    /// domain's cache as Cycles renders it: `--emission-grid flame --flame-grid none
    /// --flame-temperature 1.5,3`.
    #[arg(long)]
    pub flame_temperature: Option<String>,
    /// Blender's blackbody intensity (model blender) or k_e (model planck).
    #[arg(long, default_value_t = 1.0)]
    pub emission_scale: f32,
    /// No emission at or below this temperature (kelvin): the lights are the hotter voxels
    /// [default: 0 with --emission-model blender, whose Principled Volume emits at every
    /// temperature (a cut at 800 K leaves out some of a fireball's light); 800 with planck, whose
    /// visible emission below it is negligible]
    #[arg(long)]
    pub min_temperature: Option<f32>,
    /// Extinction per unit density (Blender's Principled Volume density).
    #[arg(long, default_value_t = 1.0)]
    pub density_scale: f32,
    /// Single-scattering albedo σ_s/σ_t (Blender's default scattering colour: 0.5).
    #[arg(long, default_value_t = 0.5)]
    pub albedo: f32,
    /// Don't place frames by Blender's config/config_NNNN.uni domain offset.
    #[arg(long)]
    pub no_domain_offset: bool,
    /// Renderer.
    #[arg(long, value_enum, default_value_t = BackendArg::Lgh)]
    pub backend: BackendArg,
    /// The paper's α (backend lgh).
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true)]
    pub alpha: f32,
    #[command(flatten)]
    pub march: MarchArgs,
    /// Skip the lights' shadows in a frame whose smoke is so thin that skipping them adds at
    /// most this share of the emitted light to its scattered light: a bound from its densest
    /// voxel and its grid's size (`lgh_volume::thin_smoke`), the image otherwise untouched
    /// (emission, absorption along camera rays). 0 never skips; not with --scene, whose
    /// surfaces shadow each other.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub shadow_skip: f32,
    #[command(flatten)]
    pub scatter: ScatterArgs,
    /// Paths per pixel (backend pathtrace).
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Scattering events per path (backend pathtrace; 1 = the marcher's single scattering).
    #[arg(long, default_value_t = 1)]
    pub max_scatter: u32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    pub width: usize,
    /// Image height in pixels.
    #[arg(long, default_value_t = 360)]
    pub height: usize,
    /// Camera `EX,EY,EZ,TX,TY,TZ[,FOV]` (eye, target, vertical field of view in degrees; default:
    /// framed on the smoke of all frames, seen from the front).
    #[arg(long, allow_hyphen_values = true)]
    pub camera: Option<String>,
    /// With --camera: the camera's up direction `UX,UY,UZ` (default: the world's up, --up). Any
    /// roll about the view axis: Blender's camera is its object's -Z view with +Y up.
    #[arg(long, allow_hyphen_values = true, requires = "camera")]
    pub camera_up: Option<String>,
    /// Lens shift `SX,SY`: the image plane moved right and up by these fractions of the image's
    /// larger side, the view direction kept (Blender's camera Shift X and Y with sensor fit Auto)
    /// [default: 0,0]
    #[arg(long, allow_hyphen_values = true)]
    pub camera_shift: Option<String>,
    /// The world's constant radiance `R,G,B` (linear) seen behind the smoke, through it:
    /// Blender's world colour × strength. The ray marcher shows it and lights nothing with it;
    /// with --backend pathtrace it is the environment, which also lights the smoke [default:
    /// black]
    #[arg(long)]
    pub background: Option<String>,
    /// Opaque surfaces around the smoke: an OBJ scene (with its MTL; diffuse albedo, Phong's
    /// `kd`) in the cache's world units, lit by the fire through the smoke and shadowed by
    /// itself (the paper's explosions in a box). Not with --backend pathtrace.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// The world's up axis (Blender: z).
    #[arg(long, value_enum, default_value_t = UpArg::Z)]
    pub up: UpArg,
    /// Render even when no frame has a light. Without it, a run whose frames are all dark is
    /// an error that says why (which grid, which flag) before any work.
    #[arg(long)]
    pub allow_dark: bool,
    /// Don't show progress.
    #[arg(long)]
    pub quiet: bool,
}

/// `--up`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum UpArg {
    /// +Y up (Houdini, most engines).
    Y,
    /// +Z up (Blender).
    Z,
}

/// Parses `A..B` (inclusive, at most 10,000 frames).
pub(crate) fn parse_frames(s: &str) -> Result<(u32, u32), crate::Error> {
    let bad = || format!("--frames {s}: expected A..B with whole numbers A ≤ B, e.g. 50..56");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let a: u32 = a.trim().parse().map_err(|_| bad())?;
    let b: u32 = b.trim().parse().map_err(|_| bad())?;
    if a > b || b - a >= 10_000 {
        return Err(bad().into());
    }
    Ok((a, b))
}

/// Comma-separated numbers of the flag `--flag`, as many as `counts` allows; `form` names them
/// in the error.
fn parse_numbers(
    flag: &str,
    s: &str,
    form: &str,
    counts: &[usize],
) -> Result<Vec<f32>, crate::Error> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--{flag} {s}: expected {form} numbers"))?;
    if !counts.contains(&v.len()) {
        let n = counts.iter().map(usize::to_string).collect::<Vec<_>>();
        return Err(format!(
            "--{flag} {s}: expected {} numbers ({form}), got {}",
            n.join(" or "),
            v.len()
        )
        .into());
    }
    Ok(v)
}

/// `--camera-up UX,UY,UZ`.
fn parse_camera_up(s: &str) -> Result<Vec3, crate::Error> {
    let v = parse_numbers("camera-up", s, "UX,UY,UZ", &[3])?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// `--camera-shift SX,SY`: finite fractions of the image's larger side.
fn parse_camera_shift(s: &str) -> Result<[f32; 2], crate::Error> {
    let v = parse_numbers("camera-shift", s, "SX,SY", &[2])?;
    if !(v[0].is_finite() && v[1].is_finite()) {
        return Err(format!("--camera-shift {s}: the shift must be finite").into());
    }
    Ok([v[0], v[1]])
}

/// `--background R,G,B`.
fn parse_background(s: &str) -> Result<Vec3, crate::Error> {
    let v = parse_numbers("background", s, "R,G,B", &[3])?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// `--flame-temperature IGNITION,MAX`: finite.
fn parse_flame_temperature(s: &str) -> Result<EmissionValues, crate::Error> {
    let v = parse_numbers("flame-temperature", s, "IGNITION,MAX", &[2])?;
    if !(v[0].is_finite() && v[1].is_finite()) {
        return Err(format!("--flame-temperature {s}: the temperatures must be finite").into());
    }
    Ok(EmissionValues::BlenderFlame {
        ignition: v[0],
        max_temperature: v[1],
    })
}

pub(crate) fn parse_camera(
    s: &str,
    up: Vec3,
    width: usize,
    height: usize,
) -> Result<Camera, crate::Error> {
    let v = parse_numbers("camera", s, "EX,EY,EZ,TX,TY,TZ[,FOV]", &[6, 7])?;
    let fov = v.get(6).copied().unwrap_or(40.0);
    Ok(Camera::look_at(
        Vec3::new(v[0], v[1], v[2]),
        Vec3::new(v[3], v[4], v[5]),
        up,
        fov,
        width,
        height,
    )?)
}

/// `OUT.exr` for one frame, `OUT_NNNN.exr` for each of several.
fn frame_out(out: &Path, frame: Option<u32>) -> PathBuf {
    match frame {
        None => out.to_path_buf(),
        Some(f) => {
            let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("frame");
            out.with_file_name(format!("{stem}_{f:04}.exr"))
        }
    }
}

/// The flags a farm task may give beside `--manifest`; every other setting is the manifest's.
/// `lgh explosion`'s default shadows and shadow step: every light shadowed as what it stands
/// for (`volumes`: a coarse light's shadow ray as a point lets through more than its lights'
/// rays do; as volume lights, less), in one-voxel steps.
const EXPLOSION_DEFAULTS: (Shadows, f32) = (Shadows::Volumes, 1.0);

const TASK_FLAGS: [&str; 4] = ["manifest", "frames", "resume", "quiet"];
/// Flags that are not settings of the render, so not kept in a manifest's `settings`: where
/// the frames are and which to render (the manifest's `files`), where the manifest is.
const NOT_SETTINGS: [&str; 6] = ["vdb", "frames", "prepare", "manifest", "resume", "quiet"];

/// `lgh explosion`'s flags given on the command line (not defaulted), except `except`.
fn given_flags(matches: &ArgMatches, except: &[&str]) -> Vec<clap::Arg> {
    crate::memory::given_flags::<ExplosionArgs>(matches, except)
}

/// The flags given on the command line (by long name, values as given; paths made absolute),
/// except [`NOT_SETTINGS`]: a manifest's `settings`, which every task replays.
fn given_settings(matches: &ArgMatches) -> Result<Vec<(String, Vec<String>)>, crate::Error> {
    let mut out = Vec::new();
    for arg in given_flags(matches, &NOT_SETTINGS) {
        let id = arg.get_id().as_str();
        let long = arg.get_long().ok_or("a flag without a long name")?;
        let values = if arg.get_action().takes_values() {
            let raw = matches.get_raw(id).into_iter().flatten();
            raw.map(|v| {
                let v = v
                    .to_str()
                    .ok_or_else(|| format!("--{long}: not UTF-8, which a manifest cannot keep"))?;
                Ok(if id == "out" || id == "scene" {
                    manifest::absolute(Path::new(v))?.display().to_string()
                } else {
                    v.to_string()
                })
            })
            .collect::<Result<Vec<String>, crate::Error>>()?
        } else {
            Vec::new()
        };
        out.push((long.to_string(), values));
    }
    Ok(out)
}

/// The arguments a manifest's tasks render with: its `settings` through the same parser as a
/// command line, the frames' files from its `files`.
fn replay(manifest: &Manifest) -> Result<ExplosionArgs, crate::Error> {
    #[derive(clap::Parser)]
    #[command(name = "lgh explosion")]
    struct Replay {
        #[command(flatten)]
        args: ExplosionArgs,
    }
    let mut argv = vec!["lgh explosion".to_string()];
    for (long, values) in &manifest.settings {
        if values.is_empty() {
            argv.push(format!("--{long}"));
        }
        argv.extend(values.iter().map(|v| format!("--{long}={v}")));
    }
    argv.push(format!("--vdb={}", manifest.files[0].path.display()));
    <Replay as clap::Parser>::try_parse_from(&argv)
        .map(|r| r.args)
        .map_err(|e| {
            crate::usage(format!(
                "the manifest's settings: {}",
                e.render().to_string().trim()
            ))
        })
}

/// What every frame's render shares: settings made ready, checked before any work.
struct Setup {
    march: MarchSettings,
    medium: Medium,
    names: GridNames,
    up: Up,
    /// `--camera`, parsed, with `--camera-up` and `--camera-shift` (`None`: framed on the smoke).
    camera: Option<Camera>,
    /// `--camera-shift`, for the camera framed on the smoke.
    shift: [f32; 2],
}

impl Setup {
    /// Checks every flag, then that each of `inputs` is a file, then makes the medium (its
    /// blackbody table is the first work): a bad flag or path is said at once.
    fn new(args: &ExplosionArgs, inputs: &[PathBuf], sink: &Sink) -> Result<Self, crate::Error> {
        crate::check_alpha(args.alpha)?;
        lgh_volume::render::check_image_size(args.width, args.height)?;
        if let Sink::Files = sink {
            output::check_out(args.out()?)?;
        }
        let mut march = args.march.settings(EXPLOSION_DEFAULTS, &args.scatter())?;
        if let Some(b) = &args.background {
            march.background = parse_background(b)?;
            march.check()?;
        }
        if args.backend == BackendArg::Pathtrace && args.scene.is_some() {
            return Err("--scene is the ray marcher's: the path tracer has no surfaces".into());
        }
        if let Some(p) = &args.scene {
            crate::files::check_file(p)
                .map_err(|e| crate::files::MissingFile(format!("--scene {e}")))?;
        }
        if args.backend == BackendArg::Pathtrace && args.scatter().depth() > 0 {
            return Err(
                "--scatter-depth is the ray marcher's: the path tracer scatters up to \
                        --max-scatter times"
                    .into(),
            );
        }
        if !(args.albedo.is_finite() && (0.0..=1.0).contains(&args.albedo)) {
            return Err(format!("--albedo {} must be in 0..=1", args.albedo).into());
        }
        if !(0.0..1.0).contains(&args.shadow_skip) {
            return Err(format!(
                "--shadow-skip {} must be a share of the emitted light in [0, 1)",
                args.shadow_skip
            )
            .into());
        }
        let up = match args.up {
            UpArg::Y => Up::Y,
            UpArg::Z => Up::Z,
        };
        // Checked before any work (and before a manifest keeps it for every task).
        let camera_up = args.camera_up.as_deref().map(parse_camera_up).transpose()?;
        let shift = args.camera_shift.as_deref().map(parse_camera_shift);
        let shift = shift.transpose()?.unwrap_or([0.0; 2]);
        let camera = args
            .camera
            .as_ref()
            .map(|c| {
                let up = camera_up.unwrap_or(up.vector());
                Ok::<_, crate::Error>(
                    parse_camera(c, up, args.width, args.height)?.with_shift(shift)?,
                )
            })
            .transpose()?;
        for p in inputs {
            crate::files::check_file(p)?;
        }
        let sigma_t = args.density_scale;
        let model = match args.emission_model {
            ModelArg::Blender => EmissionModel::Blender,
            ModelArg::Planck => EmissionModel::Planck,
        };
        let medium = Medium::new(
            (1.0 - args.albedo) * sigma_t,
            args.albedo * sigma_t,
            args.emission_scale,
            args.min_temperature(),
        )?
        .with_temperature_scale(args.temperature_scale)?
        .with_model(model)
        .with_interpolation(match args.emission_interpolation {
            InterpolationArg::Temperature => EmissionInterpolation::Temperature,
            InterpolationArg::Attributes => EmissionInterpolation::Attributes,
        });
        let names = GridNames {
            density: args.density_grid.clone(),
            emission: args.emission_grid.clone(),
            flame: match args.flame_grid.as_deref() {
                None => Some("flame".to_string()),
                Some("none") => None,
                Some(name) => Some(name.to_string()),
            },
            flame_required: args.flame_grid.is_some(),
            emission_values: match args.flame_temperature.as_deref() {
                None => EmissionValues::AsWritten,
                Some(s) => parse_flame_temperature(s)?,
            },
        };
        Ok(Setup {
            march,
            medium,
            names,
            up,
            camera,
            shift,
        })
    }
}

impl ExplosionArgs {
    /// The scattering arguments with this command's default depth: `auto` for the ray marcher
    /// (Blender's images scatter many times: single scattering alone held 0.80 of Cycles' mean
    /// on the fireball of `tools/cycles`), 0 for the path tracer, which scatters up to
    /// --max-scatter times instead.
    pub fn scatter(&self) -> ScatterArgs {
        self.scatter
            .or_depth(if self.backend == BackendArg::Pathtrace {
                DepthArg::Fixed(0)
            } else {
                DepthArg::Auto
            })
    }

    /// --min-temperature, or the emission model's default: 0 K for Blender's (its Principled
    /// Volume emits at every temperature), 800 K for Planck's (visible light below it is
    /// negligible).
    pub fn min_temperature(&self) -> f32 {
        self.min_temperature.unwrap_or(match self.emission_model {
            ModelArg::Blender => 0.0,
            ModelArg::Planck => 800.0,
        })
    }

    /// Where the frames sit: Blender's domain unless `--no-domain-offset`.
    fn placement(&self) -> cache::Placement {
        if self.no_domain_offset {
            cache::Placement::AsWritten
        } else {
            cache::Placement::BlenderDomain
        }
    }

    /// `--out` (required unless `--manifest`, whose settings hold it).
    fn out(&self) -> Result<&Path, crate::Error> {
        self.out
            .as_deref()
            .ok_or_else(|| "--out is required".into())
    }

    /// The frames of `--frames` (`[None]`: the one file `--vdb`).
    fn frame_numbers(&self) -> Result<Vec<Option<u32>>, crate::Error> {
        Ok(match &self.frames {
            None => vec![None],
            Some(s) => {
                let (a, b) = parse_frames(s)?;
                (a..=b).map(Some).collect()
            }
        })
    }
}

/// Runs `lgh explosion`: with `--manifest`, a farm task's frames; else one pass over the frames
/// for what they share (written as a manifest with `--prepare`), then every frame.
pub fn run(args: &ExplosionArgs, matches: &ArgMatches) -> Result<(), crate::Error> {
    if let Some(path) = &args.manifest {
        return run_task(args, matches, path);
    }
    let prepared = Prepared::new(args, &Sink::Files)?;
    run_into(args, matches, prepared, Sink::Files)
}

/// What every render checks before any work: the frames asked for, their files, and the
/// settings made ready ([`Setup`]).
struct Prepared {
    frames: Vec<Option<u32>>,
    paths: Vec<PathBuf>,
    setup: Setup,
}

impl Prepared {
    /// Every flag, then the frames' files: a wrong one is said before any work.
    fn new(args: &ExplosionArgs, sink: &Sink) -> Result<Self, crate::Error> {
        if args.prepare.is_some() && args.resume {
            return Err(crate::usage(
                "--resume is for rendering: --prepare renders nothing",
            ));
        }
        let frames = args.frame_numbers()?;
        let vdb = args.vdb.as_deref().ok_or("--vdb is required")?;
        let paths = frames
            .iter()
            .map(|f| match f {
                None => Ok(vdb.to_path_buf()),
                Some(f) => cache::frame_path(vdb, *f),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let setup = Setup::new(args, &paths, sink)?;
        Ok(Prepared {
            frames,
            paths,
            setup,
        })
    }
}

pub use crate::memory::{InMemoryError, Setting};

/// Where the frames go: `--out`'s files (the command), or memory ([`render_in_memory`]), with
/// the progress reported to the caller (`None`: the command's bars, unless `--quiet`).
enum Sink<'a> {
    Files,
    Memory(
        &'a mut Vec<FrameImage>,
        Option<&'a dyn lgh_volume::Progress>,
    ),
}

/// A frame rendered into memory: the image `lgh explosion` writes to its EXR.
#[derive(Clone, Debug)]
pub struct FrameImage {
    /// The frame's number (`--frames`), or `None` for the one file `--vdb`.
    pub frame: Option<u32>,
    /// The image: linear RGB, the EXR's pixels.
    pub image: lgh_image::Image,
}

/// The flags of files, which a render into memory has none of.
const FILE_FLAGS: [&str; 4] = ["out", "prepare", "manifest", "resume"];

/// `lgh explosion` with the command line `args` (after `lgh explosion`, without `--out`),
/// every frame rendered into memory instead of files: the same settings, defaults, checks and
/// images as the command, bit for bit (`lgh-py`'s tests hold them to it), and nothing printed
/// but the progress bars (none with `--quiet`) and warnings. A bad flag is a [`Usage`](crate::Usage)
/// error with the parser's message.
pub fn render_in_memory<I, T>(args: I) -> Result<Vec<FrameImage>, InMemoryError>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    render_in_memory_with(args, None)
}

/// [`render_in_memory`], reporting each frame's progress (its scattering, shadow maps and
/// image: [`lgh_volume::Progress`]) to `progress` instead of the command's bars.
pub fn render_in_memory_with<I, T>(
    args: I,
    progress: Option<&dyn lgh_volume::Progress>,
) -> Result<Vec<FrameImage>, InMemoryError>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let (args, matches) = parse_in_memory(args).map_err(InMemoryError::Refused)?;
    let mut images = Vec::new();
    let sink = Sink::Memory(&mut images, progress);
    let prepared = Prepared::new(&args, &sink).map_err(InMemoryError::Refused)?;
    run_into(&args, &matches, prepared, sink).map_err(InMemoryError::Failed)?;
    Ok(images)
}

/// A frame made ready to render from many cameras: what [`FrameRender`] borrows, owned — the
/// frame, its lights set to its intensities, the medium, `--scene`'s room — and the settings
/// it is made with. [`FrameParts::frame_render`] makes the frame render once (its scattering
/// and shadows), whose `render` then takes any camera ([`FrameParts::camera_of`]); the Python
/// package's `FrameRender` holds both.
pub struct FrameParts {
    /// The frame.
    pub volume: Volume,
    /// Its lights, at its intensities.
    pub lights: ExplosionLights,
    /// The medium.
    pub medium: Medium,
    room: Option<Room>,
    /// The settings, resolved for [`camera`](Self::camera) where they depend on a camera
    /// (`--pixel-samples auto`, `--cache-level auto`).
    pub march: MarchSettings,
    /// The many-lights method.
    pub method: Method,
    /// The camera of the command line (`--camera`, or the framing of the smoke).
    pub camera: Camera,
    up: Up,
}

impl FrameParts {
    /// The frame's render: its scattering pass and shadows made (what `progress` hears), ready
    /// for any camera.
    pub fn frame_render<'a>(
        &'a self,
        progress: &dyn lgh_volume::Progress,
    ) -> Result<FrameRender<'a>, crate::Error> {
        let frame = FrameRender::new(
            &self.lights,
            self.method,
            &self.volume,
            &self.medium,
            &self.march,
            progress,
        )?;
        Ok(match &self.room {
            Some(room) => frame.with_surfaces(room),
            None => frame,
        })
    }

    /// A camera as `lgh explosion`'s flags give it: `camera` (`EX,EY,EZ,TX,TY,TZ[,FOV]`),
    /// `up` (`--camera-up`; default: the world's up), `shift` (`--camera-shift`), a
    /// `width × height` image; errors say which flag is wrong.
    pub fn camera_of(
        &self,
        camera: &str,
        up: Option<&str>,
        shift: Option<&str>,
        (width, height): (usize, usize),
    ) -> Result<Camera, crate::Error> {
        let up = up.map(parse_camera_up).transpose()?;
        let shift = shift.map(parse_camera_shift).transpose()?;
        let camera = parse_camera(camera, up.unwrap_or(self.up.vector()), width, height)?;
        Ok(camera.with_shift(shift.unwrap_or([0.0; 2]))?)
    }
}

/// `lgh explosion --vdb VDB` with the command line `args` made ready to render from many
/// cameras ([`FrameParts`]): the same checks as [`render_in_memory`], one file (no `--frames`),
/// the ray marcher (not `--backend pathtrace`). The camera of `args` resolves the settings
/// that depend on a camera; its render is [`render_in_memory`]'s image, bit for bit.
pub fn prepare_in_memory<I, T>(args: I) -> Result<FrameParts, InMemoryError>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let (args, matches) = parse_in_memory(args).map_err(InMemoryError::Refused)?;
    if args.frames.is_some() {
        let e = "--frames: a prepared frame is one file (--vdb)";
        return Err(InMemoryError::Refused(crate::usage(e)));
    }
    if args.backend == BackendArg::Pathtrace || args.scatter.scatter_shares {
        let e = "--backend pathtrace and --scatter-shares render no prepared frame";
        return Err(InMemoryError::Refused(crate::usage(e)));
    }
    let mut images = Vec::new();
    let sink = Sink::Memory(&mut images, None);
    let prepared = Prepared::new(&args, &sink).map_err(InMemoryError::Refused)?;
    over_frames(&args, &matches, prepared, sink, |frames, _| {
        frames.into_parts().map(Some)
    })
    .map_err(InMemoryError::Failed)?
    .ok_or_else(|| InMemoryError::Refused("--prepare: a prepared frame writes no manifest".into()))
}

/// Every setting a render into memory takes ([`render_in_memory`]): the flags of `lgh
/// explosion` but `--vdb` and the flags of files, in the command's order.
#[must_use]
pub fn settings() -> Vec<Setting> {
    crate::memory::settings::<ExplosionArgs>("vdb", &FILE_FLAGS)
}

/// The command line `args` of [`render_in_memory`], parsed; the flags of files refused.
fn parse_in_memory<I, T>(args: I) -> Result<(ExplosionArgs, ArgMatches), crate::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    crate::memory::parse::<ExplosionArgs, _, _>("lgh explosion", args, &FILE_FLAGS)
}

/// One pass over the frames for what they share (written as a manifest with `--prepare`),
/// then every frame into `sink`.
fn run_into(
    args: &ExplosionArgs,
    matches: &ArgMatches,
    prepared: Prepared,
    sink: Sink,
) -> Result<(), crate::Error> {
    over_frames(args, matches, prepared, sink, |frames, n| {
        frames.render(0..n)
    })
}

/// One pass over the frames for what they share (written as a manifest with `--prepare`,
/// which ends here), then `finish(frames, count)`.
fn over_frames<T: Default>(
    args: &ExplosionArgs,
    matches: &ArgMatches,
    prepared: Prepared,
    sink: Sink,
    finish: impl FnOnce(Frames<'_>, usize) -> Result<T, crate::Error>,
) -> Result<T, crate::Error> {
    let Prepared {
        frames,
        paths,
        setup,
    } = prepared;
    // The room is read (and its files hashed for the manifest) before any frame.
    let room = args.scene.as_deref().map(Room::load).transpose()?;
    let t = Instant::now();
    let (seq, last) = cache::Sequence::open_with_last(&paths, &setup.names, args.placement())?;
    let n = seq.len();
    let pass = Pass::over(args, &setup, &seq, Rc::new(last))?;
    let files = frames
        .iter()
        .zip(&paths)
        .map(|(&f, p)| {
            let config =
                cache::blender_config_path(p).filter(|c| !args.no_domain_offset && c.is_file());
            FrameFile::hash(f, p, config.as_deref())
        })
        .collect::<Result<Vec<_>, _>>()?;
    let manifest = Manifest {
        files,
        layout: seq.layout(),
        framing: pass.framing,
        lights: pass.lights.as_ref().map(|l| l.voxels().to_vec()),
        all_dark: pass.all_dark,
        settings: given_settings(matches)?,
        scene: room.as_ref().map_or(Vec::new(), |r| r.files().to_vec()),
    };
    if let Some(why) = &manifest.all_dark {
        let what = format!("no light in any of the {n} frame(s): {why}");
        if !args.allow_dark {
            return Err(format!("{what}; --allow-dark renders it anyway").into());
        }
        eprintln!("lgh: warning: {what}");
    }
    let load_s = t.elapsed().as_secs_f64();
    if let Some(path) = &args.prepare {
        write_manifest(&manifest, path, load_s)?;
        return Ok(T::default());
    }
    let frames = Frames {
        args,
        setup: &setup,
        manifest: &manifest,
        seq,
        lights: pass.lights,
        room,
        kept: Some((n - 1, pass.kept)),
        load_s: Some(load_s),
        sink,
    };
    finish(frames, n)
}

/// What the pass over a sequence's frames found.
struct Pass {
    /// The lights: every voxel hot in any frame (`None` for the path tracer, which needs none).
    lights: Option<ExplosionLights>,
    /// The smoke's box over all frames.
    framing: Option<(Vec3, Vec3)>,
    /// Why no frame has a light, if none has.
    all_dark: Option<String>,
    /// The last frame, kept for its render.
    kept: Rc<Volume>,
}

impl Pass {
    /// One pass over the frames of `seq`, one in memory at a time, for what depends on all of
    /// them. None depends on the order, so the pass starts with the `last` frame, which opening
    /// the sequence has just read, and that frame is kept for its render.
    fn over(
        args: &ExplosionArgs,
        setup: &Setup,
        seq: &cache::Sequence,
        last: Rc<Volume>,
    ) -> Result<Pass, crate::Error> {
        let mut framing = None;
        let mut all_dark = None;
        let kept = Rc::clone(&last);
        let mut lights = None;
        let bar = progress::bar(seq.len() as u64, "reading frames", args.quiet);
        let others = (0..seq.len() - 1).map(|i| seq.frame(i).map(Rc::new));
        let mut any_lit = false;
        let frames_read = std::iter::once(Ok(last)).chain(others).map(|v| {
            let v = v?;
            framing = grow_framing(framing, &v);
            if !any_lit {
                all_dark = dark::why_no_lights(&v, &setup.medium, &setup.names);
                any_lit = all_dark.is_none();
            }
            bar.inc(1);
            Ok::<_, lgh_volume::ReadError>(v)
        });
        if args.backend != BackendArg::Pathtrace {
            lights = Some(ExplosionLights::from_frames(frames_read, &setup.medium)?);
        } else {
            for v in frames_read {
                v?;
            }
        }
        bar.finish_and_clear();
        Ok(Pass {
            lights,
            framing,
            all_dark,
            kept,
        })
    }
}

/// `--prepare`: writes the manifest (whole or not at all) and says how to render from it.
fn write_manifest(manifest: &Manifest, path: &Path, load_s: f64) -> Result<(), crate::Error> {
    let text = manifest.to_json();
    lgh_image::write_atomic(path, |w| w.write_all(text.as_bytes()))
        .map_err(|e| format!("--prepare {}: {e}", path.display()))?;
    let frames = match manifest.range() {
        Some((a, b)) => format!("frames {a}..{b}"),
        None => "one frame".to_string(),
    };
    say!(
        "lgh explosion: {frames} prepared in {load_s:.2} s ({} lights, {} bytes) -> {}",
        manifest.lights.as_ref().map_or(0, Vec::len),
        text.len(),
        path.display()
    );
    say!(
        "  render a task's frames with: lgh explosion --manifest {} --frames A..B [--resume]",
        path.display()
    );
    Ok(())
}

/// `--manifest`: renders the task's frames (`--frames`, or all of the manifest's), reading
/// only those, with the manifest's settings.
fn run_task(args: &ExplosionArgs, matches: &ArgMatches, path: &Path) -> Result<(), crate::Error> {
    if let Some(arg) = given_flags(matches, &TASK_FLAGS).first() {
        return Err(crate::usage(format!(
            "--{}: a task takes its settings from the manifest ({}); give them to --prepare \
             (a task takes only --frames, --resume, --quiet and --threads)",
            arg.get_long().unwrap_or("?"),
            path.display()
        )));
    }
    let manifest = Manifest::read(path)?;
    let mut full = replay(&manifest)?;
    full.quiet = args.quiet;
    full.resume = args.resume;
    let setup = Setup::new(&full, &[], &Sink::Files)?;
    let which = match (&args.frames, manifest.range()) {
        (None, _) => 0..manifest.files.len(),
        (Some(s), Some((first, last))) => {
            let (a, b) = parse_frames(s)?;
            if a < first || b > last {
                return Err(crate::usage(format!(
                    "--frames {s}: the manifest has frames {first}..{last}"
                )));
            }
            (a - first) as usize..(b - first + 1) as usize
        }
        (Some(s), None) => {
            return Err(crate::usage(format!(
                "--frames {s}: the manifest is of one file, not frames"
            )))
        }
    };
    let paths: Vec<PathBuf> = manifest.files.iter().map(|f| f.path.clone()).collect();
    let seq = cache::Sequence::with_layout(
        &paths,
        &setup.names,
        full.placement(),
        manifest.layout.clone(),
    )?;
    // The scene the task reads must be the one --prepare read.
    let room = full.scene.as_deref().map(Room::load).transpose()?;
    if let Some(r) = &room {
        SceneFile::check(r.files(), &manifest.scene)?;
    }
    let frames = Frames {
        args: &full,
        setup: &setup,
        manifest: &manifest,
        seq,
        lights: None,
        room,
        kept: None,
        load_s: None,
        sink: Sink::Files,
    };
    frames.render(which)
}

/// Whether `out` (and its PNG) are a finished render of the sequence `digest`: what `--resume`
/// skips.
fn finished(out: &Path, digest: &str) -> bool {
    if !(out.is_file() && out.with_extension("png").is_file()) {
        return false;
    }
    let same = lgh_image::read_exr_attributes(out)
        .map(|attrs| {
            attrs
                .iter()
                .any(|(k, v)| k == "lgh:sequence" && v == digest)
        })
        .unwrap_or(false);
    if !same {
        eprintln!(
            "lgh: {} is not of this sequence and settings (its lgh:sequence differs): rendering it again",
            out.display()
        );
    }
    same
}

/// A sequence's frames to render, with what their renders share.
struct Frames<'a> {
    args: &'a ExplosionArgs,
    setup: &'a Setup,
    manifest: &'a Manifest,
    seq: cache::Sequence,
    /// The pass's lights, or `None` to place them from the manifest (the path tracer has none).
    lights: Option<ExplosionLights>,
    /// `--scene`'s surfaces.
    room: Option<Room>,
    /// A frame already in memory (its index into the manifest's files).
    kept: Option<(usize, Rc<Volume>)>,
    /// Seconds the pass over the frames took (`None`: a farm task, which read the manifest).
    load_s: Option<f64>,
    /// Where the frames go.
    sink: Sink<'a>,
}

impl Frames<'_> {
    /// Renders the frames `which` (indices into the manifest's files).
    fn render(mut self, which: std::ops::Range<usize>) -> Result<(), crate::Error> {
        let camera = self.camera()?;
        let march = self.march_for(&camera);
        if let Sink::Memory(..) = self.sink {
            for n in which {
                let volume = self.volume(n)?;
                self.render_frame(n, &volume, (&camera, &march), None)?;
            }
            return Ok(());
        }
        self.announce(which.len())?;
        let digest = self.manifest.digest();
        for n in which {
            let out = frame_out(self.args.out()?, self.manifest.files[n].frame);
            if self.args.resume && finished(&out, &digest) {
                say!("  {}: finished before, skipped (--resume)", out.display());
                continue;
            }
            let volume = self.volume(n)?;
            self.render_frame(n, &volume, (&camera, &march), Some(&out))?;
        }
        Ok(())
    }

    /// The settings for `camera`: the rays a pixel side (the emission's too) and the cache's
    /// first level, from the image's and the voxels' sizes with `auto` (the defaults): one
    /// resolution for the whole sequence.
    fn march_for(&self, camera: &Camera) -> MarchSettings {
        let (lo, hi) = self.manifest.framing.unwrap_or_else(|| self.seq.bounds());
        self.args.march.for_camera(
            self.setup.march,
            (PixelSamplesArg::Auto, EmissionSamplesArg::Auto),
            camera,
            0.5 * (lo + hi),
            self.seq.voxel_size(),
        )
    }

    /// `march` for `volume`: without shadows where its smoke is too thin for them to matter
    /// (`--shadow-skip`, by [`ThinSmoke`]'s bound; not with `--scene`), with that bound.
    fn frame_march(
        &self,
        march: &MarchSettings,
        volume: &Volume,
    ) -> (MarchSettings, Option<ThinSmoke>) {
        // A room's surfaces shadow each other, and without shadows or with `--shadow-skip 0`
        // there is nothing to decide: no pass over the density.
        if self.room.is_some() || march.shadows == Shadows::None || self.args.shadow_skip <= 0.0 {
            return (*march, None);
        }
        let thin = ThinSmoke::of(volume, &self.setup.medium);
        if !thin.skips(self.args.shadow_skip) {
            return (*march, None);
        }
        let unshadowed = MarchSettings {
            shadows: Shadows::None,
            ..*march
        };
        (unshadowed, Some(thin))
    }

    /// The first frame made ready to render from any camera ([`prepare_in_memory`]).
    fn into_parts(mut self) -> Result<FrameParts, crate::Error> {
        let camera = self.camera()?;
        let volume = self.volume(0)?;
        let march = self.frame_march(&self.march_for(&camera), &volume).0;
        self.lights_for(&volume)?;
        let lights = self
            .lights
            .take()
            .ok_or("the path tracer prepares no frame")?;
        let volume = Rc::try_unwrap(volume).map_err(|_| "the frame is still shared")?;
        let method = self
            .args
            .backend
            .method(self.args.alpha, self.manifest.files[0].frame)
            .ok_or("the path tracer prepares no frame")?;
        Ok(FrameParts {
            volume,
            lights,
            medium: self.setup.medium.clone(),
            room: self.room.take(),
            march,
            method,
            camera,
            up: self.setup.up,
        })
    }

    /// `--camera`, or the framing of the smoke of every frame.
    fn camera(&self) -> Result<Camera, crate::Error> {
        Ok(match self.setup.camera {
            Some(c) => c,
            None => {
                let (lo, hi) = self.manifest.framing.unwrap_or_else(|| self.seq.bounds());
                let (w, h) = (self.args.width, self.args.height);
                Camera::frame_up(lo, hi, w, h, self.setup.up)?.with_shift(self.setup.shift)?
            }
        })
    }

    /// The summary's first lines: the room, the frames and the grid.
    fn announce(&self, frames: usize) -> Result<(), crate::Error> {
        if let (Some(r), Some(p)) = (&self.room, &self.args.scene) {
            say!(
                "lgh explosion: {} triangles around the smoke ({})",
                r.triangles(),
                p.display()
            );
        }
        let dims = self.seq.dims();
        let source = self.load_s.map_or("as the manifest says".to_string(), |s| {
            format!("read in {s:.2} s")
        });
        say!(
            "lgh explosion: {} of {} frame(s) on a {}x{}x{} grid (voxel {:.5}); {source}",
            frames,
            self.seq.len(),
            dims[0],
            dims[1],
            dims[2],
            self.seq.voxel_size(),
        );
        Ok(())
    }

    /// Frame `n`: the one the pass has in memory is not read again; any other is read (a
    /// task's checked against the manifest's hash first: a run that hashed the files itself,
    /// moments ago, does not read them a fourth time).
    fn volume(&mut self, n: usize) -> Result<Rc<Volume>, crate::Error> {
        if let Some((_, v)) = self.kept.take_if(|(k, _)| *k == n) {
            return Ok(v);
        }
        if self.load_s.is_none() {
            self.manifest.files[n].verify()?;
        }
        Ok(Rc::new(self.seq.frame(n)?))
    }

    /// The lights set to `volume`'s intensities (placed from the manifest on the first frame
    /// of a task), `None` for the path tracer; and how many shine.
    fn lights_for(&mut self, volume: &Volume) -> Result<usize, crate::Error> {
        let (args, medium) = (self.args, &self.setup.medium);
        if args.backend == BackendArg::Pathtrace {
            return Ok(volume.emitting_voxels(medium));
        }
        let lights = match &mut self.lights {
            Some(l) => l,
            None => {
                let voxels =
                    self.manifest.lights.clone().ok_or(
                        "the manifest has no lights (it was prepared for the path tracer)",
                    )?;
                self.lights
                    .insert(ExplosionLights::at_hot_voxels(volume, voxels)?)
            }
        };
        if lights.prune() != args.march.prune {
            lights.set_prune(args.march.prune)?;
        }
        lights.set_coarse_shadows(args.march.coarse_shadows());
        lights.set_near_field(args.march.near_field.into());
        lights.set_coarse_spread(args.march.coarse_spread.into());
        lights.set_frame(volume, medium)?;
        Ok(lights.lit())
    }

    /// Renders frame `n` (`volume`) to `out` and says what it did (`None`: into the sink's
    /// memory, silently).
    fn render_frame(
        &mut self,
        n: usize,
        volume: &Volume,
        (camera, march): (&Camera, &MarchSettings),
        out: Option<&Path>,
    ) -> Result<(), crate::Error> {
        let (args, setup) = (self.args, self.setup);
        let file = &self.manifest.files[n];
        let lit = self.lights_for(volume)?;
        if lit == 0 && self.manifest.all_dark.is_none() {
            // Other frames have lights: this one is dark, say why and go on.
            if let Some(why) = dark::why_no_lights(volume, &setup.medium, &setup.names) {
                eprintln!("lgh: warning: {}: no lights: {why}", file.path.display());
            }
        }
        let mut extra = self.header(&file.path, lit);
        // Smoke too thin for its shadows to matter, by the bound: rendered without them.
        let (march, thin) = self.frame_march(march, volume);
        let march = &march;
        if let Some(thin) = &thin {
            extra.push(("shadow_skip", args.shadow_skip.to_string()));
            extra.push(("shadows_skipped_bound", format!("{:.6e}", thin.power_bound)));
        }
        if volume.colour.is_some() {
            // Read as it is: no blackbody, no temperature cut.
            extra.push(("emission_rgb", args.emission_grid.clone()));
        }
        let label = file
            .frame
            .map_or("rendering".to_string(), |f| format!("frame {f}"));
        let bars = Bars::new(args.quiet).with_render_label(label);
        let progress: &dyn lgh_volume::Progress = match self.sink {
            Sink::Memory(_, Some(p)) => p,
            _ => &bars,
        };
        let method = args.backend.method(args.alpha, file.frame);
        let (rendered, frame) = match (&self.lights, method) {
            (Some(lights), Some(method)) => {
                let medium = &setup.medium;
                let mut frame = FrameRender::new(lights, method, volume, medium, march, progress)?;
                if let Some(room) = &self.room {
                    frame = frame.with_surfaces(room);
                }
                let shares = output::shares(&args.scatter(), &frame, camera, progress)?;
                let rendered = Rendered::of(&frame, camera, progress)?;
                // After the render: the lighting cache's vertices are those it filled.
                extra.extend(output::frame_header(&frame, shares.as_ref()));
                (rendered, Some((frame, shares)))
            }
            _ => (self.path_trace(volume, camera, progress)?, None),
        };
        let (Some(out), Sink::Files) = (out, &mut self.sink) else {
            if let Sink::Memory(images, _) = &mut self.sink {
                images.push(FrameImage {
                    frame: file.frame,
                    image: rendered.image,
                });
            }
            return Ok(());
        };
        let png = rendered.write(out, march, args.backend.name(), extra)?;
        let mut work = rendered.stats.map_or(String::new(), |st| {
            format!(", {:.1} lights per shading point", st.lights_per_point())
        });
        if let (Some(st), PixelRefinement::Adaptive { .. }) =
            (rendered.stats, march.pixel_refinement)
        {
            let n = march.pixel_samples;
            let share = 100.0 * st.refined_pixels as f64 / (args.width * args.height) as f64;
            work += &format!(
                ", {share:.1}% of pixels refined to {m}×{m} rays",
                m = march.pixel_refinement.refined(n)
            );
        }
        if let Some((f, maps)) = frame.as_ref().and_then(|(f, _)| Some((f, f.cube_maps()?))) {
            let (mb, s) = (maps.bytes() as f64 / 1e6, f.seconds());
            work += &format!(", cube maps {mb:.1} MB traced in {:.2} s", s.shadows);
        }
        if let Some(c) = frame.as_ref().and_then(|(f, _)| f.lighting_cache()) {
            let s = c.stats();
            work += &format!(
                ", lighting cache {} vertices ({:.1} CPU-s)",
                s.vertices, s.cpu_seconds
            );
        }
        say!(
            "  {}: {lit} lights, {} {:.1} s{work} -> {}, {}",
            file.path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or("?"),
            args.backend.name(),
            rendered.seconds,
            out.display(),
            png.display()
        );
        if let Some(thin) = thin {
            say!(
                "  shadows skipped: the smoke's optical depth is at most {:.3}, so they would \
                 take at most {:.3}% of the emitted light from the scattered light \
                 (--shadow-skip {}%)",
                thin.optical_depth,
                100.0 * thin.power_bound,
                100.0 * args.shadow_skip
            );
        }
        if let Some((frame, shares)) = &frame {
            output::say_scattering(frame, shares.as_ref())?;
        }
        Ok(())
    }

    /// The path tracer's image of `volume`.
    fn path_trace(
        &self,
        volume: &Volume,
        camera: &Camera,
        progress: &dyn lgh_volume::Progress,
    ) -> Result<Rendered, crate::Error> {
        let settings = PathSettings {
            spp: self.args.spp,
            max_scatter: self.args.max_scatter,
            environment: self.setup.march.background,
            ..Default::default()
        };
        Rendered::timed(|| {
            let rows = camera.height() as u64;
            lgh_volume::Progress::begin(progress, lgh_volume::Phase::Render, rows);
            let image = pathtrace::render(volume, &self.setup.medium, camera, &settings, &|r| {
                lgh_volume::Progress::advance(progress, r as u64)
            });
            lgh_volume::Progress::end(progress, lgh_volume::Phase::Render);
            Ok((image?, None))
        })
    }

    /// EXR header entries of a frame read from `path` with `lit` lights: the sequence, the
    /// medium's settings, the scene and the backend's own.
    fn header(&self, path: &Path, lit: usize) -> Vec<(&'static str, String)> {
        let args = self.args;
        let mut extra = vec![
            ("source", path.display().to_string()),
            ("sequence", self.manifest.digest()),
            ("lights", lit.to_string()),
            (
                "emission_model",
                format!("{:?}", args.emission_model).to_lowercase(),
            ),
            (
                "emission_interpolation",
                format!("{:?}", args.emission_interpolation).to_lowercase(),
            ),
            ("temperature_scale", args.temperature_scale.to_string()),
            ("emission_scale", args.emission_scale.to_string()),
            ("min_temperature", args.min_temperature().to_string()),
            ("density_scale", args.density_scale.to_string()),
            ("albedo", args.albedo.to_string()),
        ];
        if let Some(t) = &args.flame_temperature {
            extra.push(("flame_temperature", t.clone()));
        }
        if let Some(b) = &args.background {
            extra.push(("background", b.clone()));
        }
        if let Some(p) = &args.scene {
            extra.push(("scene", p.display().to_string()));
        }
        match args.backend {
            BackendArg::Lgh => {
                extra.push(("alpha", args.alpha.to_string()));
                extra.push(("prune", args.march.prune.to_string()));
            }
            BackendArg::Pathtrace => {
                extra.push(("spp", args.spp.to_string()));
                extra.push(("max_scatter", args.max_scatter.to_string()));
            }
            _ => {}
        }
        extra
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_and_cameras_parse_or_explain() {
        assert_eq!(parse_frames("50..56").unwrap(), (50, 56));
        assert!(parse_frames("56..50").is_err());
        assert!(parse_frames("5-6").is_err());
        assert!(parse_camera("0,0,5,0,0,0", Vec3::Y, 8, 8).is_ok());
        assert!(parse_camera("0,0,5,0,0,0,30", Vec3::Y, 8, 8).is_ok());
        assert!(parse_camera("0,0,5,0,0", Vec3::Y, 8, 8).is_err());
        assert!(parse_camera("0,0,0,0,0,0", Vec3::Y, 8, 8).is_err());
        // A rolled camera: its up direction given.
        assert_eq!(parse_camera_up("1, 0,0").unwrap(), Vec3::X);
        let e = parse_camera_up("1,0").unwrap_err().to_string();
        assert_eq!(e, "--camera-up 1,0: expected 3 numbers (UX,UY,UZ), got 2");
        assert_eq!(parse_camera_shift("0.25,-0.5").unwrap(), [0.25, -0.5]);
        assert_eq!(
            parse_flame_temperature("1.5,3").unwrap(),
            EmissionValues::BlenderFlame {
                ignition: 1.5,
                max_temperature: 3.0
            }
        );
        assert!(parse_flame_temperature("1.5")
            .unwrap_err()
            .to_string()
            .contains("IGNITION,MAX"));
        assert_eq!(
            parse_background("0.1,0.2,0.3").unwrap(),
            Vec3::new(0.1, 0.2, 0.3)
        );
        assert!(parse_background("1,2")
            .unwrap_err()
            .to_string()
            .contains("R,G,B"));
        assert!(parse_flame_temperature("nan,3")
            .unwrap_err()
            .to_string()
            .contains("finite"));
        let e = parse_camera_shift("0,inf").unwrap_err().to_string();
        assert_eq!(e, "--camera-shift 0,inf: the shift must be finite");
        assert!(parse_camera_shift("a,b")
            .unwrap_err()
            .to_string()
            .contains("SX,SY"));
        // The up direction needs a camera to turn: the framed one picks its own.
        let e = parse_in_memory(["--vdb", "f.vdb", "--camera-up", "0,0,1"]).unwrap_err();
        assert!(e.to_string().contains("--camera <CAMERA>"), "{e}");
        let given = [
            "--vdb",
            "f.vdb",
            "--camera",
            "0,-4,0,0,0,0",
            "--camera-up",
            "1,0,1",
        ];
        assert!(parse_in_memory(given).is_ok());
        assert_eq!(
            frame_out(Path::new("a/b.exr"), Some(7)),
            Path::new("a/b_0007.exr")
        );
    }
}
