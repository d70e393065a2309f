//! `lgh compare A.exr B.exr`: how far an image is from a reference.

use std::path::PathBuf;

use serde_json::json;

/// Arguments of `lgh compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The image to judge (linear OpenEXR).
    pub image: PathBuf,
    /// The reference (linear OpenEXR of the same size).
    pub reference: PathBuf,
    /// Print JSON: {"rel_rmse", "max_abs", "mean_abs"} (luminance; rel_rmse is null when the
    /// reference is black), the same channel by channel, "rel_rmse_rgb" (each channel's RMSE
    /// over the reference's mean of it) and "mean_ratio_rgb" (each channel's mean over the
    /// reference's; null for a channel whose reference mean is not above 0), "mean_rgb" and
    /// "reference_mean_rgb" (the means, which may be negative), and each pixel's relative error against `--point-bound`:
    /// "max_point_error", "point_error_p99", "points_over_bound" (as `lgh bench gi` reports
    /// them; null when the reference is black).
    #[arg(long)]
    pub json: bool,
    /// The bound each pixel's relative error is held to (0.1 is 10% of its light; a pixel
    /// darker than 1% of the reference's mean is held to 1% of the mean): the fraction of
    /// the lit pixels over it is reported.
    #[arg(long, default_value_t = 0.1)]
    pub point_bound: f64,
    /// Where to write the false-colour difference PNG (default: IMAGE with `-diff.png`).
    #[arg(long)]
    pub diff: Option<PathBuf>,
}

/// Runs `lgh compare`.
pub fn run(args: &CompareArgs) -> Result<(), crate::Error> {
    // Checked before anything is read or written.
    if !(args.point_bound.is_finite() && args.point_bound > 0.0) {
        return Err(format!(
            "--point-bound {}: expected a number above 0",
            args.point_bound
        )
        .into());
    }
    let a = lgh_image::read_exr(&args.image)?;
    let r = lgh_image::read_exr(&args.reference)?;
    // A NaN or an infinity would make every figure below NaN: name the pixel instead.
    for (path, img) in [(&args.image, &a), (&args.reference, &r)] {
        if let Some(((x, y), v)) = lgh_image::first_non_finite(img) {
            return Err(format!(
                "{}: pixel ({x}, {y}) is {v}, not finite; no error can be measured on it",
                path.display()
            )
            .into());
        }
    }
    let stats = lgh_image::compare(&a, &r).ok_or_else(|| {
        format!(
            "{} is {}×{} but {} is {}×{}",
            args.image.display(),
            a.width,
            a.height,
            args.reference.display(),
            r.width,
            r.height
        )
    })?;
    let diff = args.diff.clone().unwrap_or_else(|| {
        let stem = args
            .image
            .file_stem()
            .map_or("image".into(), |s| s.to_string_lossy().into_owned());
        args.image.with_file_name(format!("{stem}-diff.png"))
    });
    // Full red at the largest error, so the map always uses its whole range.
    lgh_image::difference_png(&diff, &a, &r, stats.max_abs as f32)?;
    // Relative to a black reference, an error means nothing: JSON null, and said in words.
    let black = stats.mean_reference <= 0.0;
    let points = lgh_image::point_errors(&a, &r, args.point_bound).filter(|_| !black);
    // Same sizes, not empty: compare() said so.
    let rgb = lgh_image::compare_rgb(&a, &r).ok_or("the images differ in size")?;
    if args.json {
        let rel = if black { None } else { Some(stats.rel_rmse) };
        say!(
            "{}",
            json!({
                "rel_rmse": rel,
                "rel_rmse_rgb": rgb.rel_rmse,
                "mean_ratio_rgb": rgb.mean_ratio,
                "mean_rgb": rgb.mean,
                "reference_mean_rgb": rgb.mean_reference,
                "max_abs": stats.max_abs,
                "mean_abs": stats.mean_abs,
                "max_point_error": points.map(|p| p.max),
                "point_error_p99": points.map(|p| p.p99),
                "points_over_bound": points.map(|p| p.over),
                "point_bound": args.point_bound,
            })
        );
    } else if black {
        say!(
            "relative RMSE undefined: the reference {} is black (mean luminance 0); max abs {:.4e}, mean abs {:.4e} (luminance); difference: {}",
            args.reference.display(),
            stats.max_abs,
            stats.mean_abs,
            diff.display()
        );
    } else {
        let points = points.map_or(String::new(), |p| {
            format!(
                "; pixels over {}%: {:.2}% (largest {:.2}%)",
                100.0 * args.point_bound,
                100.0 * p.over,
                100.0 * p.max
            )
        });
        // Errors as they are, means as signed differences from the reference's.
        let percent = |v: Option<f64>, off: f64| {
            v.map_or("–".into(), |v| {
                if off == 0.0 {
                    format!("{:.2}", 100.0 * v)
                } else {
                    format!("{:+.2}", 100.0 * (v - off))
                }
            })
        };
        let channels = |v: [Option<f64>; 3], off: f64| v.map(|c| percent(c, off)).join(", ");
        say!(
            "relative RMSE {:.4}%, max abs {:.4e}, mean abs {:.4e} (luminance; mean of the reference {:.4e}){points}; red, green, blue: relative RMSE {}%, mean {}% against the reference's; difference: {}",
            100.0 * stats.rel_rmse,
            stats.max_abs,
            stats.mean_abs,
            stats.mean_reference,
            channels(rgb.rel_rmse, 0.0),
            channels(rgb.mean_ratio, 1.0),
            diff.display()
        );
    }
    Ok(())
}
