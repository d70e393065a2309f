//! `lgh gi`: indirect illumination of an OBJ scene from virtual point lights (paper Sec. 6.4,
//! Fig. 13), shaded through the hierarchy or brute force with shadow rays.

use std::path::PathBuf;
use std::time::Instant;

use lgh_core::{BruteForce, GridSettings, LghBackend, LightingGridHierarchy};
use lgh_volume::render::{Camera, Framing, Up};
use lgh_volume::Method;
use lgh_vpl::indirect::{
    point_lights, render_brute, render_buckets, render_lgh, Indirect, IndirectSettings,
    NormalBuckets,
};
use lgh_vpl::primary::{area_lights, PrimaryLight};
use lgh_vpl::vpl::{trace, VplSettings};
use lgh_vpl::{Mesh, Scene};

use crate::{output, progress};

/// `--aggregation`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Aggregation {
    /// One hierarchy per dominant normal axis, coarse lights with their bucket's lobe.
    Buckets,
    /// The paper's: one hierarchy, VPLs aggregated as isotropic points.
    Isotropic,
}

/// Arguments of `lgh gi`.
#[derive(Debug, clap::Args)]
pub struct GiArgs {
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
    /// The paper's α (backend lgh).
    #[arg(long, default_value_t = 4.0)]
    pub alpha: f32,
    /// Shadow samples of a coarse light (Fig. 11d uses 9; 0 shades it as a point, Fig. 11c).
    #[arg(long, default_value_t = 9)]
    pub shadow_samples: u32,
    /// No shadow rays: every VPL reaches every point it faces.
    #[arg(long)]
    pub no_shadows: bool,
    /// How the hierarchy aggregates the VPLs' cosine lobes: `buckets`, one hierarchy per
    /// dominant normal axis whose coarse lights keep their mean normal's lobe (beyond the
    /// paper; it wins: README), or `isotropic`, the paper's one hierarchy of isotropic points.
    #[arg(long, value_enum, default_value_t = Aggregation::Buckets)]
    pub aggregation: Aggregation,
    /// Many-lights method.
    #[arg(long, value_enum, default_value_t = Method::Lgh)]
    pub backend: Method,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    pub width: usize,
    /// Image height in pixels.
    #[arg(long, default_value_t = 360)]
    pub height: usize,
    /// Camera `EX,EY,EZ,TX,TY,TZ[,FOV]` (default: the scene's box, seen from +z, y up).
    #[arg(long, allow_negative_numbers = true)]
    pub camera: Option<String>,
    /// Output image (linear OpenEXR); a tone-mapped PNG is written beside it.
    #[arg(long)]
    pub out: PathBuf,
    /// Don't show progress.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `lgh gi`.
pub fn run(args: &GiArgs) -> Result<(), crate::Error> {
    crate::check_alpha(args.alpha)?;
    lgh_volume::render::check_image_size(args.width, args.height)?;
    output::check_out(&args.out)?;
    let given: Vec<PrimaryLight> = args
        .lights
        .iter()
        .map(|s| s.parse())
        .collect::<Result<_, _>>()?;
    let t = Instant::now();
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
            "lgh gi: {defaulted} of {triangles} triangles have no material (no MTL, or one that \
             does not define theirs): they are Lambertian with albedo 0.5"
        );
    }
    let scene = Scene::new(mesh);
    let camera = match &args.camera {
        Some(s) => {
            crate::explosion::parse_camera(s, lgh_core::glam::Vec3::Y, args.width, args.height)?
        }
        None => Camera::frame_up(lo, hi, args.width, args.height, Up::Y)?,
    };
    let settings = VplSettings {
        count: args.vpls,
        max_bounces: args.bounces,
        seed: args.seed,
    };
    let traced = trace(&scene, &lights, &settings)?;
    let load_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let point = point_lights(&traced.vpls);
    let lgh = LightingGridHierarchy::build(&point, &GridSettings::default())?;
    let build_s = t.elapsed().as_secs_f64();
    let shader = Indirect::new(
        &scene,
        &traced.vpls,
        IndirectSettings {
            h0: lgh.h0(),
            shadow_samples: args.shadow_samples,
            epsilon: 1e-4 * (hi - lo).length(),
            shadows: !args.no_shadows,
        },
    );
    let bar = progress::bar(args.height as u64, "rendering", args.quiet);
    let t = Instant::now();
    let progress = |n: usize| bar.inc(n as u64);
    let rendered = match (args.backend, args.aggregation) {
        (Method::Lgh, Aggregation::Buckets) => {
            let buckets = NormalBuckets::build(&traced.vpls, &GridSettings::default())?;
            render_buckets(&scene, &camera, &buckets, args.alpha, &shader, progress)?
        }
        (Method::Lgh, Aggregation::Isotropic) => {
            let backend = LghBackend::new(&lgh, args.alpha)?;
            render_lgh(&scene, &camera, &backend, &shader, progress)?
        }
        (Method::Brute, _) => {
            let brute = BruteForce::new(&point)?;
            render_brute(&scene, &camera, &brute, &shader, progress)?
        }
    };
    bar.finish_and_clear();
    let render_s = t.elapsed().as_secs_f64();
    let mut settings = vec![
        ("obj", args.obj.display().to_string()),
        ("vpls", traced.vpls.len().to_string()),
        ("light_paths", traced.paths.to_string()),
        ("bounces", args.bounces.to_string()),
        ("seed", args.seed.to_string()),
        ("shadow_samples", args.shadow_samples.to_string()),
        ("shadows", (!args.no_shadows).to_string()),
        ("h0", lgh.h0().to_string()),
        ("render_seconds", format!("{render_s:.3}")),
    ];
    if args.backend == Method::Lgh {
        settings.push(("alpha", args.alpha.to_string()));
        let aggregation = match args.aggregation {
            Aggregation::Buckets => "buckets",
            Aggregation::Isotropic => "isotropic",
        };
        settings.push(("aggregation", aggregation.to_string()));
    }
    let attrs = output::header_attributes(args.backend.name(), &settings);
    let png = output::write_exr_png(&args.out, &rendered.image, &attrs, None)?;
    say!(
        "lgh gi: {triangles} triangles, {} primary lights ({emissive} emissive faces), {} VPLs from {} paths; traced in {load_s:.2} s, hierarchy {build_s:.2} s; {} {render_s:.1} s, {:.1} lights per point -> {}, {}",
        lights.len(),
        traced.vpls.len(),
        traced.paths,
        args.backend.name(),
        rendered.mean_lights(),
        args.out.display(),
        png.display()
    );
    Ok(())
}
