//! What every render command shares: options for the ray marcher, the progress bar over rows,
//! and the outputs (a linear EXR with the settings in its header, a tone-mapped PNG beside it).

use std::path::{Path, PathBuf};
use std::time::Instant;

use lgh_image::Image;
use lgh_volume::render::{MarchSettings, RenderStats, Shadows};

/// How lights are shadowed (`--shadows`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ShadowArg {
    /// Transmittance ray-marched to every light (exact shadows).
    Raymarch,
    /// No shadows.
    None,
}

impl ShadowArg {
    /// The renderer's setting.
    pub fn shadows(self) -> Shadows {
        match self {
            ShadowArg::Raymarch => Shadows::RayMarch,
            ShadowArg::None => Shadows::None,
        }
    }
}

/// The ray marcher's options, shared by the render commands.
#[derive(Debug, Clone, clap::Args)]
pub struct MarchArgs {
    /// Shadows of the lights (backends lgh and brute).
    #[arg(long, value_enum, default_value_t = ShadowArg::Raymarch)]
    pub shadows: ShadowArg,
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
    pub fn settings(&self, default_shadow_step: f32) -> Result<MarchSettings, String> {
        let settings = MarchSettings {
            shadows: self.shadows.shadows(),
            step_voxels: self.step,
            shadow_step_voxels: self.shadow_step.unwrap_or(default_shadow_step),
            ..Default::default()
        };
        settings.check()?;
        Ok(settings)
    }
}

/// Checks that the output is an `.exr` path and that its folder exists, before any work.
pub fn check_out(out: &Path) -> Result<PathBuf, String> {
    if out.extension().and_then(|e| e.to_str()) != Some("exr") {
        return Err(format!(
            "--out {}: the output must be an .exr file (a .png is written beside it)",
            out.display()
        ));
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
        ));
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
    render: impl FnOnce(&(dyn Fn(usize) + Sync)) -> Result<(Image, Option<RenderStats>), String>,
    rows: usize,
    label: &str,
    quiet: bool,
    out: &Path,
    march: &MarchSettings,
    backend: &str,
    mut extra: Vec<(&'static str, String)>,
) -> Result<Written, String> {
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
        ("shadows", format!("{:?}", march.shadows).to_lowercase()),
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

/// Writes the EXR (with `attrs` in its header) and the PNG beside it, tone-mapped at `exposure`
/// (`None`: automatic); returns the PNG's path.
pub fn write_exr_png(
    out: &Path,
    image: &Image,
    attrs: &[(String, String)],
    exposure: Option<f32>,
) -> Result<PathBuf, String> {
    let png = out.with_extension("png");
    lgh_image::write_exr(out, image, attrs).map_err(|e| e.to_string())?;
    let exposure = exposure.unwrap_or_else(|| lgh_image::auto_exposure(image));
    lgh_image::write_png(&png, image, exposure).map_err(|e| e.to_string())?;
    Ok(png)
}
