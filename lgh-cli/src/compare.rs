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
    /// reference is black).
    #[arg(long)]
    pub json: bool,
    /// Where to write the false-colour difference PNG (default: IMAGE with `-diff.png`).
    #[arg(long)]
    pub diff: Option<PathBuf>,
}

/// Runs `lgh compare`.
pub fn run(args: &CompareArgs) -> Result<(), crate::Error> {
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
    if args.json {
        let rel = if black { None } else { Some(stats.rel_rmse) };
        say!(
            "{}",
            json!({"rel_rmse": rel, "max_abs": stats.max_abs, "mean_abs": stats.mean_abs})
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
        say!(
            "relative RMSE {:.4}%, max abs {:.4e}, mean abs {:.4e} (luminance; mean of the reference {:.4e}); difference: {}",
            100.0 * stats.rel_rmse,
            stats.max_abs,
            stats.mean_abs,
            stats.mean_reference,
            diff.display()
        );
    }
    Ok(())
}
