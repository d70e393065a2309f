//! Indirect light from virtual point lights, shaded with visibility (paper Sec. 6.4, Figs. 11,
//! 13): what a surface point receives from the VPLs a many-lights backend hands it.
//!
//! The hierarchy aggregates lights as isotropic points, so each VPL enters it as a point of the
//! isotropic intensity `Φ ρ / 2π` ([`point_lights`]): what carries its flux into the half-space
//! in front of its surface, where everything it lights is. Shading restores what the aggregation
//! lost where it can:
//!
//! - a level-0 light is the VPL itself: its cosine lobe is restored (the factor
//!   `2 max(0, n_v·ω)`, so its flux is unchanged) and one shadow ray through the BVH decides
//!   whether it is seen;
//! - a coarser light stands for many VPLs spread with variance `σ²` (eq. 4): it is a volume
//!   light, shaded as `k` points at `p + σ ⊙ g_j`, each with `1/k` of the intensity and a shadow
//!   ray of its own, where the `g_j` are standard-normal offsets drawn from a sequence seeded by
//!   the light's level and index — the same pattern for that light at every pixel and every
//!   frame, so the soft shadows do not flicker (Fig. 11d; `k = 0` shades it as a point, Fig. 11c).
//!   That is [`Coarse::Gaussian`], the paper's. Beyond the paper, [`Coarse::Representatives`]
//!   shades a coarse light through `k` of the VPLs it stands for instead
//!   ([`crate::representatives`]): on surfaces the Gaussian's samples fall inside walls and
//!   lose the lobes, and err by tens of percent where the representatives err by a few.
//!
//! Backends whose samples are the VPLs themselves — brute force, Lightcuts' representatives —
//! go through [`render_input_lights`]; the hierarchy through [`render_lgh`], or
//! [`render_buckets`] for [`NormalBuckets`].
//!
//! Surfaces reflect physically: Lambert `ρ/π`, Phong `k_d/π + k_s (n+2)/2π (R·E)^n`. The VPL
//! singularity is clamped with the core's rule, `1 / max(d, h0)²`: a VPL closer than `h0` to the
//! point it lights gives what it would at `h0`, which drops the short-range part of the light
//! (the bright blotches of unclamped VPLs near corners).

use std::sync::atomic::{AtomicU64, Ordering};

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_core::{
    Blending, BuildError, GridSettings, Illumination, LghBackend, LightSample,
    LightingGridHierarchy, ManyLights, PointLight, QueryError, ShadingPoint,
};

use crate::brdf::brdf;
use crate::render::{render_points, render_with_shader, RenderError, Rendered};
use crate::representatives::{Allocation, Representatives};
use crate::scene::Scene;
use crate::vpl::Vpl;
use crate::Camera;

/// The hierarchy's input lights for `vpls`: each at its VPL's position with the isotropic
/// intensity `Φ ρ / 2π` that carries its cosine lobe's flux into the half-space in front of it.
#[must_use]
pub fn point_lights(vpls: &[Vpl]) -> Vec<PointLight> {
    vpls.iter()
        .map(|v| PointLight::new(v.position, isotropic_intensity(v)))
        .collect()
}

/// The isotropic intensity `Φ ρ / 2π` a VPL enters the hierarchy with ([`point_lights`]).
#[inline]
fn isotropic_intensity(v: &Vpl) -> Vec3 {
    v.power * v.albedo / (2.0 * std::f32::consts::PI)
}

/// How the VPLs are shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IndirectSettings {
    /// The singularity clamp `h0`: distances below it count as `h0`.
    pub h0: f32,
    /// Shadow samples `k` of a coarse (volume) light; 0 shades it as a point (Fig. 11c).
    pub shadow_samples: u32,
    /// Offset of shadow rays from the surfaces they leave, against self-shadowing.
    pub epsilon: f32,
    /// Whether to trace shadow rays at all (false: every light is seen, as in Paquette et al.'s
    /// experiments; it separates the error of the volume lights' shadows from the rest).
    pub shadows: bool,
}

/// A shadow-ray counter on a cache line of its own.
#[derive(Default)]
#[repr(align(64))]
struct RayCount(AtomicU64);

/// Shades the VPLs of `vpls` at surface points of `scene`.
pub struct Indirect<'a> {
    scene: &'a Scene,
    vpls: &'a [Vpl],
    settings: IndirectSettings,
    /// Shadow rays traced so far, one counter per rayon worker (and a last one for any other
    /// thread): an atomic shared by every thread cost 13% of a render in contention.
    rays: Vec<RayCount>,
}

impl<'a> Indirect<'a> {
    /// A shader for `vpls` in `scene`.
    #[must_use]
    pub fn new(scene: &'a Scene, vpls: &'a [Vpl], settings: IndirectSettings) -> Self {
        Indirect {
            scene,
            vpls,
            settings,
            rays: (0..=rayon::current_num_threads())
                .map(|_| RayCount::default())
                .collect(),
        }
    }

    /// Shadow rays this shader has traced.
    #[must_use]
    pub fn shadow_rays(&self) -> u64 {
        self.rays.iter().map(|c| c.0.load(Ordering::Relaxed)).sum()
    }

    /// Counts one shadow ray on the calling thread's counter.
    #[inline]
    fn count_ray(&self) {
        let last = self.rays.len() - 1;
        match rayon::current_thread_index().filter(|&i| i < last) {
            // Only this worker writes its counter: a plain load and store, no locked add.
            Some(i) => {
                let c = &self.rays[i].0;
                c.store(c.load(Ordering::Relaxed) + 1, Ordering::Relaxed);
            }
            None => {
                self.rays[last].0.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// The radiance `light` sends towards the viewer from `point`, visibility included. `vpl`
    /// is the index in the VPL slice of a level-0 light (a backend's own index for brute force,
    /// `LightingGridHierarchy::input_index` for the hierarchy); coarser lights ignore it.
    #[must_use]
    pub fn shade(&self, point: &ShadingPoint, light: &LightSample, vpl: Option<usize>) -> Vec3 {
        self.shade_oriented(point, light, vpl, None)
    }

    /// [`shade`](Self::shade), with the coarse light emitting the cosine lobe about `lobe` (the
    /// mean normal of the VPLs it stands for, [`NormalBuckets`]) instead of isotropically.
    #[must_use]
    pub fn shade_oriented(
        &self,
        point: &ShadingPoint,
        light: &LightSample,
        vpl: Option<usize>,
        lobe: Option<Vec3>,
    ) -> Vec3 {
        let Some(normal) = point.normal else {
            return Vec3::ZERO;
        };
        let from = point.position + normal * self.settings.epsilon;
        let facing = |q: Vec3| facing(point, normal, q);
        let occluded = |to: Vec3| self.occluded(from, to);
        if light.level == 0 {
            let Some(v) = vpl.and_then(|i| self.vpls.get(i)) else {
                return Vec3::ZERO;
            };
            return self.shade_vpl(point, normal, v, light.intensity);
        }
        // The coarse light's own lobe, if it has one: 2 max(0, n̄·ω) towards the point.
        let toward = |q: Vec3| match lobe {
            Some(n) => 2.0 * n.dot((point.position - q).normalize_or_zero()).max(0.0),
            None => 1.0,
        };
        let k = self.settings.shadow_samples;
        if k == 0 || light.variance == Vec3::ZERO {
            if !facing(light.position) || occluded(light.position) {
                return Vec3::ZERO;
            }
            let f = toward(light.position);
            return self.reflect(point, normal, light.position, light.intensity * f);
        }
        let sigma = light.variance.max(Vec3::ZERO).map(f32::sqrt);
        let mut rng = SplitMix64(SplitMix64::mix(
            (u64::from(light.level) << 32) | u64::from(light.index),
        ));
        let share = light.intensity / k as f32;
        let mut sum = Vec3::ZERO;
        for _ in 0..k {
            let mut offset = sigma * gaussian3(&mut rng);
            if let Some(n) = lobe {
                // In front of the surfaces the light stands for: mirrored to the lobe's side,
                // and lifted off the surface as a VPL's own shadow ray is.
                let behind = offset.dot(n).min(0.0);
                offset += n * (self.settings.epsilon - 2.0 * behind);
            }
            let q = light.position + offset;
            let f = toward(q);
            if f > 0.0 && facing(q) && !occluded(q) {
                sum += self.reflect(point, normal, q, share * f);
            }
        }
        sum
    }

    /// A coarse light shaded through its `k` representative VPLs `reps` (indices into this
    /// shader's VPLs; [`Representatives`]), drawn in proportion to `w_j ‖I_j‖`: each one shaded
    /// as at level 0 — its cosine lobe, its shadow ray — with the intensity
    /// `I_j ‖B I_ℓi‖ / (k ‖I_j‖)`, its own colour at the share of the light's blended luminance
    /// it was drawn for (so the estimate of `Σ_j w_j I_j (…)` is unbiased in every channel).
    /// A VPL drawn `m` times is shaded once, `m` times as bright: one shadow ray. With no
    /// representatives, [`shade`](Self::shade).
    #[must_use]
    pub fn shade_representatives(
        &self,
        point: &ShadingPoint,
        light: &LightSample,
        reps: impl ExactSizeIterator<Item = usize>,
    ) -> Vec3 {
        let (Some(normal), k) = (point.normal, reps.len()) else {
            return Vec3::ZERO;
        };
        if k == 0 || light.level == 0 {
            return self.shade(point, light, None);
        }
        // Pick j carries its own colour: I_j · ‖B I_ℓ‖ / (k ‖I_j‖), the estimator of the drawn
        // weights w_j ‖I_j‖ (unbiased per channel, not only in luminance).
        let scale = lgh_core::luminance(light.intensity) / k as f32;
        let shade = |i: usize, times: usize| {
            let Some(v) = self.vpls.get(i) else {
                return Vec3::ZERO;
            };
            let own = isotropic_intensity(v);
            let lum = lgh_core::luminance(own);
            if lum > 0.0 {
                self.shade_vpl(point, normal, v, own * (scale * times as f32 / lum))
            } else {
                Vec3::ZERO
            }
        };
        let mut reps = reps;
        if k == 1 {
            return reps.next().map_or(Vec3::ZERO, |i| shade(i, 1));
        }
        // Repeated picks (a heavy VPL drawn twice) share one shadow ray: sorted, each run once
        // with its multiplicity.
        let mut small = [0usize; 16];
        let mut large = Vec::new();
        let ids: &mut [usize] = if k <= small.len() {
            for (slot, i) in small.iter_mut().zip(reps) {
                *slot = i;
            }
            &mut small[..k]
        } else {
            large.extend(reps);
            &mut large
        };
        ids.sort_unstable();
        ids.chunk_by(|a, b| a == b)
            .map(|run| shade(run[0], run.len()))
            .sum()
    }

    /// VPL `v` with the isotropic intensity `intensity` shaded at `point` (unit `normal`): its
    /// cosine lobe restored (`2 max(0, n_v·ω)`, the flux unchanged) and one shadow ray.
    fn shade_vpl(&self, point: &ShadingPoint, normal: Vec3, v: &Vpl, intensity: Vec3) -> Vec3 {
        let lit = self.unshadowed(point, normal, v.position, v.normal, intensity);
        if lit == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let from = point.position + normal * self.settings.epsilon;
        let source = v.position + v.normal * self.settings.epsilon;
        if self.occluded(from, source) {
            return Vec3::ZERO;
        }
        lit
    }

    /// What a cosine emitter at `q` with unit normal `n` and isotropic-equivalent intensity
    /// `intensity` (`2 intensity max(0, n·ω)` towards `ω`) gives `point` (unit `normal`),
    /// unshadowed.
    fn unshadowed(
        &self,
        point: &ShadingPoint,
        normal: Vec3,
        q: Vec3,
        n: Vec3,
        intensity: Vec3,
    ) -> Vec3 {
        let to_point = point.position - q;
        let d = to_point.length();
        if d == 0.0 {
            return Vec3::ZERO;
        }
        let lobe = 2.0 * n.dot(to_point / d).max(0.0);
        if lobe == 0.0 || !facing(point, normal, q) {
            return Vec3::ZERO;
        }
        self.reflect(point, normal, q, intensity * lobe)
    }

    /// Whether the mesh hides `to` from `from` (never, without shadows): one counted ray.
    fn occluded(&self, from: Vec3, to: Vec3) -> bool {
        if !self.settings.shadows {
            return false;
        }
        self.count_ray();
        self.scene.bvh().occluded(from, to)
    }

    /// Radiance reflected towards the viewer at `point` (unit `normal`) from a point light of
    /// intensity `intensity` at `light`, with the clamped fall-off.
    fn reflect(&self, point: &ShadingPoint, normal: Vec3, light: Vec3, intensity: Vec3) -> Vec3 {
        let to_light = light - point.position;
        let d = to_light.length();
        if d == 0.0 {
            return Vec3::ZERO;
        }
        let l = to_light / d;
        let cos = normal.dot(l);
        if cos <= 0.0 {
            return Vec3::ZERO;
        }
        let brdf = brdf(point, normal, l);
        brdf * intensity * (cos * lgh_core::falloff(d, self.settings.h0))
    }
}

/// Whether `q` is in front of the surface at `point` (unit `normal`): a light behind its plane
/// gives nothing (`reflect` says so too), and is tested first to spare its shadow ray.
#[inline]
fn facing(point: &ShadingPoint, normal: Vec3, q: Vec3) -> bool {
    normal.dot(q - point.position) > 0.0
}

/// The dominant-axis part (0..6: +x, −x, +y, −y, +z, −z) of a unit normal.
fn orientation(n: Vec3) -> usize {
    let a = n.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(n[axis] < 0.0)
}

/// An orientation-aware aggregation, beyond the paper: the VPLs split by the axis their normal
/// points along most (±x, ±y, ±z), one hierarchy per bucket, whose coarse lights emit the cosine
/// lobe about their bucket's mean normal. In rooms of axis-aligned walls each bucket's normals
/// agree, and the lobe the isotropic aggregation loses is kept at every level.
pub struct NormalBuckets {
    buckets: Vec<Bucket>,
}

/// The VPLs of one bucket.
struct Bucket {
    /// Index in the VPL slice of each of the bucket's lights.
    vpl: Vec<u32>,
    /// Unit mean normal of its VPLs.
    normal: Vec3,
    lgh: LightingGridHierarchy,
    /// Its coarse lights' representative VPLs, if they shade through them.
    reps: Option<Representatives>,
}

impl NormalBuckets {
    /// Builds one hierarchy per non-empty bucket of `vpls`, with `settings`.
    ///
    /// Errors: those of [`LightingGridHierarchy::build`].
    pub fn build(vpls: &[Vpl], settings: &GridSettings) -> Result<Self, BuildError> {
        let lights = point_lights(vpls);
        let mut members: [Vec<u32>; 6] = Default::default();
        for (i, v) in vpls.iter().enumerate() {
            members[orientation(v.normal)].push(i as u32);
        }
        let mut buckets = Vec::new();
        for vpl in members.into_iter().filter(|m| !m.is_empty()) {
            let own: Vec<PointLight> = vpl.iter().map(|&i| lights[i as usize]).collect();
            let normal = vpl
                .iter()
                .map(|&i| vpls[i as usize].normal)
                .sum::<Vec3>()
                .normalize_or_zero();
            let lgh = LightingGridHierarchy::build(&own, settings)?;
            buckets.push(Bucket {
                vpl,
                normal,
                lgh,
                reps: None,
            });
        }
        Ok(NormalBuckets { buckets })
    }

    /// The same buckets, their coarse lights shaded through representative VPLs, as many as
    /// `allocation` says
    /// ([`Representatives`]) instead of Gaussian samples about their mean normal's lobe.
    #[must_use]
    pub fn with_representatives(mut self, allocation: Allocation) -> Self {
        for b in &mut self.buckets {
            b.reps = Some(Representatives::build_with(&b.lgh, allocation));
        }
        self
    }

    /// The buckets queried at α = `alpha`: each bucket's blending, computed once for every
    /// point ([`LghBackend::new`] does the same for one hierarchy).
    ///
    /// Errors: [`QueryError`] for an invalid α.
    pub fn at(&self, alpha: f32) -> Result<BucketsAt<'_>, QueryError> {
        let blendings = self
            .buckets
            .iter()
            .map(|b| b.lgh.blending(alpha))
            .collect::<Result<_, _>>()?;
        Ok(BucketsAt {
            buckets: self,
            blendings,
        })
    }
}

/// [`NormalBuckets`] at one α ([`NormalBuckets::at`]).
pub struct BucketsAt<'a> {
    buckets: &'a NormalBuckets,
    blendings: Vec<Blending>,
}

impl BucketsAt<'_> {
    /// What `point` receives from every bucket, shaded by `shader`.
    ///
    /// Errors: those of the hierarchies' queries.
    pub fn illuminate(
        &self,
        point: &ShadingPoint,
        shader: &Indirect<'_>,
    ) -> Result<Illumination, QueryError> {
        let mut radiance = Vec3::ZERO;
        let mut lights = 0;
        for (b, blending) in self.buckets.buckets.iter().zip(&self.blendings) {
            lights += b.lgh.query(point.position, blending, |s| {
                radiance += match (&b.reps, s.level) {
                    (Some(reps), 1..) => {
                        let of = reps.of(s.level, s.index).iter();
                        shader.shade_representatives(
                            point,
                            s,
                            of.map(|&i| b.vpl[i as usize] as usize),
                        )
                    }
                    _ => {
                        let vpl = (s.level == 0)
                            .then(|| b.lgh.input_index(s.index))
                            .flatten()
                            .map(|i| b.vpl[i] as usize);
                        shader.shade_oriented(point, s, vpl, Some(b.normal))
                    }
                };
            })?;
        }
        Ok(Illumination { radiance, lights })
    }
}

/// How the coarse lights (levels ≥ 1) of a hierarchy over [`point_lights`] are shaded.
#[derive(Clone, Copy, Debug)]
pub enum Coarse<'a> {
    /// The paper's volume lights: isotropic points with `k` Gaussian shadow samples (Fig. 11d).
    Gaussian,
    /// Through their representative VPLs ([`Indirect::shade_representatives`]).
    Representatives(&'a Representatives),
    /// Through a prefix of their representatives (drawn with [`Allocation::Nested`]) whose
    /// length each shading point chooses: `mean` samples per coarse light are shared among
    /// the point's coarse lights in proportion to an unshadowed estimate of what each brings
    /// there (its blended luminance × the cosine at the point, held above 1/4, × the clamped
    /// `1/d²`), rounded down to a power of two and to what there is; a light owed less than
    /// one is shaded with that probability and weighted by its inverse (Russian roulette from
    /// the point's own seeded sequence). With representatives that are not nested, every
    /// light uses all of its own (a prefix of a plain systematic draw would be biased).
    Adaptive {
        /// The representatives, nested.
        reps: &'a Representatives,
        /// The mean count per coarse light.
        mean: f32,
    },
}

/// The indirect light `shader` gives each pixel through the hierarchy `backend` built over
/// [`point_lights`] of its VPLs (the paper's isotropic aggregation), its coarse lights shaded
/// as `coarse` says.
///
/// Errors: a point the hierarchy cannot be queried at ([`RenderError::Query`]).
pub fn render_lgh(
    scene: &Scene,
    camera: &Camera,
    backend: &LghBackend<'_>,
    coarse: Coarse<'_>,
    shader: &Indirect<'_>,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    let lgh = backend.hierarchy();
    if let Coarse::Adaptive { reps, mean } = coarse {
        let illuminate = |p: &ShadingPoint| adaptive(p, backend, reps, mean, shader);
        return render_points(scene, camera, illuminate, progress);
    }
    let shade = |p: &ShadingPoint, s: &LightSample| {
        fn reps<'r>(
            r: &'r Representatives,
            s: &LightSample,
        ) -> impl ExactSizeIterator<Item = usize> + 'r {
            r.of(s.level, s.index).iter().map(|&i| i as usize)
        }
        match (coarse, s.level) {
            (Coarse::Representatives(r), 1..) => shader.shade_representatives(p, s, reps(r, s)),
            _ => {
                let vpl = (s.level == 0).then(|| lgh.input_index(s.index)).flatten();
                shader.shade(p, s, vpl)
            }
        }
    };
    render_with_shader(scene, camera, backend, shade, progress)
}

/// The indirect light `shader` gives each pixel through a backend over [`point_lights`] of
/// the VPLs (in order) whose samples are those input lights: [`lgh_core::BruteForce`], every VPL, the
/// exact answer of the same model; or Lightcuts ([`lgh_core::LightcutsBackend`]), each
/// cluster of its cut shaded as its representative VPL — that VPL's lobe and shadow ray — with
/// the cluster's intensity, as Walter et al. shade a cut. (Lightcuts' error bound does not
/// include the VPLs' lobes, up to 2: a cluster's bound can be up to twice too low.)
///
/// Errors: as [`render_lgh`].
pub fn render_input_lights<B: ManyLights + Sync>(
    scene: &Scene,
    camera: &Camera,
    backend: &B,
    shader: &Indirect<'_>,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    let shade = |p: &ShadingPoint, s: &LightSample| shader.shade(p, s, Some(s.index as usize));
    render_with_shader(scene, camera, backend, shade, progress)
}

/// The salt of the roulette's sequence at a shading point (the area lights' patterns use the
/// triangle's index, which stays below 2³²).
const ROULETTE_SALT: u64 = 0xada << 40;

/// What `point` receives through `backend` with [`Coarse::Adaptive`].
fn adaptive(
    point: &ShadingPoint,
    backend: &LghBackend<'_>,
    reps: &Representatives,
    mean: f32,
    shader: &Indirect<'_>,
) -> Result<Illumination, QueryError> {
    thread_local! {
        static COARSE: std::cell::RefCell<Vec<(LightSample, f32)>> = const { std::cell::RefCell::new(Vec::new()) };
    }
    let lgh = backend.hierarchy();
    let Some(normal) = point.normal else {
        return Ok(Illumination {
            radiance: Vec3::ZERO,
            lights: 0,
        });
    };
    let h0 = shader.settings.h0;
    COARSE.with_borrow_mut(|coarse| {
        coarse.clear();
        let mut radiance = Vec3::ZERO;
        let lights = lgh.query(point.position, backend.blending(), |s| {
            if s.level == 0 {
                let vpl = lgh.input_index(s.index);
                radiance += shader.shade(point, s, vpl);
            } else {
                // Unshadowed, isotropic, Lambertian: the estimate that shares the samples.
                let to = s.position - point.position;
                let d = to.length();
                // The cosine held above 1/4: a light whose centre is behind the surface may
                // still have representatives in front of it.
                let cos = if d > 0.0 {
                    normal.dot(to / d).max(0.25)
                } else {
                    1.0
                };
                let c = lgh_core::luminance(s.intensity) * cos * lgh_core::falloff(d, h0);
                coarse.push((*s, c));
            }
        })?;
        let total: f32 = coarse.iter().map(|c| c.1).sum();
        let budget = mean.max(0.0) * coarse.len() as f32;
        let mut rng = SplitMix64(crate::direct::point_seed(point.position, ROULETTE_SALT));
        let nested = reps.is_nested();
        for (s, c) in coarse.iter() {
            let all = reps.of(s.level, s.index);
            let want = if total > 0.0 { budget * c / total } else { 1.0 };
            // In f64: a 24-bit draw would make the probability of a tiny `want` differ from it.
            let u = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
            let (m, scale) = if !nested {
                (all.len(), 1.0)
            } else if want >= 1.0 {
                // The largest power of two not above `want`, and not above what there is.
                let m = (want as usize).clamp(1, all.len().max(1));
                let m = if m.is_power_of_two() {
                    m
                } else {
                    m.next_power_of_two() / 2
                };
                (m, 1.0)
            } else if u < f64::from(want) {
                (1, 1.0 / want)
            } else {
                continue;
            };
            let prefix = all.get(..m).unwrap_or(&[]);
            let lit = shader.shade_representatives(point, s, prefix.iter().map(|&i| i as usize));
            radiance += lit * scale;
        }
        Ok(Illumination { radiance, lights })
    })
}

/// The indirect light `shader` gives each pixel through the normal buckets at one α.
///
/// Errors: as [`render_lgh`].
pub fn render_buckets(
    scene: &Scene,
    camera: &Camera,
    buckets: &BucketsAt<'_>,
    shader: &Indirect<'_>,
    progress: impl Fn(usize) + Sync,
) -> Result<Rendered, RenderError> {
    render_points(scene, camera, |p| buckets.illuminate(p, shader), progress)
}

/// Three independent standard-normal numbers (Box–Muller).
fn gaussian3(rng: &mut SplitMix64) -> Vec3 {
    let mut pair = || {
        let u = 1.0 - rng.next_f32(); // (0, 1]
        let v = rng.next_f32();
        let r = (-2.0 * u.ln()).sqrt();
        let t = std::f32::consts::TAU * v;
        (r * t.cos(), r * t.sin())
    };
    let (a, b) = pair();
    let (c, _) = pair();
    Vec3::new(a, b, c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::primary::PrimaryLight;
    use crate::vpl::{trace, VplSettings};
    use lgh_core::{BruteForce, Material};

    /// A room: floor, back wall and left wall of a 2-unit box, and a block on the floor that
    /// casts shadows, lit by a lamp near the ceiling.
    fn room() -> (Scene, Vec<Vpl>) {
        let grey = Material::Lambert {
            albedo: Vec3::splat(0.7),
        };
        let red = Material::Lambert {
            albedo: Vec3::new(0.7, 0.1, 0.1),
        };
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let mut mesh = Mesh::quad(
            [
                v(-1., 0., 1.),
                v(1., 0., 1.),
                v(1., 0., -1.),
                v(-1., 0., -1.),
            ],
            grey,
        )
        .unwrap();
        mesh.append(
            Mesh::quad(
                [
                    v(-1., 0., -1.),
                    v(1., 0., -1.),
                    v(1., 2., -1.),
                    v(-1., 2., -1.),
                ],
                grey,
            )
            .unwrap(),
        )
        .unwrap();
        mesh.append(
            Mesh::quad(
                [
                    v(-1., 0., 1.),
                    v(-1., 0., -1.),
                    v(-1., 2., -1.),
                    v(-1., 2., 1.),
                ],
                red,
            )
            .unwrap(),
        )
        .unwrap();
        mesh.append(Mesh::cuboid(v(0.1, 0.0, -0.4), v(0.6, 0.8, 0.1), grey).unwrap())
            .unwrap();
        let scene = Scene::new(mesh);
        let lamp = PrimaryLight::Point {
            position: v(-0.3, 1.8, 0.3),
            intensity: Vec3::splat(2.0),
        };
        let settings = VplSettings {
            count: 4000,
            max_bounces: 2,
            seed: 4,
        };
        let vpls = trace(&scene, &[lamp], &settings).unwrap().vpls;
        (scene, vpls)
    }

    /// The room's VPLs, their point lights and single hierarchy, and the shading settings.
    struct Fixture {
        scene: Scene,
        vpls: Vec<Vpl>,
        lights: Vec<PointLight>,
        lgh: LightingGridHierarchy,
    }

    impl Fixture {
        fn new() -> Fixture {
            let (scene, vpls) = room();
            let lights = point_lights(&vpls);
            let lgh = LightingGridHierarchy::build(&lights, &GridSettings::default()).unwrap();
            Fixture {
                scene,
                vpls,
                lights,
                lgh,
            }
        }

        fn shader(&self) -> Indirect<'_> {
            let settings = IndirectSettings {
                h0: self.lgh.h0(),
                shadow_samples: 9,
                epsilon: 1e-4,
                shadows: true,
            };
            Indirect::new(&self.scene, &self.vpls, settings)
        }

        /// The room from the front, `w × h`.
        fn camera(w: usize, h: usize) -> Camera {
            let (eye, target) = (Vec3::new(0.4, 1.2, 3.0), Vec3::new(0.0, 0.6, 0.0));
            Camera::new(eye, target, Vec3::Y, 50.0, w, h).unwrap()
        }

        /// Brute force over every VPL: the reference.
        fn exact(&self, shader: &Indirect<'_>, camera: &Camera) -> Rendered {
            let brute = BruteForce::new(&self.lights).unwrap();
            render_input_lights(&self.scene, camera, &brute, shader, |_| {}).unwrap()
        }

        fn isotropic(&self, shader: &Indirect<'_>, camera: &Camera, alpha: f32) -> Rendered {
            let backend = LghBackend::new(&self.lgh, alpha).unwrap();
            render_lgh(
                &self.scene,
                camera,
                &backend,
                Coarse::Gaussian,
                shader,
                |_| {},
            )
            .unwrap()
        }
    }

    fn rel_rmse(a: &Rendered, r: &Rendered) -> f64 {
        lgh_image::compare(&a.image, &r.image).unwrap().rel_rmse
    }

    /// With α so large that every VPL is inside level 0's influence region, the hierarchy
    /// hands each point every VPL at full weight: its image equals brute force over every VPL
    /// with the same shadow rays and shading, up to the order of the sums (tolerance 10⁻⁵).
    /// (At α = 1, 4, 16 the isotropic aggregation errs by tens of percent here, the normal
    /// buckets by 28%, 1.7% and 0.6%: `normal_buckets_beat_isotropic_aggregation`.)
    #[test]
    fn the_hierarchy_equals_brute_force_when_every_vpl_is_level_0() {
        let f = Fixture::new();
        let (shader, camera) = (f.shader(), Fixture::camera(24, 18));
        let exact = f.exact(&shader, &camera);
        let got = f.isotropic(&shader, &camera, 256.0);
        assert_eq!(got.mean_lights(), f.vpls.len() as f64);
        let e = rel_rmse(&got, &exact);
        assert!(e < 1e-5, "{e}");
        assert!(exact.image.pixels.iter().any(|p| p.x > 0.0));
    }

    /// The orientation-aware aggregation against the paper's isotropic one, both against brute
    /// force over every VPL with the same shadow rays, at α = 1, 4, 16 in the room. Measured
    /// (32×24): isotropic 78%, 55%, 42%; buckets 28%, 1.7%, 0.60%. Without shadow rays (40×30)
    /// the buckets gave 27%, 2.0%, 0.09%: what is left is the hierarchy's own approximation
    /// (with isotropic VPLs and no shadows the single hierarchy gives 1.6% and 0.08% at
    /// α = 4, 16: its lobe loss is what the buckets remove). Asserted: the buckets win at every
    /// α, and meet issue 14's targets, ≤ 3% at α = 4 and ≤ 1% at α = 16.
    #[test]
    fn normal_buckets_beat_isotropic_aggregation() {
        let f = Fixture::new();
        let buckets = NormalBuckets::build(&f.vpls, &GridSettings::default()).unwrap();
        let (shader, camera) = (f.shader(), Fixture::camera(32, 24));
        let exact = f.exact(&shader, &camera);
        for (alpha, target) in [(1.0f32, 1.0), (4.0, 0.03), (16.0, 0.01)] {
            let iso = rel_rmse(&f.isotropic(&shader, &camera, alpha), &exact);
            let at = buckets.at(alpha).unwrap();
            let oriented = render_buckets(&f.scene, &camera, &at, &shader, |_| {});
            let oriented = rel_rmse(&oriented.unwrap(), &exact);
            println!("alpha {alpha}: isotropic {iso:.4}, buckets {oriented:.4}");
            assert!(oriented < iso, "α = {alpha}: {oriented} against {iso}");
            assert!(oriented <= target, "α = {alpha}: {oriented}");
        }
    }

    /// Representative VPLs (beyond the paper) against the paper's Gaussian shadow samples, both
    /// through the one isotropic hierarchy with k = 9, against brute force over every VPL with
    /// the same shadow rays. Measured (32×24): Gaussian 54.6% and 41.8% at α = 4 and 16 (the
    /// paper's isotropic points), representatives 2.4% and 0.17%. Asserted: representatives win at α = 4
    /// and 16 and meet issue 14's targets there, ≤ 3% and ≤ 1%.
    #[test]
    fn representative_vpls_beat_gaussian_samples() {
        let f = Fixture::new();
        let reps = Representatives::build(&f.lgh, 9);
        let (shader, camera) = (f.shader(), Fixture::camera(32, 24));
        let exact = f.exact(&shader, &camera);
        for (alpha, target) in [(4.0f32, 0.03), (16.0, 0.01)] {
            let gaussian = rel_rmse(&f.isotropic(&shader, &camera, alpha), &exact);
            let backend = LghBackend::new(&f.lgh, alpha).unwrap();
            let coarse = Coarse::Representatives(&reps);
            let drawn = render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {});
            let drawn = rel_rmse(&drawn.unwrap(), &exact);
            println!("alpha {alpha}: gaussian {gaussian:.4}, representatives {drawn:.4}");
            assert!(drawn < gaussian, "α = {alpha}: {drawn} against {gaussian}");
            assert!(drawn <= target, "α = {alpha}: {drawn}");
        }
    }

    /// The adaptive allocation (`lgh gi`'s default; here 16 nested representatives, 2 per coarse
    /// light on average, shared per point by an unshadowed estimate, Russian roulette below one)
    /// against brute force in the room: measured (32×24) 4.4% at α = 4 (the paper's Gaussian
    /// samples 54.6%) and 0.31% at α = 16. Asserted: it beats the Gaussian samples at α = 4 and
    /// is within issue 14's 1% at α = 16. (The 3% at α = 4 is for 365K VPLs, where the
    /// default measures 2.3% on the Cornell box and 2.7–3.0% on Sponza, `docs/gi.md`; the room's 4,000 VPLs make
    /// coarse lights of a few VPLs each, where the roulette's noise weighs more.) And it is the
    /// same at any thread count: the roulette's numbers come from the shading point's own
    /// sequence.
    #[test]
    fn adaptive_representatives_meet_the_targets_at_any_thread_count() {
        let f = Fixture::new();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(16));
        let (shader, camera) = (f.shader(), Fixture::camera(32, 24));
        let exact = f.exact(&shader, &camera);
        let render = |alpha: f32| {
            let backend = LghBackend::new(&f.lgh, alpha).unwrap();
            let coarse = Coarse::Adaptive {
                reps: &reps,
                mean: 2.0,
            };
            render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {}).unwrap()
        };
        let at4 = rel_rmse(&render(4.0), &exact);
        let gaussian = rel_rmse(&f.isotropic(&shader, &camera, 4.0), &exact);
        let at16 = rel_rmse(&render(16.0), &exact);
        println!("adaptive: alpha 4 {at4:.4} (gaussian {gaussian:.4}), alpha 16 {at16:.4}");
        assert!(at4 < gaussian, "{at4} against {gaussian}");
        assert!(at16 <= 0.01, "{at16}");
        // Unbiased: the image's mean matches that of every coarse light shaded through all 16
        // of its representatives (the roulette's weights and the prefixes change the noise, not
        // the mean).
        let mean = |r: &Rendered| {
            r.image
                .pixels
                .iter()
                .map(|p| p.element_sum() as f64)
                .sum::<f64>()
        };
        let backend = LghBackend::new(&f.lgh, 4.0).unwrap();
        let all = Coarse::Representatives(&reps);
        let full = render_lgh(&f.scene, &camera, &backend, all, &shader, |_| {}).unwrap();
        let ratio = mean(&render(4.0)) / mean(&full);
        println!("adaptive mean over all-16 mean: {ratio:.4}");
        // Measured 1.0030. Bound: the per-pixel noise is about the 4.4% RMSE above; over 768
        // pixels that is 0.16% if they were independent, and neighbours share lights, so an
        // order of magnitude more: 2%.
        assert!((ratio - 1.0).abs() < 0.02, "{ratio}");
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        assert_eq!(
            pool(1).install(|| render(4.0)),
            pool(3).install(|| render(4.0))
        );
    }

    /// A VPL lights only the side its normal faces, and a wall between hides it.
    #[test]
    fn a_vpl_lights_its_front_and_is_hidden_by_walls() {
        let grey = Material::Lambert {
            albedo: Vec3::splat(0.5),
        };
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let wall = Mesh::quad(
            [
                v(-1., 0.5, -1.),
                v(1., 0.5, -1.),
                v(1., 0.5, 1.),
                v(-1., 0.5, 1.),
            ],
            grey,
        )
        .unwrap();
        let scene = Scene::new(wall);
        let vpl = Vpl {
            position: Vec3::new(0.0, 1.0, 0.0),
            normal: Vec3::NEG_Y,
            power: Vec3::ONE,
            albedo: Vec3::ONE,
            bounce: 1,
        };
        let lights = point_lights(&[vpl]);
        let settings = IndirectSettings {
            h0: 0.01,
            shadow_samples: 9,
            epsilon: 1e-4,
            shadows: true,
        };
        let shader = Indirect::new(&scene, std::slice::from_ref(&vpl), settings);
        let at = |y: f32, n: Vec3| ShadingPoint {
            position: Vec3::new(0.2, y, 0.0),
            normal: Some(n),
            view: Some(n),
            material: grey,
        };
        let sample = |x: Vec3| {
            LightSample::point(
                0,
                lights[0].position,
                lights[0].intensity,
                x,
                lgh_core::Lobe::All,
            )
        };
        // Facing the VPL, below it, above the wall: lit.
        let lit = at(0.75, Vec3::Y);
        assert!(shader.shade(&lit, &sample(lit.position), Some(0)).x > 0.0);
        // Below the wall: hidden.
        let hidden = at(0.25, Vec3::Y);
        assert_eq!(
            shader.shade(&hidden, &sample(hidden.position), Some(0)),
            Vec3::ZERO
        );
        // Above the VPL, behind its lobe: dark.
        let behind = at(1.5, Vec3::NEG_Y);
        assert_eq!(
            shader.shade(&behind, &sample(behind.position), Some(0)),
            Vec3::ZERO
        );
    }
}
