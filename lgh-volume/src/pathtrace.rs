//! The physical reference: an unbiased volumetric path tracer on the ray marcher's grids
//! (ARCHITECTURE.md, "References" (b)).
//!
//! It solves exactly the model of [`crate::render::Marcher::march`],
//! `dL/ds = −σ_t L + j + σ_s/(4π) ∫ L dω`, with `σ_t = (κ_a + κ_s) ρ(x)` and `σ_s = κ_s ρ(x)`
//! from the trilinearly sampled density, `j(x) = volume.emission(medium, x)` (the emission of the
//! trilinearly sampled temperature, times the flame grid if there is one), the medium confined to
//! the density grid's box, and a uniform environment radiance outside it. It has no light model: light reaches a scattering point only along paths
//! that wander through hot gas, so it converges to the physical answer that the marcher's point
//! lights (`I0 = j h³` at voxel centres) approximate. Camera rays go through pixel centres, as the
//! marcher's do, so the two images are comparable pixel by pixel.
//!
//! # Estimator
//!
//! - **Free flights: delta tracking against a piecewise-constant majorant.** [`Majorants`] stores
//!   one majorant `σ̄` per block of [`BLOCK_VOXELS`]³ density voxels, and a 3-D DDA walks the blocks
//!   a ray crosses. Tentative collisions form a Poisson process of rate `σ̄` along the ray (the
//!   residual optical depth carries across block faces); blocks with `σ̄ = 0` are crossed for free.
//!   A tentative collision at `x` is real with probability `σ_t(x)/σ̄`, else null. This is exact
//!   (not an approximation of the transmittance) as long as `σ_t ≤ σ̄`, which the construction
//!   guarantees (see [`Majorants`]).
//! - **Emission: a collision estimator at every tentative collision.** At each tentative collision
//!   (null or real) in a block that can emit, `throughput · j(x) / σ̄` is added. By Campbell's
//!   theorem the expected sum over a Poisson process of rate `σ̄(s)` of `f(s)/σ̄(s)` is `∫ f ds`,
//!   and a tentative collision at `s` is reached (no real collision before it) with probability
//!   `T(s)`, so the expectation is `∫ T(s) j(s) ds` — also where `σ_t = 0`. That needs `σ̄ > 0`
//!   wherever `j ≠ 0`, which matters because `j` can be non-zero where the density is zero (real
//!   Blender caches store heat outside the smoke). We therefore raise the majorant of every block
//!   that can emit to at least [`EMISSION_RATE`]`/h`: on average at least that many tentative
//!   collisions per voxel length, so along a length `ℓ` of uniform emission the estimate's variance
//!   is `j² ℓ / σ̄ ≤ j² ℓ h / EMISSION_RATE`, like one random sample per voxel, and a thin but hot
//!   block cannot produce rare huge `j/σ̄` spikes. Blocks that cannot emit keep the plain extinction
//!   bound (zero where empty).
//! - **Real collisions.** The emission at the collision point has already been counted. If the
//!   path has used its [`PathSettings::max_scatter`] scattering events, or the medium does not
//!   scatter there, the path ends (absorption). Otherwise it scatters into an isotropic direction
//!   and its throughput is multiplied by the albedo `σ_s/σ_t` (all coefficients are grey, so the
//!   throughput is a scalar). Below a throughput of 0.1 a path survives with probability
//!   `throughput / 0.1` and continues with throughput 0.1 (Russian roulette: unbiased, and it ends
//!   long paths of low weight). With albedo 1 the throughput stays exactly 1.
//! - **Escape.** A path that leaves the box adds `throughput · environment`.
//! - **Determinism.** Each pixel's random numbers come from a hash of (seed, pixel index), never
//!   from thread state, and a pixel's samples are summed in order: the image is bit-identical
//!   whatever the thread count.
//!
//! ```
//! use lgh_volume::{procedural, Medium};
//! use lgh_volume::pathtrace::{render, PathSettings};
//! use lgh_volume::render::{Camera, Framing};
//! use lgh_volume::lgh_core::glam::Vec3;
//!
//! let volume = procedural(32, 0.5)?;
//! let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0)?;
//! let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 8, 6)?;
//! let settings = PathSettings { spp: 2, ..Default::default() };
//! let image = render(&volume, &medium, &camera, &settings, &|_rows| {})?;
//! assert_eq!(image.pixels.len(), 48);
//! # Ok::<(), lgh_volume::RenderError>(())
//! ```

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_image::Image;
use rayon::prelude::*;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::grid::DenseGrid;
use crate::medium::{Medium, Volume};
use crate::render::{image, shade_pixels};

/// Path-tracing parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSettings {
    /// Paths per pixel (≥ 1; [`render_with_variance`] needs ≥ 2).
    pub spp: u32,
    /// Scattering events allowed per path: 0 = emission and absorption only (what the marcher
    /// computes without lights), 1 = single scattering (the marcher with lights), and so on.
    pub max_scatter: u32,
    /// Radiance arriving from outside the density grid's box, the same from every direction.
    pub environment: Vec3,
    /// Seed: each pixel's random numbers are a hash of it and the pixel's index.
    pub seed: u64,
}

impl Default for PathSettings {
    fn default() -> Self {
        PathSettings {
            spp: 16,
            max_scatter: 8,
            environment: Vec3::ZERO,
            seed: 0,
        }
    }
}

impl PathSettings {
    /// Checks the settings: at least one path per pixel and a finite, non-negative environment.
    pub fn validate(&self) -> Result<(), RenderError> {
        if self.spp == 0 {
            return Err(RenderError::InvalidCount {
                name: "path tracer: samples per pixel",
                value: 0,
                rule: "must be at least 1",
            });
        }
        if !(self.environment.is_finite() && self.environment.min_element() >= 0.0) {
            return Err(RenderError::InvalidEnvironment {
                radiance: self.environment,
            });
        }
        Ok(())
    }
}

/// Edge of a majorant block, in density voxels.
pub const BLOCK_VOXELS: usize = 8;

/// Least tentative-collision rate in blocks that can emit, per voxel length: their majorant is at
/// least `EMISSION_RATE / h` (see the module documentation).
pub const EMISSION_RATE: f32 = 1.0;

/// Relative slack on a block's maximum that covers the rounding of the trilinear sum in f32
/// (a few times 2⁻²⁴ relative; see [`Majorants`]).
const ROUNDING_SLACK: f32 = 1e-5;

/// Majorants above this many tentative collisions per voxel length (an optical depth of 10⁴ per
/// voxel) are refused: a block that dense around thin smoke would make every ray crossing it
/// take tens of thousands of null collisions.
const MAX_COLLISIONS_PER_VOXEL: f32 = 1e4;

/// Throughput below which Russian roulette starts.
const ROULETTE_THRESHOLD: f32 = 0.1;

/// A piecewise-constant majorant of the extinction over blocks of [`BLOCK_VOXELS`]³ density
/// voxels, for delta tracking.
///
/// **Why it is a bound.** `DenseGrid::sample(p)` clamps `t = (p − origin)/h` per axis to
/// `[0, n − 1]` (the half voxel at each face takes the outermost value) and blends voxels
/// `⌊t⌋` and `⌊t⌋ + 1` (clamped to `n − 1`) with non-negative weights summing to one; outside the
/// box it is 0. So over a block whose world box is `[a, b]` per axis, only voxels
/// `⌊t(a)⌋ … ⌊t(b)⌋ + 1` (clamped) can enter — we take one more on each side against the rounding
/// of `a`, `b` and of the positions the DDA produces — and a convex combination never exceeds its
/// largest value `M`. In f32 the blend is rounded: as three levels of linear interpolations
/// `a + (b − a) w` (w exact), each adds at most ≈ 5·2⁻²⁴ times the largest magnitude of its
/// inputs, so the computed sample exceeds `max(M, 0)` by at most ≈ 15·2⁻²⁴ ≈ 9·10⁻⁷ times the
/// largest `|value|` `A` (as a sum of eight weighted terms, ≤ 13 roundings: similar); we store
/// `σ̄ = (κ_a + κ_s) · (max(M, 0) + 10⁻⁵ A)`, computed with the same f32 expression as
/// [`Medium::extinction`] (monotone in ρ, as its rounding is). The sample is 0 outside the box and
/// 0 ≤ σ̄. The tests check the bound at random points and on the faces. Negative densities (invalid
/// input) are treated as no extinction.
///
/// A block can emit if the medium emits at its temperature bound (the same construction on the
/// temperature grid, whatever that grid's geometry); its majorant is then raised to at least
/// [`EMISSION_RATE`]` / h`. This relies on emission being zero below a threshold temperature and
/// non-zero above it, as [`Medium::emission_at`] is (`T > T_min`); a flame grid only multiplies
/// it, so it cannot make a block emit.
///
/// A `Majorants` belongs to the volume and medium it was built from; with others the tracer stays
/// memory-safe and terminates but is no longer unbiased.
#[derive(Clone, Debug, PartialEq)]
pub struct Majorants {
    lo: Vec3,
    hi: Vec3,
    block: f32,
    dims: [usize; 3],
    sigma: Vec<f32>,
    emissive: Vec<bool>,
}

/// Checks that a grid can be sampled: non-empty, consistent, finite geometry.
fn check_grid(grid: &'static str, g: &DenseGrid) -> Result<(), RenderError> {
    let count = g.dims.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
    if g.dims.contains(&0) || count != Some(g.data.len()) {
        return Err(RenderError::GridShape {
            grid,
            dims: g.dims,
            values: g.data.len(),
        });
    }
    let (lo, hi) = g.bounds();
    if !(g.voxel_size.is_finite() && g.voxel_size > 0.0 && lo.is_finite() && hi.is_finite()) {
        return Err(RenderError::GridGeometry {
            grid,
            voxel_size: g.voxel_size,
            origin: g.origin,
        });
    }
    Ok(())
}

/// An upper bound on `g.sample(p)` for `p` in the world box `lo..=hi` (see [`Majorants`]).
fn sample_bound(g: &DenseGrid, lo: Vec3, hi: Vec3) -> f32 {
    let (glo, ghi) = g.bounds();
    let margin = 0.5 * g.voxel_size;
    if (0..3).any(|a| hi[a] < glo[a] - margin || lo[a] > ghi[a] + margin) {
        return 0.0; // the box misses the grid: its samples there are all 0
    }
    let range = |a: usize| {
        let n = g.dims[a];
        let index = |x: f32| {
            ((x - g.origin[a]) / g.voxel_size)
                .floor()
                .clamp(0.0, (n - 1) as f32) as usize
        };
        (
            index(lo[a]).saturating_sub(1),
            (index(hi[a]) + 2).min(n - 1),
        )
    };
    let (rx, ry, rz) = (range(0), range(1), range(2));
    let (mut most, mut largest) = (0.0f32, 0.0f32);
    for k in rz.0..=rz.1 {
        for j in ry.0..=ry.1 {
            let row = g.index(rx.0, j, k);
            for &v in &g.data[row..=row + (rx.1 - rx.0)] {
                // `max` skips NaN, which `sample` turns into null collisions anyway.
                most = most.max(v);
                largest = largest.max(v.abs());
            }
        }
    }
    most + ROUNDING_SLACK * largest
}

impl Majorants {
    /// Builds the block majorants of `volume` in `medium`. Errors on grids that cannot be
    /// sampled (empty, inconsistent, non-finite geometry) and on infinite or absurdly large
    /// extinction (more than 10⁴ tentative collisions per voxel), which would never finish.
    pub fn new(volume: &Volume, medium: &Medium) -> Result<Self, RenderError> {
        check_grid("density", &volume.density)?;
        check_grid("temperature", &volume.temperature)?;
        let g = &volume.density;
        let (lo, hi) = g.bounds();
        let h = g.voxel_size;
        let dims = g.dims.map(|n| n.div_ceil(BLOCK_VOXELS));
        let count = dims[0] * dims[1] * dims[2];
        let emission_floor = EMISSION_RATE / h;
        let blocks: Result<Vec<(f32, bool)>, RenderError> = (0..count)
            .into_par_iter()
            .map(|b| {
                let c = crate::grid::unflatten(b, dims);
                let v0 = c.map(|x| (x * BLOCK_VOXELS) as f32);
                let v1 = [0, 1, 2].map(|a| ((c[a] + 1) * BLOCK_VOXELS).min(g.dims[a]) as f32);
                let box_lo = lo + Vec3::from(v0) * h;
                let box_hi = lo + Vec3::from(v1) * h;
                let mut sigma = medium.extinction(sample_bound(g, box_lo, box_hi));
                let hottest = sample_bound(&volume.temperature, box_lo, box_hi);
                let emissive = volume.value_emits(medium, hottest);
                if emissive {
                    sigma = sigma.max(emission_floor);
                }
                if !(sigma.is_finite() && sigma * h <= MAX_COLLISIONS_PER_VOXEL) {
                    return Err(RenderError::Majorant {
                        sigma,
                        voxel_size: h,
                    });
                }
                Ok((sigma, emissive))
            })
            .collect();
        let (sigma, emissive) = blocks?.into_iter().unzip();
        Ok(Majorants {
            lo,
            hi,
            block: BLOCK_VOXELS as f32 * h,
            dims,
            sigma,
            emissive,
        })
    }

    /// The majorant `σ̄` (per unit length) of the block containing `p`; 0 outside the density
    /// grid's box. Every extinction sampled in that block is at most this.
    #[must_use]
    pub fn at(&self, p: Vec3) -> f32 {
        match self.block_of(p) {
            Some(i) => self.sigma[i],
            None => 0.0,
        }
    }

    /// Whether the block containing `p` can emit (has its majorant raised for emission).
    #[must_use]
    pub fn emissive_at(&self, p: Vec3) -> bool {
        self.block_of(p).is_some_and(|i| self.emissive[i])
    }

    /// Number of blocks per axis.
    #[must_use]
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    fn block_of(&self, p: Vec3) -> Option<usize> {
        if !(p.cmpge(self.lo).all() && p.cmplt(self.hi).all()) {
            return None;
        }
        let c = ((p - self.lo) / self.block).floor();
        let c = [0, 1, 2].map(|a| (c[a] as usize).min(self.dims[a] - 1));
        Some((c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0])
    }

    /// One free flight from `o` along the unit vector `d` (the ray `(o, d)`) by delta tracking:
    /// adds `throughput · j / σ̄` at every tentative collision in emitting blocks to `acc`, and
    /// returns the first real collision (position, density), or `None` if the path leaves the
    /// box.
    fn fly(
        &self,
        volume: &Volume,
        medium: &Medium,
        (o, d): (Vec3, Vec3),
        throughput: f32,
        acc: &mut Vec3,
        rng: &mut SplitMix64,
    ) -> Option<(Vec3, f32)> {
        let (t0, t1) = crate::grid::slab(o, d, self.lo, self.hi)?;
        // 3-D DDA over the blocks (Amanatides & Woo). Distances are f64, measured from the entry
        // point: in f32 a far camera's `t + dt` could round back to `t` in a dense block and
        // stall the walk at one point.
        let entry = o + d * t0;
        let (t1, block) = (f64::from(t1 - t0), f64::from(self.block));
        let start = (entry - self.lo) / self.block;
        let mut cell = [0i64; 3];
        let mut next = [f64::INFINITY; 3];
        let mut delta = [f64::INFINITY; 3];
        let mut step = [0i64; 3];
        for a in 0..3 {
            let n = self.dims[a] as i64;
            let c = (start[a].floor() as i64).clamp(0, n - 1);
            cell[a] = c;
            let (lo, e, da) = (f64::from(self.lo[a]), f64::from(entry[a]), f64::from(d[a]));
            if d[a] > 0.0 {
                step[a] = 1;
                next[a] = (lo + (c + 1) as f64 * block - e) / da;
                delta[a] = block / da;
            } else if d[a] < 0.0 {
                step[a] = -1;
                next[a] = (lo + c as f64 * block - e) / da;
                delta[a] = -block / da;
            }
        }
        let mut t = 0.0f64;
        let mut tau = exponential(rng);
        loop {
            let index = ((cell[2] as usize * self.dims[1]) + cell[1] as usize) * self.dims[0]
                + cell[0] as usize;
            let exit = next[0].min(next[1]).min(next[2]).min(t1);
            let sigma = self.sigma[index];
            if sigma > 0.0 {
                let sigma64 = f64::from(sigma);
                loop {
                    let dt = tau / sigma64;
                    if t + dt >= exit {
                        tau -= sigma64 * (exit - t).max(0.0);
                        break;
                    }
                    t += dt;
                    let x = entry + d * t as f32;
                    let rho = volume.density.sample(x);
                    if self.emissive[index] {
                        *acc += volume.emission(medium, x) * (throughput / sigma);
                    }
                    if rng.next_f32() * sigma < medium.extinction(rho) {
                        return Some((x, rho));
                    }
                    tau = exponential(rng);
                }
            }
            t = t.max(exit);
            if exit >= t1 {
                return None;
            }
            let a = if next[0] <= next[1] && next[0] <= next[2] {
                0
            } else if next[1] <= next[2] {
                1
            } else {
                2
            };
            cell[a] += step[a];
            if cell[a] < 0 || cell[a] >= self.dims[a] as i64 {
                return None;
            }
            next[a] += delta[a];
        }
    }
}

/// A unit-mean exponential variate, from 53 random bits (finite; the tail beyond 36.7 that it
/// cannot reach has probability 10⁻¹⁶).
fn exponential(rng: &mut SplitMix64) -> f64 {
    let u = rng.next_f64();
    -(1.0 - u).ln()
}

/// A uniformly distributed unit vector.
fn isotropic(rng: &mut SplitMix64) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * rng.next_f32();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The random-number generator of stream `index` (a pixel) under `seed`: a hash of both, so it
/// never depends on which thread runs the pixel.
#[must_use]
pub fn pixel_rng(seed: u64, index: u64) -> SplitMix64 {
    SplitMix64(SplitMix64::mix(
        SplitMix64::mix(seed) ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15),
    ))
}

/// One path-traced estimate of the radiance arriving at `origin` along `-dir` (the ray
/// `origin + t·dir`). Its expectation is the exact solution of the transfer equation with at most
/// `settings.max_scatter` scattering events. `majorants` must come from the same `volume` and
/// `medium`. A zero or non-finite `origin` or `dir` gives zero.
pub fn radiance(
    volume: &Volume,
    medium: &Medium,
    majorants: &Majorants,
    origin: Vec3,
    dir: Vec3,
    settings: &PathSettings,
    rng: &mut SplitMix64,
) -> Vec3 {
    let mut d = dir.normalize_or_zero();
    if d == Vec3::ZERO || !origin.is_finite() {
        return Vec3::ZERO;
    }
    let mut o = origin;
    let mut sum = Vec3::ZERO;
    let mut throughput = 1.0f32;
    let mut scatters = 0u32;
    loop {
        let Some((x, rho)) = majorants.fly(volume, medium, (o, d), throughput, &mut sum, rng)
        else {
            return sum + settings.environment * throughput;
        };
        let sigma_t = medium.extinction(rho);
        let sigma_s = medium.scattering * rho;
        if scatters >= settings.max_scatter || !(sigma_s > 0.0 && sigma_t > 0.0) {
            return sum;
        }
        throughput *= (sigma_s / sigma_t).min(1.0);
        if throughput < ROULETTE_THRESHOLD {
            let survive = throughput / ROULETTE_THRESHOLD;
            if rng.next_f32() >= survive {
                return sum;
            }
            throughput = ROULETTE_THRESHOLD;
        }
        scatters += 1;
        o = x;
        d = isotropic(rng);
    }
}

/// Renders the mean of `settings.spp` paths through each pixel centre, rows in parallel;
/// bit-identical for any thread count. `progress(rows)` is called as rows finish.
pub fn render(
    volume: &Volume,
    medium: &Medium,
    camera: &Camera,
    settings: &PathSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Image, RenderError> {
    let pixels = trace_pixels(volume, medium, camera, settings, None, progress)?;
    Ok(image(camera, pixels.into_iter().map(|(mean, _)| mean)))
}

/// Like [`render`], and also the per-pixel, per-channel variance of the mean (sample variance of
/// the paths divided by `spp`), for noise bounds: the standard error is its square root. Needs
/// `spp ≥ 2`.
pub fn render_with_variance(
    volume: &Volume,
    medium: &Medium,
    camera: &Camera,
    settings: &PathSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<(Image, Image), RenderError> {
    if settings.spp < 2 {
        return Err(RenderError::InvalidCount {
            name: "path tracer: samples per pixel",
            value: settings.spp as usize,
            rule: "must be at least 2 for a variance",
        });
    }
    let pixels = trace_pixels(volume, medium, camera, settings, None, progress)?;
    let mean = image(camera, pixels.iter().map(|p| p.0));
    let variance = image(camera, pixels.iter().map(|p| p.1));
    Ok((mean, variance))
}

/// Mean and variance of the mean of each pixel of `pixels` (`None`: the whole image), through
/// the crate's one pixel loop.
fn trace_pixels(
    volume: &Volume,
    medium: &Medium,
    camera: &Camera,
    settings: &PathSettings,
    pixels: Option<&[[usize; 2]]>,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<(Vec3, Vec3)>, RenderError> {
    settings.validate()?;
    let majorants = Majorants::new(volume, medium)?;
    shade_pixels(
        camera,
        pixels,
        || (),
        |_, x, y| Ok(pixel(volume, medium, &majorants, camera, settings, x, y)),
        progress,
    )
}

/// Mean and variance of the mean of pixel `(x, y)`'s paths.
fn pixel(
    volume: &Volume,
    medium: &Medium,
    majorants: &Majorants,
    camera: &Camera,
    settings: &PathSettings,
    x: usize,
    y: usize,
) -> (Vec3, Vec3) {
    let (eye, dir) = camera.ray(x, y);
    let mut rng = pixel_rng(settings.seed, (y * camera.width() + x) as u64);
    let mut stats = Welford::default();
    for _ in 0..settings.spp {
        stats.add(radiance(
            volume, medium, majorants, eye, dir, settings, &mut rng,
        ));
    }
    stats.mean_and_variance_of_mean()
}

/// The pixels `(x, y)` of `pixels` only, exactly as [`render`] computes them (same random
/// numbers), in parallel: for references and benchmarks on pixel subsets.
pub fn render_pixels(
    volume: &Volume,
    medium: &Medium,
    camera: &Camera,
    settings: &PathSettings,
    pixels: &[[usize; 2]],
) -> Result<Vec<Vec3>, RenderError> {
    let out = trace_pixels(volume, medium, camera, settings, Some(pixels), &|_| {})?;
    Ok(out.into_iter().map(|(mean, _)| mean).collect())
}

/// Running mean and sum of squared deviations per channel (Welford), in f64.
#[derive(Clone, Copy, Debug, Default)]
struct Welford {
    n: u64,
    mean: [f64; 3],
    m2: [f64; 3],
}

impl Welford {
    /// Adds another run's samples (Chan, Golub & LeVeque's pairwise update).
    #[cfg(test)]
    fn merge(&mut self, o: &Welford) {
        if o.n == 0 {
            return;
        }
        let (n, m) = (self.n as f64, o.n as f64);
        let total = n + m;
        for c in 0..3 {
            let delta = o.mean[c] - self.mean[c];
            self.mean[c] += delta * m / total;
            self.m2[c] += o.m2[c] + delta * delta * n * m / total;
        }
        self.n += o.n;
    }

    fn add(&mut self, v: Vec3) {
        self.n += 1;
        let n = self.n as f64;
        for c in 0..3 {
            let x = f64::from(v[c]);
            let delta = x - self.mean[c];
            self.mean[c] += delta / n;
            self.m2[c] += delta * (x - self.mean[c]);
        }
    }

    /// The mean, and the variance of the mean (0 with fewer than two samples).
    fn mean_and_variance_of_mean(&self) -> (Vec3, Vec3) {
        let n = self.n as f64;
        let var = |c: usize| {
            if self.n < 2 {
                0.0
            } else {
                (self.m2[c] / (n - 1.0) / n) as f32
            }
        };
        (
            Vec3::new(
                self.mean[0] as f32,
                self.mean[1] as f32,
                self.mean[2] as f32,
            ),
            Vec3::new(var(0), var(1), var(2)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lighting::Lights;
    use crate::lights::ExplosionLights;
    use crate::procedural::procedural;
    use crate::render::{Framing, MarchSettings, Marcher, RenderStats, Shadows};
    use lgh_core::BruteForce;

    /// Mean and standard error (per channel) of `n` paths along one ray, in parallel chunks with
    /// their own streams, combined in order (deterministic).
    fn estimate(
        volume: &Volume,
        medium: &Medium,
        majorants: &Majorants,
        origin: Vec3,
        dir: Vec3,
        settings: &PathSettings,
        n: usize,
    ) -> (Vec3, Vec3) {
        const CHUNK: usize = 4096;
        let parts: Vec<Welford> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut rng = pixel_rng(settings.seed, c as u64);
                let mut w = Welford::default();
                for _ in 0..CHUNK.min(n - c * CHUNK) {
                    w.add(radiance(
                        volume, medium, majorants, origin, dir, settings, &mut rng,
                    ));
                }
                w
            })
            .collect();
        let mut all = Welford::default();
        parts.iter().for_each(|w| all.merge(w));
        let (mean, variance) = all.mean_and_variance_of_mean();
        (mean, variance.map(f32::sqrt))
    }

    #[test]
    fn merged_runs_give_the_mean_and_variance_of_all_samples() {
        let v = |i: usize| Vec3::new(i as f32, (i * i % 7) as f32, 0.5);
        let (mut all, mut a, mut b) = (Welford::default(), Welford::default(), Welford::default());
        for i in 0..30 {
            all.add(v(i));
            if i < 11 {
                a.add(v(i))
            } else {
                b.add(v(i))
            }
        }
        a.merge(&b);
        let ((m1, v1), (m2, v2)) = (
            all.mean_and_variance_of_mean(),
            a.mean_and_variance_of_mean(),
        );
        assert!((m1 - m2).abs().max_element() < 1e-5 && (v1 - v2).abs().max_element() < 1e-5);
    }

    /// A cube of `n³` voxels of edge `h` centred on the origin, uniform density and temperature.
    fn uniform_cube(n: usize, h: f32, rho: f32, kelvin: f32) -> Volume {
        let origin = Vec3::splat(-0.5 * n as f32 * h + 0.5 * h);
        let mut density = DenseGrid::zeros([n; 3], h, origin);
        density.data.fill(rho);
        let mut temperature = density.clone();
        temperature.data.fill(kelvin);
        Volume::new(density, temperature)
    }

    /// Asserts `|got − want| ≤ 4 se` per channel, and that the test has power: `se` is below
    /// `max_rel_se` of `want` (else a loose estimate could pass anything).
    fn assert_within_4se(got: Vec3, se: Vec3, want: Vec3, max_rel_se: f32, what: &str) {
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() <= 4.0 * se[c],
                "{what}: channel {c}: {} vs {} (4 se = {})",
                got[c],
                want[c],
                4.0 * se[c]
            );
            assert!(
                se[c] <= max_rel_se * want[c],
                "{what}: channel {c}: standard error {} too large for {}",
                se[c],
                want[c]
            );
        }
    }

    // Tolerances below are 4 standard errors of the estimate, computed from the paths' own sample
    // variance: an unbiased estimator lands outside with probability ≈ 6·10⁻⁵ per comparison
    // (normal tail; the means are over ≥ 10⁴ paths). The seeds are fixed, so a pass is repeatable.

    #[test]
    fn emitting_absorbing_slab_matches_the_closed_form() {
        // L = j/σ_a (1 − e^{−σ_a ℓ}) through a homogeneous 2-unit cube, along an axis (ℓ = 2) and
        // along an oblique chord that crosses many majorant blocks (ℓ = 2 |d| / |d_z|).
        let v = uniform_cube(32, 1.0 / 16.0, 1.0, 2000.0);
        let rays = [
            (Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0)),
            (Vec3::new(0.3, -0.2, 5.0), Vec3::new(0.1, 0.05, -1.0)),
        ];
        for sigma in [0.1f32, 1.0, 4.0] {
            let m = Medium::new(sigma, 0.0, 1e-3, 500.0).unwrap();
            let maj = Majorants::new(&v, &m).unwrap();
            let j = m.emission_at(2000.0);
            let s = PathSettings::default();
            for (o, d) in rays {
                let chord = 2.0 * d.length() / d.z.abs();
                let want = j / sigma * (1.0 - (-sigma * chord).exp());
                let (got, se) = estimate(&v, &m, &maj, o, d.normalize(), &s, 20_000);
                assert_within_4se(got, se, want, 0.01, &format!("σ {sigma}, ray {d}"));
            }
        }
    }

    #[test]
    fn emission_where_the_density_is_zero_is_collected() {
        // No smoke, uniform heat: L = j ℓ (Blender caches have heat outside the smoke).
        let mut v = uniform_cube(32, 1.0 / 16.0, 0.0, 2000.0);
        let m = Medium::new(1.0, 1.0, 1e-3, 500.0).unwrap();
        let maj = Majorants::new(&v, &m).unwrap();
        let j = m.emission_at(2000.0);
        let s = PathSettings::default();
        let (got, se) = estimate(&v, &m, &maj, Vec3::new(0.1, 0.2, 5.0), -Vec3::Z, &s, 20_000);
        assert_within_4se(got, se, j * 2.0, 0.01, "no density");
        // A temperature grid of its own geometry, smaller than the density box: the emission is
        // exactly j over its own box (sample is uniform up to its faces), here a chord of 0.5.
        v.temperature = DenseGrid::zeros([4, 4, 4], 0.125, Vec3::splat(-0.1875));
        v.temperature.data.fill(2000.0);
        let maj = Majorants::new(&v, &m).unwrap();
        assert!(!maj.emissive_at(Vec3::splat(0.9)), "far from the heat");
        let (got, se) = estimate(&v, &m, &maj, Vec3::new(0.1, 0.2, 5.0), -Vec3::Z, &s, 20_000);
        assert_within_4se(got, se, j * 0.5, 0.02, "small temperature grid");
    }

    #[test]
    fn majorants_bound_the_extinction_and_cover_the_emission() {
        let v = procedural(32, 0.5).unwrap();
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let maj = Majorants::new(&v, &m).unwrap();
        let (lo, hi) = v.density.bounds();
        let h = v.density.voxel_size;
        let mut rng = SplitMix64(7);
        let mut points: Vec<Vec3> = (0..200_000).map(|_| rng.next_in(lo, hi)).collect();
        // The faces, where `sample` clamps: points a hair inside each face.
        for _ in 0..20_000 {
            let mut p = rng.next_in(lo, hi);
            let a = (rng.next_u64() % 3) as usize;
            p[a] = if rng.next_f32() < 0.5 {
                lo[a]
            } else {
                hi[a] - 1e-6
            };
            points.push(p);
        }
        for p in points {
            let sigma_t = m.extinction(v.density.sample(p));
            assert!(sigma_t <= maj.at(p), "{p}: σ_t {sigma_t} > σ̄ {}", maj.at(p));
            if v.emission(&m, p) != Vec3::ZERO {
                assert!(maj.emissive_at(p) && maj.at(p) >= EMISSION_RATE / h, "{p}");
            }
        }
        // The corners of the procedural cube are empty: some blocks are crossed for free.
        assert_eq!(maj.at(lo), 0.0);
        assert_eq!(maj.dims(), [4, 4, 4]);
        // Nonsense is refused, not traced forever.
        let mut bad = v.clone();
        bad.density.data[5] = f32::INFINITY;
        assert!(Majorants::new(&bad, &m).is_err());
        bad.density.data.pop();
        assert!(Majorants::new(&bad, &m).is_err());
    }

    /// Transmittance `e^{−∫σ_t}` of the trilinear density along a ray, by a fine midpoint rule in
    /// f64 (10⁵ steps: its error is far below the path tracer's noise).
    fn quadrature_transmittance(v: &Volume, m: &Medium, o: Vec3, d: Vec3) -> f64 {
        let (lo, hi) = v.density.bounds();
        let (t0, t1) = crate::grid::slab(o, d, lo, hi).unwrap();
        let n = 100_000;
        let dt = f64::from(t1 - t0) / n as f64;
        let tau: f64 = (0..n)
            .map(|i| {
                let t = f64::from(t0) + (i as f64 + 0.5) * dt;
                f64::from(m.extinction(v.density.sample(o + d * t as f32)))
            })
            .sum::<f64>()
            * dt;
        (-tau).exp()
    }

    #[test]
    fn free_flights_give_the_heterogeneous_transmittance() {
        // With no scattering allowed and no emission, a path returns the environment iff it
        // crosses without a real collision: E[L] = L_env · T. Non-uniform smoke with empty blocks
        // exercises the block majorants, the DDA and the null collisions. Each sample is 0 or
        // L_env, so se = L_env sqrt(T(1 − T)/n); we use the measured one (the same up to noise).
        let v = procedural(32, 0.5).unwrap();
        let m = Medium::new(0.5, 2.5, 0.0, 0.0).unwrap();
        let maj = Majorants::new(&v, &m).unwrap();
        let s = PathSettings {
            max_scatter: 0,
            environment: Vec3::ONE,
            ..Default::default()
        };
        let eye = Vec3::new(0.4, 0.3, 3.0);
        for target in [
            Vec3::ZERO,
            Vec3::new(0.3, -0.2, 0.1),
            Vec3::new(-0.3, 0.25, 0.0),
        ] {
            let d = (target - eye).normalize();
            let want = quadrature_transmittance(&v, &m, eye, d) as f32;
            assert!((0.05..0.95).contains(&want), "a useful ray: T = {want}");
            let (got, se) = estimate(&v, &m, &maj, eye, d, &s, 40_000);
            assert_within_4se(got, se, Vec3::splat(want), 0.02, &format!("to {target}"));
        }
    }

    #[test]
    fn white_furnace() {
        // Albedo 1, no emission, uniform environment: every path keeps throughput exactly 1 and
        // eventually escapes, so every sample — not just the mean — equals L_env. Any lost energy
        // (a wrong escape test, a path ended early, a wrong albedo weight) breaks the equality.
        let v = procedural(32, 0.5).unwrap();
        let env = Vec3::new(1.0, 0.5, 0.25);
        let cam = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 12, 8).unwrap();
        let furnace = Medium::new(0.0, 8.0, 0.0, 0.0).unwrap();
        let s = PathSettings {
            spp: 4,
            max_scatter: 10_000,
            environment: env,
            seed: 3,
        };
        let img = render(&v, &furnace, &cam, &s, &|_| {}).unwrap();
        for p in &img.pixels {
            assert!((*p - env).abs().max_element() <= 1e-6, "{p} vs {env}");
        }
        // The smoke does scatter (else the equality would be trivial): the centre pixel is well
        // below L_env when no scattering is allowed (optical depth through the core is ~5).
        let centre = |img: &Image| img.get(6, 4);
        let no_scatter = PathSettings {
            max_scatter: 0,
            spp: 64,
            ..s
        };
        let direct = render(&v, &furnace, &cam, &no_scatter, &|_| {}).unwrap();
        assert!(centre(&direct).x < 0.5 * env.x, "{}", centre(&direct));
        // Albedo 0.5 loses energy: every pixel at most L_env, the centre strictly less.
        let grey = Medium::new(4.0, 4.0, 0.0, 0.0).unwrap();
        let img = render(&v, &grey, &cam, &s, &|_| {}).unwrap();
        assert!(img.pixels.iter().all(|p| p.cmple(env).all()));
        assert!(centre(&img).x < 0.9 * env.x, "{}", centre(&img));
    }

    /// A cold scattering ball (centre (0.5, 0.5, 0.5), radius 0.3) in a 2 × 1 × 1 density box of
    /// voxel 0.05, and a hot wall `x ∈ [1.4, 1.7]` across the whole box where the density is zero,
    /// held by its own temperature grid of voxel `emitter_h` (uniform, so the emitted field is the
    /// same at every `emitter_h`). A wall rather than a small ball: it fills a large solid angle
    /// seen from the ball (≈ 1 sr), so a path tracer — which finds the emitter only by scattering
    /// towards it — resolves single scattering to well under a per cent in 10⁶ paths.
    fn ball_and_wall(emitter_h: f32) -> Volume {
        let h = 0.05;
        let mut density = DenseGrid::zeros([40, 20, 20], h, Vec3::splat(0.5 * h));
        let centre = Vec3::splat(0.5);
        for k in 0..20 {
            for j in 0..20 {
                for i in 0..40 {
                    let r2 = (density.centre(i, j, k) - centre).length_squared() / 0.09;
                    let idx = density.index(i, j, k);
                    density.data[idx] = (1.0 - r2).max(0.0).powi(2);
                }
            }
        }
        let n = |len: f32| (len / emitter_h).round() as usize;
        let origin = Vec3::new(1.4, 0.0, 0.0) + Vec3::splat(0.5 * emitter_h);
        let mut temperature = DenseGrid::zeros([n(0.3), n(1.0), n(1.0)], emitter_h, origin);
        temperature.data.fill(2500.0);
        Volume::new(density, temperature)
    }

    #[test]
    fn single_scattering_agrees_with_the_ray_marcher() {
        // The marcher with brute-force point lights (I0 = j h³ at the hot voxels' centres) and
        // ray-marched shadows against the path tracer with one scattering event, on camera rays
        // through the cold ball (they never cross the emitter). Differences:
        //  - noise of the path tracer: 4 se from the sample variance;
        //  - the marcher's discretisation: midpoint rules along camera and shadow rays, and the
        //    emitter's volume as one point per voxel. We measure it by halving every resolution —
        //    steps along both kinds of ray, and the emitter's voxels (the emitted field is the
        //    same: a uniform wall) — and, as each part converges at least linearly, bound the
        //    coarse marcher's error by 2 |M_h − M_{h/2}| (a series with ratio ≤ 1/2). For the
        //    emitter part alone the midpoint rule predicts h²/(12 d²) ≈ 6·10⁻⁴ relative at the
        //    smallest distance (the ball's density, trilinear, reaches x = 0.85; the first light
        //    column is at x = 1.425: d = 11.5 voxels; ∇²(1/r²) = 2/r⁴), which the measurement
        //    covers.
        //  - the marcher's fall-off clamp at h0 and its transmittance cut-off: inactive here
        //    (every light is ≥ 11 voxels from any scattering point; cut-off 10⁻⁹).
        let v = ball_and_wall(0.05);
        let fine = ball_and_wall(0.025);
        let m = Medium::new(1.0, 4.0, 1e-3, 1000.0).unwrap();
        let h0 = v.density.voxel_size;
        let march_with = |vol: &Volume, step: f32, o: Vec3, d: Vec3| {
            let lights = ExplosionLights::new(&[vol], &m).unwrap();
            let brute = BruteForce::new(lights.lights()).unwrap();
            let s = MarchSettings {
                step_voxels: step,
                shadow_step_voxels: 2.0 * step,
                min_transmittance: 1e-9,
                shadows: Shadows::RayMarch,
                ..Default::default()
            };
            Marcher::new(vol, &m, &s)
                .unwrap()
                .march(&Lights::new(brute, h0), o, d, &mut RenderStats::default())
                .unwrap()
        };
        let maj = Majorants::new(&v, &m).unwrap();
        let s = PathSettings {
            max_scatter: 1,
            seed: 11,
            ..Default::default()
        };
        for x in [0.4f32, 0.5, 0.65] {
            let (o, d) = (Vec3::new(x, 0.5, 3.0), -Vec3::Z);
            let coarse = march_with(&v, 0.5, o, d);
            let finer = march_with(&fine, 0.25, o, d);
            let discretisation = 2.0 * (coarse - finer).abs();
            let (got, se) = estimate(&v, &m, &maj, o, d, &s, 1 << 20);
            eprintln!(
                "x {x}: path {got} ± {se}, march {coarse}, halved {finer}, rel diff {}",
                ((got - coarse) / coarse).abs().max_element()
            );
            for c in 0..3 {
                let tol = 4.0 * se[c] + discretisation[c];
                assert!(
                    (got[c] - coarse[c]).abs() <= tol,
                    "x {x}, channel {c}: path {} vs march {} (tolerance {tol})",
                    got[c],
                    coarse[c]
                );
                // Power: the test must resolve a few-per-cent error.
                assert!(
                    tol <= 0.06 * coarse[c],
                    "x {x}, channel {c}: tolerance {tol}"
                );
            }
        }
    }

    #[test]
    fn deterministic_across_thread_counts_and_validated() {
        let v = procedural(32, 0.5).unwrap();
        let m = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
        let cam = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 20, 12).unwrap();
        let s = PathSettings {
            spp: 2,
            seed: 42,
            ..Default::default()
        };
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| render_with_variance(&v, &m, &cam, &s, &|_| {}).unwrap())
        };
        let (a, va) = run(1);
        let (b, vb) = run(2);
        let bits = |img: &Image| -> Vec<u32> {
            img.pixels
                .iter()
                .flat_map(|p| p.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(bits(&va), bits(&vb));
        assert!(
            a.pixels.iter().any(|p| p.max_element() > 0.0),
            "the fire shows"
        );
        // The same pixels come out of `render`, and another seed changes them.
        assert_eq!(bits(&render(&v, &m, &cam, &s, &|_| {}).unwrap()), bits(&a));
        let other = PathSettings { seed: 43, ..s };
        assert_ne!(
            bits(&render(&v, &m, &cam, &other, &|_| {}).unwrap()),
            bits(&a)
        );
        // Bad settings are errors, not panics.
        let zero = PathSettings { spp: 0, ..s };
        assert!(render(&v, &m, &cam, &zero, &|_| {}).is_err());
        let one = PathSettings { spp: 1, ..s };
        assert!(render_with_variance(&v, &m, &cam, &one, &|_| {}).is_err());
        let nan = PathSettings {
            environment: Vec3::NAN,
            ..s
        };
        assert!(render(&v, &m, &cam, &nan, &|_| {}).is_err());
        let maj = Majorants::new(&v, &m).unwrap();
        let mut rng = pixel_rng(0, 0);
        for (o, d) in [
            (Vec3::ZERO, Vec3::ZERO),
            (Vec3::NAN, Vec3::X),
            (Vec3::ZERO, Vec3::NAN),
        ] {
            assert_eq!(radiance(&v, &m, &maj, o, d, &s, &mut rng), Vec3::ZERO);
        }
    }
}
