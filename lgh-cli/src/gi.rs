//! `lgh gi` and `lgh bench gi`: indirect illumination of an OBJ scene from virtual point lights
//! (paper Sec. 6.4, Fig. 13), shaded through the hierarchy or brute force with shadow rays.
//! The pipeline is lgh-vpl's [`GiScene`]; here the flags become its settings and methods, and
//! its renders become images, lines and JSON.

use std::path::{Path, PathBuf};
use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_image::Image;
use lgh_vpl::gi::{
    self, AdaptiveShading, CoarseShading, DirectLight, GiError, GiMethod, GiScene, GiSetting,
    GiSettings, PerLight, SampleSetting,
};
use lgh_vpl::indirect::refine::DEFAULT_POINT_ERROR;
use lgh_vpl::primary::{LightParseError, PrimaryLight};
use lgh_vpl::vpl::{VplError, VplSettings};
use lgh_vpl::{Camera, Mesh};
use serde_json::json;

use crate::memory::{InMemoryError, Setting};
use crate::output;
use crate::progress::Bars;

/// `--aggregation`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Aggregation {
    /// One hierarchy per dominant normal axis, coarse lights with their bucket's lobe.
    Buckets,
    /// The paper's: one hierarchy, VPLs aggregated as isotropic points.
    Isotropic,
}

impl From<Aggregation> for gi::Aggregation {
    fn from(a: Aggregation) -> Self {
        match a {
            Aggregation::Buckets => gi::Aggregation::Buckets,
            Aggregation::Isotropic => gi::Aggregation::Isotropic,
        }
    }
}

/// `lgh gi --backend`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum GiBackend {
    /// The lighting grid hierarchy at `--alpha`.
    Lgh,
    /// Every VPL: the exact answer of the same model.
    Brute,
    /// Lightcuts (Walter et al. 2005) at `--lightcuts-error`, each cluster shaded as its
    /// representative VPL.
    Lightcuts,
}

/// `--sample-allocation`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SampleAllocation {
    /// `--shadow-samples` for every coarse light.
    Uniform,
    /// In proportion to each coarse light's luminance against its level's mean.
    Intensity,
    /// Chosen per shading point, in proportion to what each coarse light brings there
    /// unshadowed (a power-of-two prefix of its nested representatives).
    Adaptive,
}

impl SampleAllocation {
    /// The flag's value, for messages.
    fn name(self) -> &'static str {
        match self {
            SampleAllocation::Uniform => "uniform",
            SampleAllocation::Intensity => "intensity",
            SampleAllocation::Adaptive => "adaptive",
        }
    }
}

/// `--coarse-shadows`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CoarseShadows {
    /// The paper's (Fig. 11d): k points drawn with the light's variance σ² (eq. 4).
    Gaussian,
    /// Beyond the paper: k of the VPLs the light stands for, drawn once per light by weight,
    /// each shaded with its own lobe and shadow ray.
    Representatives,
}

/// `--missing-textures`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MissingTextures {
    /// A missing texture file is an error naming it.
    Error,
    /// A material whose texture file is missing is grey (albedo 0.5), with a warning.
    Grey,
}

impl From<MissingTextures> for lgh_vpl::MissingTextures {
    fn from(m: MissingTextures) -> Self {
        match m {
            MissingTextures::Error => lgh_vpl::MissingTextures::Error,
            MissingTextures::Grey => lgh_vpl::MissingTextures::Grey,
        }
    }
}

/// `--normals`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Normals {
    /// The OBJ's vertex normals (`vn`), interpolated; the face normal where a face names none.
    Vertex,
    /// Every face its own normal, the file's `vn` ignored (and named).
    Face,
}

impl Normals {
    /// The flag's value, for the EXR header and the JSON.
    fn name(self) -> &'static str {
        match self {
            Normals::Vertex => "vertex",
            Normals::Face => "face",
        }
    }
}

impl From<Normals> for lgh_vpl::Normals {
    fn from(n: Normals) -> Self {
        match n {
            Normals::Vertex => lgh_vpl::Normals::Vertex,
            Normals::Face => lgh_vpl::Normals::Face,
        }
    }
}

/// `--blend-at`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BlendAt {
    /// At each representative's own distance, every coarse light that may reach the point
    /// gathered: unbiased against brute force over the same VPLs.
    Representative,
    /// At the coarse light's centre, as in the paper's eq. (3): the hierarchy's smoothing stays.
    Centre,
}

impl From<BlendAt> for lgh_vpl::indirect::BlendAt {
    fn from(b: BlendAt) -> Self {
        match b {
            BlendAt::Representative => lgh_vpl::indirect::BlendAt::Representative,
            BlendAt::Centre => lgh_vpl::indirect::BlendAt::Centre,
        }
    }
}

/// `--lobe-error`, `--point-error`: a bound, or `off`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound(pub Option<f32>);

/// Parses a [`Bound`]: `off`, or a number (checked with the other settings).
fn parse_bound(s: &str) -> Result<Bound, String> {
    if s == "off" {
        return Ok(Bound(None));
    }
    s.parse::<f32>()
        .map(|e| Bound(Some(e)))
        .map_err(|_| format!("expected a number (0.01 is 1%) or off, not {s:?}"))
}

/// What `lgh gi` and `lgh bench gi` share: the scene, its lights and VPLs, the shading.
#[derive(Debug, clap::Args)]
pub struct SceneArgs {
    /// The scene (OBJ, with its MTL files beside it; emissive `Ke` faces are area lights;
    /// `map_Kd` textures multiply `Kd`). What the files ask for and is not rendered is named
    /// on stderr (with `--quiet`, only in the EXR header's `unhonoured`).
    #[arg(long)]
    pub obj: PathBuf,
    /// What a missing texture file does: `error` (naming it) or `grey` (its material's
    /// colour is grey, 0.5, and a warning names it).
    #[arg(long, value_enum, default_value_t = MissingTextures::Error)]
    pub missing_textures: MissingTextures,
    /// Which normals shade a face: `vertex`, the OBJ's `vn` interpolated (the face's normal
    /// where a face names none), or `face`, every face its own normal, for meshes whose
    /// vertex normals are poor (Sponza's: a tenth of its corners lean over 68° from their
    /// face). Shadow rays and the VPLs' hemisphere always use the face's.
    #[arg(long, value_enum, default_value_t = Normals::Vertex)]
    pub normals: Normals,
    /// A primary light, repeatable: `point:X,Y,Z,R,G,B`, `spot:X,Y,Z,DX,DY,DZ,ANGLE,R,G,B` or
    /// `sun:DX,DY,DZ,R,G,B` (intensities in W/sr, the sun's irradiance in W/m²).
    #[arg(long = "light")]
    pub lights: Vec<String>,
    /// VPLs to trace (at least; whole light paths are kept).
    #[arg(long, default_value_t = 100_000)]
    pub vpls: usize,
    /// Surfaces a light path may meet, each one depositing a VPL.
    #[arg(long, default_value_t = 3)]
    pub bounces: u32,
    /// Seed of the light paths.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Shadow samples k of a coarse light (on average with `--sample-allocation adaptive` or
    /// `intensity`). Default: 9 with `--coarse-shadows gaussian` (the paper's Fig. 11d; 0
    /// shades a coarse light as a point, Fig. 11c; at most 1024); with `representatives` (1 to
    /// 64; 0.25 to 64 for `adaptive`), 0.35 for `adaptive` (each draw resampled among
    /// `--candidates`; lights that face away from a point left out), 2 for `intensity` and
    /// `uniform`.
    #[arg(long)]
    pub shadow_samples: Option<f32>,
    /// How a coarse light's k shadow samples are placed: `representatives` (k of the VPLs it
    /// stands for, beyond the paper; `docs/gi.md` says why it is the default) or `gaussian` (the paper's, points drawn with the light's variance σ²).
    #[arg(long, value_enum, default_value_t = CoarseShadows::Representatives)]
    pub coarse_shadows: CoarseShadows,
    /// How `--coarse-shadows representatives` shares the samples among coarse lights:
    /// `adaptive`, per shading point in proportion to what each light brings there
    /// unshadowed (`--shadow-samples` per coarse light on average; below one, Russian roulette
    /// seeded by the point); `intensity`, per light in proportion to its luminance over its
    /// level's mean; or `uniform`, `--shadow-samples` each.
    /// Default: `adaptive` with `--aggregation isotropic`, `intensity` with `buckets`; refused
    /// with `--coarse-shadows gaussian`, to which it does not apply.
    #[arg(long, value_enum)]
    pub sample_allocation: Option<SampleAllocation>,
    /// The most representatives one coarse light gets, 1 to 64 (`adaptive`: rounded down to a
    /// power of two; default 32; `intensity`: default 16; refused where it does not apply,
    /// with `uniform` and `--coarse-shadows gaussian`).
    #[arg(long)]
    pub max_shadow_samples: Option<u32>,
    /// No shadow rays: every VPL reaches every point it faces.
    #[arg(long)]
    pub no_shadows: bool,
    /// How the hierarchy aggregates the VPLs: `isotropic`, the paper's one hierarchy of
    /// isotropic points, or `buckets`, one hierarchy per dominant normal axis whose coarse
    /// lights keep their mean normal's lobe (beyond the paper: better on the Cornell box,
    /// slower on Sponza; `docs/gi.md`; with `--sample-allocation intensity` or `uniform`, or
    /// `--coarse-shadows gaussian`).
    #[arg(long, value_enum, default_value_t = Aggregation::Isotropic)]
    pub aggregation: Aggregation,
    /// Lightcuts' relative error ε (Walter et al.'s 2%), for `--backend lightcuts` and
    /// `lgh bench gi --lightcuts`.
    #[arg(long, default_value_t = 0.02)]
    pub lightcuts_error: f32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    pub width: usize,
    /// Image height in pixels.
    #[arg(long, default_value_t = 360)]
    pub height: usize,
    /// Camera `EX,EY,EZ,TX,TY,TZ[,FOV]` (default: straight along −z at the scene's box, y up, its
    /// front face filling a 40° vertical field of view).
    #[arg(long, allow_hyphen_values = true)]
    pub camera: Option<String>,
    /// The most mirrors and glass surfaces (MTL `illum` 3–9) a camera or light path follows
    /// by reflection and refraction, 0 to 32; a path's branch carrying under 1/1000 of its
    /// pixel is not followed.
    #[arg(long, default_value_t = lgh_vpl::specular::DEFAULT_SPECULAR_DEPTH)]
    pub specular_depth: u32,
    /// Backend lgh, with the default coarse shading (`--coarse-shadows representatives`,
    /// `--sample-allocation adaptive`): at a Phong point whose lobe is too sharp for α, shade
    /// the glossy term from
    /// the VPLs inside the lobe's cone one by one, the cone chosen so that the glossy light
    /// left out is at most this fraction of the point's diffuse light (default 0.01); `off`:
    /// the hierarchy alone everywhere. Refused with another coarse shading.
    #[arg(long, value_parser = parse_bound)]
    pub lobe_error: Option<Bound>,
    /// Backend lgh, with the default coarse shading: the bound on each shading point's error
    /// (0.1 is 10% of its light). Where a point's error, estimated from its own samples
    /// (1.645 standard errors), may exceed it, its coarse lights are shaded again with twice
    /// the representatives, up to six times; `off`: the mean number everywhere (default 0.1;
    /// refused with another coarse shading). `lgh bench gi` counts the pixels over it
    /// (`points_over_bound`; over 0.1 with another shading).
    #[arg(long, value_parser = parse_bound)]
    pub point_error: Option<Bound>,
    /// Backend lgh, with the default coarse shading: where a coarse light's blending weight
    /// B_ℓ is taken. `representative`: at each representative's own distance, with every
    /// coarse light that may reach the point, so the hierarchy's estimate is unbiased against
    /// brute force over the same VPLs; `centre`: at the light's centre, as in the paper's
    /// eq. (3), whose smoothing stays in the image.
    /// Default `representative`; refused with another coarse shading.
    #[arg(long, value_enum)]
    pub blend_at: Option<BlendAt>,
    /// Backend lgh, with the default coarse shading: the representatives each shadow ray of a
    /// coarse light chooses among: 1, 2, 4, 8 or 16. Each is weighed by what it gives the point
    /// unshadowed, and the ray goes to one picked in proportion (resampled importance
    /// sampling): unbiased, with less of the noise of which VPL was drawn. 1 draws each
    /// representative on its own. Default 4; refused with another coarse shading.
    #[arg(long)]
    pub candidates: Option<u32>,
    /// Don't show progress.
    #[arg(long)]
    pub quiet: bool,
}

/// Arguments of `lgh gi`.
#[derive(Debug, clap::Args)]
pub struct GiArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The paper's α (backend lgh).
    #[arg(long, default_value_t = 4.0)]
    pub alpha: f32,
    /// Many-lights method.
    #[arg(long, value_enum, default_value_t = GiBackend::Lgh)]
    pub backend: GiBackend,
    /// Only the VPLs' indirect light (what `lgh bench gi` compares): no direct light from the
    /// primary lights, no emitters seen.
    #[arg(long)]
    pub no_direct: bool,
    /// Strata per side of an area light's direct-light pattern: N² shadow rays per emissive
    /// triangle and shading point, a pattern fixed per surface point (no flicker).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub area_strata: u32,
    /// Output image (linear OpenEXR); a tone-mapped PNG is written beside it.
    #[arg(long, required = true)]
    pub out: Option<PathBuf>,
}

/// Arguments of `lgh bench gi`.
#[derive(Debug, clap::Args)]
pub struct BenchGiArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The α values to run, comma-separated (the paper's Fig. 13: 1, 4, 16).
    #[arg(long, default_value = "1,4,16")]
    pub alphas: String,
    /// Shading points (about): the image is rendered at the resolution of that many pixels,
    /// framed as `--width × --height`, by brute force and by the hierarchy alike.
    #[arg(long, default_value_t = 4096)]
    pub pixels: usize,
    /// Also run Lightcuts (at `--lightcuts-error`) on the same pixels: the JSON's `lightcuts`.
    #[arg(long)]
    pub lightcuts: bool,
    /// Folder for the images and their difference images (`gi-brute.exr`, `gi-alpha-A.exr`,
    /// `gi-alpha-A-diff.png`); none written without it.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

impl SceneArgs {
    /// The library's settings for these flags, with `direct`, and Lightcuts at
    /// `--lightcuts-error`: both checked (every flag is, whatever the method run).
    fn settings(&self, direct: DirectLight) -> Result<(GiSettings, GiMethod), crate::Error> {
        let settings = GiSettings {
            vpls: VplSettings {
                count: self.vpls,
                max_bounces: self.bounces,
                seed: self.seed,
            },
            coarse: self.coarse()?,
            shadows: !self.no_shadows,
            direct,
            specular_depth: self.specular_depth,
        };
        settings.check().map_err(flag_error)?;
        let lightcuts = GiMethod::Lightcuts {
            relative_error: self.lightcuts_error,
        };
        lightcuts.check().map_err(flag_error)?;
        Ok((settings, lightcuts))
    }

    /// The coarse shading the flags ask for: `--coarse-shadows`, `--sample-allocation` (its
    /// default `adaptive` with the one hierarchy, `intensity` with the buckets) and
    /// `--aggregation` choose it, and each of the other flags must apply to it (a flag that
    /// does not is refused, naming the flags it needs); what is not given takes the library's
    /// default for that shading.
    fn coarse(&self) -> Result<CoarseShading, crate::Error> {
        let allocation = match (self.coarse_shadows, self.sample_allocation) {
            (CoarseShadows::Gaussian, Some(a)) => {
                return Err(crate::usage(format!(
                    "--sample-allocation {}: applies to --coarse-shadows representatives, not \
                     gaussian",
                    a.name()
                )))
            }
            (CoarseShadows::Gaussian, None) => None,
            (CoarseShadows::Representatives, Some(a)) => Some(a),
            (CoarseShadows::Representatives, None) => Some(match self.aggregation {
                Aggregation::Isotropic => SampleAllocation::Adaptive,
                Aggregation::Buckets => SampleAllocation::Intensity,
            }),
        };
        // What the shading is, in flags, for the refusals.
        let shading = match (allocation, self.sample_allocation) {
            (None, _) => "--coarse-shadows gaussian".to_string(),
            (Some(a), Some(_)) => format!("--sample-allocation {}", a.name()),
            (Some(a), None) => format!(
                "--sample-allocation {} (the default with --aggregation {})",
                a.name(),
                lgh_vpl::gi::Aggregation::from(self.aggregation).name()
            ),
        };
        if allocation != Some(SampleAllocation::Adaptive) {
            let adaptive_only = [
                ("--lobe-error", self.lobe_error.is_some()),
                ("--point-error", self.point_error.is_some()),
                ("--blend-at", self.blend_at.is_some()),
                ("--candidates", self.candidates.is_some()),
            ];
            if let Some((flag, _)) = adaptive_only.iter().find(|(_, given)| *given) {
                return Err(crate::usage(format!(
                    "{flag} applies only to the default coarse shading (--coarse-shadows \
                     representatives --sample-allocation adaptive), not with {shading}"
                )));
            }
        }
        if let (Some(max), None | Some(SampleAllocation::Uniform)) =
            (self.max_shadow_samples, allocation)
        {
            return Err(crate::usage(format!(
                "--max-shadow-samples {max}: applies to --sample-allocation adaptive or \
                 intensity, not with {shading}"
            )));
        }
        let aggregation = self.aggregation.into();
        let k = self.shadow_samples;
        Ok(match allocation {
            None => CoarseShading::Gaussian {
                samples: k.map_or(Ok(gi::DEFAULT_GAUSSIAN_SAMPLES), |k| {
                    whole(k, SampleSetting::Gaussian)
                })?,
                aggregation,
            },
            Some(SampleAllocation::Uniform) => CoarseShading::Representatives {
                per_light: PerLight::Uniform {
                    samples: k.map_or(Ok(gi::DEFAULT_REPRESENTATIVES), |k| {
                        whole(k, SampleSetting::Uniform)
                    })?,
                },
                aggregation,
            },
            Some(SampleAllocation::Intensity) => CoarseShading::Representatives {
                per_light: PerLight::ByIntensity {
                    mean: k.unwrap_or(gi::DEFAULT_REPRESENTATIVES as f32),
                    max: self
                        .max_shadow_samples
                        .unwrap_or(gi::DEFAULT_MAX_BY_INTENSITY),
                },
                aggregation,
            },
            Some(SampleAllocation::Adaptive) => {
                if self.aggregation == Aggregation::Buckets {
                    return Err(crate::usage(
                        "--sample-allocation adaptive needs --aggregation isotropic (the \
                         buckets take intensity or uniform)",
                    ));
                }
                let d = AdaptiveShading::default();
                CoarseShading::Adaptive(AdaptiveShading {
                    mean_samples: k.unwrap_or(d.mean_samples),
                    max_samples: self.max_shadow_samples.unwrap_or(d.max_samples),
                    lobe_error: self.lobe_error.map_or(d.lobe_error, |b| b.0),
                    point_error: self.point_error.map_or(d.point_error, |b| b.0),
                    blend: self.blend_at.map_or(d.blend, Into::into),
                    candidates: self.candidates.unwrap_or(d.candidates),
                })
            }
        })
    }

    /// `--light` and `--camera` parsed for a `width × height` image (checked before any work).
    fn lights_and_camera(
        &self,
        (width, height): (usize, usize),
    ) -> Result<(Vec<PrimaryLight>, Option<Camera>), crate::Error> {
        lgh_image::check_image_size(width, height)?;
        let given: Vec<PrimaryLight> = self
            .lights
            .iter()
            .map(|s| {
                s.parse()
                    .map_err(|e: LightParseError| format!("--light {}: {}", e.light(), e.reason()))
            })
            .collect::<Result<_, _>>()?;
        let camera = match &self.camera {
            Some(s) => Some(crate::explosion::parse_camera(s, Vec3::Y, width, height)?),
            None => None,
        };
        Ok((given, camera))
    }

    /// Checks the image size, the lights and the camera, then reads the scene, traces its VPLs
    /// and builds what `methods` need, for a `width × height` image from `--camera` or the
    /// front view.
    fn prepare(
        &self,
        settings: &GiSettings,
        (width, height): (usize, usize),
        methods: &[GiMethod],
    ) -> Result<(GiScene, Camera), crate::Error> {
        let (given, camera) = self.lights_and_camera((width, height))?;
        let options = lgh_vpl::ObjOptions {
            missing_textures: self.missing_textures.into(),
            normals: self.normals.into(),
        };
        let mesh = Mesh::load_obj_with(&self.obj, &options, |_, _| {})?;
        if !self.quiet {
            output::print_unhonoured("lgh gi", &mesh);
        }
        let camera = match camera {
            Some(c) => c,
            None => gi::front_view(mesh.bounds(), width, height)?,
        };
        let scene = GiScene::prepare(mesh, given, settings).map_err(flag_error)?;
        let mesh = scene.scene().mesh();
        let triangles = mesh.triangles().len();
        let defaulted = (0..triangles as u32)
            .filter(|&t| mesh.material(t) == lgh_vpl::DEFAULT_MATERIAL)
            .count();
        if defaulted > 0 {
            eprintln!(
                "lgh gi: {defaulted} of {triangles} triangles have no material (no MTL, or one \
                 that does not define theirs): they are Lambertian with albedo 0.5"
            );
        }
        for &method in methods {
            scene.build_for(method).map_err(flag_error)?;
        }
        Ok((scene, camera))
    }

    /// Header attributes common to every image of `scene`.
    fn header(&self, scene: &GiScene) -> Vec<(&'static str, String)> {
        let s = scene.settings();
        let c = Described::of(&s.coarse);
        vec![
            ("obj", self.obj.display().to_string()),
            ("vpls", scene.vpls().len().to_string()),
            ("light_paths", scene.light_paths().to_string()),
            ("bounces", self.bounces.to_string()),
            ("seed", self.seed.to_string()),
            ("shadow_samples", c.shadow_samples.to_string()),
            ("max_shadow_samples", or_none(c.max_shadow_samples)),
            ("sample_allocation", or_none(c.sample_allocation)),
            ("coarse_shadows", s.coarse.name().to_string()),
            ("shadows", s.shadows.to_string()),
            ("h0", scene.h0().to_string()),
            ("specular_depth", s.specular_depth.to_string()),
            ("lobe_error", bound(c.lobe_error)),
            ("point_error", bound(c.point_error)),
            ("blend_at", or_none(c.blend_at)),
            ("candidates", or_none(c.candidates)),
            ("normals", self.normals.name().to_string()),
            ("unhonoured", unhonoured(scene.scene().mesh())),
        ]
    }
}

/// `k` of `--shadow-samples` as the whole number `setting` takes (its range is the library's
/// to check, [`CoarseShading::check`]), or the refusal naming the flag.
fn whole(k: f32, setting: SampleSetting) -> Result<u32, crate::Error> {
    if k.is_finite() && k.fract() == 0.0 && (0.0..=u32::MAX as f32).contains(&k) {
        Ok(k as u32)
    } else {
        let (flag, with) = flag_of(GiSetting::Samples(setting));
        Err(format!("{flag} {k}: expected a whole number{with}").into())
    }
}

/// The flag that sets `setting`, and the flags that choose the shading it belongs to (for a
/// number of samples: ` with --coarse-shadows gaussian`, …; else empty).
fn flag_of(setting: GiSetting) -> (&'static str, &'static str) {
    match setting {
        GiSetting::Samples(s) => {
            let flag = if s.is_max() {
                "--max-shadow-samples"
            } else {
                "--shadow-samples"
            };
            let with = match s {
                SampleSetting::Gaussian => " with --coarse-shadows gaussian",
                SampleSetting::Uniform => " with --sample-allocation uniform",
                SampleSetting::IntensityMean | SampleSetting::IntensityMax => {
                    " with --sample-allocation intensity"
                }
                SampleSetting::AdaptiveMean | SampleSetting::AdaptiveMax => {
                    " with --sample-allocation adaptive"
                }
            };
            (flag, with)
        }
        GiSetting::AreaStrata => ("--area-strata", ""),
        GiSetting::LobeError => ("--lobe-error", ""),
        GiSetting::PointError => ("--point-error", ""),
        GiSetting::Candidates => ("--candidates", ""),
        GiSetting::SpecularDepth => ("--specular-depth", ""),
        GiSetting::RelativeError => ("--lightcuts-error", ""),
    }
}

/// A library error of `lgh gi`, worded with the flags: lgh-vpl names its own settings
/// (`AdaptiveShading::candidates 3: expected …`), the command line the flag that set them
/// (`--candidates 3: expected …`), with the library's own words for what it takes
/// ([`GiError::refusal`]). Errors that name no setting pass through as they are.
fn flag_error(e: GiError) -> crate::Error {
    if let Some(r) = e.refusal() {
        let (flag, with) = flag_of(r.setting);
        let or_off = if r.setting.optional() { " or off" } else { "" };
        return format!("{flag} {}: {}{or_off}{with}", r.value, r.expected).into();
    }
    match e {
        GiError::Vpl(VplError::NoLights) => {
            "the scene has no emissive face (MTL Ke) and no --light was given".into()
        }
        e => Box::new(e),
    }
}

/// A coarse shading's settings for the EXR header and the JSON, as `lgh gi`'s flags name
/// them: `None` where a setting does not apply to it.
struct Described {
    shadow_samples: f32,
    max_shadow_samples: Option<u32>,
    sample_allocation: Option<&'static str>,
    /// `None` where the shading has no such bound, `Some(None)` where it is off.
    lobe_error: Option<Option<f32>>,
    /// As `lobe_error`.
    point_error: Option<Option<f32>>,
    blend_at: Option<&'static str>,
    candidates: Option<u32>,
}

impl Described {
    fn of(coarse: &CoarseShading) -> Described {
        let none = Described {
            shadow_samples: 0.0,
            max_shadow_samples: None,
            sample_allocation: None,
            lobe_error: None,
            point_error: None,
            blend_at: None,
            candidates: None,
        };
        match *coarse {
            CoarseShading::Gaussian { samples, .. } => Described {
                shadow_samples: samples as f32,
                ..none
            },
            CoarseShading::Representatives { per_light, .. } => {
                let (shadow_samples, max_shadow_samples) = match per_light {
                    PerLight::Uniform { samples } => (samples as f32, None),
                    PerLight::ByIntensity { mean, max } => (mean, Some(max)),
                };
                Described {
                    shadow_samples,
                    max_shadow_samples,
                    sample_allocation: Some(per_light.name()),
                    ..none
                }
            }
            CoarseShading::Adaptive(a) => Described {
                shadow_samples: a.mean_samples,
                max_shadow_samples: Some(a.max_samples),
                sample_allocation: Some("adaptive"),
                lobe_error: Some(a.lobe_error),
                point_error: Some(a.point_error),
                blend_at: Some(a.blend.name()),
                candidates: Some(a.candidates),
            },
        }
    }
}

/// A bound's header value: `none` where the shading has no such bound, `off` where it is
/// turned off.
fn bound(value: Option<Option<f32>>) -> String {
    match value {
        None => "none".into(),
        Some(None) => "off".into(),
        Some(Some(e)) => e.to_string(),
    }
}

/// A header value: `none` for a setting that does not apply.
fn or_none(value: Option<impl ToString>) -> String {
    value.map_or("none".into(), |v| v.to_string())
}

/// The statements `mesh`'s files ask for and the renderer does not honour, for a header: one
/// per line, `none` if there are none.
fn unhonoured(mesh: &Mesh) -> String {
    let lines: Vec<String> = mesh.unhonoured().iter().map(|u| u.to_string()).collect();
    if lines.is_empty() {
        "none".into()
    } else {
        lines.join("\n")
    }
}

/// Runs `lgh gi`.
pub fn run(args: &GiArgs) -> Result<(), crate::Error> {
    let out = args.out.as_deref().ok_or("--out is required")?;
    output::check_out(out)?;
    let (settings, method) = args.checked()?;
    let s = &args.scene;
    let Rendered {
        scene,
        camera,
        r,
        prepare_s,
    } = args.render(&settings, method, &Bars::new(s.quiet))?;
    let mut header = s.header(&scene);
    header.push(("render_seconds", format!("{:.3}", r.seconds)));
    header.push(("direct", (!args.no_direct).to_string()));
    if let Some(d) = r.direct {
        header.push(("area_strata", args.area_strata.to_string()));
        header.push(("direct_seconds", format!("{:.3}", d.seconds)));
    }
    if let GiMethod::Lgh { alpha } = method {
        header.push(("alpha", alpha.to_string()));
        let aggregation = settings.coarse.aggregation().name();
        header.push(("aggregation", aggregation.to_string()));
    }
    let attrs = output::header_attributes(method.name(), &header);
    let png = output::write_exr_png(out, &r.rendered.image, &attrs, None)?;
    if let Some(hint) = dark_hint(
        scene.scene(),
        &camera,
        &r.rendered.image,
        s.camera.is_none(),
    ) {
        eprintln!("lgh gi: warning: {hint}");
    }
    say!(
        "lgh gi: {} triangles, {} primary lights ({} emissive faces), {} VPLs from {} paths, traced and built in {prepare_s:.2} s; indirect by {} {:.1} s, {:.1} lights and {:.1} shadow rays per point; {} -> {}, {}",
        scene.scene().mesh().triangles().len(),
        scene.primary_lights().len(),
        scene.emissive_lights(),
        scene.vpls().len(),
        scene.light_paths(),
        method.name(),
        r.seconds,
        r.rendered.mean_lights(),
        r.shadow_rays_per_point(),
        match r.direct {
            None => "no direct light".to_string(),
            Some(d) => format!(
                "direct light {:.1} s, at most {} shadow rays per point",
                d.seconds, d.max_rays_per_point
            ),
        },
        out.display(),
        png.display()
    );
    Ok(())
}

/// A render of `lgh gi`: the scene prepared, its camera, the render and the preparation's
/// seconds.
struct Rendered {
    scene: GiScene,
    camera: Camera,
    r: lgh_vpl::gi::GiRender,
    prepare_s: f64,
}

impl GiArgs {
    /// The flags checked before any work: the settings and the method.
    fn checked(&self) -> Result<(GiSettings, GiMethod), crate::Error> {
        crate::check_alpha(self.alpha)?;
        let s = &self.scene;
        let direct = if self.no_direct {
            DirectLight::Off
        } else {
            DirectLight::Stratified {
                area_strata: self.area_strata,
            }
        };
        let (settings, lightcuts) = s.settings(direct)?;
        let method = match self.backend {
            GiBackend::Lgh => GiMethod::Lgh { alpha: self.alpha },
            GiBackend::Brute => GiMethod::Brute,
            GiBackend::Lightcuts => lightcuts,
        };
        Ok((settings, method))
    }

    /// Prepares the scene (lights, VPLs, the hierarchy) and renders it with `method`.
    fn render(
        &self,
        settings: &GiSettings,
        method: GiMethod,
        progress: &dyn lgh_vpl::gi::GiProgress,
    ) -> Result<Rendered, crate::Error> {
        let s = &self.scene;
        let t = Instant::now();
        let (scene, camera) = s.prepare(settings, (s.width, s.height), &[method])?;
        let prepare_s = t.elapsed().as_secs_f64();
        let r = scene
            .render(method, &camera, &Forward(progress))
            .map_err(flag_error)?;
        Ok(Rendered {
            scene,
            camera,
            r,
            prepare_s,
        })
    }
}

/// Progress given as a trait object, to the library's `&impl GiProgress`.
struct Forward<'a>(&'a dyn lgh_vpl::gi::GiProgress);

impl lgh_vpl::gi::GiProgress for Forward<'_> {
    fn begin(&self, phase: lgh_vpl::gi::GiPhase, rows: u64) {
        self.0.begin(phase, rows);
    }
    fn advance(&self, rows: u64) {
        self.0.advance(rows);
    }
    fn end(&self, phase: lgh_vpl::gi::GiPhase) {
        self.0.end(phase);
    }
}

/// The flags of files, which a render into memory has none of.
const FILE_FLAGS: [&str; 1] = ["out"];

/// `lgh gi` with the command line `args` (after `lgh gi`, without `--out`) rendered into
/// memory: the image the command writes to its EXR, bit for bit, with the same settings,
/// defaults and checks; nothing printed but the progress bars (none with `--quiet`, or with
/// `progress` given, which hears them instead) and warnings. Flags, settings and a missing
/// `--obj` are refused before any work ([`InMemoryError::Refused`]).
pub fn render_in_memory_with<I, T>(
    args: I,
    progress: Option<&dyn lgh_vpl::gi::GiProgress>,
) -> Result<lgh_image::Image, InMemoryError>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let refused = InMemoryError::Refused;
    let (args, _) =
        crate::memory::parse::<GiArgs, _, _>("lgh gi", args, &FILE_FLAGS).map_err(refused)?;
    let (settings, method) = args.checked().map_err(refused)?;
    let s = &args.scene;
    crate::files::check_file(&s.obj)
        .map_err(|e| crate::files::MissingFile(format!("--obj {e}")))
        .map_err(|e| refused(e.into()))?;
    s.lights_and_camera((s.width, s.height)).map_err(refused)?;
    let bars = Bars::new(s.quiet);
    let progress = progress.unwrap_or(&bars);
    let rendered = args
        .render(&settings, method, progress)
        .map_err(InMemoryError::Failed)?;
    if let Some(hint) = dark_hint(
        rendered.scene.scene(),
        &rendered.camera,
        &rendered.r.rendered.image,
        s.camera.is_none(),
    ) {
        eprintln!("lgh gi: warning: {hint}");
    }
    Ok(rendered.r.rendered.image)
}

/// Every setting a render into memory of `lgh gi` takes ([`render_in_memory_with`]): its flags
/// but `--obj` and `--out`, in the command's order.
#[must_use]
pub fn settings() -> Vec<Setting> {
    crate::memory::settings::<GiArgs>("obj", &FILE_FLAGS)
}

/// The most pixels with any light that an image may have and be called black: 1%.
const DARK_SHARE: f64 = 0.01;

/// Why `image`, rendered from `camera` in `scene`, is black — at most [`DARK_SHARE`] of its
/// pixels hold any light — and the flags that place the camera; `None` if it is not.
/// `default_camera`: the camera is the front view ([`gi::front_view`], no `--camera`), which
/// stands outside the scene's box, so in a closed room it sees the outside of a wall (the
/// first image of a scanned conference room was black, and said nothing).
fn dark_hint(
    scene: &lgh_vpl::Scene,
    camera: &Camera,
    image: &Image,
    default_camera: bool,
) -> Option<String> {
    let lit = image
        .pixels
        .iter()
        .filter(|p| p.max_element() > 0.0)
        .count();
    if lit as f64 > DARK_SHARE * image.pixels.len() as f64 {
        return None;
    }
    let (width, height) = (camera.width(), camera.height());
    let hits = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (origin, dir) = camera.ray(x, y);
            scene.intersect(&lgh_vpl::Ray::new(origin, dir)).is_some()
        })
        .count();
    let seen = if hits == 0 {
        "the camera's rays hit nothing".to_string()
    } else {
        let share = 100.0 * hits as f64 / (width * height).max(1) as f64;
        format!("{share:.0}% of the camera's rays hit a surface, and no light reaches it there")
    };
    let place = if default_camera {
        "the default camera looks along -z at the scene's box from outside it, so in a closed \
         room it sees the outside of a wall: place it inside with --camera \
         EX,EY,EZ,TX,TY,TZ[,FOV]"
    } else {
        "check where --camera EX,EY,EZ,TX,TY,TZ[,FOV] stands and looks"
    };
    Some(format!("the image is black: {seen}; {place}"))
}

impl BenchGiArgs {
    /// `--alphas`, each checked.
    fn alphas(&self) -> Result<Vec<f32>, crate::Error> {
        let alphas: Vec<f32> = self
            .alphas
            .split(',')
            .map(|a| a.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("--alphas {}: expected numbers like 1,4,16", self.alphas))?;
        for &a in &alphas {
            crate::check_alpha(a)?;
        }
        Ok(alphas)
    }

    /// The framing of `--width × --height` at about `--pixels` pixels.
    fn framing(&self) -> (usize, usize) {
        let aspect = self.scene.width as f64 / self.scene.height as f64;
        let height = ((self.pixels as f64 / aspect).sqrt().round() as usize).max(1);
        let width = ((height as f64 * aspect).round() as usize).max(1);
        (width, height)
    }
}

/// Writes `gi-NAME.exr` (and its PNG) into `dir` with `header`, and, beside a run against
/// brute force's `exact` image, its difference image `gi-NAME-diff.png`.
fn write_bench_image(
    dir: &Path,
    name: &str,
    header: &[(&'static str, String)],
    image: &Image,
    exact: Option<&Image>,
) -> Result<(), crate::Error> {
    let attrs = output::header_attributes(name, header);
    output::write_exr_png(&dir.join(format!("gi-{name}.exr")), image, &attrs, None)?;
    if let Some(exact) = exact {
        let diff = dir.join(format!("gi-{name}-diff.png"));
        let max = lgh_image::compare(image, exact).map_or(0.0, |e| e.max_abs);
        lgh_image::difference_png(&diff, image, exact, max as f32)?;
    }
    Ok(())
}

/// Runs `lgh bench gi`: brute force over every VPL and the hierarchy at each α on the same
/// pixels, in the same run; JSON on stdout.
pub fn bench(args: &BenchGiArgs) -> Result<(), crate::Error> {
    let alphas = args.alphas()?;
    if let Some(dir) = &args.out {
        if !dir.is_dir() {
            return Err(format!("--out {}: not a folder", dir.display()).into());
        }
    }
    let (settings, lightcuts) = args.scene.settings(DirectLight::Off)?;
    let mut methods: Vec<GiMethod> = alphas
        .iter()
        .map(|&alpha| GiMethod::Lgh { alpha })
        .collect();
    if args.lightcuts {
        methods.push(lightcuts);
    }
    let bench = Bench::new(args, &settings, &methods)?;
    let mut runs = Vec::new();
    for &alpha in &alphas {
        let extra = ("alpha", alpha.to_string());
        let mut r = bench.against(GiMethod::Lgh { alpha }, format!("alpha-{alpha}"), extra)?;
        r["alpha"] = json!(alpha);
        runs.push(r);
    }
    let lightcuts = if args.lightcuts {
        let error = args.scene.lightcuts_error;
        let extra = ("lightcuts_error", error.to_string());
        let mut r = bench.against(lightcuts, "lightcuts".into(), extra)?;
        r["relative_error"] = json!(error);
        Some(r)
    } else {
        None
    };
    say!("{}", bench.summary(runs, lightcuts));
    Ok(())
}

/// One `lgh bench gi`: the scene prepared for its methods, the camera, and brute force's
/// render on its pixels, against which each method runs.
struct Bench<'a> {
    args: &'a BenchGiArgs,
    scene: GiScene,
    camera: Camera,
    bars: Bars,
    exact: gi::GiRender,
    /// The per-pixel bound the pixels over it are counted against: the renderer's, or the
    /// default one where it has none.
    counted_against: f64,
    /// The framing of `--pixels`.
    size: (usize, usize),
}

impl<'a> Bench<'a> {
    /// Prepares the scene with `settings` for `methods` at the framing of `--pixels`, and
    /// renders brute force (its image written with `--out`).
    fn new(
        args: &'a BenchGiArgs,
        settings: &GiSettings,
        methods: &[GiMethod],
    ) -> Result<Self, crate::Error> {
        let s = &args.scene;
        let size = args.framing();
        let (scene, camera) = s.prepare(settings, size, methods)?;
        let bars = Bars::new(s.quiet);
        let point_error = Described::of(&settings.coarse).point_error;
        let counted_against = f64::from(point_error.flatten().unwrap_or(DEFAULT_POINT_ERROR));
        let exact = scene
            .render(GiMethod::Brute, &camera, &bars)
            .map_err(flag_error)?;
        if let Some(dir) = &args.out {
            write_bench_image(dir, "brute", &s.header(&scene), &exact.rendered.image, None)?;
        }
        Ok(Bench {
            args,
            scene,
            camera,
            bars,
            exact,
            counted_against,
            size,
        })
    }

    /// `method`'s run against brute force: its JSON, and with `--out` its image `gi-NAME.exr`
    /// (with `extra` in its header) and difference image.
    fn against(
        &self,
        method: GiMethod,
        name: String,
        extra: (&'static str, String),
    ) -> Result<serde_json::Value, crate::Error> {
        let (scene, exact) = (&self.scene, &self.exact);
        let r = scene
            .render(method, &self.camera, &self.bars)
            .map_err(flag_error)?;
        let (image, truth) = (&r.rendered.image, &exact.rendered.image);
        let rel = lgh_image::compare(image, truth).map_or(f64::NAN, |e| e.rel_rmse);
        let points = lgh_image::point_errors(image, truth, self.counted_against).unwrap_or(
            lgh_image::PointErrors {
                max: f64::NAN,
                p99: f64::NAN,
                over: f64::NAN,
            },
        );
        if let Some(dir) = &self.args.out {
            let mut header = self.args.scene.header(scene);
            header.push(extra);
            write_bench_image(dir, &name, &header, image, Some(truth))?;
        }
        Ok(json!({
            "lights_per_point": r.rendered.mean_lights(),
            "shadow_rays_per_pixel": r.shadow_rays_per_point(),
            "seconds": r.seconds,
            "brute_seconds": exact.seconds,
            "rel_rmse": if rel.is_finite() { Some(rel) } else { None },
            "specular_depth": scene.settings().specular_depth,
            "bounded_points": r.bounded_points,
            "lobe_split_points": r.lobe_split_points,
            "refined_points": r.refined_points,
            "max_point_error": points.max,
            "point_error_p99": points.p99,
            "points_over_bound": points.over,
        }))
    }

    /// The bench's JSON: the settings (null where one does not apply to the coarse shading),
    /// the pixels, and the `runs` and `lightcuts` run against brute force.
    fn summary(
        &self,
        runs: Vec<serde_json::Value>,
        lightcuts: Option<serde_json::Value>,
    ) -> serde_json::Value {
        let (s, settings) = (&self.args.scene, self.scene.settings());
        let c = Described::of(&settings.coarse);
        let (width, height) = self.size;
        json!({
            "scene": s.obj.display().to_string(),
            "vpls": self.scene.vpls().len(),
            "normals": s.normals.name(),
            "aggregation": settings.coarse.aggregation().name(),
            "coarse_shadows": settings.coarse.name(),
            "shadow_samples": c.shadow_samples,
            "max_shadow_samples": c.max_shadow_samples,
            "sample_allocation": c.sample_allocation,
            "component": "indirect",
            "point_error": c.point_error,
            "blend_at": c.blend_at,
            "candidates": c.candidates,
            "points_counted_against": self.counted_against,
            "lobe_error": c.lobe_error,
            "pixels": self.exact.rendered.pixels_shaded,
            "width": width,
            "height": height,
            "brute_shadow_rays_per_pixel": self.exact.shadow_rays_per_point(),
            "runs": runs,
            "lightcuts": lightcuts,
        })
    }
}
