//! Visibility `V(x, light)` of the lights through the smoke: the one seam every shading point
//! of lgh-volume goes through (paper Sec. 4; ARCHITECTURE.md, "lgh-volume").
//!
//! [`Shadows`] is the choice (`--shadows`), [`Visibility`] the choice made ready for one frame:
//! it takes a shading point and the lights exactly as a many-lights backend returns them
//! ([`LightSample`]: level, index, centre, size `s`), so a method that needs more than a light's
//! position — the paper's deep-shadow cube maps are per light of every level — plugs in here as
//! one more variant.
//!
//! Three choices: none, the ray-marched reference, and the paper's deep-shadow cube maps
//! ([`CubeMaps`], module `deep`: precomputed per light of every level, traced through the
//! prefiltered density of module `prefilter` in the texel layout of module `cube`).
//!
//! The reference is ray-marched transmittance `V = e^{−∫σ_t}` from the shading point to
//! each light (the exact visibility of the paper's eq. 1 for a point light in smoke). Shadow rays
//! are where a render with shadows spends its time (every shading point marches one to each of
//! the hundreds of lights the hierarchy returns), so the density gets a copy laid out for them:
//! [`ShadowGrid`] pads it by one voxel of its own border values, which makes a trilinear lookup
//! anywhere in the grid's box a clamp-free read of eight neighbours, and
//! [`ShadowGrid::transmittances`] marches a shading point's rays together — eight abreast on CPUs
//! with AVX2 (module `avx2`, the crate's only `unsafe` code), with the same result bit for bit.

use lgh_core::glam::{Vec3, Vec3A};
use lgh_core::{Blending, LightSample, LightingGridHierarchy};

use crate::medium::{Medium, Volume};

pub mod cube;
pub mod deep;
mod empty;
mod knots;
mod lookup;
mod padded;
pub mod prefilter;
pub mod volume_rays;

pub use deep::{CubeMapPlan, CubeMapSettings, CubeMaps, Depths, LevelMaps};

/// How the coarse lights (levels ≥ 1) of the hierarchy cast their shadows: one of the paper's
/// flickering variants ([`Variants`](crate::Variants) holds the choice of a light set).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CoarseShadows {
    /// As volume lights, through the density prefiltered for their size `s` (eq. 6): the
    /// paper's.
    #[default]
    Volumes,
    /// As points through the plain density: the variant the paper compares against (Fig. 9).
    Points,
}

/// The lights a visibility is made for: the hierarchy, the blending whose radii `r_ℓ` bound
/// where each level is seen from (eq. 3), and how its coarse lights cast shadows.
#[derive(Clone, Copy, Debug)]
pub struct Casters<'a> {
    /// The lights' hierarchy.
    pub hierarchy: &'a LightingGridHierarchy,
    /// The blending at the render's α.
    pub blending: &'a Blending,
    /// How coarse lights cast shadows.
    pub coarse: CoarseShadows,
}

impl<'a> Casters<'a> {
    /// The lights of `hierarchy` at `blending`, coarse lights as the paper's volume lights.
    ///
    /// ```
    /// use lgh_volume::lgh_core::glam::Vec3;
    /// use lgh_volume::lgh_core::{LightingGridHierarchy, PointLight};
    /// use lgh_volume::shadow::{Casters, CoarseShadows};
    ///
    /// let lights = [PointLight::new(Vec3::ZERO, Vec3::ONE), PointLight::new(Vec3::X, Vec3::ONE)];
    /// let lgh = LightingGridHierarchy::build(&lights, &Default::default())?;
    /// let blending = lgh.blending(2.0)?;
    /// assert_eq!(Casters::new(&lgh, &blending).coarse, CoarseShadows::Volumes);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn new(hierarchy: &'a LightingGridHierarchy, blending: &'a Blending) -> Self {
        Casters {
            hierarchy,
            blending,
            coarse: CoarseShadows::Volumes,
        }
    }

    /// Whether coarse lights are traced through the prefiltered density (eq. 6).
    #[must_use]
    pub(crate) fn prefiltered(&self) -> bool {
        self.coarse == CoarseShadows::Volumes
    }
}
pub use padded::PaddedGrid;
pub use prefilter::DensityPyramid;
pub use volume_rays::VolumeRays;

/// How lights are shadowed: the user's choice (`--shadows` of `lgh demo` and `lgh explosion`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Shadows {
    /// The paper's deep-shadow cube maps, precomputed per light of every level of the
    /// hierarchy (Sec. 4). Backends without a hierarchy (brute force) ray-march instead.
    CubeMap,
    /// Transmittance ray-marched to every light (exact shadows).
    #[default]
    RayMarch,
    /// The cube maps' own model without the maps, their same-model reference: transmittance
    /// ray-marched from every light's centre through the density prefiltered for it (eq. 6;
    /// coarse lights as volume lights). Slow. Backends without a hierarchy ray-march instead.
    RayMarchVolumes,
    /// Ray-marched, each light as what it stands for: level-0 lights as points through the
    /// plain density (as [`RayMarch`](Self::RayMarch)), coarse lights as the volume lights of
    /// eq. 6 ([`RayMarchVolumes`](Self::RayMarchVolumes)' model) in steps that widen with the
    /// prefilter ([`VolumeRays::spread_part`]). A coarse light seen as a point through the
    /// plain density is the centroid of lights spread over its cell, and its one shadow ray
    /// lets through more than its lights' do: on the explosion at α = 2 the point shadows
    /// brighten the first scattered depth by 3.3% against brute force, these by 0.8%
    /// (docs/shadows.md, "Volume lights' shadows"). Backends without a hierarchy ray-march.
    Volumes,
    /// No shadows.
    None,
}

impl Shadows {
    /// The name on the command line and in EXR headers (`cubemap`, `raymarch`, `none`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Shadows::CubeMap => "cubemap",
            Shadows::RayMarch => "raymarch",
            Shadows::RayMarchVolumes => "raymarch-volumes",
            Shadows::Volumes => "volumes",
            Shadows::None => "none",
        }
    }
}

/// The visibility of a frame's lights, ready to evaluate: [`Shadows`] built for one volume and
/// medium.
#[derive(Clone, Debug)]
pub enum Visibility {
    /// No shadows: `V = 1`.
    None,
    /// Transmittance ray-marched through the density (exact up to the step and cut-off).
    RayMarched(ShadowGrid),
    /// Deep-shadow cube maps of a hierarchy's lights (paper Sec. 4).
    CubeMaps(CubeMaps),
    /// The cube maps' model ray-marched, without the maps (their same-model reference).
    VolumeRays(VolumeRays),
    /// Level-0 lights ray-marched as points, coarse lights as volume lights in cone steps
    /// ([`Shadows::Volumes`]).
    Volumes {
        /// The level-0 lights' march.
        points: ShadowGrid,
        /// The coarse lights' spread parts ([`VolumeRays::spread_part`]).
        rays: VolumeRays,
    },
}

impl Visibility {
    /// `shadows` for `volume` in `medium`, shadow rays marched in steps of at most `step_voxels`
    /// voxels and cut off at transmittance `cutoff` (see [`ShadowGrid::transmittance`]).
    /// Cube maps are made for a hierarchy ([`CubeMaps::build`], then
    /// [`Visibility::CubeMaps`]); asked for here, without one, the shadows are ray-marched.
    #[must_use]
    pub fn new(
        shadows: Shadows,
        volume: &Volume,
        medium: &Medium,
        step_voxels: f32,
        cutoff: f32,
    ) -> Self {
        match shadows {
            Shadows::None => Visibility::None,
            Shadows::RayMarch | Shadows::CubeMap | Shadows::RayMarchVolumes | Shadows::Volumes => {
                Visibility::RayMarched(ShadowGrid::new(volume, medium, step_voxels, cutoff))
            }
        }
    }

    /// Whether every light is fully visible (no shadows at all).
    #[must_use]
    pub fn is_none(&self) -> bool {
        matches!(self, Visibility::None)
    }

    /// `V(x, light)` for each light of `lights` into `out` (resized to match), in the order
    /// they were pushed; returns the density samples taken.
    pub fn transmittances(&self, x: Vec3, lights: &ShadowQuery, out: &mut Vec<f32>) -> u64 {
        match self {
            Visibility::None => {
                out.clear();
                out.resize(lights.len(), 1.0);
                0
            }
            Visibility::RayMarched(grid) => grid.transmittances(x, &lights.positions, out),
            Visibility::CubeMaps(maps) => {
                maps.transmittances(x, &lights.positions, &lights.ids, out);
                0
            }
            Visibility::VolumeRays(rays) => {
                rays.transmittances(x, &lights.positions, &lights.ids, out)
            }
            Visibility::Volumes { points, rays } => volume_lights(points, rays, x, lights, out),
        }
    }

    /// The shadows actually used (`Shadows::RayMarch` for cube maps asked of a backend without
    /// a hierarchy).
    #[must_use]
    pub fn shadows(&self) -> Shadows {
        match self {
            Visibility::None => Shadows::None,
            Visibility::RayMarched(_) => Shadows::RayMarch,
            Visibility::CubeMaps(_) => Shadows::CubeMap,
            Visibility::VolumeRays(_) => Shadows::RayMarchVolumes,
            Visibility::Volumes { .. } => Shadows::Volumes,
        }
    }
}

/// [`Visibility::Volumes`]' transmittances: each light's ray in two parts, the part that
/// reads the prefiltered density near a coarse light ([`VolumeRays::spread_part`], one light at
/// a time) and the rest — all of a level-0 light's — through the plain density, every light's
/// at once (eight abreast where the CPU can), the two multiplied.
fn volume_lights(
    points: &ShadowGrid,
    rays: &VolumeRays,
    x: Vec3,
    lights: &ShadowQuery,
    out: &mut Vec<f32>,
) -> u64 {
    thread_local! {
        static PLAIN: std::cell::RefCell<(Vec<Vec3>, Vec<f32>)> = const {
            std::cell::RefCell::new((Vec::new(), Vec::new()))
        };
    }
    PLAIN.with_borrow_mut(|(starts, spread)| {
        starts.clear();
        spread.clear();
        let mut samples = 0u64;
        for (&p, &(level, index)) in lights.positions.iter().zip(&lights.ids) {
            let (tau, start, n) = rays.spread_part(x, level, index, p);
            // Hidden already: its plain part has no length and adds no work.
            let start = if tau.is_finite() { start } else { x };
            starts.push(start);
            spread.push(if tau.is_finite() { (-tau).exp() } else { 0.0 });
            samples += u64::from(n);
        }
        samples += points.transmittances(x, starts, out);
        for (o, &t) in out.iter_mut().zip(spread.iter()) {
            *o *= t;
        }
        samples
    })
}

/// Whether `p` is in the box `lo..=hi` (faces included): where the density is.
#[inline]
fn in_box(p: Vec3, lo: Vec3, hi: Vec3) -> bool {
    p.cmpge(lo).all() && p.cmple(hi).all()
}

/// The lights whose visibility one shading point needs, pushed as a many-lights backend returns
/// them ([`LightSample`]) and kept in the form the visibility methods read: only what they use,
/// structure of arrays, so that gathering the hundreds of lights of a shading point stays in
/// cache (a method that needs a light's level, index or size stores it here too). Reused from
/// shading point to shading point.
#[derive(Clone, Debug, Default)]
pub struct ShadowQuery {
    positions: Vec<Vec3>,
    /// Level and index of each light (what the cube maps are kept by).
    ids: Vec<(u8, u32)>,
}

impl ShadowQuery {
    /// Empties the query for the next shading point (keeps its memory).
    pub fn clear(&mut self) {
        self.positions.clear();
        self.ids.clear();
    }

    /// Adds `light`.
    #[inline]
    pub fn push(&mut self, light: &LightSample) {
        self.positions.push(light.position);
        self.ids.push((light.level, light.index));
    }

    /// The lights' positions, in the order they were pushed.
    #[must_use]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Number of lights.
    #[must_use]
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True if no light was pushed.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2;

/// 2^23: a float in [−2^22, 2^22] plus this is rounded to the nearest integer, which the sum's
/// low mantissa bits hold.
const ROUND: f32 = 8_388_608.0;

/// The density padded ([`PaddedGrid`]) and the medium's extinction per unit density: what
/// [`transmittance`](Self::transmittance) reads.
#[derive(Clone, Debug)]
pub struct ShadowGrid {
    grid: PaddedGrid,
    /// The density grid's box (voxel faces), where shadow rays are marched.
    lo: Vec3,
    hi: Vec3,
    /// `σ_t` per unit density times the voxel size: optical depth per voxel of path per unit
    /// density.
    kappa_voxel: f32,
    /// 1 / the longest step along a shadow ray, in voxels.
    inv_step_voxels: f32,
    /// Optical depth `ln(1/cutoff)` past which a light counts as hidden.
    max_tau: f32,
}

impl ShadowGrid {
    /// The shadow rays of `volume`'s density in `medium`, marched with steps of at most
    /// `step_voxels` voxels and cut off at transmittance `cutoff` (see
    /// [`transmittance`](Self::transmittance)).
    #[must_use]
    pub fn new(volume: &Volume, medium: &Medium, step_voxels: f32, cutoff: f32) -> Self {
        let g = &volume.density;
        let (lo, hi) = g.bounds();
        ShadowGrid {
            grid: PaddedGrid::new(g),
            lo,
            hi,
            kappa_voxel: medium.extinction(1.0) * g.voxel_size,
            inv_step_voxels: 1.0 / step_voxels,
            max_tau: if cutoff > 0.0 {
                -cutoff.ln()
            } else {
                f32::INFINITY
            },
        }
    }

    /// Trilinear density at `p`, in padded voxel units (see [`PaddedGrid::sample`]).
    #[inline(always)]
    fn sample(&self, p: Vec3A) -> f32 {
        self.grid.sample(p)
    }

    /// Transmittance `e^{−∫σ_t}` from `a` to `b`, midpoint rule with steps of at most the step
    /// over the part of the segment inside the grid. The march stops once the transmittance is
    /// below the cut-off and returns 0: a light that dim behind smoke is taken as fully hidden,
    /// an error below the cut-off times its unshadowed contribution. Also returns the number of
    /// density samples taken.
    #[must_use]
    pub fn transmittance(&self, a: Vec3, b: Vec3) -> (f32, u32) {
        match self.ray(a, b) {
            Some(ray) => self.march(&ray),
            None => (1.0, 0),
        }
    }

    /// [`transmittance`](Self::transmittance) from `x` to each of `lights`, bit for bit, into
    /// `out` (resized to match); returns the density samples taken. On x86-64 CPUs with AVX2
    /// the rays are marched eight abreast with gathered loads, which is where a render with
    /// shadows spends its time; elsewhere one by one.
    pub fn transmittances(&self, x: Vec3, lights: &[Vec3], out: &mut Vec<f32>) -> u64 {
        out.clear();
        out.resize(lights.len(), 1.0);
        #[cfg(target_arch = "x86_64")]
        if let Some(samples) = avx2::transmittances(self, x, lights, out) {
            return samples;
        }
        self.transmittances_one_by_one(x, lights, out)
    }

    /// [`transmittances`](Self::transmittances) without SIMD.
    fn transmittances_one_by_one(&self, x: Vec3, lights: &[Vec3], out: &mut [f32]) -> u64 {
        let mut samples = 0u64;
        for (o, &l) in out.iter_mut().zip(lights) {
            let (t, n) = self.transmittance(x, l);
            *o = t;
            samples += u64::from(n);
        }
        samples
    }

    /// Whether `p` is in the grid's box (faces included).
    fn inside(&self, p: Vec3) -> bool {
        in_box(p, self.lo, self.hi)
    }

    /// Sets up the march from `a` to `b`, or `None` when nothing shadows it (it misses the box,
    /// has no length, or the grid is empty).
    fn ray(&self, a: Vec3, b: Vec3) -> Option<Ray> {
        if self.grid.is_empty() {
            return None;
        }
        // Shading points and lights are usually both inside the box: no clipping needed.
        let (a, b) = if self.inside(a) && self.inside(b) {
            (a, b)
        } else {
            let d = b - a;
            let len = d.length();
            if len <= 0.0 {
                return None;
            }
            match crate::grid::slab(a, d / len, self.lo, self.hi) {
                Some((t0, t1)) if t0 < len => (a + d * (t0 / len), a + d * (t1.min(len) / len)),
                _ => return None,
            }
        };
        // Everything in padded voxel units from here: one square root and two divisions a ray.
        let pa = self.grid.local(a);
        let seg = Vec3A::from((b - a) * self.grid.inv_voxel_size);
        let len = seg.length();
        if len.is_nan() || len <= 0.0 {
            return None;
        }
        // ⌈len / step⌉ without a libm call (no rounding instruction on baseline x86-64).
        let q = len * self.inv_step_voxels;
        let n = ((q as u32) + u32::from(((q as u32) as f32) < q)).max(1);
        let dp = seg * (1.0 / n as f32);
        // Stop once the summed density exceeds ln(1/cutoff) / (κ dt).
        let kappa = self.kappa_voxel * (len / n as f32);
        Some(Ray {
            p0: pa + 0.5 * dp,
            dp,
            n,
            kappa,
            max_sum: self.max_tau / kappa,
        })
    }

    /// Marches one ray: (transmittance, samples taken).
    fn march(&self, ray: &Ray) -> (f32, u32) {
        let mut sum = 0.0f32;
        for i in 0..ray.n {
            sum += self.sample(ray.p0 + ray.dp * i as f32);
            if sum > ray.max_sum {
                return (0.0, i + 1);
            }
        }
        (transmittance(ray.kappa, sum), ray.n)
    }
}

/// A shadow ray set up for marching, in padded voxel units: `n` samples at `p0 + i·dp` (the
/// step midpoints), each adding its density to a sum of optical depth `κ·sum`; the light is
/// hidden once the sum exceeds `max_sum`.
#[derive(Clone, Copy, Debug, Default)]
struct Ray {
    p0: Vec3A,
    dp: Vec3A,
    n: u32,
    kappa: f32,
    max_sum: f32,
}

/// `e^{−κ·sum}`: a march's transmittance.
fn transmittance(kappa: f32, sum: f32) -> f32 {
    (-kappa * sum).exp()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::DenseGrid;

    /// A volume of `dims` voxels of size 1/16 with density `f(i, j, k)`.
    fn volume(dims: [usize; 3], f: impl Fn(usize, usize, usize) -> f32) -> Volume {
        let mut density = DenseGrid::zeros(dims, 1.0 / 16.0, Vec3::new(-0.5, 0.25, 1.0));
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    density.data[(k * dims[1] + j) * dims[0] + i] = f(i, j, k);
                }
            }
        }
        let temperature = density.clone();
        Volume::new(density, temperature)
    }

    #[test]
    fn padded_lookup_is_the_densitys_trilinear_lookup() {
        // Uneven dimensions and values, points all over the box including its faces and the
        // half voxel beyond the outermost centres, where the density's lookup clamps (its
        // `sample` is zero on the far faces, which are outside its half-open box).
        let v = volume([5, 3, 4], |i, j, k| ((i * 7 + j * 13 + k * 29) % 11) as f32);
        let m = Medium::new(1.0, 0.0, 0.0, 0.0).unwrap();
        let g = ShadowGrid::new(&v, &m, 1.0, 0.0);
        let (lo, hi) = v.density.bounds();
        let mut worst = 0.0f32;
        for a in 0..=20 {
            for b in 0..=12 {
                for c in 0..=16 {
                    let t = Vec3::new(a as f32 / 20.0, b as f32 / 12.0, c as f32 / 16.0);
                    let x = lo + (hi - lo) * t;
                    let p = g.grid.local(x);
                    let u = (x - v.density.origin) / v.density.voxel_size;
                    worst = worst.max((g.sample(p) - v.density.sample_voxel(u)).abs());
                }
            }
        }
        // Values up to 10 and f32 coordinates: rounding of the fractions only.
        assert!(worst < 1e-4, "{worst}");
    }

    #[test]
    fn transmittance_is_beer_lambert() {
        // A homogeneous box 2 units on a side, σ_t = 1.
        let v = volume([32; 3], |_, _, _| 1.0);
        let v = Volume::new(
            DenseGrid {
                origin: Vec3::splat(-1.0 + 1.0 / 32.0),
                ..v.density.clone()
            },
            v.temperature.clone(),
        );
        let m = Medium::new(0.7, 0.3, 0.0, 0.0).unwrap();
        let (a, b) = (Vec3::new(0.0, 0.0, -3.0), Vec3::new(0.0, 0.0, 3.0));
        let t = ShadowGrid::new(&v, &m, 0.8, 0.0).transmittance(a, b).0;
        assert!((t - (-2.0f32).exp()).abs() < 1e-5, "{t}");
        // Below the cut-off the light counts as hidden, and the march stops early.
        let (t, n) = ShadowGrid::new(&v, &m, 0.8, 0.2).transmittance(a, b);
        assert_eq!(t, 0.0);
        assert!(n < 40, "stops early: {n} of 40 samples");
        // From inside to a point inside: only the segment counts.
        let g = ShadowGrid::new(&v, &m, 0.8, 0.0);
        let t = g.transmittance(Vec3::ZERO, Vec3::new(0.5, 0.0, 0.0)).0;
        assert!((t - (-0.5f32).exp()).abs() < 1e-5, "{t}");
        // A segment outside the box, or of length zero, is unshadowed.
        assert_eq!(
            g.transmittance(Vec3::splat(5.0), Vec3::splat(6.0)),
            (1.0, 0)
        );
        assert_eq!(g.transmittance(Vec3::ZERO, Vec3::ZERO), (1.0, 0));
    }

    #[test]
    fn heterogeneous_transmittance_matches_a_fine_quadrature() {
        // A density ramp in x times a bump in y: the midpoint rule at one sample per voxel
        // against 64 samples per voxel of the density's own lookup.
        let v = volume([24, 20, 16], |i, j, _| {
            i as f32 * 0.2 * (1.0 + (j as f32 * 0.4).sin())
        });
        let m = Medium::new(1.0, 1.0, 0.0, 0.0).unwrap();
        let g = ShadowGrid::new(&v, &m, 1.0, 0.0);
        let (lo, hi) = v.density.bounds();
        let (a, b) = (
            lo + (hi - lo) * 0.1,
            lo + (hi - lo) * Vec3::new(0.9, 0.7, 0.8),
        );
        let n = 64 * 24;
        let dt = (b - a).length() / n as f32;
        let tau: f32 = (0..n)
            .map(|i| {
                m.extinction(
                    v.density
                        .sample(a + (b - a) * ((i as f32 + 0.5) / n as f32)),
                )
            })
            .sum::<f32>()
            * dt;
        let (t, samples) = g.transmittance(a, b);
        // The midpoint rule errs by at most h² max|f''| ℓ / 24 (h = 1 voxel, ℓ = 25.3 voxels)
        // with f the density along the ray. The ramp is linear in x; the bump curves by at most
        // 0.2·23·0.4² = 0.74 per voxel² along y, and the ray's direction (0.76, 0.47, 0.44)
        // sees 0.74·0.47² plus the mixed term 2·(0.2·0.4)·0.76·0.47: |f''| ≤ 0.22 per voxel².
        // The summed density errs by ≤ 0.23 (voxel units), τ by ≤ 0.23·κ·h = 0.23·2/16 ≈ 0.03.
        assert!(
            ((-tau).exp() - t).abs() < 0.03 * t.max(1e-3),
            "{t} vs {}",
            (-tau).exp()
        );
        assert!(samples >= 24);
    }

    /// Rays between random points in and around an uneven grid of random density: shading
    /// points inside and outside the box, lights inside, outside, on the faces and on the
    /// shading point, lengths from nothing to across the box, and smoke thick enough that some
    /// lights are hidden (cut off). Returns the shading points and each one's lights.
    fn ray_sets(v: &Volume) -> Vec<(Vec3, Vec<Vec3>)> {
        let (lo, hi) = v.density.bounds();
        let mut rng = lgh_core::random::SplitMix64(11);
        let margin = (hi - lo) * 0.2;
        (0..60)
            .map(|s| {
                let x = if s % 5 == 0 {
                    rng.next_in(lo - margin, hi + margin)
                } else {
                    rng.next_in(lo, hi)
                };
                // 0 to 40 lights: every remainder modulo 8, and whole groups of eight.
                let count = (s * 7) % 41;
                let lights = (0..count)
                    .map(|i| match i % 13 {
                        0 => x,
                        1 => hi,
                        2 => rng.next_in(lo - margin, hi + margin),
                        _ => rng.next_in(lo, hi),
                    })
                    .collect();
                (x, lights)
            })
            .collect()
    }

    fn random_volume() -> Volume {
        let mut rng = lgh_core::random::SplitMix64(5);
        let values: Vec<f32> = (0..23 * 17 * 29).map(|_| rng.next_f32() * 3.0).collect();
        volume([23, 17, 29], |i, j, k| values[(k * 17 + j) * 23 + i])
    }

    #[test]
    fn batched_rays_are_the_one_by_one_rays_bit_for_bit() {
        let v = random_volume();
        // Thick enough that a ray across the box is cut off, thin enough that short ones aren't.
        let m = Medium::new(2.0, 1.5, 0.0, 0.0).unwrap();
        let (mut hidden, mut lit) = (0, 0);
        for step in [0.7f32, 2.0] {
            let g = ShadowGrid::new(&v, &m, step, 1e-3);
            let mut out = Vec::new();
            for (x, lights) in ray_sets(&v) {
                let samples = g.transmittances(x, &lights, &mut out);
                let mut expected = 0u64;
                for (l, &t) in lights.iter().zip(&out) {
                    let (want, n) = g.transmittance(x, *l);
                    assert_eq!(t.to_bits(), want.to_bits(), "{x} to {l}: {t} vs {want}");
                    expected += u64::from(n);
                    hidden += usize::from(t == 0.0 && n > 0);
                    lit += usize::from(t > 0.0 && t < 1.0);
                }
                assert_eq!(samples, expected);
            }
        }
        assert!(hidden > 20 && lit > 500, "{hidden} hidden, {lit} lit");
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_rays_are_the_one_by_one_rays_bit_for_bit() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        let v = random_volume();
        let m = Medium::new(2.0, 1.5, 0.0, 0.0).unwrap();
        let g = ShadowGrid::new(&v, &m, 1.0, 1e-3);
        for (x, lights) in ray_sets(&v) {
            let mut simd = vec![f32::NAN; lights.len()];
            let mut scalar = vec![f32::NAN; lights.len()];
            let a = avx2::transmittances(&g, x, &lights, &mut simd).expect("AVX2");
            let b = g.transmittances_one_by_one(x, &lights, &mut scalar);
            assert_eq!(a, b);
            assert_eq!(
                simd.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
                scalar.iter().map(|t| t.to_bits()).collect::<Vec<_>>()
            );
        }
    }
}
