//! `lgh paquette`: Paquette et al.'s experiments (Tables 2 and 3) on our machine.
//!
//! One case renders a test scene four ways through the same surface renderer and shader
//! (eq. (1), unoccluded): brute force over every light (the paper's RT), Ward's method and the
//! light octree, both with the absolute threshold, and Lightcuts (2 %). Then the lighting grid
//! hierarchy at the smallest α (of 1, 2, 4, 8) whose largest 8-bit error is no larger than the
//! octree's. Times are wall-clock seconds of the render (the octree's and LGH's include building
//! their hierarchy); errors are against brute force on the 8-bit scale of the paper.

use std::path::PathBuf;

use lgh_core::lightcuts::{LightTree, LightcutsBackend, LightcutsSettings, Representative};
use lgh_core::octree::{LightOctree, OctreeBackend, OctreeSettings};
use lgh_core::ward::WardBackend;
use lgh_core::{
    BruteForce, GridSettings, LghBackend, LightingGridHierarchy, ManyLights, QueryError,
};
use lgh_image::{error_8bit, Image};
use lgh_vpl::paquette::{
    self, Built, Surface, TestScene, LIGHT_COUNTS, MAX_SCENE_LIGHTS, PAPER_THRESHOLD,
};
use serde_json::{json, Value};

use crate::bench::time;

/// The α values LGH tries, smallest first.
const LGH_ALPHAS: [f32; 4] = [1.0, 2.0, 4.0, 8.0];

/// Arguments of `lgh paquette`.
#[derive(Debug, clap::Args)]
pub struct PaquetteArgs {
    /// Test scene: strings, udem or cluster.
    #[arg(long, required_unless_present = "table")]
    pub scene: Option<TestScene>,
    /// Number of equal lights (the paper uses 64, 256, 1024, 4096 and 16384).
    #[arg(long, required_unless_present = "table")]
    pub lights: Option<usize>,
    /// Surfaces: diffuse (Lambert) or specular (Phong, n = 200).
    #[arg(long, default_value = "diffuse")]
    pub material: Surface,
    /// Absolute error threshold of the octree and Ward's method, in 8-bit levels of 255 (the
    /// paper's 1 %: 2.55). Radiance 1 maps to 255.
    #[arg(long, default_value_t = PAPER_THRESHOLD * 255.0, allow_negative_numbers = true)]
    pub threshold: f32,
    /// Image width.
    #[arg(long, default_value_t = 320)]
    pub width: usize,
    /// Image height.
    #[arg(long, default_value_t = 240)]
    pub height: usize,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Run every case of Tables 2 and 3 (3 scenes × 5 light counts × 2 materials) and print the
    /// table next to the paper's numbers.
    #[arg(long, conflicts_with_all = ["scene", "lights"])]
    pub table: bool,
    /// Write each render (EXR + PNG) into this existing folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// No progress on stderr.
    #[arg(long, short)]
    pub quiet: bool,
}

/// One method's render: seconds, lights per pixel, and 8-bit error against brute force.
struct Measured {
    seconds: f64,
    lights_per_pixel: f64,
    max_error: u8,
    mean_error: f64,
    image: Image,
    /// Lights shaded per pixel (0 where no surface is seen).
    lights_map: Vec<u32>,
}

fn measure<B: ManyLights + Sync>(
    built: &Built,
    backend: &B,
    build_seconds: f64,
    reference: Option<&Image>,
) -> Result<Measured, crate::Error> {
    let (rendered, seconds) = time(|| {
        lgh_vpl::render(&built.scene, &built.camera, backend, |_| {})
            .map_err(|e| format!("{}: {e}", backend.name()))
    });
    let rendered = rendered?;
    let (max_error, mean_error) = match reference {
        Some(r) => {
            let e = error_8bit(&rendered.image, r).ok_or("image sizes differ")?;
            (e.max, e.mean)
        }
        None => (0, 0.0),
    };
    Ok(Measured {
        seconds: seconds + build_seconds,
        lights_per_pixel: rendered.mean_lights(),
        max_error,
        mean_error,
        image: rendered.image,
        lights_map: rendered.lights_map,
    })
}

/// Upper edges (8-bit levels) of the brightness classes of [`cost_by_brightness`].
const BRIGHTNESS_EDGES: [f32; 5] = [4.0, 16.0, 64.0, 256.0, f32::INFINITY];

/// A method's mean lights shaded per pixel, by how bright brute force makes the pixel (its
/// largest channel in 8-bit levels): an absolute threshold costs more where the image is bright.
fn cost_by_brightness(m: &Measured, rt: &Measured) -> Value {
    let mut classes = [(0u64, 0u64); BRIGHTNESS_EDGES.len()];
    // Brute force shades every light at every pixel that sees a surface, and none elsewhere.
    for ((px, &seen), &cost) in rt
        .image
        .pixels
        .iter()
        .zip(&rt.lights_map)
        .zip(&m.lights_map)
    {
        if seen > 0 {
            let level = 255.0 * px.max_element();
            let k = BRIGHTNESS_EDGES.iter().position(|&e| level < e);
            let k = k.unwrap_or(BRIGHTNESS_EDGES.len() - 1);
            classes[k].0 += 1;
            classes[k].1 += u64::from(cost);
        }
    }
    let mut below = 0.0;
    let rows = BRIGHTNESS_EDGES
        .iter()
        .zip(classes)
        .map(|(&edge, (pixels, lights))| {
            let row = json!({
                "from_8bit": below,
                "below_8bit": if edge.is_finite() { json!(edge) } else { Value::Null },
                "pixels": pixels,
                "lights_per_pixel": if pixels > 0 { lights as f64 / pixels as f64 } else { 0.0 },
            });
            below = edge;
            row
        });
    Value::Array(rows.collect())
}

fn method_json(m: &Measured, rt: f64) -> Value {
    json!({
        "seconds": m.seconds,
        "percent": 100.0 * m.seconds / rt,
        "lights_per_pixel": m.lights_per_pixel,
        "max_error_8bit": m.max_error,
        "mean_error_8bit": m.mean_error,
    })
}

/// Runs one case; returns its JSON record.
fn case(
    scene: TestScene,
    lights: usize,
    surface: Surface,
    args: &PaquetteArgs,
) -> Result<Value, crate::Error> {
    let built = paquette::build(scene, lights, surface, args.width, args.height)?;
    // The octree's and Ward's threshold in radiance, where 1 is 255 levels.
    let t = args.threshold / 255.0;
    let say = |what: &str| {
        if !args.quiet {
            eprintln!("{} {lights} {}: {what}", scene.name(), surface.name());
        }
    };
    say("brute force");
    let brute = BruteForce::new(&built.lights)?;
    let rt = measure(&built, &brute, 0.0, None)?;
    let reference = Some(&rt.image);
    say("Ward");
    let ward = measure(&built, &WardBackend::new(&brute, t)?, 0.0, reference)?;
    say("octree");
    let (tree, build) = time(|| LightOctree::build(&built.lights, &OctreeSettings::default()));
    let tree = tree?;
    let octree = measure(&built, &OctreeBackend::new(&tree, t)?, build, reference)?;
    say("Lightcuts");
    let (cuts, build) = time(|| LightTree::build(&built.lights, Representative::Brightest));
    let cuts = cuts?;
    let lightcuts = measure(
        &built,
        &LightcutsBackend::new(&cuts, LightcutsSettings::default())?,
        build,
        reference,
    )?;
    say("LGH");
    let (lgh, build) =
        time(|| LightingGridHierarchy::build(&built.lights, &GridSettings::default()));
    let lgh = lgh?;
    let (alpha, lgh_m) = match_octree_error(&built, &lgh, build, reference, octree.max_error)?;
    if let Some(dir) = &args.out {
        let case = (scene, lights, surface);
        for (name, m) in [("brute", &rt), ("octree", &octree), ("lgh", &lgh_m)] {
            write_render(dir, case, args.threshold, name, m)?;
        }
    }
    Ok(json!({
        "scene": scene.name(),
        "lights": lights,
        "material": surface.name(),
        "threshold_8bit": args.threshold,
        "width": args.width,
        "height": args.height,
        "rt_seconds": rt.seconds,
        "ward_percent": 100.0 * ward.seconds / rt.seconds,
        "octree_percent": 100.0 * octree.seconds / rt.seconds,
        "speedup": rt.seconds / octree.seconds,
        "max_error_8bit": octree.max_error,
        "mean_error_8bit": octree.mean_error,
        "octree": method_json(&octree, rt.seconds),
        "octree_cost_by_brightness": cost_by_brightness(&octree, &rt),
        "ward": method_json(&ward, rt.seconds),
        "lightcuts": method_json(&lightcuts, rt.seconds),
        "lgh": { "alpha": alpha, "matched_octree_error": lgh_m.max_error <= octree.max_error,
                 "build_seconds": build, "method": method_json(&lgh_m, rt.seconds) },
    }))
}

/// LGH at the smallest α of [`LGH_ALPHAS`] whose largest 8-bit error is no larger than
/// `octree_error` (the largest α when none is), with `build_seconds` of its build added.
fn match_octree_error(
    built: &Built,
    lgh: &LightingGridHierarchy,
    build_seconds: f64,
    reference: Option<&Image>,
    octree_error: u8,
) -> Result<(f32, Measured), crate::Error> {
    let mut chosen = None;
    for alpha in LGH_ALPHAS {
        let backend = LghBackend::new(lgh, alpha)?;
        let m = measure(built, &backend, build_seconds, reference)?;
        let good = m.max_error <= octree_error;
        chosen = Some((alpha, m));
        if good {
            break;
        }
    }
    Ok(chosen.ok_or("no α to try")?)
}

/// Writes method `name`'s render of the case `(scene, lights, surface)` into `dir` as EXR and
/// PNG, its header naming the case, the `threshold` (8-bit levels) and the render's seconds.
fn write_render(
    dir: &std::path::Path,
    (scene, lights, surface): (TestScene, usize, Surface),
    threshold: f32,
    name: &str,
    m: &Measured,
) -> Result<(), crate::Error> {
    let stem = format!("{}_{lights}_{}", scene.name(), surface.name());
    let attrs = crate::output::header_attributes(
        name,
        &[
            ("scene", scene.name().to_string()),
            ("lights", lights.to_string()),
            ("material", surface.name().to_string()),
            ("threshold_8bit", threshold.to_string()),
            ("render_seconds", format!("{:.3}", m.seconds)),
        ],
    );
    // Exposure 1: radiance 1 is white, as on the paper's 8-bit scale.
    let exr = dir.join(format!("{stem}_{name}.exr"));
    crate::output::write_exr_png(&exr, &m.image, &attrs, Some(1.0))?;
    Ok(())
}

/// The paper's row for a case.
fn paper_row(scene: TestScene, lights: usize, surface: Surface) -> Option<paquette::PaperRow> {
    paquette::paper_table()
        .into_iter()
        .find(|r| r.scene == scene && r.lights == lights && r.surface == surface)
}

/// Checks the arguments before any work.
fn check(args: &PaquetteArgs) -> Result<(), crate::Error> {
    QueryError::check_threshold(args.threshold)
        .map_err(|e| format!("--threshold (8-bit levels): {e}"))?;
    if let Some(n) = args.lights {
        if n == 0 || n > MAX_SCENE_LIGHTS {
            return Err(format!("--lights {n}: must be 1 to {MAX_SCENE_LIGHTS}").into());
        }
    }
    lgh_image::check_image_size(args.width, args.height)
        .map_err(|e| format!("--width/--height: {e}"))?;
    if let Some(dir) = &args.out {
        if !dir.is_dir() {
            return Err(format!("--out {}: no such folder", dir.display()).into());
        }
    }
    Ok(())
}

/// Runs `lgh paquette`.
pub fn run(args: &PaquetteArgs) -> Result<(), crate::Error> {
    check(args)?;
    let cases: Vec<(TestScene, usize, Surface)> = if args.table {
        [Surface::Diffuse, Surface::Specular]
            .into_iter()
            .flat_map(|s| {
                TestScene::ALL
                    .into_iter()
                    .flat_map(move |t| LIGHT_COUNTS.into_iter().map(move |n| (t, n, s)))
            })
            .collect()
    } else {
        let (Some(scene), Some(lights)) = (args.scene, args.lights) else {
            return Err("give --scene and --lights, or --table".into());
        };
        vec![(scene, lights, args.material)]
    };
    let mut records = Vec::new();
    for &(scene, lights, surface) in &cases {
        let mut r = case(scene, lights, surface, args)?;
        if let Some(p) = paper_row(scene, lights, surface) {
            r["paper"] = json!({
                "rt_seconds": p.rt_seconds, "ward_percent": p.ward_percent,
                "octree_percent": p.octree_percent, "speedup": p.speedup,
            });
        }
        if !args.json && !args.table {
            print_case(&r)?;
        }
        records.push(r);
    }
    if args.json {
        let v = if args.table {
            Value::Array(records)
        } else {
            records.pop().unwrap_or(Value::Null)
        };
        say!("{}", serde_json::to_string_pretty(&v)?);
    } else if args.table {
        print_table(&records)?;
    }
    Ok(())
}

fn print_case(r: &Value) -> Result<(), crate::Error> {
    say!(
        "{} with {} lights, {} surfaces, {}×{}, threshold {} of 255",
        r["scene"],
        r["lights"],
        r["material"],
        r["width"],
        r["height"],
        r["threshold_8bit"]
    );
    say!(
        "  RT (brute force)  {:9.3} s",
        r["rt_seconds"].as_f64().unwrap_or(0.0)
    );
    for key in ["ward", "octree", "lightcuts"] {
        let m = &r[key];
        say!(
            "  {key:<17} {:8.1} % of RT, {:8.1} lights/pixel, 8-bit error max {} mean {:.4}",
            m["percent"].as_f64().unwrap_or(0.0),
            m["lights_per_pixel"].as_f64().unwrap_or(0.0),
            m["max_error_8bit"],
            m["mean_error_8bit"].as_f64().unwrap_or(0.0)
        );
    }
    let l = &r["lgh"]["method"];
    say!(
        "  LGH α = {:<9} {:8.1} % of RT, {:8.1} lights/pixel, 8-bit error max {} mean {:.4}",
        r["lgh"]["alpha"],
        l["percent"].as_f64().unwrap_or(0.0),
        l["lights_per_pixel"].as_f64().unwrap_or(0.0),
        l["max_error_8bit"],
        l["mean_error_8bit"].as_f64().unwrap_or(0.0)
    );
    say!(
        "  speed-up of the octree over RT: {:.2}",
        r["speedup"].as_f64().unwrap_or(0.0)
    );
    if let Some(p) = r.get("paper") {
        say!(
            "  paper (SGI R10000): RT {} s, Ward {} %, LH {} %, speed-up {}",
            p["rt_seconds"],
            p["ward_percent"],
            p["octree_percent"],
            p["speedup"]
        );
    }
    Ok(())
}

fn print_table(records: &[Value]) -> Result<(), crate::Error> {
    say!("| scene | lights | material | RT s | Ward % | octree % | speed-up | max / mean 8-bit error | Lightcuts % | LGH α | LGH % | LGH max error | paper RT s | paper Ward % | paper LH % | paper speed-up |");
    say!("|---|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    let f = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    for r in records {
        let p = &r["paper"];
        say!(
            "| {} | {} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {} / {:.3} | {:.1} | {} | {:.1} | {} | {} | {} | {} | {} |",
            r["scene"].as_str().unwrap_or("?"),
            r["lights"],
            r["material"].as_str().unwrap_or("?"),
            f(&r["rt_seconds"]),
            f(&r["ward_percent"]),
            f(&r["octree_percent"]),
            f(&r["speedup"]),
            r["max_error_8bit"],
            f(&r["mean_error_8bit"]),
            f(&r["lightcuts"]["percent"]),
            r["lgh"]["alpha"],
            f(&r["lgh"]["method"]["percent"]),
            r["lgh"]["method"]["max_error_8bit"],
            p["rt_seconds"],
            p["ward_percent"],
            p["octree_percent"],
            p["speedup"],
        );
    }
    Ok(())
}
