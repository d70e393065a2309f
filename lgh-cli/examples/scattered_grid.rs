//! The multiple-scattering pass's depths ≥ 2 on the scattered-depth grid against the same
//! depths at every voxel (`lgh_volume::scattering`; docs/cycles.md, "The scattered-depth
//! grid's loss, depth by depth").
//!
//! ```text
//! cargo run --release -p lgh-cli --example scattered_grid -- SPACING [lgh explosion's flags]
//! ```
//!
//! runs the pass to depth 2 twice on the frame the flags give (`--vdb` and the medium's flags
//! as `lgh explosion` takes them; the camera only resolves the settings that depend on it):
//! with `--scatter-spacing 1` (every voxel) and `SPACING`. It prints each depth's power on
//! the grid over its power at every voxel — at the grid's vertices and between them — and the
//! share of depth 2's power (at every voxel) that is each voxel's own light,
//! `h³ σ_s ρ / 4π · I¹ g₀(τ)`, `g₀` a voxel light's fall-off at its own centre through its
//! own smoke (`lgh_core::NearField::Voxel`): the part of a voxel's fluence that follows its
//! own density, which a grid between voxels cannot follow.

use lgh_cli::explosion::prepare_in_memory;
use lgh_core::glam::Vec3;
use lgh_core::{NearField, ISOTROPIC_PHASE};
use lgh_volume::lighting_cache::ScatteredLight;
use lgh_volume::scattering::{scatter, Scattered};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let usage = "usage: scattered_grid SPACING [lgh explosion's flags]";
    let spacing: u8 = args.next().ok_or(usage)?.parse().map_err(|_| usage)?;
    if spacing < 2 {
        return Err(
            "SPACING must be at least 2: 1 is the every-voxel pass it is compared with".into(),
        );
    }
    let parts = prepare_in_memory(args).map_err(|e| format!("{e:?}"))?;
    let mut march = parts.march;
    march.scatter_depth = 2;
    march.scatter_stop = 0.0;
    march.scatter_skip = 0.0;
    march.lighting_cache.scattered_light = ScatteredLight::Merged;
    march.lighting_cache.scattered_spacing = spacing;
    // Refused before either pass runs: without the lighting cache there is no grid.
    if march
        .lighting_cache
        .scattered_depths(&parts.volume.density)
        .is_none()
    {
        return Err("no scattered-depth grid with these flags: is the lighting cache on?".into());
    }
    let run = |s: u8| -> Result<Scattered, Box<dyn std::error::Error>> {
        let mut m = march;
        m.lighting_cache.scattered_spacing = s;
        let t = std::time::Instant::now();
        let r = scatter(
            &parts.lights,
            parts.method,
            &parts.volume,
            &parts.medium,
            &m,
            &(),
        )?;
        let seconds = t.elapsed().as_secs_f64();
        println!("spacing {s}: the pass to depth 2 in {seconds:.1} s");
        Ok(r)
    };
    let (every, grid) = (run(1)?, run(spacing)?);
    debug_assert_eq!(grid.spacing(), spacing, "checked above");
    let lum = |v: Vec3| f64::from(lgh_core::luminance(v));
    let density = &parts.volume.density;
    let on_vertex = |v: usize| {
        let voxel = density.voxel(v);
        voxel.iter().all(|c| c % usize::from(spacing) == 0)
    };
    let voxels = every.lights().voxels();
    for depth in 1..=2 {
        let (a, b) = (every.intensities(depth), grid.intensities(depth));
        let (a, b) = (a.ok_or("no depth")?, b.ok_or("no depth")?);
        let mut sums = [[0.0f64; 2]; 2]; // [vertex?][every, grid]
        for ((&x, &y), &v) in a.iter().zip(b).zip(voxels) {
            let s = &mut sums[usize::from(on_vertex(v))];
            s[0] += lum(x);
            s[1] += lum(y);
        }
        let ratio = |s: [f64; 2]| s[1] / s[0];
        let all = [sums[0][0] + sums[1][0], sums[0][1] + sums[1][1]];
        println!(
            "depth {depth}: power on the grid / at every voxel {:.4} (vertices {:.4}, between {:.4})",
            ratio(all),
            ratio(sums[1]),
            ratio(sums[0])
        );
    }
    // Each voxel's own light in depth 2, as the pass shades it at the voxel's centre.
    let (first, second) = (every.intensities(1), every.intensities(2));
    let (first, second) = (first.ok_or("no depth")?, second.ok_or("no depth")?);
    let h = density.voxel_size;
    let (mut own, mut whole) = (0.0, 0.0);
    for ((&one, &two), &v) in first.iter().zip(second).zip(voxels) {
        let rho = density.data[v];
        if rho <= 0.0 {
            continue;
        }
        let tau = parts.medium.extinction(rho) * h;
        let g = NearField::Voxel.falloff_in(0, 0.0, h, tau);
        let scale = parts.medium.voxel_scattering(rho, h) * ISOTROPIC_PHASE;
        own += lum(one * (scale * g));
        whole += lum(two);
    }
    println!(
        "depth 2 at every voxel: {:.3} of its power is each voxel's own light",
        own / whole
    );
    Ok(())
}
