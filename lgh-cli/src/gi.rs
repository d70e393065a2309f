//! `lgh gi` and `lgh bench gi`: indirect illumination of an OBJ scene from virtual point lights
//! (paper Sec. 6.4, Fig. 13), shaded through the hierarchy or brute force with shadow rays.

use std::path::PathBuf;
use std::time::Instant;

use lgh_core::glam::Vec3;
use lgh_core::lightcuts::{LightTree, LightcutsBackend, LightcutsSettings, Representative};
use lgh_core::{BruteForce, GridSettings, LghBackend, LightingGridHierarchy, PointLight};
use lgh_volume::render::{Camera, Framing};
use lgh_vpl::direct::{render_direct, Direct, DirectSettings};
use lgh_vpl::indirect::{
    point_lights, render_buckets, render_input_lights, render_lgh, Coarse, Indirect,
    IndirectSettings, NormalBuckets,
};
use lgh_vpl::primary::{area_lights, PrimaryLight};
use lgh_vpl::representatives::{Allocation, Representatives, MAX_PER_LIGHT};
use lgh_vpl::vpl::{trace, VplSettings, Vpls};
use lgh_vpl::{Mesh, Rendered, Scene};
use serde_json::json;

use crate::{output, progress};

/// `--aggregation`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Aggregation {
    /// One hierarchy per dominant normal axis, coarse lights with their bucket's lobe.
    Buckets,
    /// The paper's: one hierarchy, VPLs aggregated as isotropic points.
    Isotropic,
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

impl GiBackend {
    fn name(self) -> &'static str {
        match self {
            GiBackend::Lgh => "lgh",
            GiBackend::Brute => "brute",
            GiBackend::Lightcuts => "lightcuts",
        }
    }
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

impl SceneArgs {
    /// `--sample-allocation`, or its default: `adaptive` for the one hierarchy, `intensity`
    /// for the buckets (whose shading has no per-point allocation).
    fn sample_allocation(&self) -> SampleAllocation {
        self.sample_allocation.unwrap_or(match self.aggregation {
            Aggregation::Isotropic => SampleAllocation::Adaptive,
            Aggregation::Buckets => SampleAllocation::Intensity,
        })
    }

    /// `--max-shadow-samples`, or its default: 32 for `adaptive` (which shares the samples per
    /// point, so a light that dominates a point may take many), 16 for `intensity`.
    fn max_shadow_samples(&self) -> u32 {
        self.max_shadow_samples
            .unwrap_or(match self.sample_allocation() {
                SampleAllocation::Adaptive => 32,
                SampleAllocation::Intensity | SampleAllocation::Uniform => 16,
            })
    }

    /// k: `--shadow-samples`, or its default for `--coarse-shadows`, checked: a whole number
    /// from 0 (Gaussian samples) or 1 (representatives) unless it is a mean (`intensity`,
    /// `adaptive`); at most 1024 Gaussian samples, or [`MAX_PER_LIGHT`] representatives.
    fn shadow_samples(&self) -> Result<f32, String> {
        let representatives = self.coarse_shadows == CoarseShadows::Representatives;
        let allocation = self.sample_allocation();
        let k = self.shadow_samples.unwrap_or(match allocation {
            _ if !representatives => 9.0,
            SampleAllocation::Adaptive => 1.25,
            SampleAllocation::Intensity | SampleAllocation::Uniform => 2.0,
        });
        let whole = !representatives || allocation == SampleAllocation::Uniform;
        let (lo, hi) = if representatives {
            (1.0, MAX_PER_LIGHT as f32)
        } else {
            (0.0, 1024.0)
        };
        if !(k.is_finite() && k >= lo && k <= hi) || (whole && k.fract() != 0.0) {
            return Err(format!(
                "--shadow-samples {k}: expected {} from {lo} to {hi} with --coarse-shadows {}",
                if whole { "a whole number" } else { "a number" },
                self.coarse_shadows.name()
            ));
        }
        if !(1..=MAX_PER_LIGHT).contains(&self.max_shadow_samples()) {
            return Err(format!(
                "--max-shadow-samples {}: expected 1 to {MAX_PER_LIGHT}",
                self.max_shadow_samples()
            ));
        }
        if representatives
            && allocation == SampleAllocation::Adaptive
            && self.aggregation == Aggregation::Buckets
        {
            return Err(
                "--sample-allocation adaptive needs --aggregation isotropic (the buckets take \
                 intensity or uniform)"
                    .into(),
            );
        }
        Ok(k)
    }
}

impl CoarseShadows {
    fn name(self) -> &'static str {
        match self {
            CoarseShadows::Gaussian => "gaussian",
            CoarseShadows::Representatives => "representatives",
        }
    }
}

impl Aggregation {
    fn name(self) -> &'static str {
        match self {
            Aggregation::Buckets => "buckets",
            Aggregation::Isotropic => "isotropic",
        }
    }
}

/// What `lgh gi` and `lgh bench gi` share: the scene, its lights and VPLs, the shading.
#[derive(Debug, clap::Args)]
pub struct SceneArgs {
    /// The scene (OBJ, with its MTL files beside it; emissive `Ke` faces are area lights).
    #[arg(long)]
    pub obj: PathBuf,
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
    /// 64), 1.25 for `adaptive`, 2 for `intensity` and `uniform`.
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
    /// Default: `adaptive` with `--aggregation isotropic`, `intensity` with `buckets`.
    #[arg(long, value_enum)]
    pub sample_allocation: Option<SampleAllocation>,
    /// The most representatives one coarse light gets, 1 to 64 (`adaptive`: rounded down to a
    /// power of two; default 32; `intensity`: default 16).
    #[arg(long)]
    pub max_shadow_samples: Option<u32>,
    /// No shadow rays: every VPL reaches every point it faces.
    #[arg(long)]
    pub no_shadows: bool,
    /// How the hierarchy aggregates the VPLs: `isotropic`, the paper's one hierarchy of
    /// isotropic points, or `buckets`, one hierarchy per dominant normal axis whose coarse
    /// lights keep their mean normal's lobe (beyond the paper: better on the Cornell box,
    /// slower on Sponza; `docs/gi.md`).
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
    #[arg(long)]
    pub out: PathBuf,
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

/// `lgh gi`'s default camera: the scene's box `lo..hi` seen straight along −z, y up, from
/// where its front face (`z = hi.z`) just fills a 40° vertical field of view — the Cornell
/// box's classic view, through its open side. (The volumes' framing, from the front-right
/// and above, sees a room from outside its walls.)
fn front_view(lo: Vec3, hi: Vec3, width: usize, height: usize) -> Result<Camera, crate::Error> {
    let fov_y = 40.0f32;
    let tan_y = (0.5 * fov_y).to_radians().tan();
    let tan_x = tan_y * width as f32 / height.max(1) as f32;
    let half = 0.5 * (hi - lo);
    let distance = 1.02 * (half.x / tan_x).max(half.y / tan_y);
    let centre = 0.5 * (lo + hi);
    let eye = Vec3::new(centre.x, centre.y, hi.z + distance);
    Ok(Camera::look_at(eye, centre, Vec3::Y, fov_y, width, height)?)
}

/// A scene ready to shade: its VPLs, their hierarchy, the camera.
struct Prepared {
    scene: Scene,
    traced: Vpls,
    point: Vec<PointLight>,
    lgh: LightingGridHierarchy,
    /// Lightcuts' ε.
    lightcuts_error: f32,
    /// How the representatives were drawn.
    allocation: Allocation,
    /// `--shadow-samples`, the mean of the adaptive allocation.
    mean_samples: f32,
    /// Representative VPLs of the single hierarchy's coarse lights (`--coarse-shadows
    /// representatives`, `--aggregation isotropic`).
    reps: Option<Representatives>,
    /// The normal buckets' hierarchies, built once when `--aggregation buckets`.
    buckets: Option<NormalBuckets>,
    /// Lightcuts' light tree over the VPLs, when asked for.
    tree: Option<LightTree>,
    camera: Camera,
    settings: IndirectSettings,
    /// The primary lights: emissive triangles, then `--light`s.
    lights: Vec<PrimaryLight>,
    emissive: usize,
    triangles: usize,
}

impl Prepared {
    /// Loads the scene, gathers its lights, traces the VPLs and builds their hierarchy, for an
    /// image of `width × height`.
    fn new(
        args: &SceneArgs,
        width: usize,
        height: usize,
        lightcuts: bool,
    ) -> Result<Self, crate::Error> {
        // Every flag is checked before the scene is read and the VPLs traced.
        let k = args.shadow_samples()?;
        if !(args.lightcuts_error.is_finite() && args.lightcuts_error > 0.0) {
            return Err(format!(
                "--lightcuts-error {}: expected a positive number (0.02 is 2%)",
                args.lightcuts_error
            )
            .into());
        }
        lgh_volume::render::check_image_size(width, height)?;
        let given: Vec<PrimaryLight> = args
            .lights
            .iter()
            .map(|s| s.parse())
            .collect::<Result<_, _>>()?;
        let mesh = Mesh::load_obj(&args.obj)?;
        let mut lights = area_lights(&mesh);
        let emissive = lights.len();
        lights.extend(given);
        if lights.is_empty() {
            return Err(lgh_vpl::vpl::VplError::NoLights.into());
        }
        let (lo, hi) = mesh.bounds();
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
        let scene = Scene::new(mesh);
        let camera = match &args.camera {
            Some(s) => crate::explosion::parse_camera(s, Vec3::Y, width, height)?,
            None => front_view(lo, hi, width, height)?,
        };
        let vpl_settings = VplSettings {
            count: args.vpls,
            max_bounces: args.bounces,
            seed: args.seed,
        };
        let traced = trace(&scene, &lights, &vpl_settings)?;
        let point = point_lights(&traced.vpls);
        let lgh = LightingGridHierarchy::build(&point, &GridSettings::default())?;
        let allocation = match args.sample_allocation() {
            SampleAllocation::Uniform => Allocation::Uniform(k as u32),
            SampleAllocation::Intensity => Allocation::ByIntensity {
                mean: k,
                max: args.max_shadow_samples(),
            },
            SampleAllocation::Adaptive => Allocation::Nested(args.max_shadow_samples()),
        };
        let representatives = args.coarse_shadows == CoarseShadows::Representatives;
        let (buckets, reps) = match args.aggregation {
            Aggregation::Buckets => {
                let b = NormalBuckets::build(&traced.vpls, &GridSettings::default())?;
                (
                    Some(if representatives {
                        b.with_representatives(allocation)
                    } else {
                        b
                    }),
                    None,
                )
            }
            Aggregation::Isotropic => (
                None,
                representatives.then(|| Representatives::build_with(&lgh, allocation)),
            ),
        };
        let tree = if lightcuts {
            let seed = Representative::Stochastic { seed: args.seed };
            Some(LightTree::build(&point, seed)?)
        } else {
            None
        };
        let settings = IndirectSettings {
            h0: lgh.h0(),
            shadow_samples: k as u32,
            epsilon: 1e-4 * (hi - lo).length(),
            shadows: !args.no_shadows,
        };
        Ok(Prepared {
            scene,
            traced,
            point,
            lgh,
            reps,
            buckets,
            tree,
            lightcuts_error: args.lightcuts_error,
            allocation,
            mean_samples: k,
            camera,
            settings,
            lights,
            emissive,
            triangles,
        })
    }

    fn shader(&self) -> Indirect<'_> {
        Indirect::new(&self.scene, &self.traced.vpls, self.settings)
    }

    /// The image by `method` (the hierarchy with the aggregation it was prepared for, at
    /// `alpha`).
    fn render(
        &self,
        shader: &Indirect<'_>,
        method: GiBackend,
        alpha: f32,
        progress: impl Fn(usize) + Sync,
    ) -> Result<Rendered, crate::Error> {
        let (scene, camera) = (&self.scene, &self.camera);
        Ok(match (method, &self.buckets) {
            (GiBackend::Lgh, Some(buckets)) => {
                render_buckets(scene, camera, &buckets.at(alpha)?, shader, progress)?
            }
            (GiBackend::Lgh, None) => {
                let backend = LghBackend::new(&self.lgh, alpha)?;
                render_lgh(
                    scene,
                    camera,
                    &backend,
                    match (&self.reps, self.allocation) {
                        (None, _) => Coarse::Gaussian,
                        (Some(reps), Allocation::Nested(_)) => Coarse::Adaptive {
                            reps,
                            mean: self.mean_samples,
                        },
                        (Some(reps), _) => Coarse::Representatives(reps),
                    },
                    shader,
                    progress,
                )?
            }
            (GiBackend::Brute, _) => {
                let brute = BruteForce::new(&self.point)?;
                render_input_lights(scene, camera, &brute, shader, progress)?
            }
            (GiBackend::Lightcuts, _) => {
                let tree = self
                    .tree
                    .as_ref()
                    .ok_or("lightcuts: no light tree was built")?;
                let settings = LightcutsSettings {
                    relative_error: self.lightcuts_error,
                    ..LightcutsSettings::default()
                };
                let cuts = LightcutsBackend::new(tree, settings)?;
                render_input_lights(scene, camera, &cuts, shader, progress)?
            }
        })
    }

    /// Header attributes common to every image of this scene.
    fn settings(&self, args: &SceneArgs) -> Vec<(&'static str, String)> {
        vec![
            ("obj", args.obj.display().to_string()),
            ("vpls", self.traced.vpls.len().to_string()),
            ("light_paths", self.traced.paths.to_string()),
            ("bounces", args.bounces.to_string()),
            ("seed", args.seed.to_string()),
            ("shadow_samples", self.mean_samples.to_string()),
            ("max_shadow_samples", args.max_shadow_samples().to_string()),
            (
                "sample_allocation",
                args.sample_allocation().name().to_string(),
            ),
            ("coarse_shadows", args.coarse_shadows.name().to_string()),
            ("shadows", (!args.no_shadows).to_string()),
            ("h0", self.lgh.h0().to_string()),
        ]
    }
}

/// Runs `lgh gi`.
pub fn run(args: &GiArgs) -> Result<(), crate::Error> {
    crate::check_alpha(args.alpha)?;
    output::check_out(&args.out)?;
    let s = &args.scene;
    let t = Instant::now();
    let p = Prepared::new(s, s.width, s.height, args.backend == GiBackend::Lightcuts)?;
    let prepare_s = t.elapsed().as_secs_f64();
    let shader = p.shader();
    let bar = progress::bar(s.height as u64, "rendering", s.quiet);
    let t = Instant::now();
    let mut rendered = p.render(&shader, args.backend, args.alpha, |n| bar.inc(n as u64))?;
    bar.finish_and_clear();
    let render_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let direct_settings = DirectSettings {
        area_strata: args.area_strata,
        epsilon: p.settings.epsilon,
    };
    let direct = Direct::new(&p.scene, &p.lights, direct_settings);
    if !args.no_direct {
        let bar = progress::bar(s.height as u64, "direct light", s.quiet);
        let lit = render_direct(&p.scene, &p.camera, &direct, |n| bar.inc(n as u64))?;
        bar.finish_and_clear();
        for (px, d) in rendered.image.pixels.iter_mut().zip(&lit.image.pixels) {
            *px += *d;
        }
    }
    let direct_s = t.elapsed().as_secs_f64();
    let mut settings = p.settings(s);
    settings.push(("render_seconds", format!("{render_s:.3}")));
    settings.push(("direct", (!args.no_direct).to_string()));
    if !args.no_direct {
        settings.push(("area_strata", args.area_strata.to_string()));
        settings.push(("direct_seconds", format!("{direct_s:.3}")));
    }
    if args.backend == GiBackend::Lgh {
        settings.push(("alpha", args.alpha.to_string()));
        settings.push(("aggregation", s.aggregation.name().to_string()));
    }
    let attrs = output::header_attributes(args.backend.name(), &settings);
    let png = output::write_exr_png(&args.out, &rendered.image, &attrs, None)?;
    say!(
        "lgh gi: {} triangles, {} primary lights ({} emissive faces), {} VPLs from {} paths, traced and built in {prepare_s:.2} s; indirect by {} {render_s:.1} s, {:.1} lights and {:.1} shadow rays per point; {} -> {}, {}",
        p.triangles,
        p.lights.len(),
        p.emissive,
        p.traced.vpls.len(),
        p.traced.paths,
        args.backend.name(),
        rendered.mean_lights(),
        shader.shadow_rays() as f64 / rendered.pixels_shaded.max(1) as f64,
        if args.no_direct {
            "no direct light".to_string()
        } else {
            format!(
                "direct light {direct_s:.1} s, at most {} shadow rays per point",
                direct.rays_per_point()
            )
        },
        args.out.display(),
        png.display()
    );
    Ok(())
}

/// Runs `lgh bench gi`: brute force over every VPL and the hierarchy at each α on the same
/// pixels, in the same run; JSON on stdout.
pub fn bench(args: &BenchGiArgs) -> Result<(), crate::Error> {
    let s = &args.scene;
    let alphas: Vec<f32> = args
        .alphas
        .split(',')
        .map(|a| a.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--alphas {}: expected numbers like 1,4,16", args.alphas))?;
    for &a in &alphas {
        crate::check_alpha(a)?;
    }
    if let Some(dir) = &args.out {
        if !dir.is_dir() {
            return Err(format!("--out {}: not a folder", dir.display()).into());
        }
    }
    // The framing of --width × --height at about --pixels pixels.
    let aspect = s.width as f64 / s.height as f64;
    let height = ((args.pixels as f64 / aspect).sqrt().round() as usize).max(1);
    let width = ((height as f64 * aspect).round() as usize).max(1);
    let p = Prepared::new(s, width, height, args.lightcuts)?;
    let write = |name: &str, r: &Rendered, extra: &[(&'static str, String)]| {
        if let Some(dir) = &args.out {
            let mut settings = p.settings(s);
            settings.extend_from_slice(extra);
            let attrs = output::header_attributes(name, &settings);
            output::write_exr_png(&dir.join(format!("gi-{name}.exr")), &r.image, &attrs, None)?;
        }
        Ok::<(), crate::Error>(())
    };
    let timed = |method, alpha| {
        let shader = p.shader();
        let bar = progress::bar(height as u64, "rendering", s.quiet);
        let t = Instant::now();
        let r = p.render(&shader, method, alpha, |n| bar.inc(n as u64));
        bar.finish_and_clear();
        r.map(|r| (r, t.elapsed().as_secs_f64(), shader.shadow_rays()))
    };
    let (exact, brute_s, brute_rays) = timed(GiBackend::Brute, 0.0)?;
    write("brute", &exact, &[])?;
    let per_pixel = |n: u64, r: &Rendered| n as f64 / r.pixels_shaded.max(1) as f64;
    // One method's run against brute force: its JSON, its image and difference image.
    let run = |method: GiBackend, alpha: f32, name: String, extra: (&'static str, String)| {
        let (r, seconds, rays) = timed(method, alpha)?;
        let rel = lgh_image::compare(&r.image, &exact.image).map_or(f64::NAN, |e| e.rel_rmse);
        write(&name, &r, &[extra])?;
        if let Some(dir) = &args.out {
            let diff = dir.join(format!("gi-{name}-diff.png"));
            let max = lgh_image::compare(&r.image, &exact.image).map_or(0.0, |e| e.max_abs);
            lgh_image::difference_png(&diff, &r.image, &exact.image, max as f32)?;
        }
        Ok::<_, crate::Error>(json!({
            "lights_per_point": r.mean_lights(),
            "shadow_rays_per_pixel": per_pixel(rays, &r),
            "seconds": seconds,
            "brute_seconds": brute_s,
            "rel_rmse": if rel.is_finite() { Some(rel) } else { None },
        }))
    };
    let mut runs = Vec::new();
    for &alpha in &alphas {
        let extra = ("alpha", alpha.to_string());
        let mut r = run(GiBackend::Lgh, alpha, format!("alpha-{alpha}"), extra)?;
        r["alpha"] = json!(alpha);
        runs.push(r);
    }
    let lightcuts = if args.lightcuts {
        let extra = ("lightcuts_error", s.lightcuts_error.to_string());
        let mut r = run(GiBackend::Lightcuts, 0.0, "lightcuts".into(), extra)?;
        r["relative_error"] = json!(s.lightcuts_error);
        Some(r)
    } else {
        None
    };
    say!(
        "{}",
        json!({
            "scene": s.obj.display().to_string(),
            "vpls": p.traced.vpls.len(),
            "aggregation": s.aggregation.name(),
            "coarse_shadows": s.coarse_shadows.name(),
            "shadow_samples": p.mean_samples,
            "max_shadow_samples": s.max_shadow_samples(),
            "sample_allocation": s.sample_allocation().name(),
            "component": "indirect",
            "pixels": exact.pixels_shaded,
            "width": width,
            "height": height,
            "brute_shadow_rays_per_pixel": per_pixel(brute_rays, &exact),
            "runs": runs,
            "lightcuts": lightcuts,
        })
    );
    Ok(())
}
