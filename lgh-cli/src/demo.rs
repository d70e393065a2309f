//! `lgh demo`: renders the embedded procedural explosion ([`lgh_volume::procedural::explosion`]:
//! a billowing fireball in a shell of soot), lit by its own hot voxels through the lighting grid
//! hierarchy, shadows ray-marched through the lighting cache (`--lighting-cache none` for the
//! exact image, `--shadows cubemap` for the paper's deep-shadow cube maps), to a linear EXR and
//! a filmic tone-mapped PNG beside it.

use std::path::PathBuf;
use std::time::Instant;

use lgh_volume::lgh_core::glam::Vec3;
use lgh_volume::lgh_core::NearField;
use lgh_volume::medium::framing_bounds;
use lgh_volume::render::{Camera, Framing, MarchSettings, Up};
use lgh_volume::surfaces::Ground;
use lgh_volume::{
    explosion, ExplosionLights, FrameRender, Medium, Method, RenderError, Shadows, Volume,
};

use crate::output::{self, EmissionSamplesArg, MarchArgs, PixelSamplesArg, Rendered, ScatterArgs};
use crate::progress::Bars;

/// Arguments of `lgh demo`.
#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// Output image (linear OpenEXR); a tone-mapped PNG is written beside it.
    #[arg(long, default_value = "demo.exr")]
    pub out: PathBuf,
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub march: MarchArgs,
    #[command(flatten)]
    pub scatter: ScatterArgs,
    /// Don't show progress.
    #[arg(long)]
    pub quiet: bool,
}

/// The demo's scene and view: what `lgh demo` and `lgh bench table1` render.
#[derive(Debug, clap::Args)]
pub struct SceneArgs {
    /// Voxels per side of the procedural explosion (32 to 512; the paper's Fig. 8 frame has about
    /// 19M voxels: 267).
    #[arg(long, default_value_t = 128)]
    pub resolution: usize,
    /// Seconds after ignition (0 to 10; the fireball grows over the first second and cools after).
    #[arg(long, default_value_t = 0.5)]
    pub time: f32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    pub width: usize,
    /// Image height in pixels.
    #[arg(long, default_value_t = 360)]
    pub height: usize,
    /// The paper's α.
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true)]
    pub alpha: f32,
    /// No ground under the explosion (by default a grey plane where its smoke ends below, lit
    /// by the fire through the smoke).
    #[arg(long)]
    pub no_ground: bool,
}

/// The demo's frame made ready: the volume, its medium, its lights (with their hierarchy), the
/// camera, and the seconds the volume and the lights took.
pub struct Scene {
    pub volume: Volume,
    pub medium: Medium,
    pub lights: ExplosionLights,
    pub camera: Camera,
    pub volume_seconds: f64,
    pub lights_seconds: f64,
}

impl Scene {
    /// `march` with what depends on the camera resolved as `lgh demo` does
    /// ([`MarchArgs::for_camera`]: one ray a pixel unless `--pixel-samples`, the emission with
    /// the light unless `--emission-samples`, the cache's first level), for the volume's framed
    /// middle.
    pub fn for_camera(&self, args: &MarchArgs, march: MarchSettings) -> MarchSettings {
        let (lo, hi) = framing_bounds(&[&self.volume]).expect("one frame");
        let voxel = self.volume.density.voxel_size;
        args.for_camera(
            march,
            (PixelSamplesArg::Fixed(1), EmissionSamplesArg::WithLight),
            &self.camera,
            0.5 * (lo + hi),
            voxel,
        )
    }
}

impl SceneArgs {
    /// Checks α and the image size (before any work).
    pub fn check(&self) -> Result<(), crate::Error> {
        crate::check_alpha(self.alpha)?;
        Ok(lgh_volume::render::check_image_size(
            self.width,
            self.height,
        )?)
    }

    /// The procedural explosion, its lights (voxels or the paper's points: `near_field`) and a
    /// camera framing it.
    pub fn build(&self, near_field: NearField) -> Result<Scene, crate::Error> {
        let t = Instant::now();
        let volume = explosion(self.resolution, self.time)?;
        let medium = demo_medium();
        let volume_seconds = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let mut lights = ExplosionLights::from_frames([Ok::<_, RenderError>(&volume)], &medium)?;
        lights.set_near_field(near_field);
        lights.set_frame(&volume, &medium)?;
        let lights_seconds = t.elapsed().as_secs_f64();
        let (lo, hi) = framing_bounds(&[&volume]).expect("one frame");
        let camera = Camera::frame(lo, hi, self.width, self.height)?;
        Ok(Scene {
            volume,
            medium,
            lights,
            camera,
            volume_seconds,
            lights_seconds,
        })
    }
}

/// The demo's shadow-ray step, in voxels: halving the shadow rays' samples (against 1-voxel
/// steps) changes the demo's scattered light far less than the hierarchy's own error at α = 2
/// and saves much of the render's time (`lgh demo --shadow-step 1` against the default, with
/// `lgh compare`, shows by how much).
pub const DEMO_SHADOW_STEP: f32 = 2.0;

/// The demo's default shadows and shadow step: coarse lights' shadows as points (`raymarch`),
/// the exact image of issue 27's Table 1, kept as that reference.
pub const DEMO_DEFAULTS: (Shadows, f32) = (Shadows::RayMarch, DEMO_SHADOW_STEP);

/// The demo's medium: smoke that absorbs and scatters (albedo 0.75) and glows above 1000 K.
pub fn demo_medium() -> Medium {
    Medium::new(2.0, 6.0, 1e-4, 1000.0).expect("valid constants")
}

/// Runs the demo.
pub fn run(args: &DemoArgs) -> Result<(), crate::Error> {
    args.scene.check()?;
    output::check_out(&args.out)?;
    let march = args.march.settings(DEMO_DEFAULTS, &args.scatter)?;
    let mut scene = args.scene.build(args.march.near_field.into())?;
    scene
        .lights
        .set_coarse_spread(args.march.coarse_spread.into());
    let march = scene.for_camera(&args.march, march);
    scene.lights.set_prune(args.march.prune)?;
    scene.lights.set_coarse_shadows(args.march.coarse_shadows());
    // The ground under the explosion, where its smoke ends, so that its light falls on
    // something.
    let ground = if args.scene.no_ground {
        None
    } else {
        let (lo, _) = framing_bounds(&[&scene.volume]).expect("one frame");
        Some(Ground::new(Up::Y, lo.y, Vec3::splat(0.5))?)
    };
    let bars = Bars::new(args.quiet);
    let cpu0 = output::cpu_seconds();
    let method = Method::Lgh {
        alpha: args.scene.alpha,
    };
    let (volume, medium) = (&scene.volume, &scene.medium);
    let mut frame = FrameRender::new(&scene.lights, method, volume, medium, &march, &bars)?;
    if let Some(g) = &ground {
        frame = frame.with_surfaces(g);
    }
    let cpu1 = output::cpu_seconds();
    // The shares' n + 2 renders are reported apart, as before: in neither CPU figure.
    let shares = output::shares(&args.scatter, &frame, &scene.camera, &bars)?;
    let cpu_render = output::cpu_seconds();
    let rendered = Rendered::of(&frame, &scene.camera, &bars)?;
    let cpu2 = output::cpu_seconds();
    let mut extra = args.scene.header(&scene);
    extra.push(("prune", args.march.prune.to_string()));
    extra.extend(output::frame_header(&frame, shares.as_ref()));
    let png = rendered.write(&args.out, &march, "lgh", extra)?;
    let cpu = match (cpu0, cpu1, cpu_render, cpu2) {
        (Some(a), Some(b), Some(r), Some(c)) => {
            let before = if frame.scattered().is_some() {
                "shadows and scattering"
            } else {
                "shadows"
            };
            format!(" (CPU: {:.1} s {before}, {:.1} s render)", b - a, c - r)
        }
        _ => String::new(),
    };
    args.scene.say(&scene)?;
    output::say_scattering(&frame, shares.as_ref())?;
    if let Some(maps) = frame.cube_maps() {
        output::say_cube_maps(maps.table(), maps.bytes(), frame.seconds().shadows)?;
    }
    output::say_lighting_cache(&frame)?;
    let stats = rendered.stats.unwrap_or_default();
    say!(
        "  render     {}x{}, shadows {}: {:.1} s ({:.1} s with the shadows' precompute){cpu}, {} shading points, {:.1} lights each, {:.1} shadow samples per light",
        args.scene.width,
        args.scene.height,
        frame.visibility().shadows().name(),
        rendered.seconds,
        rendered.seconds + frame.seconds().shadows,
        stats.shading_points,
        stats.lights_per_point(),
        stats.shadow_samples as f64 / stats.lights_evaluated.max(1) as f64
    );
    say!("  output     {} and {}", args.out.display(), png.display());
    Ok(())
}

impl SceneArgs {
    /// EXR header entries of the scene: what it is, α, its lights and whether it has a ground.
    fn header(&self, scene: &Scene) -> Vec<(&'static str, String)> {
        vec![
            (
                "scene",
                format!(
                    "procedural explosion {}^3, t = {} s",
                    self.resolution, self.time
                ),
            ),
            ("alpha", self.alpha.to_string()),
            ("lights", scene.lights.lit().to_string()),
            ("ground", (!self.no_ground).to_string()),
        ]
    }

    /// The summary lines of the scene and its hierarchy.
    fn say(&self, scene: &Scene) -> Result<(), crate::Error> {
        let h = scene.lights.hierarchy();
        let setup_s = scene.volume_seconds + scene.lights_seconds;
        say!("lgh demo: a procedural explosion lit by its own hot voxels");
        say!(
            "  volume     {0}^3 voxels at t = {1} s, {2} lights (one per voxel above 1000 K); set up in {setup_s:.2} s",
            self.resolution,
            self.time,
            scene.lights.lit()
        );
        say!(
            "  hierarchy  levels 0..={}, h1 = {:.4}, alpha {}",
            h.max_level(),
            h.h1(),
            self.alpha
        );
        Ok(())
    }
}
