//! What every render command shares: options for the ray marcher, the progress bar over rows,
//! and the outputs (a linear EXR with the settings in its header, a tone-mapped PNG beside it).

use std::path::{Path, PathBuf};
use std::time::Instant;

use lgh_image::Image;
use lgh_volume::render::{Camera, MarchSettings, Marcher, RenderStats};
use lgh_volume::shadow::{CubeMapSettings, CubeMaps, Depths, LevelMaps};
use lgh_volume::{ExplosionLights, Medium, Method, Shadows, Visibility, Volume};

/// The ray marcher's options, shared by the render commands.
#[derive(Debug, Clone, clap::Args)]
pub struct MarchArgs {
    /// Shadows of the lights: the paper's precomputed deep-shadow cube maps, shadow rays marched
    /// to every light (the exact reference), or none. Brute force has no hierarchy to make
    /// cube maps for: it ray-marches.
    #[arg(long, value_enum, default_value_t = Shadows::CubeMap)]
    pub shadows: Shadows,
    /// Memory the cube maps may take, in GB (maps that would need more are refused before any
    /// work) [default: 8 GiB, or 3/4 of the available memory if less]
    #[arg(long)]
    pub shadow_memory: Option<f64>,
    /// Cube maps store optical depth sampled at their four distances, as the paper does,
    /// instead of the least-squares fit that leaks less light through smoke.
    #[arg(long)]
    pub sampled_depths: bool,
    /// Cube maps trace coarse lights as points through the plain density instead of as volume
    /// lights through the prefiltered density (eq. 6): the flickering variant of the paper.
    #[arg(long)]
    pub point_shadows: bool,
    /// Step along camera rays, in voxels (smaller is more accurate and slower).
    #[arg(long, default_value_t = 1.0)]
    pub step: f32,
    /// Step along shadow rays, in voxels (smaller is more accurate and slower) [default: 1, or 2
    /// for lgh demo]
    #[arg(long)]
    pub shadow_step: Option<f32>,
}

impl MarchArgs {
    /// The marcher's settings, checked ([`MarchSettings::check`]); `default_shadow_step` applies
    /// without `--shadow-step`.
    pub fn settings(&self, default_shadow_step: f32) -> Result<MarchSettings, crate::Error> {
        let budget = match self.shadow_memory {
            Some(gb) if gb.is_finite() && gb > 0.0 && gb <= 1e6 => (gb * 1e9) as u64,
            Some(gb) => {
                return Err(format!("--shadow-memory {gb} must be a positive number of GB").into())
            }
            None => default_shadow_memory(),
        };
        let shadow_step = self.shadow_step.unwrap_or(default_shadow_step);
        let settings = MarchSettings {
            shadows: self.shadows,
            step_voxels: self.step,
            shadow_step_voxels: shadow_step,
            cube_maps: CubeMapSettings {
                // The texel rays step as the shadow rays do where the prefilter allows no more.
                step_voxels: shadow_step,
                prefilter: !self.point_shadows,
                depths: if self.sampled_depths {
                    Depths::Sampled
                } else {
                    Depths::Fitted
                },
                memory_budget: budget,
            },
            ..Default::default()
        };
        settings.check()?;
        Ok(settings)
    }
}

/// The cube maps' default memory: 8 GiB, or 3/4 of the memory available now if less (read
/// from `/proc/meminfo` where there is one).
fn default_shadow_memory() -> u64 {
    let cap = 8u64 << 30;
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| {
            m.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .map(|kib| kib * 1024 / 4 * 3);
    available.map_or(cap, |a| a.min(cap))
}

/// CPU seconds this process has used so far (user + system, all threads), from
/// `/proc/self/stat` (Linux; `None` elsewhere): what a time on a shared machine should be
/// judged by next to the wall-clock seconds.
pub fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces, so skip past its ')'): utime and
    // stime are the 12th and 13th, in clock ticks of 1/100 s on Linux.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?;
    Some(ticks as f64 / 100.0)
}

/// A frame's visibility made ready, with what it took: the cube maps' precompute is timed and
/// shown apart from the render.
pub struct Shadowing {
    /// The visibility to render with.
    pub visibility: Visibility,
    /// Seconds spent making it (the cube maps' tracing).
    pub seconds: f64,
}

impl Shadowing {
    /// The visibility `march.shadows` asks for, for `lights` through `method` at `alpha` on
    /// `volume`, under a progress bar over the lights whose cube maps are traced.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        lights: &ExplosionLights,
        method: Method,
        alpha: f32,
        volume: &Volume,
        medium: &Medium,
        march: &MarchSettings,
        quiet: bool,
    ) -> Result<Shadowing, crate::Error> {
        let t = Instant::now();
        let cube = march.shadows == Shadows::CubeMap && method == Method::Lgh;
        let total = if cube {
            let blending = lights.hierarchy().blending(alpha)?;
            CubeMaps::plan(
                lights.hierarchy(),
                &blending,
                &volume.density,
                &march.cube_maps,
            )
            .lights() as u64
        } else {
            0
        };
        let bar = crate::progress::bar(total, "shadow maps", quiet || !cube);
        let visibility =
            lights.visibility(method, alpha, volume, medium, march, &|n| bar.inc(n as u64))?;
        bar.finish_and_clear();
        Ok(Shadowing {
            visibility,
            seconds: t.elapsed().as_secs_f64(),
        })
    }

    /// The cube maps, if these shadows are cube maps.
    pub fn cube_maps(&self) -> Option<&CubeMaps> {
        match &self.visibility {
            Visibility::CubeMaps(m) => Some(m),
            _ => None,
        }
    }

    /// EXR header entries: the shadows used and, for cube maps, their bytes and precompute.
    pub fn header(&self) -> Vec<(&'static str, String)> {
        let mut out = vec![("shadows", self.visibility.shadows().name().to_string())];
        if let Some(m) = self.cube_maps() {
            out.push(("shadow_bytes", m.bytes().to_string()));
            out.push(("shadow_precompute_seconds", format!("{:.3}", self.seconds)));
        }
        out
    }

    /// Renders `lights` (through `method` at `alpha`) on `volume` with these shadows.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        self,
        lights: &ExplosionLights,
        method: Method,
        alpha: f32,
        volume: &Volume,
        medium: &Medium,
        camera: &Camera,
        march: &MarchSettings,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<(Image, RenderStats), crate::Error> {
        let backend = lights.backend(method, alpha)?;
        let marcher = Marcher::with_visibility(volume, medium, march, self.visibility)?;
        Ok(marcher.render(Some(&backend), camera, progress)?)
    }
}

/// Prints a level-by-level table of cube maps (the paper's Table 1 rows) to stderr.
pub fn say_cube_maps(table: &[LevelMaps], bytes: u64, seconds: f64) -> Result<(), crate::Error> {
    say!(
        "  shadows    cube maps: {:.1} MB for {} lights, traced in {seconds:.2} s",
        bytes as f64 / 1e6,
        table.iter().map(|l| l.lights).sum::<usize>()
    );
    for l in table {
        say!(
            "    level {:>2}: {:>7} lights, up to {:>4} cells per face side, {:>10} texels, depths to {:.3}, {:>9.2} MB, {:>6.1}M samples, {:.2} s",
            l.level,
            l.lights,
            l.cells,
            l.texels,
            l.reach,
            l.bytes as f64 / 1e6,
            l.samples as f64 / 1e6,
            l.seconds
        );
    }
    Ok(())
}

/// Checks that the output is an `.exr` path and that its folder exists, before any work.
pub fn check_out(out: &Path) -> Result<PathBuf, crate::Error> {
    if out.extension().and_then(|e| e.to_str()) != Some("exr") {
        return Err(format!(
            "--out {}: the output must be an .exr file (a .png is written beside it)",
            out.display()
        )
        .into());
    }
    let dir = match out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(format!(
            "--out {}: folder {} does not exist",
            out.display(),
            dir.display()
        )
        .into());
    }
    Ok(out.with_extension("png"))
}

/// What [`render_and_write`] did: the render's counts (none from the path tracer), its seconds,
/// and the PNG written beside the EXR.
pub struct Written {
    /// The marcher's counts.
    pub stats: Option<RenderStats>,
    /// Render time.
    pub seconds: f64,
    /// The PNG's path.
    pub png: PathBuf,
}

/// Runs `render` (given a progress callback over rows) under a progress bar of `rows` rows
/// labelled `label` (hidden when `quiet`), then writes `out` — an EXR whose header holds the
/// march settings, the `backend`'s name, `extra` and the render's counts and time — and the PNG
/// beside it.
#[allow(clippy::too_many_arguments)]
pub fn render_and_write(
    render: impl FnOnce(&(dyn Fn(usize) + Sync)) -> Result<(Image, Option<RenderStats>), crate::Error>,
    rows: usize,
    label: &str,
    quiet: bool,
    out: &Path,
    march: &MarchSettings,
    backend: &str,
    mut extra: Vec<(&'static str, String)>,
) -> Result<Written, crate::Error> {
    let bar = crate::progress::bar(rows as u64, label, quiet);
    let t = Instant::now();
    let (image, stats) = render(&|r| bar.inc(r as u64))?;
    let seconds = t.elapsed().as_secs_f64();
    bar.finish_and_clear();
    extra.push(("render_seconds", format!("{seconds:.3}")));
    if let Some(st) = &stats {
        extra.push(("shading_points", st.shading_points.to_string()));
        extra.push((
            "lights_per_shading_point",
            format!("{:.2}", st.lights_per_point()),
        ));
    }
    let png = write_exr_png(
        out,
        &image,
        &settings_attributes(march, backend, &extra),
        None,
    )?;
    Ok(Written {
        stats,
        seconds,
        png,
    })
}

/// The render settings as EXR header attributes (`lgh:` prefixed).
fn settings_attributes(
    march: &MarchSettings,
    backend: &str,
    extra: &[(&str, String)],
) -> Vec<(String, String)> {
    let march = [
        ("step_voxels", march.step_voxels.to_string()),
        ("shadow_step_voxels", march.shadow_step_voxels.to_string()),
        ("min_transmittance", march.min_transmittance.to_string()),
    ];
    header_attributes(backend, march.iter().chain(extra))
}

/// EXR header attributes: `lgh:backend`, then `settings` and `lgh:version`, every key with the
/// `lgh:` prefix.
pub fn header_attributes<'a>(
    backend: &str,
    settings: impl IntoIterator<Item = &'a (&'a str, String)>,
) -> Vec<(String, String)> {
    let mut attrs = vec![("lgh:backend".to_string(), backend.to_string())];
    attrs.extend(
        settings
            .into_iter()
            .map(|(k, v)| (format!("lgh:{k}"), v.clone())),
    );
    attrs.push((
        "lgh:version".to_string(),
        env!("CARGO_PKG_VERSION").to_string(),
    ));
    attrs
}

/// Writes the EXR (with `attrs` in its header, linear) and the PNG beside it, tone-mapped with
/// the filmic curve at `exposure` (`None`: automatic), which keeps a fire's highlights apart;
/// returns the PNG's path.
pub fn write_exr_png(
    out: &Path,
    image: &Image,
    attrs: &[(String, String)],
    exposure: Option<f32>,
) -> Result<PathBuf, crate::Error> {
    let png = out.with_extension("png");
    lgh_image::write_exr(out, image, attrs)?;
    let exposure = exposure.unwrap_or_else(|| lgh_image::auto_exposure(image));
    lgh_image::write_png_with(&png, image, exposure, lgh_image::ToneCurve::Filmic)?;
    Ok(png)
}
